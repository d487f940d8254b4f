//! `cargo xtask missions`: the built-in `waypoints-square-climb` flown
//! under sampled control with the position law's exact `Ω_c`, `Ω̇_c` and
//! with backward differences of `R_c`, at 100 and 500 Hz, with the
//! paper's disturbances and without. `--report PATH` writes the table as
//! Markdown with the command that made it.

use std::path::PathBuf;

/// Options of `cargo xtask missions`.
#[derive(clap::Args)]
pub struct MissionsArgs {
    /// Write the table as Markdown here.
    #[arg(long, value_name = "PATH")]
    report: Option<PathBuf>,
}

pub fn missions(a: MissionsArgs) -> Result<(), String> {
    let scene = scenes::builtin::waypoints_square_climb();
    let t = studies::missions::table(&scene, &[100.0, 500.0]).map_err(|e| e.to_string())?;
    println!("{t}");
    if let Some(p) = a.report {
        let md = format!(
            "## Exact derivatives against differences\n\n`waypoints-square-climb` (11 s, RK4 at \
             1 ms) under sampled control: position error ‖x − x_d‖ over the recorded samples \
             (every 10 ms), with the law's `Ω_c`, `Ω̇_c` and with backward differences of `R_c` \
             between control instants; ratio = differences / exact. Written by `cargo xtask \
             missions --report`.\n\n{t}"
        );
        std::fs::write(&p, md).map_err(|e| format!("writing {}: {e}", p.display()))?;
        println!("wrote {}", p.display());
    }
    Ok(())
}
