//! The vehicle of the paper's numerical example (its Section V), in one
//! place: [`Quadrotor::paper`](crate::Quadrotor::paper),
//! [`Quadrotor::paper_disturbance`](crate::Quadrotor::paper_disturbance)
//! and the scene defaults read them from here. (The example's gains are
//! the controller's: `controllers::paper`.)

/// Mass `m`, kg.
pub const MASS: f64 = 0.755;
/// Principal moments of inertia `J = diag(J1, J2, J3)`, kg m². (J3 exceeds
/// J1 + J2, which no rigid body does; the paper's example uses it as is.)
pub const INERTIA: [f64; 3] = [0.43e-2, 0.43e-2, 1.02e-2];
/// Gravity `g`, m/s², along `+e3` (down).
pub const GRAVITY: f64 = 9.81;
/// Arm length `d` (centre to rotor), m.
pub const ARM: f64 = 0.169;
/// Reaction-torque coefficient `c_τf`, m.
pub const C_TAU_F: f64 = 0.0132;
/// Translational disturbance `Δ_x`, inertial frame, N.
pub const DELTA_X: [f64; 3] = [-0.5, 0.2, 1.0];
/// Rotational disturbance `Δ_R`, body frame, N m.
pub const DELTA_R: [f64; 3] = [0.2, -0.1, -0.02];
