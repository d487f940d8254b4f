//! The hybrid flight-mode scheduler (Section V of the paper): a plan of
//! segments, each an attitude-mode or position-mode law with its reference
//! source, left when a time is reached or when `Ψ` falls below a threshold
//! (Proposition 3: a large attitude error is first reduced in attitude
//! mode, then position mode takes over).
//!
//! The plan is a borrowed slice and the reference sources are borrowed
//! closures, so the scheduler needs no heap (`no_std`). The integral states
//! stay the caller's; the scheduler only resets the position integral
//! `e_i` to zero when position mode is entered for the first time, and
//! leaves the attitude integral `e_I` to carry across every switch.

use crate::position_pid::{
    PositionReference, VehicleState, position_control, thrust_pd_projection,
};
use crate::vec::zero;
use crate::{
    AccelerationModel, AttitudeGains, AttitudeReference, ControlError, PositionGains,
    RigidBodyParams, attitude_control,
};
use lie::{Backend, Rotation, S, V3};

/// The thrust of an attitude-mode segment.
#[derive(Copy, Clone)]
pub enum ThrustCommand<'a, B: Backend> {
    /// A constant thrust, e.g. `m g`.
    Constant(S<B>),
    /// The position-PD projection `(k_x e_x + k_v e_v + m g e3 − m ẍ_d)·R e3`
    /// towards this position reference (the paper's flip).
    PdProjection(&'a dyn Fn(S<B>) -> PositionReference<B>),
}

/// A flight mode with its reference source, a function of time.
#[derive(Copy, Clone)]
pub enum FlightMode<'a, B: Backend, R: Rotation<B>> {
    /// Attitude mode (eqn:aM) tracking `R_d(t)`.
    Attitude {
        /// `t ↦ (R_d, Ω_d, Ω̇_d)`.
        reference: &'a dyn Fn(S<B>) -> AttitudeReference<B, R>,
        /// How the thrust is chosen.
        thrust: ThrustCommand<'a, B>,
    },
    /// Position mode (eqn:f, eqn:M) tracking `x_d(t)`, `b1d(t)`.
    Position {
        /// `t ↦ (x_d … x_d⁽⁴⁾, b1d, ḃ1d, b̈1d)`.
        reference: &'a dyn Fn(S<B>) -> PositionReference<B>,
    },
}

/// When a segment ends.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum SwitchWhen<B: Backend> {
    /// At this time (s): the segment is left at the first update with
    /// `t ≥` it. A simulation should land a step exactly on it.
    Time(S<B>),
    /// When `Ψ` against the segment's desired attitude drops below this.
    PsiBelow(S<B>),
    /// Never (the last segment).
    Never,
}

/// One segment of a plan.
#[derive(Copy, Clone)]
pub struct Segment<'a, B: Backend, R: Rotation<B>> {
    /// The law and its reference.
    pub mode: FlightMode<'a, B, R>,
    /// When it ends.
    pub until: SwitchWhen<B>,
}

/// The controller's integral states, held by the caller.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct IntegralStates<B: Backend> {
    /// `e_I` (attitude), carried across every switch.
    pub e_att: V3<B>,
    /// `e_i` (position), reset to zero when position mode first starts.
    pub e_pos: V3<B>,
}

impl<B: Backend> IntegralStates<B> {
    /// Both integrals zero.
    pub fn zero() -> Self {
        Self {
            e_att: zero::<B>(),
            e_pos: zero::<B>(),
        }
    }
}

/// A mode switch, for the caller to report.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Switch<B: Backend> {
    /// Segment index left.
    pub from: usize,
    /// Segment index entered.
    pub to: usize,
    /// Time of the update at which it happened.
    pub t: S<B>,
}

/// What the active law commands, with the rates of the integral states.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ControlCommand<B: Backend, R: Rotation<B>> {
    /// Total thrust `f`.
    pub thrust: S<B>,
    /// Moment `M`.
    pub moment: V3<B>,
    /// The desired attitude in use (`R_d` or `R_c`).
    pub desired: R,
    /// Its angular velocity: `Ω_d` in attitude mode, `Ω_c` in position mode.
    pub desired_omega: V3<B>,
    /// `Ψ` against it.
    pub psi: S<B>,
    /// `ė_I`.
    pub e_att_rate: V3<B>,
    /// `ė_i` (zero in attitude mode: the position integral is idle there).
    pub e_pos_rate: V3<B>,
    /// Index of the active segment.
    pub segment: usize,
    /// Whether the active segment is in position mode.
    pub position_mode: bool,
}

/// Steps through a plan of segments.
pub struct Scheduler<'a, B: Backend, R: Rotation<B>> {
    plan: &'a [Segment<'a, B, R>],
    active: usize,
    position_started: bool,
    last_psi: Option<S<B>>,
}

impl<'a, B: Backend, R: Rotation<B>> Scheduler<'a, B, R> {
    /// Starts at the first segment. An empty plan is reported as
    /// [`ControlError::EmptyPlan`] by [`Scheduler::command`].
    pub fn new(plan: &'a [Segment<'a, B, R>]) -> Self {
        Self {
            plan,
            active: 0,
            position_started: false,
            last_psi: None,
        }
    }

    /// Index of the active segment.
    pub fn active(&self) -> usize {
        self.active
    }

    /// Leaves the active segment if its condition holds at time `t` (for
    /// `PsiBelow`, with the `Ψ` of the latest command). Entering position
    /// mode for the first time zeroes `integrals.e_pos`. Returns the switch,
    /// if any (at most one per call, so each is reported).
    pub fn advance(&mut self, t: S<B>, integrals: &mut IntegralStates<B>) -> Option<Switch<B>> {
        let seg = self.plan.get(self.active)?;
        let leave = match seg.until {
            SwitchWhen::Time(ts) => t >= ts,
            SwitchWhen::PsiBelow(th) => self.last_psi.is_some_and(|p| p < th),
            SwitchWhen::Never => false,
        };
        if !leave || self.active + 1 >= self.plan.len() {
            return None;
        }
        let from = self.active;
        self.active += 1;
        self.last_psi = None;
        if matches!(self.plan[self.active].mode, FlightMode::Position { .. })
            && !self.position_started
        {
            self.position_started = true;
            integrals.e_pos = zero::<B>();
        }
        Some(Switch {
            from,
            to: self.active,
            t,
        })
    }

    /// The active law's command at time `t`.
    #[allow(clippy::too_many_arguments)]
    pub fn command(
        &mut self,
        params: &RigidBodyParams<B>,
        pos_gains: &PositionGains<B>,
        att_gains: &AttitudeGains<B>,
        t: S<B>,
        state: &VehicleState<B, R>,
        integrals: &IntegralStates<B>,
        model: AccelerationModel<B>,
    ) -> Result<ControlCommand<B, R>, ControlError> {
        let seg = self.plan.get(self.active).ok_or(ControlError::EmptyPlan)?;
        let cmd = match seg.mode {
            FlightMode::Attitude { reference, thrust } => {
                let r = reference(t);
                let out =
                    attitude_control(params, att_gains, state.r, state.omega, integrals.e_att, &r)?;
                let f = match thrust {
                    ThrustCommand::Constant(f) => f,
                    ThrustCommand::PdProjection(pref) => {
                        thrust_pd_projection(params, pos_gains, state, &pref(t))
                    }
                };
                ControlCommand {
                    thrust: f,
                    moment: out.moment,
                    desired: r.rd,
                    desired_omega: r.omega_d,
                    psi: out.psi,
                    e_att_rate: out.e_i_rate,
                    e_pos_rate: zero::<B>(),
                    segment: self.active,
                    position_mode: false,
                }
            }
            FlightMode::Position { reference } => {
                let out = position_control(
                    params,
                    pos_gains,
                    att_gains,
                    state,
                    integrals.e_pos,
                    integrals.e_att,
                    &reference(t),
                    model,
                )?;
                ControlCommand {
                    thrust: out.thrust,
                    moment: out.moment,
                    desired: out.rc,
                    desired_omega: out.omega_c,
                    psi: out.psi,
                    e_att_rate: out.e_i_att_rate,
                    e_pos_rate: out.e_i_pos_rate,
                    segment: self.active,
                    position_mode: true,
                }
            }
        };
        self.last_psi = Some(cmd.psi);
        Ok(cmd)
    }
}
