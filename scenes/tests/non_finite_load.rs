//! A vehicle whose load turns non-finite mid-run: the run stops with the
//! step's error naming the load and the stage time, and does not blame
//! the controller, whose later inputs in that step are non-finite only
//! because of the load.

use dynamics::{
    Disturbance, DynamicsError, LoadInput, Loads, Quadrotor, RigidBodyState, Vehicle, Wrench,
    body_loads,
};
use integrators::StepError;
use lie::{M3, NalgebraF64, S};
use scenarios::{SimError, Simulation};
use scenes::builtin;

type B = NalgebraF64;

/// The paper's quadrotor with a disturbance force that is NaN from
/// `t_bad` on.
struct GoesBad {
    inner: Quadrotor<B>,
    t_bad: f64,
}

impl Vehicle<B> for GoesBad {
    fn name(&self) -> &str {
        "goes-bad"
    }
    fn mass(&self) -> S<B> {
        self.inner.mass()
    }
    fn inertia(&self) -> M3<B> {
        self.inner.inertia()
    }
    fn gravity(&self) -> S<B> {
        self.inner.gravity()
    }
    fn actuator_count(&self) -> usize {
        self.inner.actuator_count()
    }
    fn wrench_from_actuators(&self, u: &[S<B>]) -> Result<Wrench<B>, DynamicsError> {
        self.inner.wrench_from_actuators(u)
    }
    fn actuators_from_wrench(&self, w: &Wrench<B>, out: &mut [S<B>]) -> Result<(), DynamicsError> {
        self.inner.actuators_from_wrench(w, out)
    }
    fn loads(
        &self,
        t: S<B>,
        state: &RigidBodyState<B>,
        input: LoadInput<'_, B>,
        _rates: &mut [S<B>],
    ) -> Option<Loads<B>> {
        let w = input.wrench_command()?;
        let bad = (t >= self.t_bad).then(|| Disturbance {
            force: B::vec3(0.0, f64::NAN, 0.0),
            moment: B::vec3(0.0, 0.0, 0.0),
        });
        Some(body_loads(self, state, w, bad))
    }
}

/// The paper's hover in position mode at h = 1 ms with the vehicle above.
fn fly(t_bad: f64) -> Result<scenarios::RunOutput, SimError> {
    let scene = builtin::hover_disturbed();
    let v = GoesBad {
        inner: Quadrotor::<B>::paper(),
        t_bad,
    };
    let plan = scenes::plan::<B>(&scene, &v);
    let mut sim = Simulation::<B>::builder(Box::new(v))
        .dt(1e-3)
        .duration(2.0)
        .record_every(0.01);
    for s in plan {
        sim = sim.segment(s);
    }
    sim.build()?.run(Default::default())
}

/// At t = 0 the first stage's load is NaN (the mode then rejects the
/// second stage's state, at t = h/2); at 1.0004 s the second stage's (of
/// the step from 1 s, at 1.0005 s), and the third stage, at the same
/// time, is rejected. Either way the error is the load's, at the first
/// bad stage, with no controller complaint attached.
#[test]
fn a_non_finite_vehicle_load_is_not_blamed_on_the_controller() {
    for (t_bad, stage, step) in [(0.0, 0.0, 0.0), (1.0004, 1.0005, 1.0)] {
        match fly(t_bad) {
            Err(SimError::Step {
                t,
                control,
                source: StepError::NonFinite { field, t: ts },
                ..
            }) => {
                assert_eq!(field, "load", "bad from {t_bad}");
                assert!(
                    (ts - stage).abs() < 1e-12,
                    "bad from {t_bad}: stage at {ts}"
                );
                assert!((t - step).abs() < 1e-12, "bad from {t_bad}: step from {t}");
                assert!(control.is_none(), "bad from {t_bad}: blamed {control:?}");
            }
            other => panic!("bad from {t_bad}: {:?}", other.map(|o| o.last.t)),
        }
    }
}

/// A non-finite state set between two calls is refused, naming the
/// field, before any step or command reads it; the run is where it was.
#[test]
fn a_non_finite_state_set_between_calls_is_refused() {
    let scene = builtin::hover_disturbed();
    for field in ["omega", "integrals"] {
        let mut sim = scenes::builder::<B>(&scene).unwrap().build().unwrap();
        sim.advance_to(0.5).unwrap();
        let s = sim.state_mut();
        if field == "omega" {
            s.body.omega[1] = f64::NAN;
        } else {
            s.integrals[0] = f64::INFINITY;
        }
        match sim.advance_to(0.6) {
            Err(SimError::Setting {
                field: "state",
                message,
            }) => {
                assert!(message.contains(&format!("`{field}`")), "{message}")
            }
            other => panic!("{field}: {other:?}"),
        }
        assert!(
            (sim.time() - 0.5).abs() < 1e-12,
            "{field}: at {}",
            sim.time()
        );
    }
}
