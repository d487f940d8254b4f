//! Geometric PID control of multirotors on SO(3) and SE(3), in one crate.
//!
//! This crate owns nothing of its own but [the user's guide](guide): it
//! re-exports the workspace's crates under their short names, so that one
//! dependency brings the Lie-group maths ([`lie`]), the vehicles
//! ([`dynamics`]), the controllers of Goodarzi, Lee & Lee
//! ([`controllers`]), the steppers ([`integrators`]), the simulation
//! engine ([`scenarios`]), the scene files and built-in scenes
//! ([`scenes`]), the CSV and MCAP logs ([`logs`]) and the studies
//! ([`studies`]); [`prelude`] holds the names most programs use. A program
//! that needs less (a flight stack with the controllers alone, a
//! simulation built in code without files) depends on that crate directly
//! and compiles nothing else.
//!
//! | crate | layer | what it adds |
//! |---|---|---|
//! | [`lie`] | maths | SO(3), SE(3), backends and scalars |
//! | [`dynamics`] | plant | the `Vehicle` trait, multirotors, wind |
//! | [`controllers`] | control | the geometric PID laws and the `Mode` trait |
//! | [`integrators`] | stepping | RK, Dormand–Prince and the Lie-group variational steppers |
//! | [`scenarios`] | engine | `Simulation`: plans, events, samples, the `Sink` trait |
//! | [`logs`] | output | CSV and MCAP sinks (Foxglove schemas) |
//! | [`scenes`] | front end | the scene format, the built-in scenes, vehicle kinds |
//! | [`studies`] | studies | Monte Carlo, regression, stress, gains, gradients, figures |
//!
//! ```
//! use geopid::prelude::*;
//!
//! let scene = scenes::load("paper-flip")?;
//! let out = scenes::run(&scene, RunOptions::default())?;
//! assert!(out.last.psi < 1e-2);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Start with the guide's [first flight](guide::first_flight).

#![deny(missing_docs)]

pub use controllers;
pub use dynamics;
pub use integrators;
pub use lie;
pub use logs;
pub use missions;
pub use scenarios;
pub use scenes;
pub use sensors;
pub use studies;

/// The names most programs use: the backends and rotations, the vehicles,
/// the flight modes, the simulation and the scene front end (as the
/// module [`scenes`], whose `load` and `run` read best qualified).
pub mod prelude {
    pub use controllers::{
        AttitudeGains, AttitudeMode, AttitudeThrust, HoldAttitude, HoldPosition, Mode, ModeOutput,
        PositionGains, PositionMode, RigidBodyParams,
    };
    pub use dynamics::{Multirotor, MultirotorParams, Quadrotor, RigidBodyState, Vehicle};
    pub use lie::{Backend, GlamF64, NalgebraF32, NalgebraF64, Rotation, So3Mat};
    pub use scenarios::{Control, RunOptions, RunOutput, Segment, SimError, Simulation, Until};
    pub use scenes::{self, Scene};
}

pub mod guide;

/// The README's Rust blocks, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
