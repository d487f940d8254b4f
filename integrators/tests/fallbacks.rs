//! No silent fallbacks: a singular inertia and a failed projection show as
//! errors, never as a made-up identity inertia or an unprojected matrix.

use dynamics::{DynamicsError, RigidBodyState, check_inertia};
use integrators::{Integrator, Load, Rk4, State, StepError, System};
use lie::{NalgebraF64, V3, ops};

type B = NalgebraF64;

/// A body spun up by a constant moment, with inertia `j` (diagonal).
struct Spun {
    j: [f64; 3],
}

impl System<B, 0> for Spun {
    fn mass(&self) -> f64 {
        1.0
    }
    fn inertia(&self) -> lie::M3<B> {
        ops::diag::<B>(self.j[0], self.j[1], self.j[2])
    }
    fn load(&mut self, _: f64, _: &State<B, 0>) -> Load<B, 0> {
        let v = |x: f64, y: f64, z: f64| -> V3<B> { B::vec3(x, y, z) };
        Load {
            force: v(0.0, 0.0, 0.0),
            moment: v(0.1, 0.2, 0.3),
            extra_rate: [],
        }
    }
}

/// With the default `inertia_inv`, a singular inertia makes the first
/// step fail with a non-finite state (it used to integrate with J⁻¹ = I).
#[test]
fn a_singular_inertia_fails_the_first_step() {
    let mut y = State::<B, 0>::new(RigidBodyState::at_rest());
    let mut ok = Spun { j: [1.0, 2.0, 3.0] };
    assert!(Rk4::default().step(&mut ok, 0.0, 0.01, &mut y).is_ok());
    let mut singular = Spun { j: [1.0, 2.0, 0.0] };
    let mut y = State::<B, 0>::new(RigidBodyState::at_rest());
    let e = Rk4::default()
        .step(&mut singular, 0.0, 0.01, &mut y)
        .unwrap_err();
    assert!(matches!(e, StepError::NonFinite { .. }), "{e}");
}

/// `check_inertia` says which leading minor is not positive.
#[test]
fn check_inertia_names_the_failing_minor() {
    let m = |rows: [[f64; 3]; 3]| {
        let c = |k: usize| B::vec3(rows[0][k], rows[1][k], rows[2][k]);
        B::mat3_from_cols(c(0), c(1), c(2))
    };
    let expected = |j| match check_inertia::<B>(j) {
        Err(DynamicsError::InvalidParameter {
            expected, value, ..
        }) => (expected, value),
        other => panic!("{other:?}"),
    };
    let (e, v) = expected(m([[-1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]));
    assert!(e.contains("J11") && v == -1.0, "{e}");
    // J11 > 0 but J11·J22 − J12² = 1 − 4 < 0.
    let (e, v) = expected(m([[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]]));
    assert!(e.contains("2×2 minor") && v == -3.0, "{e}");
    let (e, _) = expected(m([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]));
    assert!(e.contains("det J"), "{e}");
    assert!(check_inertia::<B>(m([[1.0, 0.0, 0.0], [0.0, 2.0, 0.0], [0.0, 0.0, 3.0]])).is_ok());
}
