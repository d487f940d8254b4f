//! The scene's `[sensors]` and `[estimator]` tables and the `seed` key.

use serde::{Deserialize, Serialize};

/// `[sensors]`: the sensors the vehicle carries, from a named suite.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorsSpec {
    /// The suite: `rotorpy`, `crazyflie`, `mpu9250` or `fdcl-gazebo`
    /// (`sensors::SensorSuite::preset` says what each holds).
    pub preset: String,
    /// Every noise, bias, walk and spike of the suite times this (0: a
    /// noiseless suite; 1 by default).
    #[serde(default = "one")]
    pub noise_scale: f64,
    /// The motion capture's latency, s, in place of the preset's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mocap_latency: Option<f64>,
    /// The motion capture's rate, Hz, in place of the preset's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mocap_rate: Option<f64>,
}

fn one() -> f64 {
    1.0
}

/// `[estimator]`: what the flight modes read in place of the true state.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EstimatorSpec {
    /// `none` (the truth) or `mocap` (the latest motion-capture frame).
    pub kind: EstimatorKind,
    /// For `mocap`: the body rates from the IMU's gyroscope instead of the
    /// tracker.
    #[serde(default)]
    pub gyro_rates: bool,
}

/// An estimator by name.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EstimatorKind {
    /// The modes read the true state.
    #[default]
    None,
    /// The latest motion-capture frame.
    Mocap,
}

impl EstimatorKind {
    /// Its name in a scene file and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            EstimatorKind::None => "none",
            EstimatorKind::Mocap => "mocap",
        }
    }
}

impl std::str::FromStr for EstimatorKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "none" => Ok(EstimatorKind::None),
            "mocap" => Ok(EstimatorKind::Mocap),
            _ => Err(format!("estimator \"{s}\": expected none or mocap")),
        }
    }
}

impl SensorsSpec {
    /// The suite it names, scaled and overridden; an error naming the key
    /// and the value otherwise.
    pub fn suite(&self) -> Result<sensors::SensorSuite, (&'static str, String)> {
        let Some(suite) = sensors::SensorSuite::preset(&self.preset) else {
            return Err((
                "sensors.preset",
                format!(
                    "sensors `preset` = \"{}\": expected one of {}",
                    self.preset,
                    sensors::SensorSuite::PRESETS.join(", ")
                ),
            ));
        };
        if !(self.noise_scale.is_finite() && self.noise_scale >= 0.0) {
            return Err((
                "sensors.noise_scale",
                format!(
                    "sensors `noise_scale` = {}: must be finite and not negative",
                    self.noise_scale
                ),
            ));
        }
        let mut suite = suite.noise_scaled(self.noise_scale);
        if self.mocap_latency.is_some() || self.mocap_rate.is_some() {
            let Some(m) = suite.mocap.as_mut() else {
                return Err((
                    "sensors.mocap_latency",
                    format!("the preset `{}` has no motion capture to set", self.preset),
                ));
            };
            if let Some(l) = self.mocap_latency {
                m.latency = l;
            }
            if let Some(r) = self.mocap_rate {
                m.rate = r;
            }
        }
        suite.validate().map_err(|e| {
            // The two settings a scene gives itself are reported at their
            // own keys; the rest come from the preset.
            let key = match &e {
                sensors::SensorError::Setting {
                    field: "mocap.latency",
                    ..
                } => "sensors.mocap_latency",
                sensors::SensorError::Setting {
                    field: "mocap.rate",
                    ..
                } => "sensors.mocap_rate",
                _ => "sensors",
            };
            (key, format!("sensors: {e}"))
        })?;
        Ok(suite)
    }
}

impl super::Scene {
    /// `[sensors]` and `[estimator]`: a known suite with its settings in
    /// range, and an estimator with sampled control and the sensors it
    /// needs.
    pub(super) fn validate_sensing(&self) -> Result<(), (&'static str, String)> {
        let suite = match &self.sensors {
            Some(s) => Some(s.suite()?),
            None => None,
        };
        let Some(e) = &self.estimator else {
            return Ok(());
        };
        if e.kind == EstimatorKind::None {
            return Ok(());
        }
        if self
            .control
            .control()
            .is_ok_and(|c| c.command_rate().is_none())
        {
            return Err((
                "estimator.kind",
                format!(
                    "estimator `kind` = \"{}\" needs `control.timing = \"sampled\"`: the modes read the estimate at the control instants",
                    e.kind.name()
                ),
            ));
        }
        let have = suite.map(|s| s.set()).unwrap_or_default();
        if !have.mocap || (e.gyro_rates && !have.imu) {
            let what = if have.mocap {
                "an IMU"
            } else {
                "motion capture"
            };
            return Err((
                "estimator.kind",
                format!(
                    "estimator `kind` = \"{}\"{} needs {what}: give `[sensors]` a preset with it (rotorpy, crazyflie)",
                    e.kind.name(),
                    if e.gyro_rates {
                        " with `gyro_rates`"
                    } else {
                        ""
                    },
                ),
            ));
        }
        Ok(())
    }
}
