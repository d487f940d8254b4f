//! The gains of the paper's numerical example (its Section V), in one
//! place: the `paper()` gain constructors and the scene defaults read them
//! from here. (The example's vehicle — mass, inertia, arm, disturbances —
//! is the plant's: `dynamics::paper`.)

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
