//! Swappable integrators for rigid bodies on SO(3) × Rⁿ.
//!
//! The system they advance is described by [`System`]: a rigid body
//! (mass, inertia, whether it translates) plus `N` extra scalar states (a
//! controller's integral terms, say), and a load function returning the
//! total inertial force, the body moment and the extra states' rates. They
//! are therefore not tied to a vehicle, and this crate depends on `lie`
//! alone: [`problems::Top`] (the torque-free body or the heavy top) is a
//! test problem, `scenarios::OpenLoop` runs a `dynamics` vehicle under a held
//! wrench, and the scenario runner's closed loop is one more `System`.
//!
//! | stepper | order | on SO(3) | loads per step | notes |
//! |---|---|---|---|---|
//! | [`Euler`] | 1 | no (embedding) | 1 | baseline |
//! | [`Rk4`] | 4 | no, or by projection ([`Rk4::projected`]) | 4 | classical RK4 on R's nine entries |
//! | [`Rkmk4`] | 4 | yes | 4 | Runge–Kutta–Munthe-Kaas with `dexp⁻¹ = J_r⁻¹` |
//! | [`Lgvi`] | 2 | yes | 1 (+ iterations if loads read rates) | variational, symplectic when unforced; implicit |
//! | [`Dopri`] | 5(4) | no (embedding) | 6 per accepted substep (FSAL) | adaptive, for references |
//!
//! Compile-time choice: every stepper implements [`Integrator`], so code
//! generic over `I: Integrator<B, N>` is monomorphised per stepper. Run-time
//! choice: [`Stepper`] is an enum over all of them, built from a name with
//! [`Stepper::from_name`]; its dispatch is one `match` per step, outside
//! the per-stage arithmetic.
//!
//! A step writes into the caller's [`State`]; no stepper allocates. A step
//! that fails (non-finite state, an LGVI solve with no solution, a Dormand–
//! Prince step size underflow) returns a [`StepError`] and leaves the state
//! untouched.
//!
//! # Example
//! A torque-free body (J = diag(1, 2, 3)) for 100 s by the LGVI and by
//! RK4: the variational method keeps the kinetic energy and R's
//! orthogonality to rounding, RK4 both to its truncation error.
//!
//! ```
//! use integrators::{Lgvi, Rk4, State, System, integrate_fixed};
//! use integrators::problems::Top;
//! use lie::{Backend, NalgebraF64, RigidState, Rotation, So3Mat, ops};
//! type B = NalgebraF64;
//!
//! let body = Top::<B>::free(ops::diag::<B>(1.0, 2.0, 3.0));
//! let energy = |y: &State<B, 0>| {
//!     let w = y.body.omega;
//!     0.5 * B::dot(w, body.inertia() * w)
//! };
//! let mut start = State::<B, 0>::new(RigidState::at_rest());
//! start.body.omega = B::vec3(1.0, 0.5, -0.3);
//! let e0 = energy(&start);
//! for (name, drift_bound, group_bound) in [("lgvi", 1e-12, 1e-12), ("rk4", 1e-6, 1e-8)] {
//!     let mut sys = body;
//!     let mut y = start;
//!     match name {
//!         "lgvi" => integrate_fixed(&mut Lgvi::default(), &mut sys, 0.0, 0.01, 10_000, &mut y)?,
//!         _ => integrate_fixed(&mut Rk4::default(), &mut sys, 0.0, 0.01, 10_000, &mut y)?,
//!     };
//!     let drift = (energy(&y) / e0 - 1.0).abs();
//!     assert!(drift < drift_bound, "{name}: |ΔE/E| = {drift:e}");
//!     let off_group = So3Mat::<B>::from_matrix_unchecked(y.body.r).orthogonality_error();
//!     assert!(off_group < group_bound, "{name}: ‖RᵀR − I‖ = {off_group:e}");
//! }
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

#![deny(missing_docs)]

pub mod dense;
mod dopri;
pub mod lanes;
mod lgvi;
mod method;
pub mod problems;
mod rk;
mod stepper;
mod system;

pub use dopri::Dopri;
pub use lgvi::{EndLoad, Lgvi};
pub use method::Method;
pub use rk::{Euler, Rk4, Rkmk4};
pub use stepper::{IntegratorKind, Stepper, StepperConfig, UnknownIntegrator};
pub use system::{Load, State, System, inverse_or_nan};

use core::fmt;
use lie::{Backend, S};

/// What a step did, for reports and tests.
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct StepStats {
    /// Load evaluations.
    pub evaluations: u32,
    /// Substeps taken (Dormand–Prince's accepted steps, LGVI halvings + 1).
    pub substeps: u32,
    /// Rejected substeps (Dormand–Prince).
    pub rejected: u32,
    /// Largest Newton iteration count of an implicit solve (LGVI), 0 else.
    pub newton_iterations: u32,
    /// Largest relative residual of an implicit solve (LGVI), 0 else.
    pub residual: f64,
}

impl StepStats {
    pub(crate) fn merge(&mut self, o: StepStats) {
        self.evaluations += o.evaluations;
        self.substeps += o.substeps;
        self.rejected += o.rejected;
        self.newton_iterations = self.newton_iterations.max(o.newton_iterations);
        self.residual = self.residual.max(o.residual);
    }
}

/// Why a step failed. The state is left as it was before the step.
#[derive(Clone, Debug, PartialEq)]
pub enum StepError {
    /// `h` was not finite and positive.
    InvalidStep {
        /// The step size given.
        h: f64,
    },
    /// A NaN or ±∞ appeared in the state or a load.
    NonFinite {
        /// Which quantity.
        field: &'static str,
        /// Time of the step.
        t: f64,
    },
    /// The LGVI's implicit attitude equation has no (near-identity) solution
    /// at this step size, even after halving: its hard limit `h‖Ω‖ ≲ 1`.
    NoSolution {
        /// Time of the step.
        t: f64,
        /// The (smallest) step size tried.
        h: f64,
        /// `h‖Ω‖` at that step.
        h_omega: f64,
        /// Newton iterations spent.
        iterations: u32,
        /// Relative residual reached.
        residual: f64,
    },
    /// The LGVI's end-point load iteration (loads that read `v`, `Ω` or the
    /// extra states) did not converge: the feedback is too stiff for `h`.
    EndLoadDiverged {
        /// Time of the step.
        t: f64,
        /// Step size.
        h: f64,
    },
    /// The adaptive step size fell below what the scalar can resolve.
    StepTooSmall {
        /// Time where it happened.
        t: f64,
        /// The step size proposed.
        h: f64,
    },
    /// One call took more substeps than its cap ([`Dopri::max_substeps`]).
    TooManySubsteps {
        /// Time where it happened.
        t: f64,
        /// The substep size then.
        h: f64,
        /// The cap.
        substeps: u32,
    },
}

impl fmt::Display for StepError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StepError::InvalidStep { h } => write!(f, "step size h = {h} must be finite and > 0"),
            StepError::NonFinite { field, t } => {
                write!(f, "`{field}` became non-finite at t = {t}")
            }
            StepError::NoSolution {
                t,
                h,
                h_omega,
                iterations,
                residual,
            } => write!(
                f,
                "LGVI attitude equation has no solution at t = {t} with h = {h} \
                 (h‖Ω‖ = {h_omega:.3}, the limit is about 1; {iterations} Newton iterations, \
                 residual {residual:.1e}); reduce the step"
            ),
            StepError::EndLoadDiverged { t, h } => write!(
                f,
                "LGVI end-point load iteration diverged at t = {t} with h = {h}; reduce the step"
            ),
            StepError::StepTooSmall { t, h } => write!(
                f,
                "adaptive step size fell to {h:e} at t = {t}: tolerance too tight for the scalar type"
            ),
            StepError::TooManySubsteps { t, h, substeps } => write!(
                f,
                "more than {substeps} substeps in one call (at t = {t}, substep {h:e}): the solution is blowing up or too stiff"
            ),
        }
    }
}

impl std::error::Error for StepError {}

/// A one-step method for a [`System`] with `N` extra states.
///
/// # Example
/// Code generic over the stepper is compiled once per stepper; here, the
/// error of one step of each against a tiny-step reference shows the
/// orders (halving h divides RK4's step error by about 2⁵ = 32).
///
/// ```
/// use integrators::{Integrator, Rk4, Rkmk4, State, integrate_fixed};
/// use integrators::problems::Top;
/// use lie::{Backend, NalgebraF64, RigidState, ops};
/// type B = NalgebraF64;
///
/// fn step_error<I: Integrator<B, 0> + Default>(h: f64) -> f64 {
///     let mut sys = Top::<B>::free(ops::diag::<B>(1.0, 2.0, 3.0));
///     let mut start = State::<B, 0>::new(RigidState::at_rest());
///     start.body.omega = B::vec3(1.0, 0.5, -0.3);
///     let (mut one, mut fine) = (start, start);
///     I::default().step(&mut sys, 0.0, h, &mut one).unwrap();
///     integrate_fixed(&mut Rk4::default(), &mut sys, 0.0, h / 1000.0, 1000, &mut fine).unwrap();
///     let d = one.body.omega - fine.body.omega;
///     B::dot(d, d).sqrt()
/// }
/// for ratio in [step_error::<Rk4>(0.1) / step_error::<Rk4>(0.05),
///               step_error::<Rkmk4>(0.1) / step_error::<Rkmk4>(0.05)] {
///     assert!(ratio > 20.0 && ratio < 45.0, "{ratio}");
/// }
/// ```
pub trait Integrator<B: Backend, const N: usize> {
    /// Name as accepted by [`Stepper::from_name`].
    fn name(&self) -> &'static str;
    /// Order of accuracy on smooth problems.
    fn order(&self) -> u32;
    /// Advances `y` from `t` to `t + h` in place.
    fn step<Sys: System<B, N> + ?Sized>(
        &mut self,
        sys: &mut Sys,
        t: S<B>,
        h: S<B>,
        y: &mut State<B, N>,
    ) -> Result<StepStats, StepError>;
    /// Forgets cached loads (FSAL stage, LGVI end-point load); call it after
    /// changing the state or the system between steps. Steppers also detect
    /// a changed state themselves, so this is only needed when the *system*
    /// changed (a new mode, a new command) with the state unchanged.
    fn reset(&mut self) {}
    /// A copy that integrates on its own without touching this stepper, for
    /// a method whose one call may take several internal steps (an adaptive
    /// one): a simulation samples inside such a call by integrating the
    /// copy from the call's start to the sample, since a cubic through the
    /// call's two ends would not keep the method's accuracy over a long
    /// call. `None` (the default) for one-step-per-call methods, which are
    /// sampled by the cubic Hermite extension ([`dense`]).
    fn resampler(&self) -> Option<Self>
    where
        Self: Sized,
    {
        None
    }
    /// Caps the internal substeps of one call at `cap` (a call that needs
    /// more fails with [`StepError::TooManySubsteps`]): how a simulation's
    /// divergence guard stops an adaptive method grinding through ever
    /// smaller substeps of a blow-up. A no-op for methods that take one
    /// step per call (the default).
    fn limit_substeps(&mut self, cap: u32) {
        let _ = cap;
    }
}

/// Takes `n` steps of size `h` from `t0` (see the crate example); the time of step `k` is
/// `t0 + k h` computed by multiplication, not by repeated addition.
pub fn integrate_fixed<B, I, Sys, const N: usize>(
    integrator: &mut I,
    sys: &mut Sys,
    t0: S<B>,
    h: S<B>,
    n: usize,
    y: &mut State<B, N>,
) -> Result<StepStats, StepError>
where
    B: Backend,
    I: Integrator<B, N> + ?Sized,
    Sys: System<B, N> + ?Sized,
{
    use lie::Real;
    let mut stats = StepStats::default();
    for k in 0..n {
        let t = t0 + h * S::<B>::lit(k as f64);
        stats.merge(integrator.step(sys, t, h, y)?);
    }
    Ok(stats)
}
