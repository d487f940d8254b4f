//! SVG figures of runs, Monte Carlo studies and work-precision sweeps
//! (feature `plot`, off by default: plotters is the heaviest dependency
//! and most users plot with their own tools).
//!
//! Every figure shares one style, so that each reads at a glance: legends
//! in a panel beside the plot (never over data), desired or reference
//! curves dashed with the dash in the legend, tick labels without `-0`,
//! axis titles as `quantity [unit]`.
//!
//! ```no_run
//! let scene = scenes::builtin::paper_flip();
//! let out = scenes::run(&scene, Default::default())?;
//! let files = studies::figures::run(std::path::Path::new("figures"), &scene, &out)?;
//! assert!(files.iter().any(|f| f.ends_with("psi.svg")));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use std::path::{Path, PathBuf};

use crate::metrics::WorkPoint;
use crate::montecarlo::Outcome;
use scenarios::RunOutput;
use scenes::Scene;

mod montecarlo;
mod run;
mod style;
mod work_precision;

/// A figure that could not be drawn or written.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FigureError {
    /// The figure's file (or directory).
    pub path: PathBuf,
    /// What went wrong (it names the file).
    pub message: String,
}

impl std::fmt::Display for FigureError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.message)
    }
}

impl std::error::Error for FigureError {}

fn at(path: &Path) -> impl Fn(String) -> FigureError + '_ {
    move |message| FigureError {
        path: path.to_path_buf(),
        message,
    }
}

/// Writes `psi.svg`, `position.svg` (when the run moves), `omega.svg`,
/// `rotors.svg` (when the vehicle reports rotor thrusts), `path.svg` (the
/// path from above with its reference, when the reference moves) and, for
/// a run in wind, `wind.svg` into `dir` (created if needed), from the run's
/// recorded samples; returns the files written.
pub fn run(dir: &Path, scene: &Scene, out: &RunOutput) -> Result<Vec<PathBuf>, FigureError> {
    run::figures(dir, scene, out).map_err(at(dir))
}

/// Writes `angle_vs_time.svg` (initial angle against the time to converge,
/// one dot a sample; samples that did not converge on the top edge in
/// red) and `time_histogram.svg` into `dir`.
pub fn montecarlo(dir: &Path, rows: &[Outcome]) -> Result<(), FigureError> {
    montecarlo::montecarlo(dir, rows).map_err(at(dir))
}

/// A time plot of labelled curves `(label, [(t, y)])`, a colour each,
/// the legend beside the plot.
pub fn time_series(
    path: &Path,
    title: &str,
    ylabel: &str,
    curves: &[(String, Vec<(f64, f64)>)],
) -> Result<(), FigureError> {
    run::time_series(path, title, ylabel, curves).map_err(at(path))
}

/// One sweep's error against wall time, log–log, a line per stepper.
pub fn work_precision(path: &Path, name: &str, pts: &[WorkPoint]) -> Result<(), FigureError> {
    work_precision::plot(path, name, pts).map_err(at(path))
}

/// Work-precision on `paper-flip` and `free-rigid-body` in f64 and f32, a
/// panel each, every stepper, nalgebra solid and glam dashed; `wp` holds
/// `(scene, pair, point)` with the pair spelled `backend-scalar`.
pub fn work_precision_panels(
    path: &Path,
    wp: &[(String, &str, WorkPoint)],
) -> Result<(), FigureError> {
    work_precision::plot_panels(path, wp).map_err(at(path))
}
