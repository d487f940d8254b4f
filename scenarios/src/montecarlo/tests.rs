use super::*;

/// Kolmogorov–Smirnov statistic of `xs` against the CDF `f`.
fn ks(mut xs: Vec<f64>, f: impl Fn(f64) -> f64) -> f64 {
    xs.sort_by(f64::total_cmp);
    let n = xs.len() as f64;
    xs.iter()
        .enumerate()
        .map(|(i, &x)| {
            let c = f(x);
            (c - i as f64 / n).abs().max(((i + 1) as f64 / n - c).abs())
        })
        .fold(0.0, f64::max)
}

fn setup() -> Setup {
    Setup::default()
}

/// The rotation angle of a uniform rotation has density (1 − cos θ)/π,
/// CDF (θ − sin θ)/π. With n = 20 000 the KS critical value at
/// α = 0.001 is 1.949/√n = 0.0138; a naive sampler (a uniform rotation
/// vector in the ball of radius π) must fail the same test.
#[test]
fn shoemake_angles_pass_kolmogorov_smirnov() {
    let n = 20_000;
    let cdf = |th: f64| (th - th.sin()) / std::f64::consts::PI;
    let crit = 1.949 / (n as f64).sqrt();
    let angles: Vec<f64> = (0..n)
        .map(|i| {
            let q = shoemake(&mut stream(7, i));
            Initial {
                q,
                omega: [0.0; 3],
                x: [0.0; 3],
                v: [0.0; 3],
            }
            .angle()
        })
        .collect();
    let d = ks(angles, cdf);
    println!("KS D = {d:.5} (critical {crit:.5} at α = 0.001, n = {n})");
    assert!(d < crit, "D = {d}");
    let naive: Vec<f64> = (0..n)
        .map(|i| {
            let p = in_ball(&mut stream(7, i), std::f64::consts::PI);
            (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()
        })
        .collect();
    let dn = ks(naive, cdf);
    println!("naive sampler: KS D = {dn:.5}");
    assert!(
        dn > 5.0 * crit,
        "the test must reject a naive sampler: D = {dn}"
    );
}

/// A sample's numbers depend on (seed, index) only, and stay in their
/// balls.
#[test]
fn streams_are_keyed_by_seed_and_index() {
    let s = setup();
    assert_eq!(s.initial(5), s.initial(5));
    assert_ne!(s.initial(5), s.initial(6));
    let mut s2 = s.clone();
    s2.seed = 2;
    assert_ne!(s.initial(5), s2.initial(5));
    for i in 0..200 {
        let p = s.initial(i);
        let n = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        assert!(n(p.omega) <= s.omega_max && n(p.x) <= s.x_max && n(p.v) <= s.v_max);
        assert!((p.q.iter().map(|c| c * c).sum::<f64>() - 1.0).abs() < 1e-15);
    }
}

/// Sample 4331 of seed 1 blows up (|Ω| ~ 10⁵ rad/s within 2 s): the
/// guard's substep cap stops it inside one dopri call (before the cap it
/// took 4.9·10⁶ steps) and it counts as diverged.
#[test]
fn a_blow_up_is_diverged_and_cheap() {
    let r = setup().run_sample(4331).unwrap();
    assert_eq!(r.status, Status::Diverged);
    assert!(!r.converged && r.t_converge.is_nan());
}

/// One thread or two give the same rows, and the rows survive the CSV.
#[test]
fn rows_do_not_depend_on_threads_and_round_trip() {
    let mut s = setup();
    s.deadline = 2.0;
    let all: Vec<u64> = (0..6).collect();
    let one = s.run(&all, Some(1), None).unwrap();
    let two = s.run(&all, Some(2), None).unwrap();
    // As text: NaN (not converged) is not equal to itself as f64.
    assert_eq!(write_samples(&one), write_samples(&two));
    let back = parse_samples(&write_samples(&one)).unwrap();
    assert_eq!(write_samples(&back), write_samples(&one));
    assert!(parse_samples("index\n").is_err());
}

/// The hold: enters at the interpolated crossing, resets when the
/// tolerance is lost, and ignores earlier (bisection) times.
#[test]
fn settled_interpolates_and_resets() {
    let mut h = Settled::new(0.5);
    assert!(!h.check(0.0, 3.0));
    assert!(!h.check(1.0, 0.5)); // crossing of 1 at 0.8
    assert!((h.entered().unwrap() - 0.8).abs() < 1e-15);
    assert!(!h.check(1.2, 0.9));
    assert!(h.check(1.4, 0.8));
    // A bisection call inside the last step reads without changing.
    assert!(!h.check(1.25, 0.8));
    assert!(h.check(1.35, 0.8));
    assert!(!h.check(1.5, 1.5));
    assert_eq!(h.entered(), None);
}

/// The summary counts by status and takes nearest-rank percentiles of
/// the converged samples only.
#[test]
fn summary_counts_and_percentiles() {
    let rows = (1..=100).map(|k| (Status::Converged, k as f64, 10)).chain([
        (Status::Deadline, f64::NAN, 5),
        (Status::Diverged, f64::NAN, 5),
        (Status::Error, f64::NAN, 0),
    ]);
    let s = Summary::from_rows(rows);
    assert_eq!(
        (s.samples, s.converged, s.deadline, s.diverged, s.errors),
        (103, 100, 1, 1, 1)
    );
    assert_eq!(s.integrator_steps, 1010);
    assert_eq!(
        (
            s.t_converge.median,
            s.t_converge.p95,
            s.t_converge.p99,
            s.t_converge.worst
        ),
        (50.0, 95.0, 99.0, 100.0)
    );
    assert!(Summary::from_rows([]).t_converge.median.is_nan());
}

/// A cancel flag set before the study skips every sample; set by the
/// progress callback once 16 are done, the study stops early with only
/// finished samples, each the same as in a full run.
#[test]
fn a_cancelled_study_returns_only_finished_samples() {
    use std::sync::atomic::{AtomicBool, Ordering};
    let mut s = setup();
    s.experiment = "attitude".into();
    s.deadline = 10.0;
    let all: Vec<u64> = (0..64).collect();
    let study = s.study();
    let set = AtomicBool::new(true);
    assert!(
        study
            .run_until_cancelled(&all, Some(2), None, &set)
            .unwrap()
            .is_empty()
    );
    let flag = AtomicBool::new(false);
    let stop = |n: u64| {
        if n >= 16 {
            flag.store(true, Ordering::Relaxed);
        }
    };
    let part = study
        .run_until_cancelled(&all, Some(2), Some(&stop), &flag)
        .unwrap();
    assert!(part.len() >= 16 && part.len() < 64, "{} of 64", part.len());
    let full = study.run(&all, Some(2), None).unwrap();
    for t in &part {
        let f = &full[t.index as usize];
        assert_eq!(
            (t.status, t.t_settled.map(f64::to_bits)),
            (f.status, f.t_settled.map(f64::to_bits))
        );
    }
    assert!(part.windows(2).all(|w| w[0].index < w[1].index));
}
