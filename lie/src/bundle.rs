//! SO(3) × ℝ³ × ℝ³ × ℝ³, the state of a rigid body (attitude, position,
//! velocity, body rate) as one Lie group, so that estimators and
//! integrators can write `X ⊕ τ` and `Y ⊖ X` for the whole state.
//!
//! A product group composes component-wise, so everything about it is
//! block-diagonal: the exponential is SO(3)'s on the attitude and the
//! identity map on the three vectors, and its Jacobians and adjoint are
//! `diag(J_SO(3), I, I, I)` ([`BlockDiag4`]), twelve by twelve without
//! storing the zeros. The vector parts are perturbed additively in the
//! inertial frame (unlike SE(3), whose translation is perturbed in the
//! body frame); the attitude on the right, as everywhere in this crate.

use num_traits::Zero;

use crate::backend::ops;
use crate::{LieGroup, M3, S, SimdBackend, SimdReal, So3Group, V3, so3};

/// An element of SO(3) × ℝ³ × ℝ³ × ℝ³: the group operation is the
/// rotation's composition and the vectors' sum (not a rigid motion's
/// composition: see [`Se3`](crate::Se3) for that).
///
/// `repr(C)`: the state of an integrator (attitude as a matrix) and the
/// same state as a group element (attitude as [`So3Mat`](crate::So3Mat),
/// a transparent wrapper of that matrix) share one layout, so
/// [`RigidState::as_group`] lends one as the other without a copy.
#[derive(Copy, Clone, Debug, PartialEq)]
#[repr(C)]
pub struct RigidState<B: SimdBackend, R> {
    /// Attitude (body to inertial).
    pub r: R,
    /// Position, inertial frame.
    pub x: V3<B>,
    /// Velocity, inertial frame.
    pub v: V3<B>,
    /// Angular velocity, body frame.
    pub omega: V3<B>,
}

/// A tangent vector of [`RigidState`]: coordinates `(φ, x, v, Ω)` in this
/// order (twelve), `φ` the right perturbation of the attitude.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct RigidTangent<B: SimdBackend> {
    /// Rotation vector, on the right of the attitude.
    pub phi: V3<B>,
    /// Position increment.
    pub x: V3<B>,
    /// Velocity increment.
    pub v: V3<B>,
    /// Body-rate increment.
    pub omega: V3<B>,
}

impl<B: SimdBackend> RigidTangent<B> {
    /// Builds a tangent from its parts.
    #[inline]
    pub fn new(phi: V3<B>, x: V3<B>, v: V3<B>, omega: V3<B>) -> Self {
        Self { phi, x, v, omega }
    }
    #[inline]
    fn parts(self) -> [V3<B>; 4] {
        [self.phi, self.x, self.v, self.omega]
    }
    #[inline]
    fn from_parts([phi, x, v, omega]: [V3<B>; 4]) -> Self {
        Self { phi, x, v, omega }
    }
}

/// A 12×12 block-diagonal matrix `diag(A₀, A₁, A₂, A₃)` of 3×3 blocks, in
/// the tangent order `(φ, x, v, Ω)`: every Jacobian of a product group.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct BlockDiag4<B: SimdBackend>(pub [M3<B>; 4]);

impl<B: SimdBackend> BlockDiag4<B> {
    /// `diag(a, I, I, I)`: the shape of every Jacobian of [`RigidState`].
    #[inline]
    pub fn attitude(a: M3<B>) -> Self {
        let i = ops::identity::<B>();
        Self([a, i, i, i])
    }
    /// Element `(row, col)` of the 12×12 matrix.
    pub fn entry(&self, row: usize, col: usize) -> S<B> {
        if row / 3 != col / 3 {
            return S::<B>::zero();
        }
        ops::elems::<B>(self.0[row / 3])[row % 3][col % 3]
    }
}

/// The 3×12 Jacobian of [`RigidState::act`] with respect to the state,
/// as four 3×3 blocks side by side in the tangent order `(φ, x, v, Ω)`.
pub type ActBlocks<B> = [M3<B>; 4];

impl<B: SimdBackend, R: So3Group<B>> RigidState<B, R> {
    /// Builds a state from its parts.
    #[inline]
    pub fn new(r: R, x: V3<B>, v: V3<B>, omega: V3<B>) -> Self {
        Self { r, x, v, omega }
    }
}

/// The state as a simulation carries it: `R` the attitude matrix as
/// integrated (a Runge–Kutta step leaves it a little off SO(3); the group
/// operations want a rotation, hence [`RigidState::group`]). Vehicles,
/// control laws and integrators all take this one type.
impl<B: crate::Backend> RigidState<B, M3<B>> {
    /// At rest at the origin with `R = I` (the paper's initial hover).
    pub fn at_rest() -> Self {
        Self {
            r: ops::identity::<B>(),
            x: ops::zero::<B>(),
            v: ops::zero::<B>(),
            omega: ops::zero::<B>(),
        }
    }

    /// First field that holds a NaN or ±∞ (`"r"`, `"x"`, `"v"`, `"omega"`),
    /// if any.
    pub fn non_finite_field(&self) -> Option<&'static str> {
        if !ops::is_finite_mat::<B>(self.r) {
            Some("r")
        } else if !ops::is_finite_vec::<B>(self.x) {
            Some("x")
        } else if !ops::is_finite_vec::<B>(self.v) {
            Some("v")
        } else if !ops::is_finite_vec::<B>(self.omega) {
            Some("omega")
        } else {
            None
        }
    }

    /// The state of a group element, its attitude as a matrix (the inverse
    /// of [`RigidState::group`] for `So3Mat`).
    #[inline]
    pub fn from_group<R: crate::Rotation<B>>(g: RigidState<B, R>) -> Self {
        Self {
            r: g.r.matrix(),
            x: g.x,
            v: g.v,
            omega: g.omega,
        }
    }
}

impl<B: SimdBackend> RigidState<B, M3<B>> {
    /// [`RigidState::group`] by reference: the same state, seen with its
    /// attitude as an [`So3Mat`](crate::So3Mat) (unchecked), without a
    /// copy. A closed loop hands its integrator's state to the controller
    /// this way at every load evaluation: a copy of a state the stepper
    /// has just written is read back with loads wider than its stores,
    /// which miss store forwarding.
    #[inline]
    pub fn as_group(&self) -> &RigidState<B, crate::So3Mat<B>> {
        // SAFETY: `RigidState` is `repr(C)` and `So3Mat<B>` is
        // `repr(transparent)` over `M3<B>`, so the two types have the same
        // size, alignment, field offsets and validity; the borrow keeps
        // `self`'s lifetime. `So3Mat`'s rotation invariant is not checked,
        // exactly as `group` (`from_matrix_unchecked`) does not check it.
        unsafe { &*(self as *const Self).cast::<RigidState<B, crate::So3Mat<B>>>() }
    }
    /// The same state with its attitude taken as a rotation (unchecked),
    /// for `⊕`/`⊖` on the whole state: the attitude perturbed on the right,
    /// the vectors additively.
    #[inline]
    pub fn group(self) -> RigidState<B, crate::So3Mat<B>> {
        RigidState {
            r: crate::So3Mat::from_matrix_unchecked(self.r),
            x: self.x,
            v: self.v,
            omega: self.omega,
        }
    }
}

impl<B: SimdBackend, R: So3Group<B>> LieGroup<B> for RigidState<B, R> {
    const DOF: usize = 12;
    type Tangent = RigidTangent<B>;
    type Jacobian = BlockDiag4<B>;
    type ActJacobian = ActBlocks<B>;

    #[inline]
    fn identity() -> Self {
        let z = ops::zero::<B>();
        Self::new(R::identity(), z, z, z)
    }
    #[inline]
    fn compose(self, rhs: Self) -> Self {
        Self::new(
            self.r.compose(rhs.r),
            self.x + rhs.x,
            self.v + rhs.v,
            self.omega + rhs.omega,
        )
    }
    #[inline]
    fn inverse(self) -> Self {
        Self::new(self.r.inverse(), -self.x, -self.v, -self.omega)
    }
    /// `R p + x`: a point fixed in the body, in the inertial frame.
    #[inline]
    fn act(self, p: V3<B>) -> V3<B> {
        self.r.act(p) + self.x
    }
    #[inline]
    fn exp(tau: RigidTangent<B>) -> Self {
        Self::new(R::exp(tau.phi), tau.x, tau.v, tau.omega)
    }
    #[inline]
    fn log(self) -> RigidTangent<B> {
        RigidTangent::new(self.r.log(), self.x, self.v, self.omega)
    }
    #[inline]
    fn adjoint(self) -> BlockDiag4<B> {
        // SO(3)'s adjoint is its rotation matrix.
        BlockDiag4::attitude(self.r.adjoint())
    }
    #[inline]
    fn right_jacobian(tau: RigidTangent<B>) -> BlockDiag4<B> {
        BlockDiag4::attitude(so3::right_jacobian::<B>(tau.phi))
    }
    #[inline]
    fn right_jacobian_inv(tau: RigidTangent<B>) -> BlockDiag4<B> {
        BlockDiag4::attitude(so3::right_jacobian_inv::<B>(tau.phi))
    }
    #[inline]
    fn left_jacobian(tau: RigidTangent<B>) -> BlockDiag4<B> {
        BlockDiag4::attitude(so3::left_jacobian::<B>(tau.phi))
    }
    #[inline]
    fn left_jacobian_inv(tau: RigidTangent<B>) -> BlockDiag4<B> {
        BlockDiag4::attitude(so3::left_jacobian_inv::<B>(tau.phi))
    }
    /// `∂(R p + x)/∂(φ, x, v, Ω) = [−R p^, I, 0, 0]`, `∂/∂p = R`.
    fn act_jac(self, p: V3<B>) -> (V3<B>, ActBlocks<B>, M3<B>) {
        let r = self.r.adjoint();
        let zero = ops::diag::<B>(S::<B>::zero(), S::<B>::zero(), S::<B>::zero());
        let d_phi = r * so3::hat::<B>(p) * S::<B>::simd_lit(-1.0);
        (self.act(p), [d_phi, ops::identity::<B>(), zero, zero], r)
    }
    #[inline]
    fn tangent_neg(tau: RigidTangent<B>) -> RigidTangent<B> {
        RigidTangent::from_parts(tau.parts().map(|p| -p))
    }
    fn tangent_coord(tau: &RigidTangent<B>, i: usize) -> S<B> {
        B::vec3_to_array(tau.parts()[i / 3])[i % 3]
    }
    fn tangent_from_fn(mut f: impl FnMut(usize) -> S<B>) -> RigidTangent<B> {
        let parts = core::array::from_fn(|k| B::vec3(f(3 * k), f(3 * k + 1), f(3 * k + 2)));
        RigidTangent::from_parts(parts)
    }
    fn jacobian_entry(j: &BlockDiag4<B>, row: usize, col: usize) -> S<B> {
        j.entry(row, col)
    }
    fn act_jacobian_entry(j: &ActBlocks<B>, row: usize, col: usize) -> S<B> {
        ops::elems::<B>(j[col / 3])[row][col % 3]
    }
    #[inline]
    fn jacobian_apply(j: &BlockDiag4<B>, tau: RigidTangent<B>) -> RigidTangent<B> {
        let p = tau.parts();
        RigidTangent::from_parts(core::array::from_fn(|k| j.0[k] * p[k]))
    }
    #[inline]
    fn jacobian_identity() -> BlockDiag4<B> {
        BlockDiag4::attitude(ops::identity::<B>())
    }
    #[inline]
    fn jacobian_mul(a: BlockDiag4<B>, b: BlockDiag4<B>) -> BlockDiag4<B> {
        BlockDiag4(core::array::from_fn(|k| a.0[k] * b.0[k]))
    }
    #[inline]
    fn jacobian_neg(a: BlockDiag4<B>) -> BlockDiag4<B> {
        BlockDiag4(a.0.map(|m| m * S::<B>::simd_lit(-1.0)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{GlamF32, GlamF64, NalgebraF64, Real, Rotation, So3Mat};

    /// `as_group` lends the very fields of the state (no copy), and what
    /// it lends equals `group`'s copy, on both backends and scalars.
    fn lends<B: crate::Backend>() {
        let l = |a: f64, b: f64, c: f64| B::vec3(S::<B>::lit(a), S::<B>::lit(b), S::<B>::lit(c));
        let st = RigidState::<B, M3<B>> {
            r: So3Mat::<B>::exp(l(0.3, -0.2, 0.6)).matrix(),
            x: l(1.0, -2.0, 3.0),
            v: l(-0.5, 0.25, 0.125),
            omega: l(0.7, -0.3, 0.4),
        };
        let lent = st.as_group();
        assert_eq!(*lent, st.group());
        assert!(core::ptr::eq(&lent.x, &st.x));
        assert!(core::ptr::eq(&lent.omega, &st.omega));
        assert!(core::ptr::eq(
            (&lent.r as *const So3Mat<B>).cast::<M3<B>>(),
            &st.r
        ));
        assert_eq!(lent.r.matrix(), st.r);
    }

    #[test]
    fn as_group_lends_the_state_itself() {
        lends::<NalgebraF64>();
        lends::<GlamF64>();
        lends::<GlamF32>();
    }
}
