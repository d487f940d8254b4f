//! A flight mode of one's own, scheduled by a condition of one's own: hover
//! in the paper's position mode under the paper's disturbances until the
//! vehicle has settled (‖e_x‖ < 5 cm after 3 s: a user predicate, located
//! to the instant it first holds), then `landing.rs` takes it down at
//! 0.5 m/s and cuts the thrust 10 cm above the ground.
//!
//! Run: `cargo run -p geopid --example custom_mode`

mod landing;

use controllers::{
    AccelerationModel, AttitudeGains, HoldPosition, PositionGains, PositionMode, PositionReference,
    RigidBodyParams,
};
use dynamics::paper;
use dynamics::{Quadrotor, RigidBodyState};
use landing::Landing;
use lie::GlamF64;
use scenarios::{Simulation, Until};

type B = GlamF64;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let params = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let (pg, ag) = (PositionGains::<B>::paper(), AttitudeGains::<B>::paper());
    let hover_at = [0.0, 0.0, -2.0];
    let hold = HoldPosition(PositionReference::hold(
        B::vec3(hover_at[0], hover_at[1], hover_at[2]),
        B::vec3(1.0, 0.0, 0.0),
    ));
    let hover = PositionMode::new(params, pg, ag, AccelerationModel::Nominal, hold);
    // Settled: 3 s in, within 5 cm of the hover point.
    let settled = Until::Condition(Box::new(move |t, body: &RigidBodyState<B>, _out| {
        let x = B::vec3_to_array(body.x);
        let e: f64 = (0..3)
            .map(|k| (x[k] - hover_at[k]).powi(2))
            .sum::<f64>()
            .sqrt();
        t > 3.0 && e < 0.05
    }));
    let landing = Landing::new(params, pg, ag, 0.5, 0.1);
    // Start 1 m beside and 0.5 m below the hover point, at rest.
    let mut start = RigidBodyState::<B>::at_rest();
    start.x = B::vec3(1.0, 0.0, -1.5);
    let quad = Quadrotor::<B>::paper().with_disturbance(Quadrotor::<B>::paper_disturbance())?;
    let out = Simulation::<B>::builder(Box::new(quad))
        .mode(hover, settled)
        .mode(landing, Until::Never)
        .initial(start)
        .dt(1e-3)
        .duration(12.0)
        .record_every(0.01)
        .build()?
        .run(Default::default())?;

    let sw = out.switches.first().ok_or("never settled")?;
    let at_switch =
        studies::metrics::at(&out.samples, (sw.t * 100.0).ceil() / 100.0).ok_or("no sample")?;
    println!(
        "{} → {} at t = {:.6} s (the settle condition, located), height {:.3} m",
        out.mode_names[sw.from], out.mode_names[sw.to], sw.t, -at_switch.x[2]
    );
    // Descent speed over the middle of the descent, from the samples.
    let mid: Vec<_> = out
        .samples
        .iter()
        .filter(|s| s.mode == "landing" && -s.x[2] < 1.6 && -s.x[2] > 0.6)
        .collect();
    if let (Some(a), Some(b)) = (mid.first(), mid.last()) {
        println!(
            "descent from 1.6 m to 0.6 m: {:.3} m/s (commanded 0.5)",
            (b.x[2] - a.x[2]) / (b.t - a.t)
        );
    }
    let cut = out
        .samples
        .iter()
        .find(|s| s.mode == "landing" && s.thrust == 0.0)
        .ok_or("thrust never cut")?;
    println!(
        "thrust cut at t = {:.2} s, height {:.3} m, speed {:.3} m/s, Ψ to level {:.1e}",
        cut.t, -cut.x[2], cut.v[2], cut.psi
    );
    println!(
        "e_i carried into the landing: the disturbance estimate k_i e_i = {:?} N (Δ_x = [-0.5, 0.2, 1] N; still converging)",
        at_switch.e_pos.map(|c| (c * 1.28 * 1e3).round() / 1e3)
    );
    Ok(())
}
