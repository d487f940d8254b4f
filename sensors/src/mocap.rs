//! Motion capture: position, attitude, velocity and body rates from an
//! external tracking system, at its own rate, late by its transport
//! latency, with dropped frames and the velocity and rate spikes of a
//! differentiating tracker.

use lie::{Backend, M3, Real, Rotation, S, So3Mat, V3};

use crate::NoiseKey;
use crate::error::{SensorError, setting};

/// Occasional spikes on one axis: with probability `probability` per
/// sample, one axis drawn at random moves by a magnitude drawn uniformly
/// in `[0, max]` with a random sign (RotorPy's "artifacts", the glitches
/// of a tracker that differentiates positions).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spike {
    /// Probability per sample, in [0, 1].
    pub probability: f64,
    /// Largest magnitude, units of the channel.
    pub max: f64,
}

impl Spike {
    /// No spikes.
    pub const NONE: Self = Self {
        probability: 0.0,
        max: 0.0,
    };
}

/// A motion-capture system: how often it reports, how late, and how
/// noisy. Noise is given per sample (a tracker's frames are independent
/// estimates, not a sampled density).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MocapSpec {
    /// Frame rate, Hz: frame `k` is captured at `t = k / rate`.
    pub rate: f64,
    /// Transport latency, s: frame `k` arrives at `k / rate + latency`.
    pub latency: f64,
    /// Position σ per axis and frame, m.
    pub position_sigma: f64,
    /// Velocity σ per axis and frame, m/s.
    pub velocity_sigma: f64,
    /// Attitude σ per axis and frame, rad: the reported attitude is
    /// `R Exp(η)` with `η ~ N(0, σ² I)` (a right perturbation, so the
    /// report stays on SO(3)).
    pub attitude_sigma: f64,
    /// Body-rate σ per axis and frame, rad/s.
    pub rate_sigma: f64,
    /// Probability that a frame is lost, in [0, 1).
    pub dropout: f64,
    /// Velocity spikes, m/s.
    pub velocity_spike: Spike,
    /// Body-rate spikes, rad/s.
    pub rate_spike: Spike,
}

impl MocapSpec {
    /// A perfect tracker at `rate`: no noise, no latency, no losses.
    pub const fn perfect(rate: f64) -> Self {
        Self {
            rate,
            latency: 0.0,
            position_sigma: 0.0,
            velocity_sigma: 0.0,
            attitude_sigma: 0.0,
            rate_sigma: 0.0,
            dropout: 0.0,
            velocity_spike: Spike::NONE,
            rate_spike: Spike::NONE,
        }
    }

    /// RotorPy 3.0.0's `MotionCapture` as its `Environment` builds it at
    /// the simulation rate `rate`: per-frame σ = √(rate/2)·{0.0005 m,
    /// 0.0010 m/s, 0.0005 rad, 0.0005 rad/s}; its spikes (velocity
    /// probability 0.001 up to 5 m/s, rates 0.0002 up to 1 rad/s) are off,
    /// as they are there by default ([`MocapSpec::with_rotorpy_spikes`]).
    pub fn rotorpy(rate: f64) -> Self {
        let s = Real::sqrt(rate / 2.0);
        Self {
            position_sigma: s * 0.0005,
            velocity_sigma: s * 0.0010,
            attitude_sigma: s * 0.0005,
            rate_sigma: s * 0.0005,
            ..Self::perfect(rate)
        }
    }

    /// The same tracker with RotorPy's spikes on.
    pub fn with_rotorpy_spikes(self) -> Self {
        Self {
            velocity_spike: Spike {
                probability: 0.001,
                max: 5.0,
            },
            rate_spike: Spike {
                probability: 0.0002,
                max: 1.0,
            },
            ..self
        }
    }

    /// A Crazyflie flying on an external pose, as the Crazyflie firmware's
    /// defaults for one take it: 100 Hz, σ 0.01 m and 4.5e-3 rad (the
    /// firmware's `extPosStdDev` and `extQuatStdDev`). The firmware sends
    /// no velocity or rates: the 0.01 m/s and 0.01 rad/s here and the
    /// 10 ms latency are assumptions of this preset, not the firmware's.
    pub fn crazyflie() -> Self {
        Self {
            latency: 0.010,
            position_sigma: 0.01,
            velocity_sigma: 0.01,
            attitude_sigma: 4.5e-3,
            rate_sigma: 0.01,
            ..Self::perfect(100.0)
        }
    }

    /// Every field in range: a positive finite rate, a finite latency not
    /// negative, σ finite and not negative, probabilities in [0, 1] (a
    /// dropout below 1), spike sizes finite and not negative.
    pub fn validate(&self) -> Result<(), SensorError> {
        if !(self.rate.is_finite() && self.rate > 0.0) {
            return Err(setting(
                "mocap.rate",
                self.rate,
                "a positive finite rate in Hz",
            ));
        }
        let not_negative = [
            ("mocap.latency", self.latency),
            ("mocap.position_sigma", self.position_sigma),
            ("mocap.velocity_sigma", self.velocity_sigma),
            ("mocap.attitude_sigma", self.attitude_sigma),
            ("mocap.rate_sigma", self.rate_sigma),
            ("mocap.velocity_spike.max", self.velocity_spike.max),
            ("mocap.rate_spike.max", self.rate_spike.max),
        ];
        for (field, v) in not_negative {
            if !(v.is_finite() && v >= 0.0) {
                return Err(setting(field, v, "finite and not negative"));
            }
        }
        if !(0.0..1.0).contains(&self.dropout) {
            return Err(setting(
                "mocap.dropout",
                self.dropout,
                "a probability in [0, 1)",
            ));
        }
        for (field, p) in [
            (
                "mocap.velocity_spike.probability",
                self.velocity_spike.probability,
            ),
            ("mocap.rate_spike.probability", self.rate_spike.probability),
        ] {
            if !(0.0..=1.0).contains(&p) {
                return Err(setting(field, p, "a probability in [0, 1]"));
            }
        }
        Ok(())
    }
}

/// One motion-capture frame, in the world frame (`x`, `v`) and the body
/// frame (`omega`).
#[derive(Clone, Copy, Debug)]
pub struct MocapSample<B: Backend> {
    /// Its index.
    pub k: u64,
    /// Capture time, s (`k / rate`).
    pub t: f64,
    /// Position, m.
    pub x: V3<B>,
    /// Velocity, m/s.
    pub v: V3<B>,
    /// Attitude (body to world).
    pub r: M3<B>,
    /// Body rates, rad/s.
    pub omega: V3<B>,
}

/// A motion-capture system in a run: its spec and its noise key.
#[derive(Clone, Debug)]
pub struct Mocap {
    spec: MocapSpec,
    key: NoiseKey,
}

// Pairs of normals a frame draws: position, velocity, attitude, rates;
// uniforms: the dropout, then each spike's (happens, axis, size, sign).
const NORMALS: u64 = 0;
const DROPOUT: u64 = 0;
const VEL_SPIKE: u64 = 1;
const RATE_SPIKE: u64 = 5;

impl Mocap {
    /// The tracker of `spec` drawing its noise from `key`; `spec` checked
    /// first ([`MocapSpec::validate`]).
    pub fn new(spec: MocapSpec, key: NoiseKey) -> Result<Self, SensorError> {
        spec.validate()?;
        Ok(Self { spec, key })
    }

    /// The spec it was built with.
    pub fn spec(&self) -> &MocapSpec {
        &self.spec
    }

    /// The capture time of frame `k`, s.
    pub fn time_of(&self, k: u64) -> f64 {
        k as f64 / self.spec.rate
    }

    /// Whether frame `k` is lost (a function of the key and `k` alone).
    pub fn dropped(&self, k: u64) -> bool {
        self.spec.dropout > 0.0 && self.key.uniform(k, DROPOUT) < self.spec.dropout
    }
}

impl Mocap {
    /// Frame `k` of the true state, or `None` if the frame is lost.
    /// Channels without noise or spikes are the true values bit for bit.
    pub fn frame<B: Backend>(
        &self,
        k: u64,
        x: V3<B>,
        v: V3<B>,
        r: M3<B>,
        omega: V3<B>,
    ) -> Option<MocapSample<B>> {
        if self.dropped(k) {
            return None;
        }
        let s = &self.spec;
        let add = |v: V3<B>, sigma: f64, pair: u64| -> V3<B> {
            if sigma == 0.0 {
                return v;
            }
            let [a, b] = self.key.pair(k, NORMALS + pair);
            let [c, _] = self.key.pair(k, NORMALS + pair + 1);
            let l = |z: f64| S::<B>::lit(sigma * z);
            v + B::vec3(l(a), l(b), l(c))
        };
        let mut v_m = add(v, s.velocity_sigma, 2);
        let mut w_m = add(omega, s.rate_sigma, 6);
        let x_m = add(x, s.position_sigma, 0);
        let r_m = if s.attitude_sigma == 0.0 {
            r
        } else {
            let eta = add(lie::ops::zero::<B>(), s.attitude_sigma, 4);
            B::mat3_mul(r, So3Mat::<B>::exp(eta).matrix())
        };
        v_m = self.spike::<B>(k, VEL_SPIKE, s.velocity_spike, v_m);
        w_m = self.spike::<B>(k, RATE_SPIKE, s.rate_spike, w_m);
        Some(MocapSample {
            k,
            t: self.time_of(k),
            x: x_m,
            v: v_m,
            r: r_m,
            omega: w_m,
        })
    }

    fn spike<B: Backend>(&self, k: u64, j: u64, spike: Spike, v: V3<B>) -> V3<B> {
        if spike.probability == 0.0 || self.key.uniform(k, j) >= spike.probability {
            return v;
        }
        let axis = ((self.key.uniform(k, j + 1) * 3.0) as usize).min(2);
        let size = spike.max * self.key.uniform(k, j + 2);
        let sign = if self.key.uniform(k, j + 3) < 0.5 {
            -1.0
        } else {
            1.0
        };
        let mut a = B::vec3_to_array(v);
        a[axis] += S::<B>::lit(sign * size);
        B::vec3(a[0], a[1], a[2])
    }
}
