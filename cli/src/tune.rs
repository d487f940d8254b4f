//! `geopid tune`: k_x, k_v, k_R and k_Ω tuned on the exact gradient of
//! a scene's tracking cost (`studies::sensitivity::tune_gains`), each
//! iteration printed, the tuned scene written.

use std::path::PathBuf;

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
    /// Write the tuned scene here (TOML).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// `geopid tune`. The cost is sampled at the scene's record interval.
pub fn tune(a: TuneArgs) -> Result<(), String> {
    let scene = scenes::load(&a.scene).map_err(|e| e.to_string())?;
    let weight = scene.vehicle.mass * scene.vehicle.gravity;
    let spec = GainTuning {
        factor: a.factor,
        every: scene.record.sample,
        max_gradients: a.gradients,
        max_thrust: (a.thrust_to_weight > 0.0).then_some(a.thrust_to_weight * weight),
    };
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
    if let Some(path) = &a.out {
        std::fs::write(path, out.scene.to_toml())
            .map_err(|e| format!("{}: {e}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
