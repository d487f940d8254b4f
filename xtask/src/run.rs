//! `cargo xtask run`.

use std::path::PathBuf;

use scenarios::scene::{BackendKind, Scalar, Timing};
use scenarios::{RunOptions, RunOutput, Scene, builtin, output};

/// Options of `cargo xtask run`.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// Built-in scene name (see --list) or path to a TOML scene file.
    pub scene: Option<String>,
    /// List the built-in scenes and exit.
    #[arg(long)]
    pub list: bool,
    /// Integrator: lgvi, rk4, rk4-projected, rkmk4, euler, dopri.
    #[arg(long)]
    pub integrator: Option<String>,
    /// Step size, s (dopri: longest call; it adapts inside).
    #[arg(long)]
    pub dt: Option<f64>,
    /// dopri tolerance.
    #[arg(long)]
    pub tol: Option<f64>,
    /// f32 or f64.
    #[arg(long, value_parser = ["f32", "f64"])]
    pub scalar: Option<String>,
    /// glam or nalgebra.
    #[arg(long, value_parser = ["glam", "nalgebra"])]
    pub backend: Option<String>,
    /// Set k_I = k_i = 0.
    #[arg(long)]
    pub no_integral: bool,
    /// Simulated time, s.
    #[arg(long)]
    pub duration: Option<f64>,
    /// Record interval, s.
    #[arg(long)]
    pub sample: Option<f64>,
    /// Sampled control at this rate (Hz) instead of continuous.
    #[arg(long)]
    pub control_rate: Option<f64>,
    /// Write the samples as CSV.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Write an MCAP log (open in Foxglove with foxglove/layout.json).
    #[arg(long)]
    pub mcap: Option<PathBuf>,
    /// Write SVG figures (Ψ, x vs x_d, Ω vs Ω_d, rotor thrusts) into DIR.
    #[arg(long, value_name = "DIR")]
    pub plot: Option<PathBuf>,
}

/// Applies the command-line overrides to a scene and validates it.
pub fn apply(mut scene: Scene, a: &RunArgs) -> Result<Scene, String> {
    if let Some(k) = &a.integrator {
        k.parse::<integrators::IntegratorKind>()
            .map_err(|e| format!("--integrator: {e}"))?;
        scene.integrator.kind = k.clone();
    }
    let positive = |name: &str, v: f64| {
        if v.is_finite() && v > 0.0 {
            Ok(v)
        } else {
            Err(format!("{name} {v}: must be finite and > 0"))
        }
    };
    if let Some(v) = a.dt {
        scene.integrator.dt = positive("--dt", v)?;
    }
    if let Some(v) = a.tol {
        scene.integrator.tol = positive("--tol", v)?;
    }
    if let Some(v) = a.duration {
        scene.duration = positive("--duration", v)?;
    }
    if let Some(v) = a.sample {
        scene.record.sample = positive("--sample", v)?;
    }
    if let Some(v) = a.control_rate {
        scene.control.timing = Timing::Sampled;
        scene.control.rate = positive("--control-rate", v)?;
    }
    match a.scalar.as_deref() {
        Some("f32") => scene.scalar = Scalar::F32,
        Some("f64") => scene.scalar = Scalar::F64,
        _ => {}
    }
    match a.backend.as_deref() {
        Some("glam") => scene.backend = BackendKind::Glam,
        Some("nalgebra") => scene.backend = BackendKind::Nalgebra,
        _ => {}
    }
    if a.no_integral {
        scene.gains.k_i = 0.0;
        scene.gains.k_att_i = 0.0;
    }
    scene.validate().map_err(|(_, m)| m)?;
    Ok(scene)
}

/// Runs with a progress bar on long runs (hidden when not on a terminal).
pub fn run_scene(scene: &Scene, record: bool) -> Result<RunOutput, String> {
    let est_steps = scene.duration / scene.integrator.dt;
    let bar = (est_steps > 2e5).then(|| {
        let b = indicatif::ProgressBar::new(1000);
        b.set_style(
            indicatif::ProgressStyle::with_template("{bar:40} {percent:>3}% {elapsed}<{eta}")
                .expect("static template"),
        );
        b
    });
    let mut tick = |f: f64| {
        if let Some(b) = &bar {
            b.set_position((f * 1000.0) as u64);
        }
    };
    let out = scenarios::run(
        scene,
        RunOptions {
            record,
            progress: Some(&mut tick),
        },
    )
    .map_err(|e| format!("{}: {e}", scene.name))?;
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    for w in &out.warnings {
        eprintln!("warning: {}: {w}", scene.name);
    }
    Ok(out)
}

/// Prints the end-of-run summary.
pub fn summary(scene: &Scene, out: &RunOutput) {
    let l = &out.last;
    println!(
        "{} — {} s with {} (dt {}{}), {:?}/{:?}, {} control",
        scene.name,
        scene.duration,
        scene.integrator.kind,
        scene.integrator.dt,
        if scene.integrator.kind == "dopri" {
            format!(", tol {}", scene.integrator.tol)
        } else {
            String::new()
        },
        scene.scalar,
        scene.backend,
        match scene.control.timing {
            Timing::Continuous => "continuous".to_string(),
            Timing::Sampled => format!("sampled {} Hz", scene.control.rate),
        }
    );
    println!(
        "  final: Ψ = {:.3e}, ‖e_x‖ = {:.3e} m, |Ω| = {:.3e} rad/s, e_I = {:?}, e_i = {:?}",
        l.psi,
        l.ex,
        (l.omega.iter().map(|c| c * c).sum::<f64>()).sqrt(),
        l.e_att.map(|c| (c * 1e4).round() / 1e4),
        l.e_pos.map(|c| (c * 1e4).round() / 1e4),
    );
    println!(
        "  max over recorded samples: thrust {:.3} N, rotor thrust {:.3} N; {} switches, {} located sat′ events",
        out.max_thrust,
        out.max_rotor,
        out.switches.len(),
        out.events
    );
    if !out.event_times.is_empty() {
        let ev: Vec<String> = out
            .event_times
            .iter()
            .map(|(t, k)| format!("e_i{} at {t:.9} s", k + 1))
            .collect();
        println!("  sat′ events: {}", ev.join(", "));
    }
    let sps = out.steps as f64 / out.wall.max(1e-9);
    println!(
        "  {} steps, {} evaluations, wall {:.3} s, {:.0} steps/s",
        out.steps, out.evaluations, out.wall, sps
    );
}

pub fn run(a: RunArgs) -> Result<(), String> {
    if a.list {
        for s in builtin::all() {
            println!("{:<28} {}", s.name, s.description);
        }
        return Ok(());
    }
    let name = a
        .scene
        .as_deref()
        .ok_or("give a scene name or file (cargo xtask run --list shows the built-ins)")?;
    let scene = apply(scenarios::load(name).map_err(|e| e.to_string())?, &a)?;
    let record = a.csv.is_some() || a.mcap.is_some() || a.plot.is_some();
    let out = run_scene(&scene, record)?;
    summary(&scene, &out);
    if let Some(p) = &a.csv {
        output::write_csv(p, &out).map_err(|e| format!("--csv {}: {e}", p.display()))?;
        println!("  wrote {} ({} rows)", p.display(), out.samples.len());
    }
    if let Some(p) = &a.mcap {
        output::write_mcap(p, &out)?;
        println!("  wrote {}", p.display());
    }
    if let Some(dir) = &a.plot {
        let files = crate::plot::figures(dir, &scene, &out)?;
        for f in files {
            println!("  wrote {}", f.display());
        }
    }
    Ok(())
}
