//! Geometric PID control of multirotors on SO(3) and SE(3), in one crate.
//!
//! This crate owns nothing of its own but [the user's guide](guide): it
//! re-exports the workspace's crates under their short names, so that one
//! dependency brings the Lie-group maths ([`lie`]), the vehicles
//! ([`dynamics`]), the controllers of Goodarzi, Lee & Lee
//! ([`controllers`]), the steppers ([`integrators`]) and the simulation
//! with its scenes ([`scenarios`]). A program that needs less (a flight
//! stack with the controllers alone) depends on that crate directly and
//! compiles nothing else.
//!
//! ```
//! use geopid::scenarios;
//!
//! let scene = scenarios::load("paper-flip")?;
//! let out = scenarios::run(&scene, Default::default())?;
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
pub use scenarios;

pub mod guide;

/// The README's Rust blocks, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
pub struct ReadmeDoctests;
