//! `geopid run`.

use std::io::Write as _;
use std::path::{Path, PathBuf};

use std::sync::atomic::{AtomicBool, Ordering};

use scenarios::{RunOptions, RunOutput, SimError};
use scenes::SceneError;
use scenes::scene::{BackendKind, Scalar};
use scenes::{Scene, builtin};

use crate::Error;

mod report;
mod signals;

pub use report::health_warnings;
use signals::install_signal_flags;
pub use signals::{EXIT_SIGINT, EXIT_SIGPIPE, EXIT_SIGTERM};

/// Options of `geopid run`.
#[derive(clap::Args, Debug)]
pub struct RunArgs {
    /// Built-in scene name (see --list) or path to a TOML scene file.
    pub scene: Option<String>,
    /// List the built-in scenes and exit.
    #[arg(long)]
    pub list: bool,
    /// Integrator: lgvi, rk4, rk4-projected, rkmk4, euler, dopri [default:
    /// the scene's; --print-scene shows every value a run would use].
    #[arg(long)]
    pub integrator: Option<String>,
    /// Step size, s (dopri: longest call; it adapts inside) [default: the
    /// scene's].
    #[arg(long, allow_negative_numbers = true)]
    pub dt: Option<f64>,
    /// dopri tolerance [default: the scene's].
    #[arg(long, allow_negative_numbers = true)]
    pub tol: Option<f64>,
    /// f32 or f64 [default: the scene's].
    #[arg(long, value_parser = ["f32", "f64"])]
    pub scalar: Option<String>,
    /// glam or nalgebra [default: the scene's].
    #[arg(long, value_parser = ["glam", "nalgebra"])]
    pub backend: Option<String>,
    /// Set k_I = k_i = 0.
    #[arg(long)]
    pub no_integral: bool,
    /// Simulated time, s [default: the scene's].
    #[arg(long, allow_negative_numbers = true)]
    pub duration: Option<f64>,
    /// Record interval, s [default: the scene's]. Samples are taken
    /// between steps; they never change the steps.
    #[arg(long, allow_negative_numbers = true)]
    pub sample: Option<f64>,
    /// Sampled control at this rate (Hz) instead of continuous [default:
    /// the scene's].
    #[arg(long, allow_negative_numbers = true)]
    pub control_rate: Option<f64>,
    /// A flight computer's loop rates instead of one control rate:
    /// crazyflie (estimator 1 kHz, attitude 500 Hz, position 100 Hz).
    #[arg(long, value_name = "PRESET")]
    pub loop_rates: Option<String>,
    /// The sensors the vehicle carries, a suite by name: rotorpy,
    /// crazyflie, mpu9250, fdcl-gazebo [default: the scene's].
    #[arg(long, value_name = "PRESET")]
    pub sensors: Option<String>,
    /// What the flight modes read: none (the true state), mocap (the
    /// latest motion-capture frame), iekf (the invariant EKF on SE₂(3)) or
    /// complementary (the complementary filter on SO(3)) or fdcl-ekf (the
    /// FDCL lab's EKF, on an IMU with an attitude output and a GPS); all
    /// but none need sampled control [default: the scene's].
    #[arg(long, value_parser = ["none", "mocap", "iekf", "complementary", "fdcl-ekf"])]
    pub estimator: Option<String>,
    /// Seed of the sensor noise [default: the scene's].
    #[arg(long)]
    pub seed: Option<u64>,
    /// Print the scene as TOML with the options above applied (every
    /// value a run would use), and exit without running.
    #[arg(long)]
    pub print_scene: bool,
    /// Write the samples as CSV.
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Write an MCAP log (open in Foxglove with foxglove/layout.json).
    #[arg(long)]
    pub mcap: Option<PathBuf>,
    /// Write SVG figures (Ψ, x vs x_d, the path from above, Ω vs Ω_d, rotor thrusts) into DIR.
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

/// Applies the command-line overrides to a scene and validates it.
pub fn apply(scene: Scene, a: &RunArgs) -> Result<Scene, SceneError> {
    let overrides = scenes::Overrides {
        integrator: a.integrator.clone(),
        dt: a.dt,
        tol: a.tol,
        duration: a.duration,
        sample: a.sample,
        control_rate: a.control_rate,
        loop_rates: a.loop_rates.clone(),
        scalar: a.scalar.as_deref().map(|s| match s {
            "f32" => Scalar::F32,
            _ => Scalar::F64,
        }),
        backend: a.backend.as_deref().map(|s| match s {
            "glam" => BackendKind::Glam,
            _ => BackendKind::Nalgebra,
        }),
        no_integral: a.no_integral,
        sensors: a.sensors.clone(),
        estimator: a.estimator.as_deref().and_then(|e| e.parse().ok()),
        seed: a.seed,
    };
    overrides.apply(scene)
}

/// Runs `scene` with a progress bar on long runs (hidden when not on a
/// terminal), streaming to `sink` and stopping when `cancel` is set.
pub fn run_scene_with(
    scene: &Scene,
    record: bool,
    sink: Option<&mut dyn logs::Sink>,
    cancel: Option<&AtomicBool>,
) -> Result<RunOutput, scenes::Error> {
    let est_steps = scene.estimated_steps();
    let bar = (est_steps > 2e5)
        .then(|| crate::progress(1000, "{bar:40} {percent:>3}% {msg} {elapsed}<{eta}"));
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
    let out = scenes::run(
        scene,
        RunOptions {
            record,
            progress: Some(&mut tick),
            // Reborrowed: the options' one lifetime is the closure's.
            sink: sink.map(|k| -> &mut dyn logs::Sink { k }),
            cancel,
            extrema: true,
        },
    );
    if let Some(b) = bar {
        b.finish_and_clear();
    }
    let out = out?;
    for w in &out.warnings {
        eprintln!("warning: {}: {w}", scene.name);
    }
    Ok(out)
}

/// How a run ended, for its outputs and its exit status: the warnings
/// (the run's and the health check's, printed here), the `stopped` record
/// of a run cut short (by a signal: which one; by an error: the error),
/// and the status (0; 130/143 after SIGINT/SIGTERM; 1 after an error).
fn outcome(
    scene: &Scene,
    result: &Result<RunOutput, scenes::Error>,
    last_t: Option<f64>,
    by_int: bool,
    by_term: bool,
) -> (Vec<String>, Option<logs::Stopped>, u8) {
    match result {
        Ok(out) => {
            let mut w = out.warnings.clone();
            let health = health_warnings(out);
            for h in &health {
                eprintln!("warning: {}: {h}", scene.name);
            }
            w.extend(health);
            let (reason, status) = if by_term {
                ("SIGTERM", EXIT_SIGTERM)
            } else if by_int {
                ("SIGINT", EXIT_SIGINT)
            } else {
                ("cancelled", EXIT_SIGINT)
            };
            let stopped = out.interrupted_at().map(|t| logs::Stopped {
                t,
                reason: reason.into(),
            });
            let status = if stopped.is_some() { status } else { 0 };
            (w, stopped, status)
        }
        Err(e) => (
            Vec::new(),
            Some(logs::Stopped {
                t: last_t.unwrap_or(0.0),
                reason: format!("error: {e}"),
            }),
            1,
        ),
    }
}

/// Every output path checked before the run: none may be the scene file.
fn check_paths(a: &RunArgs, scene_name: &str) -> Result<(), Error> {
    let scene_file = Path::new(scene_name);
    logs::check_paths(
        &[("--csv", a.csv.as_deref()), ("--mcap", a.mcap.as_deref())],
        a.plot.as_deref().map(|p| ("--plot", p)),
        scene_file.exists().then_some(scene_file),
    )
    .map_err(Error::Path)
}

/// `geopid run`: returns the process's exit status (0, or 130/143
/// after SIGINT/SIGTERM with the outputs closed).
pub fn run(a: RunArgs) -> Result<u8, Error> {
    if a.list {
        for s in builtin::all() {
            println!("{:<28} {}", s.name, s.description);
        }
        return Ok(0);
    }
    let name = a.scene.as_deref().ok_or_else(|| {
        Error::Usage(format!(
            "give a scene name or file (`{} scenes` lists the built-ins)",
            crate::program()
        ))
    })?;
    let scene = apply(scenes::load(name)?, &a)?;
    if a.print_scene {
        print!("{}", scene.to_toml());
        return Ok(0);
    }
    check_paths(&a, name)?;
    if !a.yes {
        scene.check_size(1e9).map_err(|mut e| {
            e.message.push_str("; pass --yes to run it anyway");
            Error::Scene(e)
        })?;
    }
    let (cancel, by_int, by_term) = install_signal_flags().map_err(|source| Error::Io {
        what: "installing the signal handlers",
        source,
    })?;
    // The files are created now (as `.partial`) and written as the run
    // goes; memory does not grow with the duration.
    let mut csv = a.csv.as_deref().map(logs::CsvWriter::create).transpose()?;
    let mut mcap = a
        .mcap
        .as_deref()
        .map(logs::McapWriter::create)
        .transpose()?;
    let mut sinks: Vec<&mut dyn logs::Sink> = Vec::new();
    if let Some(w) = csv.as_mut() {
        sinks.push(w);
    }
    if let Some(w) = mcap.as_mut() {
        sinks.push(w);
    }
    let streaming = !sinks.is_empty();
    let mut sink = logs::Watched::new(logs::Tee(sinks));
    let result = run_scene_with(
        &scene,
        a.plot.is_some(),
        streaming.then_some(&mut sink as &mut dyn logs::Sink),
        Some(&cancel),
    );
    let last_t = sink.last_t;
    drop(sink);
    // Close the files whatever happened: an error mid-run leaves
    // everything logged before it intact, with a `stopped` record saying
    // where and why.
    let (mut warnings, stopped, status) = outcome(
        &scene,
        &result,
        last_t,
        by_int.load(Ordering::Relaxed),
        by_term.load(Ordering::Relaxed),
    );
    // The report goes to stderr when an output streams to stdout
    // (`--csv /dev/stdout | ...`), so it does not land among the rows.
    let to_stdout = [a.csv.as_deref(), a.mcap.as_deref()]
        .into_iter()
        .flatten()
        .any(logs::is_stdout);
    let mut report: Box<dyn std::io::Write> = if to_stdout {
        Box::new(std::io::stderr())
    } else {
        Box::new(std::io::stdout())
    };
    if let Ok(out) = &result {
        write!(report, "{}", scenes::RunReport::new(&scene, out)).map_err(|source| Error::Io {
            what: "printing the summary",
            source,
        })?;
    }
    let health_count = warnings.len() - result.as_ref().map_or(0, |o| o.warnings.len());
    // Both files close at once: each ends with an fsync, which for a long
    // run's gigabytes takes a second or more.
    let (csv_done, mcap_done) = std::thread::scope(|sc| {
        let c = csv.map(|w| sc.spawn(move || w.finish()));
        let m = mcap.map(|w| w.finish(&warnings, stopped.as_ref()));
        (
            c.map(|h| h.join().expect("the CSV close does not panic")),
            m,
        )
    });
    // A reader that closed its pipe (`--csv /dev/stdout | head`) ends the
    // run as a shell pipeline expects: quietly, with SIGPIPE's status.
    let pipe_closed = |e: &logs::OutputError| e.io_kind == Some(std::io::ErrorKind::BrokenPipe);
    if matches!(&result, Err(scenes::Error::Run(SimError::Output(e))) if pipe_closed(e))
        || matches!(&csv_done, Some(Err(e)) if pipe_closed(e))
        || matches!(&mcap_done, Some(Err(e)) if pipe_closed(e))
    {
        return Ok(EXIT_SIGPIPE);
    }
    if let Some(rows) = csv_done {
        let rows = rows?;
        let p = a.csv.as_deref().expect("a CSV writer has a path");
        let _ = writeln!(report, "  wrote {} ({rows} rows)", p.display());
    }
    if let Some(n) = mcap_done {
        let n = n?;
        let p = a.mcap.as_deref().expect("an MCAP writer has a path");
        let _ = writeln!(report, "  wrote {} ({n} messages)", p.display());
    }
    warnings.clear();
    let out = result.map_err(|source| Error::Run {
        scene: scene.name.clone(),
        source: Box::new(source),
        held_until: last_t.filter(|_| streaming),
    })?;
    if let Some(s) = &stopped {
        eprintln!(
            "{}: stopped by {} at t = {} s of {} s; the outputs are closed and hold the run up to there",
            scene.name, s.reason, s.t, scene.duration
        );
        return Ok(status);
    }
    if a.strict && health_count > 0 {
        return Err(Error::Health {
            count: health_count,
        });
    }
    if let Some(dir) = &a.plot {
        let files = studies::figures::run(dir, &scene, &out).map_err(Error::Figure)?;
        for f in files {
            let _ = writeln!(report, "  wrote {}", f.display());
        }
    }
    Ok(status)
}
