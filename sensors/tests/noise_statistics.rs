//! The IMU's noise against the statistics it declares: per-sample σ from
//! the density, the Allan deviation of white noise and of a bias random
//! walk, the spread of the turn-on bias. Each bound says its confidence.

use lie::NalgebraF64 as B;
use sensors::{Imu, ImuSpec, Kinematics, NoiseKey, TriadErrors};

const G: f64 = 9.81;

/// `n` samples of a static IMU minus its ideal reading: per axis, the
/// accelerometer's errors then the gyroscope's.
fn errors(spec: ImuSpec, key: NoiseKey, n: usize) -> [Vec<f64>; 6] {
    let mut imu = Imu::<B>::new(spec, key).unwrap();
    let kin = Kinematics::<B>::at_rest();
    let (ia, ig) = imu.ideal(&kin, G);
    let mut out: [Vec<f64>; 6] = Default::default();
    for o in &mut out {
        o.reserve(n);
    }
    for k in 0..n as u64 {
        let s = imu.sample(k, &kin, G).unwrap();
        let (a, g) = (s.accel - ia, s.gyro - ig);
        for i in 0..3 {
            out[i].push(a[i]);
            out[3 + i].push(g[i]);
        }
    }
    out
}

/// The overlapping Allan deviation of rate samples `y` (rate `f`) at
/// cluster size `m` (τ = m/f; IEEE Std 952), from the integrated signal.
fn allan(y: &[f64], f: f64, m: usize) -> f64 {
    let dt = 1.0 / f;
    let mut theta = Vec::with_capacity(y.len() + 1);
    let mut acc = 0.0;
    theta.push(0.0);
    for v in y {
        acc += v * dt;
        theta.push(acc);
    }
    let n = theta.len();
    let tau = m as f64 * dt;
    let terms = n - 2 * m;
    let s: f64 = (0..terms)
        .map(|i| {
            let d = theta[i + 2 * m] - 2.0 * theta[i + m] + theta[i];
            d * d
        })
        .sum();
    (s / (2.0 * tau * tau * terms as f64)).sqrt()
}

fn std_dev(x: &[f64]) -> f64 {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    (x.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
}

/// Per-sample σ = density·√rate on every axis of both triads, for RotorPy's
/// preset at its 100 Hz (σ = √(f/2)·0.038² and √(f/2)·0.01²: RotorPy's own
/// formula, written out independently of the preset's density) and the
/// Crazyflie's: over 10⁵ samples the sample σ has a relative standard
/// error of 1/√(2n) = 0.22 %, so 1.5 % is seven of them.
#[test]
fn per_sample_sigma_is_density_times_root_rate() {
    let f = 100.0f64;
    let rotorpy = [
        (f / 2.0).sqrt() * 0.038 * 0.038,
        (f / 2.0).sqrt() * 0.01 * 0.01,
    ];
    let cf = [
        175e-6 * 9.806_65 * 1000f64.sqrt(),
        0.014f64.to_radians() * 1000f64.sqrt(),
    ];
    for (spec, want) in [(ImuSpec::rotorpy(f), rotorpy), (ImuSpec::crazyflie(), cf)] {
        let e = errors(spec, NoiseKey::new(11, 2), 100_000);
        for (axis, x) in e.iter().enumerate() {
            let (got, w) = (std_dev(x), want[axis / 3]);
            eprintln!("axis {axis}: per-sample σ / declared = {:.4}", got / w);
            assert!(
                (got / w - 1.0).abs() < 0.015,
                "axis {axis}: σ {got:e}, declared {w:e}"
            );
        }
    }
}

/// One hour of a static white-noise-only IMU at 1 kHz: the overlapping
/// Allan deviation at τ = 1 s is each axis's declared density within 5 %
/// (its relative confidence at 3599 clusters is 1/√(2·3599) = 1.2 %, so
/// 5 % is four of them); at τ = 10 s it has fallen as 1/√τ.
#[test]
fn white_noise_allan_deviation_at_one_second_is_the_density() {
    let spec = ImuSpec::crazyflie();
    let e = errors(spec, NoiseKey::new(5, 0), 3_600_000);
    for (axis, y) in e.iter().enumerate() {
        let n = if axis < 3 {
            spec.accel.noise_density
        } else {
            spec.gyro.noise_density
        };
        let a1 = allan(y, spec.rate, 1000);
        assert!(
            (a1 / n - 1.0).abs() < 0.05,
            "axis {axis}: σ_A(1 s) {a1:e}, density {n:e}"
        );
        let a10 = allan(y, spec.rate, 10_000);
        let r = a10 * 10f64.sqrt() / n;
        eprintln!(
            "axis {axis}: σ_A(1 s)/N = {:.4}, σ_A(10 s)·√10/N = {r:.4}",
            a1 / n
        );
        // 359 clusters: 3.7 % relative; 15 % is four of them.
        assert!((r - 1.0).abs() < 0.15, "axis {axis}: σ_A(10 s)·√10/N = {r}");
    }
}

/// Ten independent hours of a random-walk-only IMU (K = 1e-3 /√s at
/// 100 Hz), the Allan variances of the 30 accelerometer axes averaged:
/// the slope of log σ_A against log τ over τ ∈ [100, 1000] s is 0.5 within
/// 0.05, and σ_A(100 s) is K·√(τ/3) within 10 % (30 records of 34
/// clusters each: a relative spread near 3 %).
#[test]
fn random_walk_allan_deviation_rises_as_root_tau() {
    let k_walk = 1e-3;
    let spec = ImuSpec::aligned(
        100.0,
        TriadErrors {
            random_walk: k_walk,
            ..TriadErrors::NONE
        },
        TriadErrors::NONE,
    );
    let taus = [100.0, 200.0, 400.0, 700.0, 1000.0];
    let mut avar = [0.0; 5];
    let mut records = 0.0;
    for hour in 0..10 {
        let e = errors(spec, NoiseKey::new(100 + hour, 0), 360_000);
        for y in &e[..3] {
            for (a, tau) in avar.iter_mut().zip(taus) {
                *a += allan(y, spec.rate, (tau * spec.rate) as usize).powi(2);
            }
            records += 1.0;
        }
    }
    let sigma: Vec<f64> = avar.iter().map(|a| (a / records).sqrt()).collect();
    let (lx, ly): (Vec<f64>, Vec<f64>) = taus
        .iter()
        .zip(&sigma)
        .map(|(t, s)| (t.ln(), s.ln()))
        .unzip();
    let (mx, my) = (lx.iter().sum::<f64>() / 5.0, ly.iter().sum::<f64>() / 5.0);
    let slope = lx
        .iter()
        .zip(&ly)
        .map(|(x, y)| (x - mx) * (y - my))
        .sum::<f64>()
        / lx.iter().map(|x| (x - mx).powi(2)).sum::<f64>();
    eprintln!("random walk: slope {slope:.4} over τ ∈ [100, 1000] s");
    assert!((slope - 0.5).abs() < 0.05, "slope {slope}, σ_A {sigma:?}");
    let level = sigma[0] / (k_walk * (100.0f64 / 3.0).sqrt());
    eprintln!("random walk: σ_A(100 s) / K√(τ/3) = {level:.4}");
    assert!((level - 1.0).abs() < 0.10, "σ_A(100 s) / K√(τ/3) = {level}");
}

/// The turn-on bias: over 4000 IMUs (sensor numbers), each axis's starting
/// bias has the declared σ within 5 standard errors (1/√(2n) = 1.1 %
/// relative, so 5.6 %), and it stays put without a walk.
#[test]
fn turn_on_bias_has_its_declared_spread() {
    let sd = 0.02;
    let spec = ImuSpec::aligned(
        100.0,
        TriadErrors {
            turn_on_bias: sd,
            ..TriadErrors::NONE
        },
        TriadErrors {
            turn_on_bias: 2.0 * sd,
            ..TriadErrors::NONE
        },
    );
    let mut b: [Vec<f64>; 6] = Default::default();
    for sensor in 0..4000 {
        let e = errors(spec, NoiseKey::new(1, sensor), 3);
        for (axis, x) in e.iter().enumerate() {
            assert_eq!(x[0], x[2], "no walk: the bias stays");
            b[axis].push(x[0]);
        }
    }
    for (axis, x) in b.iter().enumerate() {
        let want = if axis < 3 { sd } else { 2.0 * sd };
        let got = std_dev(x);
        eprintln!("axis {axis}: turn-on bias σ / declared = {:.4}", got / want);
        assert!(
            (got / want - 1.0).abs() < 0.056,
            "axis {axis}: {got} vs {want}"
        );
    }
}
