//! `Simulation`: a scene's run to advance in pieces, look at and change.

use numpy::PyReadonlyArrayDyn;
use pyo3::exceptions::{PyRuntimeError, PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use scenarios::DivergenceGuard;
use scenes::{SceneSimulation, StateF64};

use crate::arrays::{array, input_col};
use crate::reference::{ErrorCell, position_fn, take_error};
use crate::result::{output_dict, termination};
use crate::scene::Scene;
use crate::sim_error;

/// A run of a scene, advanced by `advance_to`, inspected by `state` and
/// changed by `set_state`. Bound to the thread that made it (the flight
/// modes inside are not shareable across threads).
#[pyclass(module = "geopid._geopid", unsendable)]
pub struct Simulation {
    sim: Option<SceneSimulation>,
    /// The first exception of the reference callable, if any.
    errors: ErrorCell,
}

impl Simulation {
    fn sim(&self) -> PyResult<&SceneSimulation> {
        self.sim
            .as_ref()
            .ok_or_else(|| PyRuntimeError::new_err("this simulation has been finished"))
    }

    fn sim_mut(&mut self) -> PyResult<&mut SceneSimulation> {
        self.sim
            .as_mut()
            .ok_or_else(|| PyRuntimeError::new_err("this simulation has been finished"))
    }
}

/// One state's array of shape `tail` (or `(1, *tail)`), finite; a stack
/// of several is an error, not its first row.
fn one(field: &str, a: &PyReadonlyArrayDyn<'_, f64>, tail: &[usize]) -> PyResult<Vec<f64>> {
    let (rows, col) = input_col(field, a, None, tail, true, true)?;
    if rows != 1 {
        return Err(PyValueError::new_err(format!(
            "{field}: {rows} rows given, one state at a time"
        )));
    }
    Ok(col.data)
}

/// A vector argument of `n` values, or the current one when `None`.
fn vector(field: &str, a: Option<PyReadonlyArrayDyn<'_, f64>>, now: &[f64]) -> PyResult<Vec<f64>> {
    match a {
        None => Ok(now.to_vec()),
        Some(a) => one(field, &a, &[now.len()]),
    }
}

#[pymethods]
impl Simulation {
    /// The simulation of `scene` at t = 0; `reference`, a callable as in
    /// `run`, replaces the position reference of position-mode segments.
    #[new]
    #[pyo3(signature = (scene, reference=None))]
    fn new(py: Python<'_>, scene: &Scene, reference: Option<Py<PyAny>>) -> PyResult<Self> {
        let errors = ErrorCell::default();
        let sim = match reference {
            Some(f) => SceneSimulation::with_position(
                &scene.inner,
                DivergenceGuard::default(),
                position_fn(f, errors.clone()),
            ),
            None => SceneSimulation::new(&scene.inner),
        }
        .map_err(|e| take_error(&errors, sim_error(py, &e)))?;
        Ok(Self {
            sim: Some(sim),
            errors,
        })
    }

    /// Advances to `t` (at most the duration): every step ending at or
    /// before `t` is taken, so the pieces add up to one run bit for bit.
    /// An exception of the reference callable is re-raised.
    fn advance_to(&mut self, py: Python<'_>, t: f64) -> PyResult<()> {
        let r = self.sim_mut()?.advance_to(t);
        let raised = self.errors.lock().unwrap_or_else(|p| p.into_inner()).take();
        match (r, raised) {
            (_, Some(e)) => Err(e),
            (Err(e), None) => Err(sim_error(py, &e)),
            (Ok(()), None) => Ok(()),
        }
    }

    /// The state now: t, x, v, R (3×3), omega, integrals, vehicle_states
    /// (numpy arrays), segment and mode.
    fn state<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let s = self.sim()?.state();
        let d = PyDict::new(py);
        d.set_item("t", s.t)?;
        d.set_item("x", array(py, &[3], s.x.to_vec())?)?;
        d.set_item("v", array(py, &[3], s.v.to_vec())?)?;
        d.set_item("R", array(py, &[3, 3], s.r.as_flattened().to_vec())?)?;
        d.set_item("omega", array(py, &[3], s.omega.to_vec())?)?;
        let ni = s.integrals.len();
        d.set_item("integrals", array(py, &[ni], s.integrals)?)?;
        let nv = s.vehicle_states.len();
        d.set_item("vehicle_states", array(py, &[nv], s.vehicle_states)?)?;
        d.set_item("segment", s.segment)?;
        d.set_item("mode", s.mode)?;
        Ok(d)
    }

    /// Replaces parts of the state, by keyword: `x`, `v`, `R`, `omega`,
    /// `integrals`, `vehicle_states` (the others stay); shapes as `state`
    /// gives them, values finite, or `ValueError` naming the field.
    #[pyo3(signature = (**kwargs))]
    fn set_state(&mut self, py: Python<'_>, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<()> {
        let now = self.sim()?.state();
        let names = ["x", "v", "R", "omega", "integrals", "vehicle_states"];
        let mut given: [Option<PyReadonlyArrayDyn<'_, f64>>; 6] = Default::default();
        for (k, a) in kwargs.iter().flat_map(|d| d.iter()) {
            let k: String = k.extract()?;
            let Some(slot) = names.iter().position(|n| *n == k) else {
                return Err(PyTypeError::new_err(format!(
                    "set_state: unknown field `{k}`: expected {}",
                    names.join(", ")
                )));
            };
            let a = a
                .extract()
                .map_err(|e| PyValueError::new_err(format!("{k}: not a float array ({e})")))?;
            given[slot] = Some(a);
        }
        let [x, v, r, omega, integrals, vehicle_states] = given;
        let three = |f, a, cur: [f64; 3]| -> PyResult<[f64; 3]> {
            let v = vector(f, a, &cur)?;
            Ok([v[0], v[1], v[2]])
        };
        let r = match r {
            None => now.r,
            Some(a) => {
                let m = one("R", &a, &[3, 3])?;
                [[m[0], m[1], m[2]], [m[3], m[4], m[5]], [m[6], m[7], m[8]]]
            }
        };
        let next = StateF64 {
            x: three("x", x, now.x)?,
            v: three("v", v, now.v)?,
            r,
            omega: three("omega", omega, now.omega)?,
            integrals: vector("integrals", integrals, &now.integrals)?,
            vehicle_states: vector("vehicle_states", vehicle_states, &now.vehicle_states)?,
            ..now
        };
        self.sim_mut()?
            .set_state(&next)
            .map_err(|e| sim_error(py, &e))
    }

    /// Time reached, s.
    #[getter]
    fn time(&self) -> PyResult<f64> {
        Ok(self.sim()?.time())
    }

    /// The run's duration, s.
    #[getter]
    fn duration(&self) -> PyResult<f64> {
        Ok(self.sim()?.duration())
    }

    /// How the run ended (a dict as in `Result.termination`), or None
    /// while it can go on.
    fn termination<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.sim()?
            .termination()
            .map(|t| termination(py, &t))
            .transpose()
    }

    /// The run so far, as `run` returns it.
    fn output<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        output_dict(py, self.sim()?.output())
    }

    /// Ends the run where it is and returns its output; the object is
    /// spent afterwards.
    fn finish<'py>(&mut self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let sim = self
            .sim
            .take()
            .ok_or_else(|| PyRuntimeError::new_err("this simulation has been finished"))?;
        let out = sim.finish().map_err(|e| sim_error(py, &e))?;
        output_dict(py, &out)
    }
}
