//! The checked builder of a [`Simulation`].

use super::*;
use closed_loop::Layout;

use controllers::Mode;
use dynamics::{RigidBodyState, Vehicle, Wind};
use integrators::{Method, State, Stepper};
use lie::{Backend, Real, S};

/// Builds a [`Simulation`]; every setting is checked in
/// [`SimulationBuilder::build`], which names the field and the value of a
/// bad one.
///
/// `M` is the integration method ([`Stepper`] by default, chosen by
/// name at run time): any [`Method`], which the build sizes for the
/// extra states the plan and the vehicle need.
pub struct SimulationBuilder<'a, B: Backend, M = Stepper<B>> {
    pub(super) vehicle: Box<dyn Vehicle<B> + 'a>,
    pub(super) wind: Option<Box<dyn Wind + 'a>>,
    pub(super) plan: Vec<Segment<'a, B>>,
    pub(super) stepper: M,
    pub(super) initial: RigidBodyState<B>,
    pub(super) integrals: Vec<S<B>>,
    pub(super) vehicle_states: Option<Vec<S<B>>>,
    pub(super) dt: f64,
    pub(super) duration: f64,
    pub(super) control: Control,
    pub(super) record: f64,
    pub(super) locate_events: bool,
    pub(super) compensate: bool,
    pub(super) stop: Option<Condition<'a, B>>,
    pub(super) guard: DivergenceGuard,
    pub(super) warnings: Vec<String>,
    pub(super) sensing: sensing::Settings<'a, B>,
}

impl<'a, B: Backend, M: Method<B>> SimulationBuilder<'a, B, M> {
    /// Adds warnings to [`RunOutput::warnings`] (what the caller adjusted
    /// while building, say).
    pub fn warnings(mut self, w: impl IntoIterator<Item = String>) -> Self {
        self.warnings.extend(w);
        self
    }
    /// Appends a segment to the plan (none: the vehicle flies with zero
    /// command).
    pub fn segment(mut self, segment: Segment<'a, B>) -> Self {
        self.plan.push(segment);
        self
    }
    /// Appends `mode`, left per `until`.
    pub fn mode(self, mode: impl Mode<B> + 'a, until: Until<'a, B>) -> Self {
        self.segment(Segment {
            mode: Box::new(mode),
            until,
        })
    }
    /// The initial body state.
    pub fn initial(mut self, state: RigidBodyState<B>) -> Self {
        self.initial = state;
        self
    }
    /// Initial values of the integral register (zero by default).
    pub fn integrals(mut self, values: &[S<B>]) -> Self {
        self.integrals = values.to_vec();
        self
    }
    /// Initial values of the vehicle's internal states (rotor speeds, say;
    /// [`dynamics::Actuators::state_count`] of them, in the vehicle's order). Without
    /// them, the run starts with the states where the first command puts
    /// them (rotors spinning at the speeds of the first command).
    pub fn vehicle_states(mut self, values: &[S<B>]) -> Self {
        self.vehicle_states = Some(values.to_vec());
        self
    }
    /// Any integration method: a [`Stepper`] chosen by name, a stepper
    /// type ([`integrators::Rk4`], [`integrators::Dopri`], …), or one's own
    /// [`Method`].
    pub fn integrator<J: Method<B>>(self, stepper: J) -> SimulationBuilder<'a, B, J> {
        SimulationBuilder {
            vehicle: self.vehicle,
            wind: self.wind,
            plan: self.plan,
            stepper,
            initial: self.initial,
            integrals: self.integrals,
            vehicle_states: self.vehicle_states,
            dt: self.dt,
            duration: self.duration,
            control: self.control,
            record: self.record,
            locate_events: self.locate_events,
            compensate: self.compensate,
            stop: self.stop,
            guard: self.guard,
            warnings: self.warnings,
            sensing: self.sensing,
        }
    }
    /// The step (for Dormand–Prince: the longest call; it subdivides).
    pub fn dt(mut self, dt: f64) -> Self {
        self.dt = dt;
        self
    }
    /// Simulated time, s.
    pub fn duration(mut self, t: f64) -> Self {
        self.duration = t;
        self
    }
    /// Continuous or sampled control.
    pub fn control(mut self, control: Control) -> Self {
        self.control = control;
        self
    }
    /// A sample every `interval` seconds (0: only t = 0 and the end).
    pub fn record_every(mut self, interval: f64) -> Self {
        self.record = interval;
        self
    }
    /// Locate breakpoint crossings (on by default; off integrates across
    /// them, a first-order error at each).
    pub fn locate_events(mut self, on: bool) -> Self {
        self.locate_events = on;
        self
    }
    /// End the run at the first instant `condition` holds (checked after
    /// every step, located by bisection like a switch; the last sample is
    /// taken there and [`RunOutput::stopped_at`] says when). A Monte Carlo
    /// driver stops a converged sample this way; a hold time is the
    /// predicate's own state.
    pub fn stop_when(mut self, condition: Condition<'a, B>) -> Self {
        self.stop = Some(condition);
        self
    }
    /// The wind the vehicle flies in (none by default): evaluated at the
    /// vehicle's position at every load and handed to
    /// [`Vehicle::loads`]; the steps land on its jumps.
    pub fn wind(mut self, wind: Box<dyn Wind + 'a>) -> Self {
        self.wind = Some(wind);
        self
    }
    /// End the run with [`Termination::Diverged`] when it passes one of
    /// `guard`'s limits (none by default).
    pub fn guard(mut self, guard: DivergenceGuard) -> Self {
        self.guard = guard;
        self
    }
    /// The sensors the vehicle carries, their noise keyed on `seed` (none by
    /// default): each samples at its own instants from the steps'
    /// continuous extension, so sensing moves no step; what they measure
    /// is in [`RunOutput::measurements`] and each [`Sample::sensors`].
    pub fn sensors(mut self, suite: sensors::SensorSuite, seed: u64) -> Self {
        self.sensing.suite = suite;
        self.sensing.seed = seed;
        self
    }
    /// The estimator the flight modes read instead of the true state (none
    /// by default: they read the truth). It needs sampled control
    /// ([`Control::Sampled`]): at each control instant it takes every
    /// measurement that has arrived and gives the state the mode commands
    /// from; the plan's switch conditions read that estimate too, at the
    /// control instants, while the stop condition and the divergence guard
    /// read the truth.
    pub fn estimator(mut self, estimator: Box<dyn sensors::Estimator<B> + 'a>) -> Self {
        self.sensing.estimator = Some(estimator);
        self
    }
    /// Subtract the vehicle's configuration moment (gravity about a pivot)
    /// from every command, as the paper does on its test stand.
    pub fn compensate_configuration_moment(mut self, on: bool) -> Self {
        self.compensate = on;
        self
    }

    /// The settings' values: finite and in range, each error naming its
    /// field and value.
    fn check_settings(&self) -> Result<(), SimError> {
        if !(self.dt.is_finite() && self.dt > 0.0) {
            return Err(bad("dt", format!("{} must be finite and > 0", self.dt)));
        }
        if !(self.duration.is_finite() && self.duration > 0.0) {
            return Err(bad(
                "duration",
                format!("{} must be finite and > 0", self.duration),
            ));
        }
        if !(self.record.is_finite() && self.record >= 0.0) {
            return Err(bad(
                "record_every",
                format!("{} must be finite and ≥ 0", self.record),
            ));
        }
        if let Control::Sampled { rate } = self.control
            && !(rate.is_finite() && rate > 0.0)
        {
            return Err(bad(
                "control",
                format!("sampled rate {rate} Hz must be finite and > 0"),
            ));
        }
        if let Control::MultiRate(r) = self.control {
            r.check().map_err(|(_, msg)| bad("control", msg))?;
        }
        if let Some(f) = self.initial.non_finite_field() {
            return Err(bad("initial", format!("`{f}` is not finite")));
        }
        if self.vehicle.capabilities().contact.is_some() {
            let name = integrators::Integrator::<B, 0>::name(&self.stepper.for_slots::<0>());
            if matches!(name, "euler" | "lgvi") {
                return Err(bad(
                    "integrator",
                    format!(
                        "`{name}` cannot step the ground contact (explicit Euler is unstable \
                         on it, the LGVI's iteration on rate-dependent loads does not \
                         converge): use rk4, rk4-projected, rkmk4 or dopri"
                    ),
                ));
            }
            let rate = self
                .vehicle
                .capabilities()
                .contact
                .map_or(0.0, |c| c.stiffest_rate());
            // RK4's stability interval on the negative real axis ends at
            // 2.785; 2.5 leaves room for the modes' coupling.
            if name != "dopri" && rate * self.dt > 2.5 {
                return Err(bad(
                    "dt",
                    format!(
                        "{} s is too long for the ground contact: its stiffest mode runs at \
                         {rate:.0}/s and `{name}` is stable only for dt below {:.2e} s \
                         (or use dopri, which adapts)",
                        self.dt,
                        2.5 / rate
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The plan: segment end times increasing, Ψ thresholds in (0, 2), no
    /// switch condition on the last segment.
    fn check_plan(&self) -> Result<(), SimError> {
        let mut last = 0.0;
        for (k, seg) in self.plan.iter().enumerate() {
            let is_last = k + 1 == self.plan.len();
            match seg.until {
                Until::Time(u) if !(u.is_finite() && u > last) => {
                    return Err(bad(
                        "plan",
                        format!("segment {k} ends at {u}: must be finite and after {last}"),
                    ));
                }
                Until::Time(u) => last = u,
                Until::PsiBelow(p) if !(p.is_finite() && p > 0.0 && p < 2.0) => {
                    return Err(bad(
                        "plan",
                        format!("segment {k}: Ψ threshold {p} must be in (0, 2)"),
                    ));
                }
                _ => {}
            }
            if is_last && !matches!(seg.until, Until::Never | Until::Time(_)) {
                return Err(bad(
                    "plan",
                    format!(
                        "segment {k} is the last: its switch condition has nothing to switch to"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// The initial state: the body (still when the vehicle does not
    /// translate), the integral register and the vehicle's states given,
    /// each checked for its length and finiteness.
    fn initial_state<const N: usize>(&self, at: Layout) -> Result<State<B, N>, SimError> {
        let finite = |field: &'static str, values: &[S<B>]| {
            if values.iter().all(|v| v.is_finite()) {
                return Ok(());
            }
            let shown: Vec<f64> = values.iter().map(|v| v.to_f64_lossless()).collect();
            Err(bad(field, format!("{shown:?} must be finite")))
        };
        if self.integrals.len() > at.integrals {
            return Err(bad(
                "integrals",
                format!(
                    "{} initial values given, the plan's modes use {}",
                    self.integrals.len(),
                    at.integrals
                ),
            ));
        }
        finite("integrals", &self.integrals)?;
        let mut initial = State::<B, N>::new(self.initial);
        if !self.vehicle.capabilities().translates {
            initial.body.x = lie::ops::zero::<B>();
            initial.body.v = lie::ops::zero::<B>();
        }
        at.integrals_mut(&mut initial.extra)[..self.integrals.len()]
            .copy_from_slice(&self.integrals);
        if let Some(v) = &self.vehicle_states {
            if v.len() != at.vehicle_states {
                return Err(bad(
                    "vehicle_states",
                    format!(
                        "{} initial values given, the vehicle `{}` has {} internal states",
                        v.len(),
                        self.vehicle.name(),
                        at.vehicle_states
                    ),
                ));
            }
            finite("vehicle_states", v)?;
            at.vehicle_states_mut(&mut initial.extra).copy_from_slice(v);
        }
        Ok(initial)
    }

    /// Checks every setting, counts the extra states the plan and the
    /// vehicle need and builds the loop for the smallest of
    /// [`CAPACITIES`](super::CAPACITIES) that holds them.
    pub fn build(self) -> Result<Simulation<'a, B>, SimError> {
        self.check_settings()?;
        self.check_plan()?;
        let at = self.layout();
        let needed = at.in_use();
        let engine: Box<dyn Run<B> + 'a> = match CAPACITIES {
            [small, _] if needed <= small => Box::new(self.engine::<{ CAPACITIES[0] }>(at)?),
            [_, large] if needed <= large => Box::new(self.engine::<{ CAPACITIES[1] }>(at)?),
            [_, large] => {
                return Err(SimError::Layout {
                    integrals: at.integrals,
                    vehicle_states: at.vehicle_states,
                    capacity: large,
                });
            }
        };
        Ok(Simulation { engine })
    }

    /// The plan's integral states, then the vehicle's.
    fn layout(&self) -> Layout {
        let integrals = self
            .plan
            .iter()
            .map(|s| s.mode.integrals().count)
            .max()
            .unwrap_or(0);
        Layout {
            integrals,
            vehicle_states: self
                .vehicle
                .capabilities()
                .actuators
                .map_or(0, |a| a.state_count()),
        }
    }

    /// The loop for `N` extra states.
    fn engine<const N: usize>(self, at: Layout) -> Result<Engine<'a, B, N, M::For<N>>, SimError> {
        let initial = self.initial_state::<N>(at)?;
        if lie::ops::inverse::<B>(self.vehicle.inertia()).is_none() {
            return Err(bad("vehicle", "its inertia is singular".into()));
        }
        if let Some(c) = self.guard.substeps
            && c == 0
        {
            return Err(bad("guard", "a substep cap of 0 allows no step".into()));
        }
        for (name, v) in [
            ("omega", self.guard.omega),
            ("position_error", self.guard.position_error),
            ("moment", self.guard.moment),
        ] {
            if let Some(v) = v
                && (v.is_nan() || v <= 0.0)
            {
                return Err(bad("guard", format!("`{name}` limit {v} must be > 0")));
            }
        }
        let mut stepper = self.stepper.for_slots::<N>();
        if let Some(c) = self.guard.substeps {
            stepper.limit_substeps(c);
        }
        let sensing = self.sensing.build(self.control, self.duration)?;
        let mut plan = self.plan;
        let mut wind = self.wind;
        let mut running = stepping::prepare(
            self.vehicle.as_ref(),
            wind.as_deref_mut(),
            &mut plan,
            &stepping::Settings {
                control: self.control,
                compensate: self.compensate,
                layout: at,
                dt: self.dt,
                t_end: self.duration,
                record: self.record,
                locate_events: self.locate_events,
                vehicle_states_given: self.vehicle_states.is_some(),
            },
        )?;
        running.out.warnings.extend(self.warnings);
        Ok(Engine {
            vehicle: self.vehicle,
            wind,
            sensing,
            plan,
            stepper,
            y: initial,
            layout: at,
            duration: self.duration,
            stop: self.stop,
            guard: self.guard,
            running: Box::new(running),
            perturbed: false,
            failed: false,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use controllers::{
        AttitudeGains, AttitudeMode, AttitudeThrust, HoldAttitude, HoldPosition, RigidBodyParams,
    };
    use dynamics::{Multirotor, MultirotorParams, Quadrotor, paper};
    use integrators::{IntegratorKind, Stepper, StepperConfig};
    use lie::{GlamF64, Rotation, So3Mat};

    type B = GlamF64;

    /// Level attitude held from a 40° tilt, with the integral term on (3
    /// integral slots), by dopri at tolerance 1e-6.
    fn tilted(
        vehicle: Box<dyn Vehicle<B>>,
        mass: f64,
        inertia: [f64; 3],
    ) -> SimulationBuilder<'static, B, Stepper<B>> {
        let params = RigidBodyParams::<B>::diagonal(mass, inertia, paper::GRAVITY);
        let mode = AttitudeMode::<B, _, HoldPosition<B>>::new(
            params,
            AttitudeGains::uniform(
                0.65 * inertia[0] / 0.43e-2,
                0.11 * inertia[0] / 0.43e-2,
                0.05,
                0.8,
            ),
            HoldAttitude::new(So3Mat::<B>::identity()),
            AttitudeThrust::Constant(mass * paper::GRAVITY),
        );
        let mut start = RigidBodyState::<B>::at_rest();
        start.r = So3Mat::<B>::exp(B::vec3(0.7, -0.3, 0.2)).matrix();
        let dopri = Stepper::<B>::new(IntegratorKind::Dopri, StepperConfig { tol: 1e-6 });
        Simulation::<B>::builder(vehicle)
            .mode(mode, Until::Never)
            .initial(start)
            .duration(2.0)
            .dt(0.02)
            .integrator(dopri)
    }

    /// The final state and step count of `b` in an array of `N` extra
    /// states.
    fn at_size<const N: usize>(
        b: SimulationBuilder<'static, B, Stepper<B>>,
    ) -> (RigidBodyState<B>, u64) {
        let at = b.layout();
        let mut e = b.engine::<N>(at).unwrap();
        e.advance_to_with(2.0, RunOptions::default()).unwrap();
        let body = *e.state().body;
        (body, Box::new(e).finish().unwrap().steps)
    }

    /// Dormand–Prince's step sizes come from an error norm over the slots
    /// in use: the same run in an array with idle slots (the paper's
    /// quadrotor: 3 integrals; RotorPy's Hummingbird: 3 integrals and 4
    /// motor speeds) takes the same steps to the same state, bit for bit,
    /// so the size the builder picks never shows in a result. (Averaged
    /// over all `N` slots, the idle zeros diluted the norm: the built-in
    /// figure eight in wind took 22 969 steps at `N = 16` against 23 306
    /// at `N = 10`.)
    #[test]
    fn idle_extra_slots_do_not_change_a_dopri_run() {
        let quad = || {
            tilted(
                Box::new(Quadrotor::<B>::paper()),
                paper::MASS,
                paper::INERTIA,
            )
        };
        let a3 = at_size::<3>(quad());
        assert!(
            a3.1 > 10,
            "an adaptive run of more than a few steps: {}",
            a3.1
        );
        assert_eq!(a3, at_size::<6>(quad()), "quadrotor, N = 3 against 6");
        assert_eq!(a3, at_size::<16>(quad()), "quadrotor, N = 3 against 16");
        let hb = || {
            let v = Multirotor::<B>::new(MultirotorParams::hummingbird()).unwrap();
            tilted(Box::new(v), 0.5, [3.65e-3, 3.68e-3, 7.03e-3])
        };
        let w7 = at_size::<7>(hb());
        assert_eq!(w7, at_size::<16>(hb()), "hummingbird, N = 7 against 16");
    }
}
