//! SO(3) in the unit-quaternion representation (the conversions it shares
//! with the matrix representation are in `convert`).

use crate::backend::ops;
use crate::convert::{log_wxyz, shepperd, to_matrix};
use crate::{AttitudeErrors, Backend, M3, Real, Rotation, S, SimdBackend, SimdReal, V3, series};
use num_traits::{One, Zero};

/// A rotation stored as a unit quaternion of the backend's own type
/// (`glam::Quat`, `glam::DQuat`, `nalgebra::UnitQuaternion`).
///
/// Products of unit quaternions drift from unit norm by about one ulp per
/// product; call [`Rotation::normalized`] every few thousand products in
/// f32 (the test suite measures the drift).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct So3Quat<B: SimdBackend>(pub(crate) B::Quat);

impl<B: SimdBackend> So3Quat<B> {
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

/// The group operations (also [`LieGroup`](crate::LieGroup)'s, which calls these): inherent,
/// so that a concrete rotation needs no trait in scope and never meets two
/// traits' methods of the same name. On lane backends too (`simd`).
impl<B: SimdBackend> So3Quat<B> {
    /// The unit quaternion: [`Rotation::quaternion`] under a name of its
    /// own, for lane backends, which have no [`Rotation`].
    #[inline]
    pub fn as_quaternion(self) -> B::Quat {
        self.0
    }
    /// The rotation matrix ([`Rotation::matrix`](crate::Rotation::matrix)
    /// under a name of its own, for lane backends, which have no `Rotation`).
    #[inline]
    pub fn to_matrix(self) -> M3<B> {
        to_matrix::<B>(self.0)
    }
    /// The identity rotation.
    #[inline]
    pub fn identity() -> Self {
        let (z, o) = (S::<B>::zero(), S::<B>::one());
        Self(B::quat_from_wxyz(o, z, z, z))
    }
    /// `self ∘ rhs` (apply `rhs` first).
    #[inline]
    pub fn compose(self, rhs: Self) -> Self {
        Self(B::quat_mul(self.0, rhs.0))
    }
    /// The inverse rotation.
    #[inline]
    pub fn inverse(self) -> Self {
        Self(B::quat_conj(self.0))
    }
    /// `R v`.
    #[inline]
    pub fn act(self, v: V3<B>) -> V3<B> {
        B::quat_rotate(self.0, v)
    }
    /// `(cos(θ/2), sin(θ/2)/θ · φ)`, with a series for `sin(θ/2)/θ` near 0.
    #[inline]
    pub fn exp(phi: V3<B>) -> Self {
        let (w, k) = series::quat_exp_coeffs(ops::norm::<B>(phi));
        let [x, y, z] = B::vec3_to_array(phi);
        Self(B::quat_from_wxyz(w, x * k, y * k, z * k))
    }
    /// The rotation vector, angle in `[0, π]` (at exactly π either of
    /// `±φ`): `2α q_v/|q_v|` with the half angle `α` from `asin|q_v|` or
    /// `acos w` ([`log_wxyz`](crate::log_wxyz)), the sign of `w` folded in.
    #[inline]
    pub fn log(self) -> V3<B> {
        log_wxyz::<B>(self.wxyz())
    }
}

impl<B: SimdBackend> So3Quat<B> {
    /// Shepperd's conversion followed by normalisation, so a matrix that
    /// is slightly off SO(3) still gives a unit quaternion.
    #[inline]
    fn from_matrix_normalized(m: M3<B>) -> Self {
        let [w, x, y, z] = shepperd::<B>(m);
        let n = S::<B>::one() / (w * w + x * x + y * y + z * z).simd_sqrt();
        Self(B::quat_from_wxyz(w * n, x * n, y * n, z * n))
    }
    /// The vector part of `q_d* ⊗ q` (`self` is `q`) and its `w`.
    #[inline]
    fn error_wxyz(self, rd: Self) -> [S<B>; 4] {
        B::quat_to_wxyz(B::quat_mul(B::quat_conj(rd.0), self.0))
    }
    #[inline]
    fn psi_against(self, rd: Self) -> S<B> {
        let [_, x, y, z] = self.error_wxyz(rd);
        S::<B>::simd_lit(2.0) * (x * x + y * y + z * z)
    }
    #[inline]
    fn e_r_against(self, rd: Self) -> V3<B> {
        let [w, x, y, z] = self.error_wxyz(rd);
        let k = S::<B>::simd_lit(2.0) * w;
        B::vec3(x * k, y * k, z * k)
    }
}

/// [`AttitudeErrors`]' operations, also inherent so that a concrete
/// rotation needs no trait in scope for them.
impl<B: SimdBackend> So3Quat<B> {
    /// `Rᵀ v`, without forming the inverse.
    #[inline]
    pub fn inverse_act(self, v: V3<B>) -> V3<B> {
        B::quat_rotate(B::quat_conj(self.0), v)
    }
    /// `(e_R, Ψ)` against the identity ([`AttitudeErrors::errors_to_identity`]).
    #[inline]
    pub fn errors_to_identity(self) -> (V3<B>, S<B>) {
        let id = Self::identity();
        (self.e_r_against(id), self.psi_against(id))
    }
}

impl<B: SimdBackend> AttitudeErrors<B> for So3Quat<B> {
    #[inline]
    fn error_rotation(self, rd: Self) -> Self {
        rd.inverse().compose(self)
    }
    #[inline]
    fn inverse_act(self, v: V3<B>) -> V3<B> {
        So3Quat::inverse_act(self, v)
    }
    #[inline]
    fn errors_to_identity(self) -> (V3<B>, S<B>) {
        So3Quat::errors_to_identity(self)
    }
    #[inline]
    fn from_frame(b1: V3<B>, b2: V3<B>, b3: V3<B>) -> Self {
        Self::from_matrix_normalized(B::mat3_from_cols(b1, b2, b3))
    }
    /// Each axis rotated on its own (as `Rotation::body_axis` does).
    #[inline]
    fn body_axes(self) -> [V3<B>; 3] {
        let (z, o) = (S::<B>::zero(), S::<B>::one());
        [B::vec3(o, z, z), B::vec3(z, o, z), B::vec3(z, z, o)].map(|e| self.act(e))
    }
}

impl<B: Backend> Rotation<B> for So3Quat<B> {
    const REPR: &'static str = "quaternion";

    #[inline]
    fn matrix(self) -> M3<B> {
        to_matrix::<B>(self.0)
    }
    /// Shepperd's conversion followed by normalisation, so a matrix that is
    /// slightly off SO(3) still gives a unit quaternion.
    #[inline]
    fn from_matrix(m: M3<B>) -> Self {
        Self::from_matrix_normalized(m)
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
        self.psi_against(rd)
    }
    /// `e_R = sin θ · axis = 2 w q_v` of the error quaternion `q_d* ⊗ q`.
    #[inline]
    fn e_r(self, rd: Self) -> V3<B> {
        self.e_r_against(rd)
    }
    /// `‖RᵀR − I‖_F` of the matrix the (possibly non-unit) quaternion maps
    /// to, `≈ 2√3 |‖q‖² − 1|`, so the two representations report the same
    /// measure.
    #[inline]
    fn orthogonality_error(self) -> S<B> {
        crate::convert::orthogonality_error::<B>(self.matrix())
    }
    #[inline]
    fn normalized(self) -> Self {
        let [w, x, y, z] = self.wxyz();
        let n = S::<B>::one() / (w * w + x * x + y * y + z * z).sqrt();
        Self(B::quat_from_wxyz(w * n, x * n, y * n, z * n))
    }
}

impl<B: SimdBackend> core::ops::Mul for So3Quat<B> {
    type Output = Self;
    #[inline]
    fn mul(self, rhs: Self) -> Self {
        self.compose(rhs)
    }
}
