//! The stepping loop: from checkpoint to checkpoint (control samples,
//! time switches, the end: what changes the dynamics; each `k·Δ` or a
//! listed time, never an accumulated sum), in steps of `dt` with the last
//! one shortened to land on the checkpoint; events inside a step are
//! located by [`super::events`]. Record instants are not checkpoints:
//! samples come from each step's continuous extension, so the computed
//! trajectory, the run's extrema (over every step end and located event)
//! and its evaluation count are the same whatever is recorded.

use std::sync::atomic::Ordering;
use std::time::Instant;

use controllers::{Breakpoint, SatBranch};
use dynamics::Wrench;
use integrators::{Integrator, State, System, dense};
use lie::{Backend, Real, S};

use super::closed_loop::ClosedLoop;
use super::events::{crossing, locate_condition, split_at_crossing};
use super::record::{empty_sample, sample, track, track_figures};
use super::{Control, RunOptions, RunOutput, Sample, SimError, Simulation, SwitchRecord, Until};
use crate::output::Sink;

/// Where samples go: kept in the output, handed to the sink, or both; and
/// when: every `rec` seconds, taken from the steps' continuous extension
/// ([`integrators::dense`]) so that recording never moves the step grid.
struct Emit<'o, 's> {
    keep: bool,
    sink: Option<&'o mut (dyn Sink + 's)>,
    /// Time of the last sample emitted (a checkpoint that coincides with
    /// a located stop is not sampled twice).
    last_t: f64,
    /// Record interval, s (0: only the start and the end).
    rec: f64,
    /// Record instants emitted so far; the next is `(k + 1)·rec`.
    k: u64,
}

impl Emit<'_, '_> {
    fn sample(&mut self, out: &mut RunOutput, s: Sample) -> Result<(), SimError> {
        if s.t != self.last_t {
            self.last_t = s.t;
            if let Some(k) = self.sink.as_deref_mut() {
                k.sample(&s).map_err(SimError::Output)?;
            }
            if self.keep {
                out.samples.push(s.clone());
            }
        }
        out.last = s;
        Ok(())
    }

    fn switch(&mut self, out: &mut RunOutput, sw: SwitchRecord) -> Result<(), SimError> {
        out.switches.push(sw);
        if let Some(k) = self.sink.as_deref_mut() {
            let name = out.mode_names.get(sw.to).copied().unwrap_or("none");
            k.switch(&sw, name).map_err(SimError::Output)?;
        }
        Ok(())
    }

    fn next(&self) -> f64 {
        (self.k + 1) as f64 * self.rec
    }

    /// Whether the next record instant is `t` (to rounding of `k·rec`).
    fn due_at(&self, t: f64) -> bool {
        self.rec > 0.0 && (self.next() - t).abs() <= 1e-9 * self.rec
    }

    /// Samples the state itself when the next record instant is `t`.
    fn exact<B: Backend, const N: usize>(
        &mut self,
        out: &mut RunOutput,
        sys: &mut ClosedLoop<'_, '_, B, N>,
        t: f64,
        y: &State<B, N>,
    ) -> Result<(), SimError> {
        if self.due_at(t) {
            // Labelled with the instant `k·rec` itself, from which `t`
            // differs by the rounding of the step grid at most.
            let tk = self.next();
            self.k += 1;
            let s = sample(sys, tk, y)?;
            self.sample(out, s)?;
        }
        Ok(())
    }

    /// Samples every record instant strictly inside the step from
    /// `(t0, y0)` to `(t1, y1)` from its continuous extension (for an
    /// adaptive stepper, by integrating a copy of it from `t0`: see
    /// [`Integrator::resampler`]). The loads evaluated for it are not
    /// counted in the run's evaluations, which stay the same with and
    /// without recording; the stepper itself is not touched.
    #[allow(clippy::too_many_arguments)]
    fn inside<B: Backend, const N: usize, I: Integrator<B, N>>(
        &mut self,
        out: &mut RunOutput,
        sys: &mut ClosedLoop<'_, '_, B, N>,
        stepper: &I,
        t0: f64,
        y0: &State<B, N>,
        t1: f64,
        y1: &State<B, N>,
    ) -> Result<(), SimError> {
        if self.rec <= 0.0 || self.next() >= t1 - 1e-9 * self.rec {
            return Ok(());
        }
        let l = S::<B>::lit;
        let counted = sys.evaluations;
        if let Some(mut copy) = stepper.resampler() {
            while self.rec > 0.0 && self.next() < t1 - 1e-9 * self.rec {
                let tk = self.next();
                self.k += 1;
                let mut y = *y0;
                copy.reset();
                let stepped = copy.step(sys, l(t0), l(tk - t0), &mut y);
                sys.evaluations = counted;
                stepped.map_err(|e| SimError::Step(format!("sampling at t = {tk}: {e}")))?;
                let s = sample(sys, tk, &y)?;
                self.sample(out, s)?;
            }
            return Ok(());
        }
        let l0 = sys.load(l(t0), y0);
        let l1 = sys.load(l(t1), y1);
        sys.evaluations = counted;
        if let Some(e) = sys.error.take() {
            return Err(SimError::Control(format!("at t = {t0}: {e}")));
        }
        let r0 = dense::Rates::of(sys, y0, &l0);
        let r1 = dense::Rates::of(sys, y1, &l1);
        let h = t1 - t0;
        while self.rec > 0.0 && self.next() < t1 - 1e-9 * self.rec {
            let tk = self.next();
            self.k += 1;
            let y = dense::interpolate(y0, &r0, y1, &r1, l(h), l((tk - t0) / h));
            let s = sample(sys, tk, &y)?;
            self.sample(out, s)?;
        }
        Ok(())
    }
}

/// After the step that follows a located crossing: the law picks its
/// breakpoint branches from the state again.
fn release<B: Backend, const N: usize>(
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

/// Updates the run's extrema with the state at `t` (its command, Ψ,
/// rotor thrusts, distance from SO(3)).
fn track_state<B: Backend, const N: usize>(
    out: &mut RunOutput,
    sys: &mut ClosedLoop<'_, '_, B, N>,
    t: f64,
    y: &State<B, N>,
) -> Result<(), SimError> {
    track_figures(out, sys, t, y)
}

pub(crate) fn run<B: Backend, const N: usize, I: Integrator<B, N>>(
    sim: Simulation<'_, B, N, I>,
    opts: RunOptions<'_>,
) -> Result<RunOutput, SimError> {
    let RunOptions {
        record: keep,
        mut progress,
        sink,
        cancel,
        extrema,
    } = opts;
    let l = S::<B>::lit;
    let Simulation {
        vehicle,
        mut plan,
        mut stepper,
        initial,
        integrals: m,
        vehicle_states: nv,
        dt,
        duration: t_end,
        control,
        record,
        locate_events,
        compensate,
        mut stop,
    } = sim;
    let mode_names = plan.iter().map(|s| s.mode.name()).collect();
    let switch_times: Vec<f64> = plan
        .iter()
        .filter_map(|s| match s.until {
            Until::Time(u) => Some(u),
            _ => None,
        })
        .filter(|u| *u < t_end)
        .collect();
    let sampled = matches!(control, Control::Sampled { .. }) && !plan.is_empty();
    let ctrl = match control {
        Control::Sampled { rate } if sampled => 1.0 / rate,
        _ => 0.0,
    };
    let rec = if keep || sink.is_some() { record } else { 0.0 };
    let mut emit = Emit {
        keep,
        sink,
        last_t: f64::NAN,
        rec,
        k: 0,
    };
    let mut sys = ClosedLoop {
        vehicle: vehicle.as_ref(),
        plan: &mut plan,
        active: 0,
        m,
        nv,
        held: None,
        sampled,
        compensate,
        inertia_inv: lie::ops::inverse::<B>(vehicle.inertia())
            .ok_or_else(|| SimError::Scene("inertia is singular".into()))?,
        evaluations: 0,
        error: None,
    };
    let mut y = initial;
    // The breakpoints of the active mode, copied so that the loop can call
    // the system while it walks them.
    let refresh = |sys: &ClosedLoop<'_, '_, B, N>| -> Vec<Breakpoint<B>> {
        if locate_events {
            sys.plan
                .get(sys.active)
                .map_or_else(Vec::new, |s| s.mode.breakpoints().to_vec())
        } else {
            Vec::new()
        }
    };
    let mut bps = refresh(&sys);

    let mut out = RunOutput {
        samples: Vec::new(),
        switches: Vec::new(),
        mode_names,
        events: 0,
        event_times: Vec::new(),
        steps: 0,
        evaluations: 0,
        max_thrust: 0.0,
        max_rotor: 0.0,
        wall: 0.0,
        warnings: Vec::new(),
        stopped_at: None,
        interrupted_at: None,
        max_orthogonality_error: 0.0,
        psi_range: (f64::INFINITY, f64::NEG_INFINITY),
        last: empty_sample(),
    };
    // Control instants are checkpoints the steps land on (the command
    // changes there): a finer grid than dt shortens every step. Record
    // instants are not: samples come from the steps' continuous extension.
    if ctrl > 0.0 && ctrl < dt * (1.0 - 1e-9) {
        out.warnings.push(format!(
            "steps land on every control instant: at {} Hz the steps are at most {ctrl} s, not dt = {dt} s",
            1.0 / ctrl
        ));
    }
    // A segment that ends at or after the end of the run leaves the ones
    // after it unused: say so (a `duration` shortened on purpose is fine,
    // but a typo in `until` would otherwise show only as "0 switches").
    if let Some(k) = sys
        .plan
        .iter()
        .position(|s| matches!(s.until, Until::Time(u) if u >= t_end))
        && k + 1 < sys.plan.len()
    {
        let u = match sys.plan[k].until {
            Until::Time(u) => u,
            _ => t_end,
        };
        out.warnings.push(format!(
            "segment {k} ({}) lasts until {u} s, not before the end of the run at {t_end} s: \
             segment {} ({}) and any after it never run",
            sys.plan[k].mode.name(),
            k + 1,
            sys.plan[k + 1].mode.name()
        ));
    }
    let start = Instant::now();
    let mut t = 0.0f64;
    if sampled {
        sys.held = sys.command(l(0.0), &y);
    }
    if nv > 0 {
        // Internal states (spinning rotors, say) start where the first
        // command puts them.
        let w = sys
            .command(l(0.0), &y)
            .map_or_else(Wrench::zero, |c| Wrench {
                thrust: c.out.thrust,
                moment: c.out.moment,
            });
        vehicle.initial_states(&w, &mut y.extra[m..m + nv]);
    }
    if let Some(k) = emit.sink.as_deref_mut() {
        k.begin(&out.mode_names).map_err(SimError::Output)?;
    }
    let s0 = sample(&mut sys, 0.0, &y)?;
    track(&mut out, &s0);
    emit.sample(&mut out, s0)?;
    let (mut k_ctrl, mut k_sw) = (0u64, 0usize);
    let mut progress_next = 0.0;
    let mut forced_for_next_step = false;
    while t < t_end {
        let mut t_next = t_end;
        if ctrl > 0.0 {
            t_next = t_next.min((k_ctrl + 1) as f64 * ctrl);
        }
        if let Some(&ts) = switch_times.get(k_sw) {
            t_next = t_next.min(ts);
        }
        // Steps of dt from t, the last one shortened to land on t_next.
        let mut seg_start = t;
        let mut j = 0u64;
        while t < t_next {
            let mut ts = seg_start + (j + 1) as f64 * dt;
            if ts > t_next - 1e-12 * dt.max(t_next) {
                ts = t_next;
            }
            let h = ts - t;
            let before = y;
            let stats = stepper.step(&mut sys, l(t), l(h), &mut y).map_err(|e| {
                SimError::Step(match sys.error.take() {
                    // A non-finite reference is the reference's fault;
                    // a non-finite state means the step diverged.
                    Some(c) if c.contains("`reference") => format!(
                        "in the step from t = {t} (h = {h}): {c}: the reference returned NaN or ∞ there"
                    ),
                    Some(c) => format!(
                        "in the step from t = {t} (h = {h}): {c}; the state diverged — try a smaller --dt"
                    ),
                    None => e.to_string(),
                })
            })?;
            out.steps += u64::from(stats.substeps.max(1));
            if !bps.is_empty()
                && let Some(c) = crossing(&mut sys, &bps, t, h, &before, &y)
            {
                // Split the step at the crossing: redo [t, tc], restart
                // the dt grid from tc.
                let (tc, steps, pre) =
                    split_at_crossing(&mut sys, &mut stepper, &c, t, h, &before, &mut y)?;
                out.steps += steps;
                // The samples up to the crossing come from the rates of
                // the branch that step was integrated on (sat′ changes
                // Ω̇ through the integral term's rate).
                let post = if pre == SatBranch::Inside {
                    SatBranch::Outside
                } else {
                    SatBranch::Inside
                };
                sys.plan[sys.active].mode.force_branch(c.index, pre);
                emit.inside(&mut out, &mut sys, &stepper, t, &before, tc, &y)?;
                sys.plan[sys.active].mode.force_branch(c.index, post);
                track_state(&mut out, &mut sys, tc, &y)?;
                emit.exact(&mut out, &mut sys, tc, &y)?;
                forced_for_next_step = true;
                out.events += 1;
                out.event_times.push((tc, c.index));
                t = tc;
                seg_start = t;
                j = 0;
                continue;
            }
            // A condition switch (Ψ below a threshold, a user predicate):
            // when it holds at the end of this step, bisect on redone steps
            // for the first instant and switch there.
            if sys.has_condition() && sys.condition_holds(ts, &y) {
                let (tc, y_c) = locate_condition(
                    &mut sys,
                    &mut stepper,
                    &mut |s, tt, yy| s.condition_holds(tt, yy),
                    t,
                    ts,
                    h,
                    &before,
                    &y,
                )?;
                emit.inside(&mut out, &mut sys, &stepper, t, &before, tc, &y_c)?;
                release(&mut sys, bps.len(), &mut forced_for_next_step);
                y = y_c;
                if let Some(sw) = sys.switch(tc, &mut y) {
                    emit.switch(&mut out, sw)?;
                    bps = refresh(&sys);
                }
                if sampled {
                    sys.held = sys.command(l(tc), &y);
                }
                track_state(&mut out, &mut sys, tc, &y)?;
                emit.exact(&mut out, &mut sys, tc, &y)?;
                stepper.reset();
                t = tc;
                seg_start = t;
                j = 0;
                continue;
            }
            // The run's stop condition: located like a switch, and the run
            // ends there with a final sample.
            if stop.is_some() && sys.stop_holds(&mut stop, ts, &y) {
                let (tc, y_c) = locate_condition(
                    &mut sys,
                    &mut stepper,
                    &mut |s, tt, yy| s.stop_holds(&mut stop, tt, yy),
                    t,
                    ts,
                    h,
                    &before,
                    &y,
                )?;
                emit.inside(&mut out, &mut sys, &stepper, t, &before, tc, &y_c)?;
                y = y_c;
                let s = sample(&mut sys, tc, &y)?;
                track(&mut out, &s);
                emit.sample(&mut out, s)?;
                out.stopped_at = Some(tc);
                out.evaluations = sys.evaluations;
                out.wall = start.elapsed().as_secs_f64();
                return Ok(out);
            }
            // Samples inside the step, on the branches it was integrated
            // on; then the law decides its branches from the state again.
            emit.inside(&mut out, &mut sys, &stepper, t, &before, ts, &y)?;
            release(&mut sys, bps.len(), &mut forced_for_next_step);
            t = ts;
            j += 1;
            if t < t_next {
                // A checkpoint's own figures and sample come after what
                // happens there (a switch, a new held command).
                if extrema {
                    track_state(&mut out, &mut sys, t, &y)?;
                }
                emit.exact(&mut out, &mut sys, t, &y)?;
            }
            if let Some(p) = progress.as_deref_mut()
                && t / t_end >= progress_next
            {
                p(t / t_end);
                progress_next = (t / t_end + 0.005).min(1.0);
            }
            if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                let s = sample(&mut sys, t, &y)?;
                track(&mut out, &s);
                emit.sample(&mut out, s)?;
                out.interrupted_at = Some(t);
                out.evaluations = sys.evaluations;
                out.wall = start.elapsed().as_secs_f64();
                return Ok(out);
            }
        }
        t = t_next;
        let mut changed = false;
        if switch_times.get(k_sw).is_some_and(|&ts| ts <= t) {
            k_sw += 1;
            // Only a segment that ends at a time is left here (one waiting
            // for its condition stays active past a later segment's time).
            let due = sys
                .plan
                .get(sys.active)
                .is_some_and(|s| matches!(s.until, Until::Time(u) if u <= t));
            if due && let Some(sw) = sys.switch(t, &mut y) {
                emit.switch(&mut out, sw)?;
                bps = refresh(&sys);
                changed = true;
            }
        }
        if ctrl > 0.0 && ((k_ctrl + 1) as f64 * ctrl - t).abs() <= 1e-9 * ctrl {
            k_ctrl += 1;
        }
        if sampled && (changed || ((k_ctrl as f64) * ctrl - t).abs() <= 1e-9 * ctrl) {
            sys.held = sys.command(l(t), &y);
            changed = true;
        }
        if changed {
            stepper.reset();
        }
        if extrema || t >= t_end {
            track_state(&mut out, &mut sys, t, &y)?;
        }
        if emit.due_at(t) {
            emit.exact(&mut out, &mut sys, t, &y)?;
        } else if t >= t_end {
            let s = sample(&mut sys, t, &y)?;
            emit.sample(&mut out, s)?;
        }
    }
    out.evaluations = sys.evaluations;
    out.wall = start.elapsed().as_secs_f64();
    Ok(out)
}
