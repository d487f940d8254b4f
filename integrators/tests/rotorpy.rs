//! `dynamics::Multirotor` against RotorPy 3.0.0's `Multirotor`, open loop:
//! the same rotor-speed commands (piecewise constant at 100 Hz for 5 s, a
//! climb, roll, pitch and yaw pulses and a descent) in a constant wind,
//! aerodynamics on, for RotorPy's crazyflie and for its hummingbird with a
//! flapping coefficient added (so that parasitic drag, rotor drag, inflow,
//! translational lift and flapping are all exercised). RotorPy integrates
//! each 10 ms hold with RK45 at rtol = atol = 1e-12; this side with
//! Dormand–Prince at 1e-12 from the same state.
//!
//! The reference is `golden/rotorpy_open_loop.txt`, written by
//! `golden/rotorpy_open_loop.py`; when `python3` can import `rotorpy`, the
//! script is run afresh and its output used instead (the test says which).
//!
//! Tolerance 1e-8 (positions in m, velocities in m/s, rates in rad/s,
//! rotor speeds relative): both integrators are held to 1e-12 per step
//! over 500 holds, and the open-loop motion stays within 20° of level, so
//! the errors grow mildly; what is left above 1e-8 would be a difference of
//! model, not of integration.

use std::path::PathBuf;

use dynamics::{Multirotor, MultirotorParams, RigidBodyState};
use integrators::{Dopri, Integrator, Load, State, System};
use lie::{M3, NalgebraF64, S, V3, ops};

type B = NalgebraF64;

/// One case of the reference file.
struct Case {
    name: String,
    wind: [f64; 3],
    k_flap: f64,
    /// `(t, [ω_cmd; 4])` every 10 ms.
    cmds: Vec<(f64, [f64; 4])>,
    /// `t, x(3), v(3), R(9, row-major), Ω(3), ω(4)` every 0.1 s.
    states: Vec<Vec<f64>>,
}

fn parse(text: &str) -> Vec<Case> {
    let mut cases: Vec<Case> = Vec::new();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let mut words = line.split_whitespace();
        let key = words.next().unwrap_or_default();
        let nums: Vec<f64> = words.clone().filter_map(|w| w.parse().ok()).collect();
        match key {
            "case" => cases.push(Case {
                name: words.next().unwrap_or_default().to_string(),
                wind: [0.0; 3],
                k_flap: 0.0,
                cmds: Vec::new(),
                states: Vec::new(),
            }),
            "wind" => cases.last_mut().expect("case first").wind = [nums[0], nums[1], nums[2]],
            "k_flap" => cases.last_mut().expect("case first").k_flap = nums[0],
            "cmd" => cases
                .last_mut()
                .expect("case first")
                .cmds
                .push((nums[0], [nums[1], nums[2], nums[3], nums[4]])),
            "state" => cases.last_mut().expect("case first").states.push(nums),
            _ => panic!("unexpected line in the reference: {line}"),
        }
    }
    cases
}

/// The reference text and where it came from.
fn reference() -> (String, &'static str) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    match testkit::rotorpy_golden(&dir, "rotorpy_open_loop") {
        (text, true) => (text, "RotorPy, run now"),
        (text, false) => (text, "the stored golden (rotorpy not importable)"),
    }
}

/// The vehicle under a held rotor-speed command in a constant wind.
struct OpenLoop {
    vehicle: Multirotor<B>,
    cmd: [f64; 4],
    wind: V3<B>,
    j_inv: M3<B>,
}

impl System<B, 4> for OpenLoop {
    fn mass(&self) -> S<B> {
        self.vehicle.params().mass
    }
    fn inertia(&self) -> M3<B> {
        self.vehicle.params().inertia
    }
    fn inertia_inv(&self) -> M3<B> {
        self.j_inv
    }
    fn load(&mut self, _t: f64, y: &State<B, 4>) -> Load<B, 4> {
        let l = self.vehicle.loads_at(&y.body, &y.extra, self.wind);
        let mut extra_rate = [0.0; 4];
        self.vehicle
            .motor_rates(&self.cmd, &y.extra, &mut extra_rate);
        Load {
            force: l.force,
            moment: l.moment,
            extra_rate,
        }
    }
}

fn row_of(t: f64, y: &State<B, 4>) -> Vec<f64> {
    let b = &y.body;
    let r = ops::elems::<B>(b.r);
    let mut row = vec![t];
    row.extend(B::vec3_to_array(b.x));
    row.extend(B::vec3_to_array(b.v));
    row.extend(r.iter().flatten());
    row.extend(B::vec3_to_array(b.omega));
    row.extend(y.extra);
    row
}

/// Flies a case; returns the worst difference per quantity.
fn fly(case: &Case) -> [f64; 5] {
    let mut params = if case.name == "crazyflie" {
        MultirotorParams::<B>::crazyflie()
    } else {
        MultirotorParams::<B>::hummingbird()
    };
    params.k_flap = case.k_flap;
    let vehicle = Multirotor::new(params).expect("preset is valid");
    let j_inv = ops::inverse::<B>(vehicle.params().inertia).expect("invertible");
    let wind = B::vec3(case.wind[0], case.wind[1], case.wind[2]);
    let mut sys = OpenLoop {
        vehicle,
        cmd: [0.0; 4],
        wind,
        j_inv,
    };
    let s0 = &case.states[0];
    let mut y = State::<B, 4>::new(RigidBodyState::at_rest());
    y.extra = [s0[19], s0[20], s0[21], s0[22]];
    // Capped far above what the reference needs, so that a broken step
    // control fails instead of running on.
    let mut dopri = Dopri::<B>::new(1e-12).max_substeps(100_000);
    let mut worst = [0.0f64; 5];
    for (k, (t, cmd)) in case.cmds.iter().enumerate() {
        sys.cmd = *cmd;
        dopri.step(&mut sys, *t, 0.01, &mut y).expect("step");
        if (k + 1) % 10 == 0 {
            let want = &case.states[(k + 1) / 10];
            let got = row_of(want[0], &y);
            let diff = |a: usize, b: usize, scale: f64| {
                (a..b).fold(0.0f64, |m, i| m.max((got[i] - want[i]).abs() / scale))
            };
            let w_scale = want[19..23].iter().fold(0.0f64, |m, x| m.max(x.abs()));
            for (w, d) in worst.iter_mut().zip([
                diff(1, 4, 1.0),
                diff(4, 7, 1.0),
                diff(7, 16, 1.0),
                diff(16, 19, 1.0),
                diff(19, 23, w_scale),
            ]) {
                *w = w.max(d);
            }
        }
    }
    worst
}

fn multirotor_matches_rotorpy_open_loop() {
    let (text, source) = reference();
    let cases = parse(&text);
    assert_eq!(cases.len(), 2, "two cases in the reference");
    println!("reference: {source}");
    println!("case               |Δx| m   |Δv| m/s  |ΔR|     |ΔΩ| rad/s  |Δω|/ω");
    for case in &cases {
        assert_eq!(case.cmds.len(), 500);
        assert_eq!(case.states.len(), 51);
        let w = fly(case);
        println!(
            "{:<18} {:.1e}  {:.1e}   {:.1e}  {:.1e}     {:.1e}",
            case.name, w[0], w[1], w[2], w[3], w[4]
        );
        assert!(w.iter().all(|e| *e <= 1e-8), "{}: {w:?}", case.name);
    }
}

fn main() {
    testkit::run(&[(
        "multirotor_matches_rotorpy_open_loop",
        multirotor_matches_rotorpy_open_loop,
    )]);
}
