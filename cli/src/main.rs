//! `geopid`: the command line of the geometric PID workspace.

use clap::Parser;
use std::process::ExitCode;

/// Geometric PID control on SO(3) and SE(3): run scenes, check and tune
/// gains, Monte Carlo studies, work-precision sweeps.
#[derive(Parser)]
#[command(name = "geopid", version, about)]
struct Cli {
    #[command(subcommand)]
    command: geopid_cli::Command,
}

fn main() -> ExitCode {
    // First of all: a binary built for a newer CPU than this one stops
    // here, naming the features it lacks, instead of faulting later.
    if let Err(e) = lie::cpu::check() {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    geopid_cli::exit_code(Cli::parse().command.execute())
}
