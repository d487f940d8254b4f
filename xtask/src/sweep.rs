//! `cargo xtask sweep [scene]`: run time against error ("what
//! fast and accurate is measured by"). Every stepper over a range of step
//! sizes (dopri over tolerances) on the same scene; the error is the largest
//! difference in x and R over a 0.1 s sample grid against Dormand–Prince at
//! tol 1e-12 (independent of the stepper under test except for dopri
//! itself). Wall time is the best of three runs (the machine is shared).
//! Writes `target/sweep/<scene>.csv` and a log–log SVG.

use std::path::PathBuf;

use plotters::prelude::*;
use scenarios::Scene;

/// Options of `cargo xtask sweep`.
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
pub use scenarios::metrics::WorkPoint as Point;

pub fn sweep(a: SweepArgs) -> Result<(), String> {
    let mut base = scenarios::load(&a.scene).map_err(|e| e.to_string())?;
    match a.scalar.as_deref() {
        Some("f32") => base.scalar = scenarios::scene::Scalar::F32,
        Some("f64") => base.scalar = scenarios::scene::Scalar::F64,
        _ => {}
    }
    match a.backend.as_deref() {
        Some("glam") => base.backend = scenarios::scene::BackendKind::Glam,
        Some("nalgebra") => base.backend = scenarios::scene::BackendKind::Nalgebra,
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
    let mut text = String::from("stepper,param,steps,evaluations,wall_s,error\n");
    for p in &pts {
        text += &format!(
            "{},{},{},{},{},{}\n",
            p.kind, p.param, p.steps, p.evals, p.wall, p.error
        );
    }
    std::fs::write(&csv, text).map_err(|e| format!("{}: {e}", csv.display()))?;
    let svg = dir.join(format!("{}.svg", base.name));
    plot(&svg, &base.name, &pts)?;
    println!("wrote {} and {}", csv.display(), svg.display());
    Ok(())
}

/// Every stepper over its grid on `base` ([`scenarios::metrics::work_precision`]);
/// the settings that failed are printed.
pub fn points(
    base: &Scene,
    quick: bool,
    tick: &mut dyn FnMut(&Point),
) -> Result<Vec<Point>, String> {
    let sweep = scenarios::metrics::work_precision(base, quick, tick).map_err(|e| e.to_string())?;
    for (kind, p, e) in &sweep.failures {
        println!("  {kind} {p:e}: failed: {e}");
    }
    Ok(sweep.points)
}

/// Log–log error against wall time, a line per stepper.
pub fn plot(path: &std::path::Path, name: &str, pts: &[Point]) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let floor = 1e-16;
    let xs = pts.iter().map(|p| p.wall.max(1e-6).log10());
    let ys = pts.iter().map(|p| p.error.max(floor).log10());
    let (x0, x1) = xs.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
        (a.min(x), b.max(x))
    });
    let (y0, y1) = ys.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), y| {
        (a.min(y), b.max(y))
    });
    let shown = (840, 480);
    let (plot, side) = crate::figure::canvas(path, shown, 130)?;
    let mut c = ChartBuilder::on(&plot)
        .caption(
            format!("{name}: error against wall time"),
            crate::figure::font(17),
        )
        .margin(crate::figure::px(10))
        .x_label_area_size(crate::figure::px(40))
        .y_label_area_size(crate::figure::px(64))
        .build_cartesian_2d((x0 - 0.2)..(x1 + 0.2), (y0 - 0.5)..(y1 + 0.5))
        .map_err(|e| err(&e))?;
    crate::figure::axes(
        &mut c,
        "wall time [s], log scale",
        "max error: |Δx| [m], |ΔR| [dimensionless], log scale",
        &crate::figure::decade,
        &crate::figure::decade,
        12,
    )
    .map_err(|e| err(&e))?;
    let colors = crate::figure::COLORS;
    let mut kinds: Vec<&str> = pts.iter().map(|p| p.kind.as_str()).collect();
    kinds.dedup();
    let mut entries = Vec::new();
    for (i, k) in kinds.iter().enumerate() {
        let col = colors[i % colors.len()];
        let line: Vec<(f64, f64)> = pts
            .iter()
            .filter(|p| p.kind == *k)
            .map(|p| (p.wall.max(1e-6).log10(), p.error.max(floor).log10()))
            .collect();
        c.draw_series(LineSeries::new(line.clone(), crate::figure::line(col, 2)))
            .map_err(|e| err(&e))?;
        c.draw_series(
            line.into_iter()
                .map(|p| Circle::new(p, crate::figure::px(3), col.filled())),
        )
        .map_err(|e| err(&e))?;
        entries.push(crate::figure::Entry {
            label: k.to_string(),
            color: col,
            dash: 0,
            dots: true,
            line: true,
        });
    }
    crate::figure::legend(&side, &entries, 40)?;
    drop(c);
    drop(side);
    crate::figure::finish(plot, path, shown)
}
