//! Why a run could not be built or could not go on.

use super::OutputError;

/// Why a run could not be built or could not go on. Each variant keeps its
/// typed cause ([`std::error::Error::source`]); the messages name the time
/// and the field.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SimError {
    /// The vehicle rejected its parameters, or its allocation failed.
    Vehicle(dynamics::DynamicsError),
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
    /// A sensor's setting is out of range (before the first step), or a
    /// sensor could not sample (at `t`).
    Sensor {
        /// When, s (0 for a setting).
        t: f64,
        /// The sensor's error, naming the field and the value.
        source: sensors::SensorError,
    },
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
            SimError::Vehicle(e) => write!(f, "vehicle: {e}"),
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
            SimError::Sensor { t, source } if *t == 0.0 => write!(f, "sensors: {source}"),
            SimError::Sensor { t, source } => write!(f, "sensors: at t = {t}: {source}"),
        }
    }
}

impl std::error::Error for SimError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SimError::Vehicle(e) => Some(e),
            SimError::Step {
                control: Some(c), ..
            } => Some(c),
            SimError::Step { source, .. } => Some(source),
            SimError::Control { source, .. } => Some(source),
            SimError::Output(e) => Some(e),
            SimError::Sensor { source, .. } => Some(source),
            SimError::Setting { .. } | SimError::Layout { .. } => None,
        }
    }
}

impl From<dynamics::DynamicsError> for SimError {
    fn from(e: dynamics::DynamicsError) -> Self {
        SimError::Vehicle(e)
    }
}

impl From<OutputError> for SimError {
    fn from(e: OutputError) -> Self {
        SimError::Output(e)
    }
}
