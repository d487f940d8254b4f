//! Scenes of the geometric PID paper, run end to end, and the simulation
//! loop any vehicle, flight mode, reference and integrator plug into.
//!
//! [`Simulation`] is the library: a `Box<dyn Vehicle<B>>` (with internal
//! states if it has actuator dynamics), a plan of [`Segment`]s (any
//! [`Mode`](controllers::Mode), left at a time, on `Ψ`, or on a user
//! [`Condition`]), any integrator, continuous or sampled [`Control`], and
//! recording; it returns a [`RunOutput`] that [`output`] writes as CSV or
//! MCAP. A [`Scene`] is one front end of it (a [`Registry`] adds a
//! program's own vehicle kinds to scene files).
//!
//! ```
//! // The paper's flip from its scene, shortened to 2 s, samples every 10 ms.
//! let mut scene = scenarios::load("paper-flip")?;
//! scene.duration = 2.0;
//! scene.record.sample = 0.01;
//! let out = scenarios::run(&scene, Default::default())?;
//! assert_eq!(out.samples.len(), 201);
//! assert_eq!(out.switches.len(), 1); // attitude → position at 0.4 s
//! assert!(out.last.psi < 0.05 && out.max_thrust > 10.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! A [`Scene`] is data (vehicle, disturbances, initial state, flight-mode
//! plan with references, gains, integrator and step, control timing, scalar
//! and backend, duration, recording), built in Rust ([`builtin`]) or loaded
//! from TOML ([`Scene::from_toml`]; unknown keys and bad values are errors
//! naming the key, the value and the file position). [`run`] dispatches on
//! the scene's scalar and backend to the generic loop, which:
//!
//! - lands exactly on every mode switch and control sample (a step is
//!   shortened to hit them; times are `k·Δ`, never sums), and takes the
//!   record samples between steps from each step's continuous extension
//!   (`integrators::dense`), so recording never changes the trajectory;
//! - switches flight modes at their `until` time or, for `until_psi` (and
//!   a user condition), at the located instant Ψ drops below the threshold
//!   (bisection on redone steps);
//! - locates the breakpoints of the active mode inside a segment (the
//!   paper's sat′: a component of e_i crossing ±σ) by cubic Hermite interpolation of e_i, ė_i over the
//!   step, refines it by Newton on the integrated e_i and splits the step
//!   there, for every stepper, integrating each side on its own branch of
//!   sat′ (see `controllers::SatBranch`);
//! - pays only for what the scene uses: a pinned vehicle integrates no
//!   translation, a vehicle without disturbance evaluates none, a run with
//!   `record = false` keeps only the final state.
//!
//! [`output`] writes the CSV and the MCAP log; [`metrics`] holds what the
//! regression suite checks.
//!
//! # Layers
//! The modules import only downward or sideways (CI checks it):
//! the engine ([`Simulation`] and everything it needs, the
//! [`output::Sink`] trait it writes into, and `lanes` with feature `simd`),
//! which knows nothing of scene files or studies; the [`output`] sinks
//! (CSV, MCAP); the scenes ([`scene`], [`builtin`], [`reference`](mod@reference), building
//! a `Simulation` from a [`Scene`], [`RunReport`]); the studies
//! ([`metrics`], [`gains`], [`montecarlo`], [`regress`], [`stress`]); and
//! `figures` (feature `plot`) on top.

#![deny(missing_docs)]

pub mod builtin;
mod dynamic;
#[cfg(feature = "plot")]
pub mod figures;
mod from_scene;
pub mod gains;
#[cfg(feature = "simd")]
pub mod lanes;
pub mod metrics;
pub mod montecarlo;
pub mod output;
mod overrides;
pub mod reference;
pub mod regress;
mod report;
pub mod scene;
pub mod sensitivity;
mod sim;
pub mod stress;

pub use dynamic::{SceneSimulation, StateF64};
pub use from_scene::{
    PositionFn, Registry, SceneAttitude, ScenePosition, VehicleFactory, build_vehicle, plan,
};
pub use overrides::Overrides;
pub use report::RunReport;
pub use scene::{Scene, SceneError};
pub use sim::{
    CAPACITIES, Condition, Control, Divergence, DivergenceGuard, Health, OpenLoop, RunOptions,
    RunOutput, Sample, Segment, SimError, SimState, SimStateMut, Simulation, SimulationBuilder,
    SwitchRecord, Termination, Until,
};

use lie::Backend;

/// Runs `scene` with its scalar and backend (built-in vehicle kinds; a
/// program's own kinds go through [`Registry::run`]).
pub fn run(scene: &Scene, opts: RunOptions<'_>) -> Result<RunOutput, SimError> {
    Registry::new().run(scene, opts)
}

/// The simulation of `scene` on backend `B`, to build and step (built-in
/// vehicle kinds; see [`Registry::builder`]).
pub fn builder<B: Backend>(scene: &Scene) -> Result<SimulationBuilder<'static, B>, SimError> {
    Registry::new().builder::<B>(scene)
}

/// Runs `scene` on backend `B` (built-in vehicle kinds).
pub fn run_generic<B: Backend>(scene: &Scene, opts: RunOptions<'_>) -> Result<RunOutput, SimError> {
    Registry::new().run_generic::<B>(scene, opts)
}

/// A built-in scene by name, or a TOML file by path (built-in vehicle
/// kinds; see [`Registry::load`]).
pub fn load(name_or_path: &str) -> Result<Scene, SceneError> {
    Registry::new().load(name_or_path)
}
