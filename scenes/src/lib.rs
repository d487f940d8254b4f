//! Scenes as data, and the runs they describe.
//!
//! A [`Scene`] is data (vehicle, disturbances, initial state, flight-mode
//! plan with references, gains, integrator and step, control timing, scalar
//! and backend, duration, recording), built in Rust ([`builtin`]) or loaded
//! from TOML ([`Scene::from_toml`]; unknown keys and bad values are errors
//! naming the key, the value and the file position). [`run`] dispatches on
//! the scene's scalar and backend to the engine's generic loop
//! ([`scenarios::Simulation`]); [`builder`] hands back the simulation to
//! step and change in between. A [`Registry`] adds a program's own vehicle
//! kinds to scene files.
//!
//! ```
//! // The paper's flip from its scene, shortened to 2 s, samples every 10 ms.
//! let mut scene = scenes::load("paper-flip")?;
//! scene.duration = 2.0;
//! scene.record.sample = 0.01;
//! let out = scenes::run(&scene, Default::default())?;
//! assert_eq!(out.samples.len(), 201);
//! assert_eq!(out.switches.len(), 1); // attitude → position at 0.4 s
//! assert!(out.last.psi < 0.05 && out.max_thrust > 10.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! | module | what it holds |
//! |---|---|
//! | [`scene`] | the [`Scene`] struct, which is also the TOML schema, and its checks |
//! | [`builtin`] | the built-in scenes, by name |
//! | [`reference`](mod@reference) | the references a scene names, with their analytic derivatives |
//! | `registry` | [`Registry`]: vehicle kinds, and a [`Scene`] turned into a [`scenarios::Simulation`] |
//! | `scene_simulation` | [`SceneSimulation`]: a scene's simulation whatever its scalar and backend |
//! | `error` | [`Error`]: why a scene could not be loaded, built or run; [`SceneError`], [`BuildError`] |
//! | `overrides` | [`Overrides`]: command-line style `key=value` changes to a scene |
//! | `run_report` | [`RunReport`]: a run's summary as text |

#![deny(missing_docs)]

pub mod builtin;
mod error;
mod estimators;
mod overrides;
pub mod reference;
mod registry;
mod run_report;
pub mod scene;
mod scene_simulation;
mod sources;

pub use error::{BuildError, Error};
pub use estimators::iekf_config;
pub use overrides::Overrides;
pub use registry::{
    FactoryError, PARAMETERS, PositionFn, Registry, VehicleFactory, build_vehicle, parameter_mut,
    plan,
};
pub use run_report::RunReport;
pub use scene::{Scene, SceneError};
pub use scene_simulation::{SceneSimulation, StateF64};
pub use sources::{SceneAttitude, ScenePosition};

#[doc(hidden)]
pub use registry::{Seeds, builder_from, controller_gains, controller_params, gains};

use lie::Backend;
use scenarios::{RunOptions, RunOutput, SimulationBuilder};

/// Runs `scene` with its scalar and backend (built-in vehicle kinds; a
/// program's own kinds go through [`Registry::run`]).
pub fn run(scene: &Scene, opts: RunOptions<'_>) -> Result<RunOutput, Error> {
    Registry::new().run(scene, opts)
}

/// The simulation of `scene` on backend `B`, to build and step (built-in
/// vehicle kinds; see [`Registry::builder`]).
pub fn builder<B: Backend>(scene: &Scene) -> Result<SimulationBuilder<'static, B>, Error> {
    Registry::new().builder::<B>(scene)
}

/// Runs `scene` on backend `B` (built-in vehicle kinds).
pub fn run_generic<B: Backend>(scene: &Scene, opts: RunOptions<'_>) -> Result<RunOutput, Error> {
    Registry::new().run_generic::<B>(scene, opts)
}

/// A built-in scene by name, or a TOML file by path (built-in vehicle
/// kinds; see [`Registry::load`]).
pub fn load(name_or_path: &str) -> Result<Scene, SceneError> {
    Registry::new().load(name_or_path)
}
