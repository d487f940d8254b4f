//! `cargo xtask <command>`: the project's developer tasks.
//!
//! * `bench [--quick]` — the controller update and the closed-loop step
//!   against hand-written glam twins, work-precision on every pair, as CSV,
//!   SVG and MCAP under `target/bench/`.
//! * `bench-table` — reads criterion's results under `target/criterion` and
//!   prints the median of every `<op>/<pair>/generic` benchmark beside its
//!   `<op>/<pair>/hand` twin with the ratio (run `cargo bench -p geopid-lie` first).
//! * `features` — checks that `lie` builds in every feature combination the
//!   README promises: each backend alone, both, and `no_std` with `libm`.
//!
//! * `conservation [--steps N]` — the free-body invariant table (energy and
//!   orthogonality after 10⁵ and N steps, every stepper, f32 and f64).
//!
//! * `run <scene>` — runs a built-in scene or a scene file, prints a summary,
//!   writes CSV, MCAP and SVG plots on request (`cargo xtask run --help`).
//! * `regress [--quick]` — every built-in scene against its expectations.
//! * `montecarlo` — converged fraction and time to converge over random
//!   initial conditions (threads, shards, `merge`, `near-pi`).
//! * `stress [--quick]` — numerical stress cases against written bounds
//!   (long horizon, free body, step limits, high rates, f32 vs f64, a NaN
//!   injected mid-run with the logs read back).
//! * `sweep [scene]` — run time against error, every stepper (work-precision).
//! * `gains <scene>` — the conditions of Propositions 2 and 3 for a scene's
//!   gains, with bounds from the scene; `--synthesize` searches for gains
//!   that meet them within a thrust limit.

mod bench;
mod conservation;
mod estimation;
mod missions;
mod regress;
mod sensing;
mod stress;

use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode};

use clap::{Parser, Subcommand};

/// Developer tasks of the geometric-pid workspace.
#[derive(Parser)]
#[command(name = "cargo xtask", version, about)]
struct Cli {
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// The `geopid` command's subcommands (run, scenes, gains, montecarlo,
    /// tune, sweep), from the same code.
    #[command(flatten)]
    User(geopid_cli::Command),
    /// Run every built-in scene and check its metrics against the committed
    /// expectations.
    Regress(regress::RegressArgs),
    /// Numerical stress cases, each against a bound with its reason:
    /// long horizon, free body 10⁴ s, step-size limits, high rates, f32 vs
    /// f64, a NaN injected mid-run (--quick: under two minutes).
    Stress(stress::StressArgs),
    /// Criterion benches (controller update, closed-loop step) against
    /// hand-written twins, and work-precision on every pair; writes
    /// target/bench/{summary.csv, work_precision.csv, work_precision.svg,
    /// bench.mcap}.
    Bench(bench::BenchArgs),
    /// Flying on measurements: RMS position error against the motion
    /// capture's latency and the sensors' noise, hover and figure eight
    /// (--quick: 4 seeds, 5 s runs).
    Sensing(sensing::SensingArgs),
    /// The filters in closed loop: the invariant EKF's NEES/NIS over 100
    /// seeds, each filter's error against the truth-fed run, recovery from
    /// 90° and 170° (--quick: 10 seeds, 10 s runs).
    Estimation(estimation::EstimationArgs),
    /// What the exact Ω_c, Ω̇_c buy: the climbing square flown with them
    /// and with differences of the commanded attitude.
    Missions(missions::MissionsArgs),
    /// Table of the last `cargo bench -p geopid-lie` run: generic vs hand-written.
    BenchTable,
    /// Build `lie` in every feature combination.
    Features,
    /// Free-body invariants after 1e5 and N steps, every stepper, f32/f64.
    Conservation {
        /// Number of steps (≥ 100000).
        #[arg(long, default_value_t = 1_000_000)]
        steps: usize,
    },
}

fn main() -> ExitCode {
    // Before any of this build's instructions can fault: a binary built with
    // the machine's instruction set (this workspace's default) and copied to
    // an older CPU stops here with the features it lacks named.
    if let Err(e) = lie::cpu::check() {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    geopid_cli::set_program("cargo xtask");
    let cli = Cli::parse();
    let result = match cli.command {
        Cmd::User(c) => return geopid_cli::exit_code(c.execute()),
        Cmd::Regress(a) => regress::regress(a),
        Cmd::Stress(a) => stress::stress(a),
        Cmd::Bench(a) => bench::bench(a),
        Cmd::Sensing(a) => sensing::sensing(a),
        Cmd::Estimation(a) => estimation::estimation(a),
        Cmd::Missions(a) => missions::missions(a),
        Cmd::BenchTable => bench_table(),
        Cmd::Features => features(),
        Cmd::Conservation { steps } => conservation::conservation(steps),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .expect("xtask sits in the workspace")
        .to_path_buf()
}

/// Every `new/benchmark.json` + `new/estimates.json` pair under `dir`:
/// the id and the median time per operation, ns.
fn collect(dir: &Path, out: &mut Vec<(String, f64)>) -> Result<(), String> {
    let entries =
        std::fs::read_dir(dir).map_err(|e| format!("cannot read {}: {e}", dir.display()))?;
    for entry in entries.flatten() {
        let path = entry.path();
        if !path.is_dir() {
            continue;
        }
        if path.file_name().is_some_and(|n| n == "new") {
            let bench = path.join("benchmark.json");
            let est = path.join("estimates.json");
            if bench.exists() && est.exists() {
                let read = |p: &Path| -> Result<serde_json::Value, String> {
                    let text =
                        std::fs::read_to_string(p).map_err(|e| format!("{}: {e}", p.display()))?;
                    serde_json::from_str(&text).map_err(|e| format!("{}: {e}", p.display()))
                };
                let meta = read(&bench)?;
                let id = meta["full_id"].as_str().unwrap_or_default().to_string();
                let median = read(&est)?["median"]["point_estimate"]
                    .as_f64()
                    .ok_or_else(|| format!("{}: no median.point_estimate", est.display()))?;
                // A benchmark over a batch says how many operations one
                // iteration is; the tables are per operation.
                let per = meta["throughput"]["Elements"].as_f64().unwrap_or(1.0);
                out.push((id, median / per));
            }
        } else {
            collect(&path, out)?;
        }
    }
    Ok(())
}

fn bench_table() -> Result<(), String> {
    let root = std::env::var_os("CRITERION_HOME")
        .map(PathBuf::from)
        .or_else(|| {
            std::env::var_os("CARGO_TARGET_DIR").map(|t| PathBuf::from(t).join("criterion"))
        })
        .unwrap_or_else(|| workspace_root().join("target").join("criterion"));
    if !root.exists() {
        return Err(format!(
            "{} does not exist: run `cargo bench -p geopid-lie` first",
            root.display()
        ));
    }
    let mut rows = Vec::new();
    collect(&root, &mut rows)?;
    let _ = bench::lie_table(&rows, false);
    let _ = bench::lie_table(&rows, true);
    Ok(())
}

fn features() -> Result<(), String> {
    let combos: [&[&str]; 5] = [
        &["--no-default-features", "--features", "std,glam"],
        &["--no-default-features", "--features", "std,nalgebra"],
        &["--no-default-features", "--features", "glam,libm"],
        &["--no-default-features", "--features", "nalgebra,libm"],
        &["--no-default-features", "--features", "glam,nalgebra,libm"],
    ];
    for combo in combos {
        println!("cargo build -p geopid-lie {}", combo.join(" "));
        let status = Command::new(env!("CARGO"))
            .args(["build", "-p", "geopid-lie"])
            .args(combo)
            .current_dir(workspace_root())
            .status()
            .map_err(|e| format!("cannot run cargo: {e}"))?;
        if !status.success() {
            return Err(format!(
                "`cargo build -p geopid-lie {}` failed",
                combo.join(" ")
            ));
        }
    }
    println!("all {} feature combinations build", combos.len());
    Ok(())
}
