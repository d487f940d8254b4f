//! The interface both SO(3) representations implement, so controllers,
//! integrators and tests are written once for either: the group operations
//! come from [`LieGroup`] (its supertrait), this adds the representation's
//! conversions and the paper's attitude errors.

use crate::backend::ops;
use crate::{Backend, LieGroup, M3, Real, S, SimdBackend, V3};
use core::fmt::Debug;

/// What an attitude controller needs of a rotation, on any backend
/// including SIMD lanes ([`SimdBackend`]): the error rotation `R_dᵀR`, the
/// paper's `e_R` and `Ψ` read off it, and `Rᵀv`. A supertrait of
/// [`Rotation`], so code generic over `R: Rotation<B>` calls these as
/// before; code that must also run on lanes is written over this trait.
pub trait AttitudeErrors<B: SimdBackend>: Copy + Debug {
    /// `R_dᵀ R` (`self` is `R`), the rotation whose distance from the
    /// identity the paper's errors measure.
    fn error_rotation(self, rd: Self) -> Self;
    /// `Rᵀ v`, without forming the inverse.
    fn inverse_act(self, v: V3<B>) -> V3<B>;
    /// `(e_R, Ψ)` of this rotation against the identity. With
    /// `self = R_dᵀR` these are the paper's `e_R(R, R_d)` and `Ψ(R, R_d)`,
    /// so a controller that has formed `R_dᵀR` once (it also needs it for
    /// `RᵀR_dΩ_d`) gets both without another product.
    fn errors_to_identity(self) -> (V3<B>, S<B>);
    /// The rotation with body axes (matrix columns) `b1, b2, b3`, trusted
    /// to be orthonormal and right-handed: how a position controller turns
    /// the axes it constructs into its commanded attitude.
    fn from_frame(b1: V3<B>, b2: V3<B>, b3: V3<B>) -> Self;
    /// The body axes `R e1, R e2, R e3` (the matrix columns).
    fn body_axes(self) -> [V3<B>; 3];
}

/// The part of [`Rotation`] that every backend has, lane backends
/// included: SO(3) as a [`LieGroup`] with rotation-vector tangents and 3×3
/// Jacobians, plus the attitude errors. [`Se3`](crate::Se3) and
/// [`RigidState`](crate::RigidState) are generic over it, so they run on
/// lanes too. Implemented for every type with those two traits; the
/// adjoint of SO(3) is its rotation matrix, which is how code written over
/// this trait reads the matrix.
pub trait So3Group<B: SimdBackend>:
    LieGroup<B, Tangent = V3<B>, Jacobian = M3<B>, ActJacobian = M3<B>> + AttitudeErrors<B>
{
}

impl<B: SimdBackend, T> So3Group<B> for T where
    T: LieGroup<B, Tangent = V3<B>, Jacobian = M3<B>, ActJacobian = M3<B>> + AttitudeErrors<B>
{
}

/// An element of SO(3) in some representation (rotation matrix or unit
/// quaternion) on backend `B`. `R` maps body-frame vectors to the inertial
/// frame.
///
/// Code written against the trait runs on both representations:
///
/// ```
/// use lie::{Backend, NalgebraF64, Rotation, So3Mat, So3Quat};
/// type B = NalgebraF64;
///
/// /// The angle between two attitudes, from Ψ = 1 − cos θ.
/// fn angle<R: Rotation<B>>(a: R, b: R) -> f64 {
///     (1.0 - a.psi(b)).acos()
/// }
/// let phi = B::vec3(0.3, -0.2, 0.1);
/// let (m, q) = (So3Mat::<B>::exp(phi), So3Quat::<B>::exp(phi));
/// let theta = (0.09f64 + 0.04 + 0.01).sqrt();
/// assert!((angle(m, So3Mat::identity()) - theta).abs() < 1e-12);
/// assert!((angle(q, So3Quat::identity()) - theta).abs() < 1e-12);
/// ```
pub trait Rotation<B: Backend>:
    LieGroup<B, Tangent = V3<B>, Jacobian = M3<B>, ActJacobian = M3<B>>
    + Copy
    + Debug
    + PartialEq
    + core::ops::Mul<Output = Self>
    + AttitudeErrors<B>
{
    /// `"matrix"` or `"quaternion"`, for reports.
    const REPR: &'static str;

    /// The rotation matrix.
    fn matrix(self) -> M3<B>;
    /// From a rotation matrix, trusted to be orthogonal with det +1 (use
    /// [`So3Mat::project`](crate::So3Mat::project) for one that is not).
    fn from_matrix(m: M3<B>) -> Self;
    /// The unit quaternion.
    fn quaternion(self) -> B::Quat;
    /// From a unit quaternion.
    fn from_quaternion(q: B::Quat) -> Self;
    /// The paper's attitude error function (Proposition 1)
    /// `Ψ(R, R_d) = ½ tr(I − R_dᵀ R)`, in `[0, 2]`.
    fn psi(self, rd: Self) -> S<B>;
    /// The paper's attitude error vector (Proposition 1)
    /// `e_R = ½ (R_dᵀ R − Rᵀ R_d)^∨`, which is `sin θ · axis` of `R_dᵀ R`.
    fn e_r(self, rd: Self) -> V3<B>;
    /// `‖RᵀR − I‖_F` of the represented matrix: 0 on SO(3), grows with
    /// rounding drift.
    fn orthogonality_error(self) -> S<B>;
    /// Brought back onto SO(3): polar projection for a matrix, division by
    /// the norm for a quaternion.
    fn normalized(self) -> Self;

    /// The body axis `R e_k` (`k` in 0..3): a column of the matrix.
    #[inline]
    fn body_axis(self, k: usize) -> V3<B> {
        let z = S::<B>::lit(0.0);
        let o = S::<B>::lit(1.0);
        let e = [B::vec3(o, z, z), B::vec3(z, o, z), B::vec3(z, z, o)];
        self.act(e[k])
    }

    /// The angle of the rotation, in `[0, π]`.
    #[inline]
    fn angle(self) -> S<B> {
        ops::norm::<B>(self.log())
    }

    /// Geodesic interpolation `self · exp(t log(self⁻¹ · other))`: constant
    /// angular velocity from `self` (t = 0) to `other` (t = 1), along the
    /// shorter arc.
    #[inline]
    fn slerp(self, other: Self, t: S<B>) -> Self {
        self * Self::exp((self.inverse() * other).log() * t)
    }
}

/// The paper's angular-velocity error (Proposition 1)
/// `e_Ω = Ω − Rᵀ R_d Ω_d`, with `Ω` and `Ω_d` in their body frames.
#[inline]
pub fn e_omega<B: Backend, R: Rotation<B>>(r: R, omega: V3<B>, rd: R, omega_d: V3<B>) -> V3<B> {
    omega - r.inverse_act(rd.act(omega_d))
}
