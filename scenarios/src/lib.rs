//! Scenes of the geometric PID paper, run end to end.
//!
//! A [`Scene`] is data (vehicle, disturbances, initial state, flight-mode
//! plan with references, gains, integrator and step, control timing, scalar
//! and backend, duration, recording), built in Rust ([`builtin`]) or loaded
//! from TOML ([`Scene::from_toml`]; unknown keys and bad values are errors
//! naming the key, the value and the file position). [`run`] dispatches on
//! the scene's scalar and backend to the generic loop, which:
//!
//! - lands exactly on every mode switch, record sample and control sample
//!   (a step is shortened to hit them; times are `k·Δ`, never sums);
//! - switches flight modes at their `until` time or, for `until_psi`, at
//!   the located instant Ψ drops below the threshold (bisection on redone
//!   steps);
//! - locates the sat′ discontinuities inside a segment (a component of
//!   e_i crossing ±σ) by cubic Hermite interpolation of e_i, ė_i over the
//!   step, refines it by Newton on the integrated e_i and splits the step
//!   there, for every stepper, integrating each side on its own branch of
//!   sat′ (see `controllers::SatBranch`);
//! - pays only for what the scene uses: a pinned vehicle integrates no
//!   translation, a vehicle without disturbance evaluates none, a run with
//!   `record = false` keeps only the final state.
//!
//! [`output`] writes the CSV and the MCAP log; [`metrics`] holds what the
//! regression suite checks.

#![deny(missing_docs)]

pub mod builtin;
pub mod metrics;
pub mod output;
pub mod reference;
pub mod scene;
mod sim;

pub use scene::{Scene, SceneError};
pub use sim::{RunOptions, RunOutput, Sample, SimError, SwitchRecord, run_generic};

use lie::{GlamF32, GlamF64, NalgebraF32, NalgebraF64};
use scene::{BackendKind, Scalar};

/// Runs `scene` with its scalar and backend.
pub fn run(scene: &Scene, opts: RunOptions<'_>) -> Result<RunOutput, SimError> {
    match (scene.scalar, scene.backend) {
        (Scalar::F64, BackendKind::Nalgebra) => run_generic::<NalgebraF64>(scene, opts),
        (Scalar::F64, BackendKind::Glam) => run_generic::<GlamF64>(scene, opts),
        (Scalar::F32, BackendKind::Nalgebra) => run_generic::<NalgebraF32>(scene, opts),
        (Scalar::F32, BackendKind::Glam) => run_generic::<GlamF32>(scene, opts),
    }
}

/// A built-in scene by name, or a TOML file by path.
pub fn load(name_or_path: &str) -> Result<Scene, SceneError> {
    if let Some(s) = builtin::by_name(name_or_path) {
        return Ok(s);
    }
    let path = std::path::Path::new(name_or_path);
    if path.exists() || name_or_path.ends_with(".toml") {
        let text = std::fs::read_to_string(path).map_err(|e| SceneError {
            message: format!("cannot read scene file `{name_or_path}`: {e}"),
            location: None,
        })?;
        return Scene::from_toml(&text, name_or_path);
    }
    let names: Vec<String> = builtin::all().into_iter().map(|s| s.name).collect();
    Err(SceneError {
        message: format!(
            "no scene `{name_or_path}`: not a built-in ({}) and not a file",
            names.join(", ")
        ),
        location: None,
    })
}
