//! A Python callable as the position reference of a simulation.

use std::sync::{Arc, Mutex};

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};
use scenes::PositionFn;

/// The first error a callable raised, kept for the caller to re-raise
/// once the run has stopped (the run itself sees a NaN reference, which
/// fails the step at once).
pub(crate) type ErrorCell = Arc<Mutex<Option<PyErr>>>;

const NAMES: [&str; 8] = ["x", "v", "a", "jerk", "snap", "b1d", "b1d_dot", "b1d_ddot"];

/// What the callable returned, as the eight vectors: a tuple or list of
/// up to eight 3-vectors in `NAMES` order, or a dict with those keys;
/// left out: zero, and `b1d` = e1.
fn reference_of(out: &Bound<'_, PyAny>) -> PyResult<[[f64; 3]; 8]> {
    let mut r = [[0.0; 3]; 8];
    r[5] = [1.0, 0.0, 0.0];
    let bad = |what: String| PyValueError::new_err(format!("reference: {what}"));
    if let Ok(d) = out.cast::<PyDict>() {
        for (k, v) in d.iter() {
            let k: String = k.extract()?;
            let i = NAMES
                .iter()
                .position(|n| *n == k)
                .ok_or_else(|| bad(format!("unknown key `{k}`: expected {}", NAMES.join(", "))))?;
            r[i] = v
                .extract()
                .map_err(|_| bad(format!("`{k}` is not 3 numbers")))?;
        }
        return Ok(r);
    }
    // Read in place (this runs several times a step): a tuple by index, any
    // other sequence by iteration, no intermediate list.
    let mut count = 0;
    let mut put = |i: usize, v: &Bound<'_, PyAny>| -> PyResult<()> {
        let slot = r
            .get_mut(i)
            .ok_or_else(|| bad(format!("more than {} vectors returned", NAMES.len())))?;
        *slot = v
            .extract()
            .map_err(|_| bad(format!("`{}` is not 3 numbers", NAMES[i])))?;
        count = i + 1;
        Ok(())
    };
    match out.cast::<PyTuple>() {
        Ok(t) => {
            for (i, v) in t.iter().enumerate() {
                put(i, &v)?;
            }
        }
        Err(_) => {
            let items = out.try_iter().map_err(|_| {
                bad("expected a tuple of 3-vectors (x, v, a, jerk, snap, b1d, b1d_dot, b1d_ddot) or a dict".into())
            })?;
            for (i, v) in items.enumerate() {
                put(i, &v?)?;
            }
        }
    }
    if count == 0 {
        return Err(bad("0 vectors returned, expected 1 to 8".into()));
    }
    Ok(r)
}

/// `f` as the library's f64 position function; its errors go to `cell`.
pub(crate) fn position_fn(f: Py<PyAny>, cell: ErrorCell) -> PositionFn {
    Arc::new(move |t| {
        Python::attach(
            |py| match f.call1(py, (t,)).and_then(|o| reference_of(o.bind(py))) {
                Ok(r) => r,
                Err(e) => {
                    let mut first = cell.lock().unwrap_or_else(|p| p.into_inner());
                    first.get_or_insert(e);
                    [[f64::NAN; 3]; 8]
                }
            },
        )
    })
}

/// The callable's own error if it raised one (the run's error is only its
/// consequence), else `otherwise`.
pub(crate) fn take_error(cell: &ErrorCell, otherwise: PyErr) -> PyErr {
    cell.lock()
        .unwrap_or_else(|p| p.into_inner())
        .take()
        .unwrap_or(otherwise)
}
