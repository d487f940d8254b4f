//! What happens at the instants a step ends on or is split at: a located
//! breakpoint crossing, a located condition switch, a checkpoint (a time
//! switch, a control instant). The stepping loop calls these.

use controllers::{Breakpoint, SatBranch};
use integrators::{Integrator, State};
use lie::{Backend, Real, S, SimdReal};

use super::closed_loop::ClosedLoop;
use super::emit::Emit;
use super::events::{Crossing, event_derivatives, locate_condition, split_at_crossing};
use super::grid::Arrival;
use super::record::track_figures;
use super::sense;
use super::{BreakpointCrossing, RunOutput, SimError, Until};

/// Makes the next segment active at `t` (if there is one), reports the
/// switch, and returns the new mode's breakpoints.
fn switch_segment<B: Backend, const N: usize>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    emit: &mut Emit<'_, '_>,
    out: &mut RunOutput,
    t: f64,
    y: &mut State<B, N>,
    locate_events: bool,
) -> Result<Option<Vec<Breakpoint<B>>>, SimError> {
    match sys.switch(t, y) {
        Some(sw) => {
            emit.switch(out, sw)?;
            Ok(Some(breakpoints(sys, locate_events)))
        }
        None => Ok(None),
    }
}

/// What a switch or a control instant touches: the loop, the sample
/// stream and the run's output.
pub(super) struct Cx<'c, 's, 'a, 'o, 'k, B: Backend, const N: usize> {
    sys: &'c mut ClosedLoop<'s, 'a, B, N>,
    emit: &'c mut Emit<'o, 'k>,
    out: &'c mut RunOutput,
    locate_events: bool,
}

impl<'c, 's, 'a, 'o, 'k, B: Backend, const N: usize> Cx<'c, 's, 'a, 'o, 'k, B, N> {
    pub(super) fn new(
        sys: &'c mut ClosedLoop<'s, 'a, B, N>,
        emit: &'c mut Emit<'o, 'k>,
        out: &'c mut RunOutput,
        locate_events: bool,
    ) -> Self {
        Self {
            sys,
            emit,
            out,
            locate_events,
        }
    }

    /// A located breakpoint crossing `c` inside the step `(t, h, before)`: the
    /// step redone up to it (`y` becomes the state there), the samples inside
    /// taken on the branch that part was integrated on (sat′ changes Ω̇
    /// through the integral term's rate), the crossing counted, tracked and
    /// sampled; the law is left forced onto the far branch. Returns its time
    /// and the grid phase from there (see `Running::phase`; `phase` is the
    /// step's).
    pub(super) fn at_crossing<I: Integrator<B, N>>(
        &mut self,
        stepper: &mut I,
        c: &Crossing<B>,
        (t, h, before): (f64, f64, &State<B, N>),
        phase: S<B>,
        y: &mut State<B, N>,
    ) -> Result<(f64, S<B>), SimError> {
        let (sys, emit, out) = (&mut *self.sys, &mut *self.emit, &mut *self.out);
        let split = split_at_crossing(sys, stepper, c, (t, h, before, phase), y)?;
        let (tc, pre, post) = (split.t, split.pre, split.post);
        out.steps += split.steps;
        sys.plan[sys.active].mode.force_branch(c.index, pre);
        emit.inside(out, sys, stepper, (t, before), (tc, y))?;
        sense::piece(sys, stepper, (t, before), (tc, y))?;
        sys.plan[sys.active].mode.force_branch(c.index, post);
        track_figures(out, sys, tc, y)?;
        emit.exact(out, sys, tc, y)?;
        out.events += 1;
        out.event_times.push(BreakpointCrossing {
            t: tc,
            component: c.index,
        });
        Ok((tc, split.phase))
    }

    /// The active segment's condition holds at the end of the step
    /// `(t, ts, h, before)` (state `y`): the first instant it holds,
    /// located by bisection on redone steps; the samples up to it; the
    /// switch there (`bps` becomes the new mode's breakpoints), a new held
    /// command under sampled control, the figures and sample at it, and a
    /// stepper restart. `y` becomes the state there; returns its time and
    /// the grid phase from there (`phase` is the step's; see
    /// `Running::phase`).
    pub(super) fn at_condition<I: Integrator<B, N>>(
        &mut self,
        stepper: &mut I,
        (t, ts, h, before): (f64, f64, f64, &State<B, N>),
        phase: S<B>,
        y: &mut State<B, N>,
        bps: &mut Vec<Breakpoint<B>>,
        forced: &mut bool,
    ) -> Result<(f64, S<B>), SimError> {
        let (sys, emit, out) = (&mut *self.sys, &mut *self.emit, &mut *self.out);
        let holds = &mut |s: &mut ClosedLoop<'_, '_, B, N>, tt, yy: &_| s.condition_holds(tt, yy);
        let (tc, mut y_c) = locate_condition(sys, stepper, holds, (t, ts, h, before, y))?;
        let mut next_phase = S::<B>::lit(0.0);
        if S::<B>::CARRIES_DERIVATIVES {
            let step = (t, tc, h, before, phase);
            next_phase = switch_derivatives(sys, stepper, step, &mut y_c)?;
        }
        emit.inside(out, sys, stepper, (t, before), (tc, &y_c))?;
        sense::piece(sys, stepper, (t, before), (tc, &y_c))?;
        *y = y_c;
        self.switch_here(stepper, tc, y, bps, forced)?;
        Ok((tc, next_phase))
    }

    /// The switch to the next segment at `tc`, where the step has already
    /// ended and its samples are out (state `y`): `bps` becomes the new
    /// mode's breakpoints, a new held command under sampled control, the
    /// figures and sample at `tc`, and a stepper restart.
    pub(super) fn switch_here<I: Integrator<B, N>>(
        &mut self,
        stepper: &mut I,
        tc: f64,
        y: &mut State<B, N>,
        bps: &mut Vec<Breakpoint<B>>,
        forced: &mut bool,
    ) -> Result<(), SimError> {
        let (sys, emit, out) = (&mut *self.sys, &mut *self.emit, &mut *self.out);
        release(sys, bps.len(), forced);
        if let Some(b) = switch_segment(sys, emit, out, tc, y, self.locate_events)? {
            *bps = b;
        }
        if sys.sampled {
            sys.held = if sys.update_outer(tc, y) {
                sys.control_command(tc, y)
            } else {
                None
            };
        }
        track_figures(out, sys, tc, y)?;
        emit.exact(out, sys, tc, y)?;
        stepper.reset();
        Ok(())
    }

    /// At a checkpoint `t` (state `y`): the next segment when `switch_due`
    /// and the active one ends at a time, a new held command under sampled
    /// control after a switch or at a control instant, and a stepper
    /// restart after either. Returns the new mode's breakpoints after a
    /// switch.
    pub(super) fn at_checkpoint<I: Integrator<B, N>>(
        &mut self,
        stepper: &mut I,
        t: f64,
        y: &mut State<B, N>,
        due: Arrival,
    ) -> Result<Option<Vec<Breakpoint<B>>>, SimError> {
        let sys = &mut *self.sys;
        let Arrival {
            switch_due,
            control_due,
            outer_due,
            ..
        } = due;
        // Only a segment that ends at a time is left here (one waiting for
        // its condition stays active past a later segment's time).
        let mut leaves = switch_due
            && sys
                .plan
                .get(sys.active)
                .is_some_and(|s| matches!(s.until, Until::Time(u) if u <= t));
        // With an estimator, a condition is checked on the estimate at the
        // control instants, as a flight computer's scheduler would.
        if sys.sampled && (leaves || control_due || outer_due) {
            sys.refresh_estimate(t);
            leaves |= control_due
                && sys.estimating()
                && sys.has_condition()
                && sys.condition_holds_estimated(t, y);
        }
        let new = if leaves {
            switch_segment(sys, self.emit, self.out, t, y, self.locate_events)?
        } else {
            None
        };
        let mut changed = new.is_some();
        // A multi-rate loop's outer instant, or a mode's first instant in
        // one: the outer loop first, then the command that tracks it.
        if sys.cascade && (changed || outer_due) && !sys.update_outer(t, y) {
            sys.held = None;
            changed = true;
        } else if sys.sampled && (changed || control_due) {
            sys.held = sys.control_command(t, y);
            changed = true;
        }
        if changed {
            stepper.reset();
        }
        Ok(new)
    }
}

/// A dual run's derivatives at a located switch (see `event_derivatives`):
/// the residual is `Ψ − threshold`. A switch on a user predicate has no
/// residual, so its time's derivative is unknown: an error rather than a
/// gradient that silently leaves it out.
fn switch_derivatives<B: Backend, const N: usize, I: Integrator<B, N>>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    stepper: &mut I,
    step: (f64, f64, f64, &State<B, N>, S<B>),
    y: &mut State<B, N>,
) -> Result<S<B>, SimError> {
    if !matches!(sys.plan[sys.active].until, Until::PsiBelow(_)) {
        return Err(SimError::Setting {
            field: "plan",
            message: "a switch on a user predicate cannot be differentiated (its time's \
                      derivative needs a residual): end the segment on Ψ or at a time"
                .into(),
        });
    }
    let residual = &mut |s: &mut ClosedLoop<'_, '_, B, N>, tt: f64, yy: &State<B, N>| {
        s.condition_residual(S::<B>::lit(tt), yy)
            .unwrap_or_else(<S<B> as Real>::nan)
    };
    event_derivatives(sys, stepper, residual, step, y)
}

/// After the step that follows a located crossing: the law picks its
/// breakpoint branches from the state again.
pub(super) fn release<B: Backend, const N: usize>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    count: usize,
    forced: &mut bool,
) {
    if *forced {
        for k in 0..count {
            sys.plan[sys.active].mode.force_branch(k, SatBranch::Auto);
        }
        *forced = false;
    }
}

/// The breakpoints of the active mode (none without event location),
/// copied so that the loop can call the system while it walks them.
pub(super) fn breakpoints<B: Backend, const N: usize>(
    sys: &ClosedLoop<'_, '_, B, N>,
    locate_events: bool,
) -> Vec<Breakpoint<B>> {
    if locate_events {
        sys.plan
            .get(sys.active)
            .map_or_else(Vec::new, |s| s.mode.integrals().breakpoints.to_vec())
    } else {
        Vec::new()
    }
}
