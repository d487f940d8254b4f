//! Why a trajectory could not be planned, read or written.

use std::fmt;

/// Bad input to the planner or a malformed trajectory file. Each message
/// names the field (or the file's row and column) and the value.
#[derive(Debug)]
#[non_exhaustive]
pub enum MissionError {
    /// A planner input out of range: `field` is e.g. `"waypoints[2].y"`,
    /// `"times[3]"` or `"mean_speed"`.
    Input {
        /// The field at fault.
        field: String,
        /// Its value.
        value: f64,
        /// What it must be.
        expected: String,
    },
    /// The KKT system of an axis could not be solved (singular or not
    /// finite): the waypoints or times are degenerate.
    Solve {
        /// `"x"`, `"y"`, `"z"` or `"yaw"`.
        axis: &'static str,
    },
    /// A trajectory file's cell that is not what its column needs.
    Row {
        /// 1-based line number in the file.
        line: usize,
        /// The column's name (`"duration"`, `"x^3"`, ...).
        column: String,
        /// The cell's text.
        text: String,
        /// What it must be.
        expected: &'static str,
    },
    /// A trajectory file could not be read or written.
    Io {
        /// The file.
        path: std::path::PathBuf,
        /// The cause.
        source: std::io::Error,
    },
}

impl fmt::Display for MissionError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MissionError::Input {
                field,
                value,
                expected,
            } => write!(f, "{field} = {value}: must be {expected}"),
            MissionError::Solve { axis } => write!(
                f,
                "the minimum-snap system of axis {axis} is singular: the waypoints or \
                 times are degenerate"
            ),
            MissionError::Row {
                line,
                column,
                text,
                expected,
            } => write!(
                f,
                "line {line}, column {column}: `{text}`: must be {expected}"
            ),
            MissionError::Io { path, source } => write!(f, "{}: {source}", path.display()),
        }
    }
}

impl std::error::Error for MissionError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            MissionError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

pub(crate) fn input(
    field: impl Into<String>,
    value: f64,
    expected: impl Into<String>,
) -> MissionError {
    MissionError::Input {
        field: field.into(),
        value,
        expected: expected.into(),
    }
}
