//! RotorPy's `SE3Control` written here as a user `Mode` that commands
//! rotor speeds, flying RotorPy's crazyflie (the `multirotor` model,
//! aerodynamics on) on RotorPy's hover and circle, against RotorPy's own
//! simulation of the same: control held at 100 Hz, both integrators at
//! 1e-12. Positions, velocities, attitudes, body rates and rotor speeds
//! agree to 1e-6 over 10 s (the closed loop is stable, so the two
//! integrators' 1e-12 steps do not grow; what would show above 1e-6 is a
//! difference of model or law). Also the wall time per simulated second
//! of both, RotorPy's measured by its script in the same run.
//!
//! The reference is `golden/rotorpy_closed_loop.txt`, written by
//! `golden/rotorpy_closed_loop.py`; when `python3` imports `rotorpy` the
//! script runs afresh (the test says which).

use std::path::PathBuf;

use controllers::{ControlError, Mode, ModeOutput, RotorSpeeds, VehicleState};
use dynamics::{Multirotor, MultirotorParams, RigidBodyState, Vehicle};
use lie::{NalgebraF64, Rotation, S, So3Mat, ops};
use scenarios::{Control, Simulation, Until};
use studies::metrics::nan_max;

type B = NalgebraF64;
type A3 = [f64; 3];

/// `P = diag(1, −1, −1)`: RotorPy's z-up frames to this project's.
fn p(v: A3) -> A3 {
    [v[0], -v[1], -v[2]]
}

fn pm(r: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    let s = [1.0, -1.0, -1.0];
    core::array::from_fn(|i| core::array::from_fn(|j| s[i] * r[i][j] * s[j]))
}

fn cross(a: A3, b: A3) -> A3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn normalize(a: A3) -> A3 {
    let n = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    a.map(|c| c / n)
}

fn mat_t_mul(a: [[f64; 3]; 3], b: [[f64; 3]; 3]) -> [[f64; 3]; 3] {
    core::array::from_fn(|i| core::array::from_fn(|j| (0..3).map(|k| a[k][i] * b[k][j]).sum()))
}

/// RotorPy's trajectories, in its frame: `(x, ẋ, ẍ)`, yaw and yaw rate 0.
enum Traj {
    Hover,
    /// `ThreeDCircularTraj(radius = (1, 1, 0), freq = 0.2)`, centre 0.
    Circle,
}

impl Traj {
    fn at(&self, t: f64) -> (A3, A3, A3) {
        match self {
            Traj::Hover => ([0.0; 3], [0.0; 3], [0.0; 3]),
            Traj::Circle => {
                let w = 2.0 * std::f64::consts::PI * 0.2;
                let (s, c) = (w * t).sin_cos();
                (
                    [c, s, 0.0],
                    [-w * s, w * c, 0.0],
                    [-w * w * c, -w * w * s, 0.0],
                )
            }
        }
    }
}

/// RotorPy 3.0.0's `SE3Control.update` with its crazyflie gains, in
/// RotorPy's frame (the state converted in, the outputs out), rotor speeds
/// from its allocation inverse.
struct Se3Control {
    mass: f64,
    inertia: A3,
    /// RotorPy's `TM_to_f`: the rotor thrusts of a wrench. The same map
    /// as this vehicle's allocation inverse once the moment is in this
    /// frame (`P u2`; rotor `i` is the same rotor in both).
    mixer: Multirotor<B>,
    k_eta: f64,
    traj: Traj,
}

impl Se3Control {
    fn new(traj: Traj) -> Self {
        let mixer = Multirotor::new(MultirotorParams::<B>::crazyflie()).expect("preset");
        Self {
            mass: mixer.params().mass,
            inertia: [1.43e-5, 1.43e-5, 2.89e-5],
            k_eta: mixer.params().k_eta,
            mixer,
            traj,
        }
    }
}

impl Se3Control {
    /// One evaluation of the law: the wrench (for the logs) and the rotor
    /// speeds it mixes to (the command).
    fn answer(&self, t: S<B>, state: &VehicleState<B, So3Mat<B>>) -> ModeOutput<B> {
        let x = p(B::vec3_to_array(state.x));
        let v = p(B::vec3_to_array(state.v));
        let w = p(B::vec3_to_array(state.omega));
        let r = pm(ops::elems::<B>(state.r.matrix()));
        let (xd, vd, ad) = self.traj.at(t);
        let (kp, kd) = ([6.5, 6.5, 15.0], [4.0, 4.0, 9.0]);
        let f_des: A3 = core::array::from_fn(|i| {
            self.mass
                * (-kp[i] * (x[i] - xd[i]) - kd[i] * (v[i] - vd[i])
                    + ad[i]
                    + if i == 2 { 9.81 } else { 0.0 })
        });
        let b3 = [r[0][2], r[1][2], r[2][2]];
        let u1 = (0..3).map(|i| f_des[i] * b3[i]).sum::<f64>();
        let b3_des = normalize(f_des);
        let c1_des = [1.0, 0.0, 0.0];
        let b2_des = normalize(cross(b3_des, c1_des));
        let b1_des = cross(b2_des, b3_des);
        let r_des: [[f64; 3]; 3] = core::array::from_fn(|i| [b1_des[i], b2_des[i], b3_des[i]]);
        let (a, b) = (mat_t_mul(r_des, r), mat_t_mul(r, r_des));
        let s: [[f64; 3]; 3] =
            core::array::from_fn(|i| core::array::from_fn(|j| 0.5 * (a[i][j] - b[i][j])));
        let att_err = [-s[1][2], s[0][2], -s[0][1]];
        let jw: A3 = core::array::from_fn(|i| self.inertia[i] * w[i]);
        let gyro = cross(w, jw);
        let u2: A3 = core::array::from_fn(|i| {
            self.inertia[i] * (-310.0 * att_err[i] - 57.0 * w[i]) + gyro[i]
        });
        let m = p(u2);
        let wrench = dynamics::Wrench {
            thrust: u1,
            moment: B::vec3(m[0], m[1], m[2]),
        };
        let (mut f, mut speeds) = ([0.0; 4], [0.0; 4]);
        self.mixer
            .actuators_from_wrench(&wrench, &mut f)
            .expect("four rotors");
        for (sp, f) in speeds.iter_mut().zip(f) {
            let x = f / self.k_eta;
            *sp = x.signum() * x.abs().sqrt();
        }
        let desired = So3Mat::<B>::from_matrix_unchecked(ops::from_elems::<B>(pm(r_des)));
        ModeOutput {
            thrust: u1,
            moment: B::vec3(m[0], m[1], m[2]),
            desired,
            desired_omega: B::vec3(0.0, 0.0, 0.0),
            psi: state.r.psi(desired),
            rotor_speeds: RotorSpeeds::new(&speeds),
        }
    }
}

/// A rotor-speed law: its output carries the speeds, and the wrench on
/// the way to them for the logs.
impl Mode<B> for Se3Control {
    fn name(&self) -> &'static str {
        "se3control"
    }
    fn command(
        &self,
        t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        _integrals: &[S<B>],
        _rates: &mut [S<B>],
    ) -> Result<ModeOutput<B>, ControlError> {
        Ok(self.answer(t, state))
    }
}

/// The reference text and where it came from.
fn reference() -> (String, &'static str) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    match testkit::rotorpy_golden(&dir, "rotorpy_closed_loop") {
        (text, true) => (
            text,
            "RotorPy, run now (its wall time measured in this run)",
        ),
        (text, false) => (
            text,
            "the stored golden (rotorpy not importable; its wall time is from when it was made)",
        ),
    }
}

fn se3control_as_a_mode_matches_rotorpy_closed_loop() {
    let (text, source) = reference();
    println!("reference: {source}");
    println!("case    |Δx| m    |Δv| m/s  |ΔR|      |ΔΩ| rad/s |Δω|/ω    wall/sim-s here  RotorPy");
    let mut cases = 0;
    for block in text.split("case ").skip(1) {
        let mut lines = block.lines();
        let name = lines.next().expect("name").trim().to_string();
        let mut rotorpy_wall = f64::NAN;
        let mut want: Vec<Vec<f64>> = Vec::new();
        for l in lines {
            let mut w = l.split_whitespace();
            match w.next() {
                Some("wall_per_sim_s") => {
                    rotorpy_wall = w.next().and_then(|x| x.parse().ok()).unwrap_or(f64::NAN)
                }
                Some("state") => want.push(w.filter_map(|x| x.parse().ok()).collect()),
                _ => {}
            }
        }
        let s0 = &want[0];
        let mut start = RigidBodyState::<B>::at_rest();
        start.x = B::vec3(s0[1], s0[2], s0[3]);
        let traj = if name == "hover" {
            Traj::Hover
        } else {
            Traj::Circle
        };
        let vehicle = Multirotor::new(MultirotorParams::<B>::crazyflie()).expect("preset");
        let sim = Simulation::<B>::builder(Box::new(vehicle))
            .integrator(integrators::Dopri::<B>::new(1e-12))
            .mode(Se3Control::new(traj), Until::Never)
            .initial(start)
            .control(Control::Sampled { rate: 100.0 })
            .dt(0.01)
            .duration(10.0)
            .record_every(0.1)
            .build()
            .expect("build");
        let wall = std::time::Instant::now();
        let out = sim.run(Default::default()).expect("run");
        let wall = wall.elapsed().as_secs_f64() / 10.0;
        assert_eq!(out.samples.len(), want.len(), "{name}: samples");
        let mut worst = [0.0f64; 5];
        for (s, w) in out.samples.iter().zip(&want) {
            let r: Vec<f64> = s.r.iter().flatten().copied().collect();
            let scale = w[19..23].iter().fold(0.0f64, |m, x| m.max(x.abs()));
            let d = [
                (0..3).map(|k| (s.x[k] - w[1 + k]).abs()).fold(0.0, nan_max),
                (0..3).map(|k| (s.v[k] - w[4 + k]).abs()).fold(0.0, nan_max),
                (0..9).map(|k| (r[k] - w[7 + k]).abs()).fold(0.0, nan_max),
                (0..3)
                    .map(|k| (s.omega[k] - w[16 + k]).abs())
                    .fold(0.0, nan_max),
                (0..4)
                    .map(|k| (s.vehicle_states[k] - w[19 + k]).abs() / scale)
                    .fold(0.0, nan_max),
            ];
            for (a, b) in worst.iter_mut().zip(d) {
                *a = a.max(b);
            }
        }
        println!(
            "{name:<7} {:.1e}   {:.1e}   {:.1e}   {:.1e}     {:.1e}   {:.3} ms         {:.0} ms ({:.0}×)",
            worst[0],
            worst[1],
            worst[2],
            worst[3],
            worst[4],
            wall * 1e3,
            rotorpy_wall * 1e3,
            rotorpy_wall / wall
        );
        assert!(worst.iter().all(|e| *e <= 1e-6), "{name}: {worst:?}");
        cases += 1;
    }
    assert_eq!(cases, 2);
}

/// RotorPy's per-seed RMS position errors flying on its motion capture
/// (`golden/rotorpy_mocap.py`), and where they came from.
fn mocap_reference() -> (String, &'static str) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    match testkit::rotorpy_golden(&dir, "rotorpy_mocap") {
        (text, true) => (text, "RotorPy, run now"),
        (text, false) => (text, "the stored golden (rotorpy not importable)"),
    }
}

fn mean_sd(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    (
        m,
        (x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0)).sqrt(),
    )
}

/// Head-on with noise: RotorPy's `Environment(..., sim_rate=100)
/// .run(use_mocap=True)` against this engine flying the same vehicle and
/// law (the mode above) on the `rotorpy` motion capture through the mocap
/// estimator at 100 Hz, hover and circle, 20 seeds each, the rotors of
/// both starting at the first command on the true state. The mean RMS
/// position errors agree within 2·√(s₁²/20 + s₂²/20), the two-sided 95 %
/// band of a difference of two means of 20 (both means and spreads
/// printed).
fn flying_on_mocap_matches_rotorpy_statistically() {
    let (text, source) = mocap_reference();
    println!("reference: {source}");
    let mut cases = 0;
    for line in text.lines().filter(|l| l.starts_with("rms ")) {
        let mut w = line.split_whitespace().skip(1);
        let name = w.next().expect("case");
        let theirs: Vec<f64> = w.map(|x| x.parse().expect("a number")).collect();
        let x0 = if name == "hover" {
            [0.3, -0.2, 0.1]
        } else {
            [1.0, 0.0, 0.0]
        };
        let ours: Vec<f64> = (0..theirs.len() as u64)
            .map(|seed| {
                let traj = || {
                    if name == "hover" {
                        Traj::Hover
                    } else {
                        Traj::Circle
                    }
                };
                let mut start = RigidBodyState::<B>::at_rest();
                let x = p(x0);
                start.x = B::vec3(x[0], x[1], x[2]);
                let vehicle = Multirotor::new(MultirotorParams::<B>::crazyflie()).expect("preset");
                let suite = sensors::SensorSuite {
                    mocap: Some(sensors::MocapSpec::rotorpy(100.0)),
                    ..Default::default()
                };
                // The rotors start at the first command on the true state,
                // as RotorPy's script starts them (the engine would start
                // them at the first command on the noisy estimate: a
                // different transient for each seed).
                let (lo, hi) = (
                    vehicle.params().rotor_speed_min,
                    vehicle.params().rotor_speed_max,
                );
                let first = Se3Control::new(traj()).answer(0.0, start.as_group());
                let w0: Vec<f64> = first
                    .rotor_speeds
                    .expect("a rotor-speed law")
                    .as_slice()
                    .iter()
                    .map(|w| w.clamp(lo, hi))
                    .collect();
                let out = Simulation::<B>::builder(Box::new(vehicle))
                    .vehicle_states(&w0)
                    .integrator(integrators::Dopri::<B>::new(1e-10))
                    .mode(Se3Control::new(traj()), Until::Never)
                    .initial(start)
                    .control(Control::Sampled { rate: 100.0 })
                    .sensors(suite, seed)
                    .estimator(Box::new(sensors::MocapEstimator::<B>::new()))
                    .dt(0.01)
                    .duration(10.0)
                    .record_every(0.01)
                    .build()
                    .expect("build")
                    .run(Default::default())
                    .expect("run");
                let tr = traj();
                let sum: f64 = out
                    .samples
                    .iter()
                    .map(|s| {
                        let d = p(tr.at(s.t).0);
                        (0..3).map(|k| (s.x[k] - d[k]).powi(2)).sum::<f64>()
                    })
                    .sum();
                (sum / out.samples.len() as f64).sqrt()
            })
            .collect();
        let (m1, s1) = mean_sd(&theirs);
        let (m2, s2) = mean_sd(&ours);
        let n = theirs.len() as f64;
        let band = 2.0 * (s1 * s1 / n + s2 * s2 / n).sqrt();
        println!(
            "{name:<7} RotorPy {:.4} ± {:.4} mm, here {:.4} ± {:.4} mm over {} seeds: \
             |Δ| = {:.4} mm, band {:.4} mm",
            m1 * 1e3,
            s1 * 1e3,
            m2 * 1e3,
            s2 * 1e3,
            theirs.len(),
            (m1 - m2).abs() * 1e3,
            band * 1e3
        );
        assert_eq!(theirs.len(), 20);
        assert!((m1 - m2).abs() <= band, "{name}: {m1} vs {m2}, band {band}");
        cases += 1;
    }
    assert_eq!(cases, 2);
}

fn main() {
    testkit::run(&[
        (
            "se3control_as_a_mode_matches_rotorpy_closed_loop",
            se3control_as_a_mode_matches_rotorpy_closed_loop,
        ),
        (
            "flying_on_mocap_matches_rotorpy_statistically",
            flying_on_mocap_matches_rotorpy_statistically,
        ),
    ]);
}
