//! Why a scene could not be loaded, built or run: the scene layer's own
//! failures beside the engine's [`SimError`].

use std::sync::Arc;

use scenarios::SimError;

/// Why a scene could not be loaded, built or run. The scene layer's own
/// failures (a bad key, an unknown integrator, a program's vehicle that
/// refused to build, a derivative of a gradient run) beside the engine's
/// [`SimError`], which [`Error::Run`] keeps as it was. Each variant keeps
/// its typed cause ([`std::error::Error::source`]).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Error {
    /// The scene is invalid, or names a vehicle kind nothing registered.
    Scene(SceneError),
    /// The scene names an integrator that does not exist.
    Integrator(integrators::UnknownIntegrator),
    /// A vehicle kind registered by the program failed to build.
    CustomVehicle {
        /// Its kind, as the scene names it.
        kind: String,
        /// What its builder returned, kept as it was (also
        /// [`std::error::Error::source`]).
        source: BuildError,
    },
    /// A derivative of a gradient run turned non-finite while the value
    /// stayed finite.
    NonFiniteDerivative {
        /// The seeded scene parameter it is taken with respect to, e.g.
        /// `"gains.k_x"`.
        parameter: String,
        /// When it was found, s.
        t: f64,
        /// The state component, e.g. `"omega[1]"`.
        component: String,
    },
    /// The engine could not build or continue the run.
    Run(SimError),
}

impl Error {
    /// The engine's error, when the run itself failed.
    pub fn sim(&self) -> Option<&SimError> {
        match self {
            Error::Run(e) => Some(e),
            _ => None,
        }
    }

    /// Whether the state itself went non-finite in a step
    /// ([`SimError::is_divergence`]).
    pub fn is_divergence(&self) -> bool {
        self.sim().is_some_and(SimError::is_divergence)
    }

    /// A validation error about `key` (a [`SceneError`] without a place
    /// in a file).
    pub fn at_key(key: &str, message: String) -> Self {
        Error::Scene(SceneError::at_key(key, message))
    }

    /// A bad setting (the engine's [`SimError::Setting`]).
    pub fn setting(field: &'static str, message: String) -> Self {
        Error::Run(SimError::Setting { field, message })
    }
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Error::Scene(e) => write!(f, "scene: {e}"),
            Error::Integrator(e) => write!(f, "scene: {e}"),
            Error::CustomVehicle { kind, source } => {
                write!(f, "scene: vehicle `{kind}`: {source}")
            }
            Error::NonFiniteDerivative {
                parameter,
                t,
                component,
            } => write!(
                f,
                "gradient: the derivative of {component} with respect to `{parameter}` is not \
                 finite at t = {t} (the value is)"
            ),
            Error::Run(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Scene(e) => Some(e),
            Error::Integrator(e) => Some(e),
            Error::CustomVehicle { source, .. } => Some(source.get()),
            Error::NonFiniteDerivative { .. } => None,
            // The engine's error stands in its place: its message is
            // this one, and its own source is the cause.
            Error::Run(e) => e.source(),
        }
    }
}

impl From<SimError> for Error {
    fn from(e: SimError) -> Self {
        Error::Run(e)
    }
}

impl From<SceneError> for Error {
    fn from(e: SceneError) -> Self {
        Error::Scene(e)
    }
}

impl From<integrators::UnknownIntegrator> for Error {
    fn from(e: integrators::UnknownIntegrator) -> Self {
        Error::Integrator(e)
    }
}

impl From<dynamics::DynamicsError> for Error {
    fn from(e: dynamics::DynamicsError) -> Self {
        Error::Run(SimError::Vehicle(e))
    }
}

impl From<scenarios::OutputError> for Error {
    fn from(e: scenarios::OutputError) -> Self {
        Error::Run(SimError::Output(e))
    }
}

/// The error a program's own vehicle builder returned, of whatever type:
/// shared, so that an [`Error`] stays `Clone`; two are equal when they
/// are the same error or say the same.
#[derive(Clone, Debug)]
pub struct BuildError(Arc<dyn std::error::Error + Send + Sync>);

impl BuildError {
    /// Keeps `e`.
    pub fn new(e: Box<dyn std::error::Error + Send + Sync>) -> Self {
        Self(Arc::from(e))
    }

    /// The error as the builder returned it, to downcast to its type.
    pub fn get(&self) -> &(dyn std::error::Error + Send + Sync + 'static) {
        &*self.0
    }
}

impl PartialEq for BuildError {
    fn eq(&self, other: &Self) -> bool {
        Arc::ptr_eq(&self.0, &other.0) || self.0.to_string() == other.0.to_string()
    }
}

impl std::fmt::Display for BuildError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

/// A scene that failed to load or validate.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// What is wrong, naming the key and the value.
    pub message: String,
    /// `file:line:column` when known.
    pub location: Option<String>,
    /// The key a validation error is about, dotted by table
    /// (`integrator.kind`; in a segment, the key inside `[[plan]]`);
    /// `None` for a TOML syntax or type error, which the location alone
    /// places.
    pub key: Option<String>,
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.location {
            Some(l) => write!(f, "{l}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for SceneError {}

impl SceneError {
    /// A validation error about `key`, without a place in a file.
    pub fn at_key(key: &str, message: String) -> Self {
        Self {
            message,
            location: None,
            key: Some(key.to_string()),
        }
    }
}
