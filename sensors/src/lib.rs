//! Sensor models: what a flight computer reads instead of the true state.
//!
//! An [`Imu`] reads, at its own sample instants, the specific force and the
//! body rates at the point where it is mounted, with the errors of a real
//! part: white noise given as a density, a bias random walk, a turn-on
//! bias, scale factors and axis misalignment, and range saturation
//! ([`TriadErrors`]). Presets give the numbers of the parts and simulators
//! users compare with ([`ImuSpec::rotorpy`], [`ImuSpec::crazyflie`],
//! [`ImuSpec::mpu9250`], [`ImuSpec::fdcl_gazebo`]).
//!
//! # Frames and signs
//! As everywhere in geopid, `e3` points **down**: gravity is `+g e3` in the
//! world frame and thrust acts along `−b3`. The accelerometer reads the
//! specific force, acceleration minus gravity, so a level IMU at rest
//! reads `−g` along `b3` (the ground pushes it up):
//!
//! `f_S = R_BSᵀ (Rᵀ(a − g e3) + α × p + Ω × (Ω × p))`, `ω_S = R_BSᵀ Ω`,
//!
//! for a sensor at body position `p` with axes `R_BS` (its columns are the
//! sensor's axes in the body frame), `R` the attitude, `a` the world
//! acceleration of the centre of mass, `Ω` and `α = Ω̇` the body rates and
//! their derivative, all at the sample instant.
//!
//! # Noise that never surprises
//! Every random number is a function of `(seed, sensor, sample index,
//! channel)` ([`NoiseKey`], through [`lie::noise`]): the same seed gives the
//! same noise whatever the integrator, the step, the recording, the thread
//! or which other sensors are on. The measurements themselves move with
//! the true trajectory they are taken on; the noise added to them does not.
//!
//! ```
//! use lie::{Backend, NalgebraF64 as B};
//! use sensors::{Imu, ImuSpec, Kinematics, NoiseKey};
//!
//! // A level Crazyflie IMU at rest, noise off: −g along b3, no rates.
//! let spec = ImuSpec::crazyflie().noiseless();
//! let mut imu = Imu::<B>::new(spec, NoiseKey::new(1, 0))?;
//! let s = imu.sample(0, &Kinematics::<B>::at_rest(), 9.81)?;
//! assert_eq!(B::vec3_to_array(s.accel), [0.0, 0.0, -9.81]);
//! assert_eq!(B::vec3_to_array(s.gyro), [0.0; 3]);
//! # Ok::<(), sensors::SensorError>(())
//! ```
//!
//! # Estimators
//! What a flight mode reads in place of the truth, each an [`Estimator`]:
//! [`MocapEstimator`] (the latest frame), [`Complementary`] (the passive
//! complementary filter on SO(3) with gyro bias), [`Iekf`] (a right-invariant
//! EKF on SE₂(3) with IMU biases), [`FdclEkf`] (the FDCL lab's EKF), and, on
//! the host, [`Delayed`] around any of them (late measurements applied at
//! their capture time).
//!
//! `#![no_std]` without the `std` feature (use `libm`); no heap.

#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]

mod complementary;
#[cfg(feature = "std")]
mod delayed;
mod error;
mod estimator;
mod fdcl_ekf;
mod gps;
mod iekf;
mod imu;
pub mod kalman;
mod mocap;
mod noise;
mod presets;

pub use complementary::{Complementary, ComplementaryConfig};
#[cfg(feature = "std")]
pub use delayed::Delayed;
pub use error::SensorError;
pub use estimator::{Diagnostics, Estimator, Measurement, MocapEstimator, NavState, SensorSet};
pub use fdcl_ekf::{FDCL_DIM, FdclConfig, FdclEkf, fdcl_expm};
pub use gps::{Baro, BaroSample, BaroSpec, Gps, GpsSample, GpsSpec};
pub use iekf::{IEKF_DIM, Iekf, IekfConfig, InitialSigma, Rejections, gamma2};
pub use imu::{Imu, ImuSample, ImuSpec, Kinematics, TriadErrors};
pub use mocap::{Mocap, MocapSample, MocapSpec, Spike};
pub use noise::NoiseKey;
pub use presets::SensorSuite;
