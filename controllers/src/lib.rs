//! The geometric nonlinear PID controllers of Goodarzi, Lee & Lee,
//! "Geometric Nonlinear PID Control of a Quadrotor UAV on SE(3)" (equation
//! labels of the paper are cited as `(eqn:…)`).
//!
//! This crate owns the control laws — attitude mode (eqn:aM, eqn:eI),
//! position mode with the computed attitude and its exact derivatives
//! (eqn:Rd3, eqn:f, eqn:M, eqn:RdWc) — and the gain-condition checker of
//! Propositions 2 and 3. It owns no state beyond the integral terms, which
//! it *exposes* rather than hides: every law is a pure function that
//! returns, besides the force and moment, the time derivative of its
//! integral states, so a simulation can integrate them together with the
//! vehicle (continuous control) and a flight computer can advance them by
//! its sample period (sampled control). The [`Scheduler`] strings modes
//! into a plan of [`Phase`]s switched by time or by `Ψ`, without a heap,
//! for a flight computer. It does not own dynamics or integration.
//!
//! The same two laws are also [`Mode`] implementations ([`AttitudeMode`],
//! [`PositionMode`]): the trait a simulation schedules, which a user's own
//! flight mode implements too (see the [`mode`](Mode) docs for how the
//! integral states are shared and what carries across a switch).
//!
//! `#![no_std]` without the `std` feature (use `libm`); no heap anywhere.
//! Conventions as in the paper: `e3` points down, thrust acts along `−b3`.
//!
//! # Example
//! The paper's position law commanding a hover 1 m above the origin from
//! rest at the origin: the thrust exceeds the weight (climb: `−e3` is up)
//! and the integral rates come back for the caller to integrate.
//!
//! ```
//! use controllers::{
//!     AccelerationModel, AttitudeGains, HoldPosition, Mode, PositionGains, PositionMode,
//!     PositionReference, RigidBodyParams, VehicleState,
//! };
//! use lie::{Backend, NalgebraF64, Rotation, So3Mat};
//! type B = NalgebraF64;
//!
//! // The paper's quadrotor: m = 0.755 kg, J = diag(0.43, 0.43, 1.02)·10⁻² kg m², g = 9.81 m/s².
//! let params = RigidBodyParams::<B>::diagonal(0.755, [0.43e-2, 0.43e-2, 1.02e-2], 9.81);
//! let target = HoldPosition(PositionReference::hold(B::vec3(0.0, 0.0, -1.0), B::vec3(1.0, 0.0, 0.0)));
//! let law = PositionMode::new(
//!     params,
//!     PositionGains::paper(),
//!     AttitudeGains::paper(),
//!     AccelerationModel::Nominal,
//!     target,
//! );
//! let zero = B::vec3(0.0, 0.0, 0.0);
//! let at_rest = VehicleState { x: zero, v: zero, r: So3Mat::<B>::identity(), omega: zero };
//! let integrals = [0.0; 6]; // [e_I, e_i], the paper's layout
//! let mut rates = [0.0; 6];
//! let out = law.command(0.0, &at_rest, &integrals, &mut rates)?;
//! assert!(out.thrust > 0.755 * 9.81, "climbs: thrust {}", out.thrust);
//! assert_eq!(law.integrals().count, 6);
//! assert!(rates.iter().any(|r| *r != 0.0), "e_i grows while x is off target");
//! # Ok::<(), controllers::ControlError>(())
//! ```

#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]

mod attitude_pid;
pub mod gain_check;
mod lanes;
mod mode;
mod mode_scheduler;
pub mod paper;
mod phases;
mod position_pid;

pub use attitude_pid::{
    AttitudeGains, AttitudeOutput, AttitudeReference, attitude_control, attitude_law,
};
pub use gain_check::{GainBounds, GainCondition, GainReport, check_gains};
pub use mode::{
    AttitudeMode, AttitudeSource, AttitudeThrust, Breakpoint, HoldAttitude, HoldPosition,
    IntegralLayout, MAX_ROTORS, Mode, ModeOutput, PositionMode, PositionSource, RotorSpeeds,
    load_token,
};
pub use mode_scheduler::{NoCondition, Phase, Scheduler, Segment, Switch, Until};
pub use phases::{FlightPhase, MotorsOff, Vertical, VerticalReference};
pub use position_pid::{
    AccelerationModel, Degeneracy, Mask, PositionGains, PositionInput, PositionOutput,
    PositionReference, SatBranch, VehicleState, position_control, position_law,
    thrust_pd_projection,
};

use lie::{Backend, M3, Real, S};

/// Mass, inertia and gravity as the controller knows them.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RigidBodyParams<B: lie::SimdBackend> {
    /// Mass `m` (kg).
    pub mass: S<B>,
    /// Inertia `J` in the body frame (kg m²).
    pub inertia: M3<B>,
    /// Gravitational acceleration `g` (m/s²), acting along `+e3`.
    pub gravity: S<B>,
}

impl<B: Backend> RigidBodyParams<B> {
    /// A body whose principal axes are its body axes: mass `m` (kg),
    /// `J = diag(j1, j2, j3)` (kg m²), gravity `g` (m/s², along `+e3`).
    /// The paper's example is
    /// `diagonal(dynamics::paper::MASS, dynamics::paper::INERTIA, dynamics::paper::GRAVITY)`:
    /// the vehicle's numbers are the plant's, kept in `dynamics`.
    pub fn diagonal(mass: f64, inertia: [f64; 3], gravity: f64) -> Self {
        let s = S::<B>::lit;
        let z = s(0.0);
        let [j1, j2, j3] = inertia;
        Self {
            mass: s(mass),
            inertia: B::mat3_from_cols(
                B::vec3(s(j1), z, z),
                B::vec3(z, s(j2), z),
                B::vec3(z, z, s(j3)),
            ),
            gravity: s(gravity),
        }
    }
}

/// Errors of the control laws: bad input is reported, never turned into a
/// NaN moment.
#[derive(Copy, Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum ControlError {
    /// An input field contained NaN or ±∞.
    NonFinite {
        /// The field, e.g. `"state.omega"`.
        field: &'static str,
    },
    /// A field of the reference (the desired trajectory or attitude) was
    /// NaN or ±∞: the reference's fault, not the state's.
    NonFiniteReference {
        /// The field, e.g. `"reference.jerk"`.
        field: &'static str,
    },
    /// A [`Scheduler`] was given an empty plan.
    EmptyPlan,
    /// A mode commanded rotor speeds ([`ModeOutput::rotor_speeds`]) to a vehicle
    /// that cannot take them (its actuators are not rotors with speeds).
    RotorSpeedsUnsupported {
        /// The mode's name.
        mode: &'static str,
    },
    /// A mode commanded a number of rotor speeds other than the vehicle's
    /// rotor count.
    RotorSpeedCount {
        /// The mode's name.
        mode: &'static str,
        /// How many speeds it gave.
        given: usize,
        /// How many rotors the vehicle has.
        rotors: usize,
    },
}

impl core::fmt::Display for ControlError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            ControlError::NonFinite { field } => {
                write!(f, "controller input `{field}` is not finite")
            }
            ControlError::NonFiniteReference { field } => {
                write!(f, "controller input `{field}` is not finite")
            }
            ControlError::EmptyPlan => write!(f, "the flight-mode plan has no segments"),
            ControlError::RotorSpeedsUnsupported { mode } => write!(
                f,
                "mode `{mode}` commands rotor speeds, which this vehicle cannot take \
                 (the `multirotor` kind can)"
            ),
            ControlError::RotorSpeedCount {
                mode,
                given,
                rotors,
            } => write!(
                f,
                "mode `{mode}` commands {given} rotor speeds to a vehicle with {rotors} rotors"
            ),
        }
    }
}

impl core::error::Error for ControlError {}
