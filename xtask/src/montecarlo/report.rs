//! The summary of a Monte Carlo run: `summary.json` and what is printed.

use scenarios::montecarlo::{DIVERGED_OMEGA, DIVERGED_X, MAX_SUBSTEPS, Outcome, Setup, Summary};

use super::flags;

/// The summary of a complete run (all indices present).
pub fn summarize(setup: &Setup, rows: &[Outcome], wall: Option<f64>) -> serde_json::Value {
    let n = rows.len();
    let sum = Summary::from_rows(rows.iter().map(|r| (r.status, r.t_converge, r.steps)));
    let steps = sum.integrator_steps;
    let mut slow: Vec<&Outcome> = rows.iter().collect();
    // Not converged first, then by time to converge, slowest first.
    slow.sort_by(|a, b| {
        b.converged
            .cmp(&a.converged)
            .reverse()
            .then(b.t_converge.total_cmp(&a.t_converge))
            .then(a.index.cmp(&b.index))
    });
    let slowest: Vec<serde_json::Value> = slow
        .iter()
        .take(5)
        .map(|r| {
            serde_json::json!({
                "index": r.index, "converged": r.converged, "status": r.status.name(), "t_converge": r.t_converge,
                "angle_deg": r.angle.to_degrees(), "axis": r.axis, "omega0": r.omega0, "ex0": r.ex0,
                "command": format!("cargo xtask montecarlo {} --index {}", flags(setup), r.index),
            })
        })
        .collect();
    let mut v = serde_json::json!({
        "setup": setup,
        "samples": n,
        "converged": sum.converged,
        "deadline": sum.deadline,
        "diverged": sum.diverged,
        "errors": sum.errors,
        "converged_fraction": sum.converged_fraction,
        "t_converge": sum.t_converge,
        "largest_angle_deg": rows.iter().map(|r| r.angle).fold(0.0, f64::max).to_degrees(),
        "max_rotor_thrust": rows.iter().map(|r| r.max_rotor).fold(0.0, f64::max),
        "integrator_steps": steps,
        "slowest": slowest,
    });
    if let Some(w) = wall {
        v["wall_s"] = serde_json::json!(w);
        v["samples_per_s"] = serde_json::json!(n as f64 / w);
        v["ns_per_step"] = serde_json::json!(w * 1e9 / steps.max(1) as f64);
    }
    v
}

pub fn print_summary(s: &serde_json::Value) {
    let f = |p: &str| s.pointer(p).and_then(|v| v.as_f64()).unwrap_or(f64::NAN);
    println!(
        "{} samples, {} converged ({:.4} %); largest initial angle {:.3}°",
        s["samples"],
        s["converged"],
        100.0 * f("/converged_fraction"),
        f("/largest_angle_deg"),
    );
    println!(
        "not converged: {} at the deadline, {} diverged (|Ω| > {DIVERGED_OMEGA} rad/s, ‖e_x‖ > {DIVERGED_X} m, or more than {MAX_SUBSTEPS} substeps in one dopri call), {} integrator errors",
        s["deadline"], s["diverged"], s["errors"]
    );
    println!(
        "time to converge: median {:.3} s, 95th {:.3} s, 99th {:.3} s, worst {:.3} s",
        f("/t_converge/median"),
        f("/t_converge/p95"),
        f("/t_converge/p99"),
        f("/t_converge/worst")
    );
    if let Some(w) = s.get("wall_s").and_then(|v| v.as_f64()) {
        println!(
            "wall {w:.2} s: {:.0} samples/s, {:.0} ns per integrator step ({} steps)",
            f("/samples_per_s"),
            f("/ns_per_step"),
            s["integrator_steps"]
        );
    }
    println!("slowest samples:");
    for r in s["slowest"].as_array().into_iter().flatten() {
        println!(
            "  #{:<6} {}, t = {:.3} s, from {:.2}° (axis {:.3?}), |Ω(0)| = {:.3}, ‖e_x(0)‖ = {:.3}\n          {}",
            r["index"],
            r["status"].as_str().unwrap_or("?"),
            r["t_converge"].as_f64().unwrap_or(f64::NAN),
            r["angle_deg"].as_f64().unwrap_or(f64::NAN),
            r["axis"]
                .as_array()
                .map(|a| a.iter().filter_map(|x| x.as_f64()).collect::<Vec<_>>())
                .unwrap_or_default(),
            r["omega0"].as_f64().unwrap_or(f64::NAN),
            r["ex0"].as_f64().unwrap_or(f64::NAN),
            r["command"].as_str().unwrap_or(""),
        );
    }
}
