//! The native half of the `geopid` Python package: scenes, runs, stepping,
//! the controllers over arrays of states and the Monte Carlo study, with
//! results as numpy arrays. The Python half (`python/geopid`) gives the
//! keyword arguments, result classes and docs; this crate only converts.

use pyo3::exceptions::{PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use scenarios::SimError;
use scenes::{Error as RsError, SceneError as RsSceneError};

mod arrays;
mod control;
mod missions;
mod reference;
mod result;
mod scene;
mod sensitivity;
mod simulation;
mod study;

pyo3::create_exception!(
    _geopid,
    SceneError,
    PyValueError,
    "A scene that does not parse or validate; `key` and `location` (file:line:col) say where."
);
pyo3::create_exception!(
    _geopid,
    SimulationError,
    PyRuntimeError,
    "A run that failed: a step, a control law, or a setting of the simulation; `t` is when."
);
pyo3::create_exception!(
    _geopid,
    DivergedError,
    SimulationError,
    "A run stopped by its divergence guard (|Ω|, ‖e_x‖, ‖M‖ or the substep cap)."
);

/// Sets attributes on a new exception instance.
fn with_attrs(py: Python<'_>, err: PyErr, attrs: &[(&str, Py<PyAny>)]) -> PyErr {
    let value = err.value(py);
    for (name, v) in attrs {
        // An attribute that cannot be set leaves the message, which says
        // the same thing; the error raised is still the right class.
        let _ = value.setattr(*name, v.bind(py));
    }
    err
}

/// A scene error as `SceneError` with `key` and `location`.
pub(crate) fn scene_error(py: Python<'_>, e: &RsSceneError) -> PyErr {
    let attrs = [
        ("key", e.key.clone().into_pyobject(py).map(|o| o.unbind())),
        (
            "location",
            e.location.clone().into_pyobject(py).map(|o| o.unbind()),
        ),
    ];
    let attrs: Vec<(&str, Py<PyAny>)> = attrs
        .into_iter()
        .filter_map(|(k, v)| v.ok().map(|v| (k, v)))
        .collect();
    with_attrs(py, SceneError::new_err(e.to_string()), &attrs)
}

/// A simulation error as the Python exception of its kind: scene errors
/// as `SceneError`, bad settings as `ValueError` (with `field`), output
/// errors as `OSError`, and step and control failures and non-finite
/// derivatives as `SimulationError` with `t`.
pub(crate) fn sim_error(py: Python<'_>, e: &RsError) -> PyErr {
    let text = e.to_string();
    match e {
        RsError::Scene(s) => scene_error(py, s),
        RsError::Run(SimError::Setting { field, .. }) => {
            let f = field.into_pyobject(py).map(|o| o.into_any().unbind());
            let attrs: Vec<_> = f.ok().map(|f| ("field", f)).into_iter().collect();
            with_attrs(py, PyValueError::new_err(text), &attrs)
        }
        RsError::Run(SimError::Output(_)) => PyOSError::new_err(text),
        RsError::Run(SimError::Step { t, .. } | SimError::Control { t, .. })
        | RsError::NonFiniteDerivative { t, .. } => {
            let t = t.into_pyobject(py).map(|o| o.into_any().unbind());
            let attrs: Vec<_> = t.ok().map(|t| ("t", t)).into_iter().collect();
            with_attrs(py, SimulationError::new_err(text), &attrs)
        }
        _ => SceneError::new_err(text),
    }
}

// The wheel's second build of this extension, for x86-64-v3 CPUs, must
// be compiled for them: its name promises the instructions.
#[cfg(all(feature = "x86-64-v3", not(target_feature = "avx2")))]
compile_error!("the `x86-64-v3` module needs RUSTFLAGS=\"-C target-cpu=x86-64-v3\"");

/// The extension module, as built for any x86-64 (or for the machine that
/// builds it, from a checkout).
#[cfg(not(feature = "x86-64-v3"))]
#[pymodule]
fn _geopid(m: &Bound<'_, PyModule>) -> PyResult<()> {
    register(m)
}

/// The same module built with AVX2 and FMA: `geopid` imports it instead of
/// `_geopid` on a CPU that has them (the SIMD lanes choose their
/// instructions when compiled, so the choice is between two builds).
#[cfg(feature = "x86-64-v3")]
#[pymodule]
fn _geopid_x86_64_v3(m: &Bound<'_, PyModule>) -> PyResult<()> {
    register(m)
}

/// Which instructions this build uses (`"x86-64-v3"` or `"baseline"`).
#[pyfunction]
fn instruction_set() -> &'static str {
    lie::cpu::compiled().name()
}

/// Whether the running CPU has every x86-64-v3 feature (`cpuid`).
#[pyfunction]
fn cpu_has_x86_64_v3() -> bool {
    lie::cpu::cpu_has_x86_64_v3()
}

fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    // A build from a checkout uses the building machine's instructions:
    // copied to an older CPU, it refuses to import with the features named
    // instead of faulting in the middle of a call.
    lie::cpu::check().map_err(|e| pyo3::exceptions::PyImportError::new_err(e.to_string()))?;
    let py = m.py();
    m.add_function(wrap_pyfunction!(instruction_set, m)?)?;
    m.add_function(wrap_pyfunction!(cpu_has_x86_64_v3, m)?)?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("SimulationError", py.get_type::<SimulationError>())?;
    m.add("DivergedError", py.get_type::<DivergedError>())?;
    m.add_class::<scene::Scene>()?;
    m.add_class::<simulation::Simulation>()?;
    m.add_function(wrap_pyfunction!(result::run, m)?)?;
    m.add_function(wrap_pyfunction!(control::position_control, m)?)?;
    m.add_function(wrap_pyfunction!(control::attitude_control, m)?)?;
    m.add_function(wrap_pyfunction!(study::montecarlo, m)?)?;
    m.add_function(wrap_pyfunction!(study::montecarlo_header, m)?)?;
    m.add_function(wrap_pyfunction!(sensitivity::gradient, m)?)?;
    m.add_function(wrap_pyfunction!(sensitivity::tune, m)?)?;
    m.add_function(wrap_pyfunction!(missions::minsnap, m)?)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    Ok(())
}
