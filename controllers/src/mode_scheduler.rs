//! The hybrid flight-mode scheduler (Section V of the paper) for a flight
//! computer: a plan of phases, each a [`Mode`] left when a time is reached
//! or when `Ψ` falls below a threshold (Proposition 3: a large attitude
//! error is first reduced in attitude mode, then position mode takes over).
//!
//! The plan is a borrowed slice of borrowed modes and the integral
//! register stays the caller's, so the scheduler needs no heap (`no_std`).
//! What carries across a switch is the entered mode's choice
//! ([`Mode::enter`]: the paper's position mode zeroes `e_i` on entry, its
//! attitude mode keeps `e_I`). A simulation does the same with located
//! switch times; this is the sampled version: call [`Scheduler::advance`]
//! then [`Scheduler::command`] at each control instant and integrate the
//! rates yourself.

use crate::ControlError;
use crate::mode::{Mode, ModeOutput};
use crate::position_pid::VehicleState;
use lie::{Backend, Real, S, So3Mat};

/// When a phase ends.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Leave<B: Backend> {
    /// At this time (s): the phase is left at the first
    /// [`Scheduler::advance`] with `t ≥` it.
    At(S<B>),
    /// When `Ψ` of the latest command drops below this.
    PsiBelow(S<B>),
    /// Never (the last phase).
    Never,
}

/// One phase of a plan: a mode and when it ends.
pub struct Phase<'m, B: Backend> {
    /// The law.
    pub mode: &'m mut dyn Mode<B>,
    /// When it ends.
    pub until: Leave<B>,
}

/// A mode switch, for the caller to report.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Switch<B: Backend> {
    /// Phase index left.
    pub from: usize,
    /// Phase index entered.
    pub to: usize,
    /// Time of the update at which it happened.
    pub t: S<B>,
}

/// Steps through a plan of phases.
pub struct Scheduler<'p, 'm, B: Backend> {
    plan: &'p mut [Phase<'m, B>],
    active: usize,
    last_psi: Option<S<B>>,
}

impl<'p, 'm, B: Backend> Scheduler<'p, 'm, B> {
    /// Starts at the first phase; an empty plan is
    /// [`ControlError::EmptyPlan`].
    pub fn new(plan: &'p mut [Phase<'m, B>]) -> Result<Self, ControlError> {
        if plan.is_empty() {
            return Err(ControlError::EmptyPlan);
        }
        Ok(Self {
            plan,
            active: 0,
            last_psi: None,
        })
    }

    /// Index of the active phase.
    pub fn active(&self) -> usize {
        self.active
    }

    /// The integral slots the plan uses (the largest
    /// [`Mode::integral_count`]): the register the caller holds.
    pub fn integral_count(&self) -> usize {
        self.plan
            .iter()
            .map(|p| p.mode.integral_count())
            .max()
            .unwrap_or(0)
    }

    /// Leaves the active phase if its condition holds at time `t` (for
    /// [`Leave::PsiBelow`], with the `Ψ` of the latest command); the mode
    /// entered sees `state` and the whole register. Returns the switch, if
    /// any (at most one per call, so each is reported).
    pub fn advance(
        &mut self,
        t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        integrals: &mut [S<B>],
    ) -> Option<Switch<B>> {
        let phase = &self.plan[self.active];
        let leave = match phase.until {
            Leave::At(ts) => t >= ts,
            Leave::PsiBelow(th) => self.last_psi.is_some_and(|p| p < th),
            Leave::Never => false,
        };
        if !leave || self.active + 1 >= self.plan.len() {
            return None;
        }
        let from = self.active;
        self.active += 1;
        self.last_psi = None;
        self.plan[self.active].mode.enter(t, state, integrals);
        Some(Switch {
            from,
            to: self.active,
            t,
        })
    }

    /// The active mode's command at time `t`, its integral rates written
    /// into `rates` (zeroed first; `rates` as long as `integrals`).
    pub fn command(
        &mut self,
        t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        integrals: &[S<B>],
        rates: &mut [S<B>],
    ) -> Result<ModeOutput<B>, ControlError> {
        rates.fill(S::<B>::lit(0.0));
        let out = self.plan[self.active]
            .mode
            .command(t, state, integrals, rates)?;
        self.last_psi = Some(out.psi);
        Ok(out)
    }
}
