//! Why a run could not be built or could not go on.

use std::sync::Arc;

use super::OutputError;

/// Why a run could not be built or could not go on. Each variant keeps its
/// typed cause ([`std::error::Error::source`]); the messages name the time
/// and the field.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SimError {
    /// The scene is invalid, or names a vehicle kind nothing registered.
    Scene(SceneError),
    /// The scene names an integrator that does not exist.
    Integrator(integrators::UnknownIntegrator),
    /// The vehicle rejected its parameters, or its allocation failed.
    Vehicle(dynamics::DynamicsError),
    /// A vehicle registered by the program failed to build.
    CustomVehicle {
        /// Its kind, as the scene names it.
        kind: String,
        /// What its builder returned, kept as it was (also
        /// [`std::error::Error::source`]).
        source: BuildError,
    },
    /// A setting of the [`SimulationBuilder`](super::SimulationBuilder) (or an argument of
    /// [`Simulation::advance_to`](super::Simulation::advance_to)) is invalid.
    Setting {
        /// The setting, e.g. `"dt"`.
        field: &'static str,
        /// What is wrong with its value.
        message: String,
    },
    /// The plan and the vehicle need more extra states than the largest
    /// size a simulation is compiled for ([`CAPACITIES`](super::CAPACITIES)).
    Layout {
        /// Integral slots the plan's modes use.
        integrals: usize,
        /// Internal states the vehicle declares.
        vehicle_states: usize,
        /// The largest size.
        capacity: usize,
    },
    /// A step failed. When a mode rejected its input inside the step (a
    /// non-finite reference, say) on a finite state, `control` says which
    /// input: that is the cause, and the integrator's error the symptom.
    /// A state that turned non-finite inside the step (a load that did, an
    /// overflow) is the integrator's error alone.
    Step {
        /// Start of the step, s.
        t: f64,
        /// Its size, s.
        h: f64,
        /// The integrator's error.
        source: integrators::StepError,
        /// The mode's complaint, if one came first.
        control: Option<controllers::ControlError>,
    },
    /// A mode rejected its input outside a step (a sample, a held command).
    Control {
        /// When, s.
        t: f64,
        /// The mode's error.
        source: controllers::ControlError,
    },
    /// A sink could not write (disk full, …).
    Output(OutputError),
    /// A derivative of a gradient run (the `sensitivity` module of `geopid-studies`) turned
    /// non-finite while the value stayed finite.
    NonFiniteDerivative {
        /// The seeded parameter it is taken with respect to, e.g.
        /// `"gains.k_x"`.
        parameter: String,
        /// When it was found, s.
        t: f64,
        /// The state component, e.g. `"omega[1]"`.
        component: String,
    },
}

/// The error a program's own vehicle builder returned, of whatever type:
/// shared, so that a [`SimError`] stays `Clone`; two are equal when they
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

/// A builder setting's error.
pub(super) fn bad(field: &'static str, message: String) -> SimError {
    SimError::Setting { field, message }
}

impl SimError {
    /// A step error with the mode's complaint, if any.
    pub(crate) fn step(
        t: f64,
        h: f64,
        source: integrators::StepError,
        control: Option<controllers::ControlError>,
    ) -> Self {
        SimError::Step {
            t,
            h,
            source,
            control,
        }
    }

    /// Whether the state itself went non-finite in a step (not the
    /// reference, not a file): what a smaller step, a tighter tolerance
    /// or a [`DivergenceGuard`](super::DivergenceGuard) addresses.
    pub fn is_divergence(&self) -> bool {
        matches!(
            self,
            SimError::Control {
                source: controllers::ControlError::NonFinite { .. },
                ..
            } | SimError::Step {
                control: Some(controllers::ControlError::NonFinite { .. }),
                ..
            } | SimError::Step {
                control: None,
                source: integrators::StepError::NonFinite { .. }
                    | integrators::StepError::TooManySubsteps { .. }
                    | integrators::StepError::StepTooSmall { .. },
                ..
            }
        )
    }
}

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use controllers::ControlError as C;
        match self {
            SimError::Scene(e) => write!(f, "scene: {e}"),
            SimError::Integrator(e) => write!(f, "scene: {e}"),
            SimError::Vehicle(e) => write!(f, "vehicle: {e}"),
            SimError::CustomVehicle { kind, source } => {
                write!(f, "scene: vehicle `{kind}`: {source}")
            }
            SimError::Setting { field, message } => write!(f, "simulation `{field}`: {message}"),
            SimError::Layout {
                integrals,
                vehicle_states,
                capacity,
            } => write!(
                f,
                "the plan's modes use {integrals} integral states and the vehicle declares \
                 {vehicle_states} internal states, {} in all, but a simulation holds at most \
                 {capacity} (the largest state it is compiled for)",
                integrals + vehicle_states,
            ),
            SimError::Step {
                t,
                h,
                control: Some(c @ C::NonFiniteReference { .. }),
                ..
            } => write!(
                f,
                "integrator: in the step from t = {t} (h = {h}): {c}: the reference returned NaN or ∞ there"
            ),
            SimError::Step {
                t,
                h,
                control: Some(c),
                ..
            } => write!(
                f,
                "integrator: in the step from t = {t} (h = {h}): {c}; the state diverged"
            ),
            SimError::Step { source, .. } => write!(f, "integrator: {source}"),
            SimError::Control { t, source } => write!(f, "controller: at t = {t}: {source}"),
            SimError::Output(e) => write!(f, "output: {e}"),
            SimError::NonFiniteDerivative {
                parameter,
                t,
                component,
            } => write!(
                f,
                "gradient: the derivative of {component} with respect to `{parameter}` is not \
                 finite at t = {t} (the value is)"
            ),
        }
    }
}

impl std::error::Error for SimError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SimError::Scene(e) => Some(e),
            SimError::Integrator(e) => Some(e),
            SimError::Vehicle(e) => Some(e),
            SimError::Step {
                control: Some(c), ..
            } => Some(c),
            SimError::Step { source, .. } => Some(source),
            SimError::Control { source, .. } => Some(source),
            SimError::Output(e) => Some(e),
            SimError::CustomVehicle { source, .. } => Some(source.get()),
            SimError::Setting { .. }
            | SimError::Layout { .. }
            | SimError::NonFiniteDerivative { .. } => None,
        }
    }
}

impl From<SceneError> for SimError {
    fn from(e: SceneError) -> Self {
        SimError::Scene(e)
    }
}

impl From<dynamics::DynamicsError> for SimError {
    fn from(e: dynamics::DynamicsError) -> Self {
        SimError::Vehicle(e)
    }
}

impl From<integrators::UnknownIntegrator> for SimError {
    fn from(e: integrators::UnknownIntegrator) -> Self {
        SimError::Integrator(e)
    }
}

impl From<OutputError> for SimError {
    fn from(e: OutputError) -> Self {
        SimError::Output(e)
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
