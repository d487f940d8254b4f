//! The C ABI's filters are the library's filters: the same estimates to
//! the bit as `sensors::Iekf` and `sensors::Complementary` on `f32`, close
//! to the `f64` filter on the same stream, converging from a wrong start;
//! and every bad input is a status that leaves the filter as it was.

use geopid_control::*;
use lie::{GlamF32, NalgebraF64, Real, So3Mat};
use sensors::{
    Complementary, ComplementaryConfig, Estimator, Iekf, IekfConfig, ImuSample, InitialSigma,
    Measurement, MocapSample, NavState,
};

/// One stream event: an IMU sample or a motion-capture frame.
#[derive(Clone, Copy)]
enum Event {
    Imu(GpcImuSample),
    Mocap(GpcMocapSample),
}

const G: f64 = 9.81;
/// IMU at 1 kHz, motion capture every tenth sample.
const IMU_RATE: f64 = 1000.0;

fn exp(w: [f64; 3]) -> nalgebra::Matrix3<f64> {
    *nalgebra::Rotation3::new(nalgebra::Vector3::from(w)).matrix()
}

fn rows32(m: &nalgebra::Matrix3<f64>) -> [[f32; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)] as f32))
}

fn v32(v: nalgebra::Vector3<f64>) -> [f32; 3] {
    [v.x as f32, v.y as f32, v.z as f32]
}

/// The truth at `t`: a body turning at a constant body rate on an ellipse
/// 1 m up (e3 down): position, velocity, acceleration and attitude.
#[allow(clippy::type_complexity)]
fn truth(
    t: f64,
) -> (
    nalgebra::Vector3<f64>,
    nalgebra::Vector3<f64>,
    nalgebra::Vector3<f64>,
    nalgebra::Matrix3<f64>,
) {
    let w = [0.3, -0.2, 0.5];
    let x = nalgebra::Vector3::new(t.sin(), 0.5 * t.cos(), -1.0);
    let v = nalgebra::Vector3::new(t.cos(), -0.5 * t.sin(), 0.0);
    let a = nalgebra::Vector3::new(-t.sin(), -0.5 * t.cos(), 0.0);
    (x, v, a, exp([0.1, 0.2, 0.3]) * exp(w.map(|c| c * t)))
}

/// `seconds` of noiseless samples from the truth, in arrival order.
fn stream(seconds: f64) -> Vec<Event> {
    let n = (seconds * IMU_RATE).round() as usize;
    let mut out = Vec::new();
    for k in 1..=n {
        let t = k as f64 / IMU_RATE;
        let (x, v, a, r) = truth(t);
        let f = r.transpose() * (a - nalgebra::Vector3::new(0.0, 0.0, G));
        out.push(Event::Imu(GpcImuSample {
            t,
            accel: v32(f),
            gyro: [0.3, -0.2, 0.5],
        }));
        if k % 10 == 0 {
            out.push(Event::Mocap(GpcMocapSample {
                t,
                x: v32(x),
                v: v32(v),
                r: rows32(&r),
            }));
        }
    }
    out
}

/// The truth's state at 0, its attitude turned by `error` (rad, body axes).
fn start(error: [f64; 3]) -> GpcState {
    let (x, v, _, r) = truth(0.0);
    GpcState {
        x: v32(x),
        v: v32(v),
        r: rows32(&(r * exp(error))),
        omega: [0.0; 3],
    }
}

/// The library's IEKF configuration the ABI's `c` stands for.
fn library_iekf(c: &GpcIekfConfig) -> IekfConfig {
    let s = c.initial_sigma.map(f64::from);
    IekfConfig {
        gyro_density: c.gyro_density.into(),
        accel_density: c.accel_density.into(),
        gyro_walk: c.gyro_walk.into(),
        accel_walk: c.accel_walk.into(),
        mocap_position: c.mocap_position.into(),
        mocap_attitude: c.mocap_attitude.into(),
        initial: InitialSigma {
            position: s[0],
            velocity: s[1],
            attitude: s[2],
            gyro_bias: s[3],
            accel_bias: s[4],
        },
        mounting: c.mounting.map(|r| r.map(f64::from)),
        gravity: c.gravity.into(),
        ..IekfConfig::default()
    }
}

/// An event as a library measurement on backend `B`.
fn measurement<B: lie::Backend>(e: &Event) -> Measurement<B> {
    let v = |a: [f32; 3]| B::vec3(lit::<B>(a[0]), lit::<B>(a[1]), lit::<B>(a[2]));
    match e {
        Event::Imu(s) => Measurement::Imu(ImuSample {
            k: 0,
            t: s.t,
            accel: v(s.accel),
            gyro: v(s.gyro),
            attitude: None,
        }),
        Event::Mocap(s) => Measurement::Mocap(MocapSample {
            k: 0,
            t: s.t,
            x: v(s.x),
            v: v(s.v),
            r: lie::ops::from_elems::<B>(s.r.map(|r| r.map(lit::<B>))),
            omega: v([0.0; 3]),
        }),
    }
}

fn lit<B: lie::Backend>(x: f32) -> lie::S<B> {
    lie::S::<B>::lit(f64::from(x))
}

fn nav<B: lie::Backend>(s: &GpcState) -> NavState<B> {
    let v = |a: [f32; 3]| B::vec3(lit::<B>(a[0]), lit::<B>(a[1]), lit::<B>(a[2]));
    NavState {
        x: v(s.x),
        v: v(s.v),
        r: lie::ops::from_elems::<B>(s.r.map(|r| r.map(lit::<B>))),
        omega: v(s.omega),
    }
}

/// A library state's words, as the ABI's `GpcState` holds them.
fn words(n: &NavState<GlamF32>) -> Vec<u32> {
    let r = lie::ops::elems::<GlamF32>(n.r);
    [n.x.to_array(), n.v.to_array(), n.omega.to_array()]
        .iter()
        .flatten()
        .chain(r.iter().flatten())
        .map(|x| x.to_bits())
        .collect()
}

fn state_words(s: &GpcState) -> Vec<u32> {
    [s.x, s.v, s.omega]
        .iter()
        .flatten()
        .chain(s.r.iter().flatten())
        .map(|x| x.to_bits())
        .collect()
}

/// The ABI's IEKF over `events` from `init`: its estimate after each.
fn abi_iekf(cfg: &GpcIekfConfig, init: &GpcState, events: &[Event]) -> Vec<GpcState> {
    let mut f = GpcIekf::default();
    assert_eq!(
        gpc_iekf_init(Some(&mut f), Some(cfg), 0.0, Some(init)),
        GpcStatus::Ok
    );
    events
        .iter()
        .map(|e| {
            let (status, t) = match e {
                Event::Imu(s) => (gpc_iekf_imu(Some(&mut f), Some(s)), s.t),
                Event::Mocap(s) => (gpc_iekf_mocap(Some(&mut f), Some(s)), s.t),
            };
            assert_eq!(status, GpcStatus::Ok);
            let mut out = GpcState::default();
            assert_eq!(
                gpc_iekf_estimate(Some(&f), t + 2e-4, Some(&mut out)),
                GpcStatus::Ok
            );
            out
        })
        .collect()
}

fn event_time(e: &Event) -> f64 {
    match e {
        Event::Imu(s) => s.t,
        Event::Mocap(s) => s.t,
    }
}

#[test]
fn the_abi_iekf_is_the_library_filter_to_the_bit() {
    let cfg = gpc_iekf_default_config();
    let (init, events) = (start([0.3, 0.0, 0.0]), stream(1.0));
    let abi = abi_iekf(&cfg, &init, &events);
    let mut lib = Iekf::<GlamF32>::new(library_iekf(&cfg)).expect("valid");
    lib.reset(0.0, &nav::<GlamF32>(&init));
    for (k, (e, a)) in events.iter().zip(&abi).enumerate() {
        lib.update(&measurement::<GlamF32>(e));
        let want = words(&lib.estimate(event_time(e) + 2e-4));
        assert_eq!(state_words(a), want, "event {k}");
    }
    let mut f = GpcIekf::default();
    gpc_iekf_init(Some(&mut f), Some(&cfg), 0.0, Some(&init));
    for e in &events {
        match e {
            Event::Imu(s) => gpc_iekf_imu(Some(&mut f), Some(s)),
            Event::Mocap(s) => gpc_iekf_mocap(Some(&mut f), Some(s)),
        };
    }
    let mut d = GpcIekfDiagnostics::default();
    assert_eq!(gpc_iekf_diagnostics(Some(&f), Some(&mut d)), GpcStatus::Ok);
    let p = lib.covariance();
    for (i, v) in d.variances.iter().enumerate() {
        assert_eq!(v.to_bits(), p[i][i].to_bits(), "variance {i}");
    }
    assert!(d.nis >= 0.0 && d.rejected == [0, 0], "{d:?}");
}

#[test]
fn the_abi_complementary_filter_is_the_library_filter_to_the_bit() {
    let cfg = gpc_complementary_default_config();
    let (init, events) = (start([0.3, 0.0, 0.0]), stream(1.0));
    let mut f = GpcComplementary::default();
    assert_eq!(
        gpc_complementary_init(Some(&mut f), Some(&cfg), 0.0, Some(&init)),
        GpcStatus::Ok
    );
    let lib_cfg = ComplementaryConfig {
        k_p: cfg.k_p.into(),
        k_i: cfg.k_i.into(),
        max_interval: cfg.max_interval.into(),
        mounting: cfg.mounting.map(|r| r.map(f64::from)),
    };
    let mut lib = Complementary::<GlamF32>::new(lib_cfg).expect("valid");
    lib.reset(0.0, &nav::<GlamF32>(&init));
    for (k, e) in events.iter().enumerate() {
        let status = match e {
            Event::Imu(s) => gpc_complementary_imu(Some(&mut f), Some(s)),
            Event::Mocap(s) => gpc_complementary_mocap(Some(&mut f), Some(s)),
        };
        assert_eq!(status, GpcStatus::Ok);
        lib.update(&measurement::<GlamF32>(e));
        let t = event_time(e) + 2e-4;
        let mut out = GpcState::default();
        gpc_complementary_estimate(Some(&f), t, Some(&mut out));
        assert_eq!(state_words(&out), words(&lib.estimate(t)), "event {k}");
    }
    let mut bias = [f32::NAN; 3];
    gpc_complementary_gyro_bias(Some(&f), Some(&mut bias));
    assert_eq!(bias, lib.bias().to_array());
}

/// The largest attitude difference, rad, and position difference, m,
/// between an `f32` estimate and an `f64` one.
fn gap(a: &GpcState, b: &NavState<NalgebraF64>) -> (f64, f64) {
    let ra = nalgebra::Matrix3::from_fn(|i, j| f64::from(a.r[i][j]));
    let d = So3Mat::<NalgebraF64>::from_matrix_unchecked(ra.transpose() * b.r)
        .log()
        .norm();
    let x = nalgebra::Vector3::from(a.x.map(f64::from));
    (d, (x - b.x).norm())
}

#[test]
fn the_f32_iekf_follows_the_f64_filter_within_rounding() {
    let cfg = gpc_iekf_default_config();
    let (init, events) = (start([1.5, 0.0, 0.0]), stream(3.0));
    let abi = abi_iekf(&cfg, &init, &events);
    let mut lib = Iekf::<NalgebraF64>::new(library_iekf(&cfg)).expect("valid");
    lib.reset(0.0, &nav::<NalgebraF64>(&init));
    let (mut worst_r, mut worst_x) = (0.0f64, 0.0f64);
    for (e, a) in events.iter().zip(&abi) {
        lib.update(&measurement::<NalgebraF64>(e));
        let (r, x) = gap(a, &lib.estimate(event_time(e) + 2e-4));
        (worst_r, worst_x) = (worst_r.max(r), worst_x.max(x));
    }
    println!(
        "f32 against f64 over 3 s from 86° off: attitude {worst_r:.2e} rad, position {worst_x:.2e} m"
    );
    // f32 rounds each step's state at ~6e-8 relative; the mocap
    // corrections keep the difference from accumulating, so it stays near
    // a hundred roundings of the ~1 m state (7e-6 rad and 4e-6 m here,
    // most of it in the first second's large corrections): 3e-5 bounds it.
    assert!(
        worst_r < 3e-5 && worst_x < 3e-5,
        "{worst_r:e} rad, {worst_x:e} m"
    );
}

#[test]
fn both_filters_recover_from_a_wrong_start() {
    let events = stream(3.0);
    let last_mocap = events
        .iter()
        .rev()
        .find_map(|e| match e {
            Event::Mocap(s) => Some(*s),
            _ => None,
        })
        .expect("frames");
    let err = |s: &GpcState| {
        let a = nalgebra::Matrix3::from_fn(|i, j| f64::from(s.r[i][j]));
        let b = nalgebra::Matrix3::from_fn(|i, j| f64::from(last_mocap.r[i][j]));
        So3Mat::<NalgebraF64>::from_matrix_unchecked(a.transpose() * b)
            .log()
            .norm()
            .to_degrees()
    };
    // The invariant EKF from 86° off: its error dynamics do not depend on
    // the estimate, so a large error converges as a small one does.
    let cfg = gpc_iekf_default_config();
    let abi = abi_iekf(&cfg, &start([1.5, 0.0, 0.0]), &events);
    let iekf = err(abi.last().expect("estimates"));
    // The complementary filter from 30° off: the error and the bias loop
    // decay with the roots of s² + k_P s + k_I, 1.9/s and 0.11/s, and the
    // slow one carries a tail of about a degree at 3 s.
    let mut f = GpcComplementary::default();
    let ccfg = gpc_complementary_default_config();
    gpc_complementary_init(
        Some(&mut f),
        Some(&ccfg),
        0.0,
        Some(&start([0.52, 0.0, 0.0])),
    );
    for e in &events {
        match e {
            Event::Imu(s) => gpc_complementary_imu(Some(&mut f), Some(s)),
            Event::Mocap(s) => gpc_complementary_mocap(Some(&mut f), Some(s)),
        };
    }
    let mut out = GpcState::default();
    gpc_complementary_estimate(Some(&f), last_mocap.t, Some(&mut out));
    let comp = err(&out);
    println!("after 3 s: iekf {iekf:.4}° (from 86°), complementary {comp:.4}° (from 30°)");
    assert!(
        iekf < 0.1 && comp < 2.0,
        "iekf {iekf}°, complementary {comp}°"
    );
}

#[test]
fn bad_input_is_a_status_and_leaves_the_filter_as_it_was() {
    let cfg = gpc_iekf_default_config();
    let init = start([0.0; 3]);
    let mut f = GpcIekf::default();
    let imu = GpcImuSample {
        t: 0.001,
        accel: [0.0, 0.0, -9.81],
        gyro: [0.0; 3],
    };
    assert_eq!(
        gpc_iekf_imu(Some(&mut f), Some(&imu)),
        GpcStatus::NotInitialized
    );
    let mut bad = cfg;
    bad.gyro_density = -1.0;
    assert_eq!(
        gpc_iekf_init(Some(&mut f), Some(&bad), 0.0, Some(&init)),
        GpcStatus::InvalidConfig
    );
    bad = cfg;
    bad.mounting[0][0] = -1.0;
    assert_eq!(
        gpc_iekf_init(Some(&mut f), Some(&bad), 0.0, Some(&init)),
        GpcStatus::InvalidConfig,
        "a reflection is not a mounting"
    );
    assert_eq!(
        gpc_iekf_init(Some(&mut f), Some(&cfg), f64::NAN, Some(&init)),
        GpcStatus::InvalidTime
    );
    let mut s = init;
    s.v[1] = f32::INFINITY;
    assert_eq!(
        gpc_iekf_init(Some(&mut f), Some(&cfg), 0.0, Some(&s)),
        GpcStatus::NonFiniteState
    );
    assert!(
        f.opaque.iter().all(|w| *w == 0),
        "refused inits wrote nothing"
    );
    assert_eq!(
        gpc_iekf_init(None, Some(&cfg), 0.0, Some(&init)),
        GpcStatus::NullPointer
    );
    assert_eq!(
        gpc_iekf_init(Some(&mut f), Some(&cfg), 0.0, Some(&init)),
        GpcStatus::Ok
    );
    assert_eq!(gpc_iekf_imu(Some(&mut f), Some(&imu)), GpcStatus::Ok);
    let before = f.opaque;
    let mut nan = imu;
    nan.t = 0.002;
    nan.gyro[2] = f32::NAN;
    let mut back = imu;
    back.t = 0.0005;
    let mut frame = GpcMocapSample {
        t: 0.001,
        x: init.x,
        v: init.v,
        r: init.r,
    };
    frame.r[0][1] = 0.5;
    for (status, want) in [
        (
            gpc_iekf_imu(Some(&mut f), Some(&nan)),
            GpcStatus::NonFiniteMeasurement,
        ),
        (
            gpc_iekf_imu(Some(&mut f), Some(&back)),
            GpcStatus::InvalidTime,
        ),
        (
            gpc_iekf_mocap(Some(&mut f), Some(&frame)),
            GpcStatus::NotARotation,
        ),
        (gpc_iekf_mocap(Some(&mut f), None), GpcStatus::NullPointer),
    ] {
        assert_eq!(status, want);
    }
    assert_eq!(f.opaque, before, "a refused measurement changed the filter");
    let mut out = GpcState::default();
    assert_eq!(
        gpc_iekf_estimate(Some(&f), f64::INFINITY, Some(&mut out)),
        GpcStatus::InvalidTime
    );
    let mut c = GpcComplementary::default();
    let mut ccfg = gpc_complementary_default_config();
    ccfg.max_interval = 1.0; // k_P · 1 s = 2: an overshooting correction
    assert_eq!(
        gpc_complementary_init(Some(&mut c), Some(&ccfg), 0.0, Some(&init)),
        GpcStatus::InvalidConfig
    );
    assert_eq!(
        gpc_complementary_estimate(Some(&c), 0.0, Some(&mut out)),
        GpcStatus::NotInitialized
    );
    // A block of one kind is not a filter of the other.
    let mut other = GpcComplementary::default();
    other
        .opaque
        .copy_from_slice(&f.opaque[..GPC_COMPLEMENTARY_WORDS]);
    assert_eq!(
        gpc_complementary_estimate(Some(&other), 0.0, Some(&mut out)),
        GpcStatus::NotInitialized
    );
    for code in 10..=14 {
        // SAFETY: the function returns a static NUL-terminated string.
        let name = unsafe { std::ffi::CStr::from_ptr(gpc_status_name(code)) };
        assert_ne!(
            name.to_str().expect("UTF-8"),
            "unknown status",
            "code {code}"
        );
    }
}

#[test]
fn a_frame_captured_ahead_of_the_imu_does_not_refuse_the_next_sample() {
    // Mocap at 0.0105 s between IMU samples at 0.010 and 0.011 s: the frame
    // carries the filter past the latest sample, and the next sample,
    // later than the latest one, is taken.
    let init = start([0.0; 3]);
    let mut f = GpcIekf::default();
    let mut c = GpcComplementary::default();
    gpc_iekf_init(
        Some(&mut f),
        Some(&gpc_iekf_default_config()),
        0.0,
        Some(&init),
    );
    let ccfg = gpc_complementary_default_config();
    gpc_complementary_init(Some(&mut c), Some(&ccfg), 0.0, Some(&init));
    let imu = |t: f64| GpcImuSample {
        t,
        accel: [0.0, 0.0, -9.81],
        gyro: [0.0; 3],
    };
    let frame = GpcMocapSample {
        t: 0.0105,
        x: init.x,
        v: init.v,
        r: init.r,
    };
    assert_eq!(gpc_iekf_imu(Some(&mut f), Some(&imu(0.010))), GpcStatus::Ok);
    assert_eq!(
        gpc_complementary_imu(Some(&mut c), Some(&imu(0.010))),
        GpcStatus::Ok
    );
    assert_eq!(gpc_iekf_mocap(Some(&mut f), Some(&frame)), GpcStatus::Ok);
    assert_eq!(
        gpc_complementary_mocap(Some(&mut c), Some(&frame)),
        GpcStatus::Ok
    );
    assert_eq!(gpc_iekf_imu(Some(&mut f), Some(&imu(0.011))), GpcStatus::Ok);
    assert_eq!(
        gpc_complementary_imu(Some(&mut c), Some(&imu(0.011))),
        GpcStatus::Ok
    );
    // A sample before the latest one goes back in time.
    assert_eq!(
        gpc_iekf_imu(Some(&mut f), Some(&imu(0.0108))),
        GpcStatus::InvalidTime
    );
}
