//! A right-invariant EKF on SE₂(3) × ℝ⁶: the extended pose `(R, v, x)`
//! with gyroscope and accelerometer biases, propagated by the IMU and
//! corrected by motion-capture poses and GPS fixes.
//!
//! The error is `η = X̂ X⁻¹ = Exp(ξ)` on the extended pose (tangent
//! `(ρ, ν, φ)`, [`lie::ExtTwist`]) and `b̂ − b` on the biases: 15 states,
//! in the order `(ρ, ν, φ, b_g, b_a)`. Without the biases the error's
//! dynamics do not depend on the estimate (Barrau & Bonnabel 2017), which
//! keeps the filter consistent through large attitude errors; the biases
//! couple through `X̂` (Hartley et al. 2020), and only they.
//!
//! - Mean: the IMU's body rate and specific force, each sample taken for
//!   the interval that ends at it (what an accelerometer reports) and held
//!   past it until the next, integrated exactly on the group:
//!   `R ← R Exp(ω h)`, `v ← v + R J_l(ω h) f h + g e3 h`,
//!   `x ← x + v h + R Γ₂(ω h) f h² + ½ g e3 h²`.
//! - Covariance: `Φ = [[Φ_nav, B], [0, I]]` with `Φ_nav = exp(A h)`
//!   exact (`A` is nilpotent: `ρ̇ = ν`, `ν̇ = g^ φ`) and `B` to second
//!   order in `h`; `Φ P Φᵀ` is formed from the structure, never as a dense
//!   15×15 product.
//! - Updates: one scalar row at a time (exact for independent noise), the
//!   correction applied as `X̂ ← Exp(−ξ̂) X̂`, `b̂ ← b̂ − δb̂`.
//!
//! `e3` points down, as everywhere in geopid: gravity is `+g e3`.

use lie::num_traits::{One, Zero};
use lie::{Backend, ExtTwist, M3, Real, S, Se23, So3Mat, V3, ops, so3};

use crate::estimator::{Estimator, Measurement, NavState, SensorSet};
use crate::kalman::{Mat, scalar_update, symmetrize};
use crate::{GpsSample, ImuSample, MocapSample, SensorError, error::setting};

/// The state's dimension.
pub const IEKF_DIM: usize = 15;

/// Initial standard deviations of the estimate's error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InitialSigma {
    /// Position, m.
    pub position: f64,
    /// Velocity, m/s.
    pub velocity: f64,
    /// Attitude, rad.
    pub attitude: f64,
    /// Gyroscope bias, rad/s.
    pub gyro_bias: f64,
    /// Accelerometer bias, m/s².
    pub accel_bias: f64,
}

/// The noise the filter assumes, each a continuous density (per √Hz) or a
/// measurement σ, and the IMU's mounting.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct IekfConfig {
    /// Gyroscope white noise, rad/s/√Hz.
    pub gyro_density: f64,
    /// Accelerometer white noise, m/s²/√Hz.
    pub accel_density: f64,
    /// Gyroscope bias random walk, rad/s/√s.
    pub gyro_walk: f64,
    /// Accelerometer bias random walk, m/s²/√s.
    pub accel_walk: f64,
    /// Motion-capture position σ, m.
    pub mocap_position: f64,
    /// Motion-capture attitude σ (a right perturbation), rad.
    pub mocap_attitude: f64,
    /// GPS position σ, horizontal then vertical, m.
    pub gps_position: [f64; 2],
    /// GPS velocity σ, m/s.
    pub gps_velocity: f64,
    /// The initial error's σ.
    pub initial: InitialSigma,
    /// The IMU's axes in the body frame (`R_BS`, columns the sensor's
    /// axes). Its lever arm is not modelled: mount it at the centre of mass.
    pub mounting: [[f64; 3]; 3],
    /// Gravity, m/s².
    pub gravity: f64,
}

impl Default for IekfConfig {
    /// A Crazyflie-class IMU (the BMI088's densities, small walks) and a
    /// motion-capture system of 1 mm and 5 mrad.
    fn default() -> Self {
        Self {
            gyro_density: 2.4e-4,
            accel_density: 1.7e-3,
            gyro_walk: 1e-5,
            accel_walk: 1e-4,
            mocap_position: 1e-3,
            mocap_attitude: 5e-3,
            gps_position: [0.5, 1.0],
            gps_velocity: 0.1,
            initial: InitialSigma {
                position: 0.1,
                velocity: 0.1,
                attitude: 0.1,
                gyro_bias: 0.01,
                accel_bias: 0.1,
            },
            mounting: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            gravity: 9.81,
        }
    }
}

impl IekfConfig {
    /// Every σ and density positive and finite (a zero measurement σ
    /// would make the filter trust a noisy sensor exactly), gravity finite.
    pub fn validate(&self) -> Result<(), SensorError> {
        let i = &self.initial;
        let positive = [
            ("iekf.gyro_density", self.gyro_density),
            ("iekf.accel_density", self.accel_density),
            ("iekf.mocap_position", self.mocap_position),
            ("iekf.mocap_attitude", self.mocap_attitude),
            ("iekf.gps_position[0]", self.gps_position[0]),
            ("iekf.gps_position[1]", self.gps_position[1]),
            ("iekf.gps_velocity", self.gps_velocity),
            ("iekf.initial.position", i.position),
            ("iekf.initial.velocity", i.velocity),
            ("iekf.initial.attitude", i.attitude),
            ("iekf.initial.gyro_bias", i.gyro_bias),
            ("iekf.initial.accel_bias", i.accel_bias),
        ];
        for (field, v) in positive {
            if !(v.is_finite() && v > 0.0) {
                return Err(setting(field, v, "positive and finite"));
            }
        }
        for (field, v) in [
            ("iekf.gyro_walk", self.gyro_walk),
            ("iekf.accel_walk", self.accel_walk),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(setting(field, v, "finite and not negative"));
            }
        }
        if !self.gravity.is_finite() {
            return Err(setting("iekf.gravity", self.gravity, "finite"));
        }
        Ok(())
    }
}

/// Measurements the filter refused, by kind: non-finite, or with an
/// innovation variance that was not positive (a covariance gone bad).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Rejections {
    /// IMU samples.
    pub imu: u64,
    /// Motion-capture frames.
    pub mocap: u64,
    /// GPS fixes.
    pub gps: u64,
}

/// The invariant EKF (see the module docs).
#[derive(Clone, Debug)]
pub struct Iekf<B: Backend> {
    cfg: IekfConfig,
    r_bs: M3<B>,
    /// The estimate's time, s.
    t: f64,
    x: Se23<B>,
    bg: V3<B>,
    ba: V3<B>,
    p: Mat<S<B>, IEKF_DIM>,
    /// Factors on the process noise and on the measurement variances.
    q_scale: S<B>,
    r_scale: S<B>,
    /// The latest IMU sample's body rate and specific force (body frame).
    held: Option<(V3<B>, V3<B>)>,
    /// The latest measurement update's normalised innovation squared and
    /// its degrees of freedom, and its rows' residuals (predicted minus
    /// measured) at the prior.
    nis: Option<(f64, usize)>,
    residuals: [S<B>; 6],
    rejected: Rejections,
}

fn lit<B: Backend>(x: f64) -> S<B> {
    S::<B>::lit(x)
}

/// `Γ₂(φ) = Σ φ^ⁿ/(n + 2)!`, the position's term of the exact IMU
/// integration: `½I + c₁ φ^ + c₂ φ^²` with `c₁ = (θ − sin θ)/θ³`,
/// `c₂ = (θ² + 2 cos θ − 2)/(2θ⁴)`, by their series below θ = 0.25
/// (truncation below 1e-16 relative there; above it the closed forms lose
/// at most a few f32 ulps to cancellation).
pub fn gamma2<B: Backend>(phi: V3<B>) -> M3<B> {
    let t2 = B::dot(phi, phi);
    let (c1, c2) = if t2 < lit::<B>(0.0625) {
        let s = |c: [f64; 4]| {
            lit::<B>(c[0]) + t2 * (lit::<B>(c[1]) + t2 * (lit::<B>(c[2]) + t2 * lit::<B>(c[3])))
        };
        (
            s([1.0 / 6.0, -1.0 / 120.0, 1.0 / 5040.0, -1.0 / 362_880.0]),
            s([1.0 / 24.0, -1.0 / 720.0, 1.0 / 40_320.0, -1.0 / 3_628_800.0]),
        )
    } else {
        let th = t2.sqrt();
        let (s, c) = th.sin_cos();
        (
            (th - s) / (t2 * th),
            (t2 + lit::<B>(2.0) * c - lit::<B>(2.0)) / (lit::<B>(2.0) * t2 * t2),
        )
    };
    let h = so3::hat::<B>(phi);
    ops::identity::<B>() * lit::<B>(0.5) + h * c1 + h * h * c2
}

impl<B: Backend> Iekf<B> {
    /// A filter with `cfg`, checked first; it starts at rest at the origin
    /// until [`Estimator::reset`].
    pub fn new(cfg: IekfConfig) -> Result<Self, SensorError> {
        cfg.validate()?;
        let r_bs = ops::from_elems::<B>(cfg.mounting.map(|r| r.map(lit::<B>)));
        let mut f = Self {
            cfg,
            r_bs,
            t: 0.0,
            x: Se23::identity(),
            bg: ops::zero::<B>(),
            ba: ops::zero::<B>(),
            p: [[S::<B>::zero(); IEKF_DIM]; IEKF_DIM],
            q_scale: S::<B>::one(),
            r_scale: S::<B>::one(),
            held: None,
            nis: None,
            residuals: [S::<B>::zero(); 6],
            rejected: Rejections::default(),
        };
        f.reset_covariance();
        Ok(f)
    }

    fn reset_covariance(&mut self) {
        let i = self.cfg.initial;
        let sig = [
            i.position,
            i.velocity,
            i.attitude,
            i.gyro_bias,
            i.accel_bias,
        ];
        self.p = [[S::<B>::zero(); IEKF_DIM]; IEKF_DIM];
        for (k, row) in self.p.iter_mut().enumerate() {
            row[k] = lit::<B>(sig[k / 3] * sig[k / 3]);
        }
    }

    /// Scales the noise the filter assumes: every process-noise density's
    /// square by `q` and every measurement variance by `r` (both 1 as
    /// configured). As scalars of the backend, a gradient can be taken
    /// with respect to them: they are how a filter is tuned. Refused
    /// unless both are positive and finite.
    pub fn set_noise_scales(&mut self, q: S<B>, r: S<B>) -> Result<(), SensorError> {
        for (field, v) in [("iekf.q_scale", q), ("iekf.r_scale", r)] {
            let x = v.to_f64_lossless();
            if !(x.is_finite() && x > 0.0) {
                return Err(setting(field, x, "positive and finite"));
            }
        }
        (self.q_scale, self.r_scale) = (q, r);
        Ok(())
    }

    /// Replaces the error covariance (order `(ρ, ν, φ, b_g, b_a)`), e.g.
    /// a full initial covariance; refused unless symmetric (to 1e-12 of
    /// its diagonal) and positive definite.
    pub fn set_covariance(&mut self, p: &Mat<f64, IEKF_DIM>) -> Result<(), SensorError> {
        if !crate::kalman::is_spd(p, 1e-12) {
            let worst = p
                .iter()
                .flatten()
                .fold(0.0f64, |m, x| if x.is_finite() { m } else { *x });
            return Err(setting(
                "iekf.covariance",
                worst,
                "symmetric positive definite (a non-finite entry is shown, else 0)",
            ));
        }
        self.p = p.map(|r| r.map(lit::<B>));
        Ok(())
    }

    /// The extended pose estimate.
    pub fn pose(&self) -> Se23<B> {
        self.x
    }
    /// The gyroscope and accelerometer bias estimates (body frame).
    pub fn biases(&self) -> (V3<B>, V3<B>) {
        (self.bg, self.ba)
    }
    /// The error covariance, order `(ρ, ν, φ, b_g, b_a)`.
    pub fn covariance(&self) -> &Mat<S<B>, IEKF_DIM> {
        &self.p
    }
    /// The latest update's normalised innovation squared and its degrees
    /// of freedom (6 for a mocap pose, 3 or 6 for a GPS fix).
    pub fn last_nis(&self) -> Option<(f64, usize)> {
        self.nis
    }
    /// The measurements refused so far.
    pub fn rejections(&self) -> Rejections {
        self.rejected
    }
    /// Starts from `x0` with the configured initial covariance and zero
    /// biases: the estimate may be anything, e.g. deliberately wrong.
    pub fn reset_to(&mut self, t: f64, x0: Se23<B>) {
        self.t = t;
        self.x = x0;
        self.bg = ops::zero::<B>();
        self.ba = ops::zero::<B>();
        self.held = None;
        self.nis = None;
        self.reset_covariance();
    }

    /// The mean moved from `self.t` to `t` on the held IMU sample.
    fn mean_at(&self, t: f64) -> Se23<B> {
        let dt = t - self.t;
        let Some((w, f)) = self.held.filter(|_| dt > 0.0) else {
            return self.x;
        };
        let h = lit::<B>(dt);
        let (w, f) = (w - self.bg, f - self.ba);
        let phi = w * h;
        let r = self.x.rotation.as_matrix();
        let ge3 = B::vec3(S::<B>::zero(), S::<B>::zero(), lit::<B>(self.cfg.gravity));
        let (v, x) = (self.x.velocity, self.x.position);
        Se23::new(
            self.x.rotation.compose(So3Mat::exp(phi)).renormalized(),
            v + r * (so3::left_jacobian::<B>(phi) * f) * h + ge3 * h,
            x + v * h + r * (gamma2::<B>(phi) * f) * (h * h) + ge3 * (h * h * lit::<B>(0.5)),
        )
    }

    /// Mean and covariance moved to `t`.
    fn propagate(&mut self, t: f64) {
        let dt = t - self.t;
        if dt <= 0.0 {
            return;
        }
        if self.held.is_some() {
            self.propagate_covariance(lit::<B>(dt));
            self.x = self.mean_at(t);
        }
        self.t = t;
    }

    /// `P ← Φ P Φᵀ + Q_d` over `h`, at the estimate before the step.
    fn propagate_covariance(&mut self, h: S<B>) {
        let g = lit::<B>(self.cfg.gravity);
        let r = self.x.rotation.as_matrix();
        let (xh, vh) = (
            so3::hat::<B>(self.x.position),
            so3::hat::<B>(self.x.velocity),
        );
        let gh = so3::hat::<B>(B::vec3(S::<B>::zero(), S::<B>::zero(), g));
        let half = h * h * lit::<B>(0.5);
        // B = A_b h + ½ A_nav A_b h², columns (b_g, b_a), 3×3 blocks.
        let neg = lit::<B>(-1.0);
        let b_blocks: [[M3<B>; 2]; 3] = [
            [(xh * r * h + vh * r * half) * neg, r * (half * neg)],
            [(vh * r * h + gh * r * half) * neg, r * (h * neg)],
            [r * (h * neg), r * S::<B>::zero()],
        ];
        let mut bm = [[S::<B>::zero(); 6]; 9];
        for (bi, row) in b_blocks.iter().enumerate() {
            for (bj, blk) in row.iter().enumerate() {
                let e = ops::elems::<B>(*blk);
                for i in 0..3 {
                    bm[3 * bi + i][3 * bj..3 * bj + 3].copy_from_slice(&e[i]);
                }
            }
        }
        // Φ P Φᵀ in place: Φ P as row operations (a row reads only rows
        // below it, still unchanged when it is written), then P Φᵀ as Φ on
        // every row; no second 15×15 matrix. Φ_nav: ρ += h ν + ½h² g^φ,
        // ν += h g^φ with g^ φ = g(−φ₂, φ₁, 0); then B times the biases.
        let p = &mut self.p;
        let bias = |p: &Mat<S<B>, IEKF_DIM>, i: usize, c: usize| {
            (0..6).fold(S::<B>::zero(), |s, k| s + bm[i][k] * p[9 + k][c])
        };
        for c in 0..IEKF_DIM {
            p[0][c] = p[0][c] + h * p[3][c] + half * (-g * p[7][c]) + bias(p, 0, c);
        }
        for c in 0..IEKF_DIM {
            p[1][c] = p[1][c] + h * p[4][c] + half * (g * p[6][c]) + bias(p, 1, c);
        }
        for c in 0..IEKF_DIM {
            p[2][c] = p[2][c] + h * p[5][c] + bias(p, 2, c);
        }
        for c in 0..IEKF_DIM {
            p[3][c] = p[3][c] + h * (-g * p[7][c]) + bias(p, 3, c);
        }
        for c in 0..IEKF_DIM {
            p[4][c] = p[4][c] + h * (g * p[6][c]) + bias(p, 4, c);
        }
        for i in 5..9 {
            for c in 0..IEKF_DIM {
                let b = bias(p, i, c);
                p[i][c] += b;
            }
        }
        let phi = |v: &mut [S<B>; IEKF_DIM]| {
            let m = *v;
            let gphi = [-g * m[7], g * m[6]];
            for k in 0..2 {
                v[k] = m[k] + h * m[3 + k] + half * gphi[k];
                v[3 + k] = m[3 + k] + h * gphi[k];
            }
            v[2] = m[2] + h * m[5];
            for (i, brow) in bm.iter().enumerate() {
                let add = (0..6).fold(S::<B>::zero(), |s, k| s + brow[k] * m[9 + k]);
                v[i] += add;
            }
        };
        for row in p.iter_mut() {
            phi(row);
        }
        add_process_noise::<B>(&self.cfg, self.q_scale, &mut self.p, h, xh, vh);
        symmetrize(&mut self.p);
    }

    /// Rows `(H, residual, variance)` applied together, then the
    /// correction; false (nothing changed) if any row was refused.
    fn correct(&mut self, rows: &[RowOf<B>]) -> bool {
        let mut p = self.p;
        let mut corr = [S::<B>::zero(); IEKF_DIM];
        let mut nis = 0.0;
        for (h, r, var) in rows {
            match scalar_update(&mut p, &mut corr, h, *r, *var) {
                Some(e) => nis += e.to_f64_lossless(),
                None => return false,
            }
        }
        if corr.iter().any(|c| !c.is_finite()) {
            return false;
        }
        let v3 = |k: usize| B::vec3(corr[k], corr[k + 1], corr[k + 2]);
        let neg = lit::<B>(-1.0);
        let xi = ExtTwist::<B>::new(v3(0) * neg, v3(3) * neg, v3(6) * neg);
        self.x = Se23::exp(xi).compose(self.x);
        self.bg = self.bg - v3(9);
        self.ba = self.ba - v3(12);
        symmetrize(&mut p);
        self.p = p;
        self.nis = Some((nis, rows.len()));
        for (slot, (_, r, _)) in self.residuals.iter_mut().zip(rows) {
            *slot = *r;
        }
        true
    }

    /// The rows of a position (`pos`) or velocity (`!pos`) measurement `y`
    /// with per-axis σ: residual `ŷ − y ≈ ξ_pos − ŷ^ ξ_φ`.
    fn translation_rows(&self, y: V3<B>, sigma: [f64; 3], pos: bool) -> [RowOf<B>; 3] {
        let (yh, off) = if pos {
            (self.x.position, 0)
        } else {
            (self.x.velocity, 3)
        };
        let res = B::vec3_to_array(yh - y);
        let m = ops::elems::<B>(so3::hat::<B>(yh));
        core::array::from_fn(|i| {
            let mut h = [S::<B>::zero(); IEKF_DIM];
            h[off + i] = S::<B>::one();
            for j in 0..3 {
                h[6 + j] = -m[i][j];
            }
            (h, res[i], lit::<B>(sigma[i] * sigma[i]) * self.r_scale)
        })
    }

    fn mocap_update(&mut self, m: &MocapSample<B>) -> bool {
        if !(ops::is_finite_vec::<B>(m.x) && ops::is_finite_mat::<B>(m.r)) {
            return false;
        }
        let sp = self.cfg.mocap_position;
        let pos = self.translation_rows(m.x, [sp; 3], true);
        // Attitude: Log(R̂ R_mᵀ) ≈ ξ_φ − R η, isotropic noise.
        let rm = So3Mat::<B>::from_matrix_unchecked(m.r);
        let res = B::vec3_to_array(self.x.rotation.compose(rm.inverse()).log());
        let va = lit::<B>(self.cfg.mocap_attitude * self.cfg.mocap_attitude) * self.r_scale;
        let att: [RowOf<B>; 3] = core::array::from_fn(|i| {
            let mut h = [S::<B>::zero(); IEKF_DIM];
            h[6 + i] = S::<B>::one();
            (h, res[i], va)
        });
        self.correct(&[pos[0], pos[1], pos[2], att[0], att[1], att[2]])
    }

    fn gps_update(&mut self, m: &GpsSample<B>) -> bool {
        let [sh, sv] = self.cfg.gps_position;
        let sw = self.cfg.gps_velocity;
        match (ops::is_finite_vec::<B>(m.x), ops::is_finite_vec::<B>(m.v)) {
            (true, true) => {
                let p = self.translation_rows(m.x, [sh, sh, sv], true);
                let v = self.translation_rows(m.v, [sw; 3], false);
                self.correct(&[p[0], p[1], p[2], v[0], v[1], v[2]])
            }
            (true, false) => self.correct(&self.translation_rows(m.x, [sh, sh, sv], true)),
            _ => false,
        }
    }

    /// Sample `s` carries the filter over the interval that ends at it:
    /// the specific force its own, the rate the mean of its and the last
    /// sample's (the rotation then to second order, as the FDCL lab's
    /// `R ← R Exp(h/2 (Ω + Ω_prev))`); then it is held past it.
    fn imu_sample(&mut self, s: &ImuSample<B>, t: f64) -> bool {
        if !(ops::is_finite_vec::<B>(s.gyro) && ops::is_finite_vec::<B>(s.accel)) {
            self.propagate(t);
            return false;
        }
        let (w, f) = (self.r_bs * s.gyro, self.r_bs * s.accel);
        let mid = self.held.map_or(w, |(w0, _)| (w0 + w) * lit::<B>(0.5));
        self.held = Some((mid, f));
        self.propagate(t);
        self.held = Some((w, f));
        true
    }
}

/// `Q_d = Ad_X̂ diag(0, σ_a² I, σ_g² I) Ad_X̂ᵀ h` on the extended pose
/// (closed form, `R Rᵀ = I`), the walks' `σ² h` on the biases.
fn add_process_noise<B: Backend>(
    c: &IekfConfig,
    q_scale: S<B>,
    p: &mut Mat<S<B>, IEKF_DIM>,
    h: S<B>,
    xh: M3<B>,
    vh: M3<B>,
) {
    let hq = h * q_scale;
    let (qg, qa) = (
        lit::<B>(c.gyro_density * c.gyro_density) * hq,
        lit::<B>(c.accel_density * c.accel_density) * hq,
    );
    let id = ops::identity::<B>();
    let col = [xh, vh, id];
    for bi in 0..3 {
        for bj in 0..3 {
            let mut q = col[bi] * B::mat3_transpose(col[bj]) * qg;
            if bi == 1 && bj == 1 {
                q = q + id * qa;
            }
            let e = ops::elems::<B>(q);
            for i in 0..3 {
                for j in 0..3 {
                    p[3 * bi + i][3 * bj + j] += e[i][j];
                }
            }
        }
    }
    let (wg, wa) = (
        lit::<B>(c.gyro_walk * c.gyro_walk) * hq,
        lit::<B>(c.accel_walk * c.accel_walk) * hq,
    );
    for k in 0..3 {
        p[9 + k][9 + k] += wg;
        p[12 + k][12 + k] += wa;
    }
}

type RowOf<B> = ([S<B>; IEKF_DIM], S<B>, S<B>);

impl<B: Backend> Estimator<B> for Iekf<B> {
    fn name(&self) -> &'static str {
        "iekf"
    }
    fn needs(&self) -> SensorSet {
        SensorSet {
            imu: true,
            ..SensorSet::default()
        }
    }
    fn wants(&self) -> SensorSet {
        SensorSet {
            imu: true,
            mocap: true,
            gps: true,
            baro: false,
        }
    }
    fn reset(&mut self, t: f64, initial: &NavState<B>) {
        let r = So3Mat::<B>::from_matrix_unchecked(initial.r);
        self.reset_to(t, Se23::new(r, initial.v, initial.x));
    }
    fn update(&mut self, m: &Measurement<B>) {
        let t = m.captured();
        if !t.is_finite() {
            return;
        }
        let ok = match m {
            // The sample describes the interval that ends at it (an
            // accelerometer's reading is the loads of that interval, a
            // simulation's sample at a control instant the command before
            // it): it carries the filter there, and on until the next.
            Measurement::Imu(s) => self.imu_sample(s, t),
            Measurement::Mocap(f) => {
                self.propagate(t);
                self.mocap_update(f)
            }
            Measurement::Gps(f) => {
                self.propagate(t);
                self.gps_update(f)
            }
            _ => true,
        };
        if !ok {
            match m {
                Measurement::Imu(_) => self.rejected.imu += 1,
                Measurement::Mocap(_) => self.rejected.mocap += 1,
                _ => self.rejected.gps += 1,
            }
        }
    }
    fn diagnostics(&self) -> Option<crate::Diagnostics> {
        let d = (0..IEKF_DIM).map(|i| self.p[i][i].to_f64_lossless());
        let n = self.nis.map_or(0, |(_, k)| k);
        let innovation = self.residuals[..n].iter().map(|r| -r.to_f64_lossless());
        Some(crate::Diagnostics::of_diagonal(d, self.nis).with_innovation(innovation))
    }
    fn estimate(&self, t: f64) -> NavState<B> {
        let x = self.mean_at(t);
        let omega = self.held.map_or(ops::zero::<B>(), |(w, _)| w - self.bg);
        NavState {
            x: x.position,
            v: x.velocity,
            r: x.rotation.as_matrix(),
            omega,
        }
    }
}
