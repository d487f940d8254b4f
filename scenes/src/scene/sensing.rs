//! The scene's `[sensors]` and `[estimator]` tables and the `seed` key.

use serde::{Deserialize, Serialize};

use super::sensor_tables::{BaroTable, GpsTable, ImuTable, MocapTable, key_of};

/// `[sensors]`: the sensors the vehicle carries, from a named suite, each
/// adjusted by a table of its own (`[sensors.imu]`, `[sensors.mocap]`,
/// `[sensors.gps]`, `[sensors.baro]`).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorsSpec {
    /// The suite: `rotorpy`, `crazyflie`, `mpu9250` or `fdcl-gazebo`
    /// (`sensors::SensorSuite::preset` says what each holds); empty: only
    /// the sensors the tables give.
    #[serde(default, skip_serializing_if = "String::is_empty")]
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
    /// The IMU's settings over the preset's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub imu: Option<ImuTable>,
    /// The motion capture's settings over the preset's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mocap: Option<MocapTable>,
    /// The GPS's settings over the preset's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gps: Option<GpsTable>,
    /// The barometer's settings over the preset's.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub baro: Option<BaroTable>,
}

fn one() -> f64 {
    1.0
}

impl Default for SensorsSpec {
    /// No preset, no tables, noise scale 1.
    fn default() -> Self {
        Self {
            preset: String::new(),
            noise_scale: 1.0,
            mocap_latency: None,
            mocap_rate: None,
            imu: None,
            mocap: None,
            gps: None,
            baro: None,
        }
    }
}

impl SensorsSpec {
    /// The suite `preset` as it is.
    pub fn preset(preset: &str) -> Self {
        Self {
            preset: preset.into(),
            ..Self::default()
        }
    }
}

/// `[estimator]`: what the flight modes read in place of the true state.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EstimatorSpec {
    /// `none` (the truth), `mocap` (the latest motion-capture frame),
    /// `iekf` (the invariant EKF on SE₂(3)) or `complementary` (the
    /// passive complementary filter on SO(3)).
    pub kind: EstimatorKind,
    /// For `mocap`: the body rates from the IMU's gyroscope instead of the
    /// tracker.
    #[serde(default)]
    pub gyro_rates: bool,
    /// For `iekf` and `complementary`: the initial estimate's attitude
    /// error, a rotation vector in rad (`R̂₀ = R₀ Exp(error)`); the flight
    /// computer is told the rest of the initial state exactly.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attitude_error: Option<[f64; 3]>,
    /// For `iekf`: the initial attitude σ, rad (by default 0.1, or the
    /// size of `attitude_error` if larger).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub attitude_sigma: Option<f64>,
    /// For `complementary`: the attitude gain `k_P`, 1/s (2 by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_p: Option<f64>,
    /// For `complementary`: the gyro-bias gain `k_I`, 1/s² (0.2 by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub k_i: Option<f64>,
    /// For `iekf`: `true` (the default) applies a late measurement at the
    /// instant it describes and replays the later ones; `false` applies
    /// it when it arrives.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compensate_delay: Option<bool>,
    /// For `iekf`: a factor on the process noise it assumes (every
    /// density's square; 1 by default): above 1 it trusts the IMU less.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub q_scale: Option<f64>,
    /// For `iekf`: a factor on every measurement variance it assumes (1 by
    /// default): above 1 it trusts the motion capture and GPS less.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub r_scale: Option<f64>,
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
    /// The right-invariant EKF on SE₂(3) with IMU biases.
    Iekf,
    /// The passive complementary filter on SO(3), position from the mocap.
    Complementary,
    /// The FDCL lab's EKF: IMU with its attitude output, and GPS.
    FdclEkf,
}

impl EstimatorKind {
    /// Every kind's name.
    pub const NAMES: [&'static str; 5] = ["none", "mocap", "iekf", "complementary", "fdcl-ekf"];

    /// Its name in a scene file and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            EstimatorKind::None => "none",
            EstimatorKind::Mocap => "mocap",
            EstimatorKind::Iekf => "iekf",
            EstimatorKind::Complementary => "complementary",
            EstimatorKind::FdclEkf => "fdcl-ekf",
        }
    }

    /// The sensors it cannot fly without: `(imu, mocap, mocap or gps,
    /// gps)`.
    fn needs(self, gyro_rates: bool) -> (bool, bool, bool, bool) {
        match self {
            EstimatorKind::None => (false, false, false, false),
            EstimatorKind::Mocap => (gyro_rates, true, false, false),
            EstimatorKind::Iekf => (true, false, true, false),
            EstimatorKind::Complementary => (true, true, false, false),
            EstimatorKind::FdclEkf => (true, false, false, true),
        }
    }
}

impl std::str::FromStr for EstimatorKind {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s {
            "none" => Ok(EstimatorKind::None),
            "mocap" => Ok(EstimatorKind::Mocap),
            "iekf" => Ok(EstimatorKind::Iekf),
            "complementary" => Ok(EstimatorKind::Complementary),
            "fdcl-ekf" => Ok(EstimatorKind::FdclEkf),
            _ => Err(format!(
                "estimator \"{s}\": expected one of {}",
                EstimatorKind::NAMES.join(", ")
            )),
        }
    }
}

impl SensorsSpec {
    /// The suite it names, its sensors adjusted by their tables, then
    /// scaled by `noise_scale` (the tables' noises too) and given the
    /// motion capture's `mocap_latency` and `mocap_rate`; an error naming
    /// the key and the value otherwise.
    pub fn suite(&self) -> Result<sensors::SensorSuite, (&'static str, String)> {
        let mut suite = if self.preset.is_empty() {
            if [
                self.imu.is_some(),
                self.mocap.is_some(),
                self.gps.is_some(),
                self.baro.is_some(),
            ]
            .iter()
            .all(|x| !x)
            {
                return Err((
                    "sensors.preset",
                    "`[sensors]` names no sensor: give a `preset` or a sensor table \
                     (`[sensors.imu]`, `[sensors.mocap]`, `[sensors.gps]`, `[sensors.baro]`)"
                        .into(),
                ));
            }
            sensors::SensorSuite {
                imu: None,
                mocap: None,
                gps: None,
                baro: None,
            }
        } else {
            sensors::SensorSuite::preset(&self.preset).ok_or_else(|| {
                (
                    "sensors.preset",
                    format!(
                        "sensors `preset` = \"{}\": expected one of {}",
                        self.preset,
                        sensors::SensorSuite::PRESETS.join(", ")
                    ),
                )
            })?
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
        if let Some(t) = &self.imu {
            suite.imu = Some(t.apply(suite.imu));
        }
        if let Some(t) = &self.mocap {
            suite.mocap = Some(t.apply(suite.mocap));
        }
        if let Some(t) = &self.gps {
            suite.gps = Some(t.apply(suite.gps));
        }
        if let Some(t) = &self.baro {
            suite.baro = Some(t.apply(suite.baro));
        }
        let mut suite = suite.noise_scaled(self.noise_scale);
        self.mocap_overrides(&mut suite)?;
        self.check(&suite)?;
        Ok(suite)
    }

    /// `mocap_latency` and `mocap_rate` on the suite's motion capture
    /// (not both one of them and its key in `[sensors.mocap]`).
    fn mocap_overrides(
        &self,
        suite: &mut sensors::SensorSuite,
    ) -> Result<(), (&'static str, String)> {
        let table = self.mocap.clone().unwrap_or_default();
        for (key, given, in_table) in [
            ("sensors.mocap_latency", self.mocap_latency, table.latency),
            ("sensors.mocap_rate", self.mocap_rate, table.rate),
        ] {
            if given.is_some() && in_table.is_some() {
                return Err((
                    key,
                    format!("`{key}` and its key in `[sensors.mocap]` both given: give one"),
                ));
            }
        }
        if self.mocap_latency.is_none() && self.mocap_rate.is_none() {
            return Ok(());
        }
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
        Ok(())
    }

    /// The motion capture's latency and the GPS's delay shorter than the
    /// run (else nothing would arrive), reported at the key that set them.
    fn arrives_within(
        &self,
        suite: &sensors::SensorSuite,
        duration: f64,
    ) -> Result<(), (&'static str, String)> {
        let mocap_key = if self.mocap_latency.is_some() {
            "sensors.mocap_latency"
        } else if self.mocap.as_ref().is_some_and(|m| m.latency.is_some()) {
            "sensors.mocap.latency"
        } else {
            "sensors.preset"
        };
        let gps_key = if self.gps.as_ref().is_some_and(|g| g.delay.is_some()) {
            "sensors.gps.delay"
        } else {
            "sensors.preset"
        };
        let late = [
            (mocap_key, suite.mocap.map(|m| m.latency)),
            (gps_key, suite.gps.map(|g| g.delay)),
        ];
        for (key, wait) in late {
            if let Some(w) = wait.filter(|w| *w >= duration) {
                return Err((
                    key,
                    format!(
                        "{key}: a wait of {w} s is not shorter than the run ({duration} s): \
                         nothing would arrive"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Each sensor's settings in range, a fault reported at its scene key.
    fn check(&self, suite: &sensors::SensorSuite) -> Result<(), (&'static str, String)> {
        let named = |sensor: &str, e: sensors::SensorError| {
            let key = match &e {
                sensors::SensorError::Setting {
                    field: "mocap.latency",
                    ..
                } if self.mocap_latency.is_some() => "sensors.mocap_latency",
                sensors::SensorError::Setting {
                    field: "mocap.rate",
                    ..
                } if self.mocap_rate.is_some() => "sensors.mocap_rate",
                sensors::SensorError::Setting { field, .. } => key_of(sensor, field),
                _ => "sensors",
            };
            (key, format!("{key}: {e}"))
        };
        if let Some(s) = &suite.imu {
            s.validate().map_err(|e| named("imu", e))?;
        }
        if let Some(s) = &suite.mocap {
            s.validate().map_err(|e| named("", e))?;
        }
        if let Some(s) = &suite.gps {
            s.validate().map_err(|e| named("", e))?;
        }
        if let Some(s) = &suite.baro {
            s.validate().map_err(|e| named("", e))?;
        }
        Ok(())
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
        if let (Some(spec), Some(suite)) = (&self.sensors, &suite) {
            spec.arrives_within(suite, self.duration)?;
        }
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
        let (imu, mocap, fix, gps) = e.kind.needs(e.gyro_rates);
        let attitude = suite
            .and_then(|s| s.imu)
            .is_some_and(|i| i.attitude_sigma.is_some());
        let missing = if mocap && !have.mocap {
            Some("motion capture")
        } else if fix && !(have.mocap || have.gps) {
            Some("motion capture or a GPS")
        } else if gps && !have.gps {
            Some("a GPS")
        } else if imu && !have.imu {
            Some("an IMU")
        } else if e.kind == EstimatorKind::FdclEkf && !attitude {
            Some("an IMU with an attitude output (`sensors.imu.attitude_sigma`)")
        } else {
            None
        };
        if let Some(what) = missing {
            return Err((
                "estimator.kind",
                format!(
                    "estimator `kind` = \"{}\"{} needs {what}: give `[sensors]` a preset with it (rotorpy, crazyflie, fdcl-gazebo) or its table",
                    e.kind.name(),
                    if e.gyro_rates {
                        " with `gyro_rates`"
                    } else {
                        ""
                    },
                ),
            ));
        }
        e.check_keys()?;
        Ok(())
    }
}

impl EstimatorSpec {
    /// The complementary filter's settings from `k_p` and `k_i` (the
    /// defaults where absent) with the IMU's `mounting`, checked; a fault
    /// at the key that set it.
    pub fn complementary_config(
        &self,
        mounting: Option<[[f64; 3]; 3]>,
    ) -> Result<sensors::ComplementaryConfig, (&'static str, String)> {
        let d = sensors::ComplementaryConfig::default();
        let cfg = sensors::ComplementaryConfig {
            k_p: self.k_p.unwrap_or(d.k_p),
            k_i: self.k_i.unwrap_or(d.k_i),
            mounting: mounting.unwrap_or(d.mounting),
            ..d
        };
        cfg.validate().map_err(|e| {
            let key = match &e {
                sensors::SensorError::Setting { field, .. } if field.ends_with("k_i") => {
                    "estimator.k_i"
                }
                _ => "estimator.k_p",
            };
            (key, format!("{key}: {e}"))
        })?;
        Ok(cfg)
    }

    /// Each filter's keys given only to the kind they belong to, and in
    /// range.
    fn check_keys(&self) -> Result<(), (&'static str, String)> {
        use EstimatorKind::*;
        let kind = self.kind;
        let given: [(&'static str, bool, bool); 8] = [
            ("estimator.gyro_rates", self.gyro_rates, kind == Mocap),
            (
                "estimator.attitude_error",
                self.attitude_error.is_some(),
                matches!(kind, Iekf | Complementary),
            ),
            (
                "estimator.attitude_sigma",
                self.attitude_sigma.is_some(),
                kind == Iekf,
            ),
            ("estimator.k_p", self.k_p.is_some(), kind == Complementary),
            ("estimator.k_i", self.k_i.is_some(), kind == Complementary),
            (
                "estimator.compensate_delay",
                self.compensate_delay.is_some(),
                kind == Iekf,
            ),
            ("estimator.q_scale", self.q_scale.is_some(), kind == Iekf),
            ("estimator.r_scale", self.r_scale.is_some(), kind == Iekf),
        ];
        if let Some((key, ..)) = given.iter().find(|(_, g, fits)| *g && !fits) {
            return Err((
                key,
                format!(
                    "`{key}` does not apply to estimator `kind` = \"{}\"",
                    kind.name()
                ),
            ));
        }
        if let Some(a) = self.attitude_error
            && let Some(bad) = a.iter().find(|x| !x.is_finite())
        {
            return Err((
                "estimator.attitude_error",
                format!("`estimator.attitude_error` has {bad}: must be finite (rad)"),
            ));
        }
        if kind == Complementary {
            self.complementary_config(Option::None)?;
        }
        for (key, v, unit) in [
            ("estimator.attitude_sigma", self.attitude_sigma, " (rad)"),
            ("estimator.q_scale", self.q_scale, ""),
            ("estimator.r_scale", self.r_scale, ""),
        ] {
            if let Some(s) = v
                && !(s.is_finite() && s > 0.0)
            {
                return Err((
                    key,
                    format!("`{key}` = {s}: must be positive and finite{unit}"),
                ));
            }
        }
        Ok(())
    }
}
