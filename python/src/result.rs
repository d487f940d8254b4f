//! `run`: a scene to the end, and a `RunOutput` as a dict of numpy arrays.

use std::path::PathBuf;

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use scenarios::{Divergence, DivergenceGuard, RunOptions, RunOutput, Termination};
use scenes::SceneSimulation;

use crate::arrays::{array, interruptible, mats, rows};
use crate::reference::{ErrorCell, position_fn, take_error};
use crate::scene::Scene;
use crate::{DivergedError, sim_error};

/// How a run ended, as a dict: `kind` (completed, stopped, interrupted,
/// diverged, crashed), `t` (None when completed), for a divergence `what`
/// (omega, position_error, moment, substeps) and `value`, for a crash the
/// foot `point` and its `speed` into the ground; a reason the
/// engine gains later reads `unknown` until this binding names it.
pub(crate) fn termination<'py>(py: Python<'py>, t: &Termination) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let (kind, time) = match *t {
        Termination::Completed => ("completed", None),
        Termination::StoppedBy { t } => ("stopped", Some(t)),
        Termination::Interrupted { t } => ("interrupted", Some(t)),
        Termination::Diverged { what, t } => {
            let (name, value) = match what {
                Divergence::Omega(w) => ("omega", w),
                Divergence::PositionError(e) => ("position_error", e),
                Divergence::Moment(m) => ("moment", m),
                Divergence::Substeps(n) => ("substeps", f64::from(n)),
                _ => ("unknown", f64::NAN),
            };
            d.set_item("what", name)?;
            d.set_item("value", value)?;
            ("diverged", Some(t))
        }
        Termination::Crashed { t, point, speed } => {
            d.set_item("point", point)?;
            d.set_item("speed", speed)?;
            ("crashed", Some(t))
        }
        _ => ("unknown", None),
    };
    d.set_item("kind", kind)?;
    d.set_item("t", time)?;
    Ok(d)
}

/// The samples' columns and the run's figures.
pub(crate) fn output_dict<'py>(py: Python<'py>, out: &RunOutput) -> PyResult<Bound<'py, PyDict>> {
    let s = &out.samples;
    let d = PyDict::new(py);
    let n = s.len();
    let col = |f: fn(&scenarios::Sample) -> f64| array(py, &[n], s.iter().map(f).collect());
    d.set_item("t", col(|s| s.t)?)?;
    d.set_item("x", rows(py, s.iter().map(|s| s.x))?)?;
    d.set_item("v", rows(py, s.iter().map(|s| s.v))?)?;
    d.set_item("R", mats(py, s.iter().map(|s| s.r))?)?;
    d.set_item("omega", rows(py, s.iter().map(|s| s.omega))?)?;
    d.set_item("psi", col(|s| s.psi)?)?;
    d.set_item("ex", col(|s| s.ex)?)?;
    d.set_item("thrust", col(|s| s.thrust)?)?;
    d.set_item("moment", rows(py, s.iter().map(|s| s.moment))?)?;
    d.set_item("Rd", mats(py, s.iter().map(|s| s.rd))?)?;
    d.set_item("omega_d", rows(py, s.iter().map(|s| s.omega_d))?)?;
    d.set_item("xd", rows(py, s.iter().map(|s| s.xd))?)?;
    d.set_item("e_att", rows(py, s.iter().map(|s| s.e_att))?)?;
    d.set_item("e_pos", rows(py, s.iter().map(|s| s.e_pos))?)?;
    d.set_item("wind", rows(py, s.iter().map(|s| s.wind))?)?;
    for (key, get) in [
        (
            "rotors",
            (|s| &s.rotors) as fn(&scenarios::Sample) -> &Vec<f64>,
        ),
        ("vehicle_states", |s| &s.vehicle_states),
    ] {
        // Every sample of a run has the same count; a ragged one would be
        // a bug upstream, shown as NaN padding rather than a crash.
        let k = s.iter().map(|x| get(x).len()).max().unwrap_or(0);
        let data = s
            .iter()
            .flat_map(|x| (0..k).map(move |i| get(x).get(i).copied().unwrap_or(f64::NAN)))
            .collect();
        d.set_item(key, array(py, &[n, k], data)?)?;
    }
    let segment: Vec<usize> = s.iter().map(|s| s.segment).collect();
    d.set_item("segment", segment)?;
    let modes: Vec<&str> = s.iter().map(|s| s.mode).collect();
    d.set_item("mode", modes)?;
    d.set_item("mode_names", out.mode_names.clone())?;
    let switches: Vec<(f64, usize, usize)> =
        out.switches.iter().map(|w| (w.t, w.from, w.to)).collect();
    d.set_item("switches", switches)?;
    let events: Vec<(f64, usize)> = out.event_times.iter().map(|e| (e.t, e.component)).collect();
    d.set_item("event_times", events)?;
    let contacts: Vec<(f64, usize, bool, f64)> = out
        .contacts
        .iter()
        .map(|c| (c.t, c.point, c.pushing, c.normal_speed))
        .collect();
    d.set_item("contacts", contacts)?;
    d.set_item("steps", out.steps)?;
    d.set_item("evaluations", out.evaluations)?;
    d.set_item("max_thrust", out.max_thrust)?;
    d.set_item("max_rotor", out.max_rotor)?;
    d.set_item("wall", out.wall)?;
    d.set_item("warnings", out.warnings.clone())?;
    d.set_item("max_orthogonality_error", out.max_orthogonality_error)?;
    d.set_item("psi_range", (out.psi_range.min, out.psi_range.max))?;
    d.set_item("epsilon", out.epsilon)?;
    let health: Vec<String> = out.health().iter().map(|h| h.to_string()).collect();
    d.set_item("health", health)?;
    d.set_item("termination", termination(py, &out.termination)?)?;
    d.set_item("measurements", measurements(py, out)?)?;
    d.set_item("estimate", estimate(py, out)?)?;
    Ok(d)
}

/// The measurements of a run with sensors, by sensor, each a dict of
/// arrays with a row per sample: `imu` (`t`, `accel`, `gyro`), `mocap`
/// (`t`, `arrival`, `x`, `v`, `R`, `omega`), `gps` (`t`, `arrival`, `x`,
/// `v`), `baro` (`t`, `height`); a sensor the run lacks is absent.
fn measurements<'py>(py: Python<'py>, out: &RunOutput) -> PyResult<Bound<'py, PyDict>> {
    use scenarios::MeasurementRecord as M;
    let d = PyDict::new(py);
    let ms = &out.measurements;
    let t_of =
        |f: fn(&M) -> bool| -> Vec<f64> { ms.iter().filter(|m| f(m)).map(|m| m.t()).collect() };
    let imu: Vec<([f64; 3], [f64; 3])> = ms
        .iter()
        .filter_map(|m| match m {
            M::Imu { accel, gyro, .. } => Some((*accel, *gyro)),
            _ => None,
        })
        .collect();
    if !imu.is_empty() {
        let s = PyDict::new(py);
        let t = t_of(|m| matches!(m, M::Imu { .. }));
        s.set_item("t", array(py, &[t.len()], t)?)?;
        s.set_item("accel", rows(py, imu.iter().map(|r| r.0))?)?;
        s.set_item("gyro", rows(py, imu.iter().map(|r| r.1))?)?;
        d.set_item("imu", s)?;
    }
    let mocap: Vec<(f64, scenarios::NavSample)> = ms
        .iter()
        .filter_map(|m| match m {
            M::Mocap { arrival, state, .. } => Some((*arrival, *state)),
            _ => None,
        })
        .collect();
    if !mocap.is_empty() {
        let s = PyDict::new(py);
        let t = t_of(|m| matches!(m, M::Mocap { .. }));
        s.set_item("t", array(py, &[t.len()], t)?)?;
        let arrival: Vec<f64> = mocap.iter().map(|m| m.0).collect();
        s.set_item("arrival", array(py, &[arrival.len()], arrival)?)?;
        s.set_item("x", rows(py, mocap.iter().map(|m| m.1.x))?)?;
        s.set_item("v", rows(py, mocap.iter().map(|m| m.1.v))?)?;
        s.set_item("R", mats(py, mocap.iter().map(|m| m.1.r))?)?;
        s.set_item("omega", rows(py, mocap.iter().map(|m| m.1.omega))?)?;
        d.set_item("mocap", s)?;
    }
    let gps: Vec<(f64, [f64; 3], [f64; 3])> = ms
        .iter()
        .filter_map(|m| match m {
            M::Gps { arrival, x, v, .. } => Some((*arrival, *x, *v)),
            _ => None,
        })
        .collect();
    if !gps.is_empty() {
        let s = PyDict::new(py);
        let t = t_of(|m| matches!(m, M::Gps { .. }));
        s.set_item("t", array(py, &[t.len()], t)?)?;
        let arrival: Vec<f64> = gps.iter().map(|m| m.0).collect();
        s.set_item("arrival", array(py, &[arrival.len()], arrival)?)?;
        s.set_item("x", rows(py, gps.iter().map(|m| m.1))?)?;
        s.set_item("v", rows(py, gps.iter().map(|m| m.2))?)?;
        d.set_item("gps", s)?;
    }
    let baro: Vec<f64> = ms
        .iter()
        .filter_map(|m| match m {
            M::Baro { height, .. } => Some(*height),
            _ => None,
        })
        .collect();
    if !baro.is_empty() {
        let s = PyDict::new(py);
        let t = t_of(|m| matches!(m, M::Baro { .. }));
        s.set_item("t", array(py, &[t.len()], t)?)?;
        s.set_item("height", array(py, &[baro.len()], baro)?)?;
        d.set_item("baro", s)?;
    }
    Ok(d)
}

/// The estimate the modes read at each record sample (`x`, `v`, `R`,
/// `omega`; for a filter that keeps a covariance also `sigma`, the
/// standard deviations of its error states, `NaN` past its count, `nis`,
/// its last correction's NIS, and `innovation`, that correction's
/// observation less its prediction, `NaN` past its count), or `None` for
/// a run without an estimator.
fn estimate<'py>(py: Python<'py>, out: &RunOutput) -> PyResult<Option<Bound<'py, PyDict>>> {
    let est: Vec<scenarios::NavSample> = out
        .samples
        .iter()
        .filter_map(|s| s.sensors.as_deref().and_then(|r| r.estimate))
        .collect();
    if est.is_empty() || est.len() != out.samples.len() {
        return Ok(None);
    }
    let d = PyDict::new(py);
    d.set_item("x", rows(py, est.iter().map(|e| e.x))?)?;
    d.set_item("v", rows(py, est.iter().map(|e| e.v))?)?;
    d.set_item("R", mats(py, est.iter().map(|e| e.r))?)?;
    d.set_item("omega", rows(py, est.iter().map(|e| e.omega))?)?;
    let diag: Vec<_> = out
        .samples
        .iter()
        .filter_map(|s| s.sensors.as_deref().and_then(|r| r.diagnostics))
        .collect();
    if diag.len() == est.len() {
        let sig: Vec<f64> = diag.iter().flat_map(|d| d.sigma).collect();
        d.set_item("sigma", array(py, &[diag.len(), 15], sig)?)?;
        let nis: Vec<f64> = diag
            .iter()
            .map(|d| d.nis.map_or(f64::NAN, |n| n.0))
            .collect();
        d.set_item("nis", array(py, &[diag.len()], nis)?)?;
        let innov: Vec<f64> = diag.iter().flat_map(|d| d.innovation).collect();
        d.set_item("innovation", array(py, &[diag.len(), 6], innov)?)?;
    }
    Ok(Some(d))
}

/// The guard from a dict with keys `omega` (rad/s), `position_error`
/// (m), `moment` (N m), `substeps`.
fn guard(d: Option<&Bound<'_, PyDict>>) -> PyResult<DivergenceGuard> {
    let mut g = DivergenceGuard::default();
    for (k, v) in d.iter().flat_map(|d| d.iter()) {
        let k: String = k.extract()?;
        match k.as_str() {
            "omega" => g.omega = v.extract()?,
            "position_error" => g.position_error = v.extract()?,
            "moment" => g.moment = v.extract()?,
            "substeps" => g.substeps = v.extract()?,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "guard: unknown key `{k}`: expected omega, position_error, moment, substeps"
                )));
            }
        }
    }
    Ok(g)
}

/// The output paths checked before the run, so that a path that cannot
/// be written fails now, not after the run: `OSError` with `field`
/// (`"csv"` or `"mcap"`) and `path`.
fn check_outputs(
    py: Python<'_>,
    csv: Option<&std::path::Path>,
    mcap: Option<&std::path::Path>,
) -> PyResult<()> {
    logs::check_paths(&[("csv", csv), ("mcap", mcap)], None, None).map_err(|e| {
        let err = PyOSError::new_err(e.to_string());
        let v = err.value(py);
        // Attributes that cannot be set leave the message, which says the
        // same; the class is still right.
        let _ = v.setattr("field", e.field.as_str());
        let _ = v.setattr("path", e.path.clone());
        err
    })
}

/// Runs `scene` to the end; writes `csv` and `mcap` when given (their
/// paths checked before the run: `OSError` with `field` and `path`).
/// `reference`, a callable `t -> (x, v, a, jerk, snap, b1d, b1d_dot,
/// b1d_ddot)` (or a dict of them), replaces the position reference of
/// every position-mode segment; an exception it raises is re-raised. `guard`
/// (a dict: `omega`, `position_error`, `moment`, `substeps`) stops a run
/// that passes a limit; such a run raises `DivergedError` (with `t`,
/// `termination` and the partial `result`) unless `raise_on_divergence`
/// is false. A failed step raises `SimulationError`; Ctrl-C stops the
/// run and raises `KeyboardInterrupt`.
#[pyfunction]
#[pyo3(signature = (scene, *, csv=None, mcap=None, guard=None, reference=None,
    raise_on_divergence=true))]
pub(crate) fn run<'py>(
    py: Python<'py>,
    scene: &Scene,
    csv: Option<PathBuf>,
    mcap: Option<PathBuf>,
    guard: Option<&Bound<'py, PyDict>>,
    reference: Option<Py<PyAny>>,
    raise_on_divergence: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = &scene.inner;
    let limits = self::guard(guard)?;
    check_outputs(py, csv.as_deref(), mcap.as_deref())?;
    let cell = ErrorCell::default();
    let position = reference.map(|f| position_fn(f, cell.clone()));
    let out = match position {
        // A Python reference runs on this thread with the interpreter's
        // lock held: a call from another thread would take and release
        // the lock (and a thread state) every evaluation, many times the
        // cost of the call itself. Ctrl-C then reaches the callable,
        // whose KeyboardInterrupt stops the run and is re-raised.
        Some(p) => SceneSimulation::with_position(scene, limits, p).and_then(|mut sim| {
            sim.advance_to(sim.duration())?;
            sim.finish()
        }),
        None => interruptible(py, |cancel| {
            // Built on the worker thread: a simulation holds flight modes,
            // which stay on the thread that made them.
            let mut sim = SceneSimulation::guarded(scene, limits)?;
            let opts = RunOptions {
                cancel: Some(cancel),
                ..Default::default()
            };
            sim.advance_to_with(sim.duration(), opts)?;
            sim.finish()
        })?,
    }
    .map_err(|e| take_error(&cell, sim_error(py, &e)))?;
    if let Some(e) = cell.lock().unwrap_or_else(|p| p.into_inner()).take() {
        return Err(e);
    }
    let written = |r: Result<u64, logs::OutputError>| r.map_err(|e| sim_error(py, &e.into()));
    if let Some(p) = &csv {
        written(logs::write_csv(p, &out))?;
    }
    if let Some(p) = &mcap {
        written(logs::write_mcap(p, &out))?;
    }
    let d = output_dict(py, &out)?;
    if let (true, Some((what, t))) = (raise_on_divergence, out.diverged()) {
        let err =
            DivergedError::new_err(format!("{}: diverged at t = {t} s ({what:?})", scene.name));
        let v = err.value(py);
        v.setattr("t", t)?;
        v.setattr("termination", termination(py, &out.termination)?)?;
        v.setattr("result", d)?;
        return Err(err);
    }
    Ok(d)
}
