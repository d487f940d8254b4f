//! The flight-mode scheduler on the paper's flip plan: attitude mode until
//! 0.4 s, then position mode; and a Ψ-triggered switch.
//!
//! One pair (nalgebra-f64): the scheduler is switching logic (times,
//! thresholds, what `enter` zeroes), which no backend arithmetic touches.

use controllers::*;
use lie::{NalgebraF64 as B, Rotation, So3Mat};
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
fn hold(_t: f64) -> PositionReference<B> {
    PositionReference::hold(V::zeros(), V::y())
}

#[test]
fn time_switch_carries_e_att_and_resets_e_pos() {
    let (p, pg, ag) = (
        RigidBodyParams::<B>::paper(),
        PositionGains::<B>::paper(),
        AttitudeGains::<B>::paper(),
    );
    let plan = [
        Segment {
            mode: FlightMode::Attitude {
                reference: &flip,
                thrust: ThrustCommand::PdProjection(&hold),
            },
            until: SwitchWhen::Time(0.4),
        },
        Segment {
            mode: FlightMode::Position { reference: &hold },
            until: SwitchWhen::Never,
        },
    ];
    let mut sched = Scheduler::new(&plan);
    let state = VehicleState {
        x: V::new(0.1, 0.0, 0.0),
        v: V::zeros(),
        r: R::identity(),
        omega: V::zeros(),
    };
    // Integrals as if they had been running: e_pos holds junk that must be
    // cleared at the first entry into position mode.
    let mut ints = IntegralStates {
        e_att: V::new(0.3, -0.1, 0.2),
        e_pos: V::new(9.0, 9.0, 9.0),
    };
    let mut switches = Vec::new();
    for k in 0..=100 {
        let t = k as f64 * 0.01; // 0.40 lands exactly at k = 40
        if let Some(sw) = sched.advance(t, &mut ints) {
            switches.push(sw);
        }
        let cmd = sched
            .command(&p, &pg, &ag, t, &state, &ints, AccelerationModel::Nominal)
            .unwrap();
        assert_eq!(cmd.position_mode, t >= 0.4, "t = {t}");
        if !cmd.position_mode {
            assert_eq!(
                cmd.e_pos_rate,
                V::zeros(),
                "position integral idle in attitude mode"
            );
            // PD-projection thrust: (k_x x + m g e3)·R e3 with R = I.
            assert!((cmd.thrust - 0.755 * 9.81).abs() < 1e-12);
        }
    }
    println!("switches: {switches:?}");
    assert_eq!(
        switches,
        vec![Switch {
            from: 0,
            to: 1,
            t: 0.4
        }]
    );
    assert_eq!(ints.e_pos, V::zeros());
    assert_eq!(
        ints.e_att,
        V::new(0.3, -0.1, 0.2),
        "e_I carried across the switch"
    );
}

#[test]
fn psi_switch_waits_for_the_attitude_error() {
    let (p, pg, ag) = (
        RigidBodyParams::<B>::paper(),
        PositionGains::<B>::paper(),
        AttitudeGains::<B>::paper(),
    );
    let level = |_t: f64| AttitudeReference::<B, R> {
        rd: R::identity(),
        omega_d: V::zeros(),
        omega_d_dot: V::zeros(),
    };
    let plan = [
        Segment {
            mode: FlightMode::Attitude {
                reference: &level,
                thrust: ThrustCommand::Constant(0.755 * 9.81),
            },
            until: SwitchWhen::PsiBelow(0.01),
        },
        Segment {
            mode: FlightMode::Position { reference: &hold },
            until: SwitchWhen::Never,
        },
    ];
    let mut sched = Scheduler::new(&plan);
    let mut ints = IntegralStates::zero();
    let tilted = VehicleState {
        x: V::zeros(),
        v: V::zeros(),
        r: R::exp(V::x() * 1.0),
        omega: V::zeros(),
    };
    let level_state = VehicleState {
        r: R::identity(),
        ..tilted
    };
    assert!(sched.advance(0.0, &mut ints).is_none(), "no Ψ known yet");
    let c = sched
        .command(
            &p,
            &pg,
            &ag,
            0.0,
            &tilted,
            &ints,
            AccelerationModel::Nominal,
        )
        .unwrap();
    assert!((c.psi - (1.0 - 1f64.cos())).abs() < 1e-12 && (c.thrust - 0.755 * 9.81).abs() < 1e-15);
    assert!(
        sched.advance(0.1, &mut ints).is_none(),
        "Ψ = 0.46 is not below 0.01"
    );
    sched
        .command(
            &p,
            &pg,
            &ag,
            0.1,
            &level_state,
            &ints,
            AccelerationModel::Nominal,
        )
        .unwrap();
    assert_eq!(
        sched.advance(0.2, &mut ints),
        Some(Switch {
            from: 0,
            to: 1,
            t: 0.2
        })
    );
    assert!(
        sched
            .command(
                &p,
                &pg,
                &ag,
                0.2,
                &level_state,
                &ints,
                AccelerationModel::Nominal
            )
            .unwrap()
            .position_mode
    );
    assert!(
        sched.advance(5.0, &mut ints).is_none(),
        "the last segment never ends"
    );
}

#[test]
fn empty_plan_is_an_error() {
    let (p, pg, ag) = (
        RigidBodyParams::<B>::paper(),
        PositionGains::<B>::paper(),
        AttitudeGains::<B>::paper(),
    );
    let plan: [Segment<B, R>; 0] = [];
    let mut sched = Scheduler::new(&plan);
    let st = VehicleState {
        x: V::zeros(),
        v: V::zeros(),
        r: R::identity(),
        omega: V::zeros(),
    };
    let err = sched
        .command(
            &p,
            &pg,
            &ag,
            0.0,
            &st,
            &IntegralStates::zero(),
            AccelerationModel::Nominal,
        )
        .unwrap_err();
    assert_eq!(err, ControlError::EmptyPlan);
}
