//! The SO(3) logarithm against a 50-digit evaluation
//! (`tests/golden/so3_log_mpmath.py`) at angles from 1e-9 to π − 1e-9:
//! the series region, both sides of the asin/acos switch at π/4 and of the
//! quaternion fallback at 2π/3, and the approach to π, where `acos` of the
//! trace alone keeps half its digits.

use lie::{Backend, GlamF64, NalgebraF64, Rotation, So3Mat, So3Quat};

const GOLDEN: &str = include_str!("golden/so3_log_mpmath.txt");

/// Worst absolute error and the angle where it is, and worst error
/// relative to the angle (below θ = 1, where the rounded matrix still
/// carries θ to a few ulps, so the log must too).
fn worst<B: Backend<Scalar = f64>, R: Rotation<B>>() -> (f64, f64, f64) {
    let (mut worst, mut at, mut rel) = (0.0f64, 0.0, 0.0f64);
    for line in GOLDEN.lines() {
        let v: Vec<f64> = line
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        let m =
            lie::ops::from_elems::<B>([[v[0], v[1], v[2]], [v[3], v[4], v[5]], [v[6], v[7], v[8]]]);
        let got = B::vec3_to_array(R::from_matrix(m).log());
        let err = (0..3)
            .map(|k| (got[k] - v[9 + k]).powi(2))
            .sum::<f64>()
            .sqrt();
        let theta = v[9..12].iter().map(|x| x * x).sum::<f64>().sqrt();
        assert!(err.is_finite(), "log at θ = {theta}: {got:?}");
        if err > worst {
            (worst, at) = (err, theta);
        }
        if theta < 1.0 {
            rel = rel.max(err / theta);
        }
    }
    (worst, at, rel)
}

#[test]
fn log_is_exact_to_rounding_at_every_angle() {
    for (name, (e, at, rel)) in [
        (
            "nalgebra So3Mat",
            worst::<NalgebraF64, So3Mat<NalgebraF64>>(),
        ),
        (
            "nalgebra So3Quat",
            worst::<NalgebraF64, So3Quat<NalgebraF64>>(),
        ),
        ("glam So3Mat", worst::<GlamF64, So3Mat<GlamF64>>()),
        ("glam So3Quat", worst::<GlamF64, So3Quat<GlamF64>>()),
    ] {
        println!(
            "SO(3) log vs mpmath, {name}: worst error {e:.2e} rad (at θ = {at:.9}), relative below θ = 1: {rel:.2e}"
        );
        // Relative to θ below 1 rad: a small angle must keep its digits
        // (the series branch of the quaternion log, the small-angle
        // formulas); measured ≤ 4.2e-16 (2 ε), bound ~10×. A series used
        // above its range shows as its first dropped term, (2/5)|q_v|⁴
        // relative: 2.5e-14 at θ = 1e-3.
        assert!(rel < 4e-15, "{name}: relative {rel:e}");
        // A few ulps of π (4.4e-16 each): the matrix elements are rounded
        // to f64 and the log is conditioned by at most ~1 away from π; a
        // formula that loses digits (acos near 0 or π) shows as 1e-8 or
        // worse.
        assert!(e < 2e-15, "{name}: {e:e} at θ = {at}");
    }
}
