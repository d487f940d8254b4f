//! The heap-free flight-mode scheduler on the paper's flip plan (attitude
//! mode until 0.4 s, then position mode) and on a Ψ-triggered switch.
//!
//! One pair (nalgebra-f64): the scheduler is switching logic (times,
//! thresholds, what `enter` zeroes), which no backend arithmetic touches.

use controllers::*;
use dynamics::paper;
use lie::{NalgebraF64 as B, So3Mat};
use nalgebra::Vector3;

type V = Vector3<f64>;
type R = So3Mat<B>;

fn flip(t: f64) -> AttitudeReference<B, R> {
    use std::f64::consts::PI;
    // R_d = exp(π t e3^) exp(4π t e2^); Ω_d = R_yᵀ π e3 + 4π e2 (body frame).
    let ry = R::exp(V::y() * (4.0 * PI * t));
    let rd = R::exp(V::z() * (PI * t)) * ry;
    AttitudeReference {
        rd,
        omega_d: ry.inverse_act(V::z() * PI) + V::y() * (4.0 * PI),
        omega_d_dot: V::zeros(),
    }
}

fn hold() -> HoldPosition<B> {
    HoldPosition(PositionReference::hold(V::zeros(), V::y()))
}

fn position_mode() -> PositionMode<B, HoldPosition<B>> {
    PositionMode::new(
        RigidBodyParams::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        PositionGains::paper(),
        AttitudeGains::paper(),
        AccelerationModel::Nominal,
        hold(),
    )
}

fn state(r: R) -> VehicleState<B, R> {
    VehicleState {
        x: V::new(0.1, 0.0, 0.0),
        v: V::zeros(),
        r,
        omega: V::zeros(),
    }
}

#[test]
fn time_switch_carries_e_att_and_resets_e_pos() {
    let p = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let mut att = AttitudeMode::new(
        p,
        AttitudeGains::paper(),
        flip,
        AttitudeThrust::PdProjection {
            gains: PositionGains::paper(),
            reference: hold(),
        },
    );
    let mut pos = position_mode();
    let mut plan = [
        Phase {
            mode: &mut att,
            until: Until::Time(0.4),
        },
        Phase {
            mode: &mut pos,
            until: Until::Never,
        },
    ];
    let mut sched = Scheduler::new(&mut plan).unwrap();
    assert_eq!(sched.integral_count(), 6);
    let st = state(R::identity());
    // Integrals as if they had been running: e_i holds junk that the
    // position mode must clear when it is entered.
    let mut ints = [0.3, -0.1, 0.2, 9.0, 9.0, 9.0];
    let mut rates = [1.0; 6];
    let mut switches = Vec::new();
    for k in 0..=100 {
        let t = k as f64 * 0.01; // 0.40 lands exactly at k = 40
        if let Some(sw) = sched.advance(t, &st, &mut ints) {
            switches.push(sw);
        }
        let cmd = sched.command(t, &st, &ints, &mut rates).unwrap();
        assert_eq!(sched.active() == 1, t >= 0.4, "t = {t}");
        if t < 0.4 {
            assert_eq!(
                rates[3..],
                [0.0; 3],
                "position integral idle in attitude mode"
            );
            // PD-projection thrust: (k_x x + m g e3)·R e3 with R = I.
            assert!((cmd.thrust - 0.755 * 9.81).abs() < 1e-12);
        }
    }
    assert_eq!(
        switches,
        vec![Switch {
            from: 0,
            to: 1,
            t: 0.4
        }]
    );
    assert_eq!(ints[3..], [0.0; 3]);
    assert_eq!(ints[..3], [0.3, -0.1, 0.2], "e_I carried across the switch");
}

#[test]
fn psi_switch_waits_for_the_attitude_error() {
    let p = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let mut att = AttitudeMode::<B, _, HoldPosition<B>>::new(
        p,
        AttitudeGains::paper(),
        HoldAttitude::new(R::identity()),
        AttitudeThrust::Constant(0.755 * 9.81),
    );
    let mut pos = position_mode();
    let mut plan = [
        Phase {
            mode: &mut att,
            until: Until::PsiBelow(0.01),
        },
        Phase {
            mode: &mut pos,
            until: Until::Never,
        },
    ];
    let mut sched = Scheduler::new(&mut plan).unwrap();
    let (tilted, level) = (state(R::exp(V::x() * 1.0)), state(R::identity()));
    let (mut ints, mut rates) = ([0.0; 6], [0.0; 6]);
    assert!(
        sched.advance(0.0, &tilted, &mut ints).is_none(),
        "no Ψ known yet"
    );
    let c = sched.command(0.0, &tilted, &ints, &mut rates).unwrap();
    assert!((c.psi - (1.0 - 1f64.cos())).abs() < 1e-12 && (c.thrust - 0.755 * 9.81).abs() < 1e-15);
    assert!(
        sched.advance(0.1, &tilted, &mut ints).is_none(),
        "Ψ = 0.46 is not below 0.01"
    );
    sched.command(0.1, &level, &ints, &mut rates).unwrap();
    assert_eq!(
        sched.advance(0.2, &level, &mut ints),
        Some(Switch {
            from: 0,
            to: 1,
            t: 0.2
        })
    );
    sched.command(0.2, &level, &ints, &mut rates).unwrap();
    assert_eq!(sched.active(), 1);
    assert!(
        sched.advance(5.0, &level, &mut ints).is_none(),
        "the last phase never ends"
    );
}

#[test]
fn empty_plan_is_an_error() {
    let mut plan: [Phase<B>; 0] = [];
    assert_eq!(
        Scheduler::new(&mut plan).err(),
        Some(ControlError::EmptyPlan)
    );
}

/// What a scheduler asks of the paper's modes besides their command: both
/// command a wrench (not rotor speeds), and the position mode reports its
/// reference's position as the desired position at any time (the log's
/// x_d); the attitude mode reports its thrust law's held position, and
/// none under a constant thrust.
#[test]
fn the_papers_modes_command_wrenches_and_report_their_reference_position() {
    let circle = |t: f64| {
        let x = V::new(t.cos(), 2.0 * t.sin(), -0.5 * t);
        PositionReference::hold(x, V::y())
    };
    let pos = PositionMode::new(
        RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        PositionGains::paper(),
        AttitudeGains::paper(),
        AccelerationModel::Nominal,
        circle,
    );
    let att = AttitudeMode::new(
        RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        AttitudeGains::paper(),
        flip,
        AttitudeThrust::PdProjection {
            gains: PositionGains::paper(),
            reference: hold(),
        },
    );
    for t in [0.0f64, 0.7, 2.5] {
        let want = [t.cos(), 2.0 * t.sin(), -0.5 * t];
        assert_eq!(
            Mode::<B, R>::desired_position(&pos, t),
            Some(want),
            "t = {t}"
        );
    }
    assert_eq!(Mode::<B, R>::desired_position(&att, 1.0), Some([0.0; 3]));
    let constant = AttitudeMode::<B, _, HoldPosition<B>>::new(
        RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        AttitudeGains::paper(),
        flip,
        AttitudeThrust::Constant(7.4),
    );
    assert_eq!(Mode::<B, R>::desired_position(&constant, 1.0), None);
}
