//! The IMU: specific force and body rates at a mounted point, with the
//! errors of a real part.

use lie::{Backend, M3, Real, S, V3, ops};

use crate::NoiseKey;
use crate::error::{SensorError, setting};

/// The errors of one triad (the accelerometer's three axes, or the
/// gyroscope's), in the triad's units (m/s² or rad/s). A reading is
/// `(I + scale_misalignment)·true + bias + noise`, each axis then clamped
/// to `±range`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriadErrors {
    /// White noise density N, units/√Hz: a sample at rate f has
    /// σ = N·√f per axis (the Allan-variance and Kalibr convention: the
    /// Allan deviation of this noise is N at τ = 1 s).
    pub noise_density: f64,
    /// Bias random walk K, units/s/√Hz (= units/√s): the bias moves by
    /// K·√Δt·ξ from one sample to the next (Allan deviation K·√(τ/3)).
    pub random_walk: f64,
    /// Standard deviation of the constant bias each axis starts with,
    /// units.
    pub turn_on_bias: f64,
    /// Scale-factor errors on the diagonal, axis misalignment and
    /// cross-coupling off it (dimensionless; zero for an ideal triad).
    pub scale_misalignment: [[f64; 3]; 3],
    /// The largest magnitude an axis reads, units (`f64::INFINITY` for
    /// none).
    pub range: f64,
}

impl TriadErrors {
    /// No errors at all.
    pub const NONE: Self = Self {
        noise_density: 0.0,
        random_walk: 0.0,
        turn_on_bias: 0.0,
        scale_misalignment: [[0.0; 3]; 3],
        range: f64::INFINITY,
    };

    /// White noise of density `n` alone.
    pub const fn white(n: f64) -> Self {
        Self {
            noise_density: n,
            ..Self::NONE
        }
    }
}

/// An IMU: where it sits, how it is turned, how often it samples, and the
/// errors of its two triads.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuSpec {
    /// Sample rate, Hz: sample `k` is taken at `t = k / rate`.
    pub rate: f64,
    /// The sensor's position `p` in the body frame, m.
    pub position: [f64; 3],
    /// `R_BS` by rows: its columns are the sensor's axes in the body frame
    /// (the identity for an IMU aligned with the body).
    pub mounting: [[f64; 3]; 3],
    /// The accelerometer's errors, m/s².
    pub accel: TriadErrors,
    /// The gyroscope's errors, rad/s.
    pub gyro: TriadErrors,
    /// An attitude output, as an AHRS gives it (the FDCL lab's VectorNav):
    /// the sensor's axes in the world, `R R_BS Exp(η)` with `η` of this σ
    /// per axis, rad; `None`: rates and specific force only.
    pub attitude_sigma: Option<f64>,
}

/// The true motion at a sample instant, from the dynamics: what an IMU
/// reads is a function of these and of gravity.
#[derive(Clone, Copy, Debug)]
pub struct Kinematics<B: Backend> {
    /// Attitude `R` (body to world).
    pub r: M3<B>,
    /// Body rates `Ω`, rad/s.
    pub omega: V3<B>,
    /// World acceleration of the centre of mass `a = v̇`, m/s² (`e3` down).
    pub accel: V3<B>,
    /// Body angular acceleration `α = Ω̇`, rad/s².
    pub alpha: V3<B>,
}

impl<B: Backend> Kinematics<B> {
    /// Level and at rest.
    pub fn at_rest() -> Self {
        let (z, o) = (S::<B>::lit(0.0), S::<B>::lit(1.0));
        let zero = B::vec3(z, z, z);
        Self {
            r: ops::diag::<B>(o, o, o),
            omega: zero,
            accel: zero,
            alpha: zero,
        }
    }
}

/// One IMU sample: sample `k` at `t = k / rate`, in the sensor's axes.
#[derive(Clone, Copy, Debug)]
pub struct ImuSample<B: Backend> {
    /// Its index.
    pub k: u64,
    /// Its time, s.
    pub t: f64,
    /// Specific force, m/s².
    pub accel: V3<B>,
    /// Angular rate, rad/s.
    pub gyro: V3<B>,
    /// The sensor's attitude (sensor axes to world) from an AHRS output,
    /// if the IMU has one.
    pub attitude: Option<M3<B>>,
}

/// An IMU in a run: its spec, its noise key and the state of its bias
/// random walk.
#[derive(Clone, Debug)]
pub struct Imu<B: Backend> {
    spec: ImuSpec,
    key: NoiseKey,
    p: V3<B>,
    r_bs: M3<B>,
    accel_gain: M3<B>,
    gyro_gain: M3<B>,
    /// Per-sample white-noise σ and walk step, accelerometer then gyro.
    sigma: [f64; 2],
    step: [f64; 2],
    /// The biases at sample `next − 1` (the turn-on bias before any).
    bias: [[f64; 3]; 2],
    next: u64,
}

// Pairs of normals a sample draws from its key: white noise, the walk's
// steps; the turn-on bias from sample 0's last three pairs.
const WHITE: u64 = 0;
const WALK: u64 = 3;
const TURN_ON: u64 = 6;
// The attitude output's three normals: pairs 9 and 10.
const ATTITUDE: u64 = 9;

impl<B: Backend> Imu<B> {
    /// The IMU of `spec` drawing its noise from `key`; `spec` checked
    /// first ([`ImuSpec::validate`]).
    pub fn new(spec: ImuSpec, key: NoiseKey) -> Result<Self, SensorError> {
        spec.validate()?;
        let m = |rows: [[f64; 3]; 3], plus_identity: bool| {
            let e = |i: usize, j: usize| {
                let d = if plus_identity && i == j { 1.0 } else { 0.0 };
                S::<B>::lit(rows[i][j] + d)
            };
            B::mat3_from_cols(
                B::vec3(e(0, 0), e(1, 0), e(2, 0)),
                B::vec3(e(0, 1), e(1, 1), e(2, 1)),
                B::vec3(e(0, 2), e(1, 2), e(2, 2)),
            )
        };
        let [px, py, pz] = spec.position.map(S::<B>::lit);
        let dt = 1.0 / spec.rate;
        let on = key.six(0, TURN_ON);
        let b0 = |c: usize, sd: f64| core::array::from_fn(|i| sd * on[3 * c + i]);
        Ok(Self {
            key,
            p: B::vec3(px, py, pz),
            r_bs: m(spec.mounting, false),
            accel_gain: m(spec.accel.scale_misalignment, true),
            gyro_gain: m(spec.gyro.scale_misalignment, true),
            sigma: [spec.accel, spec.gyro].map(|e| e.noise_density * Real::sqrt(spec.rate)),
            step: [spec.accel, spec.gyro].map(|e| e.random_walk * Real::sqrt(dt)),
            bias: [
                b0(0, spec.accel.turn_on_bias),
                b0(1, spec.gyro.turn_on_bias),
            ],
            next: 0,
            spec,
        })
    }

    /// The spec it was built with.
    pub fn spec(&self) -> &ImuSpec {
        &self.spec
    }

    /// The time of sample `k`, s (`k / rate`: a product, never a sum).
    pub fn time_of(&self, k: u64) -> f64 {
        k as f64 / self.spec.rate
    }

    /// The error-free reading of `kin` under gravity `g` (m/s², along
    /// `+e3`): specific force and rates in the sensor's axes.
    pub fn ideal(&self, kin: &Kinematics<B>, g: S<B>) -> (V3<B>, V3<B>) {
        let z = S::<B>::lit(0.0);
        let specific = B::mat3_tr_mul_vec(kin.r, kin.accel - B::vec3(z, z, g))
            + B::cross(kin.alpha, self.p)
            + B::cross(kin.omega, B::cross(kin.omega, self.p));
        (
            B::mat3_tr_mul_vec(self.r_bs, specific),
            B::mat3_tr_mul_vec(self.r_bs, kin.omega),
        )
    }

    /// Sample `k` of the motion `kin` under gravity `g`. Samples go
    /// forward: `k` at least the last one's index plus one (the bias walk
    /// steps through any skipped in between, so sample `k` is the same
    /// whichever earlier samples were taken).
    pub fn sample(
        &mut self,
        k: u64,
        kin: &Kinematics<B>,
        g: S<B>,
    ) -> Result<ImuSample<B>, SensorError> {
        if k < self.next {
            return Err(SensorError::OutOfOrder { k, next: self.next });
        }
        if self.step != [0.0; 2] {
            for j in self.next.max(1)..=k {
                let n = self.key.six(j, WALK);
                for (c, b) in self.bias.iter_mut().enumerate() {
                    for (i, b) in b.iter_mut().enumerate() {
                        *b += self.step[c] * n[3 * c + i];
                    }
                }
            }
        }
        self.next = k + 1;
        let (accel, gyro) = self.ideal(kin, g);
        let white = if self.sigma == [0.0; 2] {
            [0.0; 6]
        } else {
            self.key.six(k, WHITE)
        };
        let read = |c: usize, gain: M3<B>, v: V3<B>, range: f64| {
            let add: [S<B>; 3] = core::array::from_fn(|i| {
                S::<B>::lit(self.bias[c][i] + self.sigma[c] * white[3 * c + i])
            });
            let raw = B::vec3_to_array(B::mat3_mul_vec(gain, v) + B::vec3(add[0], add[1], add[2]));
            let r = S::<B>::lit(range);
            let [x, y, z] = raw.map(|x| x.min(r).max(-r));
            B::vec3(x, y, z)
        };
        let attitude = self.spec.attitude_sigma.map(|sigma| {
            let [a, b] = self.key.pair(k, ATTITUDE);
            let [c, _] = self.key.pair(k, ATTITUDE + 1);
            let eta = B::vec3(
                S::<B>::lit(sigma * a),
                S::<B>::lit(sigma * b),
                S::<B>::lit(sigma * c),
            );
            kin.r * self.r_bs * lie::So3Mat::<B>::exp(eta).as_matrix()
        });
        Ok(ImuSample {
            k,
            t: self.time_of(k),
            accel: read(0, self.accel_gain, accel, self.spec.accel.range),
            gyro: read(1, self.gyro_gain, gyro, self.spec.gyro.range),
            attitude,
        })
    }

    /// The biases after the last sample (the turn-on biases before the
    /// first), accelerometer then gyroscope.
    pub fn biases(&self) -> [[f64; 3]; 2] {
        self.bias
    }
}

impl ImuSpec {
    /// Every field in range: a positive finite rate, a finite position, a
    /// mounting that is a rotation (orthonormal to 1e-9, determinant +1),
    /// and for each triad densities and biases finite and not negative, a
    /// finite scale and misalignment matrix, a positive range (∞ allowed).
    pub fn validate(&self) -> Result<(), SensorError> {
        if !(self.rate.is_finite() && self.rate > 0.0) {
            return Err(setting("rate", self.rate, "a positive finite rate in Hz"));
        }
        if let Some(&x) = self.position.iter().find(|x| !x.is_finite()) {
            return Err(setting("position", x, "finite (m, body frame)"));
        }
        check_rotation(&self.mounting)?;
        if let Some(sigma) = self.attitude_sigma
            && !(sigma.is_finite() && sigma >= 0.0)
        {
            return Err(setting(
                "attitude_sigma",
                sigma,
                "finite and not negative (rad)",
            ));
        }
        check_triad(&self.accel, ACCEL_FIELDS)?;
        check_triad(&self.gyro, GYRO_FIELDS)
    }

    /// The same IMU without errors of any kind: what it would read.
    pub fn noiseless(self) -> Self {
        Self {
            accel: TriadErrors::NONE,
            gyro: TriadErrors::NONE,
            attitude_sigma: self.attitude_sigma.map(|_| 0.0),
            ..self
        }
    }
}

const ACCEL_FIELDS: [&str; 5] = [
    "accel.noise_density",
    "accel.random_walk",
    "accel.turn_on_bias",
    "accel.scale_misalignment",
    "accel.range",
];
const GYRO_FIELDS: [&str; 5] = [
    "gyro.noise_density",
    "gyro.random_walk",
    "gyro.turn_on_bias",
    "gyro.scale_misalignment",
    "gyro.range",
];

fn check_triad(e: &TriadErrors, names: [&'static str; 5]) -> Result<(), SensorError> {
    for (v, name) in [e.noise_density, e.random_walk, e.turn_on_bias]
        .into_iter()
        .zip(names)
    {
        if !(v.is_finite() && v >= 0.0) {
            return Err(setting(name, v, "finite and not negative"));
        }
    }
    if let Some(&x) = e
        .scale_misalignment
        .as_flattened()
        .iter()
        .find(|x| !x.is_finite())
    {
        return Err(setting(names[3], x, "finite"));
    }
    if e.range.is_nan() || e.range <= 0.0 {
        return Err(setting(
            names[4],
            e.range,
            "positive (f64::INFINITY for no limit)",
        ));
    }
    Ok(())
}

fn check_rotation(m: &[[f64; 3]; 3]) -> Result<(), SensorError> {
    let expected = "a rotation matrix (orthonormal rows, determinant +1)";
    if let Some(&x) = m.as_flattened().iter().find(|x| !x.is_finite()) {
        return Err(setting("mounting", x, expected));
    }
    for i in 0..3 {
        for j in 0..3 {
            let d: f64 = (0..3).map(|k| m[i][k] * m[j][k]).sum();
            let want = if i == j { 1.0 } else { 0.0 };
            if (d - want).abs() > 1e-9 {
                return Err(setting("mounting", m[i][j], expected));
            }
        }
    }
    let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
        - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
        + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
    if det < 0.0 {
        return Err(setting("mounting", det, expected));
    }
    Ok(())
}
