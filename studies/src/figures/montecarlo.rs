//! The Monte Carlo study's figures.

use std::path::Path;

use plotters::prelude::*;

use super::style as figure;
use crate::montecarlo::Outcome;

const COLORS: [RGBColor; 6] = figure::COLORS;

/// `angle_vs_time.svg` (initial angle from R_d against the time to
/// converge, one dot a sample; samples that did not converge sit on the
/// top edge in red) and `time_histogram.svg` (time to converge) for
/// a Monte Carlo run.
pub(super) fn montecarlo(dir: &Path, rows: &[Outcome]) -> Result<(), String> {
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
