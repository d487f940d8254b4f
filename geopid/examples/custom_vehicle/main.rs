//! A vehicle of one's own through the whole framework: a quadrotor with
//! first-order rotor lag (`lagged.rs`, written with public items only)
//! flies the paper's flip through the same plan, scheduler, event location
//! and MCAP log as the built-in vehicles, once through the `Simulation`
//! builder and once from a scene file that names it (`Registry`).
//!
//! Run: `cargo run -p geopid --example custom_vehicle`

mod lagged;

use dynamics::{Quadrotor, Vehicle};
use lagged::LaggedQuadrotor;
use lie::{Backend, NalgebraF64, Real};
use logs::write_mcap;
use scenarios::{RunOutput, Simulation};
use scenes::{FactoryError, Registry, Scene, VehicleFactory, builtin};
use studies::metrics::{at, max_difference};

type B = NalgebraF64;

/// The paper's flip with rotor lag `tau` and optional per-rotor limits.
fn flip(tau: f64, limits: Option<(f64, f64)>) -> Result<RunOutput, Box<dyn std::error::Error>> {
    let scene = builtin::paper_flip();
    let quad = Quadrotor::<B>::paper().with_disturbance(Quadrotor::<B>::paper_disturbance())?;
    let mut vehicle = LaggedQuadrotor::new(quad, tau)?;
    if let Some((lo, hi)) = limits {
        vehicle = vehicle.with_limits(lo, hi)?;
    }
    // The scene's plan (attitude-mode flip, then position mode) as modes
    // built for this vehicle; any other plan of `Segment`s works the same.
    let plan = scenes::plan::<B>(&scene, &vehicle);
    // Six integral states (e_I, e_i) and four rotor thrusts: the builder
    // counts them and sizes the state.
    let mut sim = Simulation::<B>::builder(Box::new(vehicle))
        .dt(scene.integrator.dt)
        .duration(scene.duration)
        .record_every(scene.record.sample);
    for segment in plan {
        sim = sim.segment(segment);
    }
    Ok(sim.build()?.run(Default::default())?)
}

/// Makes `lagged-quadrotor` a vehicle kind of scene files, with
/// `[vehicle.params] tau = …` (s).
struct Lagged;

impl VehicleFactory for Lagged {
    fn build<Bk: Backend>(&self, scene: &Scene) -> Result<Box<dyn Vehicle<Bk>>, FactoryError> {
        let (v, l) = (&scene.vehicle, Bk::Scalar::lit);
        let tau = v.params.get("tau").copied().unwrap_or(0.0);
        let j = lie::ops::diag::<Bk>(l(v.inertia[0]), l(v.inertia[1]), l(v.inertia[2]));
        let mut q = Quadrotor::<Bk>::new(l(v.mass), j, l(v.gravity), l(v.arm), l(v.c_tau_f))?;
        if let Some(d) = &scene.disturbance {
            let v3 = |a: [f64; 3]| Bk::vec3(l(a[0]), l(a[1]), l(a[2]));
            q = q.with_disturbance(dynamics::Disturbance {
                force: v3(d.force),
                moment: v3(d.moment),
            })?;
        }
        Ok(Box::new(LaggedQuadrotor::new(q, l(tau))?))
    }
}

fn row(name: &str, out: &RunOutput) {
    let cell = |t: f64| {
        at(&out.samples, t).map_or("—".to_string(), |s| format!("{:.4e} {:.4e}", s.psi, s.ex))
    };
    println!(
        "| {name} | {} | {} | {} | {:.2} |",
        cell(1.0),
        cell(2.0),
        cell(4.0),
        out.max_rotor
    );
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let instant = flip(0.0, None)?;
    let builtin_run = scenes::run(&builtin::paper_flip(), Default::default())?;
    let lag = flip(0.02, None)?;
    let lag_limited = flip(0.02, Some((0.0, 9.0)))?;
    println!("paper flip, Ψ and ‖e_x‖ (m) at 1, 2, 4 s; largest rotor thrust (N)");
    println!("| vehicle | t = 1 s | t = 2 s | t = 4 s | max rotor |");
    println!("|---|---|---|---|---|");
    row("built-in quadrotor", &builtin_run);
    row("lagged, τ = 0", &instant);
    row("lagged, τ = 20 ms", &lag);
    row("lagged, τ = 20 ms, rotors in [0, 9] N", &lag_limited);
    let d = max_difference(&instant.samples, &builtin_run.samples);
    println!(
        "τ = 0 against the built-in quadrotor, every sample: max|Δx| = {:.1e} m, max|ΔR| = {:.1e}",
        d.x, d.r
    );
    let last = &lag.last;
    println!(
        "τ = 20 ms at {} s: rotor states {:?} N (the CSV's s1…s4 columns)",
        last.t,
        last.vehicle_states
            .iter()
            .map(|f| (f * 1e3).round() / 1e3)
            .collect::<Vec<_>>()
    );
    let path = std::env::temp_dir().join("custom-vehicle-flip.mcap");
    write_mcap(&path, &lag)?;
    println!(
        "wrote {} (open it in Foxglove with foxglove/layout.json)",
        path.display()
    );

    // The same vehicle named by a scene file.
    let registry = Registry::new().vehicle("lagged-quadrotor", Lagged);
    let text = builtin::paper_flip().to_toml().replace(
        "kind = \"quadrotor\"",
        "kind = \"lagged-quadrotor\"\nparams = { tau = 0.02 }",
    );
    let scene = registry.from_toml(&text, "lagged-flip.toml")?;
    let from_file = registry.run(&scene, Default::default())?;
    let d = max_difference(&from_file.samples, &lag.samples);
    println!(
        "from a scene file naming `lagged-quadrotor` (tau = 0.02): Ψ(4 s) = {:.4e}, max|Δx| to the builder run = {:.1e} m",
        from_file.last.psi, d.x
    );
    Ok(())
}
