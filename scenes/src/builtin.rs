//! The built-in scenes.

use std::f64::consts::PI;

use crate::scene::*;
use dynamics::DrydenSpec;

fn base(name: &str, description: &str, duration: f64) -> Scene {
    Scene {
        format: Some(SCENE_FORMAT),
        name: name.into(),
        description: description.into(),
        duration,
        scalar: Scalar::F64,
        backend: BackendKind::Nalgebra,
        vehicle: VehicleSpec::default(),
        disturbance: None,
        wind: None,
        ground: None,
        initial: InitialSpec::default(),
        gains: GainsSpec::default(),
        plan: Vec::new(),
        integrator: IntegratorSpec::default(),
        control: ControlSpec::default(),
        record: RecordSpec::default(),
        seed: 0,
        sensors: None,
        estimator: None,
    }
}

/// One position-mode segment to the end of the run, hover thrust.
fn position_plan(reference: PositionRef) -> Vec<SegmentSpec> {
    vec![SegmentSpec::position(reference)]
}

fn hold(x: [f64; 3], b1d: [f64; 3]) -> PositionRef {
    PositionRef::Hold { x, b1d }
}

/// The paper's numerical example (its Section V): Δ_x, Δ_R from t = 0; attitude
/// mode to 0.4 s flipping about b2 while the heading turns 90°, thrust from
/// the position-PD projection towards x_d = 0; then position mode to 4 s
/// with x_d = 0, b1d = e2. e_I integrates from 0 and carries across the
/// switch; e_i starts at zero at the switch.
pub fn paper_flip() -> Scene {
    let mut s = base(
        "paper-flip",
        "The paper's numerical example: a flip in attitude mode, then position recovery under Δ_x, Δ_R with integral action.",
        4.0,
    );
    s.disturbance = Some(DisturbanceSpec::paper());
    s.plan = vec![
        SegmentSpec::attitude(AttitudeRef::PaperFlip {}, ThrustSpec::PdProjection)
            .toward(hold([0.0; 3], [1.0, 0.0, 0.0]))
            .until(0.4),
        SegmentSpec::position(hold([0.0; 3], [0.0, 1.0, 0.0])),
    ];
    s.integrator.dt = 5e-4;
    s.record.sample = 0.002;
    s
}

/// `paper-flip` with k_I = k_i = 0: a steady-state error remains.
pub fn paper_flip_no_integral() -> Scene {
    let mut s = paper_flip();
    s.name = "paper-flip-no-integral".into();
    s.description = "The paper's flip without integral terms (k_I = k_i = 0): attitude and position settle off target.".into();
    s.gains.k_i = 0.0;
    s.gains.k_att_i = 0.0;
    s
}

/// The paper's hardware test as an attitude-only scene (pinned at the centre
/// of gravity, no stand gravity moment): 3-2-1 Euler angles φ = (π/9) sin πt,
/// θ = (π/9) cos πt, ψ = 0; Δ_R applied; 10 s.
pub fn paper_attitude_experiment() -> Scene {
    let mut s = base(
        "paper-attitude-experiment",
        "The paper's attitude experiment, attitude only: tracking φ = (π/9) sin πt, θ = (π/9) cos πt under Δ_R.",
        10.0,
    );
    s.vehicle.kind = VehicleKind::PinnedQuadrotor;
    s.disturbance = Some(DisturbanceSpec::paper());
    s.plan = vec![SegmentSpec::attitude(
        AttitudeRef::EulerExperiment {
            amplitude: PI / 9.0,
            frequency: PI,
        },
        ThrustSpec::Hover,
    )];
    s.record.sample = 0.005;
    s
}

/// The paper's experiment on its test stand (Section VI): the quadrotor on
/// a spherical joint 5 cm below its centre of gravity (an illustrative
/// height; the paper does not give it), gravity moment compensated in the
/// command as in the paper; Δ_R applied; 10 s.
pub fn paper_attitude_stand() -> Scene {
    let mut s = paper_attitude_experiment();
    s.name = "paper-attitude-stand".into();
    s.description = "The paper's experiment on its test stand: an inverted 3D pendulum (pivot 5 cm below the CG), gravity moment compensated.".into();
    s.vehicle.kind = VehicleKind::AttitudeStand;
    s.vehicle.stand_height = 0.05;
    s.control.compensate_configuration_moment = true;
    s
}

/// Hover at the origin under the paper's disturbances for 150 s: the
/// integral terms converge to Δ_x/k_i and Δ_R/k_I, ‖e_x‖ → 0.
pub fn hover_disturbed() -> Scene {
    let mut s = base(
        "hover-disturbed",
        "Hover under constant Δ_x, Δ_R: the integrals learn the disturbances (e_i → Δ_x/k_i, e_I → Δ_R/k_I).",
        150.0,
    );
    s.disturbance = Some(DisturbanceSpec::paper());
    s.plan = position_plan(hold([0.0; 3], [1.0, 0.0, 0.0]));
    s.integrator.dt = 2e-3;
    s.record.sample = 0.05;
    s
}

/// Attitude mode from a 170° error (Ψ(0) = 1 − cos 170° = 1.985 > 1,
/// Proposition 3's region), no disturbance; Ψ → 0.
pub fn large_attitude_error() -> Scene {
    let mut s = base(
        "large-attitude-error",
        "Attitude recovery from a 170° error (Ψ(0) = 1.985 > 1, Proposition 3).",
        20.0,
    );
    s.vehicle.kind = VehicleKind::PinnedQuadrotor;
    let a = 170f64.to_radians() / 2f64.sqrt();
    s.initial.rotation = [a, a, 0.0];
    s.plan = vec![SegmentSpec::attitude(
        AttitudeRef::Hold { rotation: [0.0; 3] },
        ThrustSpec::Hover,
    )];
    s.record.sample = 0.01;
    s
}

/// Tumble recovery with the hybrid scheduler: the free quadrotor starts
/// 170° off upright; attitude mode (hover thrust) rights it until
/// Ψ < 0.1, a Ψ-triggered switch located to rounding, then position mode
/// brings it back to the origin. Δ_x, Δ_R applied.
pub fn tumble_recovery() -> Scene {
    let mut s = base(
        "tumble-recovery",
        "Hybrid scheduler: recover from 170° in attitude mode until Ψ < 0.1, then return to the origin in position mode.",
        10.0,
    );
    s.disturbance = Some(DisturbanceSpec::paper());
    let a = 170f64.to_radians() / 2f64.sqrt();
    s.initial.rotation = [a, a, 0.0];
    s.plan = vec![
        SegmentSpec::attitude(AttitudeRef::Hold { rotation: [0.0; 3] }, ThrustSpec::Hover)
            .until_psi(0.1),
        SegmentSpec::position(hold([0.0; 3], [1.0, 0.0, 0.0])),
    ];
    s.integrator.dt = 5e-4;
    s.record.sample = 0.005;
    s
}

/// Position tracking of a figure eight with every derivative up to snap,
/// under the paper's disturbances, from rest at its centre.
pub fn figure_eight() -> Scene {
    let mut s = base(
        "figure-eight",
        "Tracking a Lissajous figure eight (x_d to its 4th derivative) under Δ_x, Δ_R.",
        20.0,
    );
    s.disturbance = Some(DisturbanceSpec::paper());
    s.initial.x = [0.0, 0.0, -1.0];
    s.plan = position_plan(PositionRef::FigureEight {
        center: [0.0, 0.0, -1.0],
        a: 1.0,
        b: 0.5,
        omega: 1.0,
    });
    s.record.sample = 0.01;
    s
}

/// A climbing square: a minimum-snap trajectory through five waypoints at
/// a mean 1 m/s, 1 m higher at the end, the heading turning a full circle
/// with the legs, under the paper's disturbances, from rest at the first
/// waypoint.
pub fn waypoints_square_climb() -> Scene {
    let mut s = base(
        "waypoints-square-climb",
        "A minimum-snap trajectory through a climbing 2 m square, the heading turning with the legs, under Δ_x, Δ_R.",
        11.0,
    );
    s.disturbance = Some(DisturbanceSpec::paper());
    s.initial.x = [0.0, 0.0, -1.0];
    s.plan = position_plan(PositionRef::MinSnap {
        waypoints: vec![
            [0.0, 0.0, -1.0],
            [2.0, 0.0, -1.25],
            [2.0, 2.0, -1.5],
            [0.0, 2.0, -1.75],
            [0.0, 0.0, -2.0],
        ],
        yaw: Some(vec![0.0, 0.5 * PI, PI, 1.5 * PI, 2.0 * PI]),
        times: None,
        mean_speed: Some(1.0),
        time_budget: None,
        start: 0.0,
    });
    s.record.sample = 0.01;
    s
}

/// A whole flight from the ground and back: resting on four feet at the
/// start, a take-off of 1 m at 0.5 m/s, a minimum-snap loop around a 1.5 m
/// square at 1 m/s, a landing at 0.3 m/s, and the motors cut once every
/// foot is down; a touchdown faster than 0.5 m/s would end the run as a
/// crash.
/// RK4 at 1 ms (the contact's frequency is 730 rad/s).
pub fn mission_takeoff_waypoints_land() -> Scene {
    let mut s = base(
        "mission-takeoff-waypoints-land",
        "Take-off from the ground, a minimum-snap loop around a square, landing, motors off once every foot is down.",
        20.0,
    );
    let ground = GroundSpec {
        crash_speed: 0.5,
        ..GroundSpec::default()
    };
    // At rest on the default feet (0.1 m below the centre of mass), each
    // pressed mg/(4k) into the ground.
    let rest = ground.height - 0.1 + s.vehicle.mass * s.vehicle.gravity / (4.0 * ground.stiffness);
    s.ground = Some(ground);
    s.initial.x = [0.0, 0.0, rest];
    let z = rest - 1.0;
    let mut take_off = SegmentSpec::phase(ModeKind::TakeOff).until(6.0);
    (take_off.height, take_off.rate) = (Some(1.0), Some(0.5));
    let mut land = SegmentSpec::phase(ModeKind::Land).until_clearance(0.0);
    land.rate = Some(0.3);
    s.plan = vec![
        take_off,
        SegmentSpec::position(PositionRef::MinSnap {
            waypoints: vec![
                [0.0, 0.0, z],
                [1.5, 0.0, z],
                [1.5, 1.5, z],
                [0.0, 1.5, z],
                [0.0, 0.0, z],
            ],
            yaw: None,
            times: None,
            mean_speed: Some(1.0),
            time_budget: None,
            start: 6.0,
        })
        .until(13.0),
        land,
        SegmentSpec::phase(ModeKind::MotorsOff),
    ];
    s.integrator.kind = "rk4".into();
    s.integrator.dt = 1e-3;
    s.record.sample = 0.01;
    s
}

/// DiffTune's quadrotor tuning problem (Cheng et al., T-RO 2024, and its
/// open code): a 4.34 kg vehicle, J = diag(0.0820, 0.0845, 0.1377) kg m²,
/// from rest at the origin (Ω(0) = 0.001 e3 rad/s) on the circle
/// x_d = (2(1 − cos t), 2 sin t, 0.1 sin t), b1d = e1, for 10 s; their
/// starting gains k_x = 16, k_v = 5.6, k_R = 8.81, k_Ω = 2.54 and no
/// integral terms; control held over each 2.5 ms step, RK4 at that step
/// (theirs: ode45 at 1e-6 between the control instants).
pub fn difftune_circle() -> Scene {
    let mut s = base(
        "difftune-circle",
        "DiffTune's gain-tuning problem: a 4.34 kg quadrotor from rest onto a 2 m circle, their starting gains, no integral terms.",
        10.0,
    );
    s.vehicle.mass = 4.34;
    s.vehicle.inertia = [0.0820, 0.0845, 0.1377];
    s.initial.omega = [0.0, 0.0, 0.001];
    s.plan = position_plan(PositionRef::Sinusoids {
        center: [2.0, 0.0, 0.0],
        amplitude: [2.0, 2.0, 0.1],
        omega: [1.0; 3],
        phase: [-std::f64::consts::FRAC_PI_2, 0.0, 0.0],
    });
    s.gains.k_x = 16.0;
    s.gains.k_v = 5.6;
    s.gains.k_r = 8.81;
    s.gains.k_omega = 2.54;
    s.gains.k_i = 0.0;
    s.gains.k_att_i = 0.0;
    s.integrator.kind = "rk4".into();
    s.integrator.dt = 0.0025;
    s.control.timing = Timing::Sampled;
    s.control.rate = 400.0;
    s.record.sample = 0.0025;
    s
}

/// The torque-free body J = diag(1, 2, 3) with the integrator tests' start,
/// no controller; energy and spatial momentum are conserved and the exact
/// solution is known.
pub fn free_rigid_body() -> Scene {
    let mut s = base(
        "free-rigid-body",
        "A torque-free rigid body (J = diag(1,2,3)), no controller: invariants and the exact solution.",
        100.0,
    );
    s.vehicle.kind = VehicleKind::FreeRigidBody;
    s.vehicle.inertia = [1.0, 2.0, 3.0];
    s.vehicle.mass = 1.0;
    s.vehicle.gravity = 0.0;
    s.initial.rotation = [0.3, -0.5, 0.2];
    s.initial.omega = [0.4, -0.8, -1.1];
    s.integrator.kind = "lgvi".into();
    s.integrator.dt = 0.01;
    s.record.sample = 0.1;
    s
}

/// RotorPy's crazyflie (30 g, rotor drag and inflow, 72 ms motors) with
/// the gains of RotorPy's `SE3Control` per unit mass and inertia
/// (`k_x = 6.5 m`, `k_v = 4 m`, `k_R = 310 J₁₁`, `k_Ω = 57 J₁₁`) and
/// integral gains at the paper's ratios (`k_i = 0.1 k_x`, `k_I = 0.1 k_R`);
/// RK4 at 1 ms (the motors' 72 ms and the turbulence's 5 ms noise grid
/// are both resolved).
fn crazyflie(name: &str, description: &str, duration: f64) -> Scene {
    let mut s = base(name, description, duration);
    let (m, j) = (0.03, [1.43e-5, 1.43e-5, 2.89e-5]);
    s.vehicle.kind = VehicleKind::Multirotor;
    s.vehicle.mass = m;
    s.vehicle.inertia = j;
    // RotorPy's identified J3 exceeds J1 + J2 (2.89e-5 > 2.86e-5).
    s.vehicle.allow_nonphysical_inertia = true;
    s.vehicle.gravity = 9.81;
    s.vehicle.arm = 0.043;
    s.vehicle.multirotor = Some(MultirotorSpec::default());
    s.gains.k_x = 6.5 * m;
    s.gains.k_v = 4.0 * m;
    s.gains.k_r = 310.0 * j[0];
    s.gains.k_omega = 57.0 * j[0];
    // 0.1 k_x and 0.1 k_R, written out so that a scene file can state
    // them exactly.
    s.gains.k_i = 0.0195;
    s.gains.k_att_i = 0.0004433;
    s.integrator.dt = 1e-3;
    s.record.sample = 0.01;
    s
}

/// The crazyflie holding the origin in Dryden turbulence (σ = 1 m/s, no
/// mean wind): the integral terms against a disturbance that is not
/// constant.
pub fn gusty_hover() -> Scene {
    let mut s = crazyflie(
        "gusty-hover",
        "RotorPy's crazyflie holding the origin in Dryden turbulence, σ = 1 m/s (rotor drag, 72 ms motors).",
        20.0,
    );
    s.wind = Some(WindSpec::dryden(DrydenSpec::gusty()));
    s.initial.x = [0.0, 0.0, -1.0];
    s.plan = position_plan(hold([0.0, 0.0, -1.0], [1.0, 0.0, 0.0]));
    s
}

/// The crazyflie on the figure eight in a 3 m/s wind along e1 with Dryden
/// gusts (σ = 1 m/s) on top: a mean drag the integral terms can learn,
/// and turbulence they cannot.
pub fn figure_eight_wind() -> Scene {
    let mut s = crazyflie(
        "figure-eight-wind",
        "RotorPy's crazyflie on a figure eight in a 3 m/s wind with Dryden gusts (σ = 1 m/s).",
        20.0,
    );
    // The mean wind sets the airspeed the turbulence is shaped at.
    s.wind = Some(WindSpec::dryden(DrydenSpec {
        mean: [3.0, 0.0, 0.0],
        speed: 3.0,
        ..DrydenSpec::gusty()
    }));
    s.initial.x = [0.0, 0.0, -1.0];
    s.plan = position_plan(PositionRef::FigureEight {
        center: [0.0, 0.0, -1.0],
        a: 1.0,
        b: 0.5,
        omega: 1.0,
    });
    s
}

/// `s` flown on an estimate: the Crazyflie's BMI088 at 1 kHz and motion
/// capture at 100 Hz (σ 1 cm, 4.5 mrad) on time, the invariant EKF at
/// every 1 kHz control instant, RK4 at 1 ms.
fn estimated(mut s: Scene, name: &str, description: &str) -> Scene {
    s.name = name.into();
    s.description = description.into();
    s.control = ControlSpec {
        timing: Timing::Sampled,
        rate: 1000.0,
        ..ControlSpec::default()
    };
    s.integrator.dt = 1e-3;
    s.sensors = Some(SensorsSpec {
        mocap_latency: Some(0.0),
        ..SensorsSpec::preset("crazyflie")
    });
    s.estimator = Some(EstimatorSpec {
        kind: EstimatorKind::Iekf,
        ..EstimatorSpec::default()
    });
    s.seed = 1;
    s
}

/// Hover under the paper's disturbances for 30 s, flown on the invariant
/// EKF's estimate from the IMU and motion capture.
pub fn hover_estimated() -> Scene {
    let mut s = estimated(
        hover_disturbed(),
        "hover-estimated",
        "Hover under Δ_x, Δ_R on the invariant EKF (BMI088 at 1 kHz, mocap at 100 Hz).",
    );
    s.duration = 30.0;
    s.record.sample = 0.01;
    s
}

/// The figure eight flown on the invariant EKF's estimate.
pub fn figure_eight_estimated() -> Scene {
    estimated(
        figure_eight(),
        "figure-eight-estimated",
        "The figure eight under Δ_x, Δ_R on the invariant EKF (BMI088 at 1 kHz, mocap at 100 Hz).",
    )
}

/// Tumble recovery on an estimate that starts 90° wrong: the Ψ switch
/// reads the estimate, as a flight computer's scheduler would.
pub fn tumble_recovery_estimated() -> Scene {
    let mut s = estimated(
        tumble_recovery(),
        "tumble-recovery-estimated",
        "Tumble recovery from 170° on the invariant EKF, its initial attitude 90° wrong; the Ψ switch reads the estimate.",
    );
    s.estimator = Some(EstimatorSpec {
        kind: EstimatorKind::Iekf,
        attitude_error: Some([PI / 2.0, 0.0, 0.0]),
        ..EstimatorSpec::default()
    });
    s
}

/// Every built-in scene.
pub fn all() -> Vec<Scene> {
    vec![
        paper_flip(),
        paper_flip_no_integral(),
        paper_attitude_experiment(),
        paper_attitude_stand(),
        hover_disturbed(),
        large_attitude_error(),
        tumble_recovery(),
        figure_eight(),
        free_rigid_body(),
        gusty_hover(),
        figure_eight_wind(),
        difftune_circle(),
        waypoints_square_climb(),
        mission_takeoff_waypoints_land(),
        hover_estimated(),
        figure_eight_estimated(),
        tumble_recovery_estimated(),
    ]
}

/// The built-in scene called `name`.
pub fn by_name(name: &str) -> Option<Scene> {
    all().into_iter().find(|s| s.name == name)
}
