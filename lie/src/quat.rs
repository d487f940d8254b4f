//! SO(3) in the unit-quaternion representation, and the quaternion
//! conversions that the matrix representation uses too (its logarithm goes
//! through [`shepperd`]).

use crate::Real as _;
use crate::backend::ops;
use crate::{Backend, M3, Rotation, S, V3, series};
use num_traits::{Float, One, Zero};

/// Quaternion `[w, x, y, z]` (not normalised) of a rotation matrix by
/// Shepperd's method: the pivot is the largest of `tr R, R11, R22, R33`, so
/// the square root is taken of a number ≥ 1 and no component is divided by
/// a small one. Near angle π the trace-only formula would divide by `w ≈ 0`.
#[inline]
pub fn shepperd<B: Backend>(m: M3<B>) -> [S<B>; 4] {
    let e = ops::elems::<B>(m);
    let one = S::<B>::one();
    let quarter = S::<B>::lit(0.25);
    let half = S::<B>::lit(0.5);
    let (m00, m11, m22) = (e[0][0], e[1][1], e[2][2]);
    let tr = m00 + m11 + m22;
    if tr >= m00 && tr >= m11 && tr >= m22 {
        let w = half * (one + tr).sqrt();
        let k = quarter / w;
        [
            w,
            (e[2][1] - e[1][2]) * k,
            (e[0][2] - e[2][0]) * k,
            (e[1][0] - e[0][1]) * k,
        ]
    } else if m00 >= m11 && m00 >= m22 {
        let x = half * (one + m00 - m11 - m22).sqrt();
        let k = quarter / x;
        [
            (e[2][1] - e[1][2]) * k,
            x,
            (e[0][1] + e[1][0]) * k,
            (e[0][2] + e[2][0]) * k,
        ]
    } else if m11 >= m22 {
        let y = half * (one - m00 + m11 - m22).sqrt();
        let k = quarter / y;
        [
            (e[0][2] - e[2][0]) * k,
            (e[0][1] + e[1][0]) * k,
            y,
            (e[1][2] + e[2][1]) * k,
        ]
    } else {
        let z = half * (one - m00 - m11 + m22).sqrt();
        let k = quarter / z;
        [
            (e[1][0] - e[0][1]) * k,
            (e[0][2] + e[2][0]) * k,
            (e[1][2] + e[2][1]) * k,
            z,
        ]
    }
}

/// Logarithm of a quaternion given as `[w, x, y, z]` (any positive scale).
///
/// The sign is chosen so that `w ≥ 0`, which puts the angle in `[0, π]`;
/// then `φ = 2 atan2(|q_v|, w)/|q_v| · q_v`, or its series
/// `(2/w − (2/3)|q_v|²/w³) q_v` below `Real::CUT_LOG`. At exactly π (`w = 0`)
/// the result has length π and either sign of the axis is correct.
#[inline]
pub fn log_wxyz<B: Backend>(q: [S<B>; 4]) -> V3<B> {
    let [mut w, mut x, mut y, mut z] = q;
    if w < S::<B>::zero() {
        (w, x, y, z) = (-w, -x, -y, -z);
    }
    let n2 = x * x + y * y + z * z;
    let n = n2.sqrt();
    let k = if n < S::<B>::CUT_LOG {
        let two = S::<B>::lit(2.0);
        two / w - S::<B>::lit(2.0 / 3.0) * n2 / (w * w * w)
    } else {
        S::<B>::lit(2.0) * n.atan2(w) / n
    };
    B::vec3(x * k, y * k, z * k)
}

/// The rotation matrix of a unit quaternion.
#[inline]
pub fn to_matrix<B: Backend>(q: B::Quat) -> M3<B> {
    let [w, x, y, z] = B::quat_to_wxyz(q);
    let one = S::<B>::one();
    let two = S::<B>::lit(2.0);
    let (xx, yy, zz) = (x * x, y * y, z * z);
    let (xy, xz, yz) = (x * y, x * z, y * z);
    let (wx, wy, wz) = (w * x, w * y, w * z);
    B::mat3_from_cols(
        B::vec3(one - two * (yy + zz), two * (xy + wz), two * (xz - wy)),
        B::vec3(two * (xy - wz), one - two * (xx + zz), two * (yz + wx)),
        B::vec3(two * (xz + wy), two * (yz - wx), one - two * (xx + yy)),
    )
}

/// A rotation stored as a unit quaternion of the backend's own type
/// (`glam::Quat`, `glam::DQuat`, `nalgebra::UnitQuaternion`).
///
/// Products of unit quaternions drift from unit norm by about one ulp per
/// product; call [`Rotation::normalized`] every few thousand products in
/// f32 (the test suite measures the drift).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct So3Quat<B: Backend>(pub(crate) B::Quat);

impl<B: Backend> So3Quat<B> {
    /// Wraps a quaternion the caller knows to have unit norm.
    #[inline]
    pub fn from_quaternion_unchecked(q: B::Quat) -> Self {
        Self(q)
    }
    #[inline]
    fn wxyz(self) -> [S<B>; 4] {
        B::quat_to_wxyz(self.0)
    }
}

impl<B: Backend> Rotation<B> for So3Quat<B> {
    const REPR: &'static str = "quaternion";

    #[inline]
    fn identity() -> Self {
        let (z, o) = (S::<B>::zero(), S::<B>::one());
        Self(B::quat_from_wxyz(o, z, z, z))
    }
    #[inline]
    fn compose(self, rhs: Self) -> Self {
        Self(B::quat_mul(self.0, rhs.0))
    }
    #[inline]
    fn inverse(self) -> Self {
        Self(B::quat_conj(self.0))
    }
    #[inline]
    fn act(self, v: V3<B>) -> V3<B> {
        B::quat_rotate(self.0, v)
    }
    #[inline]
    fn inverse_act(self, v: V3<B>) -> V3<B> {
        B::quat_rotate(B::quat_conj(self.0), v)
    }
    /// `(cos(θ/2), sin(θ/2)/θ · φ)`, with a series for `sin(θ/2)/θ` near 0.
    #[inline]
    fn exp(phi: V3<B>) -> Self {
        let (w, k) = series::quat_exp_coeffs(ops::norm::<B>(phi));
        let [x, y, z] = B::vec3_to_array(phi);
        Self(B::quat_from_wxyz(w, x * k, y * k, z * k))
    }
    #[inline]
    fn log(self) -> V3<B> {
        log_wxyz::<B>(self.wxyz())
    }
    #[inline]
    fn matrix(self) -> M3<B> {
        to_matrix::<B>(self.0)
    }
    /// Shepperd's conversion followed by normalisation, so a matrix that is
    /// slightly off SO(3) still gives a unit quaternion.
    #[inline]
    fn from_matrix(m: M3<B>) -> Self {
        let [w, x, y, z] = shepperd::<B>(m);
        let n = S::<B>::one() / (w * w + x * x + y * y + z * z).sqrt();
        Self(B::quat_from_wxyz(w * n, x * n, y * n, z * n))
    }
    #[inline]
    fn quaternion(self) -> B::Quat {
        self.0
    }
    #[inline]
    fn from_quaternion(q: B::Quat) -> Self {
        Self(q)
    }
    /// `Ψ = 1 − cos θ = 2|q_v|²` of the error quaternion `q_d* ⊗ q`: no
    /// cancellation near Ψ = 0, unlike `½(3 − tr)`.
    #[inline]
    fn psi(self, rd: Self) -> S<B> {
        let [_, x, y, z] = B::quat_to_wxyz(B::quat_mul(B::quat_conj(rd.0), self.0));
        S::<B>::lit(2.0) * (x * x + y * y + z * z)
    }
    /// `e_R = sin θ · axis = 2 w q_v` of the error quaternion `q_d* ⊗ q`.
    #[inline]
    fn e_r(self, rd: Self) -> V3<B> {
        let [w, x, y, z] = B::quat_to_wxyz(B::quat_mul(B::quat_conj(rd.0), self.0));
        let k = S::<B>::lit(2.0) * w;
        B::vec3(x * k, y * k, z * k)
    }
    /// `‖RᵀR − I‖_F` of the matrix the (possibly non-unit) quaternion maps
    /// to, `≈ 2√3 |‖q‖² − 1|`, so the two representations report the same
    /// measure.
    #[inline]
    fn orthogonality_error(self) -> S<B> {
        crate::so3::orthogonality_error::<B>(self.matrix())
    }
    #[inline]
    fn normalized(self) -> Self {
        let [w, x, y, z] = self.wxyz();
        let n = S::<B>::one() / (w * w + x * x + y * y + z * z).sqrt();
        Self(B::quat_from_wxyz(w * n, x * n, y * n, z * n))
    }
}

impl<B: Backend> core::ops::Mul for So3Quat<B> {
    type Output = Self;
    #[inline]
    fn mul(self, rhs: Self) -> Self {
        self.compose(rhs)
    }
}
