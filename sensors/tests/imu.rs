//! The IMU model against closed forms and finite differences, its noise
//! against the statistics it declares, its keyed noise against order and
//! neighbours, and its checks of bad settings.

use lie::{Backend, GlamF32, GlamF64, NalgebraF64, S, V3};
use nalgebra::{Matrix3, Rotation3, Unit, Vector3};
use sensors::{Imu, ImuSpec, Kinematics, NoiseKey, SensorError, TriadErrors};

const G: f64 = 9.81;

fn v<B: Backend>(a: [f64; 3]) -> V3<B> {
    let [x, y, z] = a.map(S::<B>::lit);
    B::vec3(x, y, z)
}

fn arr<B: Backend>(x: V3<B>) -> [f64; 3] {
    lie::ops::vec3_f64::<B>(x)
}

/// A level IMU at rest reads −g along b3 (e3 points down; the specific
/// force is what holds it up), exactly, on every backend and in f32; a
/// mounting turns both triads by R_BSᵀ.
fn at_rest_and_mounted<B: Backend>() {
    let mut imu = Imu::<B>::new(ImuSpec::crazyflie().noiseless(), NoiseKey::new(0, 0)).unwrap();
    let s = imu
        .sample(0, &Kinematics::<B>::at_rest(), S::<B>::lit(G))
        .unwrap();
    assert_eq!(
        arr::<B>(s.accel),
        [0.0, 0.0, -(S::<B>::lit(G).to_f64_lossless())]
    );
    assert_eq!(arr::<B>(s.gyro), [0.0; 3]);

    // The sensor's y axis along body −b3... its columns in the body frame:
    // x_S = b1, y_S = b3, z_S = −b2 (a quarter turn about b1).
    let mut spec = ImuSpec::crazyflie().noiseless();
    spec.mounting = [[1.0, 0.0, 0.0], [0.0, 0.0, -1.0], [0.0, 1.0, 0.0]];
    let mut imu = Imu::<B>::new(spec, NoiseKey::new(0, 0)).unwrap();
    let mut kin = Kinematics::<B>::at_rest();
    kin.omega = v::<B>([1.0, 2.0, 3.0]);
    let s = imu.sample(0, &kin, S::<B>::lit(G)).unwrap();
    // R_BSᵀ [0, 0, −g] = [0, −g, 0]; R_BSᵀ [1, 2, 3] = [1, 3, −2]: by hand.
    let a = arr::<B>(s.accel);
    let g = S::<B>::lit(G).to_f64_lossless();
    assert_eq!(a.map(|x| x + 0.0), [0.0, -g, 0.0], "{a:?}");
    assert_eq!(arr::<B>(s.gyro).map(|x| x + 0.0), [1.0, 3.0, -2.0]);
}

use lie::Real;

#[test]
fn a_level_imu_at_rest_reads_minus_g_along_b3() {
    at_rest_and_mounted::<NalgebraF64>();
    at_rest_and_mounted::<GlamF64>();
    at_rest_and_mounted::<GlamF32>();
}

/// A closed-form motion: x(t), and R = Exp(φ₁ u) Exp(φ₂ w) with its body
/// rates Ω = R₂ᵀu φ̇₁ + w φ̇₂ and their derivative
/// α = R₂ᵀu φ̈₁ − φ̇₁φ̇₂ w × R₂ᵀu + w φ̈₂ (from Ṙ₂ᵀ = −[w φ̇₂]× R₂ᵀ).
struct Motion;

impl Motion {
    fn u() -> Unit<Vector3<f64>> {
        Unit::new_normalize(Vector3::new(0.3, -0.5, 0.8))
    }
    fn w() -> Unit<Vector3<f64>> {
        Unit::new_normalize(Vector3::new(-0.6, 0.2, 0.4))
    }
    fn phi(t: f64) -> [[f64; 3]; 2] {
        [
            [
                0.7 * t + 0.2 * (3.0 * t).sin(),
                0.7 + 0.6 * (3.0 * t).cos(),
                -1.8 * (3.0 * t).sin(),
            ],
            [
                0.5 * (1.3 * t).sin(),
                0.65 * (1.3 * t).cos(),
                -0.845 * (1.3 * t).sin(),
            ],
        ]
    }
    fn x(t: f64) -> Vector3<f64> {
        Vector3::new(t.sin(), (2.0 * t).cos(), 0.3 * t * t)
    }
    fn a(t: f64) -> Vector3<f64> {
        Vector3::new(-t.sin(), -4.0 * (2.0 * t).cos(), 0.6)
    }
    fn r(t: f64) -> Matrix3<f64> {
        let [p1, p2] = Self::phi(t);
        (Rotation3::from_axis_angle(&Self::u(), p1[0])
            * Rotation3::from_axis_angle(&Self::w(), p2[0]))
        .into_inner()
    }
    fn rates(t: f64) -> (Vector3<f64>, Vector3<f64>) {
        let [p1, p2] = Self::phi(t);
        let r2 = Rotation3::from_axis_angle(&Self::w(), p2[0]).into_inner();
        let (u, w) = (Self::u().into_inner(), Self::w().into_inner());
        let r2u = r2.transpose() * u;
        let omega = r2u * p1[1] + w * p2[1];
        let alpha = r2u * p1[2] - w.cross(&r2u) * (p1[1] * p2[1]) + w * p2[2];
        (omega, alpha)
    }
}

/// The lever-arm terms: the specific force at a sensor 10 cm off the
/// centre of mass equals Rᵀ(ÿ − g e3) for its world position
/// y = x + R p, ÿ from a fourth-order central difference of y (h = 2 ms:
/// truncation h⁴/90·|y⁽⁶⁾| ≈ 1e-12, rounding ≈ 16ε|y|/(12h²) ≈ 1e-10;
/// the bound, 1e-8, is a hundred times that floor).
#[test]
fn the_lever_arm_terms_are_the_second_derivative_of_the_sensor_point() {
    type B = NalgebraF64;
    let p = Vector3::new(0.1, -0.04, 0.03);
    let mut spec = ImuSpec::crazyflie().noiseless();
    spec.position = p.into();
    let mut imu = Imu::<B>::new(spec, NoiseKey::new(0, 0)).unwrap();
    let y = |t: f64| Motion::x(t) + Motion::r(t) * p;
    let h = 2e-3;
    let mut worst = 0.0f64;
    for (k, t) in (0..50).map(|i| (i as u64, 0.37 * i as f64)) {
        let (omega, alpha) = Motion::rates(t);
        let kin = Kinematics::<B> {
            r: Motion::r(t),
            omega,
            accel: Motion::a(t),
            alpha,
        };
        let s = imu.sample(k, &kin, G).unwrap();
        let ydd = (-y(t + 2.0 * h) + y(t + h) * 16.0 - y(t) * 30.0 + y(t - h) * 16.0
            - y(t - 2.0 * h))
            / (12.0 * h * h);
        let want = Motion::r(t).transpose() * (ydd - Vector3::new(0.0, 0.0, G));
        worst = worst.max((s.accel - want).amax());
        assert!((s.gyro - omega).amax() == 0.0);
    }
    assert!(
        worst < 1e-8,
        "lever arm against finite differences: {worst:e}"
    );
    // And the rates are those of R: Ω against (Rᵀ Ṙ)∨ by a central
    // difference (h² truncation ≈ 1e-6 at h = 2 ms).
    let t = 1.1;
    let rd = (Motion::r(t + h) - Motion::r(t - h)) / (2.0 * h);
    let w = Motion::r(t).transpose() * rd;
    let omega_fd = Vector3::new(w[(2, 1)], w[(0, 2)], w[(1, 0)]);
    assert!((omega_fd - Motion::rates(t).0).amax() < 1e-5);
    let alpha_fd = (Motion::rates(t + h).0 - Motion::rates(t - h).0) / (2.0 * h);
    assert!((alpha_fd - Motion::rates(t).1).amax() < 1e-5);
}

/// Scale factors and misalignment multiply the true reading, saturation
/// clamps it: with noise off, `(I + E)·ideal` clamped to the range.
#[test]
fn scale_misalignment_and_range_act_on_the_ideal_reading() {
    type B = NalgebraF64;
    let e = [
        [0.01, 0.002, 0.0],
        [-0.003, -0.02, 0.001],
        [0.0, 0.004, 0.005],
    ];
    let mut spec = ImuSpec::crazyflie().noiseless();
    spec.accel.scale_misalignment = e;
    spec.accel.range = 9.0;
    spec.gyro.scale_misalignment = e;
    let mut imu = Imu::<B>::new(spec, NoiseKey::new(3, 1)).unwrap();
    let mut kin = Kinematics::<B>::at_rest();
    kin.accel = Vector3::new(2.0, -1.0, 0.5);
    kin.omega = Vector3::new(0.3, -0.2, 1.0);
    let s = imu.sample(0, &kin, G).unwrap();
    let gain = Matrix3::identity() + Matrix3::from_row_slice(e.as_flattened());
    let ideal = kin.accel - Vector3::new(0.0, 0.0, G);
    let want = (gain * ideal).map(|x| x.clamp(-9.0, 9.0));
    assert_eq!(s.accel, want);
    assert_eq!(want[2], -9.0, "the z axis saturates");
    assert_eq!(s.gyro, gain * kin.omega);
}

/// Sample k's noise is a function of (seed, sensor, k): the same whichever
/// samples were taken before it (the bias walk steps through skipped
/// ones), different for another sensor or seed, and samples go forward.
#[test]
fn noise_is_keyed_by_seed_sensor_and_sample() {
    type B = NalgebraF64;
    let mut spec = ImuSpec::mpu9250();
    spec.accel.random_walk = 1e-3;
    spec.gyro.random_walk = 1e-4;
    spec.accel.turn_on_bias = 0.05;
    let kin = Kinematics::<B>::at_rest();
    let run = |key: NoiseKey, every: u64| {
        let mut imu = Imu::<B>::new(spec, key).unwrap();
        (0..200)
            .step_by(every as usize)
            .map(|k| {
                let s = imu.sample(k, &kin, G).unwrap();
                (k, s.accel, s.gyro)
            })
            .collect::<Vec<_>>()
    };
    let all = run(NoiseKey::new(7, 0), 1);
    let fifth = run(NoiseKey::new(7, 0), 5);
    for (k, a, g) in &fifth {
        let (_, a1, g1) = all[*k as usize];
        assert_eq!((a, g), (&a1, &g1), "sample {k}");
    }
    let other_sensor = run(NoiseKey::new(7, 1), 1);
    let other_seed = run(NoiseKey::new(8, 0), 1);
    assert!(all.iter().zip(&other_sensor).all(|(x, y)| x.1 != y.1));
    assert!(all.iter().zip(&other_seed).all(|(x, y)| x.1 != y.1));

    let mut imu = Imu::<B>::new(spec, NoiseKey::new(7, 0)).unwrap();
    imu.sample(10, &kin, G).unwrap();
    let e = imu.sample(9, &kin, G).unwrap_err();
    assert_eq!(e, SensorError::OutOfOrder { k: 9, next: 11 });
    assert_eq!(
        e.to_string(),
        "sample 9 asked for after sample 10: samples go forward only"
    );
}

/// Bad settings are refused before any sample, naming the field and the
/// value.
#[test]
fn bad_settings_name_the_field_and_the_value() {
    let msg = |f: &dyn Fn(&mut ImuSpec)| {
        let mut s = ImuSpec::crazyflie();
        f(&mut s);
        Imu::<NalgebraF64>::new(s, NoiseKey::new(0, 0))
            .unwrap_err()
            .to_string()
    };
    assert_eq!(
        msg(&|s| s.accel.noise_density = -1.0),
        "accel.noise_density = -1: must be finite and not negative"
    );
    assert_eq!(
        msg(&|s| s.gyro.random_walk = f64::NAN),
        "gyro.random_walk = NaN: must be finite and not negative"
    );
    assert_eq!(
        msg(&|s| s.rate = 0.0),
        "rate = 0: must be a positive finite rate in Hz"
    );
    assert_eq!(
        msg(&|s| s.gyro.range = 0.0),
        "gyro.range = 0: must be positive (f64::INFINITY for no limit)"
    );
    // A reflection is orthonormal but not a rotation.
    let m = msg(&|s| s.mounting = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]);
    assert!(
        m.starts_with("mounting = -1: must be a rotation matrix"),
        "{m}"
    );
    let m = msg(&|s| s.mounting[0][1] = 0.1);
    assert!(m.starts_with("mounting = "), "{m}");
    assert!(msg(&|s| s.position[2] = f64::INFINITY).starts_with("position = inf"));
    // The presets themselves are valid.
    for s in [
        ImuSpec::rotorpy(100.0),
        ImuSpec::crazyflie(),
        ImuSpec::mpu9250(),
        ImuSpec::fdcl_gazebo(),
    ] {
        s.validate().unwrap();
    }
    let _ = TriadErrors::NONE;
}
