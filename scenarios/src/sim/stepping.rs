//! The stepping loop: from checkpoint to checkpoint (control samples,
//! time switches, the end: what changes the dynamics; each `k·Δ` or a
//! listed time, never an accumulated sum), in steps of `dt` with the last
//! one shortened to land on the checkpoint; events inside a step are
//! located by [`super::events`]. Record instants are not checkpoints:
//! samples come from each step's continuous extension, so the computed
//! trajectory, the run's extrema (over every step end and located event)
//! and its evaluation count are the same whatever is recorded.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use controllers::Breakpoint;
use dynamics::{Vehicle, Wind, Wrench};
use integrators::{Integrator, State};
use lie::{Backend, Real, S, SimdReal};

use super::closed_loop::{ClosedLoop, Layout, Parked};
use super::emit::{Emit, Record};
use super::events::{any_crossed, crossing, locate_condition};
use super::grid::Grid;
use super::instants::{Cx, breakpoints, release};
use super::record::{empty_sample, sample, track, track_figures};
use super::sense;
use super::{
    Control, Divergence, DivergenceGuard, Engine, PsiRange, RunOptions, RunOutput, Segment,
    SimError, Termination, Until,
};

/// The loop's state between two calls of `advance_to`: where the run is on
/// its checkpoints and step grid, the sample stream, the output so far,
/// and the closed loop's own state.
pub(crate) struct Running<B: Backend, const N: usize> {
    /// The time of the state, s.
    pub t: f64,
    /// How the run ended, once it has.
    pub done: Option<Termination>,
    pub out: RunOutput,
    started: bool,
    /// The builder was given the vehicle's internal states: the first
    /// command does not set them.
    vehicle_states_given: bool,
    dt: f64,
    t_end: f64,
    /// The checkpoint the steps are heading for.
    t_next: f64,
    /// The steps run `seg_start + k·dt` from the last checkpoint.
    seg_start: f64,
    j: u64,
    /// In a run on a scalar with derivatives: a zero carrying the
    /// derivatives of `seg_start` (zero after a fixed-time checkpoint, the
    /// crossing time's after a located crossing), so that every time and
    /// step length handed to the stepper moves with the seeded inputs as
    /// the plain run's would. Nothing for `f32`/`f64`.
    phase: S<B>,
    grid: Grid,
    bps: Vec<Breakpoint<B>>,
    /// The active law is held on a breakpoint branch for the next step.
    forced: bool,
    locate_events: bool,
    extrema: bool,
    rec: Record,
    parked: Parked<B, N>,
    progress_next: f64,
    /// The guard limit a stop-condition probe found passed (kept over the
    /// bisection's probes, as the located instant is where one held).
    diverged: Option<Divergence>,
}

impl<B: Backend, const N: usize> Running<B, N> {
    /// The active segment.
    pub fn active(&self) -> usize {
        self.parked.active
    }
}

/// The loop's state before the first step of `sim`'s run (its output
/// names the modes and carries the plan's warnings).
pub(crate) fn prepare<'a, B: Backend, const N: usize>(
    vehicle: &dyn Vehicle<B>,
    wind: Option<&mut (dyn Wind + 'a)>,
    plan: &mut [Segment<'a, B>],
    s: &Settings,
) -> Result<Running<B, N>, SimError> {
    let sampled = s.control.command_rate().is_some() && !plan.is_empty();
    let ctrl = match s.control.command_rate() {
        Some(rate) if sampled => 1.0 / rate,
        _ => 0.0,
    };
    // A multi-rate loop whose rates are equal is the single-rate loop.
    let outer = match s.control {
        Control::MultiRate(r) if sampled && r.position < r.attitude => 1.0 / r.position,
        _ => 0.0,
    };
    let sys = ClosedLoop {
        sampled,
        cascade: outer > 0.0,
        compensate: s.compensate,
        ..ClosedLoop::new(vehicle, wind, plan, s.layout)?
    };
    let mut out = empty_output(sys.plan.iter().map(|s| s.mode.name()).collect());
    out.epsilon = <S<B> as lie::Real>::epsilon().to_f64_lossless();
    out.warnings = plan_warnings(sys.plan, ctrl, s.dt, s.t_end);
    let jumps = sys
        .wind
        .as_deref()
        .map_or_else(Vec::new, |w| w.jumps(s.t_end));
    let grid = Grid::new(sys.plan, (ctrl, outer), s.t_end, jumps);
    Ok(Running {
        t: 0.0,
        done: None,
        out,
        started: false,
        vehicle_states_given: s.vehicle_states_given,
        dt: s.dt,
        t_end: s.t_end,
        t_next: grid.next(s.t_end),
        seg_start: 0.0,
        j: 0,
        phase: S::<B>::lit(0.0),
        grid,
        bps: breakpoints(&sys, s.locate_events),
        forced: false,
        locate_events: s.locate_events,
        extrema: true,
        rec: Record {
            keep: true,
            last_t: f64::NAN,
            rec: s.record,
            k: 0,
        },
        parked: sys.park(),
        progress_next: 0.0,
        diverged: None,
    })
}

/// The settings [`prepare`] reads.
pub(crate) struct Settings {
    pub control: Control,
    pub compensate: bool,
    pub layout: Layout,
    pub dt: f64,
    pub t_end: f64,
    pub record: f64,
    pub locate_events: bool,
    pub vehicle_states_given: bool,
}

/// [`Simulation::advance_to_with`]: the loop rebuilt around the
/// simulation's vehicle and plan, stepped to `until`, and parked again.
pub(crate) fn advance<B: Backend, const N: usize, I: Integrator<B, N>>(
    sim: &mut Engine<'_, B, N, I>,
    until: f64,
    opts: RunOptions<'_>,
) -> Result<(), SimError> {
    let wall = Instant::now();
    let Engine {
        vehicle,
        wind,
        sensing,
        plan,
        stepper,
        y,
        stop,
        guard,
        running: r,
        perturbed,
        layout,
        ..
    } = sim;
    if r.done.is_some() {
        return Ok(());
    }
    // A state set between two calls is refused before a step or a command
    // reads it.
    if *perturbed && let Some(f) = layout.non_finite_part(y) {
        return Err(SimError::Setting {
            field: "state",
            message: format!("`{f}` was set to a value that is not finite"),
        });
    }
    let mut sys = ClosedLoop::resume(
        vehicle.as_ref(),
        wind.as_deref_mut(),
        sensing.as_deref_mut(),
        plan,
        &r.parked,
    );
    if !r.started {
        r.extrema = opts.extrema;
        if let Some(s) = sys.sensing.as_deref_mut() {
            s.keep = opts.record || opts.sink.is_some();
        }
        r.rec.keep = opts.record;
        if !(opts.record || opts.sink.is_some()) {
            r.rec.rec = 0.0;
        }
    }
    let mut emit = Emit {
        r: r.rec,
        sink: opts.sink,
    };
    let mut result = Ok(());
    if !r.started {
        r.started = true;
        result = begin(&mut sys, &mut emit, &mut r.out, y, r.vehicle_states_given);
    }
    if std::mem::take(perturbed) {
        stepper.reset();
        release(&mut sys, r.bps.len(), &mut r.forced);
    }
    if result.is_ok() {
        let mut lp = Loop {
            sys: &mut sys,
            emit: &mut emit,
            stepper,
            stop,
            guard: *guard,
            r,
            y,
        };
        result = lp.until(until, opts.progress, opts.cancel);
    }
    if result.is_ok() {
        result = super::sense::drain(&mut sys, &mut emit, &mut r.out);
    }
    r.parked = sys.park();
    r.rec = emit.r;
    r.out.termination = r.done.unwrap_or(Termination::Interrupted { t: r.t });
    r.out.evaluations = r.parked.evaluations;
    r.out.wall += wall.elapsed().as_secs_f64();
    result
}

/// [`Simulation::finish`]: the output, with a last sample where a run not
/// at its end stopped.
pub(crate) fn finish<B: Backend, const N: usize, I: Integrator<B, N>>(
    sim: Engine<'_, B, N, I>,
) -> Result<RunOutput, SimError> {
    let Engine {
        vehicle,
        mut wind,
        mut sensing,
        mut plan,
        mut y,
        mut running,
        ..
    } = sim;
    let r = &mut *running;
    if r.done.is_none() {
        let mut sys = ClosedLoop::resume(
            vehicle.as_ref(),
            wind.as_deref_mut(),
            sensing.as_deref_mut(),
            &mut plan,
            &r.parked,
        );
        let mut emit = Emit {
            r: r.rec,
            sink: None,
        };
        if !r.started {
            r.started = true;
            let given = r.vehicle_states_given;
            begin(&mut sys, &mut emit, &mut r.out, &mut y, given)?;
        }
        r.done = Some(Termination::Interrupted { t: r.t });
        // A record instant the run paused on was sampled already (labelled
        // k·rec, which may differ from the step's end in the last bit).
        let sampled = (emit.r.last_t - r.t).abs() <= 1e-9 * r.dt;
        if !sampled {
            finish_early(&mut r.out, &mut sys, &mut emit, r.t, &y)?;
        }
        r.out.evaluations = sys.evaluations;
    }
    running.out.termination = running.done.unwrap_or(Termination::Completed);
    Ok(running.out)
}

/// What one call of `advance_to` works on.
struct Loop<'c, 's, 'a, 'o, 'k, 'p, B: Backend, const N: usize, I> {
    sys: &'c mut ClosedLoop<'s, 'a, B, N>,
    emit: &'c mut Emit<'o, 'k>,
    stepper: &'c mut I,
    stop: &'c mut Option<super::Condition<'p, B>>,
    guard: DivergenceGuard,
    r: &'c mut Running<B, N>,
    y: &'c mut State<B, N>,
}

impl<B: Backend, const N: usize, I: Integrator<B, N>> Loop<'_, '_, '_, '_, '_, '_, B, N, I> {
    /// Steps from checkpoint to checkpoint until the next step would end
    /// after `until`, the run ends, or `cancel` is set.
    fn until(
        &mut self,
        until: f64,
        mut progress: Option<&mut dyn FnMut(f64)>,
        cancel: Option<&AtomicBool>,
    ) -> Result<(), SimError> {
        let l = S::<B>::lit;
        let (dt, t_end) = (self.r.dt, self.r.t_end);
        while self.r.t < t_end {
            // Steps of dt from the last checkpoint, the last one shortened
            // to land on the next.
            while self.r.t < self.r.t_next {
                let r = &mut *self.r;
                let mut ts = r.seg_start + (r.j + 1) as f64 * dt;
                let landing = ts > r.t_next - 1e-12 * dt.max(r.t_next);
                if landing {
                    ts = r.t_next;
                }
                if ts > until + 1e-9 * dt {
                    return Ok(());
                }
                let (t, h) = (r.t, ts - r.t);
                // On the grid both ends move with `phase`; a landing step
                // ends on a fixed time and its length takes the difference.
                let t_s = l(t).with_derivatives_of(r.phase);
                let h_s = if landing {
                    l(h).with_derivatives_of(-r.phase)
                } else {
                    l(h)
                };
                let before = *self.y;
                let stats = match self.stepper.step(self.sys, t_s, h_s, self.y) {
                    Ok(s) => s,
                    Err(e) => return self.failed_step(e, t, h),
                };
                self.r.out.steps += u64::from(stats.substeps.max(1));
                if self.after_step((t, ts, h), &before)? {
                    return Ok(());
                }
                report_progress(
                    progress.as_deref_mut(),
                    self.r.t / t_end,
                    &mut self.r.progress_next,
                );
                if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
                    return self.end_early(Termination::Interrupted { t: self.r.t });
                }
            }
            self.at_checkpoint()?;
        }
        self.r.done.get_or_insert(Termination::Completed);
        Ok(())
    }

    /// What follows the step `(t, ts, h)` from `before`: a breakpoint
    /// crossing inside it (the step split there), a condition switch, the
    /// stop condition or the guard (the run ends: returns true), or the
    /// samples inside it and the figures at its end.
    fn after_step(
        &mut self,
        (t, ts, h): (f64, f64, f64),
        before: &State<B, N>,
    ) -> Result<bool, SimError> {
        let Self {
            sys,
            emit,
            stepper,
            r,
            y,
            ..
        } = self;
        if any_crossed(&r.bps, before, y)
            && let Some(c) = crossing(sys, &r.bps, t, h, before, y)
        {
            // Split the step at the crossing: redo [t, tc], restart the dt
            // grid from tc.
            let mut cx = Cx::new(sys, emit, &mut r.out, r.locate_events);
            (r.t, r.phase) = cx.at_crossing(*stepper, &c, (t, h, before), r.phase, y)?;
            r.forced = true;
            (r.seg_start, r.j) = (r.t, 0);
            return Ok(false);
        }
        if self.sys.caps.contact.is_some()
            && let Some(end) = self.contact_change((t, ts, h), before)?
        {
            // A condition that holds where a foot touched or let go is
            // taken there: the step ends at the change, and a clearance
            // condition turns true on the same crossing. (One that turned
            // true earlier inside the split step is late by at most the
            // split step.)
            let Self {
                sys,
                emit,
                stepper,
                r,
                y,
                ..
            } = self;
            if !end && sys.has_condition() && !sys.estimating() && sys.condition_holds(r.t, y) {
                let mut cx = Cx::new(sys, emit, &mut r.out, r.locate_events);
                cx.switch_here(*stepper, r.t, y, &mut r.bps, &mut r.forced)?;
            }
            return Ok(end);
        }
        let Self {
            sys,
            emit,
            stepper,
            stop,
            guard,
            r,
            y,
        } = self;
        // A condition switch (Ψ below a threshold, a user predicate): when
        // it holds at the end of this step, bisect on redone steps for the
        // first instant and switch there.
        if sys.has_condition() && !sys.estimating() && sys.condition_holds(ts, y) {
            let mut cx = Cx::new(sys, emit, &mut r.out, r.locate_events);
            let step = (t, ts, h, before);
            let (bps, forced) = (&mut r.bps, &mut r.forced);
            (r.t, r.phase) = cx.at_condition(*stepper, step, r.phase, y, bps, forced)?;
            (r.seg_start, r.j) = (r.t, 0);
            return Ok(false);
        }
        // The run's stop condition and the guard: located like a switch,
        // and the run ends there with a final sample.
        let g = *guard;
        if (stop.is_some() || g.checks_state()) && sys.stop_holds(stop, &g, &mut r.diverged, ts, y)
        {
            let diverged = &mut r.diverged;
            let holds = &mut |s: &mut ClosedLoop<'_, '_, B, N>, tt, yy: &_| {
                s.stop_holds(stop, &g, diverged, tt, yy)
            };
            let (tc, y_c) = locate_condition(sys, *stepper, holds, (t, ts, h, before, y))?;
            emit.inside(&mut r.out, sys, *stepper, (t, before), (tc, &y_c))?;
            sense::piece(sys, *stepper, (t, before), (tc, &y_c))?;
            **y = y_c;
            r.t = tc;
            let end = match r.diverged {
                Some(what) => Termination::Diverged { what, t: tc },
                None => Termination::StoppedBy { t: tc },
            };
            self.end_early(end)?;
            return Ok(true);
        }
        // Samples inside the step, on the branches it was integrated on;
        // then the law decides its branches from the state again.
        emit.inside(&mut r.out, sys, *stepper, (t, before), (ts, y))?;
        sense::piece(sys, *stepper, (t, before), (ts, y))?;
        release(sys, r.bps.len(), &mut r.forced);
        r.t = ts;
        r.j += 1;
        if r.t < r.t_next {
            // A checkpoint's own figures and sample come after what
            // happens there (a switch, a new held command).
            if r.extrema {
                track_figures(&mut r.out, sys, ts, y)?;
            }
            emit.exact(&mut r.out, sys, ts, y)?;
        }
        Ok(false)
    }

    /// A contact point starting or ceasing to push inside the step `(t, ts,
    /// h)` from `before`: its load switches, so the step is redone up to
    /// the change (bisection on redone steps) and the next one starts
    /// there. `Some(true)`: a touchdown faster than the contact's crash
    /// speed ended the run there; `Some(false)`: the step was split;
    /// `None`: no change.
    #[inline(never)]
    fn contact_change(
        &mut self,
        (t, ts, h): (f64, f64, f64),
        before: &State<B, N>,
    ) -> Result<Option<bool>, SimError> {
        let Some(c) = self.sys.caps.contact else {
            return Ok(None);
        };
        let m0 = c.pushing(&before.body);
        if c.pushing(&self.y.body) == m0 {
            return Ok(None);
        }
        let Self {
            sys,
            emit,
            stepper,
            r,
            y,
            ..
        } = self;
        let holds =
            &mut |_: &mut ClosedLoop<'_, '_, B, N>, _, yy: &State<B, N>| c.pushing(&yy.body) != m0;
        // Integrated on the side it came from: the loads switch at the
        // change, and a stage past it would carry the switch into the
        // located state.
        c.hold(Some(m0));
        let located = locate_condition(sys, *stepper, holds, (t, ts, h, before, y));
        let (tc, _) = located.inspect_err(|_| c.hold(None))?;
        let mut y_c = *before;
        stepper.reset();
        let redone = stepper.step(*sys, S::<B>::lit(t), S::<B>::lit(tc - t), &mut y_c);
        c.hold(None);
        redone.map_err(|e| sys.step_error(t, tc - t, e))?;
        emit.inside(&mut r.out, sys, *stepper, (t, before), (tc, &y_c))?;
        sense::piece(sys, *stepper, (t, before), (tc, &y_c))?;
        let changed = m0 ^ c.pushing(&y_c.body);
        let mut crash = None;
        for i in (0..64).filter(|i| changed & (1 << i) != 0) {
            let (pushing, speed) = (m0 & (1 << i) == 0, c.normal_speed(&y_c.body, i));
            r.out.contacts.push(super::ContactChange {
                t: tc,
                point: i,
                pushing,
                normal_speed: speed,
            });
            if pushing && speed > c.crash_speed() && crash.is_none() {
                crash = Some(Termination::Crashed {
                    t: tc,
                    point: i,
                    speed,
                });
            }
        }
        **y = y_c;
        stepper.reset();
        // The change's time is taken as a constant in a dual run (no
        // derivative through it).
        (r.t, r.phase) = (tc, S::<B>::lit(0.0));
        (r.seg_start, r.j) = (r.t, 0);
        if let Some(end) = crash {
            self.end_early(end)?;
            return Ok(Some(true));
        }
        Ok(Some(false))
    }

    /// At the checkpoint the steps were heading for: a time switch, a new
    /// held command, the figures and sample there; then the next one.
    fn at_checkpoint(&mut self) -> Result<(), SimError> {
        let r = &mut *self.r;
        let t = r.t_next;
        r.t = t;
        let due = r.grid.arrive(t);
        if due.jump {
            // The wind changes here: read on its new side from now on, and
            // no load of the old side carried into the next step.
            self.sys.wind_from = t;
            self.stepper.reset();
        }
        let mut cx = Cx::new(self.sys, self.emit, &mut r.out, r.locate_events);
        if let Some(b) = cx.at_checkpoint(self.stepper, t, self.y, due)? {
            r.bps = b;
        }
        if r.extrema || t >= r.t_end {
            track_figures(&mut r.out, self.sys, t, self.y)?;
        }
        self.emit
            .at_checkpoint(&mut r.out, self.sys, t, self.y, t >= r.t_end)?;
        r.t_next = r.grid.next(r.t_end);
        (r.seg_start, r.j, r.phase) = (t, 0, S::<B>::lit(0.0));
        Ok(())
    }

    /// A step failed: the guard's substep cap ends the run as diverged
    /// (the state is where the call began; not sampled again, since the
    /// blow-up is somewhere inside the call); anything else is an error,
    /// with the mode's complaint when one came first.
    fn failed_step(&mut self, e: integrators::StepError, t: f64, h: f64) -> Result<(), SimError> {
        let control = self.sys.complaint();
        if let (Some(cap), integrators::StepError::TooManySubsteps { .. }, None) =
            (self.guard.substeps, &e, control)
        {
            let what = Divergence::Substeps(cap);
            self.r.done = Some(Termination::Diverged { what, t });
            let s = sample(self.sys, t, self.y)?;
            self.r.out.last = s;
            return Ok(());
        }
        Err(SimError::step(t, h, e, control))
    }

    /// Ends the run at the state now with `end` and a last sample there.
    fn end_early(&mut self, end: Termination) -> Result<(), SimError> {
        self.r.done = Some(end);
        finish_early(&mut self.r.out, self.sys, self.emit, self.r.t, self.y)
    }
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
        termination: Termination::Interrupted { t: 0.0 },
        epsilon: f64::EPSILON,
        max_orthogonality_error: 0.0,
        psi_range: PsiRange::EMPTY,
        last: empty_sample(),
        measurements: Vec::new(),
        contacts: Vec::new(),
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

/// Ends a run before its duration (a stop condition, a cancel) with a
/// sample of the state where it stopped.
fn finish_early<B: Backend, const N: usize>(
    out: &mut RunOutput,
    sys: &mut ClosedLoop<'_, '_, B, N>,
    emit: &mut Emit<'_, '_>,
    t: f64,
    y: &State<B, N>,
) -> Result<(), SimError> {
    let s = sample(sys, t, y)?;
    track(out, &s);
    emit.sample(out, s)
}

/// The start of a run: the held command of sampled control, the vehicle's
/// internal states where the first command puts them (spinning rotors,
/// say) unless the builder was given them, the sink told the mode names,
/// and the first sample.
fn begin<B: Backend, const N: usize>(
    sys: &mut ClosedLoop<'_, '_, B, N>,
    emit: &mut Emit<'_, '_>,
    out: &mut RunOutput,
    y: &mut State<B, N>,
    vehicle_states_given: bool,
) -> Result<(), SimError> {
    let l = S::<B>::lit;
    sense::start(sys, y)?;
    if sys.sampled {
        sys.held = if sys.update_outer(0.0, y) {
            sys.control_command(0.0, y)
        } else {
            None
        };
    }
    sense::after_first_command(sys, y)?;
    if sys.layout.vehicle_states > 0 && !vehicle_states_given {
        // Sampled: the command held from t = 0 is the first one (a mode is
        // asked once per control instant); continuous: ask for it.
        let first = if sys.sampled {
            sys.held
        } else {
            sys.command(l(0.0), y)
        };
        let states = sys.layout.vehicle_states_mut(&mut y.extra);
        let ask = match &first {
            Some(c) => match &c.out.rotor_speeds {
                Some(w) => dynamics::Command::RotorSpeeds(w.as_slice()),
                None => dynamics::Command::Wrench(Wrench {
                    thrust: c.out.thrust,
                    moment: c.out.moment,
                }),
            },
            None => dynamics::Command::Wrench(Wrench::zero()),
        };
        if let Some(a) = sys.caps.actuators {
            a.initial_states(ask, states);
        }
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
