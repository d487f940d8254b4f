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

/// A body whose load turns non-finite from its `bad_from`-th evaluation
/// on (0-based), in the part `what` names.
struct TurnsBad {
    calls: usize,
    bad_from: usize,
    what: &'static str,
    translates: bool,
}

impl System<B, 2> for TurnsBad {
    fn mass(&self) -> f64 {
        2.0
    }
    fn inertia(&self) -> lie::M3<B> {
        ops::diag::<B>(1.0, 2.0, 3.0)
    }
    fn translates(&self) -> bool {
        self.translates
    }
    fn load(&mut self, _: f64, _: &State<B, 2>) -> Load<B, 2> {
        let bad = self.calls >= self.bad_from;
        self.calls += 1;
        let pick = |part: &str, x: f64| {
            if bad && self.what == part {
                f64::NAN
            } else {
                x
            }
        };
        Load {
            force: B::vec3(pick("force", 0.5), 0.0, -1.0),
            moment: B::vec3(0.1, pick("moment", 0.2), 0.3),
            extra_rate: [1.0, pick("extra", -1.0)],
        }
    }
}

/// The explicit steppers test the loads once per step, at its end, and
/// still report a non-finite load as `load` at the time of the first
/// stage that returned one (RK4's stages are at t, t + h/2, t + h/2,
/// t + h), leaving the state where the step began.
#[test]
fn a_non_finite_load_names_its_stage_time() {
    let (t, h) = (1.0, 0.1);
    let stage_times = [1.0, 1.05, 1.05, 1.1];
    for what in ["force", "moment", "extra"] {
        for (k, &ts) in stage_times.iter().enumerate() {
            for mut rk in [Rk4::default(), Rk4::projected()] {
                let mut sys = TurnsBad {
                    calls: 0,
                    bad_from: k,
                    what,
                    translates: true,
                };
                let start = State::<B, 2>::new(RigidBodyState::at_rest());
                let mut y = start;
                let e = rk.step(&mut sys, t, h, &mut y).unwrap_err();
                match e {
                    StepError::NonFinite { field, t: te } => {
                        assert_eq!((field, te), ("load", ts), "{what} bad from stage {k}")
                    }
                    other => panic!("{what} bad from stage {k}: {other}"),
                }
                assert_eq!(y.body.r, start.body.r, "the failed step moved the state");
                assert_eq!(y.extra, start.extra);
            }
        }
        let mut sys = TurnsBad {
            calls: 0,
            bad_from: 0,
            what,
            translates: true,
        };
        let mut y = State::<B, 2>::new(RigidBodyState::at_rest());
        let e = integrators::Euler::default()
            .step(&mut sys, t, h, &mut y)
            .unwrap_err();
        assert!(
            matches!(e, StepError::NonFinite { field: "load", t: te } if te == t),
            "euler, {what}: {e}"
        );
    }
}

/// A body that does not translate never reads its force: a non-finite one
/// does not stop it, and its position and velocity stay where they were.
#[test]
fn a_body_that_does_not_translate_ignores_its_force() {
    let mut sys = TurnsBad {
        calls: 0,
        bad_from: 0,
        what: "force",
        translates: false,
    };
    let mut y = State::<B, 2>::new(RigidBodyState::at_rest());
    Rk4::default()
        .step(&mut sys, 0.0, 0.1, &mut y)
        .expect("the force is not used");
    assert_eq!(
        (y.body.x, y.body.v),
        (B::vec3(0.0, 0.0, 0.0), B::vec3(0.0, 0.0, 0.0))
    );
    assert!(y.body.omega.iter().all(|w| w.is_finite() && *w != 0.0));
}
