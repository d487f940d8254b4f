//! Motion capture, GPS and barometer against the statistics they declare,
//! and the noise-free identity the closed loop relies on.

use lie::{NalgebraF64 as B, Rotation, So3Mat};
use nalgebra::{Matrix3, Vector3};
use sensors::{
    Baro, BaroSpec, Estimator, Gps, GpsSpec, Measurement, Mocap, MocapEstimator, MocapSpec,
    NavState, NoiseKey, SensorError, SensorSuite, Spike,
};

fn truth() -> (Vector3<f64>, Vector3<f64>, Matrix3<f64>, Vector3<f64>) {
    let r = So3Mat::<B>::exp(Vector3::new(0.3, -1.2, 2.0)).matrix();
    (
        Vector3::new(1.0, -2.0, -3.0),
        Vector3::new(0.5, 0.25, -0.125),
        r,
        Vector3::new(0.1, -0.2, 0.3),
    )
}

fn std_dev(x: &[f64]) -> f64 {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
}

/// Per-axis σ of position, velocity, attitude (the right perturbation's
/// log) and rates over 10⁵ frames of the `rotorpy` preset, within 3 % of
/// the declared σ: the relative standard error of a sample σ over n draws
/// is 1/√(2n) = 0.22 %, so 3 % is over 13 standard errors.
#[test]
fn mocap_sigma_per_axis_within_3_percent() {
    let spec = MocapSpec::rotorpy(100.0);
    let m = Mocap::new(spec, NoiseKey::new(7, 1)).unwrap();
    let (x, v, r, w) = truth();
    let n = 100_000u64;
    let mut e: [Vec<f64>; 12] = Default::default();
    for k in 0..n {
        let f = m.frame::<B>(k, x, v, r, w).unwrap();
        let eta = So3Mat::<B>::from_matrix_unchecked(r.transpose() * f.r).log();
        for i in 0..3 {
            e[i].push(f.x[i] - x[i]);
            e[3 + i].push(f.v[i] - v[i]);
            e[6 + i].push(eta[i]);
            e[9 + i].push(f.omega[i] - w[i]);
        }
    }
    let declared = [
        spec.position_sigma,
        spec.velocity_sigma,
        spec.attitude_sigma,
        spec.rate_sigma,
    ];
    for (c, samples) in e.iter().enumerate() {
        let ratio = std_dev(samples) / declared[c / 3];
        println!("channel {c}: sigma / declared = {ratio:.4}");
        assert!((ratio - 1.0).abs() < 0.03, "channel {c}: {ratio}");
    }
    // RotorPy's numbers: √(100/2)·0.0005 m.
    assert!((spec.position_sigma - 50f64.sqrt() * 0.0005).abs() < 1e-18);
}

/// erf by Abramowitz & Stegun 7.1.26 (|error| < 1.5e-7, far below the KS
/// statistic's resolution of 1/√n ≈ 5e-3 here).
fn erf(x: f64) -> f64 {
    let t = 1.0 / (1.0 + 0.327_591_1 * x.abs());
    let y = 1.0
        - (((((1.061_405_429 * t - 1.453_152_027) * t) + 1.421_413_741) * t - 0.284_496_736) * t
            + 0.254_829_592)
            * t
            * (-x * x).exp();
    y.copysign(x)
}

/// The Kolmogorov distribution's tail: the p-value of the KS statistic `d`
/// over `n` samples (Stephens' small-sample correction).
fn ks_p(d: f64, n: usize) -> f64 {
    let sn = (n as f64).sqrt();
    let lambda = (sn + 0.12 + 0.11 / sn) * d;
    let mut p = 0.0;
    for k in 1..100 {
        let k = k as f64;
        p += 2.0 * (-1f64).powf(k - 1.0) * (-2.0 * k * k * lambda * lambda).exp();
    }
    p.clamp(0.0, 1.0)
}

/// The rotation angle between the true and the reported attitude follows
/// the Maxwell distribution of |η| for η ~ N(0, σ²I) (its angle is |η|
/// below π). A KS test over 20 000 frames (fixed seed, so the p-value is a
/// fixed number, printed); p > 0.01 is the test's bound. σ = 0.2 rad, so
/// the angle is far from the rounding of `Exp` and `Log`.
#[test]
fn mocap_attitude_angle_is_maxwell() {
    let sigma = 0.2;
    let spec = MocapSpec {
        attitude_sigma: sigma,
        ..MocapSpec::perfect(100.0)
    };
    let m = Mocap::new(spec, NoiseKey::new(3, 1)).unwrap();
    let (x, v, r, w) = truth();
    let n = 20_000usize;
    let mut angles: Vec<f64> = (0..n as u64)
        .map(|k| {
            let f = m.frame::<B>(k, x, v, r, w).unwrap();
            So3Mat::<B>::from_matrix_unchecked(r.transpose() * f.r)
                .log()
                .norm()
        })
        .collect();
    angles.sort_by(f64::total_cmp);
    let cdf = |a: f64| {
        let z = a / sigma;
        erf(z / 2f64.sqrt()) - (2.0 / std::f64::consts::PI).sqrt() * z * (-z * z / 2.0).exp()
    };
    let d = angles
        .iter()
        .enumerate()
        .map(|(i, &a)| {
            let f = cdf(a);
            (f - i as f64 / n as f64).max((i + 1) as f64 / n as f64 - f)
        })
        .fold(0.0, f64::max);
    let p = ks_p(d, n);
    println!("Maxwell KS: D = {d:.5}, p = {p:.3} over {n} frames");
    assert!(p > 0.01, "D = {d}, p = {p}");
}

/// Dropouts and spikes at their probabilities: counts over 10⁵ frames
/// within 5 binomial standard deviations.
#[test]
fn dropouts_and_spikes_at_their_rates() {
    let spec = MocapSpec {
        dropout: 0.05,
        velocity_spike: Spike {
            probability: 0.01,
            max: 5.0,
        },
        ..MocapSpec::perfect(100.0)
    };
    let m = Mocap::new(spec, NoiseKey::new(11, 1)).unwrap();
    let (x, v, r, w) = truth();
    let n = 100_000u64;
    let (mut lost, mut spikes, mut kept, mut largest) = (0u64, 0u64, 0u64, 0.0f64);
    for k in 0..n {
        match m.frame::<B>(k, x, v, r, w) {
            None => lost += 1,
            Some(f) => {
                kept += 1;
                let d = (f.v - v).abs().max();
                if d > 0.0 {
                    spikes += 1;
                    largest = largest.max(d);
                    // One axis only.
                    assert_eq!((f.v - v).iter().filter(|c| **c != 0.0).count(), 1);
                }
            }
        }
    }
    let within = |count: u64, trials: u64, p: f64| {
        let mean = trials as f64 * p;
        (count as f64 - mean).abs() < 5.0 * (mean * (1.0 - p)).sqrt()
    };
    println!("lost {lost} of {n}, spikes {spikes} of {kept}, largest {largest}");
    assert!(within(lost, n, 0.05), "lost {lost}");
    assert!(within(spikes, kept, 0.01), "spikes {spikes}");
    assert!(largest <= 5.0 && largest > 4.5);
}

/// A perfect tracker reports the true state bit for bit, and the mocap
/// estimator passes it on bit for bit: what the zero-noise identity of
/// the closed loop rests on.
#[test]
fn perfect_mocap_is_the_truth_bit_for_bit() {
    let m = Mocap::new(MocapSpec::perfect(100.0), NoiseKey::new(1, 1)).unwrap();
    let (x, v, r, w) = truth();
    let f = m.frame::<B>(5, x, v, r, w).unwrap();
    assert_eq!((f.x, f.v, f.r, f.omega), (x, v, r, w));
    assert_eq!(f.t, 0.05);
    let mut est = MocapEstimator::<B>::new();
    est.reset(0.0, &NavState::at_rest());
    est.update(&Measurement::Mocap(f));
    let s = est.estimate(0.05);
    assert_eq!((s.x, s.v, s.r, s.omega), (x, v, r, w));
    assert!(est.needs().mocap && !est.needs().imu);
}

/// The same key gives the same frame whatever was drawn before; another
/// sensor number gives other noise.
#[test]
fn frames_are_keyed() {
    let spec = MocapSpec::rotorpy(100.0);
    let (x, v, r, w) = truth();
    let a = Mocap::new(spec, NoiseKey::new(5, 1)).unwrap();
    let b = Mocap::new(spec, NoiseKey::new(5, 2)).unwrap();
    let f1 = a.frame::<B>(42, x, v, r, w).unwrap();
    for k in 0..10 {
        a.frame::<B>(k, x, v, r, w);
    }
    let f2 = a.frame::<B>(42, x, v, r, w).unwrap();
    assert_eq!(f1.x, f2.x);
    assert_ne!(f1.x, b.frame::<B>(42, x, v, r, w).unwrap().x);
}

/// GPS σ per axis over 10⁵ fixes within 3 % (as above), the barometer's
/// height up (−x₃), its noise σ within 3 %.
#[test]
fn gps_and_baro_statistics() {
    let spec = GpsSpec {
        horizontal_sigma: 0.5,
        vertical_sigma: 1.0,
        velocity_sigma: 0.1,
        ..GpsSpec::fdcl_gazebo()
    };
    let g = Gps::new(spec, NoiseKey::new(9, 2)).unwrap();
    let (x, v, _, _) = truth();
    let n = 100_000u64;
    let mut e: [Vec<f64>; 6] = Default::default();
    for k in 0..n {
        let f = g.fix::<B>(k, x, v);
        for i in 0..3 {
            e[i].push(f.x[i] - x[i]);
            e[3 + i].push(f.v[i] - v[i]);
        }
    }
    let want = [0.5, 0.5, 1.0, 0.1, 0.1, 0.1];
    for c in 0..6 {
        let ratio = std_dev(&e[c]) / want[c];
        assert!((ratio - 1.0).abs() < 0.03, "gps channel {c}: {ratio}");
    }
    let mut b = Baro::new(BaroSpec::white(50.0, 0.3), NoiseKey::new(9, 3)).unwrap();
    let h: Vec<f64> = (0..n)
        .map(|k| b.sample(k, -x[2]).unwrap().height - 3.0)
        .collect();
    let ratio = std_dev(&h) / 0.3;
    assert!((ratio - 1.0).abs() < 0.03, "baro: {ratio}");
    assert!(matches!(
        b.sample(3, 0.0),
        Err(SensorError::OutOfOrder { k: 3, .. })
    ));
}

/// Bad settings name their field and value.
#[test]
fn bad_settings_are_named() {
    let bad = MocapSpec {
        latency: -0.01,
        ..MocapSpec::perfect(100.0)
    };
    let e = Mocap::new(bad, NoiseKey::new(0, 0)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "mocap.latency = -0.01: must be finite and not negative"
    );
    let bad = MocapSpec {
        dropout: 1.0,
        ..MocapSpec::perfect(100.0)
    };
    assert!(
        Mocap::new(bad, NoiseKey::new(0, 0))
            .unwrap_err()
            .to_string()
            .contains("mocap.dropout = 1")
    );
    let bad = GpsSpec {
        rate: f64::NAN,
        ..GpsSpec::fdcl_gazebo()
    };
    assert!(
        Gps::new(bad, NoiseKey::new(0, 0))
            .unwrap_err()
            .to_string()
            .starts_with("gps.rate = NaN")
    );
    assert!(SensorSuite::preset("crazyflie").unwrap().validate().is_ok());
    assert!(SensorSuite::preset("nope").is_none());
    for p in SensorSuite::PRESETS {
        assert!(SensorSuite::preset(p).is_some(), "{p}");
    }
}
