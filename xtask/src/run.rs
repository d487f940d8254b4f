//! `cargo xtask run`.

use std::path::{Path, PathBuf};

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
    /// Run even when the step count exceeds 10⁹.
    #[arg(long)]
    pub yes: bool,
    /// Make a numerical-health warning (R leaving SO(3), Ψ outside [0, 2])
    /// an error (exit 1).
    #[arg(long)]
    pub strict: bool,
}

/// Checks the output paths before anything runs: each one's directory
/// exists and is writable, the CSV and MCAP paths differ, and neither is
/// the scene file (which would be overwritten).
pub fn check_outputs(
    csv: Option<&Path>,
    mcap: Option<&Path>,
    scene_file: Option<&Path>,
) -> Result<(), String> {
    // The absolute form of a path that may not exist yet: its directory
    // canonicalised, then its name.
    let resolve = |opt: &str, p: &Path| -> Result<PathBuf, String> {
        let name = p
            .file_name()
            .ok_or_else(|| format!("{opt} {}: not a file name", p.display()))?;
        let dir = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let dir = dir
            .canonicalize()
            .map_err(|e| format!("{opt} {}: directory {}: {e}", p.display(), dir.display()))?;
        // Writable: create and remove a probe file next to the target.
        let probe = dir.join(format!(".gpid-write-probe-{}", std::process::id()));
        std::fs::write(&probe, b"").map_err(|e| {
            format!(
                "{opt} {}: cannot write in {}: {e}",
                p.display(),
                dir.display()
            )
        })?;
        let _ = std::fs::remove_file(&probe);
        Ok(dir.join(name))
    };
    let c = csv.map(|p| resolve("--csv", p)).transpose()?;
    let m = mcap.map(|p| resolve("--mcap", p)).transpose()?;
    if let (Some(c), Some(m)) = (&c, &m)
        && c == m
    {
        return Err(format!(
            "--csv and --mcap are the same file ({}): one would overwrite the other",
            c.display()
        ));
    }
    if let Some(scene) = scene_file.and_then(|s| s.canonicalize().ok()) {
        for (opt, p) in [("--csv", &c), ("--mcap", &m)] {
            if p.as_ref() == Some(&scene) {
                return Err(format!(
                    "{opt} {} is the scene file itself",
                    scene.display()
                ));
            }
        }
    }
    Ok(())
}

/// Steps a run takes (fixed steps; dopri's calls), for the guard against
/// runs that would not end in a reasonable time.
pub fn estimated_steps(scene: &Scene) -> f64 {
    scene.duration / scene.integrator.dt
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
            indicatif::ProgressStyle::with_template("{bar:40} {percent:>3}% {msg} {elapsed}<{eta}")
                .expect("static template"),
        );
        b
    });
    // Off a terminal (a log, CI), a line at most every 10 s instead of the
    // bar.
    let tty = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let started = std::time::Instant::now();
    let mut last_line = 0.0f64;
    let mut tick = |f: f64| {
        if let Some(b) = &bar {
            b.set_position((f * 1000.0) as u64);
            b.set_message(format!("t = {:.1} s", f * scene.duration));
        }
        let el = started.elapsed().as_secs_f64();
        if !tty && est_steps > 2e5 && el - last_line >= 10.0 {
            last_line = el;
            let eta = if f > 0.0 {
                el * (1.0 - f) / f
            } else {
                f64::NAN
            };
            eprintln!(
                "{}: t = {:.1} s of {} s ({:.1} %), {el:.0} s elapsed, about {eta:.0} s left",
                scene.name,
                f * scene.duration,
                scene.duration,
                100.0 * f
            );
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

/// R drifting off SO(3) (‖RᵀR − I‖ above 1e-6 in f64, 1e-3 in f32: about
/// 1e4 ε of accumulated rounding) or Ψ outside [0, 2] (impossible for a
/// rotation), over the recorded samples and the end.
pub fn health_warnings(scene: &Scene, out: &RunOutput) -> Vec<String> {
    let bound = match scene.scalar {
        Scalar::F64 => 1e-6,
        Scalar::F32 => 1e-3,
    };
    let mut w = Vec::new();
    let e = out.max_orthogonality_error;
    if e.is_nan() || e > bound {
        w.push(format!(
            "‖RᵀR − I‖ reached {:.2e} (bound {bound:.0e} for {:?}): R has left SO(3); use a smaller --dt or a stepper that stays on the group (rk4-projected, rkmk4, lgvi)",
            out.max_orthogonality_error, scene.scalar
        ));
    }
    let (lo, hi) = out.psi_range;
    if lo.is_nan() || hi.is_nan() || lo < -1e-12 || hi > 2.0 + 1e-12 {
        w.push(format!(
            "Ψ left [0, 2] (range [{:.3e}, {:.3e}]): not a rotation any more",
            out.psi_range.0, out.psi_range.1
        ));
    }
    w
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
    let scene_file = Path::new(name);
    check_outputs(
        a.csv.as_deref(),
        a.mcap.as_deref(),
        scene_file.exists().then_some(scene_file),
    )?;
    let steps = estimated_steps(&scene);
    if steps > 1e9 && !a.yes {
        // About 1 µs a closed-loop step here (cargo xtask bench).
        let secs = steps * 1e-6;
        let took = if secs < 86_400.0 {
            format!("{:.1} hours", secs / 3600.0)
        } else if secs < 3.2e7 {
            format!("{:.0} days", secs / 86_400.0)
        } else {
            format!("{:.1e} years", secs / 3.156e7)
        };
        return Err(format!(
            "{}: {steps:.2e} steps ({} s at dt = {} s), about {took} at 1 µs a step; pass --yes to run it anyway",
            scene.name, scene.duration, scene.integrator.dt
        ));
    }
    let record = a.csv.is_some() || a.mcap.is_some() || a.plot.is_some();
    let mut out = run_scene(&scene, record)?;
    summary(&scene, &out);
    let health = health_warnings(&scene, &out);
    for w in &health {
        eprintln!("warning: {}: {w}", scene.name);
    }
    // The MCAP log records them (a metadata record `warnings`).
    out.warnings.extend(health.iter().cloned());
    if a.strict && !health.is_empty() {
        return Err(format!(
            "--strict: {} numerical-health warning(s)",
            health.len()
        ));
    }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_paths_are_checked_before_running() {
        let dir = std::env::temp_dir().join(format!("gpid-run-paths-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let csv = dir.join("a.csv");
        let mcap = dir.join("a.mcap");
        assert!(check_outputs(Some(&csv), Some(&mcap), None).is_ok());
        // Same file twice, spelled differently.
        let same = dir.join(".").join("a.csv");
        let e = check_outputs(Some(&csv), Some(&same), None).unwrap_err();
        assert!(e.contains("same file"), "{e}");
        // A missing directory is named with the option.
        let e = check_outputs(Some(&dir.join("nodir").join("x.csv")), None, None).unwrap_err();
        assert!(e.starts_with("--csv") && e.contains("nodir"), "{e}");
        // The scene file is not an output.
        let scene = dir.join("s.toml");
        std::fs::write(&scene, "x").unwrap();
        let e = check_outputs(None, Some(&scene), Some(&scene)).unwrap_err();
        assert!(e.contains("scene file"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn absurd_step_counts_are_refused_without_yes() {
        let mut s = scenarios::builtin::paper_flip();
        s.duration = 1e12;
        assert!(estimated_steps(&s) > 1e9);
    }
}
