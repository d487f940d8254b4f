//! `geopid tune`: k_x, k_v, k_R and k_Ω tuned on the exact gradient of
//! a scene's tracking cost (`studies::sensitivity::tune_gains`), each
//! iteration printed, the tuned scene written; with `--noise-seeds N`,
//! the cost averaged over N noise realisations and the result checked on
//! held-out seeds (`studies::held_out`).

use std::path::PathBuf;

use studies::held_out::{held_out_seeds, held_out_tracking};
use studies::sensitivity::{GainTuning, tune_gains};

/// Options of `geopid tune`.
#[derive(clap::Args, Debug)]
pub struct TuneArgs {
    /// Scene (built-in name or TOML file) with a position segment.
    #[arg(default_value = "difftune-circle")]
    pub scene: String,
    /// Each gain stays within [g₀/F, g₀·F] of its starting value g₀.
    #[arg(long, default_value_t = 10.0)]
    pub factor: f64,
    /// The thrust limit as a multiple of the weight m g (0: no limit).
    #[arg(long, default_value_t = 2.0)]
    pub thrust_to_weight: f64,
    /// Gradient evaluations at most.
    #[arg(long, default_value_t = 20)]
    pub gradients: usize,
    /// Average the cost and its gradient over this many noise
    /// realisations (the scene's seed, seed + 1, …); 0: the scene's seed
    /// alone, and no held-out check.
    #[arg(long, default_value_t = 0)]
    pub noise_seeds: usize,
    /// With --noise-seeds: fly the starting and the tuned gains on this
    /// many seeds the tuning never saw, and report the paired 95 %
    /// interval of the cost's difference.
    #[arg(long, default_value_t = 20)]
    pub held_out: usize,
    /// Fly this many seconds of the scene instead of its duration.
    #[arg(long)]
    pub duration: Option<f64>,
    /// Write the tuned scene here (TOML).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// `geopid tune`. The cost is sampled at the scene's record interval.
pub fn tune(a: TuneArgs) -> Result<(), String> {
    let mut scene = scenes::load(&a.scene).map_err(|e| e.to_string())?;
    if let Some(d) = a.duration {
        if !(d.is_finite() && d > 0.0) {
            return Err(format!(
                "--duration {d}: must be a positive number of seconds"
            ));
        }
        scene.duration = d;
    }
    let weight = scene.vehicle.mass * scene.vehicle.gravity;
    let spec = GainTuning {
        factor: a.factor,
        every: scene.record.sample,
        max_gradients: a.gradients,
        max_thrust: (a.thrust_to_weight > 0.0).then_some(a.thrust_to_weight * weight),
        noise_seeds: a.noise_seeds,
    };
    if a.noise_seeds > 0 {
        println!(
            "the cost and its gradient averaged over {} noise seeds ({}..={})",
            a.noise_seeds,
            scene.seed,
            scene.seed.wrapping_add(a.noise_seeds as u64 - 1)
        );
    }
    let rmse = |cost: f64| (cost / scene.duration).sqrt();
    println!(
        "| gradient | RMS position error (m) | k_x | k_v | k_R | k_Ω | peak thrust (N) | line-search runs |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    let started = std::time::Instant::now();
    let reg = scenes::Registry::new();
    let out = tune_gains(&reg, &scene, &spec, &mut |s| {
        let [kx, kv, kr, kw] = s.values;
        println!(
            "| {} | {:.5} | {kx:.4} | {kv:.4} | {kr:.4} | {kw:.4} | {:.2} | {} |",
            s.iteration,
            rmse(s.cost),
            s.max_thrust,
            s.plain_runs
        );
    })
    .map_err(|e| e.to_string())?;
    let (first, last) = (rmse(out.history[0].cost), rmse(out.final_cost));
    println!(
        "{}: RMS position error {first:.5} m -> {last:.5} m ({:.2}x lower) in {} gradient evaluations, {:.1} s",
        scene.name,
        first / last,
        out.history.len(),
        started.elapsed().as_secs_f64()
    );
    if a.noise_seeds > 0 {
        report_held_out(&reg, &scene, &out.scene, a.held_out, spec.every)?;
    }
    if let Some(path) = &a.out {
        std::fs::write(path, out.scene.to_toml())
            .map_err(|e| format!("{}: {e}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// The starting and tuned gains on `count` held-out seeds: each one's RMS
/// position error and the paired 95 % interval of the cost's difference.
fn report_held_out(
    reg: &scenes::Registry,
    start: &scenes::Scene,
    tuned: &scenes::Scene,
    count: usize,
    every: f64,
) -> Result<(), String> {
    let seeds = held_out_seeds(start, count);
    let h = held_out_tracking(reg, start, tuned, &seeds, every).map_err(|e| e.to_string())?;
    let rmse = |c: &[f64]| {
        let mean = c.iter().sum::<f64>() / c.len() as f64;
        (mean / start.duration).sqrt()
    };
    let i = h.improvement;
    println!(
        "held out ({} seeds from {}): RMS position error {:.5} m with the starting gains, {:.5} m tuned; \
         cost lowered by {:.4e} per run, 95 % interval [{:.4e}, {:.4e}] ({})",
        seeds.len(),
        seeds[0],
        rmse(&h.start),
        rmse(&h.tuned),
        i.mean,
        i.low,
        i.high,
        if i.low > 0.0 {
            "above zero: lower on seeds the tuning never saw"
        } else if i.high < 0.0 {
            "below zero: higher on seeds the tuning never saw"
        } else {
            "includes zero: no difference shown"
        }
    );
    Ok(())
}
