//! What a run returns: samples, switches, the figures, how it ended.

/// One recorded sample, in f64 whatever the simulation scalar. New
/// fields may be added (hence `#[non_exhaustive]`).
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
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
    /// With sensors: the latest measurements and the estimate the mode
    /// last read (`None` without sensors).
    pub sensors: Option<Box<super::Readout>>,
}

/// A mode switch: its time, s, and the segments left and entered.
pub type SwitchRecord = controllers::Switch<f64>;

/// What a run produced. New figures may be added (hence
/// `#[non_exhaustive]`): read the fields, never build one.
#[derive(Clone, Debug)]
#[non_exhaustive]
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
    /// Each located crossing: its time and the component of e_i.
    pub event_times: Vec<BreakpointCrossing>,
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
    pub psi_range: PsiRange,
    /// The machine ε of the simulation's scalar (what the health bounds
    /// scale with).
    pub epsilon: f64,
    /// How the run ended ([`Simulation::output`](super::Simulation::output) of a run that can go on
    /// says [`Termination::Interrupted`] at its time).
    pub termination: Termination,
    /// The final state.
    pub last: Sample,
    /// Every measurement the sensors took, in the order taken per step
    /// (each carries its time; empty without sensors or recording).
    pub measurements: Vec<super::MeasurementRecord>,
    /// Each located change of a contact point (a foot starting or ceasing
    /// to push on the ground), in time order; empty without contact.
    pub contacts: Vec<ContactChange>,
}

/// A contact point starting or ceasing to push (a touchdown or a
/// lift-off), located inside the step where it happened.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ContactChange {
    /// The located time, s.
    pub t: f64,
    /// The contact point's index (the order the vehicle gives them).
    pub point: usize,
    /// True when it starts pushing (a touchdown), false when it stops.
    pub pushing: bool,
    /// Its velocity into the contact there, m/s (the touchdown speed).
    pub normal_speed: f64,
}

/// A located breakpoint crossing (the paper's sat′: a component of e_i
/// crossing ±σ).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct BreakpointCrossing {
    /// The located time, s.
    pub t: f64,
    /// The component of e_i that crossed (0, 1 or 2).
    pub component: usize,
}

/// The smallest and largest Ψ a run passed through (`min > max` before
/// any state was seen).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PsiRange {
    /// The smallest Ψ.
    pub min: f64,
    /// The largest Ψ.
    pub max: f64,
}

impl PsiRange {
    /// The range of no state yet: `[+∞, −∞]`, which any Ψ widens.
    pub const EMPTY: PsiRange = PsiRange {
        min: f64::INFINITY,
        max: f64::NEG_INFINITY,
    };

    /// This range widened to hold `psi`.
    pub fn with(self, psi: f64) -> PsiRange {
        PsiRange {
            min: self.min.min(psi),
            max: self.max.max(psi),
        }
    }
}

/// A sign that a run's numbers cannot be trusted ([`RunOutput::health`]).
#[derive(Copy, Clone, Debug, PartialEq)]
#[non_exhaustive]
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
        range: PsiRange,
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
                range.min, range.max
            ),
        }
    }
}

impl RunOutput {
    /// What says the run's numbers cannot be trusted, from its extrema
    /// (over every step end and located event, or the start, the events
    /// and the end without [`RunOptions::extrema`](super::RunOptions::extrema)); empty for a healthy
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
        let PsiRange { min: lo, max: hi } = self.psi_range;
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

/// How a run ended. New reasons may be added (hence `#[non_exhaustive]`):
/// a match needs a `_` arm.
#[derive(Copy, Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Termination {
    /// It ran to its duration.
    Completed,
    /// The stop condition ([`SimulationBuilder::stop_when`](super::SimulationBuilder::stop_when)) held first at
    /// `t` (located by bisection).
    StoppedBy {
        /// The located time, s.
        t: f64,
    },
    /// It was ended before its duration: by [`RunOptions::cancel`](super::RunOptions::cancel), or by
    /// [`Simulation::finish`](super::Simulation::finish) on a run not advanced to its end. `t` is
    /// where it stopped (the time of its last sample).
    Interrupted {
        /// The time of the last step, s.
        t: f64,
    },
    /// A contact point touched down faster than its contact's crash speed
    /// (`dynamics::Ground::crash_speed` for a ground): the run ends at the
    /// located touchdown.
    Crashed {
        /// The touchdown's time, s.
        t: f64,
        /// The contact point (a foot's index).
        point: usize,
        /// Its speed into the ground, m/s.
        speed: f64,
    },
    /// The [`DivergenceGuard`](super::DivergenceGuard) tripped at `t`.
    Diverged {
        /// Which limit, with the value that passed it.
        what: Divergence,
        /// When: the located first instant for a state limit; for the
        /// substep cap, the start of the call that ran out of substeps
        /// (the state and the last sample are there).
        t: f64,
    },
}

/// Which limit of a [`DivergenceGuard`](super::DivergenceGuard) a run passed.
#[derive(Copy, Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Divergence {
    /// |Ω| passed [`DivergenceGuard::omega`](super::DivergenceGuard::omega); the value, rad/s.
    Omega(f64),
    /// ‖x − x_d‖ passed [`DivergenceGuard::position_error`](super::DivergenceGuard::position_error); the value, m.
    PositionError(f64),
    /// ‖M‖ of the command passed [`DivergenceGuard::moment`](super::DivergenceGuard::moment); the value,
    /// N m.
    Moment(f64),
    /// One integrator call needed more substeps than
    /// [`DivergenceGuard::substeps`](super::DivergenceGuard::substeps) (adaptive steppers only).
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
/// ([`Integrator::limit_substeps`](integrators::Integrator::limit_substeps)).
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
