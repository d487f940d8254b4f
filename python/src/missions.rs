//! `minsnap`: a minimum-snap trajectory through waypoints, as its pieces.

use missions::{MinSnap, MissionError, pptraj};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::arrays::array;

/// A planner error as `ValueError` with the `field` it names.
fn mission_error(py: Python<'_>, e: &MissionError) -> PyErr {
    let err = PyValueError::new_err(e.to_string());
    if let MissionError::Input { field, .. } = e {
        let _ = err.value(py).setattr("field", field.as_str());
    }
    err
}

/// The minimum-snap trajectory through `points` (m, e3 down): a dict of
/// `durations` (n,), `coefficients` (n, 4, 8: x, y, z, yaw in ascending
/// powers of each piece's local time), `pptraj` (the Crazyflie CSV, z
/// up) and, at the times `sample`, `x` (m, 5, 3: x_d to its fourth
/// derivative) and `yaw` (m, 3: ψ, ψ̇, ψ̈).
#[pyfunction]
#[pyo3(signature = (points, yaw=None, times=None, mean_speed=None, time_budget=None,
    start_velocity=None, end_velocity=None, sample=None))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn minsnap<'py>(
    py: Python<'py>,
    points: Vec<[f64; 3]>,
    yaw: Option<Vec<f64>>,
    times: Option<Vec<f64>>,
    mean_speed: Option<f64>,
    time_budget: Option<f64>,
    start_velocity: Option<[f64; 3]>,
    end_velocity: Option<[f64; 3]>,
    sample: Option<Vec<f64>>,
) -> PyResult<Bound<'py, PyDict>> {
    let mut p = MinSnap::through(&points);
    if let Some(y) = &yaw {
        p = p.yaw(y);
    }
    match (times, mean_speed, time_budget) {
        (Some(t), None, None) => p = p.times(&t),
        (None, Some(v), None) => p = p.mean_speed(v),
        (None, None, Some(b)) => p = p.time_budget(b),
        (None, None, None) => {}
        _ => {
            return Err(PyValueError::new_err(
                "give at most one of `times`, `mean_speed` and `time_budget`",
            ));
        }
    }
    if start_velocity.is_some() || end_velocity.is_some() {
        p = p.end_velocities(
            start_velocity.unwrap_or([0.0; 3]),
            end_velocity.unwrap_or([0.0; 3]),
        );
    }
    let traj = py.detach(|| p.solve()).map_err(|e| mission_error(py, &e))?;
    let pieces = traj.pieces();
    let n = pieces.len();
    let out = PyDict::new(py);
    out.set_item(
        "durations",
        array(py, &[n], pieces.iter().map(|p| p.duration).collect())?,
    )?;
    let coeffs = pieces
        .iter()
        .flat_map(|p| p.coeffs.iter().flatten().copied());
    out.set_item("coefficients", array(py, &[n, 4, 8], coeffs.collect())?)?;
    out.set_item("pptraj", pptraj::write(&traj))?;
    if let Some(ts) = sample {
        if let Some(t) = ts.iter().find(|t| !t.is_finite()) {
            return Err(PyValueError::new_err(format!(
                "sample: {t} is not a finite time (s)"
            )));
        }
        let flats: Vec<_> = ts.iter().map(|t| traj.flat(*t)).collect();
        let x = flats.iter().flat_map(|f| f.x.iter().flatten().copied());
        out.set_item("x", array(py, &[ts.len(), 5, 3], x.collect())?)?;
        let y = flats.iter().flat_map(|f| f.yaw);
        out.set_item("yaw", array(py, &[ts.len(), 3], y.collect())?)?;
    }
    Ok(out)
}
