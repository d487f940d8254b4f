//! Between the C structs' arrays and glam's types, and between a z-up
//! stack's frames and the paper's.

use crate::{GpcPositionReference, GpcState, GpcStatus};
use glam_types::{Mat3, Vec3};

mod glam_types {
    pub(crate) type Vec3 = lie::V3<lie::GlamF32>;
    pub(crate) type Mat3 = lie::M3<lie::GlamF32>;
}

#[inline(always)]
pub(crate) fn vec(a: [f32; 3]) -> Vec3 {
    Vec3::from_array(a)
}

/// Row-major rows to a matrix (glam stores columns).
#[inline(always)]
pub(crate) fn mat(r: &[[f32; 3]; 3]) -> Mat3 {
    Mat3::from_cols_array_2d(r).transpose()
}

/// A matrix to row-major rows.
#[inline(always)]
pub(crate) fn rows(m: Mat3) -> [[f32; 3]; 3] {
    m.transpose().to_cols_array_2d()
}

/// `T = diag(1, −1, −1)`: x forward, y left, z up ↔ x forward, y right,
/// z down. A rotation about x by π, so `T = Tᵀ = T⁻¹` and frames keep
/// their handedness.
#[inline(always)]
fn flip(v: [f32; 3]) -> [f32; 3] {
    [v[0], -v[1], -v[2]]
}

/// Converts a vector between a z-up frame (x forward, y left, z up) and the
/// paper's z-down frame (x forward, y right, z down): `(x, −y, −z)`. The
/// map is its own inverse, so the same call takes a moment computed here
/// back to the z-up body frame. In C, pass arrays: `float m[3]` decays to
/// the pointer taken here. `input` and `output` may be the same array.
///
/// # Safety
/// Each pointer is NULL (a status) or points to three readable
/// (`input`) or writable (`output`) floats.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn gpc_vector_from_z_up(input: *const f32, output: *mut f32) -> GpcStatus {
    if input.is_null() || output.is_null() {
        return GpcStatus::NullPointer;
    }
    // SAFETY: non-NULL, and three floats by the caller's contract; read
    // fully before writing, so the two may alias.
    unsafe {
        let v = core::ptr::read_unaligned(input.cast::<[f32; 3]>());
        core::ptr::write_unaligned(output.cast::<[f32; 3]>(), flip(v));
    }
    GpcStatus::Ok
}

/// Converts a state from z-up world and body frames (the Crazyflie's:
/// x forward, y left, z up) to the paper's z-down frames:
/// `x ↦ Tx`, `v ↦ Tv`, `R ↦ T R T`, `Ω ↦ TΩ` with `T = diag(1, −1, −1)`.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_state_from_z_up(
    z_up: Option<&GpcState>,
    output: Option<&mut GpcState>,
) -> GpcStatus {
    let (Some(s), Some(o)) = (z_up.copied(), output) else {
        return GpcStatus::NullPointer;
    };
    let sign = [1.0, -1.0, -1.0];
    let mut r = s.r;
    for (i, row) in r.iter_mut().enumerate() {
        for (j, e) in row.iter_mut().enumerate() {
            *e *= sign[i] * sign[j];
        }
    }
    *o = GpcState {
        x: flip(s.x),
        v: flip(s.v),
        r,
        omega: flip(s.omega),
    };
    GpcStatus::Ok
}

/// Converts a position reference from a z-up world frame to the paper's:
/// every vector (`x_d` and its derivatives, `b1d` and its) mapped by
/// `T = diag(1, −1, −1)`.
#[unsafe(no_mangle)]
pub extern "C" fn gpc_position_reference_from_z_up(
    z_up: Option<&GpcPositionReference>,
    output: Option<&mut GpcPositionReference>,
) -> GpcStatus {
    let (Some(r), Some(o)) = (z_up.copied(), output) else {
        return GpcStatus::NullPointer;
    };
    *o = GpcPositionReference {
        x: flip(r.x),
        v: flip(r.v),
        a: flip(r.a),
        jerk: flip(r.jerk),
        snap: flip(r.snap),
        b1d: flip(r.b1d),
        b1d_dot: flip(r.b1d_dot),
        b1d_ddot: flip(r.b1d_ddot),
    };
    GpcStatus::Ok
}
