//! `cargo xtask stress [--quick]`: the numerical stress suite
//! (`studies::stress`), each figure printed beside its bound and the
//! bound's reason, PASS or FAIL, and `stress.csv`.
//!
//! Cases: long horizon (hover under Δ at 1 kHz, every stepper, f32 and
//! f64), the free rigid body for 10⁴ s (energy and momentum drift), the
//! step-size limit of every stepper on paper-flip and what happens just past
//! it, high rates (a body spinning at 100 rad/s against the exact solution,
//! a fast attitude command against a tight reference), f32 against f64 on
//! every built-in scene, and a non-finite reference injected mid-run with
//! the CSV and MCAP read back. `--quick` shortens the horizons (CI).

use std::path::PathBuf;
use std::time::Instant;

use clap::Args;
use studies::stress::{Check, Event};

/// Options of `cargo xtask stress`.
#[derive(Args)]
pub struct StressArgs {
    /// Short horizons (a minute of hover instead of an hour, 10³ s of free
    /// body instead of 10⁴): under two minutes, what CI runs.
    #[arg(long)]
    quick: bool,
    /// Only the cases whose name contains this (long-horizon, free-body,
    /// step-limit, high-rate, f32-vs-f64, non-finite).
    #[arg(long)]
    only: Option<String>,
    /// The long-horizon case's simulated time, s (default 3600, 60 with
    /// `--quick`).
    #[arg(long)]
    horizon: Option<f64>,
    /// Directory for `stress.csv` and the injected run's CSV/MCAP.
    #[arg(long, default_value = "target/stress")]
    out: PathBuf,
}

/// Prints what the suite reports, with each case's time.
fn print(e: Event<'_>, case_start: &mut Option<Instant>) {
    match e {
        Event::Case(name) => {
            if let Some(t) = case_start.take() {
                println!("   ({:.1} s)", t.elapsed().as_secs_f64());
            }
            println!("== {name}");
            *case_start = Some(Instant::now());
        }
        Event::Check(c) => {
            let verdict = if c.pass { "PASS" } else { "FAIL" };
            if c.value.is_finite() && c.bound == 1.0 && (c.value == 0.0 || c.value == 1.0) {
                println!("  {verdict} {} ({})", c.what, c.reason);
            } else {
                println!(
                    "  {verdict} {}: {:.3e} (bound {:.1e}: {})",
                    c.what, c.value, c.bound, c.reason
                );
            }
        }
        Event::Note(s) => println!("{s}"),
    }
}

pub fn stress(a: StressArgs) -> Result<(), String> {
    std::fs::create_dir_all(&a.out).map_err(|e| format!("{}: {e}", a.out.display()))?;
    let start = Instant::now();
    if let Some(h) = a.horizon
        && !(h.is_finite() && h >= 1.0)
    {
        return Err(format!("--horizon {h}: must be finite and ≥ 1 s"));
    }
    let want = |name: &str| a.only.as_deref().is_none_or(|o| name.contains(o));
    let mut case_start = None;
    let checks = studies::stress::cases(a.quick, &want, a.horizon, &a.out, &mut |e| {
        print(e, &mut case_start)
    })
    .map_err(|e| e.to_string())?;
    if let Some(t) = case_start {
        println!("   ({:.1} s)", t.elapsed().as_secs_f64());
    }
    let mut csv = String::from("case,what,value,bound,pass,reason\n");
    for c in &checks {
        csv.push_str(&format!(
            "{},\"{}\",{:e},{:e},{},\"{}\"\n",
            c.case, c.what, c.value, c.bound, c.pass, c.reason
        ));
    }
    let path = a.out.join("stress.csv");
    std::fs::write(&path, csv).map_err(|e| format!("{}: {e}", path.display()))?;
    let failed: Vec<&Check> = checks.iter().filter(|c| !c.pass).collect();
    println!(
        "stress{}: {} checks, {} failed, {:.1} s; table in {}",
        if a.quick { " --quick" } else { "" },
        checks.len(),
        failed.len(),
        start.elapsed().as_secs_f64(),
        path.display()
    );
    if failed.is_empty() {
        Ok(())
    } else {
        for c in &failed {
            println!("  FAILED {}: {}", c.case, c.what);
        }
        Err(format!("{} stress checks failed", failed.len()))
    }
}
