//! Rigid-body vehicles for the geometric PID framework.
//!
//! Conventions are the paper's: the inertial `e3` points
//! **down**, `R` maps body to inertial vectors, `Ω` is in the body frame, the
//! velocity `v` is inertial, and the total thrust `f` acts along `−R e3`:
//!
//! ```text
//! ẋ = v                                   (eqn:EL1)
//! m v̇ = m g e3 − f R e3 + Δ_x             (eqn:EL2)
//! Ṙ = R Ω^                                (eqn:EL3)
//! J Ω̇ + Ω × JΩ = M + Δ_R                  (eqn:EL4)
//! ```
//!
//! A simulation holds its vehicle as a `Box<dyn Vehicle<B>>`: the
//! [`Vehicle`] trait says what a body is (mass, inertia, gravity, whether it
//! translates), how actuator commands become a body [`Wrench`] and back,
//! what the actuators can deliver, and which disturbance and configuration
//! loads (gravity about a pivot) act on it. [`loads`] turns a vehicle, a
//! state and a commanded wrench into the total force and moment that an
//! integrator needs; nothing in it is specific to quadrotors.
//!
//! Shipped vehicles: [`Quadrotor`] (the paper's, with its allocation and
//! fixed disturbances), [`Hexarotor`] (six rotors, minimum-norm allocation
//! inverse), [`AttitudeStand`] (the paper's Section VI test
//! stand: a quadrotor on a spherical joint below its centre of gravity, an
//! inverted 3D pendulum), and [`FreeRigidBody`] (torque-free, with its
//! invariants and the exact solution in [`free_body`]).
//!
//! # Adding a vehicle
//! Implement [`Vehicle`]: `mass`, `inertia`, `gravity`, `actuator_count`,
//! `wrench_from_actuators` and `actuators_from_wrench` are required; override
//! `translates` (false for a pinned body), `saturate` (actuator limits),
//! `disturbance` and `configuration_moment` (loads that depend on the
//! attitude, such as gravity about a pivot) when they apply. A vehicle with
//! actuator dynamics declares internal states (`state_count`,
//! `initial_states`, `state_rates`) and says what its actuators deliver
//! (`applied_wrench`); simulations integrate those states with the body. The defaults cost
//! nothing: a vehicle that returns `None` from `disturbance` is never asked to
//! add one. `examples/attitude_stand.rs` is a complete second vehicle.
//!
//! # Example
//! The paper's quadrotor at rest: four equal rotor thrusts summing to the
//! weight leave no net force (e3 points down, thrust up along `−R e3`) and
//! no moment, and the allocation inverse gives the same thrusts back.
//!
//! ```
//! use dynamics::{Quadrotor, RigidBodyState, Vehicle, loads};
//! use lie::{Backend, NalgebraF64};
//! type B = NalgebraF64;
//!
//! let quad = Quadrotor::<B>::paper();
//! let each = quad.mass() * quad.gravity() / 4.0;
//! let w = quad.wrench_from_actuators(&[each; 4])?;
//! let l = loads(&quad, 0.0, &RigidBodyState::at_rest(), &w);
//! let norm = |v| B::dot(v, v).sqrt();
//! assert!(norm(l.force) < 1e-12 && norm(l.moment) < 1e-12);
//! let mut rotors = [0.0; 4];
//! quad.actuators_from_wrench(&w, &mut rotors)?;
//! assert!(rotors.iter().all(|f| (f - each).abs() < 1e-12));
//! # Ok::<(), dynamics::DynamicsError>(())
//! ```

#![deny(missing_docs)]

use core::fmt;

use lie::num_traits::Zero;
use lie::{Backend, M3, Real, S, V3, ops};

pub mod free_body;
pub mod multirotor;
pub mod paper;
mod vehicles;
pub mod wind;

pub use multirotor::{Multirotor, MultirotorParams, Rotor};
pub use vehicles::{AttitudeStand, FreeRigidBody, Hexarotor, Quadrotor, RotorLimits};
pub use wind::{ConstantWind, DrydenSpec, DrydenWind, LadderWind, SinusoidWind, Wind, WindError};

/// The rigid-body state `(R, x, v, Ω)` of the paper: attitude (body to
/// inertial, the matrix as integrated), position and velocity in the
/// inertial frame, angular velocity in the body frame. It is
/// [`lie::RigidState`] with a matrix attitude, the one state type of the
/// workspace (control laws, integrators and simulations take it too); its
/// constructors and checks are there
/// ([`at_rest`](lie::RigidState::at_rest),
/// [`non_finite_field`](lie::RigidState::non_finite_field),
/// [`group`](lie::RigidState::group)).
pub type RigidBodyState<B> = lie::RigidState<B, M3<B>>;

/// Body wrench commanded to the vehicle: total thrust `f` along `−b3` and the
/// body moment `M`.
///
/// The moment comes first: a simulation writes the wrench and hands it to
/// [`Vehicle::total_loads`] through memory at every evaluation. With the
/// thrust first, both of the callee's 16-byte loads straddled two of the
/// caller's stores, which the CPU cannot forward from its store buffer;
/// with the moment first one still does.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Wrench<B: Backend> {
    /// Body moment, N m.
    pub moment: V3<B>,
    /// Total thrust, N (positive pushes along `−R e3`, i.e. up).
    pub thrust: S<B>,
}

impl<B: Backend> Wrench<B> {
    /// No thrust, no moment.
    pub fn zero() -> Self {
        Self {
            thrust: S::<B>::zero(),
            moment: ops::zero::<B>(),
        }
    }
}

/// Unmodelled loads: a force in the inertial frame and a moment in the body
/// frame (the paper's `Δ_x`, `Δ_R`).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Disturbance<B: Backend> {
    /// Inertial-frame force `Δ_x`, N.
    pub force: V3<B>,
    /// Body-frame moment `Δ_R`, N m.
    pub moment: V3<B>,
}

/// Total external loads on the body, what an integrator needs besides the
/// mass and inertia: the inertial force (gravity, thrust and disturbance) and
/// the body moment (control, disturbance, configuration moments), without the
/// gyroscopic term `Ω × JΩ`, which every integrator treats itself.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Loads<B: Backend> {
    /// Inertial-frame force, N.
    pub force: V3<B>,
    /// Body-frame moment, N m.
    pub moment: V3<B>,
}

/// Errors from vehicle construction and allocation.
#[derive(Clone, Debug, PartialEq)]
pub enum DynamicsError {
    /// A parameter is outside its valid range.
    InvalidParameter {
        /// Which parameter.
        field: &'static str,
        /// Its value (as f64, for the message).
        value: f64,
        /// What it must satisfy.
        expected: &'static str,
    },
    /// A slice of actuator values had the wrong length.
    ActuatorCount {
        /// The vehicle's actuator count.
        expected: usize,
        /// The slice length given.
        got: usize,
    },
    /// A NaN or ±∞ reached an input.
    NonFinite {
        /// Which input.
        field: &'static str,
    },
}

impl fmt::Display for DynamicsError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DynamicsError::InvalidParameter {
                field,
                value,
                expected,
            } => write!(f, "invalid `{field}` = {value}: expected {expected}"),
            DynamicsError::ActuatorCount { expected, got } => write!(
                f,
                "actuator slice has {got} entries, the vehicle has {expected} actuators"
            ),
            DynamicsError::NonFinite { field } => write!(f, "`{field}` is not finite"),
        }
    }
}

impl std::error::Error for DynamicsError {}

/// What [`Vehicle::loads_at_rotor_speeds`] is given: commanded rotor
/// speeds, the vehicle's internal states, and the wind at the vehicle.
#[derive(Clone, Copy)]
pub struct RotorSpeedInput<'a, B: Backend> {
    /// Commanded rotor speeds, rad/s, one per rotor.
    pub speeds: &'a [S<B>],
    /// The vehicle's internal states (rotor speeds under a motor lag).
    pub states: &'a [S<B>],
    /// The inertial velocity of the air at the vehicle, m/s.
    pub wind: V3<B>,
}

/// A vehicle: a rigid body with actuators. Object safe; simulations hold a
/// `Box<dyn Vehicle<B>>` so that a new vehicle needs no change anywhere else.
///
/// # Example
/// A body with one thruster along `−b3` and no moment (a "sled"): only the
/// six required methods.
///
/// ```
/// use dynamics::{DynamicsError, RigidBodyState, Vehicle, Wrench, loads};
/// use lie::{Backend, GlamF64, M3, S, ops};
/// type B = GlamF64;
///
/// struct Sled;
/// impl Vehicle<B> for Sled {
///     fn name(&self) -> &str { "sled" }
///     fn mass(&self) -> S<B> { 1.0 }
///     fn inertia(&self) -> M3<B> { ops::identity::<B>() }
///     fn gravity(&self) -> S<B> { 9.81 }
///     fn actuator_count(&self) -> usize { 1 }
///     fn wrench_from_actuators(&self, u: &[S<B>]) -> Result<Wrench<B>, DynamicsError> {
///         match u {
///             [f] => Ok(Wrench { thrust: *f, moment: B::vec3(0.0, 0.0, 0.0) }),
///             _ => Err(DynamicsError::ActuatorCount { expected: 1, got: u.len() }),
///         }
///     }
///     fn actuators_from_wrench(&self, w: &Wrench<B>, out: &mut [S<B>]) -> Result<(), DynamicsError> {
///         match out {
///             [f] => { *f = w.thrust; Ok(()) }
///             _ => Err(DynamicsError::ActuatorCount { expected: 1, got: out.len() }),
///         }
///     }
/// }
/// // Twice the weight: 1 g upwards (−e3) net.
/// let w = Sled.wrench_from_actuators(&[2.0 * 9.81])?;
/// let l = loads(&Sled, 0.0, &RigidBodyState::at_rest(), &w);
/// assert_eq!(B::vec3_to_array(l.force), [0.0, 0.0, -9.81]);
/// assert!(Sled.wrench_from_actuators(&[1.0, 2.0]).is_err());
/// # Ok::<(), DynamicsError>(())
/// ```
pub trait Vehicle<B: Backend>: Send + Sync {
    /// Short name for reports, e.g. `"quadrotor"`.
    fn name(&self) -> &str;
    /// Mass, kg.
    fn mass(&self) -> S<B>;
    /// Inertia about the point the body rotates about (the centre of mass
    /// for a free body, the pivot for a pinned one), body frame, kg m².
    fn inertia(&self) -> M3<B>;
    /// Gravitational acceleration along `+e3`, m/s².
    fn gravity(&self) -> S<B>;
    /// Whether the body translates. `false` for a body on a spherical joint
    /// (or an attitude-only study): integrators then leave `x` and `v`
    /// untouched and skip their arithmetic.
    fn translates(&self) -> bool {
        true
    }
    /// Number of actuators (rotors, …).
    fn actuator_count(&self) -> usize;
    /// Wrench produced by the actuator values `u` (e.g. rotor thrusts).
    fn wrench_from_actuators(&self, u: &[S<B>]) -> Result<Wrench<B>, DynamicsError>;
    /// Actuator values that produce `w` (the allocation inverse), written
    /// into `out` (no allocation).
    fn actuators_from_wrench(&self, w: &Wrench<B>, out: &mut [S<B>]) -> Result<(), DynamicsError>;
    /// The wrench the actuators can actually deliver when `w` is commanded.
    /// The default has no limits.
    fn saturate(&self, w: Wrench<B>) -> Wrench<B> {
        w
    }
    /// The disturbance at time `t` in `state`, `None` when there is none (the
    /// default), so a clean vehicle evaluates nothing.
    fn disturbance(&self, _t: S<B>, _state: &RigidBodyState<B>) -> Option<Disturbance<B>> {
        None
    }
    /// Attitude-dependent moment such as gravity about a pivot, body frame;
    /// `None` (the default) when there is none.
    fn configuration_moment(&self, _state: &RigidBodyState<B>) -> Option<V3<B>> {
        None
    }
    /// Number of internal states of the vehicle (rotor speeds or thrusts
    /// with a first-order lag, motor currents, …) that an integrator must
    /// advance with the body. The default, 0, costs nothing: such a vehicle
    /// is never asked for rates.
    fn state_count(&self) -> usize {
        0
    }
    /// Values of the internal states at the start of a run, given the
    /// first command (e.g. rotors already spinning at the commanded
    /// thrust). `states` has `state_count()` entries, zero on entry.
    fn initial_states(&self, _commanded: &Wrench<B>, _states: &mut [S<B>]) {}
    /// Values of the internal states at the start of a run whose first
    /// command is rotor speeds `speeds` (a mode that commands them): the
    /// rotors spinning at them. The default leaves the states at zero.
    fn initial_states_at_rotor_speeds(&self, _speeds: &[S<B>], _states: &mut [S<B>]) {}
    /// Time derivatives of the internal states under the commanded wrench,
    /// written into `rates` (`state_count()` entries).
    fn state_rates(
        &self,
        _t: S<B>,
        _body: &RigidBodyState<B>,
        _commanded: &Wrench<B>,
        _states: &[S<B>],
        _rates: &mut [S<B>],
    ) {
    }
    /// The wrench the actuators deliver when `commanded` is asked of them
    /// in internal state `states`. The default (actuators that respond at
    /// once) is [`Vehicle::saturate`] of the command.
    fn applied_wrench(&self, commanded: &Wrench<B>, _states: &[S<B>]) -> Wrench<B> {
        self.saturate(*commanded)
    }
    /// Whether `disturbance` or `configuration_moment` read the velocities
    /// `v` or `Ω` (drag, say). Implicit integrators (LGVI) then iterate
    /// their end-point loads; the default `false` lets them evaluate once.
    fn rate_dependent_loads(&self) -> bool {
        false
    }
    /// Everything an integrator needs from the vehicle at one evaluation:
    /// the [`loads_applied`] of the [`Vehicle::applied_wrench`] of
    /// `commanded` in internal state `states`.
    ///
    /// Leave the default: it composes the methods above, and because it is
    /// compiled for each vehicle type, a simulation holding a
    /// `dyn Vehicle` pays one virtual call per evaluation instead of one per
    /// method (saturation, mass, gravity, disturbance, … are then inlined).
    #[inline]
    fn total_loads(
        &self,
        t: S<B>,
        state: &RigidBodyState<B>,
        commanded: &Wrench<B>,
        states: &[S<B>],
    ) -> Loads<B> {
        loads_applied(self, t, state, self.applied_wrench(commanded, states))
    }
    /// The loads when the rotors are commanded speeds (rad/s) directly
    /// instead of a wrench ([`RotorSpeedInput`]: the speeds, the internal
    /// states, the wind), with the internal states' rates written into
    /// `rates`. `None` (the default) for a vehicle whose actuators are not
    /// rotors with speeds.
    fn loads_at_rotor_speeds(
        &self,
        _t: S<B>,
        _state: &RigidBodyState<B>,
        _input: RotorSpeedInput<'_, B>,
        _rates: &mut [S<B>],
    ) -> Option<Loads<B>> {
        None
    }
    /// [`Vehicle::total_loads`] in a wind `wind` (the inertial velocity of
    /// the air, m/s), which the simulation's environment evaluates at the
    /// vehicle. The default ignores the wind (a vehicle without
    /// aerodynamics feels none); vehicles with drag override this.
    #[inline]
    fn total_loads_in_wind(
        &self,
        t: S<B>,
        state: &RigidBodyState<B>,
        commanded: &Wrench<B>,
        states: &[S<B>],
        _wind: V3<B>,
    ) -> Loads<B> {
        self.total_loads(t, state, commanded, states)
    }
}

/// Total loads on `vehicle` in `state` at time `t` under the commanded
/// `wrench` (passed through [`Vehicle::saturate`]): the right-hand sides of
/// (eqn:EL2) and (eqn:EL4) without the gyroscopic term.
#[inline]
pub fn loads<B: Backend, V: Vehicle<B> + ?Sized>(
    vehicle: &V,
    t: S<B>,
    state: &RigidBodyState<B>,
    wrench: &Wrench<B>,
) -> Loads<B> {
    loads_applied(vehicle, t, state, vehicle.saturate(*wrench))
}

/// Total loads when the actuators deliver `applied` (already through
/// [`Vehicle::saturate`] or [`Vehicle::applied_wrench`]): what [`loads`]
/// computes after the saturation, for vehicles with internal states.
#[inline]
pub fn loads_applied<B: Backend, V: Vehicle<B> + ?Sized>(
    vehicle: &V,
    t: S<B>,
    state: &RigidBodyState<B>,
    applied: Wrench<B>,
) -> Loads<B> {
    let w = applied;
    let [_, _, b3] = B::mat3_cols(state.r);
    let zero = S::<B>::zero();
    let mut force = if vehicle.translates() {
        B::vec3(zero, zero, vehicle.mass() * vehicle.gravity()) - b3 * w.thrust
    } else {
        ops::zero::<B>()
    };
    let mut moment = w.moment;
    if let Some(d) = vehicle.disturbance(t, state) {
        if vehicle.translates() {
            force = force + d.force;
        }
        moment = moment + d.moment;
    }
    if let Some(m) = vehicle.configuration_moment(state) {
        moment = moment + m;
    }
    Loads { force, moment }
}

/// Kinetic energy `½ ΩᵀJΩ + ½ m vᵀv`.
pub fn kinetic_energy<B: Backend>(mass: S<B>, inertia: M3<B>, state: &RigidBodyState<B>) -> S<B> {
    let half = S::<B>::lit(0.5);
    half * B::dot(state.omega, inertia * state.omega) + half * mass * B::dot(state.v, state.v)
}

/// Spatial (inertial-frame) angular momentum `π = R J Ω`, constant for a
/// torque-free body.
pub fn spatial_angular_momentum<B: Backend>(inertia: M3<B>, state: &RigidBodyState<B>) -> V3<B> {
    B::mat3_mul_vec(state.r, B::mat3_mul_vec(inertia, state.omega))
}

/// Checks that `j` is a symmetric positive-definite inertia matrix (by its
/// leading principal minors) with finite entries.
pub fn check_inertia<B: Backend>(j: M3<B>) -> Result<(), DynamicsError> {
    if !ops::is_finite_mat::<B>(j) {
        return Err(DynamicsError::NonFinite { field: "inertia" });
    }
    let e = ops::elems::<B>(j);
    let scale = e[0][0].abs() + e[1][1].abs() + e[2][2].abs();
    let tol = S::<B>::epsilon() * S::<B>::lit(64.0) * scale;
    for (i, k) in [(0, 1), (0, 2), (1, 2)] {
        let d = (e[i][k] - e[k][i]).abs();
        if d > tol {
            return Err(DynamicsError::InvalidParameter {
                field: "inertia",
                value: d.to_f64_lossless(),
                expected: "a symmetric matrix (this is |J_ik − J_ki|)",
            });
        }
    }
    let m1 = e[0][0];
    let m2 = e[0][0] * e[1][1] - e[0][1] * e[1][0];
    let m3 = ops::det::<B>(j);
    for (minor, expected) in [
        (
            m1,
            "a positive-definite matrix (this is J11, which must be > 0)",
        ),
        (
            m2,
            "a positive-definite matrix (this is the leading 2×2 minor J11·J22 − J12·J21, which must be > 0)",
        ),
        (
            m3,
            "a positive-definite matrix (this is det J, which must be > 0)",
        ),
    ] {
        if minor <= S::<B>::zero() {
            return Err(DynamicsError::InvalidParameter {
                field: "inertia",
                value: minor.to_f64_lossless(),
                expected,
            });
        }
    }
    Ok(())
}

/// Checks a strictly positive, finite scalar parameter.
pub fn check_positive<T: Real>(field: &'static str, value: T) -> Result<(), DynamicsError> {
    if !value.is_finite() || value <= T::zero() {
        return Err(DynamicsError::InvalidParameter {
            field,
            value: value.to_f64_lossless(),
            expected: "a finite value > 0",
        });
    }
    Ok(())
}
