//! SVG figures like the paper's Figures 2–3.
#![allow(clippy::needless_range_loop)] // index notation mirrors the component formulas

use std::path::{Path, PathBuf};

use plotters::prelude::*;
use scenarios::{RunOutput, Scene};

type Series = (String, Vec<(f64, f64)>, RGBColor, bool);

const COLORS: [RGBColor; 4] = [
    RGBColor(31, 119, 180),
    RGBColor(214, 39, 40),
    RGBColor(44, 160, 44),
    RGBColor(148, 103, 189),
];

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
    let root = SVGBackend::new(path, (720, 420)).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mut c = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(t0..t1, (lo - pad)..(hi + pad))
        .map_err(|e| err(&e))?;
    c.configure_mesh()
        .x_desc("t [s]")
        .y_desc(ylabel)
        .draw()
        .map_err(|e| err(&e))?;
    for (name, pts, color, dashed) in series {
        let style = ShapeStyle::from(color).stroke_width(if *dashed { 1 } else { 2 });
        let s = c
            .draw_series(LineSeries::new(pts.iter().copied(), style))
            .map_err(|e| err(&e))?;
        let col = *color;
        s.label(name.clone())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 18, y)], col));
    }
    c.configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// Writes `psi.svg`, `position.svg`, `omega.svg`, `rotors.svg` into `dir`.
pub fn figures(dir: &Path, scene: &Scene, out: &RunOutput) -> Result<Vec<PathBuf>, String> {
    std::fs::create_dir_all(dir).map_err(|e| format!("--plot {}: {e}", dir.display()))?;
    let s = &out.samples;
    let mut written = Vec::new();
    let name = &scene.name;
    let p = dir.join("psi.svg");
    chart(
        &p,
        &format!("{name}: attitude error Ψ"),
        "Ψ",
        &[(
            "Ψ".into(),
            s.iter().map(|x| (x.t, x.psi)).collect(),
            COLORS[0],
            false,
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
                false,
            ));
            series.push((
                format!("x{}d", k + 1),
                s.iter().map(|x| (x.t, x.xd[k])).collect(),
                COLORS[k],
                true,
            ));
        }
        let p = dir.join("position.svg");
        chart(
            &p,
            &format!("{name}: position x (thick) and x_d (thin), e3 down"),
            "m",
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
            false,
        ));
        series.push((
            format!("Ω{}d", k + 1),
            s.iter().map(|x| (x.t, x.omega_d[k])).collect(),
            COLORS[k],
            true,
        ));
    }
    let p = dir.join("omega.svg");
    chart(
        &p,
        &format!("{name}: Ω (thick) and Ω_d / Ω_c (thin)"),
        "rad/s",
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
                    COLORS[k % 4],
                    k >= 4,
                )
            })
            .collect();
        let p = dir.join("rotors.svg");
        chart(
            &p,
            &format!("{name}: rotor thrusts (allocation inverse)"),
            "N",
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
pub fn montecarlo(dir: &Path, rows: &[crate::montecarlo::Outcome]) -> Result<(), String> {
    let err = |p: &Path, e: &dyn std::fmt::Display| format!("{}: {e}", p.display());
    let t: Vec<f64> = rows
        .iter()
        .filter(|r| r.converged)
        .map(|r| r.t_converge)
        .collect();
    let t_max = t.iter().copied().fold(0.0, f64::max).max(1e-3) * 1.05;
    let path = dir.join("angle_vs_time.svg");
    {
        let root = SVGBackend::new(&path, (720, 460)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| err(&path, &e))?;
        let mut c = ChartBuilder::on(&root)
            .caption(
                "Monte Carlo: initial angle from R_d vs time to converge",
                ("sans-serif", 18),
            )
            .margin(10)
            .x_label_area_size(35)
            .y_label_area_size(60)
            .build_cartesian_2d(0.0..180.0, 0.0..t_max)
            .map_err(|e| err(&path, &e))?;
        c.configure_mesh()
            .x_desc("initial angle [deg]")
            .y_desc("time to converge [s]")
            .draw()
            .map_err(|e| err(&path, &e))?;
        c.draw_series(rows.iter().map(|r| {
            if r.converged {
                Circle::new((r.angle.to_degrees(), r.t_converge), 1, COLORS[0].filled())
            } else {
                Circle::new((r.angle.to_degrees(), t_max), 3, COLORS[1].filled())
            }
        }))
        .map_err(|e| err(&path, &e))?;
        root.present().map_err(|e| err(&path, &e))?;
    }
    let path = dir.join("time_histogram.svg");
    let bins = 50usize;
    let w = t_max / bins as f64;
    let mut counts = vec![0u64; bins];
    for &x in &t {
        counts[((x / w) as usize).min(bins - 1)] += 1;
    }
    let c_max = counts.iter().copied().max().unwrap_or(1).max(1) as f64 * 1.05;
    let root = SVGBackend::new(&path, (720, 420)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&path, &e))?;
    let mut c = ChartBuilder::on(&root)
        .caption("Monte Carlo: time to converge", ("sans-serif", 18))
        .margin(10)
        .x_label_area_size(35)
        .y_label_area_size(60)
        .build_cartesian_2d(0.0..t_max, 0.0..c_max)
        .map_err(|e| err(&path, &e))?;
    c.configure_mesh()
        .x_desc("time to converge [s]")
        .y_desc("samples")
        .draw()
        .map_err(|e| err(&path, &e))?;
    c.draw_series(counts.iter().enumerate().map(|(k, &n)| {
        Rectangle::new(
            [(k as f64 * w, 0.0), ((k + 1) as f64 * w, n as f64)],
            COLORS[0].filled(),
        )
    }))
    .map_err(|e| err(&path, &e))?;
    root.present().map_err(|e| err(&path, &e))?;
    Ok(())
}
