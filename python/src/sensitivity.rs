//! `gradient` and `tune`: exact derivatives of a scene's tracking error
//! with respect to its parameters, and the gains tuned on them.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use scenes::Registry;
use studies::sensitivity::{GainTuning, TUNED_GAINS, tracking_gradient, tune_gains};

use crate::arrays::{array, rows};
use crate::scene::Scene;
use crate::sim_error;

/// The tracking cost `Σ ‖x − x_d‖² Δt` of `scene` sampled every `every`
/// (default: the scene's record interval) and its gradient with respect
/// to `params` (1 to 4 parameter names), with the interpreter's lock
/// released.
#[pyfunction]
#[pyo3(signature = (scene, params, every=None))]
pub(crate) fn gradient<'py>(
    py: Python<'py>,
    scene: &Scene,
    params: Vec<String>,
    every: Option<f64>,
) -> PyResult<(f64, Bound<'py, PyAny>)> {
    let sc = &scene.inner;
    let every = every.unwrap_or(sc.record.sample);
    let names: Vec<&str> = params.iter().map(String::as_str).collect();
    let out = py.detach(|| tracking_gradient(&Registry::new(), sc, &names, every));
    let (value, g) = out.map_err(|e| sim_error(py, &e))?;
    let n = g.len();
    Ok((value, array(py, &[n], g)?))
}

/// `k_x, k_v, k_R, k_Ω` tuned on the exact gradient of the tracking cost
/// (`cargo xtask tune`), with the interpreter's lock released. Returns
/// the tuned scene, each iteration's gains, cost, gradient, peak thrust
/// and line-search runs, and the tuned scene's cost (each the mean over
/// `noise_seeds` noise realisations when that is above 1).
#[pyfunction]
#[pyo3(signature = (scene, factor, thrust_to_weight, gradients, every=None, noise_seeds=0))]
pub(crate) fn tune<'py>(
    py: Python<'py>,
    scene: &Scene,
    factor: f64,
    thrust_to_weight: Option<f64>,
    gradients: usize,
    every: Option<f64>,
    noise_seeds: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let sc = &scene.inner;
    let spec = GainTuning {
        factor,
        every: every.unwrap_or(sc.record.sample),
        max_gradients: gradients,
        max_thrust: thrust_to_weight.map(|r| r * sc.vehicle.mass * sc.vehicle.gravity),
        noise_seeds,
    };
    let out = py.detach(|| {
        let reg = Registry::new();
        tune_gains(&reg, sc, &spec, &mut |_| {})
    });
    let out = out.map_err(|e| sim_error(py, &e))?;
    let (tuned, history, last) = (out.scene, out.history, out.final_cost);
    let d = PyDict::new(py);
    d.set_item("names", TUNED_GAINS.to_vec())?;
    d.set_item("scene", Scene { inner: tuned })?;
    d.set_item("gains", rows(py, history.iter().map(|s| s.values))?)?;
    d.set_item("gradient", rows(py, history.iter().map(|s| s.gradient))?)?;
    let col = |f: fn(&studies::sensitivity::TuneStep<4>) -> f64| {
        array(py, &[history.len()], history.iter().map(f).collect())
    };
    d.set_item("cost", col(|s| s.cost)?)?;
    d.set_item("max_thrust", col(|s| s.max_thrust)?)?;
    d.set_item(
        "plain_runs",
        history.iter().map(|s| s.plain_runs).collect::<Vec<_>>(),
    )?;
    d.set_item("final_cost", last)?;
    Ok(d)
}
