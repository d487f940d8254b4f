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
    // Before any of this build's instructions can fault: a binary built with
    // the machine's instruction set and copied to an older CPU stops here
    // with the features it lacks named.
    if let Err(e) = lie::cpu::check() {
        eprintln!("error: {e}");
        return ExitCode::from(2);
    }
    geopid_cli::exit_code(Cli::parse().command.execute())
}
