//! Sensors and an estimator in the loop: sampling moves no step, a
//! noise-free tracker at the control rate is the truth bit for bit, the
//! noise does not depend on the integrator, the IMU reads the second
//! derivative of its mounted point, and bad settings are refused before
//! the first step.

use dynamics::paper;
use lie::{GlamF64 as B, Rotation, So3Mat};
use scenarios::{MeasurementRecord, RunOptions, RunOutput, SimError};
use scenes::Scene;
use scenes::scene::Timing;
use sensors::{ImuSpec, MocapEstimator, MocapSpec, SensorSuite};

fn sampled(mut scene: Scene, rate: f64) -> Scene {
    scene.control.timing = Timing::Sampled;
    scene.control.rate = rate;
    scene
}

fn figure_eight() -> Scene {
    let mut s = sampled(scenes::builtin::figure_eight(), 100.0);
    s.duration = 4.0;
    s
}

fn run(scene: &Scene, suite: Option<SensorSuite>, estimate: bool) -> Result<RunOutput, SimError> {
    let mut b = scenes::builder::<B>(scene).expect("scene builds");
    if let Some(s) = suite {
        b = b.sensors(s, 42);
    }
    if estimate {
        b = b.estimator(Box::new(MocapEstimator::<B>::new()));
    }
    b.build()?.run(RunOptions::default())
}

fn mocap_only(spec: MocapSpec) -> SensorSuite {
    SensorSuite {
        mocap: Some(spec),
        ..SensorSuite::default()
    }
}

/// The figure eight and the paper-flip's position segment under sampled
/// control at 100 Hz: flown on a perfect tracker at 100 Hz through the
/// mocap estimator, they fly the truth's trajectory bit for bit (every
/// sample and the final state), for a one-step and an adaptive stepper.
#[test]
fn perfect_mocap_at_the_control_rate_flies_the_truth_bit_for_bit() {
    let mut flip_position = sampled(scenes::builtin::paper_flip(), 100.0);
    flip_position.plan.remove(0);
    flip_position.duration = 3.0;
    for mut scene in [figure_eight(), flip_position] {
        for kind in ["rk4", "dopri"] {
            scene.integrator.kind = kind.into();
            let truth = run(&scene, None, false).unwrap();
            let est = run(&scene, Some(mocap_only(MocapSpec::perfect(100.0))), true).unwrap();
            assert_eq!(truth.samples.len(), est.samples.len());
            for (a, b) in truth.samples.iter().zip(&est.samples) {
                assert_eq!((a.t, a.x, a.v, a.r, a.omega), (b.t, b.x, b.v, b.r, b.omega));
                assert_eq!((a.thrust, a.moment), (b.thrust, b.moment), "t = {}", a.t);
            }
            assert_eq!(truth.last.x, est.last.x);
            assert_eq!(truth.last.r, est.last.r);
            let frames = est
                .measurements
                .iter()
                .filter(|m| matches!(m, MeasurementRecord::Mocap { .. }))
                .count();
            assert_eq!(frames, 1 + (100.0 * scene.duration).round() as usize);
            println!(
                "{} {kind}: {} samples identical, {frames} frames, ex(end) = {:.3e}",
                scene.name,
                est.samples.len(),
                est.last.ex
            );
        }
    }
}

/// The noise is keyed on (seed, sensor, sample, axis), not on the steps:
/// with sensors on a run that flies on the truth, the mocap's position
/// minus the true position at each frame is the same under RK4 at two
/// step sizes and Dormand–Prince, to the rounding of the position (a few
/// ulp of |x| ≤ 2 m).
#[test]
fn noise_does_not_depend_on_the_integrator() {
    let noise = |kind: &str, dt: f64| {
        let mut scene = figure_eight();
        scene.integrator.kind = kind.into();
        scene.integrator.dt = dt;
        scene.record.sample = 0.01;
        let out = run(&scene, Some(mocap_only(MocapSpec::rotorpy(100.0))), false).unwrap();
        let frames: Vec<_> = out
            .measurements
            .iter()
            .filter_map(|m| match m {
                MeasurementRecord::Mocap { t, state, .. } => Some((*t, state.x)),
                _ => None,
            })
            .collect();
        assert_eq!(frames.len(), out.samples.len());
        frames
            .iter()
            .zip(&out.samples)
            .map(|((t, x), s)| {
                assert!((t - s.t).abs() < 1e-12);
                [x[0] - s.x[0], x[1] - s.x[1], x[2] - s.x[2]]
            })
            .collect::<Vec<_>>()
    };
    let a = noise("rk4", 1e-3);
    let b = noise("rk4", 2.5e-3);
    let c = noise("dopri", 1e-2);
    let mut worst = 0.0f64;
    for ((p, q), r) in a.iter().zip(&b).zip(&c) {
        for i in 0..3 {
            worst = worst.max((p[i] - q[i]).abs()).max((p[i] - r[i]).abs());
        }
    }
    println!("largest difference of the noise across steppers: {worst:.2e}");
    assert!(worst < 8.0 * f64::EPSILON * 2.0, "{worst}");
    // And it is noise: σ = √50·0.0005 m ≈ 3.5 mm.
    let sd = (a.iter().map(|n| n[0] * n[0]).sum::<f64>() / a.len() as f64).sqrt();
    assert!((sd / (50f64.sqrt() * 0.0005) - 1.0).abs() < 0.25, "{sd}");
}

/// A level IMU at rest reads −g along b3 and no rates: the paper's
/// quadrotor hovering level on its attitude law with hover thrust, a
/// noiseless IMU at 1 kHz.
#[test]
fn a_hovering_imu_reads_minus_g_along_b3() {
    use controllers::{
        AttitudeGains, AttitudeMode, AttitudeThrust, HoldAttitude, HoldPosition, RigidBodyParams,
    };
    let params = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let mode = AttitudeMode::<B, _, HoldPosition<B>>::new(
        params,
        AttitudeGains::uniform(0.65, 0.11, 0.0, 0.8),
        HoldAttitude::new(So3Mat::<B>::identity()),
        AttitudeThrust::Constant(params.mass * params.gravity),
    );
    let suite = SensorSuite {
        imu: Some(ImuSpec::mpu9250().noiseless()),
        ..SensorSuite::default()
    };
    let out = scenarios::Simulation::<B>::builder(Box::new(dynamics::Quadrotor::<B>::paper()))
        .mode(mode, scenarios::Until::Never)
        .duration(0.5)
        .sensors(suite, 1)
        .build()
        .unwrap()
        .run(RunOptions::default())
        .unwrap();
    let mut n = 0;
    for m in &out.measurements {
        if let MeasurementRecord::Imu { accel, gyro, .. } = m {
            n += 1;
            // Hover thrust against gravity cancel to rounding.
            assert!(
                accel[0].abs() < 1e-12 && accel[1].abs() < 1e-12,
                "{accel:?}"
            );
            assert!((accel[2] + paper::GRAVITY).abs() < 1e-12, "{accel:?}");
            assert!(gyro.iter().all(|w| w.abs() < 1e-12), "{gyro:?}");
        }
    }
    assert_eq!(n, 501);
}

/// The accelerometer at a point `p` off the centre of mass, turned by
/// `R_BS`, reads `R_BSᵀ Rᵀ (d²/dt² (x + R p) − g e3)`: the second
/// derivative taken by the fourth-order central difference of the
/// recorded flight (samples every 1 ms at the IMU's instants, the
/// paper-flip under continuous control), away from the mode switch and
/// the located breakpoint crossings, where the acceleration steps. The
/// agreement's floor is the difference's O(h⁴) truncation where the
/// flip's jerk is largest (4.6e-7 m/s² at t = 2 ms, measured); its
/// rounding is ~16 ε |x| / h² ≈ 4e-9 m/s². The bound 1e-6 m/s² sits
/// just above that floor and seven orders below the lever-arm terms
/// (|Ω|² |p| reaches 11.7 m/s² in the flip).
#[test]
fn the_accelerometer_reads_the_mounted_points_acceleration() {
    let mut scene = scenes::builtin::paper_flip();
    scene.duration = 1.5;
    scene.record.sample = 1e-3;
    scene.integrator.kind = "rk4".into();
    scene.integrator.dt = 1e-3;
    let p = [0.05, -0.03, 0.02];
    let r_bs = So3Mat::<B>::exp(B::vec3(0.3, 0.2, -0.4)).matrix();
    let rows = lie::ops::mat3_f64::<B>(r_bs);
    let spec = ImuSpec {
        position: p,
        mounting: rows,
        ..ImuSpec::mpu9250().noiseless()
    };
    let suite = SensorSuite {
        imu: Some(spec),
        ..SensorSuite::default()
    };
    let out = scenes::builder::<B>(&scene)
        .unwrap()
        .sensors(suite, 1)
        .build()
        .unwrap()
        .run(RunOptions::default())
        .unwrap();
    let imu: Vec<_> = out
        .measurements
        .iter()
        .filter_map(|m| match m {
            MeasurementRecord::Imu { t, accel, .. } => Some((*t, *accel)),
            _ => None,
        })
        .collect();
    let s = &out.samples;
    let h = 1e-3;
    assert_eq!(imu.len(), 1501);
    let point = |k: usize| {
        let r = s[k].r;
        std::array::from_fn::<f64, 3, _>(|i| {
            s[k].x[i] + r[i][0] * p[0] + r[i][1] * p[1] + r[i][2] * p[2]
        })
    };
    let mut worst = 0.0f64;
    let mut largest_lever = 0.0f64;
    let mut worst_t = 0.0;
    // The switch to the position mode steps the command, and with it the
    // acceleration, and so does a breakpoint crossing (sat′ steps the
    // integral term's rate, which the attitude command differentiates): no
    // difference across them.
    let switches: Vec<f64> = out
        .switches
        .iter()
        .map(|w| w.t)
        .chain(out.event_times.iter().map(|e| e.t))
        .collect();
    for k in 2..s.len() - 2 {
        let (t, f) = imu[k];
        if switches.iter().any(|w| (w - t).abs() <= 2.5 * h) {
            continue;
        }
        assert!((t - s[k].t).abs() < 1e-12);
        let (pm2, pm1, p0, pp1, pp2) = (
            point(k - 2),
            point(k - 1),
            point(k),
            point(k + 1),
            point(k + 2),
        );
        let acc: [f64; 3] = std::array::from_fn(|i| {
            (-pp2[i] + 16.0 * pp1[i] - 30.0 * p0[i] + 16.0 * pm1[i] - pm2[i]) / (12.0 * h * h)
        });
        let sf = [acc[0], acc[1], acc[2] - paper::GRAVITY];
        let r = s[k].r;
        let body: [f64; 3] = std::array::from_fn(|j| (0..3).map(|i| r[i][j] * sf[i]).sum());
        let sensor: [f64; 3] = std::array::from_fn(|j| (0..3).map(|i| rows[i][j] * body[i]).sum());
        let w = s[k].omega;
        largest_lever = largest_lever.max((w[0] * w[0] + w[1] * w[1] + w[2] * w[2]) * 0.0616);
        for i in 0..3 {
            if (sensor[i] - f[i]).abs() > worst {
                worst_t = t;
            }
            worst = worst.max((sensor[i] - f[i]).abs());
        }
    }
    println!(
        "accelerometer vs d²/dt²(x + R p): {worst:.2e} m/s² at {worst_t} (|Ω|²|p| up to {largest_lever:.1} m/s²)"
    );
    assert!(worst < 1e-6, "{worst}");
    assert!(largest_lever > 1.0);
}

/// Bad settings, each refused before the first step naming the field.
#[test]
fn bad_sensor_settings_are_refused() {
    let scene = figure_eight();
    let build = |suite: SensorSuite, est: bool, scene: &Scene| {
        let mut b = scenes::builder::<B>(scene).unwrap().sensors(suite, 0);
        if est {
            b = b.estimator(Box::new(MocapEstimator::<B>::new()));
        }
        b.build().map(|_| ()).unwrap_err().to_string()
    };
    let e = build(SensorSuite::preset("mpu9250").unwrap(), true, &scene);
    assert!(e.contains("`mocap` needs the sensor `mocap`"), "{e}");
    let continuous = scenes::builtin::figure_eight();
    let e = build(SensorSuite::preset("rotorpy").unwrap(), true, &continuous);
    assert!(e.contains("needs sampled control"), "{e}");
    let mut late = MocapSpec::crazyflie();
    late.latency = 10.0;
    let e = build(mocap_only(late), true, &scene);
    assert!(
        e.contains("mocap.latency = 10 s is not shorter than the run"),
        "{e}"
    );
    let mut neg = MocapSpec::crazyflie();
    neg.position_sigma = -1.0;
    let e = build(mocap_only(neg), false, &scene);
    assert!(e.contains("mocap.position_sigma = -1"), "{e}");
}

/// The same seed gives the same measurements and flight, recorded or not;
/// another seed other noise; and a sensor's noise does not change when
/// another sensor is added (its stream is keyed on its own number).
#[test]
fn noise_is_keyed_on_the_seed_and_the_sensor() {
    let scene = figure_eight();
    let fly = |suite: SensorSuite, seed: u64, record: bool| {
        let out = scenes::builder::<B>(&scene)
            .unwrap()
            .sensors(suite, seed)
            .estimator(Box::new(MocapEstimator::<B>::new()))
            .build()
            .unwrap()
            .run(RunOptions {
                record,
                ..Default::default()
            })
            .unwrap();
        let frames: Vec<[f64; 3]> = out
            .measurements
            .iter()
            .filter_map(|m| match m {
                MeasurementRecord::Mocap { state, .. } => Some(state.x),
                _ => None,
            })
            .collect();
        (frames, out.last.x)
    };
    let rotorpy = SensorSuite::preset("rotorpy").unwrap();
    let mocap = mocap_only(rotorpy.mocap.unwrap());
    let (a, end_a) = fly(rotorpy, 9, true);
    let (_, end_unrecorded) = fly(rotorpy, 9, false);
    let (b, end_b) = fly(mocap, 9, true);
    let (c, _) = fly(rotorpy, 10, true);
    assert_eq!(end_a, end_unrecorded, "recording changes nothing");
    assert_eq!(
        a, b,
        "the IMU on or off leaves the mocap's noise and the flight alone"
    );
    assert_eq!(end_a, end_b);
    assert_ne!(a[5], c[5], "another seed, other noise");
}

/// With an estimator, a Ψ switch reads the estimate at the control
/// instants, as a flight computer's scheduler does: on the tumble recovery
/// (attitude mode until Ψ < 0.1, then position) under 100 Hz control on a
/// perfect tracker, the switch falls on a control instant, the first at
/// which Ψ of the true state (which the perfect tracker reports) is below
/// the threshold; without an estimator it is located between instants.
#[test]
fn a_psi_switch_reads_the_estimate_at_control_instants() {
    let mut scene = sampled(scenes::builtin::tumble_recovery(), 100.0);
    scene.record.sample = 0.01;
    let sensed = run(&scene, Some(mocap_only(MocapSpec::perfect(100.0))), true).unwrap();
    let located = run(&scene, None, false).unwrap();
    let (ts, tl) = (sensed.switches[0].t, located.switches[0].t);
    let k = (ts * 100.0).round();
    assert!((ts - k / 100.0).abs() < 1e-12, "on a control instant: {ts}");
    // The sample just before is above the threshold, the one at it below.
    let at = |t: f64| {
        sensed
            .samples
            .iter()
            .find(|s| (s.t - t).abs() < 1e-9 && s.segment == 0)
            .map(|s| s.psi)
    };
    let before = at((k - 1.0) / 100.0).expect("a sample before the switch");
    assert!(before >= 0.1, "Ψ = {before} a control period before");
    assert!(
        tl <= ts && ts - tl < 0.01 + 1e-12,
        "located {tl}, on the estimate {ts}"
    );
    println!(
        "Ψ switch: located at {tl:.6} s on the truth, at the control instant {ts} on the estimate"
    );
}
