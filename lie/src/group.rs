//! One trait for the Lie groups of this crate, with the operations
//! estimation and optimisation code is written in: ⊕ and ⊖ on either
//! side, `between`, and the Jacobians of each with respect to each
//! argument.
//!
//! Conventions (those of Solà, Deray & Atchuthan, "A micro Lie theory for
//! state estimation in robotics", 2018, and of the manif library):
//!
//! - `X ⊕ τ = X·Exp(τ)` ([`LieGroup::rplus`]) and `Y ⊖ X = Log(X⁻¹·Y)`
//!   ([`LieGroup::rminus`]): perturbations are **right** (local, in the
//!   tangent space at `X`); `lplus`/`lminus` are the left (global)
//!   versions, `Exp(τ)·X` and `Log(Y·X⁻¹)`.
//! - A Jacobian `J = Df/DX` of `f: M → N` is the matrix with
//!   `f(X ⊕ τ) ⊖ f(X) ≈ J τ` for small `τ` (right perturbations on both
//!   sides); for a vector argument or value the plus and minus are the
//!   ordinary ones.
//! - SO(3) tangents are rotation vectors `φ` (3); SE(3) tangents are
//!   twists `(ρ, φ)`, translation first (6), as [`Twist`] orders them;
//!   SE₂(3) tangents are `(ρ, ν, φ)`, position, velocity, rotation (9),
//!   as [`ExtTwist`] orders them;
//!   the rigid-body state [`RigidState`](crate::RigidState) (SO(3) × ℝ⁹)
//!   has `(φ, x, v, Ω)` (12).
//!
//! [`Rotation`] (the paper's attitude errors and the representations'
//! conversions) has `LieGroup` as its supertrait, so code generic over
//! `R: Rotation<B>` has every group operation. `So3Mat`, `So3Quat` and
//! `Se3` also have the basic operations as inherent methods, so a concrete
//! type needs no trait in scope for them.
//!
//! ```
//! use lie::{Backend, LieGroup, NalgebraF64, So3Mat, ops};
//! type B = NalgebraF64;
//! // One EKF step on SO(3): predict with a gyro increment, correct with an
//! // attitude measurement, covariance carried in the tangent space.
//! let v = |x, y, z| B::vec3(x, y, z);
//! let mut x = So3Mat::<B>::identity();
//! let mut p = ops::diag::<B>(0.01, 0.01, 0.01);
//! let (x1, j_x, j_u) = x.rplus_jac(v(0.0, 0.0, 0.1));       // X ⊕ ω Δt
//! let q = ops::diag::<B>(1e-4, 1e-4, 1e-4);                 // gyro noise
//! p = j_x * p * B::mat3_transpose(j_x) + j_u * q * B::mat3_transpose(j_u);
//! x = x1;
//! let y = So3Mat::<B>::exp(v(0.02, -0.01, 0.1));            // a measurement
//! let (z, h, _) = y.rminus_jac(x);                          // z = y ⊖ x, H = ∂z/∂x
//! let r = ops::diag::<B>(1e-3, 1e-3, 1e-3);
//! let s = h * p * B::mat3_transpose(h) + r;
//! let k = p * B::mat3_transpose(h) * ops::inverse::<B>(s).unwrap();
//! x = x.rplus(k * z);                                       // correct
//! p = (ops::identity::<B>() - k * h) * p;
//! assert!(x.rminus(y).norm() < z.norm());                   // closer to the measurement
//! assert!(p[(0, 0)] < 0.0101 && p[(0, 0)] > 0.0);
//! ```

use num_traits::{One, Zero};

use crate::backend::ops;
use crate::se3::{Matrix6, Se3, Twist, se3_left_jacobian, se3_left_jacobian_inv};
use crate::se23::{
    ExtTwist, Matrix3x9, Matrix9, Se23, mul9, se23_left_jacobian, se23_left_jacobian_inv,
};
use crate::{M3, S, SimdBackend, SimdReal, So3Group, So3Mat, So3Quat, V3, so3};

/// A `3 × 6` matrix, row-major: the Jacobian of an SE(3) action with
/// respect to the transform.
pub type Matrix3x6<T> = [[T; 6]; 3];

/// A matrix Lie group: its operations and their Jacobians (see the
/// module docs for the conventions).
pub trait LieGroup<B: SimdBackend>: Copy {
    /// Degrees of freedom: the tangent space's dimension.
    const DOF: usize;
    /// A tangent vector (`V3` for SO(3), [`Twist`] for SE(3)).
    type Tangent: Copy;
    /// A `DOF × DOF` matrix (Jacobians, the adjoint).
    type Jacobian: Copy;
    /// The `3 × DOF` Jacobian of [`LieGroup::act`] with respect to the group
    /// element.
    type ActJacobian: Copy;

    /// The identity.
    fn identity() -> Self;
    /// `X·Y`.
    fn compose(self, rhs: Self) -> Self;
    /// `X⁻¹`.
    fn inverse(self) -> Self;
    /// `X·p` for a point `p`.
    fn act(self, p: V3<B>) -> V3<B>;
    /// `Exp(τ)`.
    fn exp(tau: Self::Tangent) -> Self;
    /// `Log(X)`.
    fn log(self) -> Self::Tangent;
    /// `Adj(X)`, with `Adj(X)·τ = Log(X·Exp(τ)·X⁻¹)`.
    fn adjoint(self) -> Self::Jacobian;
    /// The right Jacobian `J_r(τ)`: `Exp(τ + δ) ≈ Exp(τ)·Exp(J_r(τ)·δ)`.
    fn right_jacobian(tau: Self::Tangent) -> Self::Jacobian;
    /// `J_r(τ)⁻¹`.
    fn right_jacobian_inv(tau: Self::Tangent) -> Self::Jacobian;
    /// `X·p` with its Jacobians with respect to `X` and to `p`.
    fn act_jac(self, p: V3<B>) -> (V3<B>, Self::ActJacobian, M3<B>);

    /// `−τ`.
    fn tangent_neg(tau: Self::Tangent) -> Self::Tangent;
    /// Coordinate `i < DOF` of a tangent.
    fn tangent_coord(tau: &Self::Tangent, i: usize) -> S<B>;
    /// The tangent with coordinates `f(0), …, f(DOF − 1)`.
    fn tangent_from_fn(f: impl FnMut(usize) -> S<B>) -> Self::Tangent;
    /// Element `(row, col)` of a Jacobian.
    fn jacobian_entry(j: &Self::Jacobian, row: usize, col: usize) -> S<B>;
    /// Element `(row, col)` of an action Jacobian (`row < 3`).
    fn act_jacobian_entry(j: &Self::ActJacobian, row: usize, col: usize) -> S<B>;
    /// `J·τ`.
    fn jacobian_apply(j: &Self::Jacobian, tau: Self::Tangent) -> Self::Tangent;
    /// The identity matrix.
    fn jacobian_identity() -> Self::Jacobian;
    /// `A·B`.
    fn jacobian_mul(a: Self::Jacobian, b: Self::Jacobian) -> Self::Jacobian;
    /// `−A`.
    fn jacobian_neg(a: Self::Jacobian) -> Self::Jacobian;

    /// The left Jacobian `J_l(τ) = J_r(−τ)`.
    #[inline]
    fn left_jacobian(tau: Self::Tangent) -> Self::Jacobian {
        Self::right_jacobian(Self::tangent_neg(tau))
    }
    /// `J_l(τ)⁻¹`.
    #[inline]
    fn left_jacobian_inv(tau: Self::Tangent) -> Self::Jacobian {
        Self::right_jacobian_inv(Self::tangent_neg(tau))
    }
    /// `X ⊕ τ = X·Exp(τ)`.
    #[inline]
    fn rplus(self, tau: Self::Tangent) -> Self {
        self.compose(Self::exp(tau))
    }
    /// `τ ⊕ X = Exp(τ)·X`.
    #[inline]
    fn lplus(self, tau: Self::Tangent) -> Self {
        Self::exp(tau).compose(self)
    }
    /// `Y ⊖ X = Log(X⁻¹·Y)` with `self = Y`.
    #[inline]
    fn rminus(self, x: Self) -> Self::Tangent {
        x.inverse().compose(self).log()
    }
    /// `Log(Y·X⁻¹)` with `self = Y`.
    #[inline]
    fn lminus(self, x: Self) -> Self::Tangent {
        self.compose(x.inverse()).log()
    }
    /// `X⁻¹·Y` with `self = X`.
    #[inline]
    fn between(self, y: Self) -> Self {
        self.inverse().compose(y)
    }
    /// `X·Y` with `∂/∂X = Adj(Y)⁻¹ = Adj(Y⁻¹)` and `∂/∂Y = I`.
    fn compose_jac(self, rhs: Self) -> (Self, Self::Jacobian, Self::Jacobian) {
        (
            self.compose(rhs),
            rhs.inverse().adjoint(),
            Self::jacobian_identity(),
        )
    }
    /// `X⁻¹` with `∂/∂X = −Adj(X)`.
    fn inverse_jac(self) -> (Self, Self::Jacobian) {
        (self.inverse(), Self::jacobian_neg(self.adjoint()))
    }
    /// `X ⊕ τ` with `∂/∂X = Adj(Exp(τ))⁻¹` and `∂/∂τ = J_r(τ)`.
    fn rplus_jac(self, tau: Self::Tangent) -> (Self, Self::Jacobian, Self::Jacobian) {
        let e = Self::exp(tau);
        (
            self.compose(e),
            e.inverse().adjoint(),
            Self::right_jacobian(tau),
        )
    }
    /// `Y ⊖ X` (`self = Y`) with `∂/∂Y = J_r⁻¹(τ)` and `∂/∂X = −J_l⁻¹(τ)`,
    /// `τ = Y ⊖ X`.
    fn rminus_jac(self, x: Self) -> (Self::Tangent, Self::Jacobian, Self::Jacobian) {
        let tau = self.rminus(x);
        (
            tau,
            Self::right_jacobian_inv(tau),
            Self::jacobian_neg(Self::left_jacobian_inv(tau)),
        )
    }
    /// `X⁻¹·Y` (`self = X`) with `∂/∂X = −Adj(Y⁻¹·X)` and `∂/∂Y = I`.
    fn between_jac(self, y: Self) -> (Self, Self::Jacobian, Self::Jacobian) {
        let d = self.between(y);
        (
            d,
            Self::jacobian_neg(d.inverse().adjoint()),
            Self::jacobian_identity(),
        )
    }
}

/// SO(3) in either representation: the group part of [`Rotation`].
macro_rules! so3_group {
    ($t:ident, $matrix:ident) => {
        impl<B: SimdBackend> LieGroup<B> for $t<B> {
            const DOF: usize = 3;
            type Tangent = V3<B>;
            type Jacobian = M3<B>;
            type ActJacobian = M3<B>;

            #[inline]
            fn identity() -> Self {
                $t::<B>::identity()
            }
            #[inline]
            fn compose(self, rhs: Self) -> Self {
                $t::<B>::compose(self, rhs)
            }
            #[inline]
            fn inverse(self) -> Self {
                $t::<B>::inverse(self)
            }
            #[inline]
            fn act(self, p: V3<B>) -> V3<B> {
                $t::<B>::act(self, p)
            }
            #[inline]
            fn exp(tau: V3<B>) -> Self {
                $t::<B>::exp(tau)
            }
            #[inline]
            fn log(self) -> V3<B> {
                $t::<B>::log(self)
            }
            #[inline]
            fn adjoint(self) -> M3<B> {
                $t::<B>::$matrix(self)
            }
            #[inline]
            fn right_jacobian(tau: V3<B>) -> M3<B> {
                so3::right_jacobian::<B>(tau)
            }
            #[inline]
            fn right_jacobian_inv(tau: V3<B>) -> M3<B> {
                so3::right_jacobian_inv::<B>(tau)
            }
            #[inline]
            fn left_jacobian(tau: V3<B>) -> M3<B> {
                so3::left_jacobian::<B>(tau)
            }
            #[inline]
            fn left_jacobian_inv(tau: V3<B>) -> M3<B> {
                so3::left_jacobian_inv::<B>(tau)
            }
            fn act_jac(self, p: V3<B>) -> (V3<B>, M3<B>, M3<B>) {
                let r = $t::<B>::$matrix(self);
                (r * p, r * so3::hat::<B>(p) * S::<B>::simd_lit(-1.0), r)
            }
            #[inline]
            fn tangent_neg(tau: V3<B>) -> V3<B> {
                -tau
            }
            fn tangent_coord(tau: &V3<B>, i: usize) -> S<B> {
                B::vec3_to_array(*tau)[i]
            }
            fn tangent_from_fn(mut f: impl FnMut(usize) -> S<B>) -> V3<B> {
                B::vec3(f(0), f(1), f(2))
            }
            fn jacobian_entry(j: &M3<B>, row: usize, col: usize) -> S<B> {
                ops::elems::<B>(*j)[row][col]
            }
            fn act_jacobian_entry(j: &M3<B>, row: usize, col: usize) -> S<B> {
                ops::elems::<B>(*j)[row][col]
            }
            #[inline]
            fn jacobian_apply(j: &M3<B>, tau: V3<B>) -> V3<B> {
                *j * tau
            }
            #[inline]
            fn jacobian_identity() -> M3<B> {
                ops::identity::<B>()
            }
            #[inline]
            fn jacobian_mul(a: M3<B>, b: M3<B>) -> M3<B> {
                a * b
            }
            #[inline]
            fn jacobian_neg(a: M3<B>) -> M3<B> {
                a * S::<B>::simd_lit(-1.0)
            }
        }
    };
}

so3_group!(So3Mat, as_matrix);
so3_group!(So3Quat, to_matrix);

/// `A·B` for 6×6 matrices.
pub fn mul6<T: SimdReal>(a: &Matrix6<T>, b: &Matrix6<T>) -> Matrix6<T> {
    let mut out = [[T::zero(); 6]; 6];
    for (i, row) in out.iter_mut().enumerate() {
        for (j, o) in row.iter_mut().enumerate() {
            *o = (0..6).fold(T::zero(), |s, k| s + a[i][k] * b[k][j]);
        }
    }
    out
}

fn identity6<T: SimdReal>() -> Matrix6<T> {
    let mut out = [[T::zero(); 6]; 6];
    for (i, row) in out.iter_mut().enumerate() {
        row[i] = T::one();
    }
    out
}

impl<B: SimdBackend, R: So3Group<B>> LieGroup<B> for Se3<B, R> {
    const DOF: usize = 6;
    type Tangent = Twist<B>;
    type Jacobian = Matrix6<S<B>>;
    type ActJacobian = Matrix3x6<S<B>>;

    #[inline]
    fn identity() -> Self {
        Se3::identity()
    }
    #[inline]
    fn compose(self, rhs: Self) -> Self {
        Se3::compose(self, rhs)
    }
    #[inline]
    fn inverse(self) -> Self {
        Se3::inverse(self)
    }
    #[inline]
    fn act(self, p: V3<B>) -> V3<B> {
        Se3::act(self, p)
    }
    #[inline]
    fn exp(tau: Twist<B>) -> Self {
        Se3::exp(tau)
    }
    #[inline]
    fn log(self) -> Twist<B> {
        Se3::log(self)
    }
    #[inline]
    fn adjoint(self) -> Matrix6<S<B>> {
        Se3::adjoint(self)
    }
    fn right_jacobian(tau: Twist<B>) -> Matrix6<S<B>> {
        se3_left_jacobian::<B>(Self::tangent_neg(tau))
    }
    fn right_jacobian_inv(tau: Twist<B>) -> Matrix6<S<B>> {
        se3_left_jacobian_inv::<B>(Self::tangent_neg(tau))
    }
    fn left_jacobian(tau: Twist<B>) -> Matrix6<S<B>> {
        se3_left_jacobian::<B>(tau)
    }
    fn left_jacobian_inv(tau: Twist<B>) -> Matrix6<S<B>> {
        se3_left_jacobian_inv::<B>(tau)
    }
    /// `∂(R p + t)/∂X = [R, −R p^]` (right perturbation `(ρ, φ)`).
    fn act_jac(self, p: V3<B>) -> (V3<B>, Matrix3x6<S<B>>, M3<B>) {
        // SO(3)'s adjoint is its rotation matrix.
        let r = self.rotation.adjoint();
        let left = ops::elems::<B>(r);
        let right = ops::elems::<B>(r * so3::hat::<B>(p) * S::<B>::simd_lit(-1.0));
        let j = core::array::from_fn(|i| {
            core::array::from_fn(|k| if k < 3 { left[i][k] } else { right[i][k - 3] })
        });
        (self.act(p), j, r)
    }
    fn tangent_neg(tau: Twist<B>) -> Twist<B> {
        Twist::new(-tau.rho, -tau.phi)
    }
    fn tangent_coord(tau: &Twist<B>, i: usize) -> S<B> {
        tau.to_array()[i]
    }
    fn tangent_from_fn(f: impl FnMut(usize) -> S<B>) -> Twist<B> {
        Twist::from_array(core::array::from_fn(f))
    }
    fn jacobian_entry(j: &Matrix6<S<B>>, row: usize, col: usize) -> S<B> {
        j[row][col]
    }
    fn act_jacobian_entry(j: &Matrix3x6<S<B>>, row: usize, col: usize) -> S<B> {
        j[row][col]
    }
    fn jacobian_apply(j: &Matrix6<S<B>>, tau: Twist<B>) -> Twist<B> {
        let t = tau.to_array();
        Twist::from_array(j.map(|row| (0..6).fold(S::<B>::zero(), |s, k| s + row[k] * t[k])))
    }
    fn jacobian_identity() -> Matrix6<S<B>> {
        identity6()
    }
    fn jacobian_mul(a: Matrix6<S<B>>, b: Matrix6<S<B>>) -> Matrix6<S<B>> {
        mul6(&a, &b)
    }
    fn jacobian_neg(a: Matrix6<S<B>>) -> Matrix6<S<B>> {
        a.map(|r| r.map(|x| -x))
    }
}

impl<B: SimdBackend, R: So3Group<B>> LieGroup<B> for Se23<B, R> {
    const DOF: usize = 9;
    type Tangent = ExtTwist<B>;
    type Jacobian = Matrix9<S<B>>;
    type ActJacobian = Matrix3x9<S<B>>;

    #[inline]
    fn identity() -> Self {
        Se23::identity()
    }
    #[inline]
    fn compose(self, rhs: Self) -> Self {
        Se23::compose(self, rhs)
    }
    #[inline]
    fn inverse(self) -> Self {
        Se23::inverse(self)
    }
    #[inline]
    fn act(self, p: V3<B>) -> V3<B> {
        Se23::act(self, p)
    }
    #[inline]
    fn exp(tau: ExtTwist<B>) -> Self {
        Se23::exp(tau)
    }
    #[inline]
    fn log(self) -> ExtTwist<B> {
        Se23::log(self)
    }
    #[inline]
    fn adjoint(self) -> Matrix9<S<B>> {
        Se23::adjoint(self)
    }
    fn right_jacobian(tau: ExtTwist<B>) -> Matrix9<S<B>> {
        se23_left_jacobian::<B>(Self::tangent_neg(tau))
    }
    fn right_jacobian_inv(tau: ExtTwist<B>) -> Matrix9<S<B>> {
        se23_left_jacobian_inv::<B>(Self::tangent_neg(tau))
    }
    fn left_jacobian(tau: ExtTwist<B>) -> Matrix9<S<B>> {
        se23_left_jacobian::<B>(tau)
    }
    fn left_jacobian_inv(tau: ExtTwist<B>) -> Matrix9<S<B>> {
        se23_left_jacobian_inv::<B>(tau)
    }
    /// `∂(R p + x)/∂X = [R, 0, −R p^]` (right perturbation `(ρ, ν, φ)`).
    fn act_jac(self, p: V3<B>) -> (V3<B>, Matrix3x9<S<B>>, M3<B>) {
        // SO(3)'s adjoint is its rotation matrix.
        let r = self.rotation.adjoint();
        let left = ops::elems::<B>(r);
        let right = ops::elems::<B>(r * so3::hat::<B>(p) * S::<B>::simd_lit(-1.0));
        let j = core::array::from_fn(|i| {
            core::array::from_fn(|k| match k {
                0..3 => left[i][k],
                3..6 => S::<B>::zero(),
                _ => right[i][k - 6],
            })
        });
        (self.act(p), j, r)
    }
    fn tangent_neg(tau: ExtTwist<B>) -> ExtTwist<B> {
        ExtTwist::new(-tau.rho, -tau.nu, -tau.phi)
    }
    fn tangent_coord(tau: &ExtTwist<B>, i: usize) -> S<B> {
        tau.to_array()[i]
    }
    fn tangent_from_fn(f: impl FnMut(usize) -> S<B>) -> ExtTwist<B> {
        ExtTwist::from_array(core::array::from_fn(f))
    }
    fn jacobian_entry(j: &Matrix9<S<B>>, row: usize, col: usize) -> S<B> {
        j[row][col]
    }
    fn act_jacobian_entry(j: &Matrix3x9<S<B>>, row: usize, col: usize) -> S<B> {
        j[row][col]
    }
    fn jacobian_apply(j: &Matrix9<S<B>>, tau: ExtTwist<B>) -> ExtTwist<B> {
        let t = tau.to_array();
        ExtTwist::from_array(j.map(|row| (0..9).fold(S::<B>::zero(), |s, k| s + row[k] * t[k])))
    }
    fn jacobian_identity() -> Matrix9<S<B>> {
        core::array::from_fn(|i| {
            core::array::from_fn(|j| {
                if i == j {
                    S::<B>::one()
                } else {
                    S::<B>::zero()
                }
            })
        })
    }
    fn jacobian_mul(a: Matrix9<S<B>>, b: Matrix9<S<B>>) -> Matrix9<S<B>> {
        mul9(&a, &b)
    }
    fn jacobian_neg(a: Matrix9<S<B>>) -> Matrix9<S<B>> {
        a.map(|r| r.map(|x| -x))
    }
}
