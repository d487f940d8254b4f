//! A C ABI for the paper's position and attitude laws (Goodarzi, Lee &
//! Lee, "Geometric Nonlinear PID Control of a Quadrotor UAV on SE(3)"), for
//! flight software: `f32` throughout, plain `#[repr(C)]` structs, no heap,
//! and a [`GpcStatus`] from every function instead of a panic.
//!
//! The header `include/geopid_control.h` is generated from this file by
//! cbindgen (a test regenerates it and fails if the committed copy
//! differs).
//!
//! # Frames and units
//! The paper's: the inertial `e3` points **down** (north-east-down), the
//! body `b3` points down through the belly, and the total thrust `f ≥ 0`
//! acts along `−b3`. Positions in m, velocities in m/s, angular velocities
//! in rad/s (body frame), moments in N m (body frame), mass in kg, inertia
//! in kg m², gravity in m/s² (a positive number: it acts along `+e3`).
//! Matrices are row-major `float[3][3]`: `r[i][j]` is `R_ij`, and the
//! columns of `R` are the body axes in the inertial frame.
//!
//! A stack whose frames point **up** (the Crazyflie's: x forward, y left,
//! z up, for the world and the body) converts its state and references
//! with [`gpc_state_from_z_up`], [`gpc_position_reference_from_z_up`] and
//! [`gpc_vector_from_z_up`] (which also converts a moment back: the map is
//! its own inverse), and keeps the thrust as it is.
//!
//! # Integrals
//! The laws are pure: they return the rates of the integral terms (`ė_I`
//! of (eqn:eI), `ė_i` of the position mode) and the caller owns the
//! integrals, as the paper's continuous-time laws do. A flight loop
//! advances them by its sample period with [`gpc_integrals_step`].
//!
//! # Example (Rust; C calls the same functions)
//! ```
//! use geopid_control::*;
//! let vehicle = gpc_paper_vehicle();
//! let (pos, att) = (gpc_paper_position_gains(), gpc_paper_attitude_gains());
//! let state = GpcState { x: [0.0; 3], v: [0.0; 3], r: GPC_IDENTITY, omega: [0.0; 3] };
//! let integrals = GpcIntegrals::default();
//! let mut reference = GpcPositionReference::default();
//! reference.x = [0.0, 0.0, -1.0]; // 1 m above the origin: e3 points down
//! reference.b1d = [1.0, 0.0, 0.0];
//! let mut out = GpcPositionOutput::default();
//! let status = gpc_position_update(
//!     Some(&vehicle), Some(&pos), Some(&att), Some(&state), Some(&integrals),
//!     Some(&reference), Some(&mut out),
//! );
//! assert_eq!(status, GpcStatus::Ok);
//! assert!(out.thrust > 0.755 * 9.81, "climbs: {}", out.thrust);
//! ```

#![no_std]
#![deny(missing_docs)]

#[cfg(feature = "std")]
extern crate std;

mod check;
mod convert;
mod estimators;
pub mod vectors;

use check::{finite_all, rotation_ok};
use controllers::{
    AccelerationModel, AttitudeGains, AttitudeReference, ControlError, PositionGains,
    PositionInput, PositionReference, RigidBodyParams, SatBranch, VehicleState,
};
pub use convert::{gpc_position_reference_from_z_up, gpc_state_from_z_up, gpc_vector_from_z_up};
use convert::{mat, rows, vec};
pub use estimators::*;
use lie::{GlamF32, So3Mat};

type B = GlamF32;

/// The identity rotation, row-major (in C, an initializer:
/// `float r[3][3] = GPC_IDENTITY;`).
pub const GPC_IDENTITY: [[f32; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// How far `RᵀR` may be from the identity (largest entry of `RᵀR − I`)
/// before `R` is refused as not a rotation. An attitude estimator's `f32`
/// rotation matrix drifts by ~1e-6 per renormalisation-free second; 1e-3 is
/// far above that and far below a transposed or mis-scaled matrix.
pub const GPC_ROTATION_TOLERANCE: f32 = 1e-3;

/// What a call did. Every function returns one; on anything but
/// [`GpcStatus::Ok`] the output is left untouched.
#[repr(C)]
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum GpcStatus {
    /// The output is written.
    Ok = 0,
    /// A pointer argument was NULL.
    NullPointer = 1,
    /// The vehicle: mass not finite and positive, or an inertia entry or
    /// gravity not finite.
    InvalidVehicle = 2,
    /// A gain not finite or negative (`sigma` included).
    InvalidGains = 3,
    /// A state field (x, v, R, Ω) contains NaN or ±∞.
    NonFiniteState = 4,
    /// The state's `R` is not a rotation (see [`GPC_ROTATION_TOLERANCE`];
    /// a reflection, `det R < 0`, is refused too).
    NotARotation = 5,
    /// An integral (`e_I` or `e_i`) contains NaN or ±∞.
    NonFiniteIntegral = 6,
    /// A reference field contains NaN or ±∞.
    NonFiniteReference = 7,
    /// The attitude reference's `R_d` is not a rotation.
    ReferenceNotARotation = 8,
    /// The sample period of [`gpc_integrals_step`] is not finite and
    /// non-negative.
    InvalidPeriod = 9,
    /// A filter's block was not made a filter of that kind by its
    /// `*_init`.
    NotInitialized = 10,
    /// A filter's configuration: a noise setting or gain out of its range
    /// (see the field's documentation), or a mounting that is not a
    /// rotation.
    InvalidConfig = 11,
    /// A measurement contains NaN or ±∞.
    NonFiniteMeasurement = 12,
    /// A time that is not finite, or an IMU sample earlier than the
    /// filter's time.
    InvalidTime = 13,
    /// The filter refused the measurement: an innovation variance that was
    /// not positive (a covariance gone bad).
    Rejected = 14,
}

/// The rigid-body state the laws read.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcState {
    /// Position `x`, inertial frame, m.
    pub x: [f32; 3],
    /// Velocity `v = ẋ`, inertial frame, m/s.
    pub v: [f32; 3],
    /// Attitude `R` (body to inertial), row-major.
    pub r: [[f32; 3]; 3],
    /// Angular velocity `Ω`, body frame, rad/s.
    pub omega: [f32; 3],
}

/// Mass, inertia and gravity as the controller knows them.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcVehicle {
    /// Mass `m`, kg (> 0).
    pub mass: f32,
    /// Inertia `J`, body frame, kg m², row-major.
    pub inertia: [[f32; 3]; 3],
    /// Gravitational acceleration `g`, m/s², acting along `+e3` (down).
    pub gravity: f32,
}

/// Position-mode gains, per inertial axis (the paper's are equal per axis).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcPositionGains {
    /// `k_x` per axis.
    pub k_x: [f32; 3],
    /// `k_v` per axis.
    pub k_v: [f32; 3],
    /// `k_i` per axis (0 disables the integral term).
    pub k_i: [f32; 3],
    /// `c1`: weight of `e_x` in `ė_i = e_v + c1 e_x`.
    pub c1: f32,
    /// `σ`: the saturation level of `sat_σ(e_i)`.
    pub sigma: f32,
    /// Nonzero: clamped anti-windup (`ė_i` zeroed in a component at `±σ`
    /// pushing outward). Zero: the paper's law.
    pub clamp_integral: u8,
}

/// Attitude gains, per body axis (the paper's are equal per axis).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcAttitudeGains {
    /// `k_R` per axis.
    pub k_r: [f32; 3],
    /// `k_Ω` per axis.
    pub k_omega: [f32; 3],
    /// `k_I` per axis (0 disables the integral term).
    pub k_i: [f32; 3],
    /// `c2`: weight of `e_R` in `ė_I = e_Ω + c2 e_R` (eqn:eI).
    pub c2: f32,
}

/// The integral terms the caller owns.
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcIntegrals {
    /// `e_I`, the attitude integral (eqn:eI), body frame.
    pub e_i_att: [f32; 3],
    /// `e_i`, the position integral, inertial frame.
    pub e_i_pos: [f32; 3],
}

/// The position command with four derivatives and the heading command with
/// two (inertial frame; zero derivatives to hold a point).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcPositionReference {
    /// `x_d`, m.
    pub x: [f32; 3],
    /// `ẋ_d`, m/s.
    pub v: [f32; 3],
    /// `ẍ_d`, m/s².
    pub a: [f32; 3],
    /// `x_d⁽³⁾`, m/s³.
    pub jerk: [f32; 3],
    /// `x_d⁽⁴⁾`, m/s⁴.
    pub snap: [f32; 3],
    /// `b1d`, the desired heading (projected; need not be unit).
    pub b1d: [f32; 3],
    /// `ḃ1d`.
    pub b1d_dot: [f32; 3],
    /// `b̈1d`.
    pub b1d_ddot: [f32; 3],
}

/// The attitude command: `R_d`, `Ω_d`, `Ω̇_d` (`Ṙ_d = R_d Ω_d^`).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcAttitudeReference {
    /// `R_d`, row-major.
    pub rd: [[f32; 3]; 3],
    /// `Ω_d`, desired body frame, rad/s.
    pub omega_d: [f32; 3],
    /// `Ω̇_d`, rad/s².
    pub omega_d_dot: [f32; 3],
}

/// What the position law computed ((eqn:f), (eqn:RdWc), (eqn:M)).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcPositionOutput {
    /// Total thrust `f`, N, along `−b3`.
    pub thrust: f32,
    /// Moment `M`, body frame, N m.
    pub moment: [f32; 3],
    /// Computed attitude `R_c`, row-major.
    pub rc: [[f32; 3]; 3],
    /// `Ω_c`, rad/s.
    pub omega_c: [f32; 3],
    /// `Ω̇_c`, rad/s².
    pub omega_c_dot: [f32; 3],
    /// `e_x = x − x_d`.
    pub e_x: [f32; 3],
    /// `e_v = v − ẋ_d`.
    pub e_v: [f32; 3],
    /// `e_R` against `R_c`.
    pub e_r: [f32; 3],
    /// `e_Ω` against `Ω_c`.
    pub e_omega: [f32; 3],
    /// `Ψ(R, R_c)`.
    pub psi: f32,
    /// `ė_i`, the position integral's rate.
    pub e_i_pos_rate: [f32; 3],
    /// `ė_I`, the attitude integral's rate.
    pub e_i_att_rate: [f32; 3],
    /// 1 when `‖A‖` was zero and the current `b3` was used as `b3c`.
    pub thrust_direction_undefined: u8,
    /// 1 when `b1d` was parallel to `b3c` and the current heading was held.
    pub heading_undefined: u8,
}

/// What the attitude law computed ((eqn:aM), (eqn:eI)).
#[repr(C)]
#[derive(Copy, Clone, Debug, Default, PartialEq)]
pub struct GpcAttitudeOutput {
    /// Moment `M`, body frame, N m.
    pub moment: [f32; 3],
    /// `e_R`.
    pub e_r: [f32; 3],
    /// `e_Ω`.
    pub e_omega: [f32; 3],
    /// `Ψ(R, R_d)`.
    pub psi: f32,
    /// `ė_I`, the attitude integral's rate.
    pub e_i_rate: [f32; 3],
}

fn params(v: &GpcVehicle) -> Result<RigidBodyParams<B>, GpcStatus> {
    let inertia = v.inertia.as_flattened();
    if !(v.mass.is_finite() && v.mass > 0.0 && v.gravity.is_finite() && finite_all(inertia)) {
        return Err(GpcStatus::InvalidVehicle);
    }
    Ok(RigidBodyParams {
        mass: v.mass,
        inertia: mat(&v.inertia),
        gravity: v.gravity,
    })
}

/// Finite and non-negative, every one.
fn gains_ok(values: &[f32]) -> bool {
    values.iter().all(|g| g.is_finite() && *g >= 0.0)
}

fn attitude_gains(g: &GpcAttitudeGains) -> Result<AttitudeGains<B>, GpcStatus> {
    let all = [g.k_r, g.k_omega, g.k_i, [g.c2; 3]];
    if !gains_ok(all.as_flattened()) {
        return Err(GpcStatus::InvalidGains);
    }
    Ok(AttitudeGains {
        k_r: vec(g.k_r),
        k_omega: vec(g.k_omega),
        k_i: vec(g.k_i),
        c2: g.c2,
    })
}

fn position_gains(g: &GpcPositionGains) -> Result<PositionGains<B>, GpcStatus> {
    let all = [g.k_x, g.k_v, g.k_i, [g.c1, g.sigma, 0.0]];
    if !gains_ok(all.as_flattened()) {
        return Err(GpcStatus::InvalidGains);
    }
    Ok(PositionGains {
        k_x: vec(g.k_x),
        k_v: vec(g.k_v),
        k_i: vec(g.k_i),
        c1: g.c1,
        sigma: g.sigma,
        clamp_integral: g.clamp_integral != 0,
        sat_branch: [SatBranch::Auto; 3],
    })
}

fn state(s: &GpcState) -> Result<VehicleState<B, So3Mat<B>>, GpcStatus> {
    let all = [s.x, s.v, s.omega];
    if !(finite_all(all.as_flattened()) && finite_all(s.r.as_flattened())) {
        return Err(GpcStatus::NonFiniteState);
    }
    if !rotation_ok(&s.r) {
        return Err(GpcStatus::NotARotation);
    }
    Ok(VehicleState {
        x: vec(s.x),
        v: vec(s.v),
        r: So3Mat::from_matrix_unchecked(mat(&s.r)),
        omega: vec(s.omega),
    })
}

fn integrals(i: &GpcIntegrals) -> Result<GpcIntegrals, GpcStatus> {
    if finite_all(&i.e_i_att) && finite_all(&i.e_i_pos) {
        Ok(*i)
    } else {
        Err(GpcStatus::NonFiniteIntegral)
    }
}

fn position_reference(r: &GpcPositionReference) -> Result<PositionReference<B>, GpcStatus> {
    let all = [r.x, r.v, r.a, r.jerk, r.snap, r.b1d, r.b1d_dot, r.b1d_ddot];
    if !finite_all(all.as_flattened()) {
        return Err(GpcStatus::NonFiniteReference);
    }
    Ok(PositionReference {
        x: vec(r.x),
        v: vec(r.v),
        a: vec(r.a),
        jerk: vec(r.jerk),
        snap: vec(r.snap),
        b1d: vec(r.b1d),
        b1d_dot: vec(r.b1d_dot),
        b1d_ddot: vec(r.b1d_ddot),
    })
}

fn attitude_reference(
    r: &GpcAttitudeReference,
) -> Result<AttitudeReference<B, So3Mat<B>>, GpcStatus> {
    let all = [r.omega_d, r.omega_d_dot];
    if !(finite_all(all.as_flattened()) && finite_all(r.rd.as_flattened())) {
        return Err(GpcStatus::NonFiniteReference);
    }
    if !rotation_ok(&r.rd) {
        return Err(GpcStatus::ReferenceNotARotation);
    }
    Ok(AttitudeReference {
        rd: So3Mat::from_matrix_unchecked(mat(&r.rd)),
        omega_d: vec(r.omega_d),
        omega_d_dot: vec(r.omega_d_dot),
    })
}

/// Inputs were checked before the law ran, so an error from it means a
/// non-finite intermediate the checks did not foresee: reported by where
/// the law traced it.
fn from_control_error(e: ControlError) -> GpcStatus {
    match e {
        ControlError::NonFiniteReference { .. } => GpcStatus::NonFiniteReference,
        _ => GpcStatus::NonFiniteState,
    }
}

/// The position mode's full update: thrust (eqn:f), computed attitude and
/// its derivatives (eqn:Rd3, eqn:RdWc), moment (eqn:M), with the nominal
/// acceleration model (the integral term as the disturbance estimate).
///
/// Every input is checked before the law runs; on a status other than
/// [`GpcStatus::Ok`], `out` is not written.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_position_update(
    vehicle: Option<&GpcVehicle>,
    position_gains_: Option<&GpcPositionGains>,
    attitude_gains_: Option<&GpcAttitudeGains>,
    state_: Option<&GpcState>,
    integrals_: Option<&GpcIntegrals>,
    reference: Option<&GpcPositionReference>,
    out: Option<&mut GpcPositionOutput>,
) -> GpcStatus {
    let (Some(v), Some(pg), Some(ag), Some(s), Some(i), Some(r), Some(out)) = (
        vehicle,
        position_gains_,
        attitude_gains_,
        state_,
        integrals_,
        reference,
        out,
    ) else {
        return GpcStatus::NullPointer;
    };
    match position_update(v, pg, ag, s, i, r) {
        Ok(o) => {
            *out = o;
            GpcStatus::Ok
        }
        Err(e) => e,
    }
}

fn position_update(
    v: &GpcVehicle,
    pg: &GpcPositionGains,
    ag: &GpcAttitudeGains,
    s: &GpcState,
    i: &GpcIntegrals,
    r: &GpcPositionReference,
) -> Result<GpcPositionOutput, GpcStatus> {
    let (params, pos_gains, att_gains) = (params(v)?, position_gains(pg)?, attitude_gains(ag)?);
    let (state, integrals, reference) = (state(s)?, integrals(i)?, position_reference(r)?);
    let input = PositionInput {
        state: &state,
        e_i_pos: vec(integrals.e_i_pos),
        e_i_att: vec(integrals.e_i_att),
        reference: &reference,
        model: AccelerationModel::Nominal,
    };
    let o = controllers::position_control(&params, &pos_gains, &att_gains, &input)
        .map_err(from_control_error)?;
    Ok(GpcPositionOutput {
        thrust: o.thrust,
        moment: o.moment.to_array(),
        rc: rows(o.rc.as_matrix()),
        omega_c: o.omega_c.to_array(),
        omega_c_dot: o.omega_c_dot.to_array(),
        e_x: o.e_x.to_array(),
        e_v: o.e_v.to_array(),
        e_r: o.e_r.to_array(),
        e_omega: o.e_omega.to_array(),
        psi: o.psi,
        e_i_pos_rate: o.e_i_pos_rate.to_array(),
        e_i_att_rate: o.e_i_att_rate.to_array(),
        thrust_direction_undefined: o.degeneracy.thrust_direction_undefined as u8,
        heading_undefined: o.degeneracy.heading_undefined as u8,
    })
}

/// The attitude mode's moment (eqn:aM) and the rate of its integral
/// (eqn:eI), for a commanded attitude; the thrust is the caller's (the
/// paper's flip uses a position-PD projection, a manual mode a stick).
/// Reads `integrals.e_i_att` only. On a status other than
/// [`GpcStatus::Ok`], `out` is not written.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_attitude_update(
    vehicle: Option<&GpcVehicle>,
    attitude_gains_: Option<&GpcAttitudeGains>,
    state_: Option<&GpcState>,
    integrals_: Option<&GpcIntegrals>,
    reference: Option<&GpcAttitudeReference>,
    out: Option<&mut GpcAttitudeOutput>,
) -> GpcStatus {
    let (Some(v), Some(ag), Some(s), Some(i), Some(r), Some(out)) =
        (vehicle, attitude_gains_, state_, integrals_, reference, out)
    else {
        return GpcStatus::NullPointer;
    };
    let run = || -> Result<GpcAttitudeOutput, GpcStatus> {
        let (params, gains) = (params(v)?, attitude_gains(ag)?);
        let (state, integrals, reference) = (state(s)?, integrals(i)?, attitude_reference(r)?);
        let o = controllers::attitude_control(
            &params,
            &gains,
            state.r,
            state.omega,
            vec(integrals.e_i_att),
            &reference,
        )
        .map_err(from_control_error)?;
        Ok(GpcAttitudeOutput {
            moment: o.moment.to_array(),
            e_r: o.e_r.to_array(),
            e_omega: o.e_omega.to_array(),
            psi: o.psi,
            e_i_rate: o.e_i_rate.to_array(),
        })
    };
    match run() {
        Ok(o) => {
            *out = o;
            GpcStatus::Ok
        }
        Err(e) => e,
    }
}

/// Advances the integrals by one sample period `dt` (s) with their rates
/// (`e += dt ė`, the sampled form of the paper's integrals). A NULL rate
/// leaves that integral as it is (an attitude-mode loop passes NULL for
/// `e_i_pos_rate`). In C, pass the output's arrays (`out.e_i_att_rate`).
/// On a status other than [`GpcStatus::Ok`] nothing is written.
///
/// # Safety
/// `integrals` is NULL (a status) or a valid `GpcIntegrals`; each rate is
/// NULL or points to three readable floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn gpc_integrals_step(
    integrals: *mut GpcIntegrals,
    e_i_att_rate: *const f32,
    e_i_pos_rate: *const f32,
    dt: f32,
) -> GpcStatus {
    // SAFETY: NULL or a valid, exclusive `GpcIntegrals` (the contract).
    let Some(i) = (unsafe { integrals.as_mut() }) else {
        return GpcStatus::NullPointer;
    };
    if !(dt.is_finite() && dt >= 0.0) {
        return GpcStatus::InvalidPeriod;
    }
    // SAFETY: NULL or three readable floats (the contract).
    let read = |p: *const f32| {
        if p.is_null() {
            [0.0; 3]
        } else {
            unsafe { core::ptr::read_unaligned(p.cast::<[f32; 3]>()) }
        }
    };
    let (ra, rp) = (read(e_i_att_rate), read(e_i_pos_rate));
    if !(finite_all(&ra) && finite_all(&rp)) {
        return GpcStatus::NonFiniteIntegral;
    }
    for k in 0..3 {
        i.e_i_att[k] += dt * ra[k];
        i.e_i_pos[k] += dt * rp[k];
    }
    GpcStatus::Ok
}

/// The paper's quadrotor: `m = 0.755` kg, `J = diag(0.43, 0.43, 1.02)·10⁻²`
/// kg m², `g = 9.81` m/s².
#[unsafe(no_mangle)]
pub extern "C" fn gpc_paper_vehicle() -> GpcVehicle {
    let mut inertia = [[0.0; 3]; 3];
    for (k, j) in [0.43e-2, 0.43e-2, 1.02e-2].into_iter().enumerate() {
        inertia[k][k] = j;
    }
    GpcVehicle {
        mass: 0.755,
        inertia,
        gravity: 9.81,
    }
}

/// The paper's position gains: `k_x = 12.8, k_v = 4.22, k_i = 1.28,
/// c1 = 3.6, σ = 1`, clamp off.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_paper_position_gains() -> GpcPositionGains {
    let g = controllers::paper::POSITION_GAINS;
    GpcPositionGains {
        k_x: [g.k_x as f32; 3],
        k_v: [g.k_v as f32; 3],
        k_i: [g.k_i as f32; 3],
        c1: g.c1 as f32,
        sigma: g.sigma as f32,
        clamp_integral: 0,
    }
}

/// The paper's attitude gains: `k_R = 0.65, k_Ω = 0.11, k_I = 0.06,
/// c2 = 0.8`.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_paper_attitude_gains() -> GpcAttitudeGains {
    let g = controllers::paper::ATTITUDE_GAINS;
    GpcAttitudeGains {
        k_r: [g.k_r as f32; 3],
        k_omega: [g.k_omega as f32; 3],
        k_i: [g.k_i as f32; 3],
        c2: g.c2 as f32,
    }
}

/// A static, NUL-terminated name of a status code (`"ok"`,
/// `"non-finite state"`, …) for a log line; `"unknown status"` for a
/// number that is no [`GpcStatus`] (the code is taken as an integer so
/// that any value a C caller holds is safe to pass).
#[unsafe(no_mangle)]
pub extern "C" fn gpc_status_name(code: i32) -> *const core::ffi::c_char {
    let s: &'static core::ffi::CStr = match code {
        0 => c"ok",
        1 => c"null pointer",
        2 => c"invalid vehicle (mass, inertia or gravity)",
        3 => c"invalid gains (not finite or negative)",
        4 => c"non-finite state",
        5 => c"state R is not a rotation",
        6 => c"non-finite integral",
        7 => c"non-finite reference",
        8 => c"reference R_d is not a rotation",
        9 => c"invalid sample period",
        10 => c"filter not initialised",
        11 => c"invalid filter configuration",
        12 => c"non-finite measurement",
        13 => c"invalid time (not finite, or an IMU sample going back)",
        14 => c"measurement rejected by the filter",
        _ => c"unknown status",
    };
    s.as_ptr()
}
