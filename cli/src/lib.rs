//! The `geopid` command: run a scene, list the built-ins, check and tune a
//! scene's gains, Monte Carlo studies of the paper's attractivity claims,
//! and run time against error for every stepper.
//!
//! The binary is `geopid` (`cargo install --path cli` from a clone). This
//! library is its parser and its commands, so that the workspace's
//! developer tool (`cargo xtask`) offers the same subcommands from the same
//! code: [`Command`] is a clap subcommand enum a program flattens into its
//! own, and [`Command::execute`] runs one.
//!
//! ```
//! use clap::Parser;
//! #[derive(Parser)]
//! struct Cli {
//!     #[command(subcommand)]
//!     command: geopid_cli::Command,
//! }
//! let cli = Cli::parse_from(["geopid", "run", "paper-flip", "--duration", "0.1"]);
//! assert!(matches!(cli.command, geopid_cli::Command::Run(_)));
//! ```

#![deny(missing_docs)]

use std::sync::OnceLock;

pub mod gains;
pub mod montecarlo;
pub mod run;
pub mod sweep;
pub mod tune;

pub use run::{EXIT_SIGINT, EXIT_SIGPIPE, EXIT_SIGTERM};

/// The subcommands of `geopid` (and of `cargo xtask`, which adds its own).
#[derive(clap::Subcommand, Debug)]
pub enum Command {
    /// Run a scene (built-in name or TOML file) and write CSV/MCAP/plots.
    Run(Box<run::RunArgs>),
    /// List the built-in scenes, one name a line.
    Scenes,
    /// The gain conditions of Propositions 2–3 for a scene, or a search for
    /// gains that meet them (--synthesize).
    Gains(Box<gains::GainsArgs>),
    /// Many random initial conditions through attitude or position mode:
    /// the converged fraction and the time to converge (almost global
    /// attractivity, Propositions 2–3); `merge` combines shards, `near-pi`
    /// measures the slow escape from the π equilibrium.
    Montecarlo(Box<montecarlo::McArgs>),
    /// The gains k_x, k_v, k_R, k_Ω tuned on the exact gradient of a
    /// scene's tracking cost, within bounds and a thrust limit.
    Tune(tune::TuneArgs),
    /// Run time against error for every stepper on one scene.
    Sweep(sweep::SweepArgs),
}

impl Command {
    /// Runs the command; returns the process's exit status on success (0,
    /// or 130/143/141 for a run stopped by SIGINT/SIGTERM or a closed
    /// pipe, its outputs closed).
    pub fn execute(self) -> Result<u8, Error> {
        let done = |r: Result<(), String>| r.map(|()| 0).map_err(Error::Failed);
        match self {
            Command::Run(a) => run::run(*a),
            Command::Scenes => {
                for s in scenes::builtin::all() {
                    println!("{}", s.name);
                }
                Ok(0)
            }
            Command::Gains(a) => done(gains::gains(*a)),
            Command::Montecarlo(a) => done(montecarlo::montecarlo(*a)),
            Command::Tune(a) => done(tune::tune(a)),
            Command::Sweep(a) => done(sweep::sweep(a)),
        }
    }
}

/// Why a command failed. [`Error::exit_code`] is the process's status:
/// 2 for what the user asked (a scene, an option, an output path), 1 for a
/// run or study that failed on its way, as the Python package's command
/// line reports them.
#[derive(Debug)]
#[non_exhaustive]
pub enum Error {
    /// The scene failed to load or validate, or an option made it invalid.
    Scene(scenes::SceneError),
    /// An output could not be created or written.
    Output(logs::OutputError),
    /// Two outputs name the same file, or an output is the scene file.
    Path(logs::PathError),
    /// An option or an argument is missing or wrong.
    Usage(String),
    /// The run failed: a step, a control input, an output mid-run.
    Run {
        /// The scene's name.
        scene: String,
        /// The scene layer's error, or the engine's inside it (boxed: it
        /// is large, and this is the exceptional path).
        source: Box<scenes::Error>,
        /// Until when the outputs hold the run, when they streamed.
        held_until: Option<f64>,
    },
    /// `--strict`: the run finished with numerical-health warnings.
    Health {
        /// How many.
        count: usize,
    },
    /// The figures could not be drawn.
    Figure(studies::figures::FigureError),
    /// The terminal or a signal handler failed.
    Io {
        /// What was being done.
        what: &'static str,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A study (gains, Monte Carlo, tuning, a sweep) failed; the message
    /// names the option, file or sample.
    Failed(String),
}

impl Error {
    /// The process's exit status for this error.
    pub fn exit_code(&self) -> u8 {
        match self {
            Error::Scene(_) | Error::Output(_) | Error::Path(_) | Error::Usage(_) => 2,
            // A scene that fails only when built (an unknown integrator, a
            // vehicle kind's parameter) is still what the user asked.
            Error::Run { source, .. }
                if matches!(
                    **source,
                    scenes::Error::Scene(_)
                        | scenes::Error::Integrator(_)
                        | scenes::Error::CustomVehicle { .. }
                ) =>
            {
                2
            }
            _ => 1,
        }
    }
}

impl std::fmt::Display for Error {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Error::Scene(e) => write!(f, "{e}"),
            Error::Output(e) => write!(f, "{e}"),
            Error::Path(e) => write!(f, "{e}"),
            Error::Usage(m) | Error::Failed(m) => f.write_str(m),
            Error::Run {
                scene,
                source,
                held_until,
            } => {
                write!(f, "{scene}: {source}")?;
                // The library names the cause; what to change is the
                // command line's to say.
                if source.is_divergence() {
                    f.write_str(" — try a smaller --dt (or --tol for dopri)")?;
                }
                if let Some(t) = held_until {
                    write!(f, " (the outputs hold the run up to t = {t} s)")?;
                }
                Ok(())
            }
            Error::Health { count } => {
                write!(f, "--strict: {count} numerical-health warning(s)")
            }
            Error::Figure(e) => write!(f, "{e}"),
            Error::Io { what, source } => write!(f, "{what}: {source}"),
        }
    }
}

impl std::error::Error for Error {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            Error::Scene(e) => Some(e),
            Error::Output(e) => Some(e),
            Error::Path(e) => Some(e),
            Error::Run { source, .. } => Some(source.as_ref()),
            Error::Figure(e) => Some(e),
            Error::Io { source, .. } => Some(source),
            Error::Usage(_) | Error::Health { .. } | Error::Failed(_) => None,
        }
    }
}

impl From<scenes::SceneError> for Error {
    fn from(e: scenes::SceneError) -> Self {
        Error::Scene(e)
    }
}

impl From<logs::OutputError> for Error {
    fn from(e: logs::OutputError) -> Self {
        Error::Output(e)
    }
}

static PROGRAM: OnceLock<&'static str> = OnceLock::new();

/// Names the program in the commands this library prints for a user to
/// run (a Monte Carlo sample's replay, a shard's merge): `"geopid"` unless
/// set, `"cargo xtask"` in the workspace's developer tool. The first call
/// wins.
pub fn set_program(name: &'static str) {
    let _ = PROGRAM.set(name);
}

/// The program's name as [`set_program`] left it.
pub fn program() -> &'static str {
    PROGRAM.get().copied().unwrap_or("geopid")
}

/// A progress bar of `len` steps drawn with `template` on stderr when it
/// is a terminal, hidden otherwise (a log, CI).
pub fn progress(len: u64, template: &str) -> indicatif::ProgressBar {
    let b = indicatif::ProgressBar::new(len);
    if let Ok(style) = indicatif::ProgressStyle::with_template(template) {
        b.set_style(style);
    }
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        b.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    b
}

/// A command's result as the process's exit status, an error printed as
/// `error: …` on stderr.
pub fn exit_code(result: Result<u8, Error>) -> std::process::ExitCode {
    match result {
        Ok(status) => std::process::ExitCode::from(status),
        Err(e) => {
            eprintln!("error: {e}");
            std::process::ExitCode::from(e.exit_code())
        }
    }
}
