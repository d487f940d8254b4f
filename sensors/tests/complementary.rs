//! The passive complementary filter on the known motion of `motion`:
//! convergence from large attitude errors with the rate the paper's
//! linearisation gives, the gyro bias found, the noise it leaves, and
//! bad input refused.

mod motion;
use lie::{So3Mat, ops};
use motion::{B, G, truth, v};
use sensors::{
    Complementary, ComplementaryConfig, Estimator, Imu, ImuSpec, Measurement, Mocap, MocapSpec,
    NoiseKey, TriadErrors,
};

/// Attitude error every 10 ms and the final gyro-bias error, over `secs`
/// from `offset` rad off about a fixed axis; the IMU with a turn-on gyro
/// bias of `bias` (per axis, this seed's draw), mocap at 100 Hz.
fn run(
    cfg: ComplementaryConfig,
    secs: f64,
    offset: f64,
    bias: f64,
    noise: bool,
) -> (Vec<f64>, f64) {
    let mut spec = ImuSpec::crazyflie();
    spec.gyro = TriadErrors {
        turn_on_bias: bias,
        ..spec.gyro
    };
    let mut mocap = MocapSpec {
        latency: 0.0,
        ..MocapSpec::crazyflie()
    };
    if !noise {
        spec = spec.noiseless();
        spec.gyro.turn_on_bias = bias;
        mocap = MocapSpec::perfect(100.0);
    }
    let mut imu = Imu::<B>::new(spec, NoiseKey::new(5, 0)).unwrap();
    let mocap = Mocap::new(mocap, NoiseKey::new(5, 1)).unwrap();
    let mut f = Complementary::<B>::new(cfg).unwrap();
    let (r0, v0, x0, _, _) = truth(0.0);
    let axis = [0.6, -0.48, 0.64].map(|c| c * offset);
    f.reset_to(0.0, r0.compose(So3Mat::exp(v(axis))), x0, v0);
    let mut errs = vec![];
    for k in 0..=(secs * 1000.0) as u64 {
        let t = k as f64 / 1000.0;
        let (r, vel, x, a, w) = truth(t);
        if k % 10 == 0 && k > 0 {
            if let Some(m) = mocap.frame::<B>(k / 10, x, vel, r.as_matrix(), w) {
                f.update(&Measurement::Mocap(m));
            }
            let est = f.estimate(t);
            let e = So3Mat::from_matrix_unchecked(est.r)
                .inverse()
                .compose(r)
                .log();
            errs.push(ops::norm::<B>(e));
        }
        let kin = sensors::Kinematics::<B> {
            r: r.as_matrix(),
            omega: w,
            accel: a,
            alpha: v([0.0; 3]),
        };
        f.update(&Measurement::Imu(imu.sample(k, &kin, G).unwrap()));
    }
    let b = imu.biases()[1];
    let be = ops::vec3_f64::<B>(f.bias());
    let bias_err = (0..3).map(|i| (be[i] - b[i]).powi(2)).sum::<f64>().sqrt();
    (errs, bias_err)
}

fn settle(errs: &[f64], below: f64) -> Option<f64> {
    match errs.iter().rposition(|e| *e >= below) {
        Some(i) if i + 1 == errs.len() => None,
        Some(i) => Some((i + 2) as f64 * 0.01),
        None => Some(0.01),
    }
}

#[test]
fn converges_from_large_errors_at_the_predicted_rate() {
    // The bias loop off: with it, the bias integrates the large error
    // too and then takes k_P/k_I to unwind (shown, not bounded, below).
    let cfg = ComplementaryConfig {
        k_i: 0.0,
        ..ComplementaryConfig::default()
    };
    for deg in [90.0f64, 170.0] {
        let (errs, _) = run(cfg, 10.0, deg.to_radians(), 0.0, false);
        let t = settle(&errs, 2f64.to_radians());
        let (with_bias, _) = run(
            ComplementaryConfig::default(),
            30.0,
            deg.to_radians(),
            0.0,
            false,
        );
        println!(
            "complementary from {deg}° with the bias loop on: below 2° for good after {:?} s",
            settle(&with_bias, 2f64.to_radians())
        );
        // Without noise or bias the error angle obeys θ̇ = −k_P sin θ
        // (R̂ᵀR_y is a rotation by θ; its skew part is sin θ times the
        // axis), so tan(θ/2) decays as e^{−k_P t}: from θ₀ to 2° takes
        // ln(tan(θ₀/2)/tan(1°))/k_P.
        let want = ((deg.to_radians() / 2.0).tan() / 1f64.to_radians().tan()).ln() / cfg.k_p;
        println!(
            "complementary from {deg}°: below 2° for good after {t:?} s (predicted {want:.3} s)"
        );
        // The discrete correction every 10 ms and the 10 ms sampling of
        // the error: within two samples of the prediction.
        let t = t.expect("did not converge");
        assert!((t - want).abs() <= 0.025, "{t} vs {want}");
    }
}

#[test]
fn finds_the_gyro_bias_and_holds_the_attitude_under_noise() {
    let cfg = ComplementaryConfig::default();
    let (errs, bias_err) = run(cfg, 30.0, 0.0, 0.01, true);
    let tail = &errs[errs.len() - 1000..];
    let rms = (tail.iter().map(|e| e * e).sum::<f64>() / tail.len() as f64).sqrt();
    println!(
        "complementary, BMI088 noise, 4.5 mrad mocap, 0.01 rad/s turn-on bias: last 10 s attitude RMS {:.3} mrad, bias error {bias_err:.2e} rad/s after 30 s",
        rms * 1e3
    );
    // The bias loop's time constant is k_P/k_I = 10 s: after three of
    // them the bias error is a few % of its 0.017 rad/s start, plus the
    // noise the mocap's 4.5 mrad lets through (k_I·σ·√(Δ·τ) ≈ 1e-4).
    assert!(bias_err < 1.5e-3, "{bias_err:e}");
    // The mocap's σ = 4.5 mrad per axis, filtered with k_P Δ = 0.02:
    // σ·√(3·k_PΔ/2) ≈ 1 mrad, plus the gyro noise's share; 2 mrad bounds it.
    assert!(rms < 2e-3, "{rms:e}");
}

#[test]
fn bad_gains_and_non_finite_input() {
    let cfg = ComplementaryConfig {
        k_p: 20.0,
        ..ComplementaryConfig::default()
    };
    let e = Complementary::<B>::new(cfg).unwrap_err().to_string();
    assert_eq!(
        e,
        "complementary.max_interval = 0.1: must be positive, with k_p·max_interval below 1"
    );
    let cfg = ComplementaryConfig {
        k_i: f64::NAN,
        ..ComplementaryConfig::default()
    };
    assert!(
        Complementary::<B>::new(cfg)
            .unwrap_err()
            .to_string()
            .starts_with("complementary.k_i = NaN")
    );
    let mut f = Complementary::<B>::new(ComplementaryConfig::default()).unwrap();
    let s = sensors::ImuSample::<B> {
        k: 0,
        t: 0.0,
        accel: v([0.0, 0.0, -G]),
        gyro: v([f64::NAN, 0.0, 0.0]),
        attitude: None,
    };
    f.update(&Measurement::Imu(s));
    assert_eq!(f.rejections(), 1);
    let est = f.estimate(1.0);
    assert!(ops::is_finite_mat::<B>(est.r) && ops::is_finite_vec::<B>(est.omega));
}
