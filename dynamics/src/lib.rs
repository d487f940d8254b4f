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
//! [`Vehicle`] trait says what a body is (mass, inertia, gravity), how
//! actuator commands become a body [`Wrench`] and back, and, in its one
//! load path [`Vehicle::loads`], the total force and moment that an
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
//! Implement [`Vehicle`]'s seven required methods (`name`, `mass`,
//! `inertia`, `gravity`, `actuator_count`, `wrench_from_actuators`,
//! `actuators_from_wrench`). The simulation calls one more, `loads`, whose
//! default is the rigid body under the command ([`body_loads`]); override
//! it for a disturbance, aerodynamics, a wind or actuator dynamics.
//! `capabilities` names the optional parts, each a value or a trait of its
//! own: a body that does not translate, loads that read the rates,
//! [`Actuators`] with limits or internal states (integrated with the body;
//! their rates are written by `loads`), a [`ConfigurationMoment`] (gravity
//! about a pivot). `examples/attitude_stand.rs` is a complete second
//! vehicle.
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
mod ground;
pub mod multirotor;
pub mod paper;
mod vehicle;
mod vehicles;
pub mod wind;

pub use ground::{Ground, OnGround};
pub use multirotor::{Multirotor, MultirotorParams, Rotor};
pub use vehicle::{
    Actuators, Capabilities, Command, ConfigurationMoment, Contact, LoadInput, Vehicle, body_loads,
    loads,
};
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
/// [`Vehicle::loads`] through memory at every evaluation. With the
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
