//! `So3Quat::from_matrix` normalises: a matrix off SO(3) by a scale (as a
//! drifting integrator leaves it) still gives a unit quaternion, near the
//! exact rotation's (Shepperd's `w = ½√(1 + tr)` does not scale with the
//! matrix, so the rotation moves by the order of the scale error).

use lie::{Backend, NalgebraF64, Rotation, So3Mat, So3Quat};

type B = NalgebraF64;

#[test]
fn a_scaled_rotation_gives_the_unit_quaternion_of_the_rotation() {
    for (phi, scale) in [
        ([0.3, -0.2, 0.9], 1.01),
        ([2.0, 1.0, -0.5], 0.97),
        ([-0.1, 3.0, 0.2], 1.003),
    ] {
        let phi = <B as Backend>::vec3(phi[0], phi[1], phi[2]);
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
