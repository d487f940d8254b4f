//! Event location inside a step.
//!
//! - **Breakpoint crossings** (the paper's sat′: a component of e_i
//!   crossing ±σ): found from the step's end values, the time estimated by
//!   cubic Hermite interpolation of the state and its rate, refined by
//!   Newton on redone steps; the step is split there and each side
//!   integrated on its own branch of the law.
//! - **Condition switches** (`Ψ` below a threshold, a user predicate):
//!   bisection on redone steps for the first time the condition holds.

use controllers::{Breakpoint, SatBranch};
use integrators::{Integrator, Load, State};
use lie::{Backend, Real, S, SimdReal};

use super::SimError;
use super::closed_loop::ClosedLoop;

/// Whether some breakpoint's slot changed sides of its level between the
/// two states: the test after every step, the usual answer `false`.
#[inline(always)]
pub(crate) fn any_crossed<B: Backend, const N: usize>(
    bps: &[Breakpoint<B>],
    before: &State<B, N>,
    after: &State<B, N>,
) -> bool {
    bps.iter().any(|bp| sides(bp, before, after).is_some())
}

/// `(level, e₀, e₁, |e₀| − level)` when `bp`'s slot changed sides of its
/// level from `e₀` to `e₁`. A component sitting on ±level (just located)
/// is not a new crossing. (Plain sign tests: both values are finite, the
/// step has checked its state, and ±0 is caught by the last test.)
#[inline(always)]
fn sides<B: Backend, const N: usize>(
    bp: &Breakpoint<B>,
    before: &State<B, N>,
    after: &State<B, N>,
) -> Option<(f64, f64, f64, f64)> {
    let level = bp.level.to_f64_lossless();
    let e0 = before.extra[bp.slot].to_f64_lossless();
    let e1 = after.extra[bp.slot].to_f64_lossless();
    let (g0, g1) = (e0.abs() - level, e1.abs() - level);
    let same = (g0 < 0.0) == (g1 < 0.0) || g1 == 0.0 || g0.abs() <= 1e-12 * level;
    (!same).then_some((level, e0, e1, g0))
}

/// A located breakpoint crossing: time, breakpoint index, slot, the value
/// the slot lands on (±level), and that value as the law's scalar (it
/// carries the level's derivatives in a dual run).
pub(crate) struct Crossing<B: Backend> {
    pub t: f64,
    pub index: usize,
    pub slot: usize,
    pub level: f64,
    pub target: f64,
    pub target_s: S<B>,
}

/// The earliest breakpoint whose slot crossed its level inside the step,
/// with the crossing time from cubic Hermite interpolation of the slot and
/// its rate over the step.
///
/// Out of line, and asked only once [`any_crossed`] has seen a slot change
/// sides: inlined into the loop, the optimiser computed the finiteness
/// tests of the two loads it needs, for both states, after every step
/// whether or not a slot had crossed.
#[cold]
#[inline(never)]
pub(crate) fn crossing<B: Backend, const N: usize>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    bps: &[Breakpoint<B>],
    t: f64,
    h: f64,
    before: &State<B, N>,
    after: &State<B, N>,
) -> Option<Crossing<B>> {
    let mut found: Option<Crossing<B>> = None;
    let mut rates: Option<(Load<B, N>, Load<B, N>)> = None;
    for (k, bp) in bps.iter().enumerate() {
        let Some((level, e0, e1, g0)) = sides(bp, before, after) else {
            continue;
        };
        let target = if g0 < 0.0 {
            level.copysign(e1)
        } else {
            level.copysign(e0)
        };
        let (l0, l1) = rates.get_or_insert_with(|| {
            use integrators::System;
            (
                sys.load(S::<B>::lit(t), before),
                sys.load(S::<B>::lit(t + h), after),
            )
        });
        let d0 = l0.extra_rate[bp.slot].to_f64_lossless();
        let d1 = l1.extra_rate[bp.slot].to_f64_lossless();
        let p = |s: f64| {
            let (s2, s3) = (s * s, s * s * s);
            (2.0 * s3 - 3.0 * s2 + 1.0) * e0
                + (s3 - 2.0 * s2 + s) * h * d0
                + (-2.0 * s3 + 3.0 * s2) * e1
                + (s3 - s2) * h * d1
                - target
        };
        let (mut lo, mut hi) = (0.0, 1.0);
        let plo = p(lo);
        if plo.signum() == p(hi).signum() {
            // The cubic disagrees with the endpoints (should not happen for
            // a smooth state): fall back to linear interpolation.
            lo = (target - e0) / (e1 - e0);
            hi = lo;
        } else {
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if p(mid).signum() == plo.signum() {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
        }
        let tc = t + h * 0.5 * (lo + hi);
        if found.as_ref().is_none_or(|f| tc < f.t) {
            found = Some(Crossing {
                t: tc,
                index: k,
                slot: bp.slot,
                level,
                target,
                target_s: if target < 0.0 { -bp.level } else { bp.level },
            });
        }
    }
    found
}

/// Where a step was split at a crossing: the located time, the steps
/// taken, the branches before and after, and the grid phase from there
/// (see [`event_derivatives`]).
pub(crate) struct Split<B: Backend> {
    pub t: f64,
    pub steps: u64,
    pub pre: SatBranch,
    pub post: SatBranch,
    pub phase: S<B>,
}

/// Redoes the step from `(t, before)` to the crossing `c`, refining its
/// time by Newton on the integrated slot (the Hermite estimate is only
/// O(h⁴) accurate; for Dormand–Prince's long calls that error, times the
/// rate, was 1e-7 in the state), and lands the slot on ±level. The active
/// mode integrates up to the crossing on the branch it was on and is left
/// forced onto the far branch. `phase` carries the derivatives of the
/// step's start time (a dual run; see [`event_derivatives`]).
pub(crate) fn split_at_crossing<B: Backend, const N: usize, I: Integrator<B, N>>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    stepper: &mut I,
    c: &Crossing<B>,
    (t, h, before, phase): (f64, f64, &State<B, N>, S<B>),
    y: &mut State<B, N>,
) -> Result<Split<B>, SimError> {
    use integrators::System;
    let l = S::<B>::lit;
    let mut steps = 0u64;
    let (mut tc, level) = (c.t, c.level);
    let was_inside = before.extra[c.slot].to_f64_lossless().abs() < level;
    let (pre, post) = if was_inside {
        (SatBranch::Inside, SatBranch::Outside)
    } else {
        (SatBranch::Outside, SatBranch::Inside)
    };
    sys.plan[sys.active].mode.force_branch(c.index, pre);
    for _ in 0..8 {
        *y = *before;
        stepper.reset();
        let hc = tc - t;
        if hc > 0.0 {
            let stats = stepper
                .step(sys, l(t), l(hc), y)
                .map_err(|e| sys.step_error(t, hc, e))?;
            steps += u64::from(stats.substeps.max(1));
        }
        let g = y.extra[c.slot].to_f64_lossless() - c.target;
        if g.abs() <= 1e-13 * level.max(1.0) {
            break;
        }
        let rate = sys.load(l(tc), y).extra_rate[c.slot].to_f64_lossless();
        // A zero or non-finite rate gives no Newton step: keep the time.
        let newton = g / rate;
        if !newton.is_finite() {
            break;
        }
        tc = (tc - newton).clamp(t, t + h);
    }
    let mut next_phase = l(0.0);
    if S::<B>::CARRIES_DERIVATIVES {
        let target = c.target_s;
        let slot = c.slot;
        let residual = &mut |_: &mut ClosedLoop<'_, '_, B, N>, _: f64, yy: &State<B, N>| {
            yy.extra[slot] - target
        };
        next_phase = event_derivatives(sys, stepper, residual, (t, tc, h, before, phase), y)?;
        steps += EVENT_REDOS;
    }
    // Land the slot on ±level exactly and integrate the next step on the
    // far side's branch (stages a rounding error from the boundary would
    // otherwise pick either side).
    y.extra[c.slot] = c.target_s.with_derivatives_of(y.extra[c.slot]);
    sys.plan[sys.active].mode.force_branch(c.index, post);
    stepper.reset();
    Ok(Split {
        t: tc,
        steps,
        pre,
        post,
        phase: next_phase,
    })
}

/// The residual whose zero an event is located at, as the law's scalar:
/// `(sys, t, y) ↦ g` (`e_slot − (±σ)` for a crossing, `Ψ − threshold` for
/// a switch); negative on one side.
pub(crate) type Residual<'r, 's, 'a, B, const N: usize> =
    dyn FnMut(&mut ClosedLoop<'s, 'a, B, N>, f64, &State<B, N>) -> S<B> + 'r;

/// The sub-steps [`event_derivatives`] redoes (held end, two for the
/// rate, moving end), counted in the run's steps.
pub(crate) const EVENT_REDOS: u64 = 4;

/// A dual run's derivatives at an event located at `tc` inside the step
/// `(t, h)` from `before` (`phase`: the derivatives of `t`); `y` holds the
/// values there and gets the derivatives, and the event time's
/// derivatives are returned as a zero carrying them. The values are left
/// alone: the real part stays the plain run's.
///
/// The event time moves with the seeded inputs. The located time solves
/// `g(t_c, y(t_c)) = 0` for the state `y` of the sub-step `t → t_c`, so by
/// the implicit function theorem `t_c′ = −g′/ġ`, with `g′` from the
/// sub-step redone with its end held fixed and `ġ` from the same discrete
/// sub-step (a central difference of its values, δ = 1e-4 h: truncation
/// δ²g‴ and rounding ε g/δ are both below 1e-9 of the rate). The sub-step
/// is then redone with its length moving by `t_c′ − t′`, and the grid runs
/// on from `t_c` carrying `t_c′`, so the derivative is that of the flight
/// the plain run computes, step lengths and all (the jump of the vector
/// field across the event, `(f⁻ − f⁺) t_c′`, comes out of the two
/// sub-steps' lengths; without it a gradient through a saturation crossing
/// or a switch is wrong at first order).
pub(crate) fn event_derivatives<'s, 'a, B: Backend, const N: usize, I: Integrator<B, N>>(
    sys: &mut ClosedLoop<'s, 'a, B, N>,
    stepper: &mut I,
    residual: &mut Residual<'_, 's, 'a, B, N>,
    (t, tc, h, before, phase): (f64, f64, f64, &State<B, N>, S<B>),
    y: &mut State<B, N>,
) -> Result<S<B>, SimError> {
    let l = S::<B>::lit;
    let t_s = l(t).with_derivatives_of(phase);
    // On a copy of an adaptive stepper: these steps are the dual run's
    // alone and must not move the step size the plain run goes on with.
    let mut redo = |sys: &mut ClosedLoop<'s, 'a, B, N>, hc: S<B>| {
        let mut yy = *before;
        let stepped = match stepper.resampler() {
            Some(mut copy) => copy.step(sys, t_s, hc, &mut yy),
            None => {
                stepper.reset();
                stepper.step(sys, t_s, hc, &mut yy)
            }
        };
        stepped.map_err(|e| sys.step_error(t, hc.to_f64_lossless(), e))?;
        Ok::<_, SimError>(yy)
    };
    let hc = tc - t;
    let held = redo(sys, l(hc).with_derivatives_of(-phase))?;
    let delta = 1e-4 * h;
    let (lo, hi) = if hc > delta {
        (hc - delta, hc + delta)
    } else {
        (hc, hc + delta)
    };
    let (y_hi, y_lo) = (redo(sys, l(hi))?, redo(sys, l(lo))?);
    let (g_hi, g_lo) = (residual(sys, t + hi, &y_hi), residual(sys, t + lo, &y_lo));
    let rate = (g_hi.to_f64_lossless() - g_lo.to_f64_lossless()) / (hi - lo);
    let g = residual(sys, tc, &held);
    let shift = l(0.0).with_derivatives_of(-g / l(rate));
    let moved = redo(sys, l(hc).with_derivatives_of(shift - phase))?;
    with_derivatives_of_state::<B, N>(y, &moved);
    Ok(shift)
}

/// `y`'s values with `d`'s derivatives, component by component.
fn with_derivatives_of_state<B: Backend, const N: usize>(y: &mut State<B, N>, d: &State<B, N>) {
    use lie::ops::with_derivatives_of as vec;
    let (b, e) = (&mut y.body, &d.body);
    let (rc, ec) = (B::mat3_cols(b.r), B::mat3_cols(e.r));
    b.r = B::mat3_from_cols(
        vec::<B>(rc[0], ec[0]),
        vec::<B>(rc[1], ec[1]),
        vec::<B>(rc[2], ec[2]),
    );
    b.x = vec::<B>(b.x, e.x);
    b.v = vec::<B>(b.v, e.v);
    b.omega = vec::<B>(b.omega, e.omega);
    for (a, b) in y.extra.iter_mut().zip(&d.extra) {
        *a = a.with_derivatives_of(*b);
    }
}

/// The first time in `(t, ts]` at which a condition (the active
/// segment's, or the run's stop condition) holds, given that it holds at
/// the end `ts = t + h` (state `y`) of the step `(t, ts, h, before, y)`:
/// bisection on redone steps from `(t, before)` to 1e-12 h, or to the
/// time's own resolution ε·ts if that is coarser (40 halvings at most
/// then; the cap of 64 only stops a bisection that cannot converge).
/// Returns the time and the state there.
#[allow(clippy::type_complexity)]
pub(crate) fn locate_condition<B: Backend, const N: usize, I: Integrator<B, N>>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    stepper: &mut I,
    holds: &mut dyn FnMut(&mut ClosedLoop<'_, '_, B, N>, f64, &State<B, N>) -> bool,
    (t, ts, h, before, y): (f64, f64, f64, &State<B, N>, &State<B, N>),
) -> Result<(f64, State<B, N>), SimError> {
    let l = S::<B>::lit;
    let (mut lo, mut hi) = (0.0, h);
    let mut y_hi = *y;
    for _ in 0..64 {
        if hi - lo <= 1e-12 * h.max(1e-300) || hi - lo <= f64::EPSILON * ts {
            break;
        }
        let mid = 0.5 * (lo + hi);
        let mut ym = *before;
        stepper.reset();
        stepper
            .step(sys, l(t), l(mid), &mut ym)
            .map_err(|e| sys.step_error(t, mid, e))?;
        if holds(sys, t + mid, &ym) {
            hi = mid;
            y_hi = ym;
        } else {
            lo = mid;
        }
    }
    Ok((t + hi, y_hi))
}
