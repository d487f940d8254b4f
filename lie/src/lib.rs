//! SO(3), SE(3) and SE₂(3), written once and compiled for `f32`/`f64` on the
//! nalgebra or glam backend.
//!
//! This crate owns the group maths every other crate of the workspace
//! stands on: hat/vee, exp/log, composition, inverse, action, adjoint, the
//! left/right Jacobians and their inverses, projection onto the group, and
//! the attitude error function `Ψ` with the error vectors `e_R`, `e_Ω` of
//! Goodarzi, Lee & Lee (Proposition 1). One trait, [`LieGroup`], gives
//! SO(3) ([`So3Mat`], [`So3Quat`]), SE(3) ([`Se3`]), the extended poses
//! SE₂(3) ([`Se23`]) and the rigid-body
//! state SO(3) × ℝ³ × ℝ³ × ℝ³ ([`RigidState`]) the operations estimation
//! code is written in: ⊕/⊖ on either side, `between`, and the Jacobians of
//! each with respect to each argument. It deliberately owns no dynamics,
//! no integrators and no allocation: it is `#![no_std]` when the `std`
//! feature is off (the `libm` feature then supplies the maths functions).
//!
//! # How the abstraction works
//!
//! A [`Backend`] is a zero-sized marker for a (library, scalar) pair:
//! [`NalgebraF32`], [`NalgebraF64`], [`GlamF32`], [`GlamF64`] (and
//! [`GlamF32A`], glam's SIMD-aligned f32 types). Its associated
//! types are the library's own `Vec3`/`Mat3`/`Quat`, and the trait has
//! thirteen primitive functions (dot, cross, columns in and out, transpose,
//! quaternion product and rotation, …), each one line of the library's own
//! API; `+`, `−`, scalar and matrix products come from the library's
//! operators through bounds on the associated types. Every formula — exp,
//! log, Jacobians, Ψ — is a generic `#[inline]` function over `B: Backend`,
//! so each (library, scalar) pair is monomorphised into straight-line code
//! on that library's types. There is no shim layer that makes one library
//! imitate the other, and no conversion at the API boundary: an
//! `So3Mat<GlamF32>` *is* a `glam::Mat3`.
//!
//! ```
//! use lie::{GlamF64, Rotation, So3Mat, So3Quat};
//! use glam::DVec3;
//!
//! let phi = DVec3::new(0.3, -0.2, 0.9);
//! let r = So3Mat::<GlamF64>::exp(phi);
//! let q = So3Quat::<GlamF64>::exp(phi);
//! // Same rotation in both representations, native glam types out.
//! let v = DVec3::new(1.0, 2.0, 3.0);
//! assert!((r.act(v) - q.act(v)).length() < 1e-14);
//! assert!((r.log() - phi).length() < 1e-14);
//! let m: glam::DMat3 = r.matrix();
//! # let _ = m;
//! ```
//!
//! # What it costs
//!
//! * **Run time:** nothing measurable. `cargo bench -p geopid-lie` runs every
//!   operation beside the same formula written by hand on glam or nalgebra
//!   types; the generic/hand-written ratios are reported in the
//!   repository's notes. Where the generic formula reads elements through
//!   columns (`elems`), the optimiser removes the copies.
//! * **Compile time:** each formula is compiled once per pair that a
//!   program uses; a flight stack that uses only `GlamF32` pays for one.
//! * **Docs:** the formulas are documented once, on generic items, instead
//!   of once per concrete type.
//!
//! # Numerically delicate spots
//!
//! * exp and all Jacobians near zero angle: Taylor branches below cut-offs
//!   chosen per formula and per precision (see [`Real`] and [`series`]).
//! * log near and at angle π: through Shepperd's largest-pivot
//!   matrix→quaternion conversion and `atan2`, never `acos` of the trace.
//! * projection onto SO(3): the exact polar factor, not Gram–Schmidt (which
//!   favours the first column).
//!
//! # Features
//!
//! `std` (default), `libm` (for `no_std`), `nalgebra` (default), `glam`
//! (default). `cargo build -p geopid-lie --no-default-features --features glam,libm`
//! builds the crate as `no_std`.
//!
//! `simd` adds two lane backends, `NalgebraF64x4` and `NalgebraF32x8`
//! (nalgebra's types over simba's `WideF64x4`/`WideF32x8`): one value holds
//! four or eight independent inputs, and the same generic formulas advance
//! all of them at once. The scalar trait splits for them into [`SimdReal`]
//! (a number or a vector of them; comparisons give a mask, every branch of
//! a formula is a lane-wise select) and [`Real`]. SO(3) in both
//! representations, [`Se3`], [`RigidState`] and the whole [`LieGroup`]
//! trait run on lanes ([`So3Group`] is the part of [`Rotation`] they need);
//! [`lanes`] moves values in and out. The scalar backends are unchanged by
//! this: every [`Backend`] is a [`SimdBackend`] with one lane.
//!
//! `dual` adds `Dual<N>`, a forward-mode dual number (a value and `N`
//! derivatives), and `NalgebraDual<N>`, the nalgebra backend on it: every
//! formula written over a backend returns exact derivatives, and the real
//! part is the `f64` result bit for bit (see `Dual`).

#![cfg_attr(not(feature = "std"), no_std)]
#![deny(missing_docs)]

#[cfg(not(any(feature = "std", feature = "libm")))]
compile_error!("lie needs either the `std` or the `libm` feature for its maths functions");

mod backend;
mod bundle;
mod convert;
pub mod cpu;
#[cfg(feature = "dual")]
mod dual;
mod group;
pub mod lanes;
mod simd;
mod backends {
    #[cfg(feature = "glam")]
    pub mod glam;
    #[cfg(feature = "simd")]
    pub mod lanes;
    #[cfg(feature = "nalgebra")]
    pub mod nalgebra;
}
pub mod noise;
mod quat;
mod real;
mod rotation;
mod se23;
mod se3;
pub mod series;
pub mod so3;

pub use backend::{Backend, M3, S, SimdBackend, V3, ops};
#[cfg(feature = "glam")]
pub use backends::glam::{GlamF32, GlamF32A, GlamF64};
#[cfg(feature = "dual")]
pub use backends::nalgebra::NalgebraDual;
#[cfg(feature = "nalgebra")]
pub use backends::nalgebra::{NalgebraF32, NalgebraF64};
#[cfg(feature = "simd")]
pub use backends::nalgebra::{NalgebraF32x8, NalgebraF64x4};
pub use bundle::{ActBlocks, BlockDiag4, RigidState, RigidTangent};
pub use convert::{log_matrix, log_wxyz, shepperd};
#[cfg(feature = "dual")]
pub use dual::Dual;
pub use group::{LieGroup, Matrix3x6, mul6};
pub use num_traits;
pub use quat::So3Quat;
pub use real::Real;
pub use rotation::{AttitudeErrors, Rotation, So3Group, e_omega};
pub use se3::{Matrix4, Matrix6, Se3, Twist, q_block, se3_left_jacobian, se3_left_jacobian_inv};
pub use se23::{
    ExtTwist, Matrix3x9, Matrix5, Matrix9, Se23, mul9, se23_left_jacobian, se23_left_jacobian_inv,
};
#[cfg(feature = "simd")]
pub use simba::simd::{WideF32x8, WideF64x4};
pub use simd::{SimdMask, SimdReal};
pub use so3::{
    So3Mat, hat, left_jacobian, left_jacobian_inv, orthogonality_error, right_jacobian,
    right_jacobian_inv, vee,
};

/// Errors from the checked entry points of this crate.
#[derive(Clone, Debug, PartialEq)]
pub enum LieError {
    /// An input contained NaN or ±∞.
    NonFinite {
        /// Which input.
        what: &'static str,
    },
    /// A matrix with `det ≤ 0` has no nearest rotation (its polar factor is
    /// a reflection).
    NotProjectable {
        /// The determinant met during the iteration.
        det: f64,
    },
    /// The polar iteration did not settle within its iteration cap (it
    /// converges quadratically, so this means a matrix so far from
    /// orthogonal, or so badly scaled, that its projection is meaningless).
    NotConverged {
        /// The last Newton step's size, ‖X_{k+1} − X_k‖_F.
        step: f64,
    },
}

impl core::fmt::Display for LieError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            LieError::NonFinite { what } => write!(f, "{what} contains a non-finite value"),
            LieError::NotProjectable { det } => write!(
                f,
                "matrix cannot be projected onto SO(3): determinant {det} is not positive"
            ),
            LieError::NotConverged { step } => write!(
                f,
                "projection onto SO(3) did not converge: last step {step:e} after the iteration cap"
            ),
        }
    }
}

impl core::error::Error for LieError {}

/// The usual imports: `use lie::prelude::*;` brings the traits, the
/// backends, the scalar and vector aliases and `ops`, so generic code needs
/// nothing else (the scalar's elementary functions are methods of [`Real`]):
///
/// ```
/// use lie::prelude::*;
///
/// /// The rotation angle of `R`, for any backend and scalar.
/// fn angle<B: Backend>(r: So3Mat<B>) -> S<B> {
///     let v: V3<B> = r.log();
///     ops::norm::<B>(v)
/// }
/// let r = So3Mat::<GlamF64>::exp(glam::DVec3::new(0.0, 0.3, 0.4));
/// assert!((angle(r) - 0.5).abs() < 1e-15);
/// assert!(Real::abs(angle(r) - 0.5) < 1e-15);
/// ```
pub mod prelude {
    pub use crate::{
        AttitudeErrors, Backend, LieError, LieGroup, M3, Real, RigidState, RigidTangent, Rotation,
        S, Se3, Se23, So3Mat, So3Quat, Twist, V3, ops,
    };
    #[cfg(feature = "glam")]
    pub use crate::{GlamF32, GlamF32A, GlamF64};
    #[cfg(feature = "nalgebra")]
    pub use crate::{NalgebraF32, NalgebraF64};
}
