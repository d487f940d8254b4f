//! numpy arrays in and out, with shapes checked and named in errors, and
//! long work off the interpreter's lock but still stoppable by Ctrl-C.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Condvar, Mutex};
use std::time::Duration;

use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{IntoPyArray, PyReadonlyArrayDyn, PyUntypedArrayMethods};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// An f64 array of `shape` from row-major `data`.
pub(crate) fn array<'py>(
    py: Python<'py>,
    shape: &[usize],
    data: Vec<f64>,
) -> PyResult<Bound<'py, PyAny>> {
    let a = ArrayD::from_shape_vec(IxDyn(shape), data)
        .map_err(|e| PyValueError::new_err(format!("internal array shape {shape:?}: {e}")))?;
    Ok(a.into_pyarray(py).into_any())
}

/// `rows` of `N` values each as an `(n, N)` array.
pub(crate) fn rows<'py, const K: usize>(
    py: Python<'py>,
    rows: impl Iterator<Item = [f64; K]>,
) -> PyResult<Bound<'py, PyAny>> {
    let data: Vec<f64> = rows.flatten().collect();
    let n = data.len() / K;
    array(py, &[n, K], data)
}

/// 3×3 matrices (rows) as an `(n, 3, 3)` array.
pub(crate) fn mats<'py>(
    py: Python<'py>,
    m: impl Iterator<Item = [[f64; 3]; 3]>,
) -> PyResult<Bound<'py, PyAny>> {
    let data: Vec<f64> = m.flat_map(|m| m.into_iter().flatten()).collect();
    let n = data.len() / 9;
    array(py, &[n, 3, 3], data)
}

/// Rows of `per` values: one row per index, or one row for all
/// (`stride` 0, a broadcast argument).
pub(crate) struct Col {
    pub(crate) data: Vec<f64>,
    pub(crate) stride: usize,
}

impl Col {
    /// One row for all.
    pub(crate) fn one(row: &[f64]) -> Self {
        Self {
            data: row.to_vec(),
            stride: 0,
        }
    }

    /// Row `i`, starting at value `per·i` (or the only row).
    #[inline]
    pub(crate) fn row(&self, i: usize) -> &[f64] {
        &self.data[self.stride * i..]
    }
}

/// A float array argument, after checking that its shape is `(n, *tail)`
/// (or `tail` alone, one row for all, when `broadcast`); the error names
/// `field` and both shapes. With `finite`, a NaN or infinity is an error
/// naming the field and the row too.
pub(crate) fn input_col(
    field: &str,
    a: &PyReadonlyArrayDyn<'_, f64>,
    n: Option<usize>,
    tail: &[usize],
    broadcast: bool,
    finite: bool,
) -> PyResult<(usize, Col)> {
    let shape = a.shape();
    let per: usize = tail.iter().product();
    let broadcast = broadcast && shape == tail;
    if !broadcast
        && (shape.len() != tail.len() + 1
            || shape[1..] != *tail
            || n.is_some_and(|n| shape[0] != n))
    {
        let want = match n {
            Some(n) => format!("({n}, {})", dims(tail)),
            None if broadcast => format!("{} or (n, {})", tuple(tail), dims(tail)),
            None => format!("(n, {})", dims(tail)),
        };
        return Err(PyValueError::new_err(format!(
            "{field}: shape {}, expected {want}",
            tuple(shape)
        )));
    }
    // A C-contiguous array is one copy; any other layout goes element
    // by element in logical order.
    let values: Vec<f64> = match a.as_slice() {
        Ok(s) => s.to_vec(),
        Err(_) => a.as_array().iter().copied().collect(),
    };
    if let Some(i) = values.iter().position(|v| finite && !v.is_finite()) {
        let at = if broadcast {
            String::new()
        } else {
            format!("[{}]", i / per.max(1))
        };
        return Err(PyValueError::new_err(format!(
            "{field}{at}: {} is not finite",
            values[i]
        )));
    }
    let rows = if broadcast { n.unwrap_or(1) } else { shape[0] };
    let stride = if broadcast { 0 } else { per };
    Ok((
        rows,
        Col {
            data: values,
            stride,
        },
    ))
}

/// A shape as Python prints it: `(3,)`, `(4, 3)`.
fn tuple(shape: &[usize]) -> String {
    match shape {
        [d] => format!("({d},)"),
        _ => format!("({})", dims(shape)),
    }
}

fn dims(tail: &[usize]) -> String {
    tail.iter()
        .map(|d| d.to_string())
        .collect::<Vec<_>>()
        .join(", ")
}

/// Runs `work` on a thread of its own with the interpreter's lock
/// released, checking for signals every 50 ms: on Ctrl-C the cancel flag
/// is set, `work` is waited for (it stops at its next check of the flag),
/// and the `KeyboardInterrupt` is raised. A short `work` returns as soon
/// as it is done (the wait is on a condition variable, not a sleep).
pub(crate) fn interruptible<T: Send>(
    py: Python<'_>,
    work: impl FnOnce(&AtomicBool) -> T + Send,
) -> PyResult<T> {
    let cancel = AtomicBool::new(false);
    let done = (Mutex::new(false), Condvar::new());
    std::thread::scope(|scope| {
        let (cancel, done) = (&cancel, &done);
        let handle = scope.spawn(move || {
            let out = work(cancel);
            *done.0.lock().unwrap_or_else(|p| p.into_inner()) = true;
            done.1.notify_all();
            out
        });
        let mut signal = Ok(());
        loop {
            let finished = py.detach(|| {
                let g = done.0.lock().unwrap_or_else(|p| p.into_inner());
                let (g, _) = done
                    .1
                    .wait_timeout_while(g, Duration::from_millis(50), |d| !*d)
                    .unwrap_or_else(|p| p.into_inner());
                *g
            });
            if finished {
                break;
            }
            if signal.is_ok()
                && let Err(e) = py.check_signals()
            {
                cancel.store(true, Ordering::Relaxed);
                signal = Err(e);
            }
        }
        let out = py.detach(|| handle.join());
        let out = out.map_err(|_| PyValueError::new_err("the native run panicked"))?;
        signal.map(|()| out)
    })
}
