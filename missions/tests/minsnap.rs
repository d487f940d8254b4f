//! The minimum-snap conditions on random waypoint sets: positions at the
//! waypoints, derivatives 0–4 continuous at interior ones, the ends at
//! rest, and no feasible perturbation with a smaller snap cost (feasible
//! directions from this test's own constraint rows, the cost by Gauss
//! quadrature); the reference's heading derivatives against central
//! differences; and bad input named.

use controllers::PositionSource;
use lie::NalgebraF64 as B;
use missions::{COEFFS, MinSnap, MissionError, Piece, Trajectory};
use nalgebra::{DMatrix, DVector};

/// SplitMix64 (`lie`'s finaliser on a Weyl sequence): a reproducible
/// stream for the random sets.
struct Rng(u64);
impl Rng {
    fn uniform(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        (lie::noise::mix(self.0) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.uniform()
    }
}

fn random_problem(rng: &mut Rng) -> MinSnap {
    let n = 2 + (rng.uniform() * 7.0) as usize;
    let mut p = [0.0; 3];
    let mut points = vec![p];
    let mut yaw = vec![0.0];
    for _ in 1..n {
        p = p.map(|c| c + rng.range(-2.0, 2.0));
        p[0] += 0.2; // never two points together
        points.push(p);
        yaw.push(rng.range(-3.0, 3.0));
    }
    let v0 = [rng.range(-1.0, 1.0), 0.0, rng.range(-0.5, 0.5)];
    MinSnap::through(&points)
        .yaw(&yaw)
        .mean_speed(rng.range(0.3, 3.0))
        .end_velocities(v0, [0.0; 3])
}

/// The `d`-th derivative of `Σ c_j τʲ` by the power sum (not the crate's
/// Horner evaluation).
fn deriv(c: &[f64; COEFFS], d: usize, tau: f64) -> f64 {
    (d..COEFFS)
        .map(|j| c[j] * ((j - d + 1)..=j).product::<usize>() as f64 * tau.powi((j - d) as i32))
        .sum()
}

/// Derivatives 0–4 match at every interior waypoint to 1e-9 of the
/// largest magnitude of that derivative at the waypoints, and the
/// positions are the waypoints to 1e-12 of the set's extent, over 200
/// random sets (2–8 waypoints, random yaw, start velocity and speed).
#[test]
fn derivatives_are_continuous_at_interior_waypoints() {
    let mut rng = Rng(7);
    let mut worst = 0.0f64;
    for case in 0..200 {
        let problem = random_problem(&mut rng);
        let traj = problem.solve().unwrap();
        let pieces = traj.pieces();
        for a in 0..4 {
            for d in 0..5 {
                let mut scale = 1e-12f64;
                let mut jump = 0.0f64;
                for w in pieces.windows(2) {
                    let end = deriv(&w[0].coeffs[a], d, w[0].duration);
                    let start = deriv(&w[1].coeffs[a], d, 0.0);
                    scale = scale.max(end.abs()).max(start.abs());
                    jump = testkit::nan_max(jump, (end - start).abs());
                }
                worst = worst.max(jump / scale);
                assert!(
                    jump <= 1e-9 * scale,
                    "case {case}, axis {a}, order {d}: {jump:e} of {scale:e}"
                );
            }
        }
    }
    println!("largest relative jump of derivatives 0–4 over 200 sets: {worst:.1e}");
}

/// Gauss–Legendre nodes and weights on [0, 1], 8 points (exact for the
/// degree-6 square of a degree-3 snap).
fn gauss8() -> Vec<(f64, f64)> {
    let x = [
        0.183_434_642_495_649_8,
        0.525_532_409_916_329,
        0.796_666_477_413_626_7,
        0.960_289_856_497_536_3,
    ];
    let w = [
        0.362_683_783_378_362,
        0.313_706_645_877_887_3,
        0.222_381_034_453_374_5,
        0.101_228_536_290_376_3,
    ];
    let mut out = vec![];
    for k in 0..4 {
        out.push((0.5 * (1.0 - x[k]), 0.5 * w[k]));
        out.push((0.5 * (1.0 + x[k]), 0.5 * w[k]));
    }
    out
}

fn snap_cost(coeffs: &[f64], durations: &[f64]) -> f64 {
    let mut j = 0.0;
    for (i, t) in durations.iter().enumerate() {
        let c: [f64; COEFFS] = coeffs[COEFFS * i..COEFFS * (i + 1)].try_into().unwrap();
        for (x, w) in gauss8() {
            j += w * t * deriv(&c, 4, x * t).powi(2);
        }
    }
    j
}

/// On 20 random sets and each axis: the constraints written here (a
/// waypoint at each end of each piece, velocity to snap continuous, the
/// end velocities, zero acceleration and jerk at the ends) give the
/// feasible directions as the null space of their rows; along 20 random
/// directions in it, scaled to change the cost by about 1e-3 relative,
/// the cost never falls below the solution's (by more than 1e-9 relative,
/// the quadrature's rounding).
#[test]
fn no_feasible_perturbation_lowers_the_snap_cost() {
    let mut rng = Rng(11);
    for case in 0..20 {
        let traj = random_problem(&mut rng).solve().unwrap();
        let pieces = traj.pieces();
        let durations: Vec<f64> = pieces.iter().map(|p| p.duration).collect();
        let m = pieces.len();
        let n = COEFFS * m;
        let mut rows: Vec<Vec<f64>> = vec![];
        let row_at = |i: usize, d: usize, tau: f64, sign: f64| -> Vec<f64> {
            let mut r = vec![0.0; n];
            for j in d..COEFFS {
                let f = ((j - d + 1)..=j).product::<usize>() as f64;
                r[COEFFS * i + j] = sign * f * tau.powi((j - d) as i32);
            }
            r
        };
        for (i, &t) in durations.iter().enumerate() {
            rows.push(row_at(i, 0, 0.0, 1.0));
            rows.push(row_at(i, 0, t, 1.0));
            if i + 1 < m {
                for d in 1..=4 {
                    let a = row_at(i, d, t, 1.0);
                    let b = row_at(i + 1, d, 0.0, -1.0);
                    rows.push(a.iter().zip(&b).map(|(x, y)| x + y).collect());
                }
            }
        }
        for d in 1..=3 {
            rows.push(row_at(0, d, 0.0, 1.0));
            rows.push(row_at(m - 1, d, durations[m - 1], 1.0));
        }
        let a = DMatrix::from_fn(rows.len(), n, |r, c| rows[r][c]);
        // Padded square with zero rows, so that the SVD's V is whole.
        let square = DMatrix::from_fn(n, n, |r, c| if r < rows.len() { rows[r][c] } else { 0.0 });
        let svd = square.svd(false, true);
        let vt = svd.v_t.unwrap();
        let smax = svd.singular_values.max();
        let rank = svd
            .singular_values
            .iter()
            .filter(|s| **s > 1e-10 * smax)
            .count();
        assert_eq!(rank, rows.len(), "case {case}: independent constraints");
        for axis in 0..4 {
            let c: Vec<f64> = pieces.iter().flat_map(|p| p.coeffs[axis]).collect();
            let j0 = snap_cost(&c, &durations);
            for _ in 0..20 {
                let mut dir = DVector::<f64>::zeros(n);
                // nalgebra sorts no singular values: the null space is
                // where they are small.
                for (k, sv) in svd.singular_values.iter().enumerate() {
                    if *sv <= 1e-10 * smax {
                        dir += vt.row(k).transpose() * rng.range(-1.0, 1.0);
                    }
                }
                let off = (&a * &dir).norm();
                assert!(
                    off <= 1e-9 * smax * dir.norm(),
                    "case {case}: not feasible, {off:e}"
                );
                if dir.norm() == 0.0 {
                    continue; // one piece: the constraints fix it whole
                }
                let dj = snap_cost(dir.as_slice(), &durations);
                let eps = (1e-3 * j0.max(1e-6) / dj.max(1e-300)).sqrt();
                let moved: Vec<f64> = c.iter().zip(dir.iter()).map(|(x, d)| x + eps * d).collect();
                let j1 = snap_cost(&moved, &durations);
                assert!(
                    j1 >= j0 * (1.0 - 1e-9),
                    "case {case}, axis {axis}: {j1} < {j0}"
                );
            }
        }
    }
}

/// The heading and its derivatives against central differences of the
/// reference itself, and `x_d`'s derivatives likewise (step 1e-4: the
/// differences' own error is about 1e-7 of the magnitudes).
#[test]
fn the_reference_derivatives_are_consistent() {
    let traj = MinSnap::through(&[[0.0, 0.0, -1.0], [1.0, 0.5, -1.5], [2.0, -0.5, -1.0]])
        .yaw(&[0.0, 1.5, -0.5])
        .solve()
        .unwrap();
    let h = 1e-4;
    let at = |t: f64| PositionSource::<B>::position(&traj, t);
    for k in 1..40 {
        let t = traj.duration() * k as f64 / 40.0;
        let (a, b, c) = (at(t - h), at(t), at(t + h));
        let pairs = [
            (a.x, c.x, b.v),
            (a.v, c.v, b.a),
            (a.a, c.a, b.jerk),
            (a.jerk, c.jerk, b.snap),
            (a.b1d, c.b1d, b.b1d_dot),
            (a.b1d_dot, c.b1d_dot, b.b1d_ddot),
        ];
        for (o, (lo, hi, d)) in pairs.iter().enumerate() {
            let fd = (hi - lo) / (2.0 * h);
            assert!(
                (fd - d).norm() < 1e-6 * (1.0 + d.norm()),
                "t {t}, order {o}: {fd} vs {d}"
            );
        }
        assert!((b.b1d.norm() - 1.0).abs() < 1e-15);
    }
    // At rest after the end and before the start.
    let end = at(traj.duration() + 1.0);
    assert_eq!(
        end.v.norm() + end.a.norm() + end.snap.norm() + end.b1d_dot.norm(),
        0.0
    );
    assert!((end.x - B::vec3(2.0, -0.5, -1.0)).norm() < 1e-12);
}

fn message(e: MissionError) -> String {
    e.to_string()
}

/// Each class of bad input gets an error naming its field and value.
#[test]
fn bad_input_is_named() {
    let sq = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]];
    let cases: Vec<(MinSnap, &str)> = vec![
        (
            MinSnap::through(&sq[..1]),
            "waypoints = 1: must be at least two waypoints",
        ),
        (
            MinSnap::through(&[[0.0; 3], [1.0, f64::NAN, 0.0]]),
            "waypoints[1].y = NaN",
        ),
        (
            MinSnap::through(&sq).times(&[0.0, 2.0, 2.0]),
            "times[2] = 2: must be finite and after times[1] = 2",
        ),
        (
            MinSnap::through(&sq).times(&[0.0, 1.0]),
            "times = 2: must be one time per waypoint (3)",
        ),
        (
            MinSnap::through(&sq).times(&[0.5, 1.0, 2.0]),
            "times[0] = 0.5",
        ),
        (
            MinSnap::through(&[[0.0; 3], [0.0; 3], [1.0, 0.0, 0.0]]),
            "waypoints[1] distance = 0",
        ),
        (
            MinSnap::through(&sq).mean_speed(0.0),
            "mean_speed = 0: must be positive",
        ),
        (
            MinSnap::through(&sq).yaw(&[0.0, 1.0]),
            "yaw = 2: must be one yaw per waypoint (3)",
        ),
        (
            MinSnap::through(&sq).yaw(&[0.0, f64::INFINITY, 1.0]),
            "yaw[1] = inf",
        ),
        (
            MinSnap::through(&sq).end_velocities([0.0, f64::NAN, 0.0], [0.0; 3]),
            "start_velocity = NaN",
        ),
    ];
    for (problem, want) in cases {
        let got = message(problem.solve().unwrap_err());
        assert!(got.contains(want), "{got:?} lacks {want:?}");
    }
    let piece = Piece {
        duration: -1.0,
        coeffs: [[0.0; COEFFS]; 4],
    };
    let got = message(Trajectory::new(vec![piece]).unwrap_err());
    assert!(got.contains("pieces[0].duration = -1"), "{got}");
}

/// A time budget: the durations sum to it, the snap cost is no larger
/// than with durations in proportion to the lengths (RotorPy's rule scaled
/// to the same total), and at the end the cost's derivatives with respect
/// to each duration are equal (the condition for a minimum on the plane
/// `Σ T = budget`), measured here by central differences of
/// `MinSnap::snap_cost` over each duration alone.
#[test]
fn a_time_budget_is_shared_out_to_minimise_the_snap_cost() {
    let points = [
        [0.0, 0.0, -1.0],
        [0.3, 0.0, -1.0],
        [3.3, 0.0, -1.2],
        [3.5, 1.0, -1.2],
        [3.7, 1.2, -1.4],
    ];
    let budget = 8.0;
    let plan = MinSnap::through(&points).time_budget(budget);
    let best = plan.durations().unwrap();
    assert!((best.iter().sum::<f64>() - budget).abs() < 1e-12);
    let proportional = MinSnap::through(&points)
        .mean_speed(1.0)
        .durations()
        .unwrap();
    let sum: f64 = proportional.iter().sum();
    let proportional: Vec<f64> = proportional.iter().map(|t| t * budget / sum).collect();
    let (j_best, j_prop) = (
        plan.snap_cost(&best).unwrap(),
        plan.snap_cost(&proportional).unwrap(),
    );
    let grads: Vec<f64> = (0..best.len())
        .map(|i| {
            let h = 1e-6 * best[i];
            let mut t = best.clone();
            t[i] += h;
            let up = plan.snap_cost(&t).unwrap();
            t[i] -= 2.0 * h;
            let down = plan.snap_cost(&t).unwrap();
            (up - down) / (2.0 * h)
        })
        .collect();
    let mean = grads.iter().sum::<f64>() / grads.len() as f64;
    let spread = grads.iter().fold(0.0f64, |m, g| m.max((g - mean).abs())) / mean.abs();
    println!(
        "budget {budget} s: durations {best:.3?}, cost {j_best:.4e} against {j_prop:.4e} in \
         proportion to length; ∂J/∂T_i spread {spread:.1e}"
    );
    assert!(j_best <= j_prop);
    // The descent stops at a relative gradient of 1e-9 and the
    // differences here err by about 1e-8 of the cost: 1e-5 allows both
    // (measured 1.7e-7); an unfinished descent leaves O(1) spreads.
    assert!(spread < 1e-5, "{grads:?}");
    let bad = MinSnap::through(&points)
        .time_budget(-1.0)
        .solve()
        .unwrap_err();
    assert!(bad.to_string().contains("time_budget = -1"), "{bad}");
}
