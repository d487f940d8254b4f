//! GPS (position and velocity, late by a delay) and a barometer (height
//! with a drifting bias).

use lie::{Backend, Real, S, V3};

use crate::NoiseKey;
use crate::error::{SensorError, setting};

/// A GPS receiver: world position and velocity with white noise, each fix
/// delivered `delay` seconds after the instant it describes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GpsSpec {
    /// Fix rate, Hz: fix `k` describes `t = k / rate`.
    pub rate: f64,
    /// Delay, s: fix `k` arrives at `k / rate + delay`.
    pub delay: f64,
    /// Horizontal position σ per axis and fix (`e1`, `e2`), m.
    pub horizontal_sigma: f64,
    /// Vertical position σ per fix (`e3`), m.
    pub vertical_sigma: f64,
    /// Velocity σ per axis and fix, m/s.
    pub velocity_sigma: f64,
}

impl GpsSpec {
    /// The GPS of the FDCL lab's Gazebo simulator (`fdcl-gwu/uav_simulator`):
    /// 10 Hz, Gaussian noise of σ = 0.01 m on every position axis and
    /// 0.01 m/s on every velocity axis, no delay.
    pub const fn fdcl_gazebo() -> Self {
        Self {
            rate: 10.0,
            delay: 0.0,
            horizontal_sigma: 0.01,
            vertical_sigma: 0.01,
            velocity_sigma: 0.01,
        }
    }

    /// Every field in range: a positive finite rate, delay and σ finite and
    /// not negative.
    pub fn validate(&self) -> Result<(), SensorError> {
        if !(self.rate.is_finite() && self.rate > 0.0) {
            return Err(setting(
                "gps.rate",
                self.rate,
                "a positive finite rate in Hz",
            ));
        }
        for (field, v) in [
            ("gps.delay", self.delay),
            ("gps.horizontal_sigma", self.horizontal_sigma),
            ("gps.vertical_sigma", self.vertical_sigma),
            ("gps.velocity_sigma", self.velocity_sigma),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(setting(field, v, "finite and not negative"));
            }
        }
        Ok(())
    }
}

/// One GPS fix, world frame (`e3` down).
#[derive(Clone, Copy, Debug)]
pub struct GpsSample<B: Backend> {
    /// Its index.
    pub k: u64,
    /// The instant it describes, s.
    pub t: f64,
    /// Position, m.
    pub x: V3<B>,
    /// Velocity, m/s.
    pub v: V3<B>,
}

/// A GPS receiver in a run.
#[derive(Clone, Debug)]
pub struct Gps {
    spec: GpsSpec,
    key: NoiseKey,
}

impl Gps {
    /// The receiver of `spec` drawing its noise from `key`.
    pub fn new(spec: GpsSpec, key: NoiseKey) -> Result<Self, SensorError> {
        spec.validate()?;
        Ok(Self { spec, key })
    }

    /// The spec it was built with.
    pub fn spec(&self) -> &GpsSpec {
        &self.spec
    }

    /// The instant fix `k` describes, s.
    pub fn time_of(&self, k: u64) -> f64 {
        k as f64 / self.spec.rate
    }

    /// Fix `k` of the true position `x` and velocity `v`.
    pub fn fix<B: Backend>(&self, k: u64, x: V3<B>, v: V3<B>) -> GpsSample<B> {
        let s = &self.spec;
        let [a, b] = self.key.pair(k, 0);
        let [c, d] = self.key.pair(k, 1);
        let [e, f] = self.key.pair(k, 2);
        let l = S::<B>::lit;
        let (h, z, u) = (s.horizontal_sigma, s.vertical_sigma, s.velocity_sigma);
        let x = if h == 0.0 && z == 0.0 {
            x
        } else {
            x + B::vec3(l(h * a), l(h * b), l(z * c))
        };
        let v = if u == 0.0 {
            v
        } else {
            v + B::vec3(l(u * d), l(u * e), l(u * f))
        };
        GpsSample {
            k,
            t: self.time_of(k),
            x,
            v,
        }
    }
}

/// A barometric altimeter: height above the origin (`−x₃`, since `e3`
/// points down) with white noise and a bias that starts off and drifts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BaroSpec {
    /// Sample rate, Hz.
    pub rate: f64,
    /// Height σ per sample, m.
    pub sigma: f64,
    /// Bias random walk, m/√s: the bias moves by `K·√Δt·ξ` per sample.
    pub random_walk: f64,
    /// σ of the bias it starts with, m.
    pub turn_on_bias: f64,
}

impl BaroSpec {
    /// A barometer at `rate` with white noise `sigma` alone.
    pub const fn white(rate: f64, sigma: f64) -> Self {
        Self {
            rate,
            sigma,
            random_walk: 0.0,
            turn_on_bias: 0.0,
        }
    }

    /// Every field in range.
    pub fn validate(&self) -> Result<(), SensorError> {
        if !(self.rate.is_finite() && self.rate > 0.0) {
            return Err(setting(
                "baro.rate",
                self.rate,
                "a positive finite rate in Hz",
            ));
        }
        for (field, v) in [
            ("baro.sigma", self.sigma),
            ("baro.random_walk", self.random_walk),
            ("baro.turn_on_bias", self.turn_on_bias),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(setting(field, v, "finite and not negative"));
            }
        }
        Ok(())
    }
}

/// One barometer sample.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BaroSample {
    /// Its index.
    pub k: u64,
    /// Its time, s.
    pub t: f64,
    /// Height above the origin, m (up is positive).
    pub height: f64,
}

/// A barometer in a run: its spec, its key and its bias.
#[derive(Clone, Debug)]
pub struct Baro {
    spec: BaroSpec,
    key: NoiseKey,
    bias: f64,
    next: u64,
}

impl Baro {
    /// The barometer of `spec` drawing its noise from `key`.
    pub fn new(spec: BaroSpec, key: NoiseKey) -> Result<Self, SensorError> {
        spec.validate()?;
        let bias = spec.turn_on_bias * key.pair(0, 3)[0];
        Ok(Self {
            spec,
            key,
            bias,
            next: 0,
        })
    }

    /// The spec it was built with.
    pub fn spec(&self) -> &BaroSpec {
        &self.spec
    }

    /// The time of sample `k`, s.
    pub fn time_of(&self, k: u64) -> f64 {
        k as f64 / self.spec.rate
    }

    /// Sample `k` at the true height `height` (m, up). Samples go forward
    /// (the bias walks through any skipped).
    pub fn sample(&mut self, k: u64, height: f64) -> Result<BaroSample, SensorError> {
        if k < self.next {
            return Err(SensorError::OutOfOrder { k, next: self.next });
        }
        if self.spec.random_walk > 0.0 {
            let step = self.spec.random_walk * Real::sqrt(1.0 / self.spec.rate);
            for j in self.next.max(1)..=k {
                self.bias += step * self.key.pair(j, 1)[0];
            }
        }
        self.next = k + 1;
        let white = if self.spec.sigma == 0.0 {
            0.0
        } else {
            self.spec.sigma * self.key.pair(k, 0)[0]
        };
        Ok(BaroSample {
            k,
            t: self.time_of(k),
            height: height + self.bias + white,
        })
    }
}
