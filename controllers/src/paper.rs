//! The numbers of the paper's numerical example (its Section V), in one
//! place: every `paper()` constructor of this workspace (the controller's
//! model and gains here, the quadrotor and its disturbances in `dynamics`,
//! the scene defaults in `scenarios`) reads them from here.

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
/// Position gains `k_x`, `k_v`, `k_i`, `c1` and the saturation level `σ`.
pub const POSITION_GAINS: PositionGains = PositionGains {
    k_x: 12.8,
    k_v: 4.22,
    k_i: 1.28,
    c1: 3.6,
    sigma: 1.0,
};
/// Attitude gains `k_R`, `k_Ω`, `k_I`, `c2`.
pub const ATTITUDE_GAINS: AttitudeGains = AttitudeGains {
    k_r: 0.65,
    k_omega: 0.11,
    k_i: 0.06,
    c2: 0.8,
};

/// The paper's scalar position gains.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PositionGains {
    /// `k_x`.
    pub k_x: f64,
    /// `k_v`.
    pub k_v: f64,
    /// `k_i`.
    pub k_i: f64,
    /// `c1`.
    pub c1: f64,
    /// `σ` of `sat_σ`.
    pub sigma: f64,
}

/// The paper's scalar attitude gains.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct AttitudeGains {
    /// `k_R`.
    pub k_r: f64,
    /// `k_Ω`.
    pub k_omega: f64,
    /// `k_I`.
    pub k_i: f64,
    /// `c2`.
    pub c2: f64,
}
