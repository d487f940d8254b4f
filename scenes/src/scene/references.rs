//! The references a scene's segments track, as data: the analytic
//! curves and the planned trajectories (minimum-snap through waypoints, a
//! Crazyflie trajectory file).

use std::path::Path;

use missions::{MinSnap, MissionError, Trajectory};
use serde::{Deserialize, Serialize};

/// Attitude references.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum AttitudeRef {
    /// The paper's flip: R_d(t) = exp(π t e3^) exp(4π t e2^). A struct
    /// variant with no fields, not a unit variant, so that an unknown key
    /// beside `kind` is rejected (serde lets a unit variant of a tagged
    /// enum ignore extra keys).
    PaperFlip {},
    /// The paper's experiment: 3-2-1 Euler angles φ = a sin(ωt),
    /// θ = a cos(ωt), ψ = 0, R_d = R_y(θ) R_x(φ).
    EulerExperiment {
        /// Amplitude a, rad (paper: π/9).
        amplitude: f64,
        /// ω, rad/s (paper: π).
        frequency: f64,
    },
    /// A fixed attitude, as a rotation vector.
    Hold {
        /// Rotation vector, rad.
        rotation: [f64; 3],
    },
}

/// Position references.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
// An explicit tag: without it the variant is read out of a niche of the
// waypoints' `Vec`, which costs the curves' evaluation in every step.
#[repr(u8)]
pub enum PositionRef {
    /// Hold x_d with heading b1d.
    Hold {
        /// x_d, m.
        x: [f64; 3],
        /// b1d (normalised internally).
        b1d: [f64; 3],
    },
    /// Lissajous figure eight x_d = c + (a sin ωt, b sin 2ωt, 0), b1d = e1.
    FigureEight {
        /// Centre, m.
        center: [f64; 3],
        /// Half-width along e1, m.
        a: f64,
        /// Half-height along e2, m.
        b: f64,
        /// ω, rad/s.
        omega: f64,
    },
    /// A sinusoid on each axis, x_d,i = c_i + A_i sin(ω_i t + φ_i), b1d =
    /// e1: ellipses, circles in any plane and with any start point, and
    /// Lissajous curves (DiffTune's circle `(2(1 − cos t), 2 sin t,
    /// 0.1 sin t)` is A = (2, 2, 0.1), ω = (1, 1, 1), φ = (−π/2, 0, 0),
    /// c = (2, 0, 0)).
    Sinusoids {
        /// c, m.
        center: [f64; 3],
        /// A per axis, m.
        amplitude: [f64; 3],
        /// ω per axis, rad/s.
        omega: [f64; 3],
        /// φ per axis, rad.
        phase: [f64; 3],
    },
    /// Circle x_d = c + r (cos ωt, sin ωt, 0), b1d = e1; ω < 0 turns the
    /// other way (RotorPy's z-up circle seen with e3 down).
    Circle {
        /// Centre, m.
        center: [f64; 3],
        /// Radius, m.
        radius: f64,
        /// ω, rad/s.
        omega: f64,
    },
    /// A minimum-snap trajectory through `waypoints` (degree-7 pieces,
    /// position at each waypoint, v, a, jerk and snap continuous between
    /// pieces, at rest at both ends), flown from time `start`: it holds
    /// the first waypoint before and the last after. At most one of
    /// `times`, `mean_speed` and `time_budget` sets the timing; with none,
    /// each segment takes its length at 1 m/s (RotorPy's rule).
    #[serde(rename = "minsnap")]
    MinSnap {
        /// The waypoints, m (e3 down), at least two.
        waypoints: Vec<[f64; 3]>,
        /// The yaw at each waypoint, rad (about e3; 0 faces e1); 0
        /// throughout when absent.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        yaw: Option<Vec<f64>>,
        /// The time at each waypoint, s after `start`: 0 first, increasing.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        times: Option<Vec<f64>>,
        /// Each segment's length over this speed is its duration, m/s.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        mean_speed: Option<f64>,
        /// A total time, s, shared out between the segments to minimise
        /// the snap cost.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        time_budget: Option<f64>,
        /// When the trajectory starts, s.
        #[serde(default)]
        start: f64,
    },
    /// A Crazyflie piecewise-polynomial trajectory file (`pptraj` CSV,
    /// z up, as the Crazyflie's tools write it), flown from time `start`.
    TrajectoryFile {
        /// The file; a relative path is relative to the scene file (to
        /// the working directory for a scene given as text).
        path: String,
        /// When the trajectory starts, s.
        #[serde(default)]
        start: f64,
    },
}

impl PositionRef {
    /// The planned trajectory of a `minsnap` or `trajectory-file`
    /// reference and its start time; `None` for the analytic curves.
    /// Solves the minimum-snap problem or reads the file each call.
    pub fn plan(&self) -> Result<Option<(Trajectory, f64)>, PlanError> {
        match self {
            PositionRef::MinSnap {
                waypoints,
                yaw,
                times,
                mean_speed,
                time_budget,
                start,
            } => {
                let mut p = MinSnap::through(waypoints);
                if let Some(y) = yaw {
                    p = p.yaw(y);
                }
                let chosen = [times.is_some(), mean_speed.is_some(), time_budget.is_some()];
                if chosen.iter().filter(|c| **c).count() > 1 {
                    return Err(PlanError::Timing);
                }
                if let Some(t) = times {
                    p = p.times(t);
                } else if let Some(v) = mean_speed {
                    p = p.mean_speed(*v);
                } else if let Some(b) = time_budget {
                    p = p.time_budget(*b);
                }
                Ok(Some((p.solve().map_err(PlanError::Mission)?, *start)))
            }
            PositionRef::TrajectoryFile { path, start } => {
                let t = missions::pptraj::read_file(Path::new(path)).map_err(PlanError::Mission)?;
                Ok(Some((t, *start)))
            }
            _ => Ok(None),
        }
    }

    /// A relative trajectory file's path made relative to `dir` (the scene
    /// file's directory).
    pub(crate) fn resolve_path(&mut self, dir: &Path) {
        if let PositionRef::TrajectoryFile { path, .. } = self
            && Path::new(path.as_str()).is_relative()
        {
            *path = dir.join(path.as_str()).to_string_lossy().into_owned();
        }
    }
}

/// Why a planned reference could not be built.
#[derive(Debug)]
#[non_exhaustive]
pub enum PlanError {
    /// More than one of `times`, `mean_speed` and `time_budget`.
    Timing,
    /// The planner or the file reader refused its input.
    Mission(MissionError),
}

impl PlanError {
    /// The scene key at fault, for locating it in the file.
    pub(crate) fn key(&self) -> &'static str {
        match self {
            PlanError::Timing => "times",
            PlanError::Mission(MissionError::Input { field, .. }) => {
                ["waypoints", "yaw", "times", "mean_speed", "time_budget"]
                    .into_iter()
                    .find(|k| field.starts_with(k))
                    .unwrap_or("waypoints")
            }
            // A degenerate system: the waypoints and their times.
            PlanError::Mission(MissionError::Solve { .. }) => "waypoints",
            PlanError::Mission(_) => "path",
        }
    }
}

impl std::fmt::Display for PlanError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlanError::Timing => f.write_str(
                "give at most one of `times`, `mean_speed` and `time_budget` for a minsnap reference",
            ),
            PlanError::Mission(e) => e.fmt(f),
        }
    }
}

impl std::error::Error for PlanError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            PlanError::Timing => None,
            PlanError::Mission(e) => Some(e),
        }
    }
}
