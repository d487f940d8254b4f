//! The hybrid flight-mode scheduler (Section V of the paper) for a flight
//! computer: a plan of phases, each a [`Mode`] left when a time is reached
//! or when `Ψ` falls below a threshold (Proposition 3: a large attitude
//! error is first reduced in attitude mode, then position mode takes over).
//!
//! The plan's types, [`Segment`], [`Until`] and [`Switch`], are the ones a
//! simulation's plan is made of (with boxed modes, `f64` times and
//! closures as conditions), so a plan is described once for both.
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

/// When a segment of a flight plan ends: the one definition that both a
/// flight computer's [`Scheduler`] and a simulation's plan use.
///
/// `T` is the clock's number (the scalar `S<B>` on a flight computer, `f64`
/// seconds in a simulation) and `C` a user's condition: a closure in a
/// simulation, [`NoCondition`] (the default, no value of it exists) where
/// there is none, as on a flight computer without a heap.
#[derive(Copy, Clone, PartialEq)]
pub enum Until<T, C = NoCondition> {
    /// Never (the last segment).
    Never,
    /// At this time, s: the [`Scheduler`] leaves the segment at the first
    /// [`Scheduler::advance`] with `t ≥` it; a simulation lands a step on it.
    Time(T),
    /// When `Ψ` of the mode's command drops below this (the
    /// [`Scheduler`] reads the latest command's; a simulation locates the
    /// crossing by bisection on redone steps).
    PsiBelow(T),
    /// When the user's predicate first holds.
    Condition(C),
}

impl<T: core::fmt::Debug, C> core::fmt::Debug for Until<T, C> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Until::Never => write!(f, "Never"),
            Until::Time(t) => write!(f, "Time({t:?})"),
            Until::PsiBelow(p) => write!(f, "PsiBelow({p:?})"),
            // A closure has nothing to print.
            Until::Condition(_) => write!(f, "Condition(..)"),
        }
    }
}

/// The condition type of a plan without user conditions: it has no values,
/// so `Until::Condition` cannot be built and needs no code.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum NoCondition {}

/// One segment of a flight plan: a mode `M` (a borrowed `&mut dyn Mode` on
/// a flight computer, a boxed one in a simulation) and when it ends, `U`
/// (an [`Until`]).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Segment<M, U> {
    /// The law.
    pub mode: M,
    /// When it ends.
    pub until: U,
}

/// A flight computer's segment: a borrowed mode left at a time or when `Ψ`
/// drops below a threshold, in the scalar's own clock.
pub type Phase<'m, B> = Segment<&'m mut dyn Mode<B>, Until<S<B>>>;

/// A mode switch, for the caller to report.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Switch<T> {
    /// Time of the switch, s (for the [`Scheduler`], of the update at which
    /// it happened).
    pub t: T,
    /// Segment index left.
    pub from: usize,
    /// Segment index entered.
    pub to: usize,
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
    /// [`Mode::integrals`]): the register the caller holds.
    pub fn integral_count(&self) -> usize {
        self.plan
            .iter()
            .map(|p| p.mode.integrals().count)
            .max()
            .unwrap_or(0)
    }

    /// Leaves the active phase if its condition holds at time `t` (for
    /// [`Until::PsiBelow`], with the `Ψ` of the latest command); the mode
    /// entered sees `state` and the whole register. Returns the switch, if
    /// any (at most one per call, so each is reported).
    pub fn advance(
        &mut self,
        t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        integrals: &mut [S<B>],
    ) -> Option<Switch<S<B>>> {
        let phase = &self.plan[self.active];
        let leave = match phase.until {
            Until::Time(ts) => t >= ts,
            Until::PsiBelow(th) => self.last_psi.is_some_and(|p| p < th),
            Until::Never => false,
            Until::Condition(never) => match never {},
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
