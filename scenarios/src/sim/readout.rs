//! What the sensors measured and what the estimator made of it, in `f64`:
//! beside the truth in each [`Sample`](super::Sample), every measurement in
//! [`RunOutput::measurements`](super::RunOutput::measurements).

use lie::Backend;
use sensors::{GpsSample, ImuSample, MocapSample, NavState};

/// A navigation state in `f64` (world frame, `e3` down; rates in the body
/// frame).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct NavSample {
    /// Position, m.
    pub x: [f64; 3],
    /// Velocity, m/s.
    pub v: [f64; 3],
    /// Attitude, rows.
    pub r: [[f64; 3]; 3],
    /// Body rates, rad/s.
    pub omega: [f64; 3],
}

impl NavSample {
    /// `s` in `f64`.
    pub fn of<B: Backend>(s: &NavState<B>) -> Self {
        Self {
            x: lie::ops::vec3_f64::<B>(s.x),
            v: lie::ops::vec3_f64::<B>(s.v),
            r: lie::ops::mat3_f64::<B>(s.r),
            omega: lie::ops::vec3_f64::<B>(s.omega),
        }
    }
}

/// The latest of each measurement and the estimate the flight mode last
/// read, at a record sample (`None` for what the run has not got).
#[derive(Clone, Debug, Default, PartialEq)]
#[non_exhaustive]
pub struct Readout {
    /// The estimate of the last control instant.
    pub estimate: Option<NavSample>,
    /// The estimator's standard deviations and last NIS then, for a filter
    /// that keeps them.
    pub diagnostics: Option<sensors::Diagnostics>,
    /// The latest specific force, sensor axes, m/s².
    pub accel: Option<[f64; 3]>,
    /// The latest angular rate, sensor axes, rad/s.
    pub gyro: Option<[f64; 3]>,
    /// The latest motion-capture position (taken, not necessarily arrived),
    /// m.
    pub mocap_x: Option<[f64; 3]>,
    /// The latest GPS position (taken), m.
    pub gps_x: Option<[f64; 3]>,
    /// The latest barometric height, m (up).
    pub baro: Option<f64>,
}

/// One measurement a sensor took, with the instant it describes and, for
/// the late ones, when it arrives.
#[derive(Copy, Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum MeasurementRecord {
    /// An IMU sample (sensor axes).
    Imu {
        /// Its time, s.
        t: f64,
        /// Specific force, m/s².
        accel: [f64; 3],
        /// Angular rate, rad/s.
        gyro: [f64; 3],
        /// The attitude output (sensor axes to world), for an IMU with one.
        attitude: Option<[[f64; 3]; 3]>,
    },
    /// A motion-capture frame.
    Mocap {
        /// Capture time, s.
        t: f64,
        /// Arrival time, s.
        arrival: f64,
        /// What it reports.
        state: NavSample,
    },
    /// A GPS fix.
    Gps {
        /// The instant it describes, s.
        t: f64,
        /// Arrival time, s.
        arrival: f64,
        /// Position, m.
        x: [f64; 3],
        /// Velocity, m/s.
        v: [f64; 3],
    },
    /// A barometer sample.
    Baro {
        /// Its time, s.
        t: f64,
        /// Height, m (up).
        height: f64,
    },
}

impl MeasurementRecord {
    pub(crate) fn imu<B: Backend>(m: &ImuSample<B>) -> Self {
        Self::Imu {
            t: m.t,
            accel: lie::ops::vec3_f64::<B>(m.accel),
            gyro: lie::ops::vec3_f64::<B>(m.gyro),
            attitude: m.attitude.map(lie::ops::mat3_f64::<B>),
        }
    }

    pub(crate) fn mocap<B: Backend>(m: &MocapSample<B>, arrival: f64) -> Self {
        Self::Mocap {
            t: m.t,
            arrival,
            state: NavSample::of::<B>(&NavState {
                x: m.x,
                v: m.v,
                r: m.r,
                omega: m.omega,
            }),
        }
    }

    pub(crate) fn gps<B: Backend>(m: &GpsSample<B>, arrival: f64) -> Self {
        Self::Gps {
            t: m.t,
            arrival,
            x: lie::ops::vec3_f64::<B>(m.x),
            v: lie::ops::vec3_f64::<B>(m.v),
        }
    }

    /// The instant it describes, s.
    pub fn t(&self) -> f64 {
        match *self {
            Self::Imu { t, .. } | Self::Mocap { t, .. } | Self::Gps { t, .. } => t,
            Self::Baro { t, .. } => t,
        }
    }

    /// The sensor's name: `imu`, `mocap`, `gps` or `baro`.
    pub fn sensor(&self) -> &'static str {
        match self {
            Self::Imu { .. } => "imu",
            Self::Mocap { .. } => "mocap",
            Self::Gps { .. } => "gps",
            Self::Baro { .. } => "baro",
        }
    }
}
