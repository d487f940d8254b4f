//! The invariant EKF on a known motion, without the simulator: a body
//! turning at a constant rate while its centre moves on a smooth closed
//! curve, read by the crate's own IMU and motion-capture models.
//!
//! - Consistency: over 100 noise realisations, the mean NEES of the error
//!   in the filter's own coordinates (the log of `X̂ X⁻¹`, the biases'
//!   differences) inside the two-sided 95 % χ² band at ≥ 90 % of the
//!   instants after a burn-in; the mocap updates' NIS likewise.
//! - Large errors: from 90° and 170° off in attitude it converges.
//! - Bad input: a non-finite measurement is counted and changes nothing.

use lie::{ExtTwist, Se23, ops};
use sensors::{
    Estimator, Iekf, IekfConfig, Imu, ImuSpec, InitialSigma, Measurement, Mocap, MocapSpec,
    NavState, NoiseKey, TriadErrors,
};

mod motion;
use motion::{B, G, truth, v};

/// An IMU with noise, walks and turn-on biases, and the filter matched to
/// it and to the mocap.
fn setup(att_sigma0: f64) -> (ImuSpec, MocapSpec, IekfConfig) {
    let mut imu = ImuSpec::crazyflie();
    imu.gyro = TriadErrors {
        random_walk: 2e-4,
        turn_on_bias: 5e-3,
        ..imu.gyro
    };
    imu.accel = TriadErrors {
        random_walk: 2e-3,
        turn_on_bias: 0.05,
        ..imu.accel
    };
    let mocap = MocapSpec {
        latency: 0.0,
        ..MocapSpec::crazyflie()
    };
    let cfg = IekfConfig {
        gyro_density: imu.gyro.noise_density,
        accel_density: imu.accel.noise_density,
        gyro_walk: imu.gyro.random_walk,
        accel_walk: imu.accel.random_walk,
        mocap_position: mocap.position_sigma,
        mocap_attitude: mocap.attitude_sigma,
        initial: InitialSigma {
            position: 0.02,
            velocity: 0.02,
            attitude: att_sigma0,
            gyro_bias: imu.gyro.turn_on_bias,
            accel_bias: imu.accel.turn_on_bias,
        },
        gravity: G,
        ..IekfConfig::default()
    };
    (imu, mocap, cfg)
}

/// `eᵀ P⁻¹ e` by Cholesky.
fn nees(p: &[[f64; 15]; 15], e: &[f64; 15]) -> f64 {
    let mut l = [[0.0f64; 15]; 15];
    for j in 0..15 {
        let d = p[j][j] - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>();
        assert!(d > 0.0, "covariance not positive definite at {j}: {d:e}");
        l[j][j] = d.sqrt();
        for i in j + 1..15 {
            l[i][j] = (p[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>()) / l[j][j];
        }
    }
    let mut y = [0.0f64; 15];
    for i in 0..15 {
        y[i] = (e[i] - (0..i).map(|k| l[i][k] * y[k]).sum::<f64>()) / l[i][i];
    }
    y.iter().map(|x| x * x).sum()
}

struct Run {
    /// NEES every 10 ms, NIS of every mocap update.
    nees: Vec<f64>,
    nis: Vec<f64>,
    /// Attitude error of the estimate every 10 ms, rad.
    att_err: Vec<f64>,
}

/// One run of `secs` s: IMU at 1 kHz, mocap at 100 Hz; the initial
/// estimate drawn from the filter's P₀ (or turned by `offset` rad about
/// a fixed axis when given).
fn run(
    seed: u64,
    secs: f64,
    cfg: IekfConfig,
    imu: ImuSpec,
    mocap: MocapSpec,
    offset: Option<f64>,
) -> Run {
    let mut imu_m = Imu::<B>::new(imu, NoiseKey::new(seed, 0)).unwrap();
    let mocap_m = Mocap::new(mocap, NoiseKey::new(seed, 1)).unwrap();
    let mut f = Iekf::<B>::new(cfg).unwrap();
    let (r0, v0, x0, _, _) = truth(0.0);
    let truth0 = Se23::<B>::new(r0, v0, x0);
    let init = NoiseKey::new(seed, 7);
    let i = cfg.initial;
    let sig = [i.position, i.velocity, i.attitude];
    let xi: [f64; 9] = core::array::from_fn(|k| sig[k / 3] * init.pair(0, k as u64)[0]);
    let start = match offset {
        Some(a) => {
            let axis = [0.6, -0.48, 0.64];
            Se23::exp(ExtTwist::new(
                v([0.0; 3]),
                v([0.0; 3]),
                v(axis.map(|c| c * a)),
            )) * truth0
        }
        None => Se23::exp(ExtTwist::from_array(xi)) * truth0,
    };
    f.reset_to(0.0, start);
    let mut out = Run {
        nees: vec![],
        nis: vec![],
        att_err: vec![],
    };
    let n = (secs * 1000.0) as u64;
    for k in 0..=n {
        let t = k as f64 / 1000.0;
        let (r, vel, x, a, w) = truth(t);
        // The IMU first, as a simulation hands over equal arrivals.
        let kin = sensors::Kinematics::<B> {
            r: r.as_matrix(),
            omega: w,
            accel: a,
            alpha: v([0.0; 3]),
        };
        let s = imu_m.sample(k, &kin, G).unwrap();
        f.update(&Measurement::Imu(s));
        if k % 10 == 0 && k > 0 {
            let km = k / 10;
            if let Some(m) = mocap_m.frame::<B>(km, x, vel, r.as_matrix(), w) {
                f.update(&Measurement::Mocap(m));
                out.nis.push(f.last_nis().unwrap().0);
            }
            let xt = Se23::<B>::new(r, vel, x);
            let eta = (f.pose() * xt.inverse()).log();
            let biases = imu_m.biases();
            let (bg, ba) = f.biases();
            let mut e = [0.0; 15];
            for (k, c) in eta.to_array().iter().enumerate() {
                e[k] = *c;
            }
            let (bg, ba) = (ops::vec3_f64::<B>(bg), ops::vec3_f64::<B>(ba));
            for j in 0..3 {
                e[9 + j] = bg[j] - biases[1][j];
                e[12 + j] = ba[j] - biases[0][j];
            }
            let p: [[f64; 15]; 15] = *f.covariance();
            out.nees.push(nees(&p, &e));
            out.att_err.push(ops::norm::<B>(eta.phi));
        }
    }
    out
}

/// The two-sided 95 % band of a mean of `m` independent NEES of `dof`
/// degrees of freedom each (`m·mean` is χ² with `m·dof`): Wilson–Hilferty's cube-root normal approximation, good to
/// 1e-3 relative for k in the hundreds.
fn band(m: usize, dof: usize) -> (f64, f64) {
    let k = (m * dof) as f64;
    let q = |z: f64| k * (1.0 - 2.0 / (9.0 * k) + z * (2.0 / (9.0 * k)).sqrt()).powi(3) / m as f64;
    (q(-1.959_964), q(1.959_964))
}

/// The share of instants after `skip` whose mean over the runs is in the band.
fn inside(runs: &[Vec<f64>], skip: usize, dof: usize) -> (f64, f64) {
    let m = runs.len();
    let len = runs.iter().map(Vec::len).min().unwrap();
    let (lo, hi) = band(m, dof);
    let means: Vec<f64> = (skip..len)
        .map(|i| runs.iter().map(|r| r[i]).sum::<f64>() / m as f64)
        .collect();
    let share = means.iter().filter(|x| (lo..=hi).contains(*x)).count() as f64 / means.len() as f64;
    let avg = means.iter().sum::<f64>() / means.len() as f64;
    (share, avg)
}

#[test]
fn consistent_under_a_matched_noise_model() {
    let (imu, mocap, cfg) = setup(0.05);
    let runs: Vec<Run> = (0..100)
        .map(|s| run(s, 10.0, cfg, imu, mocap, None))
        .collect();
    let nees: Vec<Vec<f64>> = runs.iter().map(|r| r.nees.clone()).collect();
    let nis: Vec<Vec<f64>> = runs.iter().map(|r| r.nis.clone()).collect();
    // 2 s burn-in: 200 instants of 10 ms.
    let (share, avg) = inside(&nees, 200, 15);
    let (share_nis, avg_nis) = inside(&nis, 200, 6);
    let (lo, hi) = band(100, 15);
    println!(
        "iekf, 100 runs × 10 s: mean NEES {avg:.2} (15 states, band {lo:.2}–{hi:.2}) inside at {:.1} % of instants; mean NIS {avg_nis:.2} (6) inside at {:.1} %",
        100.0 * share,
        100.0 * share_nis
    );
    // A consistent filter sits inside 95 % of the time; 90 % leaves room
    // for chance (and for the instants' correlation) without passing a
    // filter whose NEES is off by the band's width.
    assert!(share >= 0.9, "NEES inside at {share}");
    assert!(share_nis >= 0.9, "NIS inside at {share_nis}");
}

#[test]
fn converges_from_large_attitude_errors() {
    let (imu, mocap, cfg) = setup(3.0);
    for deg in [90.0f64, 170.0] {
        let r = run(3, 5.0, cfg, imu, mocap, Some(deg.to_radians()));
        let below = r.att_err.iter().position(|e| *e < 2f64.to_radians());
        let settle = r.att_err.iter().rposition(|e| *e >= 2f64.to_radians());
        println!(
            "iekf from {deg}°: below 2° first at {:?} s, for good after {:?} s, final {:.3}°",
            below.map(|i| (i + 1) as f64 * 0.01),
            settle.map(|i| (i + 2) as f64 * 0.01),
            r.att_err.last().unwrap().to_degrees()
        );
        // The attitude is observed directly at 100 Hz with 4.5 mrad: once
        // the filter's σ is honest it converges within a few updates.
        assert!(settle.map_or(0.0, |i| (i + 2) as f64 * 0.01) < 1.0);
    }
}

#[test]
fn the_innovation_is_the_frame_against_the_prior_estimate() {
    // Level at rest, the estimate told 2 cm and 0.05 rad off; one frame of
    // the truth at t = 0.1 s. The reported innovation is the frame's
    // position minus the estimate's just before it, then the attitude's
    // Log(R_m R̂ᵀ) (measured minus predicted, the invariant EKF's rows).
    let (_, _, cfg) = setup(0.05);
    let mut f = Iekf::<B>::new(cfg).unwrap();
    let off = lie::So3Mat::<B>::exp(v([0.05, -0.02, 0.01]));
    f.reset(
        0.0,
        &NavState {
            x: v([0.02, 0.0, -1.0]),
            r: off.as_matrix(),
            ..NavState::at_rest()
        },
    );
    assert!(
        f.diagnostics()
            .unwrap()
            .innovation
            .iter()
            .all(|x| x.is_nan())
    );
    for k in 1..=100 {
        f.update(&Measurement::Imu(sensors::ImuSample {
            k,
            t: k as f64 * 1e-3,
            accel: v([0.0, 0.0, -G]),
            gyro: v([0.0; 3]),
            attitude: None,
        }));
    }
    let prior = f.estimate(0.1);
    let frame = sensors::MocapSample::<B> {
        k: 10,
        t: 0.1,
        x: v([0.0, 0.0, -1.0]),
        v: v([0.0; 3]),
        r: ops::identity::<B>(),
        omega: v([0.0; 3]),
    };
    f.update(&Measurement::Mocap(frame));
    let d = f.diagnostics().unwrap();
    let dx = frame.x - prior.x;
    let dr = lie::So3Mat::<B>::from_matrix_unchecked(frame.r * prior.r.transpose()).log();
    let want = [dx[0], dx[1], dx[2], dr[0], dr[1], dr[2]];
    for (k, (got, want)) in d.innovation.iter().zip(want).enumerate() {
        // Both sides are the same few roundings of the same numbers.
        assert!((got - want).abs() < 1e-15, "{k}: {got} vs {want}");
    }
    assert_eq!(d.nis.unwrap().1, 6);
    assert!(
        d.innovation[3].abs() > 0.04,
        "the 0.05 rad error shows: {d:?}"
    );
}

#[test]
fn a_non_finite_measurement_is_counted_and_ignored() {
    let (_, _, cfg) = setup(0.05);
    let mut f = Iekf::<B>::new(cfg).unwrap();
    f.reset(0.0, &NavState::at_rest());
    let before = (f.pose(), *f.covariance());
    let mut m = sensors::MocapSample::<B> {
        k: 1,
        t: 0.0,
        x: v([f64::NAN, 0.0, 0.0]),
        v: v([0.0; 3]),
        r: ops::identity::<B>(),
        omega: v([0.0; 3]),
    };
    f.update(&Measurement::Mocap(m));
    m.x = v([0.0; 3]);
    m.r *= f64::INFINITY;
    f.update(&Measurement::Mocap(m));
    assert_eq!(f.rejections().mocap, 2);
    assert_eq!(f.pose(), before.0);
    assert_eq!(*f.covariance(), before.1);
}

#[test]
fn bad_settings_name_their_field() {
    let cfg = IekfConfig {
        mocap_attitude: 0.0,
        ..IekfConfig::default()
    };
    let e = Iekf::<B>::new(cfg).unwrap_err().to_string();
    assert_eq!(e, "iekf.mocap_attitude = 0: must be positive and finite");
}

#[test]
fn a_covariance_must_be_symmetric_positive_definite() {
    let mut f = Iekf::<B>::new(IekfConfig::default()).unwrap();
    let mut p = [[0.0; 15]; 15];
    for (i, row) in p.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    f.set_covariance(&p).unwrap();
    // Indefinite: a correlation above one between two states.
    p[0][1] = 2.0;
    p[1][0] = 2.0;
    let e = f.set_covariance(&p).unwrap_err().to_string();
    assert!(
        e.starts_with("iekf.covariance = 0: must be symmetric positive definite"),
        "{e}"
    );
    p[1][0] = 0.0;
    assert!(
        f.set_covariance(&p).is_err(),
        "an asymmetric matrix was taken"
    );
    p[1][0] = f64::NAN;
    let e = f.set_covariance(&p).unwrap_err().to_string();
    assert!(e.starts_with("iekf.covariance = NaN"), "{e}");
    // The last good one is kept.
    assert_eq!(f.covariance()[0][1], 0.0);
}
