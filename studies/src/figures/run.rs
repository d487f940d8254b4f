//! A run's figures, like the paper's Figures 2–3.
#![allow(clippy::needless_range_loop)] // index notation mirrors the component formulas

use std::path::{Path, PathBuf};

use scenarios::{RunOutput, Sample};

use plotters::prelude::*;
use scenes::Scene;

use super::style as figure;

/// A curve: label, points, colour, dash pattern (0 solid; see
/// [`figure::DASHES`]).
type Series = (String, Vec<(f64, f64)>, RGBColor, usize);

const COLORS: [RGBColor; 6] = figure::COLORS;

/// A time plot of `series` with the legend beside it.
fn chart(path: &Path, title: &str, ylabel: &str, series: &[Series]) -> Result<(), String> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    let (mut t0, mut t1) = (f64::INFINITY, f64::NEG_INFINITY);
    for (_, pts, _, _) in series {
        for &(t, y) in pts {
            lo = lo.min(y);
            hi = hi.max(y);
            t0 = t0.min(t);
            t1 = t1.max(t);
        }
    }
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(format!("{}: nothing to plot", path.display()));
    }
    let pad = ((hi - lo) * 0.05).max(1e-9);
    let shown = (845, 420);
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let (plot, side) = figure::canvas(path, shown, 135)?;
    let mut c = ChartBuilder::on(&plot)
        .caption(title, figure::font(17))
        .margin(figure::px(10))
        .x_label_area_size(figure::px(40))
        .y_label_area_size(figure::px(64))
        .build_cartesian_2d(t0..t1, (lo - pad)..(hi + pad))
        .map_err(|e| err(&e))?;
    figure::axes(&mut c, "t [s]", ylabel, &figure::tick, &figure::tick, 12).map_err(|e| err(&e))?;
    let mut entries = Vec::new();
    for (name, pts, color, dash) in series {
        let style = figure::line(*color, 2);
        if *dash > 0 {
            let (len, gap) = figure::DASHES[*dash % figure::DASHES.len()];
            let (len, gap) = (figure::px(len), figure::px(gap));
            c.draw_series(DashedLineSeries::new(pts.iter().copied(), len, gap, style))
                .map_err(|e| err(&e))?;
        } else {
            c.draw_series(LineSeries::new(pts.iter().copied(), style))
                .map_err(|e| err(&e))?;
        }
        entries.push(figure::Entry {
            label: name.clone(),
            color: *color,
            dash: *dash,
            dots: false,
            line: true,
        });
    }
    figure::legend(&side, &entries, 40)?;
    drop(c);
    drop(side);
    figure::finish(plot, path, shown)
}

/// [`chart`] of plain curves, a colour each, all solid.
pub(super) fn time_series(
    path: &Path,
    title: &str,
    ylabel: &str,
    curves: &[(String, Vec<(f64, f64)>)],
) -> Result<(), String> {
    let series: Vec<Series> = curves
        .iter()
        .enumerate()
        .map(|(i, (l, pts))| (l.clone(), pts.clone(), COLORS[i % COLORS.len()], 0))
        .collect();
    chart(path, title, ylabel, &series)
}

/// Three components of a measured vector (solid) and of its desired
/// value (dashed, a pattern per component, so that curves lying on one
/// another stay apart), a colour per component.
fn measured_and_desired(
    s: &[Sample],
    symbol: &str,
    measured: impl Fn(&Sample) -> [f64; 3],
    desired: impl Fn(&Sample) -> [f64; 3],
) -> Vec<Series> {
    let mut series = Vec::new();
    for k in 0..3 {
        let label = format!("{symbol}{}", k + 1);
        let line = |f: &dyn Fn(&Sample) -> [f64; 3]| s.iter().map(|x| (x.t, f(x)[k])).collect();
        series.push((label.clone(), line(&measured), COLORS[k], 0));
        series.push((
            format!("{label}d (desired)"),
            line(&desired),
            COLORS[k],
            k + 1,
        ));
    }
    series
}

/// `n` solid curves `symbol1 … symboln` of one component each, a colour
/// per component.
fn components(
    s: &[Sample],
    n: usize,
    symbol: &str,
    get: impl Fn(&Sample, usize) -> f64,
) -> Vec<Series> {
    (0..n)
        .map(|k| {
            let line = s.iter().map(|x| (x.t, get(x, k))).collect();
            (
                format!("{symbol}{}", k + 1),
                line,
                COLORS[k % COLORS.len()],
                0,
            )
        })
        .collect()
}

/// The path seen from above (x1 across, x2 up the page, equal scales): the
/// flown one solid, the reference (`logs::ReferencePath`, a line per plan
/// segment) dashed.
fn top_view(path: &Path, title: &str, s: &[Sample]) -> Result<(), String> {
    let mut reference = logs::ReferencePath::default();
    s.iter().for_each(|x| reference.push(x));
    let lines = reference.lines();
    let flown: Vec<(f64, f64)> = s.iter().map(|x| (x.x[0], x.x[1])).collect();
    let all = flown.iter().copied().chain(
        lines
            .iter()
            .flat_map(|(_, p)| p.iter().map(|q| (q[0], q[1]))),
    );
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for (a, b) in all {
        (lo[0], hi[0]) = (lo[0].min(a), hi[0].max(a));
        (lo[1], hi[1]) = (lo[1].min(b), hi[1].max(b));
    }
    // One scale on both axes, the longer span padded by 5 %.
    let half = 0.55 * (hi[0] - lo[0]).max(hi[1] - lo[1]).max(1e-3);
    let mid = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let shown = (600, 470);
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let (plot, side) = figure::canvas(path, shown, 135)?;
    let mut c = ChartBuilder::on(&plot)
        .caption(title, figure::font(17))
        .margin(figure::px(10))
        .x_label_area_size(figure::px(40))
        .y_label_area_size(figure::px(64))
        .build_cartesian_2d(
            (mid[0] - half)..(mid[0] + half),
            (mid[1] - half)..(mid[1] + half),
        )
        .map_err(|e| err(&e))?;
    figure::axes(&mut c, "x1 [m]", "x2 [m]", &figure::tick, &figure::tick, 12)
        .map_err(|e| err(&e))?;
    c.draw_series(LineSeries::new(flown, figure::line(COLORS[0], 2)))
        .map_err(|e| err(&e))?;
    let (len, gap) = figure::DASHES[1];
    for (_, points) in &lines {
        let pts = points.iter().map(|q| (q[0], q[1]));
        let style = figure::line(COLORS[1], 2);
        c.draw_series(DashedLineSeries::new(
            pts,
            figure::px(len),
            figure::px(gap),
            style,
        ))
        .map_err(|e| err(&e))?;
    }
    let entry = |label: &str, color, dash| figure::Entry {
        label: label.into(),
        color,
        dash,
        dots: false,
        line: true,
    };
    let entries = [
        entry("flown", COLORS[0], 0),
        entry("reference", COLORS[1], 1),
    ];
    figure::legend(&side, &entries, 40)?;
    drop(c);
    drop(side);
    figure::finish(plot, path, shown)
}

/// Writes `psi.svg`, `position.svg`, `omega.svg`, `rotors.svg`, for a run
/// with a moving position reference `path.svg`, and for a run in wind
/// `wind.svg` into `dir`.
pub(super) fn figures(dir: &Path, scene: &Scene, out: &RunOutput) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let s = &out.samples;
    let name = &scene.name;
    let mut written = Vec::new();
    let mut draw = |file: &str, title: String, ylabel: &str, series: &[Series]| {
        let p = dir.join(file);
        chart(&p, &format!("{name}: {title}"), ylabel, series)?;
        written.push(p);
        Ok::<(), String>(())
    };
    let psi = [(
        "Ψ".into(),
        s.iter().map(|x| (x.t, x.psi)).collect(),
        COLORS[0],
        0,
    )];
    draw(
        "psi.svg",
        "attitude error Ψ".into(),
        "Ψ [dimensionless]",
        &psi,
    )?;
    if s.iter().any(|x| x.x != [0.0; 3] || x.xd != [0.0; 3]) {
        let series = measured_and_desired(s, "x", |x| x.x, |x| x.xd);
        let title = "position x (solid), x_d (dashed); e3 down".into();
        draw("position.svg", title, "x [m]", &series)?;
    }
    let series = measured_and_desired(s, "Ω", |x| x.omega, |x| x.omega_d);
    draw(
        "omega.svg",
        "Ω (solid), Ω_d or Ω_c (dashed)".into(),
        "Ω [rad/s]",
        &series,
    )?;
    let n_rot = s.first().map_or(0, |x| x.rotors.len());
    if n_rot > 0 {
        let series = components(s, n_rot, "f", |x, k| x.rotors[k]);
        let title = "rotor thrusts (allocation inverse)".into();
        draw("rotors.svg", title, "rotor thrust [N]", &series)?;
    }
    if s.iter().any(|x| x.wind != [0.0; 3]) {
        let series = components(s, 3, "w", |x, k| x.wind[k]);
        let title = "wind at the vehicle (inertial, e3 down)".into();
        draw("wind.svg", title, "w [m/s]", &series)?;
    }
    if s.windows(2).any(|w| w[0].xd != w[1].xd) {
        let p = dir.join("path.svg");
        top_view(&p, &format!("{name}: path from above (e3 down)"), s)?;
        written.push(p);
    }
    Ok(written)
}
