//! Conversions both SO(3) representations use: the quaternion of a
//! rotation matrix (Shepperd), the logarithm of a quaternion, the matrix
//! of a unit quaternion, and the distance of a matrix from orthogonality.
//! `so3` and `quat` sit above this module and not above each other.

use crate::backend::ops;
use crate::{M3, Real, S, SimdBackend, SimdMask, SimdReal, V3};
use num_traits::{One, Zero};

/// Quaternion `[w, x, y, z]` (not normalised) of a rotation matrix by
/// Shepperd's method: the pivot is the largest of `tr R, R11, R22, R33`, so
/// the square root is taken of a number ≥ 1 and no component is divided by
/// a small one. Near angle π the trace-only formula would divide by `w ≈ 0`.
#[inline]
pub fn shepperd<B: SimdBackend>(m: M3<B>) -> [S<B>; 4] {
    let e = ops::elems::<B>(m);
    let one = S::<B>::one();
    let quarter = S::<B>::simd_lit(0.25);
    let half = S::<B>::simd_lit(0.5);
    let (m00, m11, m22) = (e[0][0], e[1][1], e[2][2]);
    let tr = m00 + m11 + m22;
    S::<B>::simd_branch(
        tr.simd_ge(m00) & tr.simd_ge(m11) & tr.simd_ge(m22),
        || {
            let w = half * (one + tr).simd_sqrt();
            let k = quarter / w;
            [
                w,
                (e[2][1] - e[1][2]) * k,
                (e[0][2] - e[2][0]) * k,
                (e[1][0] - e[0][1]) * k,
            ]
        },
        || {
            S::<B>::simd_branch(
                m00.simd_ge(m11) & m00.simd_ge(m22),
                || {
                    let x = half * (one + m00 - m11 - m22).simd_sqrt();
                    let k = quarter / x;
                    [
                        (e[2][1] - e[1][2]) * k,
                        x,
                        (e[0][1] + e[1][0]) * k,
                        (e[0][2] + e[2][0]) * k,
                    ]
                },
                || {
                    S::<B>::simd_branch(
                        m11.simd_ge(m22),
                        || {
                            let y = half * (one - m00 + m11 - m22).simd_sqrt();
                            let k = quarter / y;
                            [
                                (e[0][2] - e[2][0]) * k,
                                (e[0][1] + e[1][0]) * k,
                                y,
                                (e[1][2] + e[2][1]) * k,
                            ]
                        },
                        || {
                            let z = half * (one - m00 - m11 + m22).simd_sqrt();
                            let k = quarter / z;
                            [
                                (e[1][0] - e[0][1]) * k,
                                (e[0][2] + e[2][0]) * k,
                                (e[1][2] + e[2][1]) * k,
                                z,
                            ]
                        },
                    )
                },
            )
        },
    )
}

/// Logarithm of a unit quaternion given as `[w, x, y, z]`.
///
/// The sign is chosen so that `w ≥ 0`, which puts the angle in `[0, π]`.
/// The half angle `α` comes from whichever of `asin|q_v|` (below π/2,
/// where `|q_v| < w`) and `acos w` (above) is well conditioned there, then
/// `φ = 2α/|q_v| · q_v`; below `Real::CUT_LOG` the factor is the series
/// `2 + |q_v|²/3`. One `asin` or `acos` costs half an `atan2`, which is why
/// the unit norm is assumed rather than divided out: a quaternion off unit
/// norm by `δ` gives an angle off by about `δ` (products drift by an ulp
/// each). At exactly π (`w = 0`) the result has length π and either sign
/// of the axis is correct.
#[inline]
pub fn log_wxyz<B: SimdBackend>(q: [S<B>; 4]) -> V3<B> {
    let [w, x, y, z] = q;
    let [w, x, y, z] = S::<B>::simd_branch(
        w.simd_lt(S::<B>::zero()),
        || [-w, -x, -y, -z],
        || [w, x, y, z],
    );
    let n2 = x * x + y * y + z * z;
    let n = n2.simd_sqrt();
    let two = S::<B>::simd_lit(2.0);
    let [k] = S::<B>::simd_branch(
        n.simd_lt(S::<B>::simd_splat(<S<B> as SimdReal>::Element::CUT_LOG)),
        || [two + n2 * S::<B>::simd_lit(1.0 / 3.0)],
        || {
            S::<B>::simd_branch(
                n.simd_lt(w),
                || [two * n.simd_asin() / n],
                || [two * w.simd_acos() / n],
            )
        },
    );
    B::vec3(x * k, y * k, z * k)
}

/// Logarithm of a rotation matrix. Up to 2π/3 (`cos θ = (tr R − 1)/2 ≥
/// −1/2`), straight from the skew part `u = (R₃₂ − R₂₃, R₁₃ − R₃₁,
/// R₂₁ − R₁₂) = 2 sin θ · axis`, with one inverse sine: `θ = asin(|u|/2)`
/// below π/4 and `θ = π/2 − asin(cos θ)` from there, each argument where
/// `asin` is well conditioned (|x| ≤ 1/√2: condition number at most √2);
/// `acos` of the trace alone loses half the digits near 0. Which argument
/// is a select, not a branch, so angles on both sides of π/4 in one batch
/// cost no mispredictions, and the reciprocal of `|u|` is taken before
/// the call so that the division runs beside it. Beyond 2π/3 through
/// Shepperd's quaternion, where a diagonal pivot keeps the axis accurate up
/// to π (`u` vanishes there).
#[inline]
pub fn log_matrix<B: SimdBackend>(m: M3<B>) -> V3<B> {
    let e = ops::elems::<B>(m);
    let c2 = e[0][0] + e[1][1] + e[2][2] - S::<B>::one();
    let (ux, uy, uz) = (e[2][1] - e[1][2], e[0][2] - e[2][0], e[1][0] - e[0][1]);
    let s2 = ux * ux + uy * uy + uz * uz;
    let s = s2.simd_sqrt();
    let half = S::<B>::simd_lit(0.5);
    // Beyond 2π/3 in every lane (one lane: an early return). The matrix is
    // rebuilt here from the elements already read, so that only this rare
    // branch writes a copy for the call to point at (passing `m` made
    // every call copy the whole matrix first).
    let far = c2.simd_lt(S::<B>::simd_lit(-1.0));
    if far.all() {
        let [x, y, z] = log_beyond_two_thirds_pi::<B>(&ops::from_elems::<B>(e));
        return B::vec3(x, y, z);
    }
    // k = θ/(2 sin θ), so that φ = k u.
    let [k] = S::<B>::simd_branch(
        s.simd_lt(S::<B>::simd_splat(<S<B> as SimdReal>::Element::CUT_LOG)),
        || [half + s2 * S::<B>::simd_lit(1.0 / 48.0)],
        || {
            let small = c2.simd_gt(S::<B>::simd_lit(core::f64::consts::SQRT_2));
            let inv = S::<B>::one() / s;
            let quarter_turn = S::<B>::simd_lit(core::f64::consts::FRAC_PI_2);
            if <S<B> as SimdReal>::LANES == 1 {
                // One lane: a branch with an `asin` call on each side, so a
                // batch whose angles are mostly on one side of π/4 runs on
                // speculation; the select below, blended before the call,
                // put the compare on the call's critical path (1.3× over a
                // batch in f64).
                S::<B>::simd_branch(
                    small,
                    || [(s * half).simd_asin() * inv],
                    || [(quarter_turn - (c2 * half).simd_asin()) * inv],
                )
            } else {
                // Lanes: one `asin` for all lanes, its argument selected.
                let a = (S::<B>::simd_select(small, s, c2) * half).simd_asin();
                [S::<B>::simd_select(small, a, quarter_turn - a) * inv]
            }
        },
    );
    let near = [ux * k, uy * k, uz * k];
    // Lanes only (for one lane `far` is false here): some lanes beyond.
    if far.any() {
        let beyond = log_beyond_two_thirds_pi::<B>(&ops::from_elems::<B>(e));
        let [x, y, z] = core::array::from_fn(|i| S::<B>::simd_select(far, beyond[i], near[i]));
        return B::vec3(x, y, z);
    }
    B::vec3(near[0], near[1], near[2])
}

/// [`log_matrix`] beyond 2π/3, kept out of line: inlined, its quaternion
/// code crowded the common path's registers (1.2× nalgebra's log over a
/// batch of rotations instead of 1.01–1.07×). Returns an array, not a
/// vector, so that a three-`f32` result comes back in registers and an
/// `f64` one is written straight where the caller wants it.
#[inline(never)]
#[cold]
fn log_beyond_two_thirds_pi<B: SimdBackend>(m: &M3<B>) -> [S<B>; 3] {
    B::vec3_to_array(log_wxyz::<B>(shepperd::<B>(*m)))
}

/// The rotation matrix of a unit quaternion.
#[inline]
pub fn to_matrix<B: SimdBackend>(q: B::Quat) -> M3<B> {
    let [w, x, y, z] = B::quat_to_wxyz(q);
    let one = S::<B>::one();
    let two = S::<B>::simd_lit(2.0);
    let (xx, yy, zz) = (x * x, y * y, z * z);
    let (xy, xz, yz) = (x * y, x * z, y * z);
    let (wx, wy, wz) = (w * x, w * y, w * z);
    B::mat3_from_cols(
        B::vec3(one - two * (yy + zz), two * (xy + wz), two * (xz - wy)),
        B::vec3(two * (xy - wz), one - two * (xx + zz), two * (yz + wx)),
        B::vec3(two * (xz + wy), two * (yz - wx), one - two * (xx + yy)),
    )
}

/// `‖RᵀR − I‖_F`, the distance of a matrix from orthogonality.
#[inline]
pub fn orthogonality_error<B: SimdBackend>(m: M3<B>) -> S<B> {
    ops::frob_norm::<B>(B::mat3_transpose(m) * m - ops::identity::<B>())
}
