//! The closed loop's edges, each against a value known without the code
//! under test: a Ψ condition is a strict inequality, a last segment that
//! ends at a time has nothing to switch to, the divergence guard measures
//! the Euclidean distance to the desired position, a user's wind is read
//! on its new side after a jump and at its own time after that, and the
//! LGVI integrates a rotor lag under sampled control by the trapezoidal
//! rule (its end-load iteration, needed because the rotor speeds' rate
//! depends on them).

use controllers::{
    AccelerationModel, AttitudeGains, HoldPosition, Mode, PositionGains, PositionMode,
    PositionReference, RigidBodyParams,
};
use dynamics::{Multirotor, MultirotorParams, Quadrotor, RigidBodyState, Wind};
use lie::NalgebraF64;
use scenarios::{Control, Divergence, DivergenceGuard, RunOutput, Simulation, Until};

type B = NalgebraF64;

#[path = "common/idle.rs"]
mod idle;
use dynamics::paper;
use idle::Idle;

/// Reports a fixed Ψ and commands nothing: its state does not matter to
/// the conditions tested here.
fn fixed_psi(psi: f64) -> Box<dyn Mode<B>> {
    Box::new(Idle {
        psi,
        speeds: Vec::new(),
    })
}

fn fly(plan: Vec<(Box<dyn Mode<B>>, Until<'static, B>)>, duration: f64) -> RunOutput {
    let mut b = Simulation::<B>::builder(Box::new(Quadrotor::<B>::paper()))
        .dt(1e-3)
        .duration(duration)
        .record_every(0.01);
    for (mode, until) in plan {
        b = b.segment(scenarios::Segment { mode, until });
    }
    b.build().unwrap().run(Default::default()).unwrap()
}

/// "Ψ below θ" is strict: Ψ exactly θ (1.0, exact in f64) never switches;
/// one ulp above it switches at the first step (located by bisection to
/// 1e-12 of the 1 ms step, so within 1e-14 s of the start).
#[test]
fn a_psi_condition_is_a_strict_inequality() {
    let plan = |theta: f64| -> Vec<(Box<dyn Mode<B>>, Until<'static, B>)> {
        vec![
            (fixed_psi(1.0), Until::PsiBelow(theta)),
            (fixed_psi(1.0), Until::Never),
        ]
    };
    let equal = fly(plan(1.0), 0.05);
    assert!(equal.switches.is_empty(), "{:?}", equal.switches);
    let above = fly(plan(1.0f64.next_up()), 0.05);
    assert_eq!(above.switches.len(), 1);
    assert!(above.switches[0].t < 1e-14, "{}", above.switches[0].t);
}

/// A last segment that "ends" at a time before the end of the run has no
/// segment to switch to: the run goes on in it, exactly as if it never
/// ended (no switch, the same samples to rounding).
#[test]
fn a_last_segment_ending_at_a_time_runs_on() {
    let hover = || -> Box<dyn Mode<B>> {
        Box::new(PositionMode::new(
            RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
            PositionGains::paper(),
            AttitudeGains::paper(),
            AccelerationModel::Nominal,
            HoldPosition(PositionReference::hold(
                B::vec3(0.5, 0.0, -1.0),
                B::vec3(1.0, 0.0, 0.0),
            )),
        ))
    };
    let timed = fly(vec![(hover(), Until::Time(0.05))], 0.1);
    let never = fly(vec![(hover(), Until::Never)], 0.1);
    assert!(timed.switches.is_empty(), "{:?}", timed.switches);
    assert_eq!(timed.samples.len(), never.samples.len());
    let mut worst = 0.0f64;
    for (a, b) in timed.samples.iter().zip(&never.samples) {
        assert_eq!(a.t, b.t);
        let (p, q) = (flat(a), flat(b));
        worst = p
            .iter()
            .zip(&q)
            .fold(worst, |w, (u, v)| w.max((u - v).abs()));
    }
    // The end time is a checkpoint the steps land on, so the steps after
    // it are timed from it: the same flight to rounding (measured 4e-16;
    // the state's entries are O(1)).
    println!("ended at a time vs never: max |Δ| = {worst:.1e}");
    assert!(worst < 1e-13, "{worst:e}");
}

fn flat(s: &scenarios::Sample) -> Vec<f64> {
    let mut v = Vec::new();
    v.extend(s.x);
    v.extend(s.v);
    v.extend(s.r.iter().flatten());
    v.extend(s.omega);
    v
}

/// The guard's position error is ‖x − x_d‖: from 3 m and 4 m off in x and
/// y (5 m in all), a limit of 4.9 m stops the run, located at the start
/// (the vehicle starts at rest: the error is 5 m to 5.7e-11 at the end
/// of the first step, where it is first checked; bound 5e-9) and a limit
/// of 5.01 m never trips while the loop pulls it in.
#[test]
fn the_guard_measures_the_distance_to_the_desired_position() {
    let run = |limit: f64| {
        let mode = PositionMode::new(
            RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
            PositionGains::paper(),
            AttitudeGains::paper(),
            AccelerationModel::Nominal,
            HoldPosition(PositionReference::hold(
                B::vec3(0.0, 0.0, -1.0),
                B::vec3(1.0, 0.0, 0.0),
            )),
        );
        let mut start = RigidBodyState::<B>::at_rest();
        start.x = B::vec3(3.0, 4.0, -1.0);
        Simulation::<B>::builder(Box::new(Quadrotor::<B>::paper()))
            .mode(mode, Until::Never)
            .initial(start)
            .dt(1e-3)
            .duration(0.5)
            .record_every(0.01)
            .guard(DivergenceGuard {
                position_error: Some(limit),
                ..Default::default()
            })
            .build()
            .unwrap()
            .run(Default::default())
            .unwrap()
    };
    let tripped = run(4.9).diverged();
    match tripped {
        Some((Divergence::PositionError(e), t)) => {
            println!("tripped at t = {t} s with ‖x − x_d‖ = {e} m");
            assert!((e - 5.0).abs() < 5e-9, "{e}");
            assert!(t <= 1e-3, "{t}");
        }
        other => panic!("not stopped by the position error: {other:?}"),
    }
    assert_eq!(run(5.01).diverged(), None);
}

/// A user's wind that jumps at 1 s and then grows with time:
/// `u = 0` before, `u = t` from 1 s on.
struct JumpThenRamp;

impl Wind for JumpThenRamp {
    fn velocity(&mut self, t: f64, _x: [f64; 3]) -> [f64; 3] {
        [if t > 1.0 { t } else { 0.0 }, 0.0, 0.0]
    }
    fn jumps(&self, t_end: f64) -> Vec<f64> {
        [1.0].into_iter().filter(|&t| t < t_end).collect()
    }
}

/// From the jump on, the samples see the wind's new side (at 1 s itself:
/// u = 1 to rounding), and after it the wind at their own time, not at the
/// jump's (u = t exactly: the same expression at the same t).
#[test]
fn a_users_wind_is_read_on_its_new_side_and_then_at_its_own_time() {
    let out = Simulation::<B>::builder(Box::new(Quadrotor::<B>::paper()))
        .dt(1e-3)
        .duration(2.5)
        .record_every(0.1)
        .wind(Box::new(JumpThenRamp))
        .build()
        .unwrap()
        .run(Default::default())
        .unwrap();
    let mut checked = 0;
    for s in &out.samples {
        let want = if s.t >= 1.0 { s.t } else { 0.0 };
        let tol = if s.t == 1.0 { 1e-15 } else { 0.0 };
        assert!(
            (s.wind[0] - want).abs() <= tol,
            "u = {} at t = {}",
            s.wind[0],
            s.t
        );
        checked += usize::from(s.t > 1.0);
    }
    assert!(checked >= 14, "{checked} samples after the jump");
}

/// Under sampled control the rotor-speed command is held, so a first-order
/// lag `ω̇ = (ω_c − ω)/τ` between control instants is linear, and the
/// LGVI's trapezoidal treatment of the vehicle's states has the closed
/// form `ω_n = ω_c + (ω₀ − ω_c) ρⁿ`, `ρ = (1 − h/2τ)/(1 + h/2τ)`. Its
/// end-load iteration must run for it (the rate depends on ω at the end
/// of the step); one pass gives Heun's `ρ = 1 − h/τ + h²/2τ²` instead,
/// 4.6e-3 rad/s off here within 40 steps. Iterated to rounding, the
/// measured error is 6.8e-13 rad/s (rounding of ω ≈ 1 800 rad/s over 40
/// steps); bound 5e-11.
#[test]
fn the_lgvi_integrates_a_held_rotor_lag_by_the_trapezoidal_rule() {
    let (w0, wc, h) = (1500.0, 1800.0, 1e-3);
    let mut params = MultirotorParams::<B>::crazyflie();
    params.aero = false;
    let tau = params.tau_m;
    let vehicle = Multirotor::new(params).unwrap();
    let replay = Idle {
        psi: 0.0,
        speeds: vec![(0.0, vec![w0; 4]), (0.01, vec![wc; 4])],
    };
    let out = Simulation::<B>::builder(Box::new(vehicle))
        .mode(replay, Until::Never)
        .integrator({
            let mut lgvi = integrators::Lgvi::<B, 16>::default();
            lgvi.end_load = integrators::EndLoad::IterateToRounding { max: 50 };
            lgvi
        })
        .control(Control::Sampled { rate: 100.0 })
        .dt(h)
        .duration(0.05)
        .record_every(h)
        .build()
        .unwrap()
        .run(Default::default())
        .unwrap();
    let rho = (1.0 - h / (2.0 * tau)) / (1.0 + h / (2.0 * tau));
    let mut worst = 0.0f64;
    for s in out.samples.iter().filter(|s| s.t > 0.01 + 1e-9) {
        let n = ((s.t - 0.01) / h).round() as i32;
        let want = wc + (w0 - wc) * rho.powi(n);
        for w in &s.vehicle_states[..4] {
            worst = worst.max((w - want).abs());
        }
    }
    println!("LGVI rotor lag against the trapezoidal closed form: {worst:.2e} rad/s");
    assert!(worst < 5e-11, "{worst:e}");
}

/// A condition is located by bisection on redone steps until the bracket
/// is 1e-12 of the step or the time's own resolution ε·t, whichever is
/// coarser: at h = 1 ms and t = 1.2345 s that is 40 halvings (2⁴⁰ ≥ 1e12),
/// at h = 0.1 ms 39 (the bracket reaches ε·1.2345 = 2.7e-16 s first). Each
/// halving redoes one RK4 step, four load evaluations, on top of four per
/// step taken. The condition is read at the time of the redone step's end:
/// a predicate of time is located to that resolution, not at the step's
/// end (1.235 s).
#[test]
fn a_condition_is_bisected_to_its_step_or_its_time_resolution() {
    let t_switch = 1.2345;
    for h in [1e-3, 1e-4] {
        let run = |until: Option<Until<'static, B>>| {
            let mut b = Simulation::<B>::builder(Box::new(Quadrotor::<B>::paper()))
                .dt(h)
                .duration(1.5)
                .record_every(0.01);
            if let Some(u) = until {
                b = b.segment(scenarios::Segment {
                    mode: fixed_psi(0.0),
                    until: u,
                });
            }
            b.segment(scenarios::Segment {
                mode: fixed_psi(0.0),
                until: Until::Never,
            })
            .build()
            .unwrap()
            .run(Default::default())
            .unwrap()
        };
        let located = run(Some(Until::Condition(Box::new(move |t, _, _| {
            t >= t_switch
        }))));
        let plain = run(None);
        let floor = (1e-12 * h).max(f64::EPSILON * t_switch);
        let halvings = (0..).find(|k| h / 2f64.powi(*k) <= floor).unwrap() as u64;
        let extra = located.evaluations - 4 * located.steps;
        println!("h = {h}: {halvings} halvings expected, {extra} evaluations beyond the steps'");
        assert_eq!(plain.evaluations, 4 * plain.steps, "RK4: four per step");
        assert_eq!(extra, 4 * halvings, "h = {h}");
        assert_eq!(located.switches.len(), 1);
        let tc = located.switches[0].t;
        assert!(
            (tc - t_switch).abs() <= 2.0 * floor,
            "located at {tc}, h = {h}"
        );
    }
}
