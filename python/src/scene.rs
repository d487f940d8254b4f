//! `Scene`: a scene loaded from a built-in name, a file, TOML text or
//! JSON text (what the Python side makes of a dict), with overrides.

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyInt, PyList, PyTuple};
use scenes::Overrides;
use scenes::SceneError as RsSceneError;
use scenes::scene::{BackendKind, Scalar};

use crate::scene_error;

/// A validated scene (the scene schema of the Rust crate `scenarios`).
#[pyclass(module = "geopid._geopid", frozen)]
#[derive(Clone)]
pub struct Scene {
    pub(crate) inner: scenes::Scene,
}

fn parse_enum<T>(field: &str, v: &str, options: &[(&str, T)]) -> Result<T, RsSceneError>
where
    T: Copy,
{
    options
        .iter()
        .find(|(name, _)| *name == v)
        .map(|(_, t)| *t)
        .ok_or_else(|| {
            let names: Vec<&str> = options.iter().map(|(n, _)| *n).collect();
            RsSceneError::at_key(
                field,
                format!("{field} = \"{v}\": expected one of {}", names.join(", ")),
            )
        })
}

/// A Python value as a TOML value; `at` is its dotted key for errors.
fn to_toml(v: &Bound<'_, PyAny>, at: &str) -> PyResult<toml::Value> {
    use toml::Value;
    if let Ok(d) = v.cast::<PyDict>() {
        let mut t = toml::map::Map::new();
        for (k, x) in d.iter() {
            let k: String = k
                .extract()
                .map_err(|_| PyTypeError::new_err(format!("{at}: keys must be strings")))?;
            let key = if at.is_empty() {
                k.clone()
            } else {
                format!("{at}.{k}")
            };
            t.insert(k, to_toml(&x, &key)?);
        }
        return Ok(Value::Table(t));
    }
    if v.is_instance_of::<PyBool>() {
        return Ok(Value::Boolean(v.extract()?));
    }
    if v.is_instance_of::<PyInt>() {
        return Ok(Value::Integer(v.extract()?));
    }
    if let Ok(x) = v.extract::<f64>() {
        return Ok(Value::Float(x));
    }
    if let Ok(s) = v.extract::<String>() {
        return Ok(Value::String(s));
    }
    if v.is_instance_of::<PyList>() || v.is_instance_of::<PyTuple>() {
        let items: PyResult<Vec<Value>> = v
            .try_iter()?
            .enumerate()
            .map(|(i, x)| to_toml(&x?, &format!("{at}[{i}]")))
            .collect();
        return Ok(Value::Array(items?));
    }
    if v.hasattr("tolist")? {
        // numpy arrays and scalars.
        return to_toml(&v.call_method0("tolist")?, at);
    }
    Err(PyTypeError::new_err(format!(
        "{at}: a {} has no place in a scene (numbers, strings, bools, lists and dicts do)",
        v.get_type().name()?
    )))
}

/// The overrides named by keyword arguments.
fn overrides(py: Python<'_>, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Overrides> {
    let mut o = Overrides::default();
    let Some(kwargs) = kwargs else {
        return Ok(o);
    };
    let err = |e: RsSceneError| scene_error(py, &e);
    for (k, v) in kwargs.iter() {
        let key: String = k.extract()?;
        if v.is_none() {
            continue;
        }
        match key.as_str() {
            "integrator" => o.integrator = Some(v.extract()?),
            "dt" => o.dt = Some(v.extract()?),
            "tol" => o.tol = Some(v.extract()?),
            "duration" => o.duration = Some(v.extract()?),
            "sample" => o.sample = Some(v.extract()?),
            "control_rate" => o.control_rate = Some(v.extract()?),
            "loop_rates" => o.loop_rates = Some(v.extract()?),
            "no_integral" => o.no_integral = v.extract()?,
            "sensors" => o.sensors = Some(v.extract()?),
            "seed" => o.seed = Some(v.extract()?),
            "estimator" => {
                let s: String = v.extract()?;
                let options = [
                    ("none", scenes::scene::EstimatorKind::None),
                    ("mocap", scenes::scene::EstimatorKind::Mocap),
                    ("iekf", scenes::scene::EstimatorKind::Iekf),
                    ("complementary", scenes::scene::EstimatorKind::Complementary),
                    ("fdcl-ekf", scenes::scene::EstimatorKind::FdclEkf),
                ];
                o.estimator = Some(parse_enum("estimator.kind", &s, &options).map_err(err)?);
            }
            "scalar" => {
                let s: String = v.extract()?;
                let options = [("f32", Scalar::F32), ("f64", Scalar::F64)];
                o.scalar = Some(parse_enum("scalar", &s, &options).map_err(err)?);
            }
            "backend" => {
                let s: String = v.extract()?;
                let options = [
                    ("nalgebra", BackendKind::Nalgebra),
                    ("glam", BackendKind::Glam),
                ];
                o.backend = Some(parse_enum("backend", &s, &options).map_err(err)?);
            }
            _ => {
                return Err(PyTypeError::new_err(format!(
                    "unknown setting `{key}`: expected integrator, dt, tol, duration, sample, \
                     control_rate, loop_rates, scalar, backend, no_integral, sensors, estimator or seed"
                )));
            }
        }
    }
    Ok(o)
}

#[pymethods]
impl Scene {
    /// A built-in scene by name, or a scene file by path.
    #[staticmethod]
    fn load(py: Python<'_>, name_or_path: &str) -> PyResult<Self> {
        scenes::load(name_or_path)
            .map(|inner| Self { inner })
            .map_err(|e| scene_error(py, &e))
    }

    /// Parses TOML text; `origin` names it in error locations.
    #[staticmethod]
    #[pyo3(signature = (text, origin = "<string>"))]
    fn from_toml(py: Python<'_>, text: &str, origin: &str) -> PyResult<Self> {
        scenes::Scene::from_toml(text, origin)
            .map(|inner| Self { inner })
            .map_err(|e| scene_error(py, &e))
    }

    /// A scene from a dict in the scene schema (nested dicts for tables,
    /// lists for arrays); it is turned into TOML first so that it is
    /// checked exactly as a file. A dict is written against this version,
    /// so one without `format` is taken as the current format (a file
    /// without it gets a note; a dict does not); a `format` it has is
    /// checked as in a file.
    #[staticmethod]
    #[pyo3(signature = (d, origin = "<dict>"))]
    fn from_dict(py: Python<'_>, d: &Bound<'_, PyDict>, origin: &str) -> PyResult<Self> {
        let mut table = to_toml(d.as_any(), "")?;
        if let toml::Value::Table(t) = &mut table {
            t.entry("format")
                .or_insert(toml::Value::Integer(scenes::scene::SCENE_FORMAT.into()));
        }
        let text = toml::to_string(&table).map_err(|e| {
            scene_error(py, &RsSceneError::at_key("scene", format!("{origin}: {e}")))
        })?;
        Self::from_toml(py, &text, origin)
    }

    /// The scene with settings replaced: keywords `integrator`, `dt`,
    /// `tol`, `duration`, `sample`, `control_rate`, `loop_rates`, `scalar` ("f32" or
    /// "f64"), `backend` ("nalgebra" or "glam"), `no_integral`, `sensors`
    /// (a suite's name), `estimator` ("none", "mocap", "iekf",
    /// "complementary" or "fdcl-ekf"), `seed`; `None`
    /// keeps the scene's value. Validated: a bad value raises `SceneError`
    /// naming the key, an unknown keyword `TypeError`.
    #[pyo3(signature = (**kwargs))]
    fn with_overrides(&self, py: Python<'_>, kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<Self> {
        let o = overrides(py, kwargs)?;
        o.apply(self.inner.clone())
            .map(|inner| Self { inner })
            .map_err(|e| scene_error(py, &e))
    }

    /// The scene as TOML (every value a run uses).
    fn to_toml(&self) -> String {
        self.inner.to_toml()
    }

    /// Its name.
    #[getter]
    fn name(&self) -> &str {
        &self.inner.name
    }

    /// Simulated time, s.
    #[getter]
    fn duration(&self) -> f64 {
        self.inner.duration
    }

    /// The built-in scene names.
    #[staticmethod]
    fn builtin_names() -> Vec<String> {
        scenes::builtin::all().into_iter().map(|s| s.name).collect()
    }

    fn __repr__(&self) -> String {
        format!(
            "Scene(name={:?}, duration={}, integrator={:?}, dt={})",
            self.inner.name,
            self.inner.duration,
            self.inner.integrator.kind,
            self.inner.integrator.dt
        )
    }
}
