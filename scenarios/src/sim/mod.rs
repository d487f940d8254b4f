//! The simulation engine: any vehicle, any flight modes, any integrator,
//! through one loop with exact landing on checkpoints, located events and
//! recording. The bottom layer of the crate: it imports nothing from the
//! scenes, outputs, studies or figures above it.
//!
//! | file | what it holds |
//! |---|---|
//! | `mod.rs` | [`Simulation`], [`Segment`], [`Until`], [`Control`], [`RunOptions`] |
//! | `builder.rs` | [`SimulationBuilder`]: every setting checked, naming the field and the value |
//! | `output_types.rs` | what a run returns: [`Sample`], [`SwitchRecord`], [`RunOutput`], [`Termination`], [`Health`], and the [`DivergenceGuard`] |
//! | `error.rs` | [`SimError`]: why a run could not be built or could not go on (scene and study errors wrap it in the crates above) |
//! | `sink.rs` | [`Sink`], where samples and switches go as they are produced, and its [`OutputError`]; the CSV and MCAP writers above implement it |
//! | `closed_loop.rs` | the vehicle, the plan and the held command as one [`integrators::System`]; the extra-state layout; switching |
//! | `stepping.rs` | the stepping loop: checkpoints (control instants, switch times, end), steps landing on them, samples from the continuous extension, extrema over every step, progress |
//! | `events.rs` | event location: breakpoint crossings (the paper's sat′) and condition switches (`Ψ` below a threshold, a user predicate) |
//! | `record.rs` | one [`Sample`] from the state and the command |
//!
//! # Extra states
//! The integrator advances the body and a fixed-size array of extra
//! scalars: slots `0..m` are the plan's integral register (`m` = the
//! largest [`Mode::integrals`] count of the plan; the paper's modes use
//! `[e_I, e_i]`, so `m = 6`), slots `m..m + n` the vehicle's internal
//! states (`n` = [`dynamics::Actuators::state_count`]). Users meet them by name
//! ([`SimState::integrals`], [`SimState::vehicle_states`],
//! [`SimulationBuilder::integrals`], [`SimulationBuilder::vehicle_states`]),
//! never by offset, and never choose the array's size:
//! [`SimulationBuilder::build`] counts `m + n` and picks the smallest of
//! [`CAPACITIES`] that holds them, so the loop is compiled for a size known
//! at compile time (its stage arithmetic unrolled) without a user naming
//! it. Unused slots stay zero and change nothing: a run in a larger array
//! takes the same steps to the same state, bit for bit (Dormand–Prince's
//! error norm reads the slots in use only). A plan and vehicle that need
//! more than the largest are a [`SimError::Layout`] naming both counts.

mod builder;
pub(crate) mod closed_loop;
mod emit;
mod error;
mod events;
mod grid;
mod instants;
mod open_loop;
mod output_types;
mod readout;
pub(crate) mod sense;
mod sensing;
pub use open_loop::OpenLoop;
pub use readout::{MeasurementRecord, NavSample, Readout};
pub(crate) mod record;
mod sink;
mod stepping;
pub use builder::SimulationBuilder;
pub use error::SimError;
use error::bad;
pub use output_types::{
    BreakpointCrossing, ContactChange, Divergence, DivergenceGuard, Health, PsiRange, RunOutput,
    Sample, SwitchRecord, Termination,
};
pub use sink::{OutputError, Sink, Tee, Watched};

use std::sync::atomic::AtomicBool;

use controllers::{Mode, ModeOutput};
use dynamics::{RigidBodyState, Vehicle, Wind};
use integrators::{Integrator, IntegratorKind, State, Stepper, StepperConfig};
use lie::{Backend, S};

/// The extra states of a [`Simulation`] ([`Simulation::layout`]).
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct StateLayout {
    /// Integral states the plan's modes use (the largest
    /// [`Mode::integrals`] count).
    pub integrals: usize,
    /// Internal states the vehicle declares.
    pub vehicle_states: usize,
}

/// Options of one run.
pub struct RunOptions<'a> {
    /// Keep the samples in [`RunOutput::samples`] (plots, metrics over
    /// time). Off, and without a sink, only the final state is kept and no
    /// sample is taken between the ends.
    pub record: bool,
    /// Called with the fraction done, at most ~200 times a run.
    pub progress: Option<&'a mut dyn FnMut(f64)>,
    /// Receives every sample and switch as the run produces them (CSV and
    /// MCAP writers stream this way, so memory stays bounded whatever the
    /// duration). A sink error ends the run with [`SimError::Output`].
    pub sink: Option<&'a mut dyn Sink>,
    /// Checked after every step: once set (by a signal handler, a UI), the
    /// run stops where it is, takes a last sample there, and returns
    /// normally with [`RunOutput::interrupted_at`] set.
    pub cancel: Option<&'a AtomicBool>,
    /// Track [`RunOutput::max_thrust`], [`RunOutput::max_rotor`],
    /// [`RunOutput::max_orthogonality_error`] and [`RunOutput::psi_range`]
    /// over every step end and located event (on by default). It asks the
    /// mode for its whole command at every step's end, and the next step's
    /// first load reuses that answer's wrench, so what it adds is the
    /// difference between a command and a wrench and the figures
    /// themselves, not a controller evaluation of their own; off, those
    /// fields cover only the start, the located events and the
    /// end.
    pub extrema: bool,
}

impl Default for RunOptions<'_> {
    fn default() -> Self {
        Self {
            record: true,
            progress: None,
            sink: None,
            cancel: None,
            extrema: true,
        }
    }
}

/// A user's switching condition: `(t, body state, the active mode's
/// command at that state) ↦ leave now?`.
pub type Condition<'a, B> = Box<dyn FnMut(f64, &RigidBodyState<B>, &ModeOutput<B>) -> bool + 'a>;

/// When a segment ends: `controllers::Until` with times in `f64` seconds
/// and a boxed [`Condition`]. The simulation lands a step on
/// `Until::Time(t)`, locates `Until::PsiBelow(ψ)` (`Ψ` against the mode's
/// desired attitude) by bisection on redone steps, and checks
/// `Until::Condition(f)` after every step, located by bisection like
/// `PsiBelow` (so it should switch from false to true once within a step).
pub type Until<'a, B> = controllers::Until<f64, Condition<'a, B>>;

/// One segment of a plan: a boxed flight mode and when it ends
/// (`controllers::Segment`, the same type a flight computer's scheduler
/// steps through).
pub type Segment<'a, B> = controllers::Segment<Box<dyn Mode<B> + 'a>, Until<'a, B>>;

/// When the controller runs.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Control {
    /// Inside the vector field: every load evaluation computes the command
    /// (the paper's continuous-time closed loop).
    Continuous,
    /// At `rate` Hz, the command held in between (zero-order hold, as a
    /// flight computer does); the integral rates are held too.
    Sampled {
        /// Control rate, Hz.
        rate: f64,
    },
    /// A multi-rate loop, as a flight computer schedules its tasks: the
    /// attitude law at [`LoopRates::attitude`] Hz (the held command, as
    /// [`Control::Sampled`]), the outer loop of a cascaded mode (the
    /// position law's `f, R_c, Ω_c, Ω̇_c`, see [`controllers::PositionMode`])
    /// at [`LoopRates::position`] Hz and held in between, and the
    /// estimator's estimate taken at [`LoopRates::estimator`] Hz and read at
    /// the next control instant. Steps land on the attitude and position
    /// instants; the rates need not divide one another, and an outer
    /// output reaches the motors at the next attitude instant at or after
    /// its own.
    MultiRate(LoopRates),
}

impl Control {
    /// The attitude (command) rate of sampled or multi-rate control.
    pub fn command_rate(&self) -> Option<f64> {
        match *self {
            Control::Continuous => None,
            Control::Sampled { rate } => Some(rate),
            Control::MultiRate(r) => Some(r.attitude),
        }
    }
}

/// The rates of a multi-rate loop, Hz.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct LoopRates {
    /// The estimator: a control instant reads the estimate of the last of
    /// its instants (each an instant `k / estimator`), from the
    /// measurements arrived by then.
    pub estimator: f64,
    /// The attitude law: the command is held between its instants.
    pub attitude: f64,
    /// The outer (position) loop: at most `attitude`.
    pub position: f64,
}

impl LoopRates {
    /// The Crazyflie's stabilizer: estimator at 1 kHz, attitude at
    /// 500 Hz, position at 100 Hz (the firmware's `RATE_MAIN_LOOP`,
    /// `ATTITUDE_RATE` and `POSITION_RATE`).
    pub const fn crazyflie() -> Self {
        Self {
            estimator: 1000.0,
            attitude: 500.0,
            position: 100.0,
        }
    }

    /// The first rate that is not finite and positive, or a position rate
    /// above the attitude rate: the field and why.
    pub fn check(&self) -> Result<(), (&'static str, String)> {
        for (field, r) in [
            ("estimator", self.estimator),
            ("attitude", self.attitude),
            ("position", self.position),
        ] {
            if !(r.is_finite() && r > 0.0) {
                return Err((field, format!("{field} rate {r} Hz must be finite and > 0")));
            }
        }
        if self.position > self.attitude {
            return Err((
                "position",
                format!(
                    "position rate {} Hz is above the attitude rate {} Hz: the outer loop runs at most as often as the inner one",
                    self.position, self.attitude
                ),
            ));
        }
        Ok(())
    }
}

/// A simulation ready to run: build it with [`Simulation::builder`].
///
/// The vehicle, the plan, the integrator and the state, stepped by one
/// loop compiled for the backend `B`, the integrator and the size of the
/// extra-state array the builder picked; this handle reaches it through
/// one virtual call per [`Simulation::advance_to`], never per step.
///
/// ```
/// use controllers::{AttitudeGains, AttitudeMode, AttitudeThrust, HoldAttitude, HoldPosition, RigidBodyParams};
/// use dynamics::{Quadrotor, RigidBodyState, Vehicle, paper};
/// use lie::{NalgebraF64, Rotation, So3Mat, Backend};
/// use scenarios::{Segment, Simulation, Until};
/// type B = NalgebraF64;
///
/// // The paper's quadrotor on a pivot would be `AttitudeStand`; here it flies.
/// let quad = Quadrotor::<B>::paper();
/// let params = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
/// // Hold R_d = I with the paper's k_R, k_Ω (no integral term: no
/// // disturbance here) and hover thrust.
/// let gains = AttitudeGains::uniform(0.65, 0.11, 0.0, 0.8);
/// let hold = HoldAttitude::new(So3Mat::<B>::identity());
/// let mode = AttitudeMode::<B, _, HoldPosition<B>>::new(
///     params, gains, hold, AttitudeThrust::Constant(params.mass * params.gravity));
/// // Start tilted 30° about b1.
/// let mut start = RigidBodyState::<B>::at_rest();
/// start.r = So3Mat::<B>::exp(B::vec3(0.5236, 0.0, 0.0)).matrix();
/// let out = Simulation::<B>::builder(Box::new(quad))
///     .segment(Segment { mode: Box::new(mode), until: Until::Never })
///     .initial(start)
///     .duration(5.0)
///     .dt(1e-3)
///     .record_every(0.1)
///     .build()?
///     .run(Default::default())?;
/// // Linear decay at the slower root of J₁s² + k_Ω s + k_R, s ≈ −9.3 /s.
/// assert!(out.last.psi < 1e-12, "Ψ(5 s) = {}", out.last.psi);
/// assert_eq!(out.samples.len(), 51);
/// # Ok::<(), scenarios::SimError>(())
/// ```
pub struct Simulation<'a, B: Backend> {
    engine: Box<dyn Run<B> + 'a>,
}

/// The extra-state array's sizes a [`Simulation`] is compiled for, the
/// smallest that holds the plan's integrals and the vehicle's states
/// picked at [`SimulationBuilder::build`]: 6 is the paper's two integral
/// vectors, 16 a multirotor's rotor speeds beside them.
pub const CAPACITIES: [usize; 2] = [6, 16];

/// The simulation for `N` extra states and the integrator `I`: what
/// [`Simulation`] holds behind [`Run`].
pub(crate) struct Engine<'a, B: Backend, const N: usize, I> {
    vehicle: Box<dyn Vehicle<B> + 'a>,
    /// The air's velocity, evaluated at the vehicle at every load.
    wind: Option<Box<dyn Wind + 'a>>,
    /// The sensors and the estimator, when the run has them.
    sensing: Option<Box<sensing::Sensing<'a, B>>>,
    plan: Vec<Segment<'a, B>>,
    stepper: I,
    /// The state now: the initial state until the run starts.
    y: State<B, N>,
    /// Where the integrals and the vehicle's states are in `y`.
    layout: closed_loop::Layout,
    duration: f64,
    stop: Option<Condition<'a, B>>,
    guard: DivergenceGuard,
    /// The loop's state between calls.
    running: Box<stepping::Running<B, N>>,
    /// The state was changed through [`Simulation::state_mut`] since the
    /// last step: the stepper forgets its cached loads before the next.
    perturbed: bool,
    /// A call failed: the run cannot go on.
    failed: bool,
}

impl<'a, B: Backend> Simulation<'a, B> {
    /// Starts a simulation of `vehicle` (defaults: no plan, at rest, RK4
    /// with `dt = 1e-3`, 1 s, continuous control, a sample every 0.01 s,
    /// events located).
    pub fn builder(vehicle: Box<dyn Vehicle<B> + 'a>) -> SimulationBuilder<'a, B> {
        SimulationBuilder {
            vehicle,
            wind: None,
            plan: Vec::new(),
            stepper: Stepper::new(IntegratorKind::Rk4, StepperConfig::default()),
            initial: RigidBodyState::at_rest(),
            integrals: Vec::new(),
            vehicle_states: None,
            dt: 1e-3,
            duration: 1.0,
            control: Control::Continuous,
            record: 0.01,
            locate_events: true,
            compensate: false,
            stop: None,
            guard: DivergenceGuard::default(),
            warnings: Vec::new(),
            sensing: sensing::Settings::default(),
        }
    }
}

/// The state of a [`Simulation`] at [`SimState::t`], in the simulation's
/// scalar: what [`Simulation::state`] shows.
#[derive(Clone, Debug)]
pub struct SimState<'s, B: Backend> {
    /// Time, s.
    pub t: f64,
    /// The rigid body.
    pub body: &'s RigidBodyState<B>,
    /// The plan's integral register (the paper's modes: `[e_I, e_i]`).
    pub integrals: &'s [S<B>],
    /// The vehicle's internal states (rotor speeds, say).
    pub vehicle_states: &'s [S<B>],
    /// The active segment of the plan.
    pub segment: usize,
    /// Its mode's name (`"none"` without a plan).
    pub mode: &'static str,
}

/// The state of a [`Simulation`] to change between two calls of
/// [`Simulation::advance_to`] ([`Simulation::state_mut`]).
#[derive(Debug)]
pub struct SimStateMut<'s, B: Backend> {
    /// Time, s (read only: a run's time moves only by stepping).
    pub t: f64,
    /// The rigid body.
    pub body: &'s mut RigidBodyState<B>,
    /// The plan's integral register.
    pub integrals: &'s mut [S<B>],
    /// The vehicle's internal states.
    pub vehicle_states: &'s mut [S<B>],
}

impl<B: Backend> Simulation<'_, B> {
    /// Runs to the end: [`Simulation::advance_to`] the duration, then
    /// [`Simulation::finish`].
    pub fn run(mut self, opts: RunOptions<'_>) -> Result<RunOutput, SimError> {
        let end = self.duration();
        self.advance_to_with(end, opts)?;
        self.finish()
    }

    /// Advances the run to `t` (at most its duration), recording samples
    /// as [`RunOptions::default`] does; see [`Simulation::advance_to_with`].
    pub fn advance_to(&mut self, t: f64) -> Result<(), SimError> {
        self.advance_to_with(t, RunOptions::default())
    }

    /// Advances the run to `t`: takes every step that ends at or before
    /// `t` (to rounding), with what happens at them (events, switches,
    /// samples, the stop condition, the guard), and stops before the
    /// first step that would end after `t`. Pausing never moves the step
    /// grid, so a run advanced in any number of pieces is the same, bit
    /// for bit, as one advanced in one call; the price is that
    /// [`Simulation::time`] is the last step's end, which is `t` itself
    /// when `t` falls on the grid (`k·dt` from the last checkpoint:
    /// the start, a switch, a control instant, a located event) and up to
    /// one step before it otherwise.
    ///
    /// The first call starts the run and fixes [`RunOptions::record`] and
    /// [`RunOptions::extrema`] for it; every call's sink receives the
    /// samples and switches that call produces. After the run has ended
    /// (its duration, the stop condition, the guard, a cancel) a call does
    /// nothing; after an error it returns [`SimError::Setting`].
    ///
    /// ```
    /// use controllers::{AttitudeGains, AttitudeMode, AttitudeThrust, HoldAttitude, HoldPosition, RigidBodyParams};
    /// use dynamics::{Quadrotor, Vehicle, paper};
    /// use lie::{Backend, NalgebraF64, Rotation, So3Mat};
    /// use scenarios::{Simulation, Until};
    /// type B = NalgebraF64;
    ///
    /// let params = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    /// let mode = AttitudeMode::<B, _, HoldPosition<B>>::new(
    ///     params,
    ///     AttitudeGains::uniform(0.65, 0.11, 0.0, 0.8),
    ///     HoldAttitude::new(So3Mat::<B>::identity()),
    ///     AttitudeThrust::Constant(params.mass * params.gravity),
    /// );
    /// let mut sim = Simulation::<B>::builder(Box::new(Quadrotor::<B>::paper()))
    ///     .mode(mode, Until::Never)
    ///     .duration(6.0)
    ///     .build()?;
    /// // Hover level for a second, then a kick about b1 of 3 rad/s.
    /// sim.advance_to(1.0)?;
    /// assert!(sim.state().body.omega.norm() < 1e-12);
    /// sim.state_mut().body.omega = B::vec3(3.0, 0.0, 0.0);
    /// sim.advance_to(1.5)?;
    /// // Level until the kick (Ψ = 0), tilted by it (the largest Ψ over
    /// // every step so far).
    /// let psi_peak = sim.output().psi_range.max;
    /// assert!(psi_peak > 1e-4, "the kick tilted it: Ψ = {psi_peak}");
    /// // The attitude loop brings it back level.
    /// let out = sim.run(Default::default())?;
    /// assert!(out.last.psi < 1e-9, "Ψ(6 s) = {}", out.last.psi);
    /// # Ok::<(), scenarios::SimError>(())
    /// ```
    pub fn advance_to_with(&mut self, t: f64, opts: RunOptions<'_>) -> Result<(), SimError> {
        self.engine.advance_to_with(t, opts)
    }

    /// Ends the run where it is and returns its output. A run not yet at
    /// its end gets a last sample at [`Simulation::time`] (kept in
    /// [`RunOutput::last`] and, when recording, in the samples; no sink is
    /// told) and [`Termination::Interrupted`]; the error is that sample's
    /// (a mode rejecting the state there).
    pub fn finish(self) -> Result<RunOutput, SimError> {
        self.engine.finish()
    }

    /// The run's output so far (samples, switches, events, extrema; the
    /// last sample taken is [`RunOutput::last`]); empty before the first
    /// [`Simulation::advance_to`].
    pub fn output(&self) -> &RunOutput {
        self.engine.output()
    }

    /// The simulated time now, s.
    pub fn time(&self) -> f64 {
        self.engine.time()
    }

    /// The run's duration, s.
    pub fn duration(&self) -> f64 {
        self.engine.duration()
    }

    /// How the run ended; `None` while it can go on.
    pub fn termination(&self) -> Option<Termination> {
        self.engine.termination()
    }

    /// The state now.
    pub fn state(&self) -> SimState<'_, B> {
        self.engine.state()
    }

    /// The state now, to change before the next
    /// [`Simulation::advance_to`]: the run resumes from the changed state
    /// on the same step grid (the stepper forgets its cached loads, a law
    /// held at a breakpoint branch picks its branch from the state again;
    /// under sampled control the held command stays until the next control
    /// instant, as on a flight computer). A value that is not finite is
    /// refused by the next `advance_to` ([`SimError::Setting`] naming the
    /// field), before any step or command reads it. Before the first
    /// step, the vehicle's
    /// internal states are still to be set from the first command; to
    /// start from states of one's own, give them to the builder
    /// ([`SimulationBuilder::vehicle_states`]), which keeps them.
    pub fn state_mut(&mut self) -> SimStateMut<'_, B> {
        self.engine.state_mut()
    }

    /// How many integral states the plan's modes use and how many
    /// internal states the vehicle has.
    pub fn layout(&self) -> StateLayout {
        self.engine.layout()
    }
}

/// What [`Simulation`] asks of the loop it holds, whatever the loop's
/// extra-state size and integrator.
trait Run<B: Backend> {
    fn advance_to_with(&mut self, t: f64, opts: RunOptions<'_>) -> Result<(), SimError>;
    fn finish(self: Box<Self>) -> Result<RunOutput, SimError>;
    fn output(&self) -> &RunOutput;
    fn time(&self) -> f64;
    fn duration(&self) -> f64;
    fn termination(&self) -> Option<Termination>;
    fn state(&self) -> SimState<'_, B>;
    fn state_mut(&mut self) -> SimStateMut<'_, B>;
    fn layout(&self) -> StateLayout;
}

impl<B: Backend, const N: usize, I: Integrator<B, N>> Run<B> for Engine<'_, B, N, I> {
    fn advance_to_with(&mut self, t: f64, opts: RunOptions<'_>) -> Result<(), SimError> {
        if t.is_nan() {
            return Err(SimError::Setting {
                field: "advance_to",
                message: "the time is NaN".into(),
            });
        }
        if self.failed {
            return Err(SimError::Setting {
                field: "advance_to",
                message: "an earlier call failed; the run cannot go on".into(),
            });
        }
        let r = stepping::advance(self, t.min(self.duration), opts);
        self.failed = r.is_err();
        r
    }

    fn finish(self: Box<Self>) -> Result<RunOutput, SimError> {
        stepping::finish(*self)
    }

    fn output(&self) -> &RunOutput {
        &self.running.out
    }

    fn time(&self) -> f64 {
        self.running.t
    }

    fn duration(&self) -> f64 {
        self.duration
    }

    fn termination(&self) -> Option<Termination> {
        self.running.done
    }

    fn state(&self) -> SimState<'_, B> {
        let at = self.layout;
        let segment = self.running.active();
        SimState {
            t: self.running.t,
            body: &self.y.body,
            integrals: at.integrals(&self.y.extra),
            vehicle_states: at.vehicle_states(&self.y.extra),
            segment,
            mode: self.plan.get(segment).map_or("none", |s| s.mode.name()),
        }
    }

    fn state_mut(&mut self) -> SimStateMut<'_, B> {
        self.perturbed = true;
        let t = self.running.t;
        let (integrals, vehicle_states) = self.layout.split_mut(&mut self.y.extra);
        SimStateMut {
            t,
            body: &mut self.y.body,
            integrals,
            vehicle_states,
        }
    }

    fn layout(&self) -> StateLayout {
        StateLayout {
            integrals: self.layout.integrals,
            vehicle_states: self.layout.vehicle_states,
        }
    }
}
