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
use super::events::{Crossing, crossing, locate_condition, split_at_crossing};
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

impl<'o, 's> Emit<'o, 's> {
    fn new(keep: bool, sink: Option<&'o mut (dyn Sink + 's)>, rec: f64) -> Self {
        Self {
            keep,
            sink,
            last_t: f64::NAN,
            rec,
            k: 0,
        }
    }

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

    /// At a checkpoint, after what happens there: the sample of a record
    /// instant that falls on it, and the run's last sample at the end.
    fn at_checkpoint<B: Backend, const N: usize>(
        &mut self,
        out: &mut RunOutput,
        sys: &mut ClosedLoop<'_, '_, B, N>,
        t: f64,
        y: &State<B, N>,
        end: bool,
    ) -> Result<(), SimError> {
        if self.due_at(t) {
            self.exact(out, sys, t, y)
        } else if end {
            let s = sample(sys, t, y)?;
            self.sample(out, s)
        } else {
            Ok(())
        }
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
        // An adaptive stepper re-integrates a copy of itself; a one-step
        // method interpolates between the end states and their rates.
        let mut ext = match stepper.resampler() {
            Some(copy) => Extension::Redo(copy),
            None => {
                let (l0, l1) = (sys.load(l(t0), y0), sys.load(l(t1), y1));
                sys.evaluations = counted;
                if let Some(e) = sys.error.take() {
                    return Err(SimError::Control(format!("at t = {t0}: {e}")));
                }
                Extension::Hermite(
                    dense::Rates::of(sys, y0, &l0),
                    dense::Rates::of(sys, y1, &l1),
                )
            }
        };
        let h = t1 - t0;
        while self.next() < t1 - 1e-9 * self.rec {
            let tk = self.next();
            self.k += 1;
            let y = match &mut ext {
                Extension::Redo(c) => {
                    let mut y = *y0;
                    c.reset();
                    let stepped = c.step(sys, l(t0), l(tk - t0), &mut y);
                    sys.evaluations = counted;
                    stepped.map_err(|e| SimError::Step(format!("sampling at t = {tk}: {e}")))?;
                    y
                }
                Extension::Hermite(r0, r1) => {
                    dense::interpolate(y0, r0, y1, r1, l(h), l((tk - t0) / h))
                }
            };
            let s = sample(sys, tk, &y)?;
            self.sample(out, s)?;
        }
        Ok(())
    }
}

/// How samples inside a step are made: by re-integrating a copy of an
/// adaptive stepper, or from the cubic Hermite extension through the end
/// states and their rates.
enum Extension<B: Backend, const N: usize, I> {
    Redo(I),
    Hermite(dense::Rates<B, N>, dense::Rates<B, N>),
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
    let (mut progress, cancel, extrema) = (opts.progress, opts.cancel, opts.extrema);
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
    let sampled = matches!(control, Control::Sampled { .. }) && !plan.is_empty();
    let ctrl = match control {
        Control::Sampled { rate } if sampled => 1.0 / rate,
        _ => 0.0,
    };
    let mut grid = Grid::new(&plan, ctrl, t_end);
    let rec = if opts.record || opts.sink.is_some() {
        record
    } else {
        0.0
    };
    let mut emit = Emit::new(opts.record, opts.sink, rec);
    let mut sys = ClosedLoop {
        sampled,
        compensate,
        ..ClosedLoop::new(vehicle.as_ref(), &mut plan, m, nv)?
    };
    let mut y = initial;
    let mut bps = breakpoints(&sys, locate_events);

    let mut out = empty_output(mode_names);
    out.warnings = plan_warnings(sys.plan, ctrl, dt, t_end);
    let start = Instant::now();
    let mut t = 0.0f64;
    begin(&mut sys, &mut emit, &mut out, &mut y)?;
    let mut progress_next = 0.0;
    let mut forced_for_next_step = false;
    while t < t_end {
        let t_next = grid.next(t_end);
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
            let stats = stepper
                .step(&mut sys, l(t), l(h), &mut y)
                .map_err(|e| step_error(&mut sys, &e, t, h))?;
            out.steps += u64::from(stats.substeps.max(1));
            if !bps.is_empty()
                && let Some(c) = crossing(&mut sys, &bps, t, h, &before, &y)
            {
                // Split the step at the crossing: redo [t, tc], restart
                // the dt grid from tc.
                let mut cx = Cx::new(&mut sys, &mut emit, &mut out, locate_events);
                t = cx.at_crossing(&mut stepper, &c, (t, h, &before), &mut y)?;
                forced_for_next_step = true;
                seg_start = t;
                j = 0;
                continue;
            }
            // A condition switch (Ψ below a threshold, a user predicate):
            // when it holds at the end of this step, bisect on redone steps
            // for the first instant and switch there.
            if sys.has_condition() && sys.condition_holds(ts, &y) {
                let step = (t, ts, h, &before);
                let mut cx = Cx::new(&mut sys, &mut emit, &mut out, locate_events);
                let tc = cx.at_condition(
                    &mut stepper,
                    step,
                    &mut y,
                    &mut bps,
                    &mut forced_for_next_step,
                )?;
                t = tc;
                seg_start = t;
                j = 0;
                continue;
            }
            // The run's stop condition: located like a switch, and the run
            // ends there with a final sample.
            if stop.is_some() && sys.stop_holds(&mut stop, ts, &y) {
                let step = (t, ts, h, &before, &y);
                let holds = &mut |s: &mut ClosedLoop<'_, '_, B, N>, tt, yy: &_| {
                    s.stop_holds(&mut stop, tt, yy)
                };
                let (tc, y_c) = locate_condition(&mut sys, &mut stepper, holds, step)?;
                emit.inside(&mut out, &mut sys, &stepper, t, &before, tc, &y_c)?;
                y = y_c;
                out.stopped_at = Some(tc);
                return finish_early(out, &mut sys, &mut emit, tc, &y, start);
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
            report_progress(progress.as_deref_mut(), t / t_end, &mut progress_next);
            if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                out.interrupted_at = Some(t);
                return finish_early(out, &mut sys, &mut emit, t, &y, start);
            }
        }
        t = t_next;
        let (switch_due, control_due) = grid.arrive(t);
        let mut cx = Cx::new(&mut sys, &mut emit, &mut out, locate_events);
        if let Some(b) = cx.at_checkpoint(&mut stepper, t, &mut y, switch_due, control_due)? {
            bps = b;
        }
        if extrema || t >= t_end {
            track_state(&mut out, &mut sys, t, &y)?;
        }
        emit.at_checkpoint(&mut out, &mut sys, t, &y, t >= t_end)?;
    }
    out.evaluations = sys.evaluations;
    out.wall = start.elapsed().as_secs_f64();
    Ok(out)
}

/// The run's output before the first sample: empty, with the extrema at
/// their neutral values.
fn empty_output(mode_names: Vec<&'static str>) -> RunOutput {
    RunOutput {
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
    }
}

/// What the plan and control settings will do that a user may not expect:
/// steps shortened by a control grid finer than `dt`, segments that never
/// run.
fn plan_warnings<B: Backend>(
    plan: &[super::Segment<'_, B>],
    ctrl: f64,
    dt: f64,
    t_end: f64,
) -> Vec<String> {
    let mut warnings = Vec::new();
    // Control instants are checkpoints the steps land on (the command
    // changes there): a finer grid than dt shortens every step. Record
    // instants are not: samples come from the steps' continuous extension.
    if ctrl > 0.0 && ctrl < dt * (1.0 - 1e-9) {
        warnings.push(format!(
            "steps land on every control instant: at {} Hz the steps are at most {ctrl} s, not dt = {dt} s",
            1.0 / ctrl
        ));
    }
    // A segment that ends at or after the end of the run leaves the ones
    // after it unused: say so (a `duration` shortened on purpose is fine,
    // but a typo in `until` would otherwise show only as "0 switches").
    if let Some(k) = plan
        .iter()
        .position(|s| matches!(s.until, Until::Time(u) if u >= t_end))
        && k + 1 < plan.len()
    {
        let u = match plan[k].until {
            Until::Time(u) => u,
            _ => t_end,
        };
        warnings.push(format!(
            "segment {k} ({}) lasts until {u} s, not before the end of the run at {t_end} s: \
             segment {} ({}) and any after it never run",
            plan[k].mode.name(),
            k + 1,
            plan[k + 1].mode.name()
        ));
    }
    warnings
}

/// A failed step's error: a mode's complaint about its input, said as the
/// reference's fault or as divergence, else the integrator's own.
fn step_error<B: Backend, const N: usize>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    e: &integrators::StepError,
    t: f64,
    h: f64,
) -> SimError {
    SimError::Step(match sys.error.take() {
        // A non-finite reference is the reference's fault; a non-finite
        // state means the step diverged.
        Some(c) if c.contains("`reference") => format!(
            "in the step from t = {t} (h = {h}): {c}: the reference returned NaN or ∞ there"
        ),
        Some(c) => format!(
            "in the step from t = {t} (h = {h}): {c}; the state diverged — try a smaller --dt"
        ),
        None => e.to_string(),
    })
}

/// Ends a run before its duration (a stop condition, a cancel) with a
/// sample of the state where it stopped.
fn finish_early<B: Backend, const N: usize>(
    mut out: RunOutput,
    sys: &mut ClosedLoop<'_, '_, B, N>,
    emit: &mut Emit<'_, '_>,
    t: f64,
    y: &State<B, N>,
    start: Instant,
) -> Result<RunOutput, SimError> {
    let s = sample(sys, t, y)?;
    track(&mut out, &s);
    emit.sample(&mut out, s)?;
    out.evaluations = sys.evaluations;
    out.wall = start.elapsed().as_secs_f64();
    Ok(out)
}

/// The checkpoints that change the dynamics: control instants `k·Δ` of
/// sampled control (`ctrl` = Δ, 0 for continuous control) and the times
/// at which segments end, each computed, never accumulated.
struct Grid {
    ctrl: f64,
    k_ctrl: u64,
    switch_times: Vec<f64>,
    k_sw: usize,
}

impl Grid {
    fn new<B: Backend>(plan: &[super::Segment<'_, B>], ctrl: f64, t_end: f64) -> Self {
        let switch_times = plan
            .iter()
            .filter_map(|s| match s.until {
                Until::Time(u) => Some(u),
                _ => None,
            })
            .filter(|u| *u < t_end)
            .collect();
        Self {
            ctrl,
            k_ctrl: 0,
            switch_times,
            k_sw: 0,
        }
    }

    /// The next checkpoint, or `t_end`.
    fn next(&self, t_end: f64) -> f64 {
        let mut t_next = t_end;
        if self.ctrl > 0.0 {
            t_next = t_next.min((self.k_ctrl + 1) as f64 * self.ctrl);
        }
        if let Some(&ts) = self.switch_times.get(self.k_sw) {
            t_next = t_next.min(ts);
        }
        t_next
    }

    /// Arrived at checkpoint `t`: whether a time switch is due there, and
    /// whether it is a control instant.
    fn arrive(&mut self, t: f64) -> (bool, bool) {
        let switch_due = self.switch_times.get(self.k_sw).is_some_and(|&ts| ts <= t);
        if switch_due {
            self.k_sw += 1;
        }
        let on = |k: u64| (k as f64 * self.ctrl - t).abs() <= 1e-9 * self.ctrl;
        if self.ctrl > 0.0 && on(self.k_ctrl + 1) {
            self.k_ctrl += 1;
        }
        (switch_due, self.ctrl > 0.0 && on(self.k_ctrl))
    }
}

/// The breakpoints of the active mode (none without event location),
/// copied so that the loop can call the system while it walks them.
fn breakpoints<B: Backend, const N: usize>(
    sys: &ClosedLoop<'_, '_, B, N>,
    locate_events: bool,
) -> Vec<Breakpoint<B>> {
    if locate_events {
        sys.plan
            .get(sys.active)
            .map_or_else(Vec::new, |s| s.mode.breakpoints().to_vec())
    } else {
        Vec::new()
    }
}

/// The start of a run: the held command of sampled control, the vehicle's
/// internal states where the first command puts them (spinning rotors,
/// say), the sink told the mode names, and the first sample.
fn begin<B: Backend, const N: usize>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    emit: &mut Emit<'_, '_>,
    out: &mut RunOutput,
    y: &mut State<B, N>,
) -> Result<(), SimError> {
    let l = S::<B>::lit;
    if sys.sampled {
        sys.held = sys.command(l(0.0), y);
    }
    if sys.nv > 0 {
        let w = sys
            .command(l(0.0), y)
            .map_or_else(Wrench::zero, |c| Wrench {
                thrust: c.out.thrust,
                moment: c.out.moment,
            });
        let (m, nv) = (sys.m, sys.nv);
        sys.vehicle.initial_states(&w, &mut y.extra[m..m + nv]);
    }
    if let Some(k) = emit.sink.as_deref_mut() {
        k.begin(&out.mode_names).map_err(SimError::Output)?;
    }
    let s0 = sample(sys, 0.0, y)?;
    track(out, &s0);
    emit.sample(out, s0)
}

/// Calls the progress callback with the fraction done, at most every 0.5 %.
fn report_progress(progress: Option<&mut (dyn FnMut(f64) + '_)>, done: f64, next: &mut f64) {
    if let Some(p) = progress
        && done >= *next
    {
        p(done);
        *next = (done + 0.005).min(1.0);
    }
}

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
struct Cx<'c, 's, 'a, 'o, 'k, B: Backend, const N: usize> {
    sys: &'c mut ClosedLoop<'s, 'a, B, N>,
    emit: &'c mut Emit<'o, 'k>,
    out: &'c mut RunOutput,
    locate_events: bool,
}

impl<'c, 's, 'a, 'o, 'k, B: Backend, const N: usize> Cx<'c, 's, 'a, 'o, 'k, B, N> {
    fn new(
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
    /// sampled; the law is left forced onto the far branch. Returns its time.
    fn at_crossing<I: Integrator<B, N>>(
        &mut self,
        stepper: &mut I,
        c: &Crossing,
        (t, h, before): (f64, f64, &State<B, N>),
        y: &mut State<B, N>,
    ) -> Result<f64, SimError> {
        let (sys, emit, out) = (&mut *self.sys, &mut *self.emit, &mut *self.out);
        let (tc, steps, pre, post) = split_at_crossing(sys, stepper, c, t, h, before, y)?;
        out.steps += steps;
        sys.plan[sys.active].mode.force_branch(c.index, pre);
        emit.inside(out, sys, stepper, t, before, tc, y)?;
        sys.plan[sys.active].mode.force_branch(c.index, post);
        track_state(out, sys, tc, y)?;
        emit.exact(out, sys, tc, y)?;
        out.events += 1;
        out.event_times.push((tc, c.index));
        Ok(tc)
    }

    /// The active segment's condition holds at the end of the step
    /// `(t, ts, h, before)` (state `y`): the first instant it holds,
    /// located by bisection on redone steps; the samples up to it; the
    /// switch there (`bps` becomes the new mode's breakpoints), a new held
    /// command under sampled control, the figures and sample at it, and a
    /// stepper restart. `y` becomes the state there; returns its time.
    fn at_condition<I: Integrator<B, N>>(
        &mut self,
        stepper: &mut I,
        (t, ts, h, before): (f64, f64, f64, &State<B, N>),
        y: &mut State<B, N>,
        bps: &mut Vec<Breakpoint<B>>,
        forced: &mut bool,
    ) -> Result<f64, SimError> {
        let (sys, emit, out) = (&mut *self.sys, &mut *self.emit, &mut *self.out);
        let holds = &mut |s: &mut ClosedLoop<'_, '_, B, N>, tt, yy: &_| s.condition_holds(tt, yy);
        let (tc, y_c) = locate_condition(sys, stepper, holds, (t, ts, h, before, y))?;
        emit.inside(out, sys, stepper, t, before, tc, &y_c)?;
        release(sys, bps.len(), forced);
        *y = y_c;
        if let Some(b) = switch_segment(sys, emit, out, tc, y, self.locate_events)? {
            *bps = b;
        }
        if sys.sampled {
            sys.held = sys.command(S::<B>::lit(tc), y);
        }
        track_state(out, sys, tc, y)?;
        emit.exact(out, sys, tc, y)?;
        stepper.reset();
        Ok(tc)
    }

    /// At a checkpoint `t` (state `y`): the next segment when `switch_due`
    /// and the active one ends at a time, a new held command under sampled
    /// control after a switch or at a control instant, and a stepper
    /// restart after either. Returns the new mode's breakpoints after a
    /// switch.
    fn at_checkpoint<I: Integrator<B, N>>(
        &mut self,
        stepper: &mut I,
        t: f64,
        y: &mut State<B, N>,
        switch_due: bool,
        control_due: bool,
    ) -> Result<Option<Vec<Breakpoint<B>>>, SimError> {
        let sys = &mut *self.sys;
        // Only a segment that ends at a time is left here (one waiting for
        // its condition stays active past a later segment's time).
        let leaves = switch_due
            && sys
                .plan
                .get(sys.active)
                .is_some_and(|s| matches!(s.until, Until::Time(u) if u <= t));
        let new = if leaves {
            switch_segment(sys, self.emit, self.out, t, y, self.locate_events)?
        } else {
            None
        };
        let mut changed = new.is_some();
        if sys.sampled && (changed || control_due) {
            sys.held = sys.command(S::<B>::lit(t), y);
            changed = true;
        }
        if changed {
            stepper.reset();
        }
        Ok(new)
    }
}
