//! The simulation engine: any vehicle, flight-mode plan, reference and
//! integrator through one loop.
//!
//! [`Simulation`] takes a `Box<dyn Vehicle<B>>` (with internal states if it
//! has actuator dynamics), a plan of [`Segment`]s (any
//! [`Mode`](controllers::Mode), left at a time, on `Ψ`, or on a user
//! [`Condition`]), any integrator, continuous or sampled [`Control`], and
//! recording; it returns a [`RunOutput`] and streams every sample into a
//! [`Sink`] as it goes. The loop:
//!
//! - lands exactly on every mode switch and control sample (a step is
//!   shortened to hit them; times are `k·Δ`, never sums), and takes the
//!   record samples between steps from each step's continuous extension
//!   (`integrators::dense`), so recording never changes the trajectory;
//! - switches flight modes at their `until` time or, for `until_psi` (and
//!   a user condition), at the located instant Ψ drops below the threshold
//!   (bisection on redone steps);
//! - locates the breakpoints of the active mode inside a segment (the
//!   paper's sat′: a component of e_i crossing ±σ) by cubic Hermite
//!   interpolation of e_i, ė_i over the step, refines it by Newton on the
//!   integrated e_i and splits the step there, for every stepper,
//!   integrating each side on its own branch of sat′ (see
//!   `controllers::SatBranch`);
//! - pays only for what the run uses: a pinned vehicle integrates no
//!   translation, a vehicle without disturbance evaluates none, a run
//!   without recording keeps only the final state.
//!
//! This crate is the bottom of the simulation layers and depends on no
//! file format: the scene files and the built-in scenes are
//! `geopid-scenes`, the CSV and MCAP sinks `geopid-logs`, the Monte Carlo,
//! regression and tuning studies `geopid-studies`.
//!
//! ```
//! use controllers::{AttitudeGains, AttitudeMode, AttitudeThrust, HoldAttitude, HoldPosition, RigidBodyParams};
//! use dynamics::{Quadrotor, RigidBodyState, paper};
//! use lie::{Backend, NalgebraF64, Rotation, So3Mat};
//! use scenarios::{Simulation, Until};
//! type B = NalgebraF64;
//!
//! // The paper's quadrotor holding level attitude from a 30° tilt.
//! let params = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
//! let mode = AttitudeMode::<B, _, HoldPosition<B>>::new(
//!     params,
//!     AttitudeGains::uniform(0.65, 0.11, 0.0, 0.8),
//!     HoldAttitude::new(So3Mat::<B>::identity()),
//!     AttitudeThrust::Constant(params.mass * params.gravity),
//! );
//! let mut start = RigidBodyState::<B>::at_rest();
//! start.r = So3Mat::<B>::exp(B::vec3(0.5236, 0.0, 0.0)).matrix();
//! let out = Simulation::<B>::builder(Box::new(Quadrotor::<B>::paper()))
//!     .mode(mode, Until::Never)
//!     .initial(start)
//!     .duration(3.0)
//!     .build()?
//!     .run(Default::default())?;
//! assert!(out.last.psi < 1e-6, "Ψ(3 s) = {}", out.last.psi);
//! # Ok::<(), scenarios::SimError>(())
//! ```

#![deny(missing_docs)]

#[cfg(feature = "simd")]
pub mod lanes;
mod sim;

pub use sim::{
    BreakpointCrossing, CAPACITIES, Condition, ContactChange, Control, Divergence, DivergenceGuard,
    Health, LoopRates, MeasurementRecord, NavSample, OpenLoop, OutputError, PsiRange, Readout,
    RunOptions, RunOutput, Sample, Segment, SimError, SimState, SimStateMut, Simulation,
    SimulationBuilder, Sink, StateLayout, SwitchRecord, Tee, Termination, Until, Watched,
};
