//! Work-precision figures: error against wall time, log–log.

use std::path::Path;

use plotters::prelude::*;

use super::style as figure;
use crate::metrics::WorkPoint;

/// Errors below this are drawn at it (an exact result has no logarithm).
const FLOOR: f64 = 1e-16;

/// The point's place on the log–log axes (wall times below 1 µs at 1 µs).
fn log_xy(p: &WorkPoint) -> (f64, f64) {
    (p.wall.max(1e-6).log10(), p.error.max(FLOOR).log10())
}

/// The ranges of `log_xy` over `pts`: (x0, x1), (y0, y1).
fn log_ranges<'a>(pts: impl Iterator<Item = &'a WorkPoint>) -> ((f64, f64), (f64, f64)) {
    let wide = (f64::INFINITY, f64::NEG_INFINITY);
    pts.map(log_xy)
        .fold((wide, wide), |((x0, x1), (y0, y1)), (x, y)| {
            ((x0.min(x), x1.max(x)), (y0.min(y), y1.max(y)))
        })
}

/// Log–log error against wall time, a line per stepper.
pub(super) fn plot(path: &Path, name: &str, pts: &[WorkPoint]) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let ((x0, x1), (y0, y1)) = log_ranges(pts.iter());
    let shown = (840, 480);
    let (plot, side) = figure::canvas(path, shown, 130)?;
    let mut c = ChartBuilder::on(&plot)
        .caption(format!("{name}: error against wall time"), figure::font(17))
        .margin(figure::px(10))
        .x_label_area_size(figure::px(40))
        .y_label_area_size(figure::px(64))
        .build_cartesian_2d((x0 - 0.2)..(x1 + 0.2), (y0 - 0.5)..(y1 + 0.5))
        .map_err(|e| err(&e))?;
    figure::axes(
        &mut c,
        "wall time [s], log scale",
        "max error: |Δx| [m], |ΔR| [dimensionless], log scale",
        &figure::decade,
        &figure::decade,
        12,
    )
    .map_err(|e| err(&e))?;
    let colors = figure::COLORS;
    let mut kinds: Vec<&str> = pts.iter().map(|p| p.kind.as_str()).collect();
    kinds.dedup();
    let mut entries = Vec::new();
    for (i, k) in kinds.iter().enumerate() {
        let col = colors[i % colors.len()];
        let line: Vec<(f64, f64)> = pts.iter().filter(|p| p.kind == *k).map(log_xy).collect();
        c.draw_series(LineSeries::new(line.clone(), figure::line(col, 2)))
            .map_err(|e| err(&e))?;
        c.draw_series(
            line.into_iter()
                .map(|p| Circle::new(p, figure::px(3), col.filled())),
        )
        .map_err(|e| err(&e))?;
        entries.push(figure::Entry {
            label: k.to_string(),
            color: col,
            dash: 0,
            dots: true,
            line: true,
        });
    }
    figure::legend(&side, &entries, 40)?;
    drop(c);
    drop(side);
    figure::finish(plot, path, shown)
}

/// Work-precision of every stepper on two scenes and two scalars, a panel
/// each (`paper-flip`, `free-rigid-body` × f64, f32); nalgebra solid,
/// glam dashed; `wp` holds `(scene, pair, point)`, the pair as
/// `backend-scalar`.
pub(super) fn plot_panels(path: &Path, wp: &[(String, &str, WorkPoint)]) -> Result<(), String> {
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let shown = (1340, 900);
    let (root, side) = figure::canvas(path, shown, 140)?;
    let panels = root.split_evenly((2, 2));
    let colors = figure::COLORS;
    let kinds = ["euler", "lgvi", "rk4", "rk4-projected", "rkmk4", "dopri"];
    for (i, (scene, scalar)) in [
        ("paper-flip", "f64"),
        ("paper-flip", "f32"),
        ("free-rigid-body", "f64"),
        ("free-rigid-body", "f32"),
    ]
    .into_iter()
    .enumerate()
    {
        let sel: Vec<&(String, &str, WorkPoint)> = wp
            .iter()
            .filter(|(s, p, _)| s == scene && p.ends_with(scalar))
            .collect();
        if sel.is_empty() {
            continue;
        }
        let ((x0, x1), (y0, y1)) = log_ranges(sel.iter().map(|x| &x.2));
        let mut c = ChartBuilder::on(&panels[i])
            .caption(format!("{scene}, {scalar}"), figure::font(16))
            .margin(figure::px(8))
            .x_label_area_size(figure::px(36))
            .y_label_area_size(figure::px(56))
            .build_cartesian_2d((x0 - 0.2)..(x1 + 0.2), (y0 - 0.5)..(y1 + 0.5))
            .map_err(|e| err(&e))?;
        figure::axes(
            &mut c,
            "wall time [s], log scale",
            "max error [m, rad], log scale",
            &figure::decade,
            &figure::decade,
            11,
        )
        .map_err(|e| err(&e))?;
        for (k, kind) in kinds.iter().enumerate() {
            let col = colors[k % colors.len()];
            for backend in ["nalgebra", "glam"] {
                let line: Vec<(f64, f64)> = sel
                    .iter()
                    .filter(|x| x.2.kind == *kind && x.1.starts_with(backend))
                    .map(|x| log_xy(&x.2))
                    .collect();
                if line.is_empty() {
                    continue;
                }
                let style = figure::line(col, 2);
                if backend == "nalgebra" {
                    c.draw_series(LineSeries::new(line.clone(), style))
                        .map_err(|e| err(&e))?;
                } else {
                    let (d, g) = figure::DASHES[1];
                    c.draw_series(DashedLineSeries::new(
                        line.clone(),
                        figure::px(d),
                        figure::px(g),
                        style,
                    ))
                    .map_err(|e| err(&e))?;
                }
                c.draw_series(
                    line.into_iter()
                        .map(|p| Circle::new(p, figure::px(2), col.filled())),
                )
                .map_err(|e| err(&e))?;
            }
        }
    }
    let mut entries: Vec<figure::Entry> = kinds
        .iter()
        .enumerate()
        .map(|(k, kind)| figure::Entry {
            label: kind.to_string(),
            color: colors[k % colors.len()],
            dash: 0,
            dots: true,
            line: true,
        })
        .collect();
    for (label, dash) in [("nalgebra", 0), ("glam", 1)] {
        entries.push(figure::Entry {
            label: label.into(),
            color: BLACK,
            dash,
            dots: false,
            line: true,
        });
    }
    figure::legend(&side, &entries, 40)?;
    drop(panels);
    drop(side);
    figure::finish(root, path, shown)
}
