//! `cargo xtask regress [--quick]`: the regression suite
//! (`studies::regress`) as a table, each scene's main run logged to
//! `target/regress/<scene>.mcap`.

use std::path::PathBuf;

use scenarios::RunOutput;

use scenes::Scene;

#[derive(clap::Args, Debug)]
pub struct RegressArgs {
    /// Run the subset CI runs (every scene but the two long ones).
    #[arg(long)]
    pub quick: bool,
}

pub fn regress(a: RegressArgs) -> Result<(), String> {
    let start = std::time::Instant::now();
    let dir = PathBuf::from("target/regress");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let mut logged = Ok(());
    let mut log = |scene: &Scene, out: &RunOutput| {
        let path = dir.join(format!("{}.mcap", scene.name));
        if let Err(e) = logs::write_mcap(&path, out) {
            logged = Err(format!("{}: {e}", path.display()));
        }
    };
    let checks = studies::regress::checks(a.quick, &mut log).map_err(|e| e.to_string())?;
    logged?;
    println!("| scene | metric | value | expected | tolerance | ok |");
    println!("|---|---|---|---|---|---|");
    let mut failed = 0;
    for r in &checks {
        let ok = r.ok();
        if !ok {
            failed += 1;
        }
        let expected = if r.two_sided {
            format!("{:.10e}", r.expected)
        } else {
            "≤ tolerance".to_string()
        };
        println!(
            "| {} | {} | {:.10e} | {} | {:.1e} | {} |",
            r.scene,
            r.metric,
            r.value,
            expected,
            r.tol,
            if ok { "ok" } else { "FAIL" }
        );
    }
    println!();
    for r in checks.iter().filter(|r| !r.ok()) {
        println!(
            "FAIL {} / {}: tolerance because {}",
            r.scene, r.metric, r.why
        );
    }
    println!(
        "{} checks, {} failed, {:.1} s{}; MCAP logs in target/regress/",
        checks.len(),
        failed,
        start.elapsed().as_secs_f64(),
        if a.quick { " (--quick)" } else { "" }
    );
    if failed > 0 {
        Err(format!("{failed} regression checks failed"))
    } else {
        Ok(())
    }
}
