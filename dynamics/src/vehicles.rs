//! The shipped vehicles.

use crate::paper;
use lie::num_traits::Zero;
use lie::{Backend, M3, Real, S, V3, ops};

use crate::{
    Actuators, Capabilities, ConfigurationMoment, Disturbance, DynamicsError, LoadInput, Loads,
    RigidBodyState, Vehicle, Wrench, body_loads, check_inertia, check_positive,
};

/// Per-rotor thrust limits, N. The paper's model allows signed thrust, so
/// its scenes run without limits; a real vehicle has `0 ≤ f_i ≤ f_max`.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RotorLimits<B: Backend> {
    /// Lowest thrust a rotor can make.
    pub min: S<B>,
    /// Highest thrust a rotor can make.
    pub max: S<B>,
}

/// What the quadrotor and the hexarotor share: `N` rotor thrusts mapped to
/// the wrench through a 4×`N` allocation (rows `f, M1, M2, M3`), checked
/// on the way in and out, clamped to per-rotor limits.
mod rotors {
    use super::RotorLimits;
    use crate::{DynamicsError, Wrench};
    use lie::Real;
    use lie::{Backend, S};

    /// The wrench of thrusts `f` under allocation `a`, each row summed left
    /// to right from its first product.
    #[inline(always)]
    pub(super) fn wrench<B: Backend, const N: usize>(
        a: &[[S<B>; N]; 4],
        f: &[S<B>; N],
    ) -> Wrench<B> {
        let row = |r: &[S<B>; N]| (1..N).fold(r[0] * f[0], |acc, k| acc + r[k] * f[k]);
        Wrench {
            thrust: row(&a[0]),
            moment: B::vec3(row(&a[1]), row(&a[2]), row(&a[3])),
        }
    }

    /// `u` as `N` finite rotor thrusts.
    #[inline]
    pub(super) fn read<B: Backend, const N: usize>(u: &[S<B>]) -> Result<[S<B>; N], DynamicsError> {
        let f: [S<B>; N] = u.try_into().map_err(|_| DynamicsError::ActuatorCount {
            expected: N,
            got: u.len(),
        })?;
        if f.iter().any(|x| !x.is_finite()) {
            return Err(DynamicsError::NonFinite {
                field: "rotor thrusts",
            });
        }
        Ok(f)
    }

    /// Writes `f` into `out`, which must hold exactly `N` thrusts.
    #[inline]
    pub(super) fn write<B: Backend, const N: usize>(
        out: &mut [S<B>],
        f: &[S<B>; N],
    ) -> Result<(), DynamicsError> {
        if out.len() != N {
            return Err(DynamicsError::ActuatorCount {
                expected: N,
                got: out.len(),
            });
        }
        out.copy_from_slice(f);
        Ok(())
    }

    /// Each thrust clamped to `[min, max]`.
    #[inline]
    pub(super) fn clamp<B: Backend, const N: usize>(f: [S<B>; N], l: RotorLimits<B>) -> [S<B>; N] {
        f.map(|x| x.max(l.min).min(l.max))
    }
}

/// The paper's quadrotor (Section II): rotors 1–4 on the body axes `+b1`,
/// `+b2`, `−b1`, `−b2` at arm length `d`, alternating spin directions with
/// reaction-torque coefficient `c_τf`, fixed disturbances `Δ_x`, `Δ_R`.
///
/// Allocation, rotor thrusts `f1..f4` to `(f, M1, M2, M3)` (the paper's allocation):
/// ```text
/// [ 1    1    1    1  ]
/// [ 0   −d    0    d  ]
/// [ d    0   −d    0  ]
/// [−c    c   −c    c  ]      det = 8 c d²
/// ```
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Quadrotor<B: Backend> {
    mass: S<B>,
    inertia: M3<B>,
    gravity: S<B>,
    arm: S<B>,
    c_tau_f: S<B>,
    disturbance: Option<Disturbance<B>>,
    limits: Option<RotorLimits<B>>,
}

impl<B: Backend> Quadrotor<B> {
    /// A quadrotor with validated parameters: `mass > 0`, `inertia`
    /// symmetric positive definite, `gravity ≥ 0`, `arm > 0`, `c_tau_f ≠ 0`
    /// (the allocation is singular otherwise).
    pub fn new(
        mass: S<B>,
        inertia: M3<B>,
        gravity: S<B>,
        arm: S<B>,
        c_tau_f: S<B>,
    ) -> Result<Self, DynamicsError> {
        check_positive("mass", mass)?;
        check_inertia::<B>(inertia)?;
        if !gravity.is_finite() || gravity < S::<B>::zero() {
            return Err(DynamicsError::InvalidParameter {
                field: "gravity",
                value: gravity.to_f64_lossless(),
                expected: "a finite value ≥ 0",
            });
        }
        check_positive("arm", arm)?;
        if !c_tau_f.is_finite() || c_tau_f == S::<B>::zero() {
            return Err(DynamicsError::InvalidParameter {
                field: "c_tau_f",
                value: c_tau_f.to_f64_lossless(),
                expected: "a finite non-zero value (the allocation is singular at 0)",
            });
        }
        Ok(Self {
            mass,
            inertia,
            gravity,
            arm,
            c_tau_f,
            disturbance: None,
            limits: None,
        })
    }

    /// The paper's numerical example: m = 0.755 kg,
    /// J = diag(0.43, 0.43, 1.02)·10⁻² kg m², d = 0.169 m, c_τf = 0.0132 m,
    /// g = 9.81 m/s², no disturbance (add [`Quadrotor::paper_disturbance`]
    /// with [`Quadrotor::with_disturbance`]).
    pub fn paper() -> Self {
        let l = S::<B>::lit;
        Self::new(
            l(paper::MASS),
            ops::diag::<B>(
                l(paper::INERTIA[0]),
                l(paper::INERTIA[1]),
                l(paper::INERTIA[2]),
            ),
            l(paper::GRAVITY),
            l(paper::ARM),
            l(paper::C_TAU_F),
        )
        .expect("the paper's parameters are valid")
    }

    /// The paper's fixed disturbances Δ_x = [−0.5, 0.2, 1] N,
    /// Δ_R = [0.2, −0.1, −0.02] N m.
    pub fn paper_disturbance() -> Disturbance<B> {
        let l = S::<B>::lit;
        let ([f1, f2, f3], [m1, m2, m3]) = (paper::DELTA_X, paper::DELTA_R);
        Disturbance {
            force: B::vec3(l(f1), l(f2), l(f3)),
            moment: B::vec3(l(m1), l(m2), l(m3)),
        }
    }

    /// The same vehicle with a constant disturbance.
    pub fn with_disturbance(mut self, d: Disturbance<B>) -> Result<Self, DynamicsError> {
        if !ops::is_finite_vec::<B>(d.force) {
            return Err(DynamicsError::NonFinite {
                field: "disturbance.force",
            });
        }
        if !ops::is_finite_vec::<B>(d.moment) {
            return Err(DynamicsError::NonFinite {
                field: "disturbance.moment",
            });
        }
        self.disturbance = Some(d);
        Ok(self)
    }

    /// The same vehicle with per-rotor thrust limits (`min < max`).
    pub fn with_rotor_limits(mut self, limits: RotorLimits<B>) -> Result<Self, DynamicsError> {
        if !limits.min.is_finite() || !limits.max.is_finite() || limits.min >= limits.max {
            return Err(DynamicsError::InvalidParameter {
                field: "rotor_limits",
                value: (limits.max - limits.min).to_f64_lossless(),
                expected: "finite min < max (this is max − min)",
            });
        }
        self.limits = Some(limits);
        Ok(self)
    }

    /// Arm length `d`, m.
    pub fn arm(&self) -> S<B> {
        self.arm
    }

    /// Reaction-torque coefficient `c_τf`, m.
    pub fn c_tau_f(&self) -> S<B> {
        self.c_tau_f
    }

    /// The fixed disturbance, if any.
    pub fn fixed_disturbance(&self) -> Option<Disturbance<B>> {
        self.disturbance
    }

    /// The allocation matrix, rows `(f, M1, M2, M3)`, columns rotors 1–4.
    pub fn allocation(&self) -> [[S<B>; 4]; 4] {
        let (d, c, o, z) = (self.arm, self.c_tau_f, S::<B>::lit(1.0), S::<B>::zero());
        [[o, o, o, o], [z, -d, z, d], [d, z, -d, z], [-c, c, -c, c]]
    }

    /// Rotor thrusts from a wrench: the closed-form inverse of
    /// [`Quadrotor::allocation`].
    pub fn rotor_thrusts(&self, w: &Wrench<B>) -> [S<B>; 4] {
        let half = S::<B>::lit(0.5);
        let [m1, m2, m3] = B::vec3_to_array(w.moment);
        let yaw = m3 / self.c_tau_f;
        // f1 + f3 = (f − M3/c)/2, f2 + f4 = (f + M3/c)/2,
        // f1 − f3 = M2/d,         f4 − f2 = M1/d.
        let s13 = (w.thrust - yaw) * half;
        let s24 = (w.thrust + yaw) * half;
        let d13 = m2 / self.arm;
        let d42 = m1 / self.arm;
        [
            (s13 + d13) * half,
            (s24 - d42) * half,
            (s13 - d13) * half,
            (s24 + d42) * half,
        ]
    }

    fn wrench_of(&self, f: [S<B>; 4]) -> Wrench<B> {
        rotors::wrench(&self.allocation(), &f)
    }
}

impl<B: Backend> Vehicle<B> for Quadrotor<B> {
    fn name(&self) -> &str {
        "quadrotor"
    }
    fn mass(&self) -> S<B> {
        self.mass
    }
    fn inertia(&self) -> M3<B> {
        self.inertia
    }
    fn gravity(&self) -> S<B> {
        self.gravity
    }
    fn actuator_count(&self) -> usize {
        4
    }
    fn wrench_from_actuators(&self, u: &[S<B>]) -> Result<Wrench<B>, DynamicsError> {
        Ok(self.wrench_of(rotors::read::<B, _>(u)?))
    }
    fn actuators_from_wrench(&self, w: &Wrench<B>, out: &mut [S<B>]) -> Result<(), DynamicsError> {
        rotors::write::<B, _>(out, &self.rotor_thrusts(w))
    }
    /// The paper's vehicle: gravity, the delivered thrust and moment, the
    /// fixed disturbance (Δ_x, Δ_R); it takes no rotor speeds.
    #[inline]
    fn loads(
        &self,
        _t: S<B>,
        state: &RigidBodyState<B>,
        input: LoadInput<'_, B>,
        _rates: &mut [S<B>],
    ) -> Option<Loads<B>> {
        let w = input.wrench_command()?;
        Some(body_loads(self, state, self.saturate(w), self.disturbance))
    }
    fn capabilities(&self) -> Capabilities<'_, B> {
        Capabilities::RIGID.with_actuators(self)
    }
}

impl<B: Backend> Actuators<B> for Quadrotor<B> {
    /// Within the rotor limits ([`Quadrotor::saturate`]); no lag.
    fn delivered(&self, command: &Wrench<B>, _states: &[S<B>]) -> Wrench<B> {
        self.saturate(*command)
    }
}

impl<B: Backend> Quadrotor<B> {
    /// The wrench the rotors deliver when `w` is commanded: each rotor's
    /// thrust clamped to the limits and mapped back; a plain clamp (no
    /// priority to attitude over thrust), which is what the hardware does
    /// when the mixer is naive. The identity without limits.
    pub fn saturate(&self, w: Wrench<B>) -> Wrench<B> {
        match self.limits {
            None => w,
            Some(l) => self.wrench_of(rotors::clamp(self.rotor_thrusts(&w), l)),
        }
    }
}

/// The paper's attitude test stand (Section VI): the quadrotor mounted on a
/// spherical joint whose centre lies a height `l` *below* its centre of
/// gravity, so the body cannot translate and gravity tips it over — an
/// inverted 3D pendulum with moment `M_g = m g ρ × Rᵀe3`, `ρ = −l e3` (the
/// centre of gravity in body coordinates, measured from the pivot; e3 is
/// down, so `−l e3` is above).
///
/// The inertia about the pivot is `J + m(|ρ|² I − ρρᵀ)` (parallel axes).
/// The thrust acts through the centre of gravity along `−b3`, parallel to
/// `ρ`, so it adds no moment about the pivot. A controller cancels the
/// destabilising moment by adding `−M_g` ([`AttitudeStand::gravity_moment`])
/// to its command, the compensation term the paper adds for its experiment.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct AttitudeStand<B: Backend> {
    quad: Quadrotor<B>,
    height: S<B>,
    inertia_pivot: M3<B>,
}

impl<B: Backend> AttitudeStand<B> {
    /// `quad` on a pivot `height` metres below its centre of gravity
    /// (`height ≥ 0`; 0 puts the pivot at the centre of gravity and removes
    /// the gravity moment).
    pub fn new(quad: Quadrotor<B>, height: S<B>) -> Result<Self, DynamicsError> {
        if !height.is_finite() || height < S::<B>::zero() {
            return Err(DynamicsError::InvalidParameter {
                field: "height",
                value: height.to_f64_lossless(),
                expected: "a finite value ≥ 0 (metres of the centre of gravity above the pivot)",
            });
        }
        let m = quad.mass;
        let rho = Self::rho_of(height);
        let rr = B::dot(rho, rho);
        let [r0, r1, r2] = B::vec3_to_array(rho);
        let outer = B::mat3_from_cols(rho * r0, rho * r1, rho * r2);
        let inertia_pivot = quad.inertia + (ops::identity::<B>() * rr - outer) * m;
        Ok(Self {
            quad,
            height,
            inertia_pivot,
        })
    }

    fn rho_of(height: S<B>) -> V3<B> {
        let z = S::<B>::zero();
        B::vec3(z, z, -height)
    }

    /// The centre of gravity relative to the pivot, body frame.
    pub fn rho(&self) -> V3<B> {
        Self::rho_of(self.height)
    }

    /// The quadrotor on the stand.
    pub fn quadrotor(&self) -> &Quadrotor<B> {
        &self.quad
    }

    /// Gravity moment about the pivot at attitude `r`, body frame:
    /// `m g ρ × Rᵀe3`. Zero upright, growing like `sin(tilt)`.
    pub fn gravity_moment(&self, r: M3<B>) -> V3<B> {
        let z = S::<B>::zero();
        let down_body = B::mat3_tr_mul_vec(r, B::vec3(z, z, S::<B>::lit(1.0)));
        B::cross(self.rho(), down_body) * (self.quad.mass * self.quad.gravity)
    }
}

impl<B: Backend> Vehicle<B> for AttitudeStand<B> {
    fn name(&self) -> &str {
        "attitude-stand"
    }
    fn mass(&self) -> S<B> {
        self.quad.mass
    }
    fn inertia(&self) -> M3<B> {
        self.inertia_pivot
    }
    fn gravity(&self) -> S<B> {
        self.quad.gravity
    }
    fn actuator_count(&self) -> usize {
        4
    }
    fn wrench_from_actuators(&self, u: &[S<B>]) -> Result<Wrench<B>, DynamicsError> {
        self.quad.wrench_from_actuators(u)
    }
    fn actuators_from_wrench(&self, w: &Wrench<B>, out: &mut [S<B>]) -> Result<(), DynamicsError> {
        self.quad.actuators_from_wrench(w, out)
    }
    /// The quadrotor's loads about the pivot: no force (the joint holds
    /// the body), the delivered moment, Δ_R and gravity's moment.
    #[inline]
    fn loads(
        &self,
        _t: S<B>,
        state: &RigidBodyState<B>,
        input: LoadInput<'_, B>,
        _rates: &mut [S<B>],
    ) -> Option<Loads<B>> {
        let w = input.wrench_command()?;
        Some(body_loads(
            self,
            state,
            self.quad.saturate(w),
            self.quad.fixed_disturbance(),
        ))
    }
    fn capabilities(&self) -> Capabilities<'_, B> {
        let caps = Capabilities::RIGID
            .translating(false)
            .with_actuators(&self.quad);
        if self.height == S::<B>::zero() {
            caps
        } else {
            caps.with_configuration_moment(self)
        }
    }
}

impl<B: Backend> ConfigurationMoment<B> for AttitudeStand<B> {
    /// Gravity about the pivot, [`AttitudeStand::gravity_moment`].
    fn moment(&self, state: &RigidBodyState<B>) -> V3<B> {
        self.gravity_moment(state.r)
    }
}

/// A torque-free rigid body for integrator tests: no actuators, no gravity,
/// no translation. Its energy `½ΩᵀJΩ` and spatial angular momentum `RJΩ` are
/// conserved; [`crate::free_body::ExactFreeBody`] is its exact solution for a
/// diagonal inertia.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FreeRigidBody<B: Backend> {
    inertia: M3<B>,
}

impl<B: Backend> FreeRigidBody<B> {
    /// A free body with the given inertia (symmetric positive definite).
    pub fn new(inertia: M3<B>) -> Result<Self, DynamicsError> {
        check_inertia::<B>(inertia)?;
        Ok(Self { inertia })
    }

    /// `J = diag(1, 2, 3)`, the usual test body.
    pub fn diag123() -> Self {
        let l = S::<B>::lit;
        Self {
            inertia: ops::diag::<B>(l(1.0), l(2.0), l(3.0)),
        }
    }
}

impl<B: Backend> Vehicle<B> for FreeRigidBody<B> {
    fn name(&self) -> &str {
        "free-rigid-body"
    }
    fn mass(&self) -> S<B> {
        S::<B>::lit(1.0)
    }
    fn inertia(&self) -> M3<B> {
        self.inertia
    }
    fn gravity(&self) -> S<B> {
        S::<B>::zero()
    }
    fn actuator_count(&self) -> usize {
        0
    }
    fn wrench_from_actuators(&self, u: &[S<B>]) -> Result<Wrench<B>, DynamicsError> {
        if !u.is_empty() {
            return Err(DynamicsError::ActuatorCount {
                expected: 0,
                got: u.len(),
            });
        }
        Ok(Wrench::zero())
    }
    fn actuators_from_wrench(&self, _w: &Wrench<B>, out: &mut [S<B>]) -> Result<(), DynamicsError> {
        if !out.is_empty() {
            return Err(DynamicsError::ActuatorCount {
                expected: 0,
                got: out.len(),
            });
        }
        Ok(())
    }
    fn capabilities(&self) -> Capabilities<'_, B> {
        Capabilities::RIGID.translating(false)
    }
}

/// A flat hexarotor: six rotors at angles `θ_k = k·60°` (k = 0…5, rotor 1
/// on `+b1`) and arm length `d`, spins alternating so that rotor k's reaction
/// torque is `(−1)^(k+1) c_τf f_k` (rotor 1 like the quadrotor's rotor 1).
/// Rotor k at `d(cos θ_k, sin θ_k, 0)` thrusting along `−b3` gives
/// `M1 = −d sin θ_k f_k`, `M2 = d cos θ_k f_k` — the quadrotor's rows are the
/// same formula at θ = 0°, 90°, 180°, 270°.
///
/// With six actuators for four wrench components the allocation inverse is
/// not unique; [`Vehicle::actuators_from_wrench`] returns the minimum-norm
/// rotor thrusts `Aᵀ(AAᵀ)⁻¹w`, and for this symmetric layout
/// `AAᵀ = diag(6, 3d², 3d², 6c²)`, so it is closed form.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Hexarotor<B: Backend> {
    base: Quadrotor<B>,
}

impl<B: Backend> Hexarotor<B> {
    /// A hexarotor with the same parameters (and validation) as
    /// [`Quadrotor::new`].
    pub fn new(
        mass: S<B>,
        inertia: M3<B>,
        gravity: S<B>,
        arm: S<B>,
        c_tau_f: S<B>,
    ) -> Result<Self, DynamicsError> {
        Ok(Self {
            base: Quadrotor::new(mass, inertia, gravity, arm, c_tau_f)?,
        })
    }

    /// The paper's airframe parameters on a six-rotor layout.
    pub fn paper() -> Self {
        Self {
            base: Quadrotor::paper(),
        }
    }

    /// The same vehicle with a constant disturbance.
    pub fn with_disturbance(self, d: Disturbance<B>) -> Result<Self, DynamicsError> {
        Ok(Self {
            base: self.base.with_disturbance(d)?,
        })
    }

    /// The same vehicle with per-rotor thrust limits.
    pub fn with_rotor_limits(self, limits: RotorLimits<B>) -> Result<Self, DynamicsError> {
        Ok(Self {
            base: self.base.with_rotor_limits(limits)?,
        })
    }

    /// The 4×6 allocation matrix, rows `(f, M1, M2, M3)`.
    #[allow(clippy::needless_range_loop)] // k is the rotor index in θ_k
    pub fn allocation(&self) -> [[S<B>; 6]; 4] {
        let (d, c) = (self.base.arm, self.base.c_tau_f);
        let mut a = [[S::<B>::zero(); 6]; 4];
        for k in 0..6 {
            let th = S::<B>::lit(core::f64::consts::FRAC_PI_3 * k as f64);
            let spin = if k % 2 == 0 { -c } else { c };
            a[0][k] = S::<B>::lit(1.0);
            a[1][k] = -d * th.sin();
            a[2][k] = d * th.cos();
            a[3][k] = spin;
        }
        a
    }

    /// Minimum-norm rotor thrusts for `w`.
    pub fn rotor_thrusts(&self, w: &Wrench<B>) -> [S<B>; 6] {
        let a = self.allocation();
        let (d, c) = (self.base.arm, self.base.c_tau_f);
        let [m1, m2, m3] = B::vec3_to_array(w.moment);
        let three_d2 = S::<B>::lit(3.0) * d * d;
        // (AAᵀ)⁻¹ w, then Aᵀ.
        let y = [
            w.thrust / S::<B>::lit(6.0),
            m1 / three_d2,
            m2 / three_d2,
            m3 / (S::<B>::lit(6.0) * c * c),
        ];
        core::array::from_fn(|k| a[0][k] * y[0] + a[1][k] * y[1] + a[2][k] * y[2] + a[3][k] * y[3])
    }

    fn wrench_of(&self, f: &[S<B>; 6]) -> Wrench<B> {
        rotors::wrench(&self.allocation(), f)
    }
}

impl<B: Backend> Vehicle<B> for Hexarotor<B> {
    fn name(&self) -> &str {
        "hexarotor"
    }
    fn mass(&self) -> S<B> {
        self.base.mass
    }
    fn inertia(&self) -> M3<B> {
        self.base.inertia
    }
    fn gravity(&self) -> S<B> {
        self.base.gravity
    }
    fn actuator_count(&self) -> usize {
        6
    }
    fn wrench_from_actuators(&self, u: &[S<B>]) -> Result<Wrench<B>, DynamicsError> {
        Ok(self.wrench_of(&rotors::read::<B, _>(u)?))
    }
    fn actuators_from_wrench(&self, w: &Wrench<B>, out: &mut [S<B>]) -> Result<(), DynamicsError> {
        rotors::write::<B, _>(out, &self.rotor_thrusts(w))
    }
    /// Gravity, the delivered thrust and moment, the fixed disturbance.
    #[inline]
    fn loads(
        &self,
        _t: S<B>,
        state: &RigidBodyState<B>,
        input: LoadInput<'_, B>,
        _rates: &mut [S<B>],
    ) -> Option<Loads<B>> {
        let w = input.wrench_command()?;
        Some(body_loads(
            self,
            state,
            self.saturate(w),
            self.base.fixed_disturbance(),
        ))
    }
    fn capabilities(&self) -> Capabilities<'_, B> {
        Capabilities::RIGID.with_actuators(self)
    }
}

impl<B: Backend> Actuators<B> for Hexarotor<B> {
    /// Within the rotor limits ([`Hexarotor::saturate`]); no lag.
    fn delivered(&self, command: &Wrench<B>, _states: &[S<B>]) -> Wrench<B> {
        self.saturate(*command)
    }
}

impl<B: Backend> Hexarotor<B> {
    /// The wrench the rotors deliver when `w` is commanded: the
    /// minimum-norm rotor thrusts clamped and mapped back (no
    /// redistribution through the null space). The identity without
    /// limits.
    pub fn saturate(&self, w: Wrench<B>) -> Wrench<B> {
        match self.base.limits {
            None => w,
            Some(l) => self.wrench_of(&rotors::clamp(self.rotor_thrusts(&w), l)),
        }
    }
}
