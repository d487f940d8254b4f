//! A scene's [`Simulation`] with its scalar and backend chosen at run
//! time, for front ends that cannot name the generic type (bindings to
//! other languages, a UI that loads any scene file).

use dynamics::RigidBodyState;
use lie::{Backend, GlamF32, GlamF64, NalgebraF32, NalgebraF64, Real, Rotation};

use crate::Error;
use crate::Registry;
use crate::reference::{m, v};
use crate::registry::{PositionFn, Seeds, builder_from};
use crate::scene::{BackendKind, Scalar, Scene};
use scenarios::{DivergenceGuard, RunOptions, RunOutput, Simulation, Termination};

/// A simulation's state in f64, whatever the scalar it runs in.
#[derive(Clone, Debug, PartialEq)]
pub struct StateF64 {
    /// Time, s.
    pub t: f64,
    /// Position, m (inertial frame, e3 down).
    pub x: [f64; 3],
    /// Velocity, m/s.
    pub v: [f64; 3],
    /// Attitude, rows of the body-to-inertial rotation matrix.
    pub r: [[f64; 3]; 3],
    /// Body angular velocity, rad/s.
    pub omega: [f64; 3],
    /// The plan's integral register (the paper's modes: `[e_I, e_i]`).
    pub integrals: Vec<f64>,
    /// The vehicle's internal states.
    pub vehicle_states: Vec<f64>,
    /// The active segment.
    pub segment: usize,
    /// Its mode's name.
    pub mode: &'static str,
}

/// What [`SceneSimulation`] needs of a `Simulation<B>`.
trait Stepping {
    fn advance_to_with(&mut self, t: f64, opts: RunOptions<'_>) -> Result<(), Error>;
    fn state(&self) -> StateF64;
    fn set_state(&mut self, s: &StateF64) -> Result<(), Error>;
    fn output(&self) -> &RunOutput;
    fn termination(&self) -> Option<Termination>;
    fn time(&self) -> f64;
    fn duration(&self) -> f64;
    fn finish(self: Box<Self>) -> Result<RunOutput, Error>;
}

/// Every element finite, or a [`SimError::Setting`](scenarios::SimError::Setting) naming the field.
fn finite(field: &'static str, values: &[f64]) -> Result<(), Error> {
    match values.iter().find(|v| !v.is_finite()) {
        Some(v) => Err(Error::setting(field, format!("{v} is not finite"))),
        None => Ok(()),
    }
}

impl<B: Backend> Stepping for Simulation<'static, B> {
    fn advance_to_with(&mut self, t: f64, opts: RunOptions<'_>) -> Result<(), Error> {
        Ok(Simulation::advance_to_with(self, t, opts)?)
    }

    fn state(&self) -> StateF64 {
        let s = Simulation::state(self);
        StateF64 {
            t: s.t,
            x: lie::ops::vec3_f64::<B>(s.body.x),
            v: lie::ops::vec3_f64::<B>(s.body.v),
            r: lie::ops::mat3_f64::<B>(s.body.r),
            omega: lie::ops::vec3_f64::<B>(s.body.omega),
            integrals: s.integrals.iter().map(|c| c.to_f64_lossless()).collect(),
            vehicle_states: s
                .vehicle_states
                .iter()
                .map(|c| c.to_f64_lossless())
                .collect(),
            segment: s.segment,
            mode: s.mode,
        }
    }

    fn set_state(&mut self, s: &StateF64) -> Result<(), Error> {
        let at = self.layout();
        let (ni, nv) = (at.integrals, at.vehicle_states);
        for (field, got, want) in [
            ("state.integrals", s.integrals.len(), ni),
            ("state.vehicle_states", s.vehicle_states.len(), nv),
        ] {
            if got != want {
                return Err(Error::setting(
                    field,
                    format!("{got} values given, this simulation has {want}"),
                ));
            }
        }
        finite("state.x", &s.x)?;
        finite("state.v", &s.v)?;
        finite("state.r", s.r.as_flattened())?;
        finite("state.omega", &s.omega)?;
        finite("state.integrals", &s.integrals)?;
        finite("state.vehicle_states", &s.vehicle_states)?;
        let lit = <lie::S<B> as Real>::lit;
        let to = self.state_mut();
        *to.body = RigidBodyState {
            r: m::<B>(s.r).matrix(),
            x: v::<B>(s.x),
            v: v::<B>(s.v),
            omega: v::<B>(s.omega),
        };
        for (slot, v) in to.integrals.iter_mut().zip(&s.integrals) {
            *slot = lit(*v);
        }
        for (slot, v) in to.vehicle_states.iter_mut().zip(&s.vehicle_states) {
            *slot = lit(*v);
        }
        Ok(())
    }

    fn output(&self) -> &RunOutput {
        Simulation::output(self)
    }

    fn termination(&self) -> Option<Termination> {
        Simulation::termination(self)
    }

    fn time(&self) -> f64 {
        Simulation::time(self)
    }

    fn duration(&self) -> f64 {
        Simulation::duration(self)
    }

    fn finish(self: Box<Self>) -> Result<RunOutput, Error> {
        Ok(Simulation::finish(*self)?)
    }
}

/// A scene's simulation, to step, inspect and change, with the scene's
/// scalar and backend picked at run time (the generic [`Simulation`]
/// does the work; this only forwards). Values cross in f64: an f32 scene
/// rounds what [`SceneSimulation::set_state`] is given.
///
/// ```
/// let mut scene = scenes::load("hover-disturbed")?;
/// scene.duration = 4.0;
/// let mut sim = scenes::SceneSimulation::new(&scene)?;
/// sim.advance_to(1.0)?;
/// let mut s = sim.state();
/// s.omega[0] += 2.0; // a kick about b1
/// sim.set_state(&s)?;
/// sim.advance_to(4.0)?;
/// let out = sim.finish()?;
/// assert!(out.last.psi < 1e-3);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct SceneSimulation {
    inner: Box<dyn Stepping>,
}

impl std::fmt::Debug for SceneSimulation {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SceneSimulation")
            .field("t", &self.time())
            .field("duration", &self.duration())
            .finish()
    }
}

impl SceneSimulation {
    /// The simulation of `scene` (built-in vehicle kinds; see
    /// [`Registry::simulation`]).
    pub fn new(scene: &Scene) -> Result<Self, Error> {
        Registry::new().simulation(scene)
    }

    /// The simulation of `scene` stopped by `guard` when it diverges.
    pub fn guarded(scene: &Scene, guard: DivergenceGuard) -> Result<Self, Error> {
        Registry::new().simulation_guarded(scene, guard)
    }

    /// The simulation of `scene` with `guard`, every position-mode
    /// segment tracking `position` instead of its scene reference (a
    /// reference computed elsewhere: another language, a planner).
    pub fn with_position(
        scene: &Scene,
        guard: DivergenceGuard,
        position: PositionFn,
    ) -> Result<Self, Error> {
        Registry::new().simulation_with(scene, guard, Some(position))
    }

    /// Advances to `t`, recording samples ([`Simulation::advance_to`]).
    pub fn advance_to(&mut self, t: f64) -> Result<(), Error> {
        self.inner.advance_to_with(t, RunOptions::default())
    }

    /// [`Simulation::advance_to_with`].
    pub fn advance_to_with(&mut self, t: f64, opts: RunOptions<'_>) -> Result<(), Error> {
        self.inner.advance_to_with(t, opts)
    }

    /// The state now, in f64.
    pub fn state(&self) -> StateF64 {
        self.inner.state()
    }

    /// Replaces the body state, the integral register and the vehicle's
    /// states (`t`, `segment` and `mode` of `s` are not read: time moves
    /// only by stepping). Lengths must match [`SceneSimulation::state`]'s and
    /// values be finite, or it is a [`SimError::Setting`](scenarios::SimError::Setting) naming the field;
    /// `r` is taken as given (a matrix off SO(3) is the caller's choice,
    /// which [`RunOutput::health`] reports).
    pub fn set_state(&mut self, s: &StateF64) -> Result<(), Error> {
        self.inner.set_state(s)
    }

    /// The run so far.
    pub fn output(&self) -> &RunOutput {
        self.inner.output()
    }

    /// How the run ended, once it has.
    pub fn termination(&self) -> Option<Termination> {
        self.inner.termination()
    }

    /// Time reached, s.
    pub fn time(&self) -> f64 {
        self.inner.time()
    }

    /// The run's duration, s.
    pub fn duration(&self) -> f64 {
        self.inner.duration()
    }

    /// Ends the run where it is ([`Simulation::finish`]).
    pub fn finish(self) -> Result<RunOutput, Error> {
        self.inner.finish()
    }
}

impl Registry {
    /// [`SceneSimulation`] of `scene` with this registry's vehicle kinds.
    pub fn simulation(&self, scene: &Scene) -> Result<SceneSimulation, Error> {
        self.simulation_guarded(scene, DivergenceGuard::default())
    }

    /// [`Registry::simulation`] with a divergence guard (a run it stops
    /// ends with [`Termination::Diverged`]).
    pub fn simulation_guarded(
        &self,
        scene: &Scene,
        guard: DivergenceGuard,
    ) -> Result<SceneSimulation, Error> {
        self.simulation_with(scene, guard, None)
    }

    /// [`Registry::simulation_guarded`] with every position-mode segment
    /// tracking `position` when given ([`SceneSimulation::with_position`]).
    pub fn simulation_with(
        &self,
        scene: &Scene,
        guard: DivergenceGuard,
        position: Option<PositionFn>,
    ) -> Result<SceneSimulation, Error> {
        fn on<B: Backend>(
            r: &Registry,
            scene: &Scene,
            guard: DivergenceGuard,
            position: Option<&PositionFn>,
        ) -> Result<Box<dyn Stepping>, Error> {
            r.check(scene)?;
            let (vehicle, plan) = r.parts::<B>(scene, position, Seeds::NONE)?;
            Ok(Box::new(
                builder_from::<B>(scene, vehicle, plan, Seeds::NONE)?
                    .guard(guard)
                    .build()?,
            ))
        }
        let inner = match (scene.scalar, scene.backend) {
            (Scalar::F64, BackendKind::Nalgebra) => {
                on::<NalgebraF64>(self, scene, guard, position.as_ref())?
            }
            (Scalar::F64, BackendKind::Glam) => {
                on::<GlamF64>(self, scene, guard, position.as_ref())?
            }
            (Scalar::F32, BackendKind::Nalgebra) => {
                on::<NalgebraF32>(self, scene, guard, position.as_ref())?
            }
            (Scalar::F32, BackendKind::Glam) => {
                on::<GlamF32>(self, scene, guard, position.as_ref())?
            }
        };
        Ok(SceneSimulation { inner })
    }
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use controllers::PositionSource;
    use lie::NalgebraF64;

    use super::*;
    use crate::ScenePosition;

    type B = NalgebraF64;

    fn arrays(r: controllers::PositionReference<B>) -> [[f64; 3]; 8] {
        [r.x, r.v, r.a, r.jerk, r.snap, r.b1d, r.b1d_dot, r.b1d_ddot].map(B::vec3_to_array)
    }

    /// The scene's own reference handed back as an f64 function flies the
    /// same run bit for bit (f64 scene: the conversions are exact), and a
    /// different one is tracked instead.
    #[test]
    fn a_position_function_replaces_the_scene_reference() {
        let mut scene = crate::load("figure-eight").unwrap();
        scene.duration = 3.0;
        let spec = scene.plan[0].position.clone().unwrap();
        let own = ScenePosition::<B>::new(&spec);
        let f: PositionFn = Arc::new(move |t| arrays(own.position(t)));
        let guard = DivergenceGuard::default();
        let plain = SceneSimulation::new(&scene).unwrap().finish_all();
        let same = SceneSimulation::with_position(&scene, guard, f)
            .unwrap()
            .finish_all();
        assert_eq!(plain.samples.len(), same.samples.len());
        for (a, b) in plain.samples.iter().zip(&same.samples) {
            assert_eq!((a.t, a.x, a.r, a.omega), (b.t, b.x, b.r, b.omega));
        }
        // Hold 2 m below the start instead: after 3 s the vehicle is near it.
        let hold: PositionFn = Arc::new(|_| {
            let mut r = [[0.0; 3]; 8];
            r[0] = [0.0, 0.0, -2.0];
            r[5] = [1.0, 0.0, 0.0];
            r
        });
        let other = SceneSimulation::with_position(&scene, guard, hold)
            .unwrap()
            .finish_all();
        let last = other.samples.last().unwrap();
        assert_eq!(last.xd, [0.0, 0.0, -2.0]);
        assert!(last.ex < 0.2, "‖e_x‖ = {}", last.ex);
    }

    impl SceneSimulation {
        fn finish_all(mut self) -> RunOutput {
            let end = self.duration();
            self.advance_to(end).unwrap();
            self.finish().unwrap()
        }
    }
}
