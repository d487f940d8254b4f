//! A multirotor with motors and aerodynamics: any number of rotors at given
//! positions and spin directions, rotor speeds as states with a first-order
//! motor lag and speed limits, and the drag, rotor-drag (H-force),
//! translational-lift and blade-flapping terms of the quasi-static rotor
//! model used by RotorPy's `Multirotor` (its parameter names are kept, so a
//! RotorPy parameter set carries over value for value).
//!
//! Frames: this crate's (inertial `e3` down, thrust along `−b3`). RotorPy is
//! z-up in both frames; the two are related by the rotation `P = diag(1, −1,
//! −1)` applied to the world and to the body, so a RotorPy rotor position
//! `(x, y, z)` is `(x, −y, −z)` here, and positions, velocities and rates
//! convert the same way (`R ↦ P R P`). The model in this frame, with
//! `v_a = Rᵀ(v − w)` the body-frame airspeed in wind `w`, `v_i = v_a + Ω × r_i`
//! the airspeed of hub `i` and `ω_i` its rotor speed:
//!
//! ```text
//! thrust_i = −(k_η ω_i² + k_h (v_i,x² + v_i,y²)) e3          (translational lift in k_h)
//! H_i      = −ω_i diag(k_d, k_d, k_z) v_i                     (rotor drag)
//! D        = −|v_a| diag(c_Dx, c_Dy, c_Dz) v_a                 (parasitic drag, at the CoM)
//! F_body   = Σ (thrust_i + H_i) + D
//! M_body   = Σ [ r_i × (thrust_i + H_i) − s_i k_m ω_i² e3 + k_flap ω_i (v_i × e3) ]
//! ω̇_i      = (clamp(ω_cmd,i) − ω_i) / τ_m
//! ```
//!
//! with `s_i = ±1` RotorPy's `rotor_directions` entry (its `+1` rotor has a
//! reaction moment along RotorPy's `+z`, which is `−e3` here).

use lie::num_traits::{One, Zero};
use lie::{Backend, M3, Real, S, V3, ops};

use crate::{
    Actuators, Capabilities, Command, Disturbance, DynamicsError, LoadInput, Loads, RigidBodyState,
    Vehicle, Wrench, check_inertia, check_positive,
};

/// The most rotors a [`Multirotor`] has: its evaluations keep rotor
/// values on the stack.
pub const MAX_ROTORS: usize = 16;

/// One rotor: hub position in the body frame (this crate's, `e3` down) and
/// RotorPy's spin-direction sign.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Rotor<B: Backend> {
    /// Hub position relative to the centre of mass, body frame, m.
    pub position: V3<B>,
    /// `+1` or `−1`, as RotorPy's `rotor_directions`.
    pub direction: S<B>,
}

/// The parameters of a [`Multirotor`], under RotorPy's names (SI units).
#[derive(Clone, Debug, PartialEq)]
pub struct MultirotorParams<B: Backend> {
    /// kg.
    pub mass: S<B>,
    /// Body-frame inertia about the centre of mass, kg m².
    pub inertia: M3<B>,
    /// m/s² (RotorPy uses 9.81).
    pub gravity: S<B>,
    /// The rotors.
    pub rotors: Vec<Rotor<B>>,
    /// Thrust coefficient, N/(rad/s)².
    pub k_eta: S<B>,
    /// Yaw-moment coefficient, N m/(rad/s)².
    pub k_m: S<B>,
    /// Rotor drag coefficient in the rotor plane, kg/rad.
    pub k_d: S<B>,
    /// Induced-inflow coefficient along the rotor axis, kg/rad.
    pub k_z: S<B>,
    /// Translational-lift coefficient, kg/m.
    pub k_h: S<B>,
    /// Flapping-moment coefficient, kg m/rad.
    pub k_flap: S<B>,
    /// Parasitic drag coefficients along the body axes, N/(m/s)².
    pub c_d: V3<B>,
    /// Motor time constant, s; 0 makes the rotors follow their commands at
    /// once (no rotor states).
    pub tau_m: S<B>,
    /// Lowest rotor speed, rad/s.
    pub rotor_speed_min: S<B>,
    /// Highest rotor speed, rad/s.
    pub rotor_speed_max: S<B>,
    /// Whether the aerodynamic terms (everything but `k_η ω²` and `k_m ω²`)
    /// are on, as RotorPy's `aero` flag.
    pub aero: bool,
}

impl<B: Backend> MultirotorParams<B> {
    /// Four rotors in the X configuration at `arm` from the centre, rotor 1
    /// front-right and on clockwise seen from above, directions `+1, −1,
    /// +1, −1` (RotorPy's quadrotor layout: its `r1 = d(½√2, ½√2, 0)` in its
    /// z-up frame is `d(½√2, −½√2, 0)` here).
    pub fn x_layout(arm: S<B>) -> Vec<Rotor<B>> {
        let h = arm * S::<B>::lit(core::f64::consts::FRAC_1_SQRT_2);
        let z = S::<B>::zero();
        [(h, -h, 1.0), (h, h, -1.0), (-h, h, 1.0), (-h, -h, -1.0)]
            .into_iter()
            .map(|(x, y, s)| Rotor {
                position: B::vec3(x, y, z),
                direction: S::<B>::lit(s),
            })
            .collect()
    }

    /// RotorPy 3.0.0's `crazyflie_params` (Bitcraze Crazyflie 2.0; inertia
    /// with `J3 > J1 + J2`, which no rigid body has, as identified).
    pub fn crazyflie() -> Self {
        let l = S::<B>::lit;
        Self {
            mass: l(0.03),
            inertia: ops::diag::<B>(l(1.43e-5), l(1.43e-5), l(2.89e-5)),
            gravity: l(9.81),
            rotors: Self::x_layout(l(0.043)),
            k_eta: l(2.3e-8),
            k_m: l(7.8e-10),
            k_d: l(10.2506e-7),
            k_z: l(7.553e-7),
            k_h: l(0.0),
            k_flap: l(0.0),
            c_d: B::vec3(l(0.0), l(0.0), l(0.0)),
            tau_m: l(0.072),
            rotor_speed_min: l(0.0),
            rotor_speed_max: l(2500.0),
            aero: true,
        }
    }

    /// RotorPy 3.0.0's `hummingbird_params` (AscTec Hummingbird).
    pub fn hummingbird() -> Self {
        let l = S::<B>::lit;
        Self {
            mass: l(0.5),
            inertia: ops::diag::<B>(l(3.65e-3), l(3.68e-3), l(7.03e-3)),
            gravity: l(9.81),
            rotors: Self::x_layout(l(0.17)),
            k_eta: l(5.57e-6),
            k_m: l(1.36e-7),
            k_d: l(1.19e-4),
            k_z: l(2.32e-4),
            k_h: l(3.39e-3),
            k_flap: l(0.0),
            c_d: B::vec3(l(0.5e-2), l(0.5e-2), l(1e-2)),
            tau_m: l(0.005),
            rotor_speed_min: l(0.0),
            rotor_speed_max: l(1500.0),
            aero: true,
        }
    }
}

/// A multirotor with motor lag and aerodynamics (see the module docs for
/// the model). Its actuators, as a [`Vehicle`], are rotor thrusts
/// `k_η ω_i²`; its internal states are the rotor speeds.
#[derive(Clone, Debug, PartialEq)]
pub struct Multirotor<B: Backend> {
    p: MultirotorParams<B>,
    disturbance: Option<Disturbance<B>>,
    /// Rows of the 4×n allocation `(f, M1, M2, M3) = A u` of rotor thrusts.
    alloc: [Vec<S<B>>; 4],
    /// Its minimum-norm inverse `Aᵀ(AAᵀ)⁻¹`, n rows of 4.
    alloc_inv: Vec<[S<B>; 4]>,
}

fn invalid(field: &'static str, value: f64, expected: &'static str) -> DynamicsError {
    DynamicsError::InvalidParameter {
        field,
        value,
        expected,
    }
}

impl<B: Backend> Multirotor<B> {
    /// Validates the parameters (positive mass, time constant ≥ 0, speeds
    /// `0 ≤ min < max`, positive `k_η` and `k_m`, drag coefficients ≥ 0,
    /// finite rotor positions, directions ±1, at least four rotors whose
    /// allocation has full rank) and builds the vehicle.
    pub fn new(p: MultirotorParams<B>) -> Result<Self, DynamicsError> {
        check_positive("mass", p.mass)?;
        check_inertia::<B>(p.inertia)?;
        check_positive("k_eta", p.k_eta)?;
        check_positive("k_m", p.k_m)?;
        check_positive("rotor_speed_max", p.rotor_speed_max)?;
        let nonneg = [
            ("gravity", p.gravity),
            ("k_d", p.k_d),
            ("k_z", p.k_z),
            ("k_h", p.k_h),
            ("k_flap", p.k_flap),
            ("tau_m", p.tau_m),
            ("rotor_speed_min", p.rotor_speed_min),
        ];
        let c = B::vec3_to_array(p.c_d);
        let drag = [("c_Dx", c[0]), ("c_Dy", c[1]), ("c_Dz", c[2])];
        for (field, v) in nonneg.into_iter().chain(drag) {
            if !v.is_finite() || v < S::<B>::zero() {
                return Err(invalid(field, v.to_f64_lossless(), "a finite value ≥ 0"));
            }
        }
        if p.rotor_speed_min >= p.rotor_speed_max {
            return Err(invalid(
                "rotor_speed_min",
                p.rotor_speed_min.to_f64_lossless(),
                "a value below rotor_speed_max",
            ));
        }
        if p.rotors.len() < 4 || p.rotors.len() > MAX_ROTORS {
            return Err(invalid(
                "rotors",
                p.rotors.len() as f64,
                "4 to 16 rotors (fewer cannot make an arbitrary moment and thrust; the \
                 per-evaluation buffers hold 16)",
            ));
        }
        for r in &p.rotors {
            if !ops::is_finite_vec::<B>(r.position) {
                return Err(DynamicsError::NonFinite {
                    field: "rotor position",
                });
            }
            if (r.direction.abs() - S::<B>::one()).abs() > S::<B>::zero() {
                return Err(invalid(
                    "rotor direction",
                    r.direction.to_f64_lossless(),
                    "+1 or -1",
                ));
            }
        }
        let alloc = allocation(&p);
        let alloc_inv = min_norm_inverse::<B>(&alloc)?;
        Ok(Self {
            p,
            disturbance: None,
            alloc,
            alloc_inv,
        })
    }

    /// Adds constant loads (the paper's `Δ_x`, inertial, and `Δ_R`, body).
    pub fn with_disturbance(mut self, d: Disturbance<B>) -> Self {
        self.disturbance = Some(d);
        self
    }

    /// The parameters.
    pub fn params(&self) -> &MultirotorParams<B> {
        &self.p
    }

    /// The rotor speed that makes thrust `f` without aerodynamics,
    /// `√(f/k_η)` (0 for `f ≤ 0`), clamped to the speed limits.
    #[inline]
    pub fn speed_for_thrust(&self, f: S<B>) -> S<B> {
        let w = (f.max(S::<B>::zero()) / self.p.k_eta).sqrt();
        w.max(self.p.rotor_speed_min).min(self.p.rotor_speed_max)
    }

    /// The rotor-speed commands for a commanded wrench: the minimum-norm
    /// rotor thrusts, then [`Multirotor::speed_for_thrust`] of each (what
    /// RotorPy's `cmd_ctbm` abstraction does), written into `out`.
    pub fn speed_commands(&self, w: &Wrench<B>, out: &mut [S<B>]) {
        self.thrusts(w, out);
        for o in out.iter_mut() {
            *o = self.speed_for_thrust(*o);
        }
    }

    /// The minimum-norm rotor thrusts of `w` into `out` (one per rotor).
    fn thrusts(&self, w: &Wrench<B>, out: &mut [S<B>]) {
        let [m1, m2, m3] = B::vec3_to_array(w.moment);
        let x = [w.thrust, m1, m2, m3];
        for (o, row) in out.iter_mut().zip(&self.alloc_inv) {
            *o = (0..4).fold(S::<B>::zero(), |s, k| s + row[k] * x[k]);
        }
    }

    /// The wrench of the rotors at `speeds` without aerodynamics.
    fn wrench_at_speeds(&self, speeds: &[S<B>]) -> Result<Wrench<B>, DynamicsError> {
        let mut f = [S::<B>::zero(); MAX_ROTORS];
        for (f, w) in f.iter_mut().zip(speeds) {
            *f = self.p.k_eta * *w * *w;
        }
        self.wrench_from_actuators(&f[..speeds.len().min(MAX_ROTORS)])
    }

    /// `ω̇_i = (clamp(ω_cmd,i) − ω_i)/τ_m` into `rates` (zero when `τ_m = 0`,
    /// where the speeds are the commands themselves).
    pub fn motor_rates(&self, commands: &[S<B>], speeds: &[S<B>], rates: &mut [S<B>]) {
        let lo = self.p.rotor_speed_min;
        let hi = self.p.rotor_speed_max;
        for ((r, c), w) in rates.iter_mut().zip(commands).zip(speeds) {
            *r = if self.p.tau_m > S::<B>::zero() {
                (c.max(lo).min(hi) - *w) / self.p.tau_m
            } else {
                S::<B>::zero()
            };
        }
    }

    /// The body-frame force and moment of the rotors at `speeds` and of
    /// the airframe, at body rate `omega` and body-frame airspeed
    /// `airspeed` (the module docs' `F_body`, `M_body`).
    pub fn body_wrench(&self, speeds: &[S<B>], omega: V3<B>, airspeed: V3<B>) -> (V3<B>, V3<B>) {
        let p = &self.p;
        let e3 = B::vec3(S::<B>::zero(), S::<B>::zero(), S::<B>::one());
        let mut force = ops::zero::<B>();
        let mut moment = ops::zero::<B>();
        for (r, &w) in p.rotors.iter().zip(speeds) {
            let mut lift = p.k_eta * w * w;
            let mut f = ops::zero::<B>();
            if p.aero {
                let vi = airspeed + B::cross(omega, r.position);
                let [vx, vy, vz] = B::vec3_to_array(vi);
                lift += p.k_h * (vx * vx + vy * vy);
                f = B::vec3(p.k_d * vx, p.k_d * vy, p.k_z * vz) * (-w);
                moment = moment + B::cross(vi, e3) * (p.k_flap * w);
            }
            f = f - e3 * lift;
            force = force + f;
            moment = moment + B::cross(r.position, f) - e3 * (r.direction * p.k_m * w * w);
        }
        if p.aero {
            // diag(c_D) v_a component by component, no matrix formed.
            let ([cx, cy, cz], [ax, ay, az]) =
                (B::vec3_to_array(p.c_d), B::vec3_to_array(airspeed));
            force = force - B::vec3(cx * ax, cy * ay, cz * az) * ops::norm::<B>(airspeed);
        }
        (force, moment)
    }

    /// The loads (inertial force with gravity, body moment, and the
    /// constant disturbance if one was added) at rotor `speeds` in `wind`
    /// (inertial air velocity, m/s).
    pub fn loads_at(&self, state: &RigidBodyState<B>, speeds: &[S<B>], wind: V3<B>) -> Loads<B> {
        let airspeed = B::mat3_tr_mul_vec(state.r, state.v - wind);
        let (fb, mb) = self.body_wrench(speeds, state.omega, airspeed);
        let z = S::<B>::zero();
        let mut l = Loads {
            force: B::vec3(z, z, self.p.mass * self.p.gravity) + B::mat3_mul_vec(state.r, fb),
            moment: mb,
        };
        if let Some(d) = self.disturbance {
            l.force = l.force + d.force;
            l.moment = l.moment + d.moment;
        }
        l
    }

    fn with_speeds<T>(
        &self,
        commanded: &Wrench<B>,
        states: &[S<B>],
        f: impl FnOnce(&[S<B>]) -> T,
    ) -> T {
        if self.p.tau_m > S::<B>::zero() && !states.is_empty() {
            return f(states);
        }
        let mut cmd = [S::<B>::zero(); MAX_ROTORS];
        let n = self.p.rotors.len().min(MAX_ROTORS);
        self.speed_commands(commanded, &mut cmd[..n]);
        f(&cmd[..n])
    }
}

/// The 4×n allocation of rotor thrusts to `(f, M1, M2, M3)` without
/// aerodynamics: thrust `−f_i e3` at `r_i` gives `r_i × (−f_i e3)`, and the
/// reaction moment `−s_i (k_m/k_η) f_i` about `e3`.
fn allocation<B: Backend>(p: &MultirotorParams<B>) -> [Vec<S<B>>; 4] {
    let c = p.k_m / p.k_eta;
    let mut rows: [Vec<S<B>>; 4] = Default::default();
    for r in &p.rotors {
        let [x, y, _] = B::vec3_to_array(r.position);
        rows[0].push(S::<B>::one());
        rows[1].push(-y);
        rows[2].push(x);
        rows[3].push(-r.direction * c);
    }
    rows
}

/// `Aᵀ(AAᵀ)⁻¹` for a 4×n `A` of full row rank.
fn min_norm_inverse<B: Backend>(a: &[Vec<S<B>>; 4]) -> Result<Vec<[S<B>; 4]>, DynamicsError> {
    let dot = |i: usize, j: usize| {
        a[i].iter()
            .zip(&a[j])
            .fold(S::<B>::zero(), |s, (x, y)| s + *x * *y)
    };
    let aat: [[f64; 4]; 4] =
        core::array::from_fn(|i| core::array::from_fn(|j| dot(i, j).to_f64_lossless()));
    let inv = invert4(aat).ok_or(invalid(
        "rotors",
        a[0].len() as f64,
        "rotor positions and directions whose allocation has full rank",
    ))?;
    let n = a[0].len();
    Ok((0..n)
        .map(|k| {
            core::array::from_fn(|j| {
                (0..4).fold(S::<B>::zero(), |s, i| s + a[i][k] * S::<B>::lit(inv[i][j]))
            })
        })
        .collect())
}

/// The inverse of a symmetric positive-definite 4×4 matrix by Gauss–Jordan
/// elimination with partial pivoting; `None` when a pivot is negligible.
fn invert4(m: [[f64; 4]; 4]) -> Option<[[f64; 4]; 4]> {
    let mut a = m;
    let mut inv = [[0.0; 4]; 4];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    let scale = (0..4).fold(0.0f64, |s, i| s.max(m[i][i].abs()));
    for col in 0..4 {
        let piv = (col..4).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        if a[piv][col].abs() <= 1e-12 * scale {
            return None;
        }
        a.swap(col, piv);
        inv.swap(col, piv);
        let d = a[col][col];
        for k in 0..4 {
            a[col][k] /= d;
            inv[col][k] /= d;
        }
        for r in 0..4 {
            if r != col {
                let f = a[r][col];
                for k in 0..4 {
                    a[r][k] -= f * a[col][k];
                    inv[r][k] -= f * inv[col][k];
                }
            }
        }
    }
    Some(inv)
}

impl<B: Backend> Vehicle<B> for Multirotor<B> {
    fn name(&self) -> &str {
        "multirotor"
    }
    fn mass(&self) -> S<B> {
        self.p.mass
    }
    fn inertia(&self) -> M3<B> {
        self.p.inertia
    }
    fn gravity(&self) -> S<B> {
        self.p.gravity
    }
    fn actuator_count(&self) -> usize {
        self.p.rotors.len()
    }
    /// Rotor thrusts `u_i` to the wrench without aerodynamics.
    fn wrench_from_actuators(&self, u: &[S<B>]) -> Result<Wrench<B>, DynamicsError> {
        let n = self.p.rotors.len();
        if u.len() != n {
            return Err(DynamicsError::ActuatorCount {
                expected: n,
                got: u.len(),
            });
        }
        if u.iter().any(|x| !x.is_finite()) {
            return Err(DynamicsError::NonFinite {
                field: "rotor thrusts",
            });
        }
        let row = |i: usize| {
            self.alloc[i]
                .iter()
                .zip(u)
                .fold(S::<B>::zero(), |s, (a, f)| s + *a * *f)
        };
        Ok(Wrench {
            thrust: row(0),
            moment: B::vec3(row(1), row(2), row(3)),
        })
    }
    fn actuators_from_wrench(&self, w: &Wrench<B>, out: &mut [S<B>]) -> Result<(), DynamicsError> {
        if out.len() != self.alloc_inv.len() {
            return Err(DynamicsError::ActuatorCount {
                expected: self.alloc_inv.len(),
                got: out.len(),
            });
        }
        self.thrusts(w, out);
        Ok(())
    }
    /// The rotors' aerodynamic loads (and the disturbance, if one was
    /// added) at their speeds: through the motor lag (clamped to the speed
    /// limits) when `τ_m > 0` and the caller integrates the rotor speeds,
    /// else straight at the commanded speeds.
    #[inline]
    fn loads(
        &self,
        _t: S<B>,
        state: &RigidBodyState<B>,
        input: LoadInput<'_, B>,
        rates: &mut [S<B>],
    ) -> Option<Loads<B>> {
        let LoadInput {
            command,
            states,
            wind,
            ..
        } = input;
        let lagged = self.p.tau_m > S::<B>::zero() && !states.is_empty();
        match command {
            Command::Wrench(w) => {
                let l = self.with_speeds(&w, states, |s| self.loads_at(state, s, wind));
                if !states.is_empty() {
                    let mut cmd = [S::<B>::zero(); MAX_ROTORS];
                    let n = states.len().min(MAX_ROTORS);
                    self.speed_commands(&w, &mut cmd[..n]);
                    self.motor_rates(&cmd[..n], states, rates);
                }
                Some(l)
            }
            Command::RotorSpeeds(speeds) => {
                if lagged {
                    self.motor_rates(speeds, states, rates);
                    return Some(self.loads_at(state, states, wind));
                }
                let mut w = [S::<B>::zero(); MAX_ROTORS];
                let n = speeds.len().min(MAX_ROTORS);
                for (w, c) in w.iter_mut().zip(speeds) {
                    *w = c.max(self.p.rotor_speed_min).min(self.p.rotor_speed_max);
                }
                Some(self.loads_at(state, &w[..n], wind))
            }
        }
    }
    fn capabilities(&self) -> Capabilities<'_, B> {
        Capabilities::RIGID
            .rate_dependent(self.p.aero)
            .with_actuators(self)
    }
}

impl<B: Backend> Actuators<B> for Multirotor<B> {
    /// The wrench of the rotors at their speeds (the integrated ones under
    /// a motor lag, else the clamped commanded ones), without aerodynamics:
    /// what the log reports as thrust and moment.
    fn delivered(&self, command: &Wrench<B>, states: &[S<B>]) -> Wrench<B> {
        self.with_speeds(command, states, |w| {
            self.wrench_at_speeds(w).unwrap_or(*command)
        })
    }
    /// One rotor speed a rotor under a motor lag (`τ_m > 0`), else none.
    fn state_count(&self) -> usize {
        if self.p.tau_m > S::<B>::zero() {
            self.p.rotors.len()
        } else {
            0
        }
    }
    /// Rotors spinning at the speeds of the first command (clamped to the
    /// limits).
    fn initial_states(&self, first: Command<'_, B>, states: &mut [S<B>]) {
        match first {
            Command::Wrench(w) => self.speed_commands(&w, states),
            Command::RotorSpeeds(speeds) => {
                for (s, w) in states.iter_mut().zip(speeds) {
                    *s = w.max(self.p.rotor_speed_min).min(self.p.rotor_speed_max);
                }
            }
        }
    }
}
