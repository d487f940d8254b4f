//! The vehicle, the plan and the held command as one [`System`]: what the
//! integrator sees. Also the scheduler's part of the loop (which segment is
//! active, switching into the next).

use controllers::{ControlError, ModeOutput, RotorSpeeds};
use dynamics::{Capabilities, Command as Ask, LoadInput, Vehicle, Wind, Wrench};
use integrators::{Load, State, System};
use lie::{Backend, Real, S, SimdReal, V3};

use super::{Segment, SwitchRecord, Until};

/// Where the plan's integrals and the vehicle's states sit in the
/// integrator's extra-state array: the integrals first, then the vehicle's
/// states, the rest idle. The one place that knows the offsets; everything
/// else asks it for the part it means.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub(crate) struct Layout {
    /// How many integral states the plan's modes use (the largest
    /// [`controllers::Mode::integrals`] count).
    pub integrals: usize,
    /// How many internal states the vehicle declares.
    pub vehicle_states: usize,
}

impl Layout {
    /// Slots holding states.
    #[inline(always)]
    pub fn in_use(self) -> usize {
        self.integrals + self.vehicle_states
    }
    /// The integral register in `slots`.
    #[inline(always)]
    pub fn integrals<T>(self, slots: &[T]) -> &[T] {
        &slots[..self.integrals]
    }
    /// The integral register in `slots`, to write.
    #[inline(always)]
    pub fn integrals_mut<T>(self, slots: &mut [T]) -> &mut [T] {
        &mut slots[..self.integrals]
    }
    /// The vehicle's states in `slots`.
    #[inline(always)]
    pub fn vehicle_states<T>(self, slots: &[T]) -> &[T] {
        &slots[self.integrals..self.in_use()]
    }
    /// The vehicle's states in `slots`, to write.
    #[inline(always)]
    pub fn vehicle_states_mut<T>(self, slots: &mut [T]) -> &mut [T] {
        &mut slots[self.integrals..self.in_use()]
    }
    /// The first part of `y` that is not finite (`r`, `x`, `v`, `omega`,
    /// `integrals`, `vehicle_states`), if any.
    pub fn non_finite_part<B: Backend, const N: usize>(
        self,
        y: &State<B, N>,
    ) -> Option<&'static str> {
        let bad = |xs: &[S<B>]| xs.iter().any(|x| !x.is_finite());
        y.body.non_finite_field().or_else(|| {
            if bad(self.integrals(&y.extra)) {
                Some("integrals")
            } else if bad(self.vehicle_states(&y.extra)) {
                Some("vehicle_states")
            } else {
                None
            }
        })
    }
    /// Both parts of `slots`, to write.
    pub fn split_mut<T>(self, slots: &mut [T]) -> (&mut [T], &mut [T]) {
        let (integrals, rest) = slots.split_at_mut(self.integrals);
        (integrals, &mut rest[..self.vehicle_states])
    }
}

/// A command with the integral register's rates.
#[derive(Copy, Clone)]
pub(crate) struct Command<B: Backend, const N: usize> {
    pub out: ModeOutput<B>,
    pub rates: [S<B>; N],
}

pub(crate) struct ClosedLoop<'s, 'a, B: Backend, const N: usize> {
    pub vehicle: &'s dyn Vehicle<B>,
    /// The vehicle's optional parts, read once.
    pub caps: Capabilities<'s, B>,
    pub wind: Option<&'s mut (dyn Wind + 'a)>,
    /// The sensors and the estimator, when the run has them.
    pub sensing: Option<&'s mut super::sensing::Sensing<'a, B>>,
    pub plan: &'s mut [Segment<'a, B>],
    pub active: usize,
    /// Where the integrals and the vehicle's states are.
    pub layout: Layout,
    /// Sampled control: the held command.
    pub held: Option<Command<B, N>>,
    pub sampled: bool,
    /// A multi-rate loop: the active mode's outer loop is updated at the
    /// outer instants (see [`ClosedLoop::update_outer`]).
    pub cascade: bool,
    /// Cancel the vehicle's configuration moment in the command.
    pub compensate: bool,
    pub inertia_inv: lie::M3<B>,
    pub evaluations: u64,
    /// The first input a mode rejected since it was last taken.
    pub error: Option<ControlError>,
    /// The state that rejection came on was finite (see
    /// [`ClosedLoop::complaint`]).
    pub error_on_finite_state: bool,
    /// The last wind jump the run has arrived at (−∞ before the first):
    /// from there on the wind is read just after it, on its new side,
    /// while the step that ended there read it on the old side.
    pub wind_from: f64,
    /// The answer the run's figures just got at the end of a step, for
    /// the next load if it comes at the same point (see [`Answer`]).
    pub answer: Option<Answer<B, N>>,
}

/// The active mode's wrench and integral rates at `(t, y)`, kept by the
/// per-step figures (which ask the mode for its whole command at every
/// step's end) for the next step's first load, which asks the same mode
/// at the same point: a mode's answer depends on the time, the state and
/// its configuration alone (`controllers::Mode` says so), so the answer
/// is the one the mode would give again, bit for bit. Kept for one load
/// only (any load takes it), and only on scalars that carry no
/// derivatives (a dual step's start time carries the grid phase's).
#[derive(Copy, Clone)]
pub(crate) struct Answer<B: Backend, const N: usize> {
    t: f64,
    y: State<B, N>,
    active: usize,
    wrench: Wrench<B>,
    rates: [S<B>; N],
}

impl<B: Backend, const N: usize> Answer<B, N> {
    /// The answer of `command` at `(t, y)` from the segment `active`.
    pub fn new(t: S<B>, y: &State<B, N>, active: usize, c: &Command<B, N>) -> Option<Self> {
        (!S::<B>::CARRIES_DERIVATIVES && c.out.rotor_speeds.is_none()).then(|| Self {
            t: t.to_f64_lossless(),
            y: *y,
            active,
            wrench: Wrench {
                thrust: c.out.thrust,
                moment: c.out.moment,
            },
            rates: c.rates,
        })
    }

    /// Whether this is the answer at `(t, y)` from the segment `active`:
    /// the same bits (`==` would take −0 for +0).
    fn fits(&self, active: usize, t: S<B>, y: &State<B, N>) -> bool {
        let bits =
            |a: S<B>, b: S<B>| a.to_f64_lossless().to_bits() == b.to_f64_lossless().to_bits();
        let same3 = |a: V3<B>, b: V3<B>| {
            let (a, b) = (B::vec3_to_array(a), B::vec3_to_array(b));
            (0..3).all(|k| bits(a[k], b[k]))
        };
        let (p, q) = (&self.y.body, &y.body);
        let (pr, qr) = (B::mat3_cols(p.r), B::mat3_cols(q.r));
        self.active == active
            && self.t.to_bits() == t.to_f64_lossless().to_bits()
            && (0..3).all(|k| same3(pr[k], qr[k]))
            && same3(p.x, q.x)
            && same3(p.v, q.v)
            && same3(p.omega, q.omega)
            && (0..N).all(|k| bits(self.y.extra[k], y.extra[k]))
    }
}

/// What a [`ClosedLoop`] holds besides its borrows: kept between two calls
/// of `advance_to`, when the loop is rebuilt around the same vehicle and
/// plan.
#[derive(Copy, Clone)]
pub(crate) struct Parked<B: Backend, const N: usize> {
    pub active: usize,
    layout: Layout,
    held: Option<Command<B, N>>,
    sampled: bool,
    cascade: bool,
    compensate: bool,
    inertia_inv: lie::M3<B>,
    pub evaluations: u64,
    wind_from: f64,
}

/// `answer` unless `speeds` (what `mode` commanded) are not one per rotor
/// of `vehicle` (asked only when there are speeds): then the mode's error.
#[inline(always)]
fn check_speeds<B: Backend, T>(
    answer: Result<T, ControlError>,
    speeds: Option<&RotorSpeeds<B>>,
    mode: &dyn controllers::Mode<B>,
    vehicle: &dyn Vehicle<B>,
) -> Result<T, ControlError> {
    match speeds {
        Some(w) if w.as_slice().len() != vehicle.actuator_count() => {
            Err(ControlError::RotorSpeedCount {
                mode: mode.name(),
                given: w.as_slice().len(),
                rotors: vehicle.actuator_count(),
            })
        }
        _ => answer,
    }
}

/// A load of NaNs: what a failed command hands the integrator, which then
/// stops on a non-finite state (the error is kept for the report).
fn nan_load<B: Backend, const N: usize>() -> Load<B, N> {
    let nan = S::<B>::nan();
    let n = B::vec3(nan, nan, nan);
    Load {
        force: n,
        moment: n,
        extra_rate: [nan; N],
    }
}

impl<'s, 'a, B: Backend, const N: usize> ClosedLoop<'s, 'a, B, N> {
    /// `vehicle` flying `plan` from its first segment, continuous control,
    /// its states laid out by `layout`; an error for a singular inertia.
    pub fn new(
        vehicle: &'s dyn Vehicle<B>,
        wind: Option<&'s mut (dyn Wind + 'a)>,
        plan: &'s mut [Segment<'a, B>],
        layout: Layout,
    ) -> Result<Self, super::SimError> {
        let inertia_inv =
            lie::ops::inverse::<B>(vehicle.inertia()).ok_or_else(|| super::SimError::Setting {
                field: "vehicle",
                message: "its inertia is singular".into(),
            })?;
        Ok(Self {
            vehicle,
            caps: vehicle.capabilities(),
            wind,
            sensing: None,
            plan,
            active: 0,
            layout,
            held: None,
            sampled: false,
            cascade: false,
            compensate: false,
            inertia_inv,
            evaluations: 0,
            error: None,
            error_on_finite_state: true,
            wind_from: f64::NEG_INFINITY,
            answer: None,
        })
    }

    /// The loop's own state, to rebuild it with [`ClosedLoop::resume`].
    pub fn park(&self) -> Parked<B, N> {
        Parked {
            active: self.active,
            layout: self.layout,
            held: self.held,
            sampled: self.sampled,
            cascade: self.cascade,
            compensate: self.compensate,
            inertia_inv: self.inertia_inv,
            evaluations: self.evaluations,
            wind_from: self.wind_from,
        }
    }

    /// The loop around `vehicle` and `plan` as it was parked.
    pub fn resume(
        vehicle: &'s dyn Vehicle<B>,
        wind: Option<&'s mut (dyn Wind + 'a)>,
        sensing: Option<&'s mut super::sensing::Sensing<'a, B>>,
        plan: &'s mut [Segment<'a, B>],
        p: &Parked<B, N>,
    ) -> Self {
        Self {
            vehicle,
            caps: vehicle.capabilities(),
            wind,
            sensing,
            plan,
            active: p.active,
            layout: p.layout,
            held: p.held,
            sampled: p.sampled,
            cascade: p.cascade,
            compensate: p.compensate,
            inertia_inv: p.inertia_inv,
            evaluations: p.evaluations,
            error: None,
            error_on_finite_state: true,
            wind_from: p.wind_from,
            answer: None,
        }
    }

    /// The time the wind is read at for an evaluation at `t`: just after
    /// the last jump arrived at when `t` is on it (within the scalar's
    /// rounding of it), so that the steps from a jump on see its new side.
    fn wind_time(&self, t: f64) -> f64 {
        if self.wind_from == f64::NEG_INFINITY {
            return t;
        }
        let tol = 8.0 * S::<B>::epsilon().to_f64_lossless() * self.wind_from.abs();
        if t <= self.wind_from + tol {
            self.wind_from.next_up()
        } else {
            t
        }
    }

    /// The wind at `(t, y)` (zero without one).
    pub fn wind_at(&mut self, t: f64, y: &State<B, N>) -> [f64; 3] {
        let tw = self.wind_time(t);
        match self.wind.as_deref_mut() {
            Some(w) => w.velocity(tw, lie::ops::vec3_f64::<B>(y.body.x)),
            None => [0.0; 3],
        }
    }

    /// The active mode's command at `(t, y)`; `None` without a plan or when
    /// the mode rejects its input (the error is kept for the report).
    #[inline]
    pub fn command(&mut self, t: S<B>, y: &State<B, N>) -> Option<Command<B, N>> {
        let mut rates = [S::<B>::lit(0.0); N];
        let out = self.command_into(t, y, &mut rates)?;
        Some(Command { out, rates })
    }

    /// [`ClosedLoop::command`] writing the integral rates into `rates`
    /// (zero on entry): the load evaluation's path, without an intermediate
    /// copy. Rotor speeds of a count other than the vehicle's rotors are
    /// the mode's error.
    #[inline(always)]
    fn command_into(
        &mut self,
        t: S<B>,
        y: &State<B, N>,
        rates: &mut [S<B>; N],
    ) -> Option<ModeOutput<B>> {
        let answer = self.ask(t, y, rates)?;
        self.settle(y, answer, |out| &mut out.moment)
    }

    /// The active mode's answer at `(t, y)` as it gave it (`None` without a
    /// plan); rotor speeds of a count other than the vehicle's rotors are
    /// its error.
    #[inline(always)]
    fn ask(
        &self,
        t: S<B>,
        y: &State<B, N>,
        rates: &mut [S<B>; N],
    ) -> Option<Result<ModeOutput<B>, ControlError>> {
        let seg = self.plan.get(self.active)?;
        let at = self.layout;
        let answer = seg.mode.command(
            t,
            y.body.as_group(),
            at.integrals(&y.extra),
            at.integrals_mut(rates),
        );
        let speeds = answer.as_ref().ok().and_then(|o| o.rotor_speeds);
        Some(check_speeds(
            answer,
            speeds.as_ref(),
            &*seg.mode,
            self.vehicle,
        ))
    }

    /// What both command paths do with a mode's answer: a compensating
    /// loop subtracts the vehicle's configuration moment from the
    /// commanded one (`moment` finds it in the answer); an error is kept
    /// for the report after the step (a non-finite state: the integrator
    /// sees NaN loads and stops).
    #[inline(always)]
    fn settle<T>(
        &mut self,
        y: &State<B, N>,
        answer: Result<T, ControlError>,
        moment: impl FnOnce(&mut T) -> &mut V3<B>,
    ) -> Option<T> {
        match answer {
            Ok(mut out) => {
                if self.compensate
                    && let Some(c) = self.caps.configuration_moment
                {
                    let m = moment(&mut out);
                    *m = *m - c.moment(&y.body);
                }
                Some(out)
            }
            Err(e) => {
                self.complain(y, e);
                None
            }
        }
    }

    /// Keeps `e`, the first rejection since the last was taken, and
    /// whether the state the mode was given was finite.
    fn complain(&mut self, y: &State<B, N>, e: ControlError) {
        if self.error.is_none() {
            self.error = Some(e);
            self.error_on_finite_state = y.is_finite();
        }
    }

    /// The mode's rejection to report with a failed step, taken: `None`
    /// when the mode was given a non-finite state. The explicit steppers
    /// evaluate every stage of a step before they test its loads, so the
    /// stages after one with a non-finite load (from the vehicle, say)
    /// see a non-finite state, which the mode rejects: not the cause,
    /// which the step's error names. (A state that overflowed inside a
    /// step is the step's error too; a non-finite state set between two
    /// calls is refused before the first step.)
    pub fn complaint(&mut self) -> Option<ControlError> {
        let c = self.error.take()?;
        self.error_on_finite_state.then_some(c)
    }

    /// The error of the step from `t` of length `h` that failed with `e`,
    /// with the mode's rejection that caused it, if one did.
    pub fn step_error(&mut self, t: f64, h: f64, e: integrators::StepError) -> super::SimError {
        let control = self.complaint();
        super::SimError::step(t, h, e, control)
    }

    /// The wrench the active mode commands at `(t, y)`, its integral rates
    /// written into `rates` and any rotor speeds into `speeds`: the load's
    /// path, through [`controllers::Mode::load_command`], so that the load
    /// does not pay for the desired attitude and `Ψ` that only samples and
    /// switch conditions read.
    #[inline(always)]
    fn wrench_into(
        &mut self,
        t: S<B>,
        y: &State<B, N>,
        rates: &mut [S<B>; N],
        speeds: &mut Option<RotorSpeeds<B>>,
    ) -> Option<Wrench<B>> {
        let seg = self.plan.get(self.active)?;
        let at = self.layout;
        let answer = seg
            .mode
            .load_command(
                controllers::load_token(),
                t,
                y.body.as_group(),
                at.integrals(&y.extra),
                at.integrals_mut(rates),
                speeds,
            )
            .map(|(thrust, moment)| Wrench { thrust, moment });
        let answer = check_speeds(answer, speeds.as_ref(), &*seg.mode, self.vehicle);
        self.settle(y, answer, |w| &mut w.moment)
    }

    /// The kept [`Answer`]'s wrench if it is the one at `(t, y)`, its
    /// rates then copied into `rates`. A load that finds no answer kept
    /// (every load of a run without figures, three of four on a recorded
    /// RK4 step) pays one test of a flag: taking the answer out of the
    /// `Option` at every load copied it whole (+5.6 % instructions on the
    /// paper-flip unrecorded).
    #[inline(always)]
    fn reuse(&mut self, t: S<B>, y: &State<B, N>, rates: &mut [S<B>; N]) -> Option<Wrench<B>> {
        // By reference: the test of the flag, not a copy of the answer.
        self.answer.as_ref()?;
        self.take_answer(t, y, rates)
    }

    /// [`ClosedLoop::reuse`] once an answer is kept: it is used or
    /// dropped, never kept for a second load.
    #[cold]
    #[inline(never)]
    fn take_answer(
        &mut self,
        t: S<B>,
        y: &State<B, N>,
        rates: &mut [S<B>; N],
    ) -> Option<Wrench<B>> {
        let a = self.answer.take()?;
        a.fits(self.active, t, y).then(|| {
            *rates = a.rates;
            a.wrench
        })
    }

    /// The vehicle's internal states in `y`.
    pub fn vehicle_states<'y>(&self, y: &'y State<B, N>) -> &'y [S<B>] {
        self.layout.vehicle_states(&y.extra)
    }

    /// Whether an estimator stands between the sensors and the mode: the
    /// mode then reads its estimate at each control instant, and the
    /// switch conditions read it there too.
    pub fn estimating(&self) -> bool {
        self.sensing.as_deref().is_some_and(|s| s.estimating())
    }

    /// The estimator's estimate for the control instant `t`, from every
    /// measurement arrived by then (nothing without an estimator).
    pub fn refresh_estimate(&mut self, t: f64) {
        if let Some(s) = self.sensing.as_deref_mut() {
            s.refresh(t);
        }
    }

    /// The command a control instant holds: the active mode's at the
    /// estimate (at the true state without an estimator), with the
    /// plan's true integral register.
    pub fn control_command(&mut self, t: f64, y: &State<B, N>) -> Option<Command<B, N>> {
        match self.sensing.as_deref() {
            Some(s) if s.estimating() => {
                let ye = s.estimated(y);
                self.command(S::<B>::lit(t), &ye)
            }
            _ => self.command(S::<B>::lit(t), y),
        }
    }

    /// An outer instant of a multi-rate loop, or a mode's first instant in
    /// one: the active mode updates its outer loop at the estimate (the
    /// true state without an estimator). False when the mode rejected its
    /// input (kept for the report: the caller holds no command); true
    /// outside a multi-rate loop, where nothing is done.
    pub fn update_outer(&mut self, t: f64, y: &State<B, N>) -> bool {
        if !self.cascade {
            return true;
        }
        let ye = match self.sensing.as_deref() {
            Some(s) => s.estimated(y),
            None => *y,
        };
        let Some(seg) = self.plan.get_mut(self.active) else {
            return true;
        };
        let integrals = self.layout.integrals(&ye.extra);
        match seg.mode.update_outer(
            controllers::load_token(),
            S::<B>::lit(t),
            ye.body.as_group(),
            integrals,
        ) {
            Ok(()) => {
                // The mode's answers change here.
                self.answer = None;
                true
            }
            Err(e) => {
                self.complain(&ye, e);
                false
            }
        }
    }

    /// Whether the active segment's condition holds at the estimate of the
    /// control instant `t` (what a flight computer's scheduler knows).
    pub fn condition_holds_estimated(&mut self, t: f64, y: &State<B, N>) -> bool {
        let ye = match self.sensing.as_deref() {
            Some(s) => s.estimated(y),
            None => *y,
        };
        self.condition_holds(t, &ye)
    }

    /// Whether the active segment ends on a condition checked after each
    /// step (`Ψ` or a user predicate).
    pub fn has_condition(&self) -> bool {
        self.plan
            .get(self.active)
            .is_some_and(|s| matches!(s.until, Until::PsiBelow(_) | Until::Condition(_)))
            && self.active + 1 < self.plan.len()
    }

    /// Whether the active segment's condition holds at `(t, y)` (a fresh
    /// command, in sampled control too).
    pub fn condition_holds(&mut self, t: f64, y: &State<B, N>) -> bool {
        let Some(c) = self.command(S::<B>::lit(t), y) else {
            return false;
        };
        match &mut self.plan[self.active].until {
            Until::PsiBelow(th) => c.out.psi.to_f64_lossless() < *th,
            Until::Condition(f) => f(t, &y.body, &c.out),
            Until::Never | Until::Time(_) => false,
        }
    }

    /// The active segment's switch condition as a residual that is
    /// negative where it holds, `Ψ − threshold` for `PsiBelow`: what the
    /// derivative of a located switch time is taken from. `None` for a
    /// user predicate (a boolean has no derivative) or without a command.
    pub fn condition_residual(&mut self, t: S<B>, y: &State<B, N>) -> Option<S<B>> {
        let Until::PsiBelow(th) = self.plan[self.active].until else {
            return None;
        };
        let c = self.command(t, y)?;
        Some(c.out.psi - S::<B>::lit(th))
    }

    /// Whether the run ends at `(t, y)`: a limit of `guard` passed (noted
    /// in `diverged`, checked first) or the stop condition holds (false
    /// without a command to show them).
    pub fn stop_holds(
        &mut self,
        stop: &mut Option<super::Condition<'_, B>>,
        guard: &super::DivergenceGuard,
        diverged: &mut Option<super::Divergence>,
        t: f64,
        y: &State<B, N>,
    ) -> bool {
        let out = match self.command(S::<B>::lit(t), y) {
            Some(c) => c.out,
            None => return false,
        };
        if guard.checks_state() {
            let norm = |v: lie::V3<B>| {
                let a = B::vec3_to_array(v).map(|c| c.to_f64_lossless());
                (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
            };
            let mut ex = 0.0;
            if guard.position_error.is_some() {
                let x = B::vec3_to_array(y.body.x).map(|c| c.to_f64_lossless());
                let d = self.plan[self.active]
                    .mode
                    .desired_position(t)
                    .unwrap_or([0.0; 3]);
                let e = [x[0] - d[0], x[1] - d[1], x[2] - d[2]];
                ex = (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
            }
            let moment = if guard.moment.is_some() {
                norm(out.moment)
            } else {
                0.0
            };
            if let Some(d) = guard.check(norm(y.body.omega), ex, moment) {
                diverged.get_or_insert(d);
                return true;
            }
        }
        match stop.as_mut() {
            Some(f) => f(t, &y.body, &out),
            None => false,
        }
    }

    /// Makes the next segment active at `t`; its mode decides what of the
    /// integral register carries over.
    pub fn switch(&mut self, t: f64, y: &mut State<B, N>) -> Option<SwitchRecord> {
        if self.active + 1 >= self.plan.len() {
            return None;
        }
        let from = self.active;
        self.active += 1;
        self.plan[self.active].mode.enter(
            S::<B>::lit(t),
            y.body.as_group(),
            self.layout.integrals_mut(&mut y.extra),
        );
        Some(SwitchRecord {
            t,
            from,
            to: self.active,
        })
    }
}

impl<B: Backend, const N: usize> System<B, N> for ClosedLoop<'_, '_, B, N> {
    fn mass(&self) -> S<B> {
        self.vehicle.mass()
    }
    fn inertia(&self) -> lie::M3<B> {
        self.vehicle.inertia()
    }
    fn inertia_inv(&self) -> lie::M3<B> {
        self.inertia_inv
    }
    fn translates(&self) -> bool {
        self.caps.translates
    }
    /// The plan's integrals and the vehicle's states.
    fn extra_in_use(&self) -> usize {
        self.layout.in_use()
    }
    fn load_depends_on_rates(&self) -> bool {
        (!self.plan.is_empty() && !self.sampled)
            || self.layout.vehicle_states > 0
            || self.caps.rate_dependent_loads
    }
    // Inlined into the stepper: out of line, the load came back through
    // memory and the step waited on it.
    #[inline(always)]
    fn load(&mut self, t: S<B>, y: &State<B, N>) -> Load<B, N> {
        self.evaluations += 1;
        let mut rates = [S::<B>::lit(0.0); N];
        let wrench = |out: &ModeOutput<B>| Wrench {
            thrust: out.thrust,
            moment: out.moment,
        };
        let mut fresh = None;
        let (w, speeds) = if self.plan.is_empty() {
            (Wrench::zero(), None)
        } else if self.sampled {
            match &self.held {
                Some(c) => {
                    rates = c.rates;
                    (wrench(&c.out), c.out.rotor_speeds.as_ref())
                }
                None => (Wrench::zero(), None),
            }
        } else if let Some(w) = self.reuse(t, y, &mut rates) {
            (w, None)
        } else {
            match self.wrench_into(t, y, &mut rates, &mut fresh) {
                Some(w) => (w, fresh.as_ref()),
                None => return nan_load(),
            }
        };
        let at = self.layout;
        let states = at.vehicle_states(&y.extra);
        // The wind's field alone: the held command is borrowed.
        let air = match self.wind.is_some() {
            true => {
                let tw = self.wind_time(t.to_f64_lossless());
                let a = self.wind.as_deref_mut().map_or([0.0; 3], |w| {
                    w.velocity(tw, lie::ops::vec3_f64::<B>(y.body.x))
                });
                B::vec3(S::<B>::lit(a[0]), S::<B>::lit(a[1]), S::<B>::lit(a[2]))
            }
            false => lie::ops::zero::<B>(),
        };
        let ask = match speeds {
            Some(w) => Ask::RotorSpeeds(w.as_slice()),
            None => Ask::Wrench(w),
        };
        let input = LoadInput::new(ask, states, air);
        let l = match self
            .vehicle
            .loads(t, &y.body, input, at.vehicle_states_mut(&mut rates))
        {
            Some(l) => l,
            None => {
                let mode = self.plan[self.active].mode.name();
                self.error
                    .get_or_insert(ControlError::RotorSpeedsUnsupported { mode });
                return nan_load();
            }
        };
        Load {
            force: l.force,
            moment: l.moment,
            extra_rate: rates,
        }
    }
}
