//! `So3Quat::from_matrix` normalises: a matrix off SO(3) by a scale (as a
//! drifting integrator leaves it) still gives a unit quaternion, near the
//! exact rotation's (Shepperd's `w = ½√(1 + tr)` does not scale with the
//! matrix, so the rotation moves by the order of the scale error).

use lie::{NalgebraF64, Rotation, So3Mat, So3Quat};

type B = NalgebraF64;

#[test]
fn a_scaled_rotation_gives_the_unit_quaternion_of_the_rotation() {
    for (phi, scale) in [
        ([0.3, -0.2, 0.9], 1.01),
        ([2.0, 1.0, -0.5], 0.97),
        ([-0.1, 3.0, 0.2], 1.003),
    ] {
        let phi = B::vec3(phi[0], phi[1], phi[2]);
        let r = So3Mat::<B>::exp(phi).as_matrix();
        let exact = So3Quat::<B>::from_matrix(r).quaternion();
        let scaled = So3Quat::<B>::from_matrix(r * scale).quaternion();
        // Unit to rounding (a few ε), and within the scale error of the
        // exact rotation's quaternion (measured 1.3e-3 at 1 %).
        assert!(
            (scaled.norm() - 1.0).abs() < 1e-15,
            "|q| = {}",
            scaled.norm()
        );
        let d = (scaled.coords - exact.coords)
            .norm()
            .min((scaled.coords + exact.coords).norm());
        assert!(d < 0.2 * (scale - 1.0f64).abs(), "scale {scale}: {d:e}");
    }
}

/// The same for `So3Mat::quaternion` of a matrix that has drifted off
/// SO(3) (it is stored unchecked), and `renormalized`, one Newton–Schulz
/// step, squares such a drift: from 1e-3 to the order of 1e-6.
#[test]
fn a_drifted_matrix_gives_a_unit_quaternion_and_renormalizes() {
    let r = So3Mat::<B>::exp(B::vec3(0.4, -1.1, 0.7)).as_matrix();
    let drifted = So3Mat::<B>::from_matrix_unchecked(r * 1.001);
    let q = drifted.quaternion();
    assert!((q.norm() - 1.0).abs() < 1e-15, "|q| = {}", q.norm());
    let before = drifted.orthogonality_error();
    let after = drifted.renormalized().orthogonality_error();
    // ‖RᵀR − I‖ of s·R is |s² − 1|·√3 = 3.5e-3; one step leaves
    // (3/4)(s² − 1)²·√3 = 5.2e-6 (measured the same). Bound 2× above, and
    // below, so that a step that does nothing or overshoots fails.
    println!("Newton–Schulz: ‖RᵀR − I‖ {before:.2e} → {after:.2e}");
    assert!(
        before > 3e-3 && after < 1e-5 && after > 1e-7,
        "{before:e} → {after:e}"
    );
}
