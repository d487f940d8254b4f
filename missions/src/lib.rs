//! Missions a user plans: minimum-snap trajectories through waypoints and
//! the Crazyflie's piecewise-polynomial trajectory files, each a
//! [`Trajectory`] that a position mode flies as its reference (a
//! [`controllers::PositionSource`] to the fourth derivative, with the
//! heading from a yaw trajectory and its two derivatives).
//!
//! Frames are the workspace's: e₃ points down, and the yaw turns about
//! e₃. A Crazyflie file is z-up; [`pptraj`] converts on the way in and
//! out.

mod error;
mod minsnap;
mod poly;
pub mod pptraj;
mod trajectory;

pub use error::MissionError;
pub use minsnap::{MinSnap, Timing};
pub use poly::{COEFFS, Piece};
pub use trajectory::{Flat, Trajectory};
