//! SVG figures like the paper's Figures 2–3.
#![allow(clippy::needless_range_loop)] // index notation mirrors the component formulas

use std::path::{Path, PathBuf};

use plotters::prelude::*;
use scenarios::{RunOutput, Scene};

use crate::figure;

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

/// Writes `psi.svg`, `position.svg`, `omega.svg`, `rotors.svg` and, for a
/// run in wind, `wind.svg` into `dir`.
pub fn figures(dir: &Path, scene: &Scene, out: &RunOutput) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("--plot {}: {e}", dir.display()))?;
    let s = &out.samples;
    let mut written = Vec::new();
    let name = &scene.name;
    let p = dir.join("psi.svg");
    chart(
        &p,
        &format!("{name}: attitude error Ψ"),
        "Ψ [dimensionless]",
        &[(
            "Ψ".into(),
            s.iter().map(|x| (x.t, x.psi)).collect(),
            COLORS[0],
            0,
        )],
    )?;
    written.push(p);
    if s.iter().any(|x| x.x != [0.0; 3] || x.xd != [0.0; 3]) {
        let mut series = Vec::new();
        for k in 0..3 {
            series.push((
                format!("x{}", k + 1),
                s.iter().map(|x| (x.t, x.x[k])).collect(),
                COLORS[k],
                0,
            ));
            series.push((
                format!("x{}d (desired)", k + 1),
                s.iter().map(|x| (x.t, x.xd[k])).collect(),
                COLORS[k],
                k + 1,
            ));
        }
        let p = dir.join("position.svg");
        chart(
            &p,
            &format!("{name}: position x (solid), x_d (dashed); e3 down"),
            "x [m]",
            &series,
        )?;
        written.push(p);
    }
    let mut series = Vec::new();
    for k in 0..3 {
        series.push((
            format!("Ω{}", k + 1),
            s.iter().map(|x| (x.t, x.omega[k])).collect(),
            COLORS[k],
            0,
        ));
        series.push((
            format!("Ω{}d (desired)", k + 1),
            s.iter().map(|x| (x.t, x.omega_d[k])).collect(),
            COLORS[k],
            k + 1,
        ));
    }
    let p = dir.join("omega.svg");
    chart(
        &p,
        &format!("{name}: Ω (solid), Ω_d or Ω_c (dashed)"),
        "Ω [rad/s]",
        &series,
    )?;
    written.push(p);
    let n_rot = s.first().map_or(0, |x| x.rotors.len());
    if n_rot > 0 {
        let series: Vec<Series> = (0..n_rot)
            .map(|k| {
                (
                    format!("f{}", k + 1),
                    s.iter().map(|x| (x.t, x.rotors[k])).collect(),
                    COLORS[k % COLORS.len()],
                    0,
                )
            })
            .collect();
        let p = dir.join("rotors.svg");
        chart(
            &p,
            &format!("{name}: rotor thrusts (allocation inverse)"),
            "rotor thrust [N]",
            &series,
        )?;
        written.push(p);
    }
    if s.iter().any(|x| x.wind != [0.0; 3]) {
        let series: Vec<Series> = (0..3)
            .map(|k| {
                (
                    format!("w{}", k + 1),
                    s.iter().map(|x| (x.t, x.wind[k])).collect(),
                    COLORS[k],
                    0,
                )
            })
            .collect();
        let p = dir.join("wind.svg");
        chart(
            &p,
            &format!("{name}: wind at the vehicle (inertial, e3 down)"),
            "w [m/s]",
            &series,
        )?;
        written.push(p);
    }
    Ok(written)
}

/// `angle_vs_time.svg` (initial angle from R_d against the time to
/// converge, one dot a sample; samples that did not converge sit on the
/// top edge in red) and `time_histogram.svg` (time to converge) for
/// `cargo xtask montecarlo`.
pub fn montecarlo(dir: &Path, rows: &[scenarios::montecarlo::Outcome]) -> Result<(), String> {
    let err = |p: &Path, e: &dyn std::fmt::Display| format!("{}: {e}", p.display());
    let t: Vec<f64> = rows
        .iter()
        .filter(|r| r.converged)
        .map(|r| r.t_converge)
        .collect();
    let t_max = t.iter().copied().fold(0.0, f64::max).max(1e-3) * 1.05;
    let path = dir.join("angle_vs_time.svg");
    let shown = (860, 460);
    {
        let (plot, side) = figure::canvas(&path, shown, 140)?;
        let mut c = ChartBuilder::on(&plot)
            .caption(
                "Monte Carlo: initial angle from R_d vs time to converge",
                figure::font(17),
            )
            .margin(figure::px(12))
            .x_label_area_size(figure::px(40))
            .y_label_area_size(figure::px(64))
            .build_cartesian_2d(0.0..180.0, 0.0..t_max)
            .map_err(|e| err(&path, &e))?;
        figure::axes(
            &mut c,
            "initial angle [deg]",
            "time to converge [s]",
            &figure::tick,
            &figure::tick,
            12,
        )
        .map_err(|e| err(&path, &e))?;
        c.draw_series(rows.iter().map(|r| {
            if r.converged {
                Circle::new(
                    (r.angle.to_degrees(), r.t_converge),
                    figure::px(2),
                    COLORS[0].mix(0.6).filled(),
                )
            } else {
                Circle::new(
                    (r.angle.to_degrees(), t_max),
                    figure::px(3),
                    COLORS[1].filled(),
                )
            }
        }))
        .map_err(|e| err(&path, &e))?;
        let dot = |label: &str, color| figure::Entry {
            label: label.into(),
            color,
            dash: 0,
            dots: true,
            line: false,
        };
        figure::legend(
            &side,
            &[
                dot("converged", COLORS[0]),
                dot("did not (top edge)", COLORS[1]),
            ],
            40,
        )?;
        drop(c);
        drop(side);
        figure::finish(plot, &path, shown)?;
    }
    let path = dir.join("time_histogram.svg");
    let bins = 50usize;
    let w = t_max / bins as f64;
    let mut counts = vec![0u64; bins];
    for &x in &t {
        counts[((x / w) as usize).min(bins - 1)] += 1;
    }
    let c_max = counts.iter().copied().max().unwrap_or(1).max(1) as f64 * 1.05;
    let shown = (720, 420);
    let (plot, _) = figure::canvas(&path, shown, 0)?;
    let mut c = ChartBuilder::on(&plot)
        .caption("Monte Carlo: time to converge", figure::font(17))
        .margin(figure::px(12))
        .x_label_area_size(figure::px(40))
        .y_label_area_size(figure::px(64))
        .build_cartesian_2d(0.0..t_max, 0.0..c_max)
        .map_err(|e| err(&path, &e))?;
    // Counts are whole: label only the integer ticks.
    let count = |v: &f64| {
        if (v - v.round()).abs() < 1e-9 {
            format!("{}", v.round() as i64)
        } else {
            String::new()
        }
    };
    figure::axes(
        &mut c,
        "time to converge [s]",
        "samples [count]",
        &figure::tick,
        &count,
        12,
    )
    .map_err(|e| err(&path, &e))?;
    c.draw_series(counts.iter().enumerate().map(|(k, &n)| {
        Rectangle::new(
            [(k as f64 * w, 0.0), ((k + 1) as f64 * w, n as f64)],
            COLORS[0].filled(),
        )
    }))
    .map_err(|e| err(&path, &e))?;
    drop(c);
    figure::finish(plot, &path, shown)
}
