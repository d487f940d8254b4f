//! How much the integral terms buy in wind: the crazyflie (RotorPy's
//! model: rotor drag and inflow, 72 ms motors) in `gusty-hover` (Dryden
//! turbulence, σ = 1 m/s) and `figure-eight-wind` (3 m/s mean wind plus
//! the same gusts), each with and without the integral terms and with
//! the motors' 72 ms lag or none, 20 s each. Prints a Markdown table: RMS
//! and max ‖e_x‖ and Ψ over the run after the first 2 s (the start-up
//! transient), and the peak rotor speed.
//!
//! `cargo run --release -p geopid --example wind_table`

use scenarios::RunOptions;
use scenes::scene::VehicleKind;
use scenes::{Overrides, Scene};

/// `(rms ‖e_x‖, max ‖e_x‖, rms Ψ, max Ψ, peak rotor speed)`.
fn figures(scene: &Scene) -> Result<[f64; 5], Box<dyn std::error::Error>> {
    let out = scenes::run(scene, RunOptions::default())?;
    let spec = scene.vehicle.multirotor.clone().unwrap_or_default();
    let k_eta = spec.k_eta.unwrap_or(2.3e-8);
    let tail: Vec<_> = out.samples.iter().filter(|s| s.t >= 2.0).collect();
    let n = tail.len().max(1) as f64;
    let rms = |f: &dyn Fn(&scenarios::Sample) -> f64| {
        (tail.iter().map(|s| f(s).powi(2)).sum::<f64>() / n).sqrt()
    };
    let max = |f: &dyn Fn(&scenarios::Sample) -> f64| tail.iter().map(|s| f(s)).fold(0.0, f64::max);
    // Rotor speeds are the vehicle's states with a motor lag; without one
    // they follow the commanded thrusts, ω = √(f/k_η).
    let peak = out
        .samples
        .iter()
        .flat_map(|s| {
            if s.vehicle_states.is_empty() {
                s.rotors
                    .iter()
                    .map(|f| (f.max(0.0) / k_eta).sqrt())
                    .collect::<Vec<_>>()
            } else {
                s.vehicle_states.clone()
            }
        })
        .fold(0.0, f64::max);
    Ok([
        rms(&|s| s.ex),
        max(&|s| s.ex),
        rms(&|s| s.psi),
        max(&|s| s.psi),
        peak,
    ])
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!(
        "| scene | integral terms | τ_m | RMS ‖e_x‖ (m) | max ‖e_x‖ (m) | RMS Ψ | max Ψ | peak rotor speed (rad/s) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for name in ["gusty-hover", "figure-eight-wind"] {
        for tau_m in [0.072, 0.0] {
            for integral in [true, false] {
                let mut scene = Overrides {
                    no_integral: !integral,
                    ..Default::default()
                }
                .apply(scenes::load(name)?)?;
                assert_eq!(scene.vehicle.kind, VehicleKind::Multirotor);
                if let Some(m) = scene.vehicle.multirotor.as_mut() {
                    m.tau_m = Some(tau_m);
                }
                let [rx, mx, rp, mp, w] = figures(&scene)?;
                println!(
                    "| {name} | {} | {} ms | {rx:.4} | {mx:.4} | {rp:.2e} | {mp:.2e} | {w:.0} |",
                    if integral { "on" } else { "off" },
                    tau_m * 1e3
                );
            }
        }
    }
    Ok(())
}
