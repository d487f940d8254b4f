//! A user's vehicle with internal states (rotor lag) through the public
//! simulation API: the τ → 0 limit equals the built-in quadrotor, the lag's
//! effect is first order in τ, its states are integrated, logged and
//! counted in the layout.
//!
//! One pair: the examples this tests are written for one (a user picks
//! one); pair independence of the loop is `scenes::f32_glam_follows_f64_nalgebra`.

#[path = "../../geopid/examples/custom_vehicle/lagged.rs"]
mod lagged;

use dynamics::{DynamicsError, Quadrotor, Vehicle, Wrench};
use lagged::LaggedQuadrotor;
use lie::{M3, NalgebraF64};
use logs::{csv_header, write_csv, write_mcap};
use scenarios::{RunOutput, SimError, Simulation};
use scenes::builtin;
use studies::metrics::{Difference, max_difference, nan_max};

type B = NalgebraF64;

fn vehicle(tau: f64) -> LaggedQuadrotor<B> {
    let quad = Quadrotor::<B>::paper()
        .with_disturbance(Quadrotor::<B>::paper_disturbance())
        .unwrap();
    LaggedQuadrotor::new(quad, tau).unwrap()
}

fn flip(tau: f64, dt: f64) -> RunOutput {
    fly(vehicle(tau), dt)
}

fn fly(v: LaggedQuadrotor<B>, dt: f64) -> RunOutput {
    let scene = builtin::paper_flip();
    let plan = scenes::plan::<B>(&scene, &v);
    let mut sim = Simulation::<B>::builder(Box::new(v))
        .dt(dt)
        .duration(scene.duration)
        .record_every(0.01);
    for s in plan {
        sim = sim.segment(s);
    }
    sim.build().unwrap().run(Default::default()).unwrap()
}

#[test]
fn without_lag_equals_the_built_in_quadrotor() {
    let mut scene = builtin::paper_flip();
    scene.record.sample = 0.01;
    let reference = scenes::run(&scene, Default::default()).unwrap();
    let lagless = flip(0.0, scene.integrator.dt);
    // Same equations, same stepper and grid; the only difference is the
    // allocation round trip A(A⁻¹w), a few ulps per evaluation. Measured:
    // |Δx| 1.5e-15, |Δv| 2.9e-15, |ΔR| 1.4e-15, e_i 8.2e-15 over the flip;
    // bounds 25–70× that (a lag that stays first order at τ = 0, or one
    // wrong rotor, moves them by 1e-3 and more).
    let Difference {
        x: dx,
        v: dv,
        r: dr,
        compared: n,
    } = max_difference(&lagless.samples, &reference.samples);
    println!("τ = 0 vs built-in over {n} samples: |Δx| {dx:.1e}, |Δv| {dv:.1e}, |ΔR| {dr:.1e}");
    assert_eq!(n, reference.samples.len());
    assert!(dx < 1e-13 && dv < 2e-13 && dr < 1e-13, "{dx} {dv} {dr}");
    let de = lagless
        .samples
        .iter()
        .zip(&reference.samples)
        .flat_map(|(a, b)| (0..3).map(move |k| (a.e_pos[k] - b.e_pos[k]).abs()))
        .fold(0.0, nan_max);
    println!("τ = 0 vs built-in: |Δe_i| {de:.1e}");
    assert!(de < 5e-13, "e_i differs by {de}");
    assert!(lagless.last.vehicle_states.is_empty());
    assert_eq!(lagless.events, reference.events);
}

#[test]
fn lag_effect_is_first_order_in_tau() {
    // Rotor lag perturbs the applied wrench by about τ·ẇ, so the trajectory
    // moves by O(τ): halving τ halves the gap to τ = 0. Step 1e-4 keeps RK4
    // well inside its stability limit (h/τ ≤ 0.1) and its own error
    // (~1e-12 on this scene) far below the gaps (~1e-3).
    let base = flip(0.0, 1e-4);
    let gaps: Vec<f64> = [4e-3, 2e-3, 1e-3]
        .iter()
        .map(|&tau| max_difference(&flip(tau, 1e-4).samples, &base.samples).x)
        .collect();
    let r1 = gaps[0] / gaps[1];
    let r2 = gaps[1] / gaps[2];
    println!(
        "max|Δx| for τ = 4, 2, 1 ms: {:.3e} {:.3e} {:.3e}; ratios {r1:.3} {r2:.3}",
        gaps[0], gaps[1], gaps[2]
    );
    // O(τ²) terms make the ratio drift from 2 by ~τ/T_dyn (a few %).
    assert!(
        (r1 - 2.0).abs() < 0.15 && (r2 - 2.0).abs() < 0.1,
        "{r1} {r2}"
    );
}

#[test]
fn rotor_states_are_integrated_and_logged() {
    let out = flip(0.02, 5e-4);
    let first = &out.samples[0];
    assert_eq!(first.vehicle_states.len(), 4);
    // Started at the first command's allocation: the rotors sum to it.
    let sum: f64 = first.vehicle_states.iter().sum();
    assert!(
        (sum - first.thrust).abs() < 1e-12,
        "{sum} vs {}",
        first.thrust
    );
    // After the flip the states have moved, and the logged rotor thrusts
    // are the states (what the body feels), not the command.
    let last = &out.last;
    for (s, r) in last.vehicle_states.iter().zip(&last.rotors) {
        assert!((s - r).abs() < 1e-12, "{s} vs {r}");
    }
    assert!((last.vehicle_states.iter().sum::<f64>() - last.thrust).abs() > 1e-6);
    let dir = std::env::temp_dir().join(format!("gpid-custom-vehicle-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let csv = dir.join("lag.csv");
    write_csv(&csv, &out).unwrap();
    let text = std::fs::read_to_string(&csv).unwrap();
    let mut lines = text.lines();
    assert_eq!(lines.next().unwrap(), csv_header(4));
    let row: Vec<&str> = lines.last().unwrap().split(',').collect();
    let s4: f64 = row.last().unwrap().parse().unwrap();
    assert_eq!(s4, last.vehicle_states[3]);
    let mcap = dir.join("lag.mcap");
    write_mcap(&mcap, &out).unwrap();
    let bytes = std::fs::read(&mcap).unwrap();
    let mut n = 0;
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic == logs::STATES_TOPIC {
            n += 1;
        }
    }
    assert_eq!(n, out.samples.len());
    std::fs::remove_dir_all(&dir).ok();
}

/// The lagged quadrotor with more internal states than any simulation
/// holds (the extra ones idle), to test the layout's limit.
struct ManyStates(LaggedQuadrotor<B>);

impl Vehicle<B> for ManyStates {
    fn name(&self) -> &str {
        "many-states"
    }
    fn mass(&self) -> f64 {
        self.0.mass()
    }
    fn inertia(&self) -> M3<B> {
        self.0.inertia()
    }
    fn gravity(&self) -> f64 {
        self.0.gravity()
    }
    fn actuator_count(&self) -> usize {
        self.0.actuator_count()
    }
    fn wrench_from_actuators(&self, u: &[f64]) -> Result<Wrench<B>, DynamicsError> {
        self.0.wrench_from_actuators(u)
    }
    fn actuators_from_wrench(&self, w: &Wrench<B>, out: &mut [f64]) -> Result<(), DynamicsError> {
        self.0.actuators_from_wrench(w, out)
    }
    fn capabilities(&self) -> dynamics::Capabilities<'_, B> {
        dynamics::Capabilities::RIGID.with_actuators(self)
    }
}

impl dynamics::Actuators<B> for ManyStates {
    fn delivered(&self, commanded: &Wrench<B>, _states: &[f64]) -> Wrench<B> {
        *commanded
    }
    fn state_count(&self) -> usize {
        11
    }
}

/// The simulation sizes its state for the plan and the vehicle: the
/// paper's six integrals and the lag's four rotor states build without
/// the user naming a size, and a vehicle declaring more than the largest
/// size holds is an error naming both counts.
#[test]
fn the_state_is_sized_for_the_plan_and_the_vehicle() {
    let scene = builtin::paper_flip();
    let build = |v: Box<dyn Vehicle<B>>| {
        let plan = scenes::plan::<B>(&scene, v.as_ref());
        let mut sim = Simulation::<B>::builder(v);
        for s in plan {
            sim = sim.segment(s);
        }
        sim.build()
    };
    let sim = build(Box::new(vehicle(0.02))).unwrap();
    let at = sim.layout();
    assert_eq!((at.integrals, at.vehicle_states), (6, 4));
    assert_eq!(sim.state().vehicle_states.len(), 4);
    let largest = *scenarios::CAPACITIES.last().unwrap();
    match build(Box::new(ManyStates(vehicle(0.02)))) {
        Err(
            e @ SimError::Layout {
                integrals: 6,
                vehicle_states: 11,
                ..
            },
        ) => {
            let msg = e.to_string();
            assert!(msg.contains("6 integral states") && msg.contains("11 internal states"));
            assert!(msg.contains(&format!("at most {largest}")), "{msg}");
        }
        Err(e) => panic!("wrong error {e}"),
        Ok(_) => panic!("{largest} slots cannot hold 17 states"),
    }
}

#[test]
fn rotor_limits_hold_every_rotor_in_range() {
    // The demanded thrusts are clamped to [0, 9] N and the lag relaxes the
    // states towards them, so no state leaves the range (RK4's stage
    // combination of a stable linear lag at h/τ = 0.025 does not overshoot
    // beyond rounding). The unlimited flip peaks at 12.7 N, so it binds.
    let out = fly(vehicle(0.02).with_limits(0.0, 9.0).unwrap(), 5e-4);
    let (lo, hi) = out
        .samples
        .iter()
        .flat_map(|s| s.vehicle_states.iter())
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
            (lo.min(x), hi.max(x))
        });
    println!("rotor states over the limited flip: [{lo:.4}, {hi:.4}] N");
    assert!(lo >= -1e-12 && hi <= 9.0 + 1e-12, "{lo} {hi}");
    assert!(hi > 8.9, "the limit should bind: {hi}");
    assert!(vehicle(0.02).with_limits(1.0, 1.0).is_err());
    assert!(LaggedQuadrotor::new(Quadrotor::<B>::paper(), -1.0).is_err());
}
