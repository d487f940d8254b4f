//! A user's flight mode and switching condition through the public API:
//! the condition is located, the mode's own entry logic runs, and what it
//! keeps of the integral register is kept.
//!
//! One pair: the examples this tests are written for one (a user picks
//! one); pair independence of the loop is `scenes::f32_glam_follows_f64_nalgebra`.

#[path = "../../geopid/examples/custom_mode/landing.rs"]
mod landing;

use controllers::{
    AccelerationModel, AttitudeGains, HoldPosition, PositionGains, PositionMode, PositionReference,
    RigidBodyParams,
};
use dynamics::Quadrotor;
use dynamics::paper;
use landing::Landing;
use lie::NalgebraF64;
use scenarios::{RunOutput, Simulation, Until};

type B = NalgebraF64;

fn hover_then_land(until: Until<'static, B>, duration: f64) -> RunOutput {
    let params = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let (pg, ag) = (PositionGains::<B>::paper(), AttitudeGains::<B>::paper());
    let hold = HoldPosition(PositionReference::hold(
        B::vec3(0.0, 0.0, -2.0),
        B::vec3(1.0, 0.0, 0.0),
    ));
    let mut start = dynamics::RigidBodyState::<B>::at_rest();
    start.x = B::vec3(0.0, 0.0, -2.0);
    let quad = Quadrotor::<B>::paper()
        .with_disturbance(Quadrotor::<B>::paper_disturbance())
        .unwrap();
    Simulation::<B>::builder(Box::new(quad))
        .mode(
            PositionMode::new(params, pg, ag, AccelerationModel::Nominal, hold),
            until,
        )
        .mode(Landing::new(params, pg, ag, 0.5, 0.1), Until::Never)
        .initial(start)
        .dt(1e-3)
        .duration(duration)
        .record_every(0.01)
        .build()
        .unwrap()
        .run(Default::default())
        .unwrap()
}

#[test]
fn a_user_condition_is_located_to_the_instant_it_first_holds() {
    // A predicate that turns true at t = 1.234 (off the 1 ms grid): the
    // bisection on redone steps locates it to 1e-12 of a step.
    let out = hover_then_land(Until::Condition(Box::new(|t, _, _| t >= 1.234)), 1.5);
    assert_eq!(out.switches.len(), 1);
    let sw = out.switches[0];
    println!("condition t ≥ 1.234 located at {:.15}", sw.t);
    assert!((sw.t - 1.234).abs() < 1e-14, "{}", sw.t);
    assert_eq!(
        (out.mode_names[sw.from], out.mode_names[sw.to]),
        ("position", "landing")
    );
    assert_eq!(out.samples.last().unwrap().mode, "landing");
}

#[test]
fn landing_descends_at_its_speed_and_cuts_thrust_at_its_height() {
    let out = hover_then_land(Until::Condition(Box::new(|t, _, _| t >= 2.0)), 7.0);
    // The descent: 0.5 m/s commanded; after the entry transient the
    // position loop tracks a constant-velocity reference with zero error
    // in steady state (integral action), so the measured slope is within
    // a few % of it.
    let mid: Vec<_> = out
        .samples
        .iter()
        .filter(|s| s.mode == "landing" && -s.x[2] < 1.5 && -s.x[2] > 0.7)
        .collect();
    let (a, b) = (mid.first().unwrap(), mid.last().unwrap());
    let speed = (b.x[2] - a.x[2]) / (b.t - a.t);
    println!("descent speed {speed:.4} m/s");
    assert!((speed - 0.5).abs() < 0.02, "{speed}");
    // The first sample with the thrust cut is just below 10 cm (one 10 ms
    // sample at ≤ 0.6 m/s is ≤ 6 mm).
    let cut = out
        .samples
        .iter()
        .find(|s| s.mode == "landing" && s.thrust == 0.0)
        .expect("thrust cut");
    println!("cut at t = {:.2}, height {:.4} m", cut.t, -cut.x[2]);
    assert!(-cut.x[2] <= 0.1 && -cut.x[2] > 0.094, "{}", cut.x[2]);
}

#[test]
fn integrals_the_mode_keeps_carry_across_the_switch() {
    // Landing keeps e_i (the paper's position mode would zero it on entry):
    // the sample just after the switch continues the hover's e_i.
    let out = hover_then_land(Until::Condition(Box::new(|t, _, _| t >= 2.0)), 2.02);
    let before = studies::metrics::at(&out.samples, 2.0).unwrap();
    let after = studies::metrics::at(&out.samples, 2.01).unwrap();
    let jump: f64 = (0..3)
        .map(|k| (after.e_pos[k] - before.e_pos[k]).abs())
        .sum();
    let size: f64 = before.e_pos.iter().map(|c| c.abs()).sum();
    println!("|e_i| {size:.3e}, change over the 10 ms across the switch {jump:.3e}");
    assert!(size > 0.1 && jump < 0.05 * size, "{size} {jump}");
}
