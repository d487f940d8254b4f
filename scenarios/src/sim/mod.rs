//! The simulation: any vehicle, any flight modes, any integrator, through
//! one loop with exact landing on checkpoints, located events and
//! recording.
//!
//! | file | what it holds |
//! |---|---|
//! | `mod.rs` | the public types: [`Simulation`] and its builder, [`Segment`], [`Until`], [`Control`], [`Sample`], [`RunOutput`], [`SimError`] |
//! | `closed_loop.rs` | the vehicle, the plan and the held command as one [`integrators::System`]; the extra-state layout; switching |
//! | `stepping.rs` | the stepping loop: checkpoints (control instants, switch times, end), steps landing on them, samples from the continuous extension, extrema over every step, progress |
//! | `events.rs` | event location: breakpoint crossings (the paper's sat′) and condition switches (`Ψ` below a threshold, a user predicate) |
//! | `record.rs` | one [`Sample`] from the state and the command |
//!
//! # Extra states
//! The integrator advances the body and `N` extra scalars (the const
//! parameter of [`Simulation`], 6 by default): slots `0..m` are the plan's
//! integral register (`m` = the largest [`Mode::integral_count`] of the
//! plan; the paper's modes use `[e_I, e_i]`, so `m = 6`), slots `m..m + n`
//! the vehicle's internal states (`n` = [`Vehicle::state_count`]); the rest
//! stay zero. A plan and vehicle that need more than `N` are a
//! [`SimError::Layout`] naming both counts.

pub(crate) mod closed_loop;
mod events;
mod report;
pub use report::RunReport;
pub(crate) mod record;
mod stepping;

use std::sync::atomic::AtomicBool;

use controllers::{Mode, ModeOutput};
use dynamics::{RigidBodyState, Vehicle, Wind};
use integrators::{Integrator, IntegratorKind, State, Stepper, StepperConfig};
use lie::num_traits::Float;
use lie::{Backend, Real, S};

use crate::output::{OutputError, Sink};
use crate::scene::SceneError;

/// One recorded sample, in f64 whatever the simulation scalar.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// Time, s.
    pub t: f64,
    /// Position (0 when not translating).
    pub x: [f64; 3],
    /// Velocity.
    pub v: [f64; 3],
    /// Attitude, rows.
    pub r: [[f64; 3]; 3],
    /// Body angular velocity.
    pub omega: [f64; 3],
    /// Ψ against the active desired attitude.
    pub psi: f64,
    /// ‖x − x_d‖ (0 without a position reference).
    pub ex: f64,
    /// Commanded thrust.
    pub thrust: f64,
    /// Commanded moment.
    pub moment: [f64; 3],
    /// Name of the active mode ([`Mode::name`](controllers::Mode::name); `"none"` without a plan).
    pub mode: &'static str,
    /// Active segment.
    pub segment: usize,
    /// Desired attitude (R_d or R_c), rows.
    pub rd: [[f64; 3]; 3],
    /// Desired angular velocity (Ω_d or Ω_c).
    pub omega_d: [f64; 3],
    /// Desired position (0 without one).
    pub xd: [f64; 3],
    /// Integral slots 0–2 (the paper's attitude integral e_I; 0 when the
    /// plan uses fewer slots).
    pub e_att: [f64; 3],
    /// Integral slots 3–5 (the paper's position integral e_i).
    pub e_pos: [f64; 3],
    /// Rotor thrusts delivered (the allocation inverse of the vehicle's
    /// applied wrench; empty without rotors).
    pub rotors: Vec<f64>,
    /// The vehicle's internal states (empty for a vehicle without any).
    pub vehicle_states: Vec<f64>,
    /// The wind at the vehicle, inertial, m/s (zero without one).
    pub wind: [f64; 3],
}

/// A mode switch.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SwitchRecord {
    /// Time, s.
    pub t: f64,
    /// Segment left.
    pub from: usize,
    /// Segment entered.
    pub to: usize,
}

/// What a run produced.
#[derive(Clone, Debug)]
pub struct RunOutput {
    /// Samples every `record.sample` seconds, plus t = 0 and the end,
    /// taken from the steps' continuous extension (the steps do not land
    /// on them).
    pub samples: Vec<Sample>,
    /// Mode switches.
    pub switches: Vec<SwitchRecord>,
    /// The name of each segment's mode, in plan order.
    pub mode_names: Vec<&'static str>,
    /// Located breakpoint crossings (sat′: e_i crossing ±σ).
    pub events: usize,
    /// Their times and breakpoint indices (the component of e_i).
    pub event_times: Vec<(f64, usize)>,
    /// Integrator steps (accepted substeps for dopri and halved LGVI
    /// steps, redone steps at events included).
    pub steps: u64,
    /// Load (vector-field) evaluations.
    pub evaluations: u64,
    /// Largest commanded thrust over every step end, located event and
    /// t = 0: the same with and without recording.
    pub max_thrust: f64,
    /// Largest rotor thrust magnitude over the same states.
    pub max_rotor: f64,
    /// Wall time of the loop, s.
    pub wall: f64,
    /// Settings that were adjusted or are doubtful (a tolerance below what
    /// the scalar can deliver, say), one sentence each, for the caller to
    /// show.
    pub warnings: Vec<String>,
    /// Largest ‖RᵀR − I‖_F over the same states (0 on SO(3); grows when a
    /// stepper drifts off the group).
    pub max_orthogonality_error: f64,
    /// Smallest and largest Ψ over the same states (in [0, 2] for a
    /// rotation).
    pub psi_range: (f64, f64),
    /// The machine ε of the simulation's scalar (what the health bounds
    /// scale with).
    pub epsilon: f64,
    /// How the run ended ([`Simulation::output`] of a run that can go on
    /// says [`Termination::Interrupted`] at its time).
    pub termination: Termination,
    /// The final state.
    pub last: Sample,
}

/// A sign that a run's numbers cannot be trusted ([`RunOutput::health`]).
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Health {
    /// ‖RᵀR − I‖_F passed `bound` (1e-6 in f64, 1e-3 in f32: far above
    /// the rounding a run accumulates, far below what changes a result
    /// visibly): R has left SO(3).
    OffGroup {
        /// The largest ‖RᵀR − I‖_F (NaN when it became NaN).
        error: f64,
        /// The bound for the scalar.
        bound: f64,
    },
    /// Ψ left [0, 2] by more than rounding and the distance from SO(3)
    /// explain: R is not a rotation any more.
    PsiOutOfRange {
        /// Smallest and largest Ψ.
        range: (f64, f64),
    },
}

impl std::fmt::Display for Health {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Health::OffGroup { error, bound } => write!(
                f,
                "‖RᵀR − I‖ reached {error:.2e} (bound {bound:.0e} for this scalar): R has left SO(3)"
            ),
            Health::PsiOutOfRange { range } => write!(
                f,
                "Ψ left [0, 2] (range [{:.3e}, {:.3e}]): not a rotation any more",
                range.0, range.1
            ),
        }
    }
}

impl RunOutput {
    /// What says the run's numbers cannot be trusted, from its extrema
    /// (over every step end and located event, or the start, the events
    /// and the end without [`RunOptions::extrema`]); empty for a healthy
    /// run.
    pub fn health(&self) -> Vec<Health> {
        let bound = if self.epsilon < 1e-10 { 1e-6 } else { 1e-3 };
        let mut w = Vec::new();
        let e = self.max_orthogonality_error;
        if e.is_nan() || e > bound {
            w.push(Health::OffGroup { error: e, bound });
        }
        // Ψ is computed as ¼‖R − R_d‖², never negative; an R off SO(3) by
        // e = ‖RᵀR − I‖ moves it by up to ~e, and rounding by ~10 ε. Only
        // a departure from [0, 2] beyond that says R is not a rotation.
        let slack = 10.0 * self.epsilon + e;
        let (lo, hi) = self.psi_range;
        if lo.is_nan() || hi.is_nan() || lo < -slack || hi > 2.0 + slack {
            w.push(Health::PsiOutOfRange {
                range: self.psi_range,
            });
        }
        w
    }

    /// The located time when the stop condition ended the run.
    pub fn stopped_at(&self) -> Option<f64> {
        match self.termination {
            Termination::StoppedBy { t } => Some(t),
            _ => None,
        }
    }
    /// Where the run was interrupted ([`Termination::Interrupted`]).
    pub fn interrupted_at(&self) -> Option<f64> {
        match self.termination {
            Termination::Interrupted { t } => Some(t),
            _ => None,
        }
    }
    /// What the divergence guard caught, and when.
    pub fn diverged(&self) -> Option<(Divergence, f64)> {
        match self.termination {
            Termination::Diverged { what, t } => Some((what, t)),
            _ => None,
        }
    }
}

/// How a run ended.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Termination {
    /// It ran to its duration.
    Completed,
    /// The stop condition ([`SimulationBuilder::stop_when`]) held first at
    /// `t` (located by bisection).
    StoppedBy {
        /// The located time, s.
        t: f64,
    },
    /// It was ended before its duration: by [`RunOptions::cancel`], or by
    /// [`Simulation::finish`] on a run not advanced to its end. `t` is
    /// where it stopped (the time of its last sample).
    Interrupted {
        /// The time of the last step, s.
        t: f64,
    },
    /// The [`DivergenceGuard`] tripped at `t`.
    Diverged {
        /// Which limit, with the value that passed it.
        what: Divergence,
        /// When: the located first instant for a state limit; for the
        /// substep cap, the start of the call that ran out of substeps
        /// (the state and the last sample are there).
        t: f64,
    },
}

/// Which limit of a [`DivergenceGuard`] a run passed.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum Divergence {
    /// |Ω| passed [`DivergenceGuard::omega`]; the value, rad/s.
    Omega(f64),
    /// ‖x − x_d‖ passed [`DivergenceGuard::position_error`]; the value, m.
    PositionError(f64),
    /// ‖M‖ of the command passed [`DivergenceGuard::moment`]; the value,
    /// N m.
    Moment(f64),
    /// One integrator call needed more substeps than
    /// [`DivergenceGuard::substeps`] (adaptive steppers only).
    Substeps(u32),
}

impl std::fmt::Display for Divergence {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Divergence::Omega(w) => write!(f, "|Ω| = {w:.4e} rad/s"),
            Divergence::PositionError(e) => write!(f, "‖x − x_d‖ = {e:.4e} m"),
            Divergence::Moment(m) => write!(f, "‖M‖ = {m:.4e} N m"),
            Divergence::Substeps(n) => {
                write!(f, "one integrator call needed more than {n} substeps")
            }
        }
    }
}

/// Limits past which a run counts as diverged and ends with
/// [`Termination::Diverged`] instead of integrating a blow-up to its
/// duration (or to a non-finite state). Each is off when `None` (the
/// default: no limit). The state limits are checked after every step and
/// the first instant one is passed is located by bisection, as a stop
/// condition is; the substep cap is handed to the integrator
/// ([`Integrator::limit_substeps`]).
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct DivergenceGuard {
    /// Largest |Ω|, rad/s.
    pub omega: Option<f64>,
    /// Largest ‖x − x_d‖ (‖x‖ when the mode has no desired position), m.
    pub position_error: Option<f64>,
    /// Largest ‖M‖ of the command, N m.
    pub moment: Option<f64>,
    /// Most substeps in one integrator call.
    pub substeps: Option<u32>,
}

impl DivergenceGuard {
    /// Whether any state limit is set (the substep cap aside).
    pub fn checks_state(&self) -> bool {
        self.omega.is_some() || self.position_error.is_some() || self.moment.is_some()
    }

    /// The first limit passed by `|Ω| = omega`, `‖x − x_d‖ = ex` and
    /// `‖M‖ = moment` (in that order), if any.
    pub fn check(&self, omega: f64, ex: f64, moment: f64) -> Option<Divergence> {
        let over = |limit: Option<f64>, v: f64| limit.is_some_and(|l| v > l);
        if over(self.omega, omega) {
            Some(Divergence::Omega(omega))
        } else if over(self.position_error, ex) {
            Some(Divergence::PositionError(ex))
        } else if over(self.moment, moment) {
            Some(Divergence::Moment(moment))
        } else {
            None
        }
    }
}

/// Why a run could not be built or could not go on. Each variant keeps its
/// typed cause ([`std::error::Error::source`]); the messages name the time
/// and the field.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum SimError {
    /// The scene is invalid, or names a vehicle kind nothing registered.
    Scene(SceneError),
    /// The scene names an integrator that does not exist.
    Integrator(integrators::UnknownIntegrator),
    /// The vehicle rejected its parameters, or its allocation failed.
    Vehicle(dynamics::DynamicsError),
    /// A vehicle registered by the program failed to build.
    CustomVehicle {
        /// Its kind, as the scene names it.
        kind: String,
        /// What its builder said.
        message: String,
    },
    /// A setting of the [`SimulationBuilder`] (or an argument of
    /// [`Simulation::advance_to`]) is invalid.
    Setting {
        /// The setting, e.g. `"dt"`.
        field: &'static str,
        /// What is wrong with its value.
        message: String,
    },
    /// The plan and the vehicle need more extra states than the simulation
    /// holds.
    Layout {
        /// Integral slots the plan's modes use.
        integrals: usize,
        /// Internal states the vehicle declares.
        vehicle_states: usize,
        /// The simulation's `N`.
        capacity: usize,
    },
    /// A step failed. When a mode rejected its input inside the step (a
    /// non-finite state or reference reaching the law), `control` says
    /// which input: that is the cause, and the integrator's error the
    /// symptom.
    Step {
        /// Start of the step, s.
        t: f64,
        /// Its size, s.
        h: f64,
        /// The integrator's error.
        source: integrators::StepError,
        /// The mode's complaint, if one came first.
        control: Option<controllers::ControlError>,
    },
    /// A mode rejected its input outside a step (a sample, a held command).
    Control {
        /// When, s.
        t: f64,
        /// The mode's error.
        source: controllers::ControlError,
    },
    /// A sink could not write (disk full, …).
    Output(OutputError),
}

/// A builder setting's error.
fn bad(field: &'static str, message: String) -> SimError {
    SimError::Setting { field, message }
}

impl SimError {
    /// A step error with the mode's complaint, if any.
    pub(crate) fn step(
        t: f64,
        h: f64,
        source: integrators::StepError,
        control: Option<controllers::ControlError>,
    ) -> Self {
        SimError::Step {
            t,
            h,
            source,
            control,
        }
    }

    /// Whether the state itself went non-finite in a step (not the
    /// reference, not a file): what a smaller step, a tighter tolerance
    /// or a [`DivergenceGuard`] addresses.
    pub fn is_divergence(&self) -> bool {
        matches!(
            self,
            SimError::Step {
                control: Some(controllers::ControlError::NonFinite { .. }),
                ..
            } | SimError::Step {
                control: None,
                source: integrators::StepError::NonFinite { .. }
                    | integrators::StepError::TooManySubsteps { .. }
                    | integrators::StepError::StepTooSmall { .. },
                ..
            }
        )
    }
}

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        use controllers::ControlError as C;
        match self {
            SimError::Scene(e) => write!(f, "scene: {e}"),
            SimError::Integrator(e) => write!(f, "scene: {e}"),
            SimError::Vehicle(e) => write!(f, "vehicle: {e}"),
            SimError::CustomVehicle { kind, message } => {
                write!(f, "scene: vehicle `{kind}`: {message}")
            }
            SimError::Setting { field, message } => write!(f, "simulation `{field}`: {message}"),
            SimError::Layout {
                integrals,
                vehicle_states,
                capacity,
            } => write!(
                f,
                "the plan's modes use {integrals} integral states and the vehicle declares \
                 {vehicle_states} internal states, {} in all, but the simulation holds \
                 N = {capacity}; build it as `Simulation::<B, {}>`",
                integrals + vehicle_states,
                integrals + vehicle_states
            ),
            SimError::Step {
                t,
                h,
                control: Some(c @ C::NonFiniteReference { .. }),
                ..
            } => write!(
                f,
                "integrator: in the step from t = {t} (h = {h}): {c}: the reference returned NaN or ∞ there"
            ),
            SimError::Step {
                t,
                h,
                control: Some(c),
                ..
            } => write!(
                f,
                "integrator: in the step from t = {t} (h = {h}): {c}; the state diverged"
            ),
            SimError::Step { source, .. } => write!(f, "integrator: {source}"),
            SimError::Control { t, source } => write!(f, "controller: at t = {t}: {source}"),
            SimError::Output(e) => write!(f, "output: {e}"),
        }
    }
}

impl std::error::Error for SimError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            SimError::Scene(e) => Some(e),
            SimError::Integrator(e) => Some(e),
            SimError::Vehicle(e) => Some(e),
            SimError::Step {
                control: Some(c), ..
            } => Some(c),
            SimError::Step { source, .. } => Some(source),
            SimError::Control { source, .. } => Some(source),
            SimError::Output(e) => Some(e),
            SimError::CustomVehicle { .. } | SimError::Setting { .. } | SimError::Layout { .. } => {
                None
            }
        }
    }
}

impl From<SceneError> for SimError {
    fn from(e: SceneError) -> Self {
        SimError::Scene(e)
    }
}

impl From<dynamics::DynamicsError> for SimError {
    fn from(e: dynamics::DynamicsError) -> Self {
        SimError::Vehicle(e)
    }
}

impl From<integrators::UnknownIntegrator> for SimError {
    fn from(e: integrators::UnknownIntegrator) -> Self {
        SimError::Integrator(e)
    }
}

impl From<OutputError> for SimError {
    fn from(e: OutputError) -> Self {
        SimError::Output(e)
    }
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
    /// over every step end and located event (on by default). It costs one
    /// controller evaluation per step (about 1.6k instructions on a
    /// closed-loop RK4 step of about 8k); off, those fields cover only the
    /// start, the located events and the end.
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

/// When a segment ends.
pub enum Until<'a, B: Backend> {
    /// Never (the last segment).
    Never,
    /// At this time, s; the simulation lands a step on it.
    Time(f64),
    /// When `Ψ` against the mode's desired attitude drops below this. The
    /// crossing is located by bisection on redone steps.
    PsiBelow(f64),
    /// When the user's predicate first holds, checked after every step and
    /// located by bisection like `PsiBelow` (so it should switch from false
    /// to true once within a step).
    Condition(Condition<'a, B>),
}

impl<B: Backend> std::fmt::Debug for Until<'_, B> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Until::Never => write!(f, "Never"),
            Until::Time(t) => write!(f, "Time({t})"),
            Until::PsiBelow(p) => write!(f, "PsiBelow({p})"),
            Until::Condition(_) => write!(f, "Condition(..)"),
        }
    }
}

/// One segment of a plan: a flight mode and when it ends.
pub struct Segment<'a, B: Backend> {
    /// The law.
    pub mode: Box<dyn Mode<B> + 'a>,
    /// When it ends.
    pub until: Until<'a, B>,
}

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
}

/// A simulation ready to run: build it with [`Simulation::builder`].
///
/// `N` is the number of extra states the integrator carries (see the
/// module docs); `I` the integrator, any [`Integrator`] (by default the
/// run-time [`Stepper`]).
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
pub struct Simulation<'a, B: Backend, const N: usize = 6, I = Stepper<B, N>> {
    vehicle: Box<dyn Vehicle<B> + 'a>,
    /// The air's velocity, evaluated at the vehicle at every load.
    wind: Option<Box<dyn Wind + 'a>>,
    plan: Vec<Segment<'a, B>>,
    stepper: I,
    /// The state now: the initial state until the run starts.
    y: State<B, N>,
    integrals: usize,
    vehicle_states: usize,
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

impl<'a, B: Backend, const N: usize> Simulation<'a, B, N, Stepper<B, N>> {
    /// Starts a simulation of `vehicle` (defaults: no plan, at rest, RK4
    /// with `dt = 1e-3`, 1 s, continuous control, a sample every 0.01 s,
    /// events located).
    pub fn builder(vehicle: Box<dyn Vehicle<B> + 'a>) -> SimulationBuilder<'a, B, N> {
        SimulationBuilder {
            vehicle,
            wind: None,
            plan: Vec::new(),
            stepper: Stepper::new(IntegratorKind::Rk4, StepperConfig::default()),
            initial: RigidBodyState::at_rest(),
            integrals: Vec::new(),
            dt: 1e-3,
            duration: 1.0,
            control: Control::Continuous,
            record: 0.01,
            locate_events: true,
            compensate: false,
            stop: None,
            guard: DivergenceGuard::default(),
            warnings: Vec::new(),
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

impl<B: Backend, const N: usize, I: Integrator<B, N>> Simulation<'_, B, N, I> {
    /// Runs to the end: [`Simulation::advance_to`] the duration, then
    /// [`Simulation::finish`].
    pub fn run(mut self, opts: RunOptions<'_>) -> Result<RunOutput, SimError> {
        let end = self.duration;
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
    /// let psi_peak = sim.output().psi_range.1;
    /// assert!(psi_peak > 1e-4, "the kick tilted it: Ψ = {psi_peak}");
    /// // The attitude loop brings it back level.
    /// let out = sim.finish_run()?;
    /// assert!(out.last.psi < 1e-9, "Ψ(6 s) = {}", out.last.psi);
    /// # Ok::<(), scenarios::SimError>(())
    /// ```
    pub fn advance_to_with(&mut self, t: f64, opts: RunOptions<'_>) -> Result<(), SimError> {
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

    /// Advances to the end of the run and returns its output.
    pub fn finish_run(mut self) -> Result<RunOutput, SimError> {
        let end = self.duration;
        self.advance_to(end)?;
        self.finish()
    }

    /// Ends the run where it is and returns its output. A run not yet at
    /// its end gets a last sample at [`Simulation::time`] (kept in
    /// [`RunOutput::last`] and, when recording, in the samples; no sink is
    /// told) and [`Termination::Interrupted`]; the error is that sample's
    /// (a mode rejecting the state there).
    pub fn finish(self) -> Result<RunOutput, SimError> {
        stepping::finish(self)
    }

    /// The run's output so far (samples, switches, events, extrema; the
    /// last sample taken is [`RunOutput::last`]); empty before the first
    /// [`Simulation::advance_to`].
    pub fn output(&self) -> &RunOutput {
        &self.running.out
    }

    /// The simulated time now, s.
    pub fn time(&self) -> f64 {
        self.running.t
    }

    /// The run's duration, s.
    pub fn duration(&self) -> f64 {
        self.duration
    }

    /// How the run ended; `None` while it can go on.
    pub fn termination(&self) -> Option<Termination> {
        self.running.done
    }

    /// The state now.
    pub fn state(&self) -> SimState<'_, B> {
        let (m, nv) = (self.integrals, self.vehicle_states);
        let segment = self.running.active();
        SimState {
            t: self.time(),
            body: &self.y.body,
            integrals: &self.y.extra[..m],
            vehicle_states: &self.y.extra[m..m + nv],
            segment,
            mode: self.plan.get(segment).map_or("none", |s| s.mode.name()),
        }
    }

    /// The state now, to change before the next
    /// [`Simulation::advance_to`]: the run resumes from the changed state
    /// on the same step grid (the stepper forgets its cached loads, a law
    /// held at a breakpoint branch picks its branch from the state again;
    /// under sampled control the held command stays until the next control
    /// instant, as on a flight computer). Change it only to finite values:
    /// the first step checks them.
    pub fn state_mut(&mut self) -> SimStateMut<'_, B> {
        self.perturbed = true;
        let (m, nv) = (self.integrals, self.vehicle_states);
        let t = self.time();
        let (integrals, rest) = self.y.extra.split_at_mut(m);
        SimStateMut {
            t,
            body: &mut self.y.body,
            integrals,
            vehicle_states: &mut rest[..nv],
        }
    }

    /// `(m, n)`: integral slots used by the plan and the vehicle's internal
    /// states (slots `0..m` and `m..m + n` of the extra states).
    pub fn layout(&self) -> (usize, usize) {
        (self.integrals, self.vehicle_states)
    }
}

/// Builds a [`Simulation`]; every setting is checked in
/// [`SimulationBuilder::build`], which names the field and the value of a
/// bad one.
pub struct SimulationBuilder<'a, B: Backend, const N: usize = 6, I = Stepper<B, N>> {
    vehicle: Box<dyn Vehicle<B> + 'a>,
    wind: Option<Box<dyn Wind + 'a>>,
    plan: Vec<Segment<'a, B>>,
    stepper: I,
    initial: RigidBodyState<B>,
    integrals: Vec<S<B>>,
    dt: f64,
    duration: f64,
    control: Control,
    record: f64,
    locate_events: bool,
    compensate: bool,
    stop: Option<Condition<'a, B>>,
    guard: DivergenceGuard,
    warnings: Vec<String>,
}

impl<'a, B: Backend, const N: usize, I: Integrator<B, N>> SimulationBuilder<'a, B, N, I> {
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
    /// Any integrator.
    pub fn integrator<J: Integrator<B, N>>(self, stepper: J) -> SimulationBuilder<'a, B, N, J> {
        SimulationBuilder {
            vehicle: self.vehicle,
            wind: self.wind,
            plan: self.plan,
            stepper,
            initial: self.initial,
            integrals: self.integrals,
            dt: self.dt,
            duration: self.duration,
            control: self.control,
            record: self.record,
            locate_events: self.locate_events,
            compensate: self.compensate,
            stop: self.stop,
            guard: self.guard,
            warnings: self.warnings,
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
    /// [`Vehicle::total_loads_in_wind`]; the steps land on its jumps.
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
        if let Some(f) = self.initial.non_finite_field() {
            return Err(bad("initial", format!("`{f}` is not finite")));
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

    /// Checks every setting and lays out the extra states.
    pub fn build(self) -> Result<Simulation<'a, B, N, I>, SimError> {
        self.check_settings()?;
        self.check_plan()?;
        let integrals = self
            .plan
            .iter()
            .map(|s| s.mode.integral_count())
            .max()
            .unwrap_or(0);
        let vehicle_states = self.vehicle.state_count();
        if integrals + vehicle_states > N {
            return Err(SimError::Layout {
                integrals,
                vehicle_states,
                capacity: N,
            });
        }
        if self.integrals.len() > integrals {
            return Err(bad(
                "integrals",
                format!(
                    "{} initial values given, the plan's modes use {integrals}",
                    self.integrals.len()
                ),
            ));
        }
        if self.integrals.iter().any(|v| !v.is_finite()) {
            return Err(bad(
                "integrals",
                format!(
                    "{:?} must be finite",
                    self.integrals
                        .iter()
                        .map(|v| v.to_f64_lossless())
                        .collect::<Vec<_>>()
                ),
            ));
        }
        let mut initial = State::<B, N>::new(self.initial);
        if !self.vehicle.translates() {
            initial.body.x = lie::ops::zero::<B>();
            initial.body.v = lie::ops::zero::<B>();
        }
        initial.extra[..self.integrals.len()].copy_from_slice(&self.integrals);
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
        let mut stepper = self.stepper;
        if let Some(c) = self.guard.substeps {
            stepper.limit_substeps(c);
        }
        let mut plan = self.plan;
        let mut wind = self.wind;
        let mut running = stepping::prepare(
            self.vehicle.as_ref(),
            wind.as_deref_mut(),
            &mut plan,
            &stepping::Settings {
                control: self.control,
                compensate: self.compensate,
                m: integrals,
                nv: vehicle_states,
                dt: self.dt,
                t_end: self.duration,
                record: self.record,
                locate_events: self.locate_events,
            },
        )?;
        running.out.warnings.extend(self.warnings);
        Ok(Simulation {
            vehicle: self.vehicle,
            wind,
            plan,
            stepper,
            y: initial,
            integrals,
            vehicle_states,
            duration: self.duration,
            stop: self.stop,
            guard: self.guard,
            running: Box::new(running),
            perturbed: false,
            failed: false,
        })
    }
}
