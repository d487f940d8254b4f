//! The two helpers controllers use to avoid repeated products:
//! `errors_to_identity` of `R_dᵀR` equals `(e_R(R, R_d), Ψ(R, R_d))`, and
//! `body_axis(k)` equals `R e_k`, for both representations on all four
//! (backend, scalar) pairs; `ops::diagonal` finds a principal-axes
//! inertia (±0 off the diagonal, nothing else) and its element-wise
//! product equals the matrix product exactly.

mod common;

use common::*;
use lie::{
    Backend, GlamF32, GlamF32A, GlamF64, NalgebraF32, NalgebraF64, Rotation, So3Mat, So3Quat,
};

fn check<B: Backend, R: Rotation<B>>(label: &str) {
    let mut rng = Rng::new(7);
    // Rounding of a few products of O(1) entries.
    let tol = 16.0 * eps::<B>();
    let mut worst = 0.0f64;
    for _ in 0..500 {
        let r = R::exp(vb::<B>(rng.rotvec(3.1)));
        let rd = R::exp(vb::<B>(rng.rotvec(3.1)));
        let (e_r, psi) = (rd.inverse() * r).errors_to_identity();
        let d_e = dist(v64::<B>(e_r), v64::<B>(r.e_r(rd)));
        let d_psi = (lie::Real::to_f64_lossless(psi) - lie::Real::to_f64_lossless(r.psi(rd))).abs();
        let z = s::<B>(0.0);
        let o = s::<B>(1.0);
        let axes = [B::vec3(o, z, z), B::vec3(z, o, z), B::vec3(z, z, o)];
        let d_axis = (0..3)
            .map(|k| dist(v64::<B>(r.body_axis(k)), v64::<B>(r.act(axes[k]))))
            .fold(0.0, testkit::nan_max);
        worst = [d_e, d_psi, d_axis]
            .into_iter()
            .fold(worst, testkit::nan_max);
    }
    println!("[{label}] errors_to_identity / body_axis vs e_r, psi, act: {worst:.1e}");
    assert!(worst < tol, "{label}: {worst} ≥ {tol}");
}

#[test]
fn helpers_agree_with_the_definitions() {
    check::<NalgebraF64, So3Mat<NalgebraF64>>("nalgebra-f64 matrix");
    check::<NalgebraF64, So3Quat<NalgebraF64>>("nalgebra-f64 quaternion");
    check::<GlamF64, So3Mat<GlamF64>>("glam-f64 matrix");
    check::<GlamF64, So3Quat<GlamF64>>("glam-f64 quaternion");
    check::<NalgebraF32, So3Mat<NalgebraF32>>("nalgebra-f32 matrix");
    check::<NalgebraF32, So3Quat<NalgebraF32>>("nalgebra-f32 quaternion");
    check::<GlamF32, So3Mat<GlamF32>>("glam-f32 matrix");
    check::<GlamF32, So3Quat<GlamF32>>("glam-f32 quaternion");
    check::<GlamF32A, So3Mat<GlamF32A>>("glam-f32a matrix");
    check::<GlamF32A, So3Quat<GlamF32A>>("glam-f32a quaternion");
}

fn diagonal_case<B: Backend>(label: &str) {
    use lie::ops::{diag, diagonal, from_elems};
    let mut rng = Rng::new(11);
    let j = diag::<B>(s::<B>(0.43e-2), s::<B>(0.43e-2), s::<B>(1.02e-2));
    let d = diagonal::<B>(j).expect("a diagonal matrix has a diagonal");
    for _ in 0..200 {
        let v = vb::<B>(rng.rotvec(30.0));
        let (a, b) = (B::vec3_to_array(j * v), B::vec3_to_array(d));
        let w = B::vec3_to_array(v);
        // Bit for bit: the matrix product only adds exact zeros.
        for k in 0..3 {
            assert_eq!(a[k], b[k] * w[k], "{label}: component {k}");
        }
    }
    // Any non-zero off-diagonal element, however small (a subnormal
    // included), or not a number, is not diagonal; −0 is a zero. The
    // one-lane test ORs bit patterns, so each of these is a pattern it
    // must tell apart from ±0.
    let tiny = s::<B>(if eps::<B>() > 1e-10 { 1e-45 } else { 5e-324 });
    assert!(
        lie::Real::to_f64_lossless(tiny) > 0.0,
        "{label}: the subnormal rounds to zero"
    );
    for (r, c) in [(0, 1), (0, 2), (1, 0), (1, 2), (2, 0), (2, 1)] {
        for (bad, what) in [
            (s::<B>(1e-30), "1e-30"),
            (-tiny, "−subnormal"),
            (tiny, "subnormal"),
            (s::<B>(f64::NAN), "NaN"),
            (s::<B>(f64::INFINITY), "∞"),
        ] {
            let mut e = lie::ops::elems::<B>(j);
            e[r][c] = bad;
            assert!(
                diagonal::<B>(from_elems::<B>(e)).is_none(),
                "{label}: {what} at ({r}, {c})"
            );
        }
        let mut e = lie::ops::elems::<B>(j);
        e[r][c] = s::<B>(-0.0);
        assert!(
            diagonal::<B>(from_elems::<B>(e)).is_some(),
            "{label}: −0 at ({r}, {c})"
        );
    }
}

#[test]
fn diagonal_matrices_are_recognised_and_multiply_exactly() {
    diagonal_case::<NalgebraF64>("nalgebra-f64");
    diagonal_case::<GlamF64>("glam-f64");
    diagonal_case::<NalgebraF32>("nalgebra-f32");
    diagonal_case::<GlamF32>("glam-f32");
    diagonal_case::<GlamF32A>("glam-f32a");
}
