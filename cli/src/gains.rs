//! `geopid gains`: the conditions of Propositions 2 and 3 for a
//! scene's gains, with the bounds taken from the scene, and a search for
//! gains that provably meet them (`--synthesize`).
//!
//! The bounds, the checker and the search are `studies::gains`; this is
//! their command line: arguments, the report as text and JSON.

use std::path::PathBuf;
use std::time::Instant;

use controllers::GainReport;
use scenes::Scene;
use scenes::scene::GainsSpec;
use serde_json::json;
use studies::gains::{CONDITIONS, NAMES, SceneBounds, Synthesis, report, scene_bounds};

/// Options of `geopid gains`.
#[derive(clap::Args, Debug)]
pub struct GainsArgs {
    /// Built-in scene name or TOML scene file.
    pub scene: String,
    /// ψ1 < 1: the bound on the initial attitude error (eqn:Psi0).
    #[arg(long, default_value_t = 0.05)]
    pub psi1: f64,
    /// e_xmax, m: the bound on the initial position error (eqn:ex0).
    #[arg(long, default_value_t = 1.0)]
    pub ex_max: f64,
    /// Write the report as JSON.
    #[arg(long, value_name = "FILE")]
    pub json: Option<PathBuf>,
    /// Exit 1 when a condition fails.
    #[arg(long)]
    pub require: bool,
    /// Use the gains of a JSON report (its `gains` object) instead of the
    /// scene's.
    #[arg(long, value_name = "FILE")]
    pub gains: Option<PathBuf>,
    /// Search for gains that meet every condition (see the module docs).
    #[arg(long)]
    pub synthesize: bool,
    /// Synthesis: largest rotor thrust allowed over the scene, N (default:
    /// the scene's peak with its own gains).
    #[arg(long)]
    pub thrust_limit: Option<f64>,
    /// Synthesis: objective evaluations in each phase.
    #[arg(long, default_value_t = 3000)]
    pub evaluations: usize,
}

fn num(x: f64) -> serde_json::Value {
    if x.is_finite() {
        json!(x)
    } else {
        serde_json::Value::Null
    }
}

fn gains_json(g: &GainsSpec) -> serde_json::Value {
    serde_json::to_value(g).unwrap_or_default()
}

fn report_json(g: &GainsSpec, sb: &SceneBounds, r: &GainReport) -> serde_json::Value {
    let b = &sb.bounds;
    json!({
        "gains": gains_json(g),
        "bounds": {"b1": b.b1, "b2": b.b2, "delta_x": b.delta_x, "psi1": b.psi1,
                   "e_x_max": b.e_x_max, "max_omega_d": sb.max_omega_d, "norm_2j_minus_trj": sb.j_norm},
        "conditions": r.conditions.iter().map(|c| json!({
            "name": c.label, "statement": c.statement, "value": num(c.value),
            "bound": num(c.bound), "holds": c.holds, "margin": num(c.margin)})).collect::<Vec<_>>(),
        "lambda_min_w1": r.lambda_min_w1,
        "alpha": r.alpha,
        "time_constants": {"attitude": num(r.attitude_time_constant), "position": num(r.position_time_constant)},
        "all_hold": r.all_hold(),
    })
}

fn print_bounds(sb: &SceneBounds) {
    let b = &sb.bounds;
    println!(
        "bounds: B1 = {:.5} N, B2 = {:.5} (‖2J − tr J·I‖ = {:.5} × max‖Ω_d‖ = {:.5} rad/s), δ_x = {:.5} N, ψ1 = {}, e_xmax = {} m ({} samples)",
        b.b1, b.b2, sb.j_norm, sb.max_omega_d, b.delta_x, b.psi1, b.e_x_max, sb.samples
    );
}

/// The scene's gains with the keys of a report's `gains` object laid over
/// them (an unknown key or a wrong type is an error naming it; the values
/// are checked with the scene).
fn read_gains(path: &PathBuf, base: &GainsSpec) -> Result<GainsSpec, String> {
    let at = |e: &dyn std::fmt::Display| format!("{}: {e}", path.display());
    let text = std::fs::read_to_string(path).map_err(|e| at(&e))?;
    let v: serde_json::Value = serde_json::from_str(&text).map_err(|e| at(&e))?;
    let Some(serde_json::Value::Object(given)) = v.get("gains") else {
        return Err(at(&"no `gains` object"));
    };
    let mut merged = gains_json(base);
    for (k, x) in given {
        merged[k] = x.clone();
    }
    serde_json::from_value(merged).map_err(|e| at(&format_args!("`gains`: {e}")))
}

/// `geopid gains`.
pub fn gains(a: GainsArgs) -> Result<(), String> {
    if !(a.psi1 > 0.0 && a.psi1 < 1.0) {
        return Err(format!("--psi1 {}: must be in (0, 1)", a.psi1));
    }
    if !(a.ex_max.is_finite() && a.ex_max > 0.0) {
        return Err(format!("--ex-max {}: must be finite and > 0", a.ex_max));
    }
    let mut scene = scenes::load(&a.scene).map_err(|e| e.to_string())?;
    if let Some(p) = &a.gains {
        scene.gains = read_gains(p, &scene.gains)?;
        scene
            .validate()
            .map_err(|(_, why)| format!("{}: {why}", p.display()))?;
    }
    let sb = scene_bounds(&scene, a.psi1, a.ex_max).map_err(|e| e.to_string())?;
    if a.synthesize {
        return synthesize(&scene, &sb, &a);
    }
    let r = report(&scene, &scene.gains, &sb.bounds).map_err(|e| e.to_string())?;
    println!("{}: gains {}", scene.name, gains_json(&scene.gains));
    print_bounds(&sb);
    println!("{r}");
    println!(
        "λm(W1) = {:.5} ({})",
        r.lambda_min_w1,
        if r.lambda_min_w1 > 0.0 {
            "positive: (eqn:kRkWb) has a finite bound"
        } else {
            "not positive: (eqn:kRkWb) cannot hold until (eqn:c1b) does"
        }
    );
    println!(
        "verdict: {}",
        if r.all_hold() {
            "every condition of Propositions 2 and 3 holds"
        } else {
            "some conditions fail (they are sufficient, not necessary: the loop may still converge)"
        }
    );
    if let Some(p) = &a.json {
        write_json(p, &report_json(&scene.gains, &sb, &r))?;
    }
    if a.require && !r.all_hold() {
        return Err("--require: a condition fails".into());
    }
    Ok(())
}

fn write_json(path: &PathBuf, v: &serde_json::Value) -> Result<(), String> {
    let text = serde_json::to_string_pretty(v).map_err(|e| e.to_string())?;
    std::fs::write(path, text + "\n").map_err(|e| format!("{}: {e}", path.display()))?;
    println!("wrote {}", path.display());
    Ok(())
}

fn flight_row(name: &str, out: &scenarios::RunOutput, peak: f64) -> String {
    let at = |t: f64| {
        studies::metrics::at(&out.samples, t)
            .map_or("—".into(), |s| format!("{:.3e} / {:.3e}", s.psi, s.ex))
    };
    // The time after which Ψ stays below 1e-3.
    let settle = out
        .samples
        .iter()
        .rposition(|s| s.psi >= 1e-3)
        .map_or(Some(0.0), |k| out.samples.get(k + 1).map(|s| s.t));
    format!(
        "| {name} | {} | {} | {} | {peak:.2} | {} |",
        at(1.0),
        at(2.0),
        at(4.0),
        settle.map_or(format!("> {} s", out.last.t), |t| format!("{t:.2} s"))
    )
}

fn synthesize(scene: &Scene, sb: &SceneBounds, a: &GainsArgs) -> Result<(), String> {
    let start = Instant::now();
    print_bounds(sb);
    let s = studies::gains::synthesize(scene, sb, a.thrust_limit, a.evaluations)
        .map_err(|e| e.to_string())?;
    println!(
        "rotor thrust limit {:.3} N ({}); searching {} gains in log space",
        s.thrust_limit,
        if a.thrust_limit.is_some() {
            "--thrust-limit"
        } else {
            "the scene's peak with its own gains"
        },
        NAMES.join(", ")
    );
    let (free, free_score, free_peak) = &s.free;
    println!(
        "without a thrust limit: {}",
        if *free_score > 0.0 {
            format!(
                "nearest certified gains {}, peak rotor thrust {}",
                gains_json(free),
                free_peak.map_or("— (too stiff to fly: step < 1 µs)".into(), |p| format!(
                    "{p:.1} N"
                ))
            )
        } else {
            format!("no certified gains found (best worst log margin {free_score:.3})")
        }
    );
    let r = &s.report;
    println!("{r}");
    let verdict = verdict(&s);
    println!("verdict: {verdict}");
    println!("gains: {}", gains_json(&s.gains));
    println!(
        "| gains | Ψ / ‖e_x‖ at 1 s | at 2 s | at 4 s | peak rotor thrust (N) | Ψ < 1e-3 from |"
    );
    println!("|---|---|---|---|---|---|");
    println!("{}", flight_row("scene's own", &s.own.1, s.own.0));
    match &s.flown {
        Some((p, out)) => println!("{}", flight_row("synthesized", out, *p)),
        None => println!("| synthesized | diverged | | | | |"),
    }
    let own = report(scene, &scene.gains, &sb.bounds).map_err(|e| e.to_string())?;
    println!(
        "time constants: own {:.3} s / {:.3} s, synthesized {:.3} s / {:.3} s (attitude / position); search {:.1} s",
        own.attitude_time_constant,
        own.position_time_constant,
        r.attitude_time_constant,
        r.position_time_constant,
        start.elapsed().as_secs_f64()
    );
    if let Some(p) = &a.json {
        let mut v = report_json(&s.gains, sb, r);
        v["synthesis"] = json!({
            "certified": s.certified,
            "verdict": verdict,
            "thrust_limit": s.thrust_limit,
            "peak_rotor_thrust": s.flown.as_ref().map(|x| x.0),
            "binding": CONDITIONS[s.binding],
            "best_log_margin": s.best_log_margin,
            "without_thrust_limit": {"worst_log_margin": free_score, "peak_rotor_thrust": free_peak,
                                      "gains": gains_json(free)},
            "seconds": start.elapsed().as_secs_f64(),
        });
        write_json(p, &v)?;
    }
    Ok(())
}

/// One line: certified, or which condition binds and by how much.
fn verdict(s: &Synthesis) -> String {
    if s.certified {
        "certified: every condition of Propositions 2 and 3 holds".to_string()
    } else {
        format!(
            "infeasible within the thrust limit: {} binds; best worst log margin {:.4} (λm(W1) = {:.4}, peak rotor thrust {})",
            CONDITIONS[s.binding],
            s.best_log_margin,
            s.lambda_min_w1,
            s.phase1_peak.map_or("—".into(), |p| format!("{p:.2} N"))
        )
    }
}
