//! The FDCL lab's EKF as `fdcl-gwu/uav_simulator`'s `estimator.py`
//! publishes it: 10 states (position, velocity, an attitude error, an
//! accelerometer bias along `e3`), predicted from the IMU, corrected by
//! the IMU's own attitude (an AHRS) at every sample and by GPS position
//! and velocity.
//!
//! Written from the published equations, step for step, so that the same
//! measurement stream gives the same estimates as their code (checked
//! against it in `sensors/tests/fdcl_ekf.rs`), including two traits of
//! theirs a textbook filter would not have: an attitude correction moves
//! only the attitude (its gains on position, velocity and bias are
//! dropped while the covariance is updated as if they were applied), and
//! a GPS correction moves all but the attitude.
//!
//! - Prediction over `h` with the IMU's acceleration **without gravity**
//!   `a_imu` and rate `Ω_imu`, in the IMU's frame (`R_bi` to the body):
//!   `Ω = R_bi Ω_imu`, `R ← R Exp(h/2 (Ω + Ω_prev))`, `a = R R_bi a_imu +
//!   b_a e3`, `x ← x + h v + h²/2 a_prev`, `v ← v + h/2 (a + a_prev)`;
//!   the covariance through `Φ = I + h A (I + h/2 A)`.
//! - Attitude correction with `R_imu` (IMU to world): `δz = ½ vee(M − Mᵀ)`,
//!   `M = Rᵀ R_imu R_biᵀ`; `R ← R Exp(η)`.
//! - GPS correction with `x`, `v`; Joseph-form covariance updates.

use lie::num_traits::{One, Zero};
use lie::{Backend, M3, Real, S, V3, ops, so3};

use crate::estimator::{Estimator, Measurement, NavState, SensorSet};
use crate::kalman::{self, Mat, mul, spd_inverse, transpose};

/// `(x, v, a, R, Ω)`, as their `get_states` returns them.
pub type States<B> = (V3<B>, V3<B>, V3<B>, M3<B>, V3<B>);

/// The state's dimension.
pub const FDCL_DIM: usize = 10;

/// The filter's settings: `estimator.py`'s values by default.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FdclConfig {
    /// Process noise variances: acceleration (3), angular rate (3), the
    /// bias (1).
    pub q: [f64; 7],
    /// Initial covariance diagonal: position, velocity, attitude, bias.
    pub p0: [f64; FDCL_DIM],
    /// Attitude measurement variance per axis.
    pub v_attitude: f64,
    /// GPS position and velocity variances per axis.
    pub v_gps: [f64; 2],
    /// The IMU's frame to the body's (`R_bi`).
    pub r_bi: [[f64; 3]; 3],
    /// Gravity, m/s².
    pub gravity: f64,
}

impl Default for FdclConfig {
    /// `Q = diag(1e-3 ×3, 0.025 ×3, 1e-4)`, `P₀ = diag(1 ×6, 0.01 ×3, 1)`,
    /// `V = 0.01 I` for the attitude and the GPS, `R_bi = diag(1, −1, −1)`,
    /// `g = 9.81`.
    fn default() -> Self {
        Self {
            q: [1e-3, 1e-3, 1e-3, 0.025, 0.025, 0.025, 1e-4],
            p0: [1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 0.01, 0.01, 0.01, 1.0],
            v_attitude: 0.01,
            v_gps: [0.01, 0.01],
            r_bi: [[1.0, 0.0, 0.0], [0.0, -1.0, 0.0], [0.0, 0.0, -1.0]],
            gravity: 9.81,
        }
    }
}

/// The FDCL lab's EKF (see the module docs).
#[derive(Clone, Debug)]
pub struct FdclEkf<B: Backend> {
    cfg: FdclConfig,
    r_bi: M3<B>,
    x: V3<B>,
    v: V3<B>,
    a: V3<B>,
    r: M3<B>,
    w: V3<B>,
    b_a: S<B>,
    a_imu_pre: V3<B>,
    p: Mat<S<B>, FDCL_DIM>,
    /// The last IMU sample's time (the reset's before the first).
    t: f64,
    rejected: u64,
    nis: Option<(f64, usize)>,
    /// The latest update's innovation (measured minus predicted).
    innovation: [S<B>; 6],
}

fn lit<B: Backend>(x: f64) -> S<B> {
    S::<B>::lit(x)
}

/// Writes the 3×3 block `m` at (`r0`, `c0`).
fn put<B: Backend, const R: usize, const C: usize>(
    out: &mut [[S<B>; C]; R],
    r0: usize,
    c0: usize,
    m: M3<B>,
) {
    for (i, row) in ops::elems::<B>(m).iter().enumerate() {
        out[r0 + i][c0..c0 + 3].copy_from_slice(row);
    }
}

/// `expm_SO3` as the lab writes it: `I + sinc θ r^ + ½ sinc²(θ/2) r^²`
/// with their series for `sinc` below 1e-6.
pub fn fdcl_expm<B: Backend>(r: V3<B>) -> M3<B> {
    let sinc = |x: S<B>| {
        if x.abs() < lit::<B>(1e-6) {
            let x2 = x * x;
            lit::<B>(1.0) - x2 / lit::<B>(6.0) + x2 * x2 / lit::<B>(120.0)
                - x2 * x2 * x2 / lit::<B>(5040.0)
                + x2 * x2 * x2 * x2 / lit::<B>(362_880.0)
                - x2 * x2 * x2 * x2 * x2 / lit::<B>(39_916_800.0)
        } else {
            x.sin() / x
        }
    };
    let th = ops::norm::<B>(r);
    let (y, y2) = (sinc(th), sinc(th / lit::<B>(2.0)));
    let h = so3::hat::<B>(r);
    ops::identity::<B>() + h * y + h * h * (lit::<B>(0.5) * y2 * y2)
}

impl<B: Backend> FdclEkf<B> {
    /// At the origin, level, at rest, with `cfg`'s initial covariance.
    pub fn new(cfg: FdclConfig) -> Self {
        let z = ops::zero::<B>();
        let mut p = [[S::<B>::zero(); FDCL_DIM]; FDCL_DIM];
        for (i, row) in p.iter_mut().enumerate() {
            row[i] = lit::<B>(cfg.p0[i]);
        }
        Self {
            cfg,
            r_bi: ops::from_elems::<B>(cfg.r_bi.map(|r| r.map(lit::<B>))),
            x: z,
            v: z,
            a: z,
            r: ops::identity::<B>(),
            w: z,
            b_a: S::<B>::zero(),
            a_imu_pre: z,
            p,
            t: 0.0,
            rejected: 0,
            nis: None,
            innovation: [S::<B>::zero(); 6],
        }
    }

    /// Position, velocity, acceleration, attitude and body rate, as their
    /// `get_states` returns them.
    pub fn states(&self) -> States<B> {
        (self.x, self.v, self.a, self.r, self.w)
    }
    /// The accelerometer bias along `e3`, m/s².
    pub fn bias(&self) -> S<B> {
        self.b_a
    }
    /// The covariance, order `(x, v, attitude, b_a)`.
    pub fn covariance(&self) -> &Mat<S<B>, FDCL_DIM> {
        &self.p
    }
    /// Starts from position `x`, velocity `v` and attitude `r`, the rest
    /// as [`FdclEkf::new`].
    pub fn reset_to(&mut self, x: V3<B>, v: V3<B>, r: M3<B>) {
        *self = Self::new(self.cfg);
        (self.x, self.v, self.r) = (x, v, r);
    }

    /// The prediction over `h` s with `a_imu` (acceleration without
    /// gravity) and `w_imu` (rate), both in the IMU's frame.
    pub fn predict(&mut self, h: f64, a_imu: V3<B>, w_imu: V3<B>) {
        let hs = lit::<B>(h);
        let e3 = B::vec3(S::<B>::zero(), S::<B>::zero(), S::<B>::one());
        let (r_pre, w_pre, ba_pre) = (self.r, self.w, self.b_a);
        self.w = self.r_bi * w_imu;
        self.r = self.r * fdcl_expm::<B>((self.w + w_pre) * (hs / lit::<B>(2.0)));
        self.a = self.r * (self.r_bi * a_imu) + e3 * self.b_a;
        let a_pre = r_pre * (self.r_bi * self.a_imu_pre) + e3 * ba_pre;
        self.x = self.x + self.v * hs + a_pre * (hs * hs / lit::<B>(2.0));
        self.v = self.v + (self.a + a_pre) * (hs / lit::<B>(2.0));

        let mut a = [[S::<B>::zero(); FDCL_DIM]; FDCL_DIM];
        put::<B, 10, 10>(&mut a, 0, 3, ops::identity::<B>());
        put::<B, 10, 10>(
            &mut a,
            3,
            6,
            r_pre * so3::hat::<B>(self.r_bi * self.a_imu_pre) * lit::<B>(-1.0),
        );
        for (i, c) in B::vec3_to_array(e3).into_iter().enumerate() {
            a[3 + i][9] = c;
        }
        put::<B, 10, 10>(
            &mut a,
            6,
            6,
            so3::hat::<B>(self.r_bi * w_imu) * lit::<B>(-1.0),
        );
        let mut f = [[S::<B>::zero(); 7]; FDCL_DIM];
        put::<B, 10, 7>(&mut f, 3, 0, r_pre * self.r_bi);
        put::<B, 10, 7>(&mut f, 6, 3, self.r_bi);
        f[9][6] = S::<B>::one();
        let scale = |m: &Mat<S<B>, FDCL_DIM>, k: S<B>| m.map(|r| r.map(|x| x * k));
        let id = kalman::identity::<S<B>, FDCL_DIM>();
        let psi = kalman::add::<S<B>, 10, 10>(&id, &scale(&a, hs / lit::<B>(2.0)));
        let phi = kalman::add::<S<B>, 10, 10>(&id, &scale(&mul(&a, &psi), hs));
        let fd = mul(&psi, &f).map(|r| r.map(|x| x * hs));
        let q: [[S<B>; 7]; 7] = core::array::from_fn(|i| {
            core::array::from_fn(|j| {
                if i == j {
                    lit::<B>(self.cfg.q[i])
                } else {
                    S::<B>::zero()
                }
            })
        });
        self.p = kalman::add::<S<B>, 10, 10>(
            &mul(&mul(&phi, &self.p), &transpose(&phi)),
            &mul(&mul(&fd, &q), &transpose(&fd)),
        );
        self.a_imu_pre = a_imu;
    }

    /// The attitude correction with `r_imu`, the IMU's frame to the world;
    /// false (nothing changed) if the innovation's covariance is not
    /// positive definite.
    pub fn correct_attitude(&mut self, r_imu: M3<B>) -> bool {
        let m = B::mat3_transpose(self.r) * r_imu * B::mat3_transpose(self.r_bi);
        let dz = B::vec3_to_array(so3::vee::<B>((m - B::mat3_transpose(m)) * lit::<B>(0.5)));
        let mut h = [[S::<B>::zero(); FDCL_DIM]; 3];
        put::<B, 3, 10>(&mut h, 0, 6, ops::identity::<B>());
        let v = ops::identity::<B>() * lit::<B>(self.cfg.v_attitude);
        // G V Gᵀ with G = R_bi.
        let gvg = ops::elems::<B>(self.r_bi * v * B::mat3_transpose(self.r_bi));
        let Some(k) = self.gain(&h, &gvg, &dz) else {
            return false;
        };
        let x: [S<B>; FDCL_DIM] =
            core::array::from_fn(|i| (0..3).fold(S::<B>::zero(), |s, j| s + k[i][j] * dz[j]));
        self.r = self.r * fdcl_expm::<B>(B::vec3(x[6], x[7], x[8]));
        self.joseph(&h, &k, &gvg);
        true
    }

    /// The GPS correction with position `xg` and velocity `vg`; false
    /// (nothing changed) if the innovation's covariance is not positive
    /// definite.
    pub fn correct_gps(&mut self, xg: V3<B>, vg: V3<B>) -> bool {
        let (dx, dv) = (B::vec3_to_array(xg - self.x), B::vec3_to_array(vg - self.v));
        let dz = [dx[0], dx[1], dx[2], dv[0], dv[1], dv[2]];
        let mut h = [[S::<B>::zero(); FDCL_DIM]; 6];
        put::<B, 6, 10>(&mut h, 0, 0, ops::identity::<B>());
        put::<B, 6, 10>(&mut h, 3, 3, ops::identity::<B>());
        let [vx, vv] = self.cfg.v_gps;
        let v: Mat<S<B>, 6> = core::array::from_fn(|i| {
            core::array::from_fn(|j| match (i == j, i < 3) {
                (true, true) => lit::<B>(vx),
                (true, false) => lit::<B>(vv),
                _ => S::<B>::zero(),
            })
        });
        let Some(k) = self.gain(&h, &v, &dz) else {
            return false;
        };
        let x: [S<B>; FDCL_DIM] =
            core::array::from_fn(|i| (0..6).fold(S::<B>::zero(), |s, j| s + k[i][j] * dz[j]));
        self.x = self.x + B::vec3(x[0], x[1], x[2]);
        self.v = self.v + B::vec3(x[3], x[4], x[5]);
        self.b_a += x[9];
        self.joseph(&h, &k, &v);
        true
    }

    /// `K = P Hᵀ (H P Hᵀ + V)⁻¹`, and the innovation `dz`'s normalised
    /// square kept as the last NIS.
    fn gain<const M: usize>(
        &mut self,
        h: &[[S<B>; FDCL_DIM]; M],
        v: &Mat<S<B>, M>,
        dz: &[S<B>; M],
    ) -> Option<[[S<B>; M]; FDCL_DIM]> {
        let ph = mul(&self.p, &transpose(h));
        let s = kalman::add::<S<B>, M, M>(&mul(h, &ph), v);
        let si = spd_inverse(&s)?;
        let nis = (0..M).fold(S::<B>::zero(), |a, i| {
            a + dz[i] * (0..M).fold(S::<B>::zero(), |b, j| b + si[i][j] * dz[j])
        });
        self.nis = Some((nis.to_f64_lossless(), M));
        for (slot, d) in self.innovation.iter_mut().zip(dz) {
            *slot = *d;
        }
        Some(mul(&ph, &si))
    }

    /// The last correction's normalised innovation squared and its degrees
    /// of freedom (3 for an attitude, 6 for a GPS fix).
    pub fn last_nis(&self) -> Option<(f64, usize)> {
        self.nis
    }

    /// `P ← (I − KH) P (I − KH)ᵀ + K V Kᵀ`.
    fn joseph<const M: usize>(
        &mut self,
        h: &[[S<B>; FDCL_DIM]; M],
        k: &[[S<B>; M]; FDCL_DIM],
        v: &Mat<S<B>, M>,
    ) {
        let kh = mul(k, h);
        let ikh: Mat<S<B>, FDCL_DIM> = core::array::from_fn(|i| {
            core::array::from_fn(|j| {
                if i == j {
                    S::<B>::one() - kh[i][j]
                } else {
                    -kh[i][j]
                }
            })
        });
        self.p = kalman::add::<S<B>, 10, 10>(
            &mul(&mul(&ikh, &self.p), &transpose(&ikh)),
            &mul(&mul(k, v), &transpose(k)),
        );
    }
}

impl<B: Backend> FdclEkf<B> {
    /// Measurements refused: non-finite, or an innovation covariance that
    /// was not positive definite.
    pub fn rejections(&self) -> u64 {
        self.rejected
    }

    /// One IMU sample as their `imu_callback` takes it: the acceleration
    /// without gravity in the IMU's frame, `f + R_WSᵀ g e3`, with the
    /// sample's own attitude output when it has one (else the estimate's
    /// `R R_bi`), the prediction over the time since the last sample, then
    /// the attitude correction.
    fn imu(&mut self, s: &crate::ImuSample<B>) -> bool {
        let att_ok = s.attitude.is_none_or(|r| ops::is_finite_mat::<B>(r));
        if !(ops::is_finite_vec::<B>(s.accel) && ops::is_finite_vec::<B>(s.gyro) && att_ok) {
            return false;
        }
        let r_ws = s.attitude.unwrap_or(self.r * self.r_bi);
        let ge3 = B::vec3(S::<B>::zero(), S::<B>::zero(), lit::<B>(self.cfg.gravity));
        let a_imu = s.accel + B::mat3_transpose(r_ws) * ge3;
        self.predict(s.t - self.t, a_imu, s.gyro);
        self.t = s.t;
        s.attitude.is_none_or(|r| self.correct_attitude(r))
    }
}

impl<B: Backend> Estimator<B> for FdclEkf<B> {
    fn name(&self) -> &'static str {
        "fdcl-ekf"
    }
    fn needs(&self) -> SensorSet {
        SensorSet {
            imu: true,
            gps: true,
            ..SensorSet::default()
        }
    }
    fn wants(&self) -> SensorSet {
        self.needs()
    }
    fn reset(&mut self, t: f64, initial: &NavState<B>) {
        self.reset_to(initial.x, initial.v, initial.r);
        self.t = t;
    }
    fn update(&mut self, m: &Measurement<B>) {
        let ok = match m {
            Measurement::Imu(s) => self.imu(s),
            Measurement::Gps(g) if ops::is_finite_vec::<B>(g.x) && ops::is_finite_vec::<B>(g.v) => {
                self.correct_gps(g.x, g.v)
            }
            Measurement::Gps(_) => false,
            _ => true,
        };
        if !ok {
            self.rejected += 1;
        }
    }
    fn diagnostics(&self) -> Option<crate::Diagnostics> {
        let d = (0..FDCL_DIM).map(|i| self.p[i][i].to_f64_lossless());
        let n = self.nis.map_or(0, |(_, k)| k);
        let innovation = self.innovation[..n].iter().map(|v| v.to_f64_lossless());
        Some(crate::Diagnostics::of_diagonal(d, self.nis).with_innovation(innovation))
    }
    fn estimate(&self, _t: f64) -> NavState<B> {
        NavState {
            x: self.x,
            v: self.v,
            r: self.r,
            omega: self.w,
        }
    }
}
