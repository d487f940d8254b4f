//! The passive complementary filter on SO(3) with gyro-bias estimation
//! (Mahony, Hamel & Pflimlin, "Nonlinear complementary filters on the
//! special orthogonal group", IEEE TAC 2008), with position and velocity
//! from the motion capture: what a Crazyflie-class flight CPU affords.
//!
//! Between attitude measurements the gyroscope drives the estimate,
//! `R̂ ← R̂ Exp((ω_y − b̂) h)`, each sample covering the interval that ends
//! at it at the mean of its rate and the last one's; at a measured attitude `R_y` the error
//! `ω = vex(P_a(R̂ᵀ R_y))` (`P_a` the skew part) turns the estimate toward
//! it and moves the bias against it over the interval `Δ` since the last
//! one: `R̂ ← R̂ Exp(k_P ω Δ)`, `b̂ ← b̂ − k_I ω Δ`. The error's size
//! `sin θ` makes convergence almost global: from any attitude but the
//! exact opposite one, slowly at first when the error is near 180°.

use lie::{Backend, M3, Real, S, So3Mat, V3, ops, so3};

use crate::estimator::{Estimator, Measurement, NavState, SensorSet};
use crate::{SensorError, error::setting};

/// The complementary filter's gains and the IMU's mounting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ComplementaryConfig {
    /// Attitude gain `k_P`, 1/s: the estimate's error decays at about
    /// this rate once small.
    pub k_p: f64,
    /// Bias gain `k_I`, 1/s² (below `k_P²/4` for a well-damped bias).
    pub k_i: f64,
    /// The IMU's axes in the body frame (`R_BS`).
    pub mounting: [[f64; 3]; 3],
    /// The longest interval an attitude measurement's correction may span,
    /// s: one after a long dropout is weighted as if it came this long
    /// after the last (keeps `k_P Δ` below one). The first one's interval
    /// runs from the reset.
    pub max_interval: f64,
}

impl Default for ComplementaryConfig {
    /// `k_P = 2/s`, `k_I = 0.2/s²` (well damped: `k_I < k_P²/4 = 1`), for
    /// attitude measurements at 100 Hz (`k_P Δ = 0.02`); a 0.1 s cap.
    fn default() -> Self {
        Self {
            k_p: 2.0,
            k_i: 0.2,
            mounting: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            max_interval: 0.1,
        }
    }
}

impl ComplementaryConfig {
    /// Gains finite and not negative, `k_P · max_interval` below one (a
    /// larger step would overshoot the measurement).
    pub fn validate(&self) -> Result<(), SensorError> {
        for (field, v) in [
            ("complementary.k_p", self.k_p),
            ("complementary.k_i", self.k_i),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(setting(field, v, "finite and not negative"));
            }
        }
        let m = self.max_interval;
        if !(m.is_finite() && m > 0.0 && self.k_p * m < 1.0) {
            return Err(setting(
                "complementary.max_interval",
                m,
                "positive, with k_p·max_interval below 1",
            ));
        }
        Ok(())
    }
}

/// The filter (see the module docs).
#[derive(Clone, Debug)]
pub struct Complementary<B: Backend> {
    cfg: ComplementaryConfig,
    r_bs: M3<B>,
    t: f64,
    r: So3Mat<B>,
    bias: V3<B>,
    /// The latest gyro reading in the body frame.
    gyro: Option<V3<B>>,
    /// The latest mocap position and velocity and their time.
    x: V3<B>,
    v: V3<B>,
    t_fix: f64,
    /// When the last attitude measurement was taken.
    t_att: Option<f64>,
    rejected: u64,
}

impl<B: Backend> Complementary<B> {
    /// A filter with `cfg`, checked first.
    pub fn new(cfg: ComplementaryConfig) -> Result<Self, SensorError> {
        cfg.validate()?;
        let z = ops::zero::<B>();
        Ok(Self {
            cfg,
            r_bs: ops::from_elems::<B>(cfg.mounting.map(|r| r.map(S::<B>::lit))),
            t: 0.0,
            r: So3Mat::identity(),
            bias: z,
            gyro: None,
            x: z,
            v: z,
            t_fix: 0.0,
            t_att: None,
            rejected: 0,
        })
    }

    /// The attitude estimate.
    pub fn attitude(&self) -> So3Mat<B> {
        self.r
    }
    /// The gyro bias estimate (body frame).
    pub fn bias(&self) -> V3<B> {
        self.bias
    }
    /// Measurements refused as non-finite.
    pub fn rejections(&self) -> u64 {
        self.rejected
    }
    /// Starts from attitude `r` (anything, e.g. deliberately wrong),
    /// position `x`, velocity `v`, zero bias.
    pub fn reset_to(&mut self, t: f64, r: So3Mat<B>, x: V3<B>, v: V3<B>) {
        (self.t, self.r, self.x, self.v, self.t_fix) = (t, r, x, v, t);
        self.bias = ops::zero::<B>();
        self.gyro = None;
        self.t_att = Some(t);
    }

    fn attitude_at(&self, t: f64) -> So3Mat<B> {
        match self.gyro {
            Some(w) if t > self.t => {
                let phi = (w - self.bias) * S::<B>::lit(t - self.t);
                self.r.compose(So3Mat::exp(phi)).renormalized()
            }
            _ => self.r,
        }
    }

    /// One attitude measurement `r_y` at `t`.
    fn correct(&mut self, t: f64, r_y: M3<B>) {
        let dt = self
            .t_att
            .map_or(self.cfg.max_interval, |t0| t - t0)
            .clamp(0.0, self.cfg.max_interval);
        self.t_att = Some(t);
        let e = B::mat3_transpose(self.r.as_matrix()) * r_y;
        let w = so3::vee::<B>((e - B::mat3_transpose(e)) * S::<B>::lit(0.5));
        let h = S::<B>::lit(dt);
        self.r = self
            .r
            .compose(So3Mat::exp(w * (S::<B>::lit(self.cfg.k_p) * h)))
            .renormalized();
        self.bias = self.bias - w * (S::<B>::lit(self.cfg.k_i) * h);
    }
}

impl<B: Backend> Estimator<B> for Complementary<B> {
    fn name(&self) -> &'static str {
        "complementary"
    }
    fn needs(&self) -> SensorSet {
        SensorSet {
            imu: true,
            mocap: true,
            ..SensorSet::default()
        }
    }
    fn wants(&self) -> SensorSet {
        self.needs()
    }
    fn reset(&mut self, t: f64, initial: &NavState<B>) {
        let r = So3Mat::from_matrix_unchecked(initial.r);
        self.reset_to(t, r, initial.x, initial.v);
    }
    fn update(&mut self, m: &Measurement<B>) {
        let t = m.captured();
        match m {
            // The sample covers the interval that ends at it, at the mean
            // of its rate and the last one's, as the invariant EKF takes
            // it; then it is held past it.
            Measurement::Imu(s) if ops::is_finite_vec::<B>(s.gyro) && t.is_finite() => {
                let w = self.r_bs * s.gyro;
                self.gyro = Some(self.gyro.map_or(w, |w0| (w0 + w) * S::<B>::lit(0.5)));
                self.r = self.attitude_at(t);
                self.t = self.t.max(t);
                self.gyro = Some(w);
            }
            Measurement::Mocap(f)
                if ops::is_finite_mat::<B>(f.r)
                    && ops::is_finite_vec::<B>(f.x)
                    && ops::is_finite_vec::<B>(f.v)
                    && t.is_finite() =>
            {
                self.r = self.attitude_at(t);
                self.t = self.t.max(t);
                self.correct(t, f.r);
                (self.x, self.v, self.t_fix) = (f.x, f.v, t);
            }
            Measurement::Imu(_) | Measurement::Mocap(_) => self.rejected += 1,
            _ => {}
        }
    }
    fn estimate(&self, t: f64) -> NavState<B> {
        NavState {
            x: self.x + self.v * S::<B>::lit((t - self.t_fix).max(0.0)),
            v: self.v,
            r: self.attitude_at(t).as_matrix(),
            omega: self.gyro.map_or(ops::zero::<B>(), |w| w - self.bias),
        }
    }
}
