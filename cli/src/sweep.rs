//! `geopid sweep [scene]`: run time against error ("what
//! fast and accurate is measured by"). Every stepper over a range of step
//! sizes (dopri over tolerances) on the same scene; the error is the largest
//! difference in x and R over a 0.1 s sample grid against Dormand–Prince at
//! tol 1e-12 (independent of the stepper under test except for dopri
//! itself). Wall time is the best of three runs (the machine is shared).
//! Writes `target/sweep/<scene>.csv` and a log–log SVG.

use std::path::PathBuf;

use scenes::Scene;

/// Options of `geopid sweep`.
#[derive(clap::Args, Debug)]
pub struct SweepArgs {
    /// Scene (built-in name or TOML file); default paper-flip.
    #[arg(default_value = "paper-flip")]
    pub scene: String,
    /// f32 or f64.
    #[arg(long, value_parser = ["f32", "f64"])]
    pub scalar: Option<String>,
    /// glam or nalgebra.
    #[arg(long, value_parser = ["glam", "nalgebra"])]
    pub backend: Option<String>,
}

/// One point of a work-precision sweep.
pub use studies::metrics::WorkPoint as Point;

/// `geopid sweep`: the sweep, its CSV and figure.
pub fn sweep(a: SweepArgs) -> Result<(), String> {
    let mut base = scenes::load(&a.scene).map_err(|e| e.to_string())?;
    match a.scalar.as_deref() {
        Some("f32") => base.scalar = scenes::scene::Scalar::F32,
        Some("f64") => base.scalar = scenes::scene::Scalar::F64,
        _ => {}
    }
    match a.backend.as_deref() {
        Some("glam") => base.backend = scenes::scene::BackendKind::Glam,
        Some("nalgebra") => base.backend = scenes::scene::BackendKind::Nalgebra,
        _ => {}
    }
    let pts = points(&base, false, &mut |_| {})?;
    println!(
        "{}: error = max(|Δx|, |ΔR|) over 0.1 s samples vs dopri 1e-12; wall = best of 3",
        base.name
    );
    println!("| stepper | dt / tol | steps | evaluations | wall (ms) | error |");
    println!("|---|---|---|---|---|---|");
    for p in &pts {
        println!(
            "| {} | {:e} | {} | {} | {:.2} | {:.2e} |",
            p.kind,
            p.param,
            p.steps,
            p.evals,
            p.wall * 1e3,
            p.error
        );
    }
    let dir = PathBuf::from("target/sweep");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let csv = dir.join(format!("{}.csv", base.name));
    let mut text = format!("{}\n", Point::CSV_COLUMNS);
    for p in &pts {
        text += &p.csv_row();
        text.push('\n');
    }
    std::fs::write(&csv, text).map_err(|e| format!("{}: {e}", csv.display()))?;
    let svg = dir.join(format!("{}.svg", base.name));
    studies::figures::work_precision(&svg, &base.name, &pts).map_err(|e| e.to_string())?;
    println!("wrote {} and {}", csv.display(), svg.display());
    Ok(())
}

/// Every stepper over its grid on `base` ([`studies::metrics::work_precision`]);
/// the settings that failed are printed.
pub fn points(
    base: &Scene,
    quick: bool,
    tick: &mut dyn FnMut(&Point),
) -> Result<Vec<Point>, String> {
    let sweep = studies::metrics::work_precision(base, quick, tick).map_err(|e| e.to_string())?;
    for (kind, p, e) in &sweep.failures {
        println!("  {kind} {p:e}: failed: {e}");
    }
    Ok(sweep.points)
}
