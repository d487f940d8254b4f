//! Why a sensor could not be built or sampled.

/// A sensor setting that is out of range, or a sample asked for out of
/// order. The message names the field and the value.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SensorError {
    /// A setting is negative, non-finite or otherwise out of its range.
    Setting {
        /// The field, e.g. `"accel.noise_density"`.
        field: &'static str,
        /// Its value (for a matrix, the element at fault).
        value: f64,
        /// What it must be.
        expected: &'static str,
    },
    /// A sample older than the last one: the bias random walk only goes
    /// forward.
    OutOfOrder {
        /// The sample asked for.
        k: u64,
        /// The next sample the sensor can give.
        next: u64,
    },
}

impl core::fmt::Display for SensorError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            SensorError::Setting {
                field,
                value,
                expected,
            } => write!(f, "{field} = {value}: must be {expected}"),
            SensorError::OutOfOrder { k, next } => write!(
                f,
                "sample {k} asked for after sample {}: samples go forward only",
                next.saturating_sub(1)
            ),
        }
    }
}

impl core::error::Error for SensorError {}

pub(crate) fn setting(field: &'static str, value: f64, expected: &'static str) -> SensorError {
    SensorError::Setting {
        field,
        value,
        expected,
    }
}
