//! `[sensors.imu]`, `[sensors.mocap]`, `[sensors.gps]`, `[sensors.baro]`:
//! one sensor's settings over the preset's. A key left out keeps the
//! preset's value; a table for a sensor the preset lacks starts from that
//! sensor without errors (an IMU at 1 kHz at the centre of mass, motion
//! capture at 100 Hz, GPS at 10 Hz, a barometer at 50 Hz, no latency).

use sensors::{BaroSpec, GpsSpec, ImuSpec, MocapSpec, Spike, TriadErrors};
use serde::{Deserialize, Serialize};

/// Sets `*field` to `value` when the table gives one.
fn set<T: Copy>(field: &mut T, value: Option<T>) {
    if let Some(v) = value {
        *field = v;
    }
}

/// One triad's errors (`[sensors.imu.accel]`, `[sensors.imu.gyro]`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TriadTable {
    /// White-noise density, units/√Hz (per-sample σ = density·√rate).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise_density: Option<f64>,
    /// Bias random walk, units/√s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub random_walk: Option<f64>,
    /// Turn-on bias σ per axis, units.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn_on_bias: Option<f64>,
    /// Scale-factor and misalignment errors by rows (the reading is
    /// `(I + this)·true`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub scale_misalignment: Option<[[f64; 3]; 3]>,
    /// The largest magnitude an axis reads, units (`inf`: none).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<f64>,
}

impl TriadTable {
    fn apply(&self, e: &mut TriadErrors) {
        set(&mut e.noise_density, self.noise_density);
        set(&mut e.random_walk, self.random_walk);
        set(&mut e.turn_on_bias, self.turn_on_bias);
        set(&mut e.scale_misalignment, self.scale_misalignment);
        set(&mut e.range, self.range);
    }
}

/// `[sensors.imu]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ImuTable {
    /// Sample rate, Hz.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate: Option<f64>,
    /// Position in the body frame, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position: Option<[f64; 3]>,
    /// `R_BS` by rows (a rotation).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mounting: Option<[[f64; 3]; 3]>,
    /// The accelerometer, m/s².
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accel: Option<TriadTable>,
    /// The gyroscope, rad/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gyro: Option<TriadTable>,
    /// An attitude output (an AHRS) with this σ per axis, rad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attitude_sigma: Option<f64>,
}

impl ImuTable {
    /// `base` (or an error-free 1 kHz IMU at the centre of mass) with this
    /// table's values.
    pub fn apply(&self, base: Option<ImuSpec>) -> ImuSpec {
        let mut s = base.unwrap_or(ImuSpec {
            rate: 1000.0,
            position: [0.0; 3],
            mounting: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            accel: TriadErrors::NONE,
            gyro: TriadErrors::NONE,
            attitude_sigma: None,
        });
        if self.attitude_sigma.is_some() {
            s.attitude_sigma = self.attitude_sigma;
        }
        set(&mut s.rate, self.rate);
        set(&mut s.position, self.position);
        set(&mut s.mounting, self.mounting);
        if let Some(t) = &self.accel {
            t.apply(&mut s.accel);
        }
        if let Some(t) = &self.gyro {
            t.apply(&mut s.gyro);
        }
        s
    }
}

/// A spike's probability per sample and largest size.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpikeTable {
    /// Probability per sample, in [0, 1].
    pub probability: f64,
    /// The largest spike, units.
    pub max: f64,
}

/// `[sensors.mocap]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MocapTable {
    /// Frame rate, Hz.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate: Option<f64>,
    /// Transport latency, s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub latency: Option<f64>,
    /// Position σ per axis per frame, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub position_sigma: Option<f64>,
    /// Velocity σ per axis per frame, m/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity_sigma: Option<f64>,
    /// Attitude σ per axis of the right perturbation `R Exp(η)`, rad.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attitude_sigma: Option<f64>,
    /// Body-rate σ per axis per frame, rad/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate_sigma: Option<f64>,
    /// Probability that a frame is lost, in [0, 1).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dropout: Option<f64>,
    /// Velocity spikes (RotorPy's), m/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity_spike: Option<SpikeTable>,
    /// Body-rate spikes (RotorPy's), rad/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate_spike: Option<SpikeTable>,
}

impl MocapTable {
    /// `base` (or noiseless 100 Hz motion capture without latency) with
    /// this table's values.
    pub fn apply(&self, base: Option<MocapSpec>) -> MocapSpec {
        let mut s = base.unwrap_or(MocapSpec::perfect(100.0));
        set(&mut s.rate, self.rate);
        set(&mut s.latency, self.latency);
        set(&mut s.position_sigma, self.position_sigma);
        set(&mut s.velocity_sigma, self.velocity_sigma);
        set(&mut s.attitude_sigma, self.attitude_sigma);
        set(&mut s.rate_sigma, self.rate_sigma);
        set(&mut s.dropout, self.dropout);
        let spike = |t: &SpikeTable| Spike {
            probability: t.probability,
            max: t.max,
        };
        set(
            &mut s.velocity_spike,
            self.velocity_spike.as_ref().map(spike),
        );
        set(&mut s.rate_spike, self.rate_spike.as_ref().map(spike));
        s
    }
}

/// `[sensors.gps]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GpsTable {
    /// Fix rate, Hz.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate: Option<f64>,
    /// Delay from capture to arrival, s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub delay: Option<f64>,
    /// Horizontal position σ per axis, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub horizontal_sigma: Option<f64>,
    /// Vertical position σ, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub vertical_sigma: Option<f64>,
    /// Velocity σ per axis, m/s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub velocity_sigma: Option<f64>,
}

impl GpsTable {
    /// `base` (or a noiseless 10 Hz GPS without delay) with this table's
    /// values.
    pub fn apply(&self, base: Option<GpsSpec>) -> GpsSpec {
        let mut s = base.unwrap_or(GpsSpec {
            rate: 10.0,
            delay: 0.0,
            horizontal_sigma: 0.0,
            vertical_sigma: 0.0,
            velocity_sigma: 0.0,
        });
        set(&mut s.rate, self.rate);
        set(&mut s.delay, self.delay);
        set(&mut s.horizontal_sigma, self.horizontal_sigma);
        set(&mut s.vertical_sigma, self.vertical_sigma);
        set(&mut s.velocity_sigma, self.velocity_sigma);
        s
    }
}

/// `[sensors.baro]`.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BaroTable {
    /// Sample rate, Hz.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rate: Option<f64>,
    /// White-noise σ per sample, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sigma: Option<f64>,
    /// Bias random walk, m/√s.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub random_walk: Option<f64>,
    /// Turn-on bias σ, m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub turn_on_bias: Option<f64>,
}

impl BaroTable {
    /// `base` (or a noiseless 50 Hz barometer) with this table's values.
    pub fn apply(&self, base: Option<BaroSpec>) -> BaroSpec {
        let mut s = base.unwrap_or(BaroSpec::white(50.0, 0.0));
        set(&mut s.rate, self.rate);
        set(&mut s.sigma, self.sigma);
        set(&mut s.random_walk, self.random_walk);
        set(&mut s.turn_on_bias, self.turn_on_bias);
        s
    }
}

/// Every key a sensor check can fault, as the scene names it.
const KEYS: [&str; 34] = [
    "sensors.imu.rate",
    "sensors.imu.attitude_sigma",
    "sensors.imu.position",
    "sensors.imu.mounting",
    "sensors.imu.accel.noise_density",
    "sensors.imu.accel.random_walk",
    "sensors.imu.accel.turn_on_bias",
    "sensors.imu.accel.scale_misalignment",
    "sensors.imu.accel.range",
    "sensors.imu.gyro.noise_density",
    "sensors.imu.gyro.random_walk",
    "sensors.imu.gyro.turn_on_bias",
    "sensors.imu.gyro.scale_misalignment",
    "sensors.imu.gyro.range",
    "sensors.mocap.rate",
    "sensors.mocap.latency",
    "sensors.mocap.position_sigma",
    "sensors.mocap.velocity_sigma",
    "sensors.mocap.attitude_sigma",
    "sensors.mocap.rate_sigma",
    "sensors.mocap.dropout",
    "sensors.mocap.velocity_spike.probability",
    "sensors.mocap.velocity_spike.max",
    "sensors.mocap.rate_spike.probability",
    "sensors.mocap.rate_spike.max",
    "sensors.gps.rate",
    "sensors.gps.delay",
    "sensors.gps.horizontal_sigma",
    "sensors.gps.vertical_sigma",
    "sensors.gps.velocity_sigma",
    "sensors.baro.rate",
    "sensors.baro.sigma",
    "sensors.baro.random_walk",
    "sensors.baro.turn_on_bias",
];

/// The scene key of a sensor's field (`sensor` is `imu`, whose checks name
/// fields without it, or empty for the others, whose checks name it).
pub(super) fn key_of(sensor: &str, field: &str) -> &'static str {
    let full = if sensor.is_empty() {
        format!("sensors.{field}")
    } else {
        format!("sensors.{sensor}.{field}")
    };
    KEYS.iter()
        .find(|k| **k == full)
        .copied()
        .unwrap_or("sensors")
}
