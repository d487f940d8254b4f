//! A Monte Carlo study over wind seeds, through the library's `Study`: the
//! crazyflie of `gusty-hover` released 0.5 m from its hover point in a
//! random direction, in Dryden turbulence (σ = 1 m/s) drawn from a seed of
//! its own per sample, settled when it holds within 10 cm and Ψ < 10⁻²
//! for 2 s. Run with and without the integral terms on the same draws.
//!
//! `cargo run --release -p geopid --example wind_study [samples]`

use dynamics::{DrydenSpec, DrydenWind, RigidBodyState};
use lie::{NalgebraF64, Real};
use scenarios::{DivergenceGuard, Simulation, Until};
use scenes::Error;
use scenes::{Overrides, Scene};
use studies::montecarlo::rand_core::Rng;
use studies::montecarlo::{Study, Summary, in_ball};

type B = NalgebraF64;

/// A sample's draws: the turbulence seed and the start offset.
struct Draw {
    seed: u64,
    offset: [f64; 3],
}

/// Runs the study on `scene` (its vehicle, plan and gains) for `indices`.
fn run(scene: Scene, indices: &[u64]) -> Result<Summary, Error> {
    let hover = [0.0, 0.0, -1.0];
    let study = Study::new(
        7,
        2.0,
        |rng: &mut studies::montecarlo::Stream| {
            let seed = rng.next_u64();
            let d = in_ball(rng, 1.0);
            let n = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt().max(1e-9);
            Draw {
                seed,
                offset: d.map(|c| 0.5 * c / n),
            }
        },
        move |d: &Draw| {
            let vehicle = scenes::build_vehicle::<B>(&scene)?;
            let plan = scenes::plan::<B>(&scene, vehicle.as_ref());
            let wind = DrydenWind::new(DrydenSpec {
                seed: d.seed,
                ..DrydenSpec::gusty()
            })
            .map_err(|e| Error::setting("wind", e.to_string()))?;
            let mut start = RigidBodyState::<B>::at_rest();
            start.x = B::vec3(
                hover[0] + d.offset[0],
                hover[1] + d.offset[1],
                hover[2] + d.offset[2],
            );
            let mut b = Simulation::<B>::builder(vehicle)
                .initial(start)
                .dt(1e-3)
                .duration(20.0)
                .record_every(0.02)
                .wind(Box::new(wind))
                .guard(DivergenceGuard {
                    omega: Some(100.0),
                    position_error: Some(20.0),
                    ..Default::default()
                });
            for seg in plan {
                b = b.segment(scenarios::Segment {
                    mode: seg.mode,
                    until: Until::Never,
                });
            }
            Ok(b)
        },
        move |_t, body: &RigidBodyState<B>, out: &controllers::ModeOutput<B>| {
            let x = B::vec3_to_array(body.x);
            let e = (0..3)
                .map(|k| (x[k] - hover[k]).powi(2))
                .sum::<f64>()
                .sqrt();
            (e / 0.1).max(out.psi.to_f64_lossless() / 1e-2)
        },
    );
    Ok(Summary::of(&study.run(indices, None, None)?))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let n: u64 = std::env::args().nth(1).map_or(Ok(100), |a| a.parse())?;
    let indices: Vec<u64> = (0..n).collect();
    println!(
        "| integral terms | samples | settled | out of time | diverged | median settle (s) | 95th (s) |"
    );
    println!("|---|---|---|---|---|---|---|");
    for integral in [true, false] {
        let scene = Overrides {
            no_integral: !integral,
            ..Default::default()
        }
        .apply(scenes::load("gusty-hover")?)?;
        let s = run(scene, &indices)?;
        println!(
            "| {} | {} | {} ({:.0} %) | {} | {} | {:.2} | {:.2} |",
            if integral { "on" } else { "off" },
            s.samples,
            s.converged,
            100.0 * s.converged_fraction,
            s.deadline,
            s.diverged,
            s.t_converge.median,
            s.t_converge.p95
        );
    }
    Ok(())
}
