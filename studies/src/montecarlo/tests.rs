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

/// The rotation matrix of a unit quaternion `(w, x, y, z)`, written out
/// here so the test shares no code with the sampler or the scenes.
fn matrix(q: [f64; 4]) -> [[f64; 3]; 3] {
    let [w, x, y, z] = q;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// Kolmogorov–Smirnov statistics of the rotation axes against the uniform
/// law on the sphere (each component of a uniform unit vector is uniform
/// on [−1, 1], Archimedes; the azimuth about e3 is uniform on (−π, π]),
/// and the largest entry of the mean rotation matrix in standard errors
/// (a Haar-uniform R has E[R] = 0 and Var R_ij = 1/3).
fn axis_law(qs: &[[f64; 4]]) -> ([f64; 4], f64) {
    let axes: Vec<[f64; 3]> = qs
        .iter()
        .map(|q| {
            let s = (q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
            [q[1] / s, q[2] / s, q[3] / s]
        })
        .collect();
    let unif = |c: f64| (c + 1.0) / 2.0;
    let comp = |k: usize| ks(axes.iter().map(|a| a[k]).collect(), unif);
    let pi = std::f64::consts::PI;
    let azimuth = ks(axes.iter().map(|a| a[1].atan2(a[0])).collect(), |p| {
        (p + pi) / (2.0 * pi)
    });
    let n = qs.len() as f64;
    let mut mean = [[0.0; 3]; 3];
    for q in qs {
        let r = matrix(*q);
        for i in 0..3 {
            for j in 0..3 {
                mean[i][j] += r[i][j] / n;
            }
        }
    }
    let se = (1.0 / (3.0 * n)).sqrt();
    let worst = mean.iter().flatten().map(|m| m.abs() / se);
    // NaN-safe: a NaN entry makes the figure NaN, which fails `<`.
    let worst = worst.fold(0.0, |a: f64, b| {
        if b.is_nan() || a.is_nan() {
            f64::NAN
        } else {
            a.max(b)
        }
    });
    ([comp(0), comp(1), comp(2), azimuth], worst)
}

/// The whole law of a uniform rotation, not only its angle: the axis is
/// uniform on the sphere (KS on each component and on the azimuth, the
/// same α = 0.001 as for the angle) and the mean of R is zero within 4.5
/// standard errors per entry (nine entries at 4.5σ: a false alarm
/// has probability 6e-5 for a fixed seed that is drawn once). A sampler
/// with the right angle law but an axis drawn from a uniform point in the
/// cube (biased towards the cube's diagonals) must fail the same checks.
#[test]
fn shoemake_axes_are_uniform_and_the_mean_rotation_is_zero() {
    let n = 20_000;
    let crit = 1.949 / (n as f64).sqrt();
    let qs: Vec<[f64; 4]> = (0..n).map(|i| shoemake(&mut stream(7, i))).collect();
    let (d, mean_se) = axis_law(&qs);
    println!("axis KS D (x, y, z, azimuth) = {d:.5?}, critical {crit:.5}; mean R: {mean_se:.2} SE");
    for (k, dk) in d.iter().enumerate() {
        assert!(*dk < crit, "axis statistic {k}: D = {dk} ≥ {crit}");
    }
    assert!(mean_se < 4.5, "mean of R: {mean_se} standard errors");
    // The same angles about axes from the cube: the law of the axis is
    // wrong while the angle marginal is untouched.
    let biased: Vec<[f64; 4]> = (0..n)
        .map(|i| {
            let q = qs[i as usize];
            let half = (q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
            let mut rng = stream(8, i);
            let c = [0; 3].map(|_| 2.0 * uniform(&mut rng) - 1.0);
            let cn = (c[0] * c[0] + c[1] * c[1] + c[2] * c[2]).sqrt();
            [q[0], half * c[0] / cn, half * c[1] / cn, half * c[2] / cn]
        })
        .collect();
    let (db, _) = axis_law(&biased);
    println!("cube-biased axes: KS D = {db:.5?}");
    assert!(
        db.iter().any(|x| *x > 2.0 * crit),
        "the test must reject an axis-biased sampler: {db:?}"
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
    // A run cut off by the cap reports no final figures (they would be
    // the blown-up state's).
    assert!(
        r.final_psi.is_nan() && r.final_ex.is_nan(),
        "{} {}",
        r.final_psi,
        r.final_ex
    );
}

/// One thread or two give the same rows, and the rows survive the CSV.
#[test]
fn rows_do_not_depend_on_threads_and_round_trip() {
    let mut s = setup();
    s.deadline = 2.0;
    let all: Vec<u64> = (0..6).collect();
    let one = s.run(&all, Some(1), None).unwrap();
    let two = s.run(&all, Some(2), None).unwrap();
    let order: Vec<u64> = one.iter().map(|r| r.index).collect();
    assert_eq!(order, all, "one row per sample, in index order");
    // The study's step count is the rows' (which read the runs directly).
    let trials = s.study().run(&all, Some(2), None).unwrap();
    let steps: u64 = one.iter().map(|r| r.steps).sum();
    assert!(steps > 0);
    assert_eq!(Summary::of(&trials).integrator_steps, steps);
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

/// The attitude experiment starts every sample at the origin at rest in
/// translation (only R and Ω are drawn); the position experiment draws x
/// and v too. A row reports the norms of the sample's own |Ω(0)| and
/// ‖x(0)‖, written out here from the drawn initial condition.
#[test]
fn experiments_draw_what_they_study_and_rows_report_it() {
    let mut att = setup();
    att.experiment = "attitude".into();
    att.deadline = 0.5;
    let n = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    for i in 0..20 {
        let p = att.initial(i);
        assert_eq!((p.x, p.v), ([0.0; 3], [0.0; 3]), "attitude sample {i}");
        assert!(n(p.omega) > 0.0);
    }
    let pos = setup();
    assert!((0..20).all(|i| n(pos.initial(i).x) > 0.0 && n(pos.initial(i).v) > 0.0));
    let mut short = pos.clone();
    short.deadline = 0.5;
    let rows = short.run(&[3, 4], Some(1), None).unwrap();
    for r in &rows {
        let p = short.initial(r.index);
        assert_eq!((r.omega0, r.ex0), (n(p.omega), n(p.x)), "row {}", r.index);
    }
}

/// The settle metric by value: `max(Ψ/psi_tol, ‖x‖/x_tol)` in the
/// position experiment, `Ψ/psi_tol` alone in the attitude one.
#[test]
fn the_settle_metric_is_the_larger_tolerance_ratio() {
    type B = lie::GlamF64;
    let mut s = setup();
    s.psi_tol = 1e-3;
    s.x_tol = 0.01;
    let mut st = RigidBodyState::<B>::at_rest();
    st.x = B::vec3(0.03, 0.0, -0.04);
    let out = |psi: f64| controllers::ModeOutput::<B> {
        thrust: 0.0,
        moment: B::vec3(0.0, 0.0, 0.0),
        desired: lie::So3Mat::<B>::identity(),
        desired_omega: B::vec3(0.0, 0.0, 0.0),
        psi,
        rotor_speeds: None,
    };
    // ‖x‖ = 0.05: 5 tolerances; Ψ = 2e-3: 2 (then 8e-3: 8).
    assert_eq!(s.metric(&st, &out(2e-3)), 0.05 / 0.01);
    assert_eq!(s.metric(&st, &out(8e-3)), 8e-3 / 1e-3);
    s.experiment = "attitude".into();
    assert_eq!(s.metric(&st, &out(2e-3)), 2e-3 / 1e-3);
}

/// A cancel set while a sample flies interrupts that sample: it is not
/// reported (its figures would be of a cut-off run). Here the sample's
/// own settle metric sets the flag at t = 0.5 s of a 2 s deadline.
#[test]
fn a_cancel_during_a_sample_interrupts_it() {
    use std::sync::atomic::{AtomicBool, Ordering};
    let mut s = setup();
    s.deadline = 2.0;
    let flag = AtomicBool::new(false);
    let inner = s.study();
    let study = Study::new(
        inner.seed,
        inner.hold,
        inner.draw,
        inner.build,
        |t: f64, _: &RigidBodyState<lie::GlamF64>, _: &ModeOutput<lie::GlamF64>| {
            if t >= 0.5 {
                flag.store(true, Ordering::Relaxed);
            }
            2.0
        },
    );
    let got = study
        .run_until_cancelled(&[0], Some(1), None, &flag)
        .unwrap();
    assert!(flag.load(Ordering::Relaxed));
    assert!(got.is_empty(), "{} samples reported", got.len());
}

/// `uniform` is on [0, 1) with mean 1/2, and `in_ball` is uniform in its
/// ball: inside radius r, (‖p‖/r)³ uniform on [0, 1] (Kolmogorov–Smirnov,
/// critical 0.0138 at α = 0.001 for n = 20 000) and mean zero (each
/// component within 4 standard errors, r/√(5n)).
#[test]
fn uniform_and_in_ball_follow_their_laws() {
    let n = 20_000;
    let mut rng = stream(11, 0);
    let u: Vec<f64> = (0..n).map(|_| uniform(&mut rng)).collect();
    assert!(u.iter().all(|x| (0.0..1.0).contains(x)));
    let mean = u.iter().sum::<f64>() / n as f64;
    let se = (1.0f64 / 12.0).sqrt() / (n as f64).sqrt();
    assert!((mean - 0.5).abs() < 4.0 * se, "mean {mean}");
    let r = 2.5;
    let pts: Vec<[f64; 3]> = (0..n).map(|_| in_ball(&mut rng, r)).collect();
    let radii: Vec<f64> = pts
        .iter()
        .map(|p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt())
        .collect();
    assert!(radii.iter().all(|&q| q <= r), "a point outside the ball");
    let d = ks(radii.iter().map(|q| (q / r).powi(3)).collect(), |x| x);
    println!("in_ball: KS D = {d:.5}");
    assert!(d < 1.949 / (n as f64).sqrt(), "D = {d}");
    let se = r / (5.0 * n as f64).sqrt();
    for k in 0..3 {
        let m = pts.iter().map(|p| p[k]).sum::<f64>() / n as f64;
        assert!(m.abs() < 4.0 * se, "mean of component {k}: {m}");
    }
}

/// Two shards merged give one run's rows and `samples.csv` byte for byte;
/// a missing shard, a duplicated one and a shard of another run are errors
/// naming what they found.
#[test]
fn shards_merged_equal_one_run() {
    use shards::{Shard, ShardError, merge, write_samples, write_shard};
    let mut s = setup();
    s.samples = 6;
    s.deadline = 2.0;
    let base = std::env::temp_dir().join(format!("gpid-shards-{}", std::process::id()));
    let dir = |n: &str| {
        let p = base.join(n);
        std::fs::create_dir_all(&p).unwrap();
        p
    };
    let one = s.run(&Shard::WHOLE.indices(6), Some(1), None).unwrap();
    write_samples(&dir("single"), &one).unwrap();
    let mut dirs = Vec::new();
    for k in 0..2 {
        let shard = Shard { k, n: 2 };
        let rows = s.run(&shard.indices(6), Some(2), None).unwrap();
        let d = dir(&format!("shard{k}"));
        write_shard(&d, &s, shard, &rows).unwrap();
        dirs.push(d);
    }
    let (merged_setup, merged) = merge(&dirs).unwrap();
    assert_eq!(merged_setup, s);
    write_samples(&dir("merged"), &merged).unwrap();
    assert_eq!(
        std::fs::read(base.join("merged/samples.csv")).unwrap(),
        std::fs::read(base.join("single/samples.csv")).unwrap()
    );
    let missing = merge(&dirs[..1]).unwrap_err();
    assert!(
        matches!(
            missing,
            ShardError::Gap {
                index: 1,
                duplicated: false,
                ..
            }
        ),
        "{missing}"
    );
    let twice = merge(&[dirs[0].clone(), dirs[0].clone(), dirs[1].clone()]).unwrap_err();
    assert!(
        matches!(
            twice,
            ShardError::Gap {
                index: 0,
                duplicated: true,
                ..
            }
        ),
        "{twice}"
    );
    let mut other = s.clone();
    other.seed += 1;
    write_shard(&dirs[1], &other, Shard { k: 1, n: 2 }, &one[1..]).unwrap();
    let e = merge(&dirs).unwrap_err();
    assert!(matches!(e, ShardError::DifferentRun { .. }), "{e}");
    assert!(matches!(merge(&[]), Err(ShardError::Empty)));
    std::fs::remove_dir_all(&base).ok();
}

#[test]
fn shards_parse() {
    use shards::{Shard, ShardError};
    assert_eq!("1/4".parse::<Shard>().unwrap(), Shard { k: 1, n: 4 });
    assert_eq!(Shard { k: 1, n: 4 }.indices(10), [1, 5, 9]);
    for bad in ["4/4", "0/0", "x", "1/", "-1/2"] {
        let e = bad.parse::<Shard>().unwrap_err();
        assert!(matches!(&e, ShardError::Spec(s) if s == bad), "{e}");
    }
}

/// The near-π CSV has one row per axis and δ, each number reading back as
/// the value; a run that never settled is named by its δ.
#[test]
fn near_pi_csv_rows_read_back() {
    let mut a = NearPiAxis {
        axis: "e1",
        j: 0.0820,
        lambda: 0.5,
        times: vec![(1e-1, 3.25), (1e-2, 1.0 / 3.0)],
        slope: 2.0,
    };
    assert_eq!(a.unsettled(), None);
    assert_eq!(a.slope_error(), 0.0);
    let csv = near_pi_csv(std::slice::from_ref(&a));
    let rows: Vec<Vec<&str>> = csv.lines().map(|l| l.split(',').collect()).collect();
    assert_eq!(rows[0], ["axis", "delta", "t_converge"]);
    assert_eq!(rows.len(), 3);
    for (row, (d, t)) in rows[1..].iter().zip(&a.times) {
        assert_eq!(row[0], "e1");
        assert_eq!(row[1].parse::<f64>().unwrap(), *d);
        assert_eq!(row[2].parse::<f64>().unwrap(), *t);
    }
    a.times.push((1e-3, f64::NAN));
    a.times.push((1e-4, f64::NAN));
    assert_eq!(a.unsettled(), Some(1e-3));
}
