//! `montecarlo`: the paper's two Monte Carlo experiments, the rows of
//! `samples.csv` as columns.

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use studies::montecarlo::{Outcome, SAMPLES_HEADER, Setup, write_samples};

use crate::arrays::{array, interruptible};
use crate::sim_error;

/// The setup: the command line's defaults with the keys of `json` (a
/// JSON object with `Setup`'s field names) laid over them; an unknown
/// key is a `ValueError` naming it.
fn setup(json: Option<&str>) -> PyResult<Setup> {
    let mut value = serde_json::to_value(Setup::default())
        .map_err(|e| PyValueError::new_err(format!("setup: {e}")))?;
    if let Some(text) = json {
        let given: serde_json::Map<String, serde_json::Value> =
            serde_json::from_str(text).map_err(|e| PyValueError::new_err(format!("setup: {e}")))?;
        let base = value
            .as_object_mut()
            .ok_or_else(|| PyValueError::new_err("setup"))?;
        for (k, v) in given {
            if !base.contains_key(&k) {
                let keys: Vec<&str> = base.keys().map(String::as_str).collect();
                return Err(PyValueError::new_err(format!(
                    "unknown setting `{k}`: expected one of {}",
                    keys.join(", ")
                )));
            }
            base.insert(k, v);
        }
    }
    let s: Setup =
        serde_json::from_value(value).map_err(|e| PyValueError::new_err(format!("setup: {e}")))?;
    Ok(s)
}

/// Runs samples `0..samples` (or `indices`) of the experiment on
/// `threads` threads (None: one per core), with the interpreter's lock
/// released; Ctrl-C stops it and raises `KeyboardInterrupt`. Returns the
/// columns of `samples.csv` and its text (`csv`), byte for byte what
/// `cargo xtask montecarlo` writes for the same setup. With `lanes`, on
/// SIMD lanes (`Setup::run_lanes`; the setup must have
/// `locate_events = false`).
#[pyfunction]
#[pyo3(signature = (setup_json=None, indices=None, threads=None, lanes=false))]
pub(crate) fn montecarlo<'py>(
    py: Python<'py>,
    setup_json: Option<&str>,
    indices: Option<Vec<u64>>,
    threads: Option<usize>,
    lanes: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let s = setup(setup_json)?;
    if threads == Some(0) {
        return Err(PyValueError::new_err("threads = 0: must be at least 1"));
    }
    let indices = indices.unwrap_or_else(|| (0..s.samples).collect());
    let rows = interruptible(py, |cancel| {
        if lanes {
            s.run_lanes_until_cancelled(&indices, threads, None, cancel)
                .map(|(rows, _)| rows)
        } else {
            s.run_until_cancelled(&indices, threads, None, cancel)
        }
    })?
    .map_err(|e| sim_error(py, &e))?;
    columns(py, &rows)
}

/// The header of `samples.csv`.
#[pyfunction]
pub(crate) fn montecarlo_header() -> &'static str {
    SAMPLES_HEADER
}

fn columns<'py>(py: Python<'py>, rows: &[Outcome]) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let n = rows.len();
    let f = |get: fn(&Outcome) -> f64| array(py, &[n], rows.iter().map(get).collect());
    d.set_item("index", rows.iter().map(|r| r.index).collect::<Vec<_>>())?;
    d.set_item("angle", f(|r| r.angle)?)?;
    for k in 0..3 {
        let a = array(py, &[n], rows.iter().map(|r| r.axis[k]).collect())?;
        d.set_item(format!("axis{}", k + 1), a)?;
    }
    d.set_item("omega0", f(|r| r.omega0)?)?;
    d.set_item("ex0", f(|r| r.ex0)?)?;
    d.set_item(
        "converged",
        rows.iter().map(|r| r.converged).collect::<Vec<_>>(),
    )?;
    d.set_item("t_converge", f(|r| r.t_converge)?)?;
    d.set_item("final_psi", f(|r| r.final_psi)?)?;
    d.set_item("final_ex", f(|r| r.final_ex)?)?;
    d.set_item("max_thrust", f(|r| r.max_thrust)?)?;
    d.set_item("max_rotor", f(|r| r.max_rotor)?)?;
    d.set_item("steps", rows.iter().map(|r| r.steps).collect::<Vec<_>>())?;
    let status: Vec<&str> = rows.iter().map(|r| r.status.name()).collect();
    d.set_item("status", status)?;
    d.set_item("csv", write_samples(rows))?;
    Ok(d)
}
