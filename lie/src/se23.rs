//! SE₂(3), the group of extended poses `(R, v, x)`: an attitude, a
//! velocity and a position, composed as the 5×5 matrices
//! `[[R, v, x], [0, 1, 0], [0, 0, 1]]`.
//!
//! It is the state space of the invariant EKF for inertial navigation
//! (Barrau & Bonnabel 2017): on it, IMU propagation with gravity is
//! group-affine, so the error of a right-invariant filter evolves
//! independently of the estimate. Tangent vectors are [`ExtTwist`]s
//! `(ρ, ν, φ)`, position part, velocity part, rotation part, in that order
//! (the translation-first order of [`Twist`](crate::Twist)). The algebra is
//! two SE(3) translations sharing one rotation, so every formula is SE(3)'s
//! applied to `ρ` and to `ν`:
//!
//! - `Exp(ρ, ν, φ) = (Exp φ, J_l(φ) ν, J_l(φ) ρ)`;
//! - `Adj(X) = [[R, 0, x^R], [0, R, v^R], [0, 0, R]]`;
//! - `J_l(ρ, ν, φ) = [[J_l(φ), 0, Q(ρ, φ)], [0, J_l(φ), Q(ν, φ)], [0, 0, J_l(φ)]]`
//!   with [`q_block`](crate::q_block) the SE(3) block, and `J_r(τ) = J_l(−τ)`.
//!
//! ```
//! use lie::{ExtTwist, LieGroup, NalgebraF64, Se23};
//! use nalgebra::Vector3;
//! type B = NalgebraF64;
//! let tau = ExtTwist::<B>::new(
//!     Vector3::new(1.0, 2.0, 3.0),   // ρ
//!     Vector3::new(0.1, 0.0, -0.2),  // ν
//!     Vector3::new(0.3, -0.2, 2.9),  // φ, near π
//! );
//! let x = Se23::<B>::exp(tau);
//! assert!((x.log().to_array().iter().zip(tau.to_array()))
//!     .all(|(a, b)| (a - b).abs() < 1e-12));
//! // Adj(X)·η = Log(X·Exp(η)·X⁻¹)
//! let eta = ExtTwist::<B>::from_array([0.1, 0.2, 0.3, -0.1, 0.0, 0.1, 0.01, 0.02, 0.0]);
//! let lhs = Se23::<B>::jacobian_apply(&x.adjoint(), eta).to_array();
//! let rhs = (x * Se23::<B>::exp(eta) * x.inverse()).log().to_array();
//! assert!(lhs.iter().zip(rhs).all(|(a, b)| (a - b).abs() < 1e-12));
//! ```

use num_traits::{One, Zero};

use crate::backend::ops;
use crate::se3::q_block;
use crate::{M3, S, SimdBackend, SimdReal, So3Group, So3Mat, V3, so3};

/// A 9×9 matrix, row-major, indices `[row][col]`, tangent order `(ρ, ν, φ)`.
pub type Matrix9<T> = [[T; 9]; 9];
/// A 3×9 matrix, row-major: the Jacobian of an SE₂(3) action with respect
/// to the extended pose.
pub type Matrix3x9<T> = [[T; 9]; 3];
/// A 5×5 matrix, row-major, indices `[row][col]`.
pub type Matrix5<T> = [[T; 5]; 5];

/// A tangent vector of SE₂(3): `(ρ, ν, φ)`.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct ExtTwist<B: SimdBackend> {
    /// Position part.
    pub rho: V3<B>,
    /// Velocity part.
    pub nu: V3<B>,
    /// Rotation part.
    pub phi: V3<B>,
}

impl<B: SimdBackend> ExtTwist<B> {
    /// Builds a tangent from its parts.
    #[inline]
    pub fn new(rho: V3<B>, nu: V3<B>, phi: V3<B>) -> Self {
        Self { rho, nu, phi }
    }
    /// `[ρ1, ρ2, ρ3, ν1, ν2, ν3, φ1, φ2, φ3]`.
    #[inline]
    pub fn to_array(self) -> [S<B>; 9] {
        let (r, n, p) = (
            B::vec3_to_array(self.rho),
            B::vec3_to_array(self.nu),
            B::vec3_to_array(self.phi),
        );
        [r[0], r[1], r[2], n[0], n[1], n[2], p[0], p[1], p[2]]
    }
    /// From `[ρ1, ρ2, ρ3, ν1, ν2, ν3, φ1, φ2, φ3]`.
    #[inline]
    pub fn from_array(a: [S<B>; 9]) -> Self {
        Self {
            rho: B::vec3(a[0], a[1], a[2]),
            nu: B::vec3(a[3], a[4], a[5]),
            phi: B::vec3(a[6], a[7], a[8]),
        }
    }
    /// `τ^`, the 5×5 matrix `[[φ^, ν, ρ], [0, 0, 0], [0, 0, 0]]`.
    pub fn hat(self) -> Matrix5<S<B>> {
        let p = ops::elems::<B>(so3::hat::<B>(self.phi));
        let (n, r) = (B::vec3_to_array(self.nu), B::vec3_to_array(self.rho));
        let z = S::<B>::zero();
        core::array::from_fn(|i| {
            if i < 3 {
                [p[i][0], p[i][1], p[i][2], n[i], r[i]]
            } else {
                [z; 5]
            }
        })
    }
    /// The inverse of [`ExtTwist::hat`] (reads the skew part of the
    /// rotation block).
    pub fn vee(m: Matrix5<S<B>>) -> Self {
        let blk = ops::from_elems::<B>(core::array::from_fn(|i| [m[i][0], m[i][1], m[i][2]]));
        Self {
            rho: B::vec3(m[0][4], m[1][4], m[2][4]),
            nu: B::vec3(m[0][3], m[1][3], m[2][3]),
            phi: so3::vee::<B>(blk),
        }
    }
}

/// An extended pose: attitude (body to world), velocity and position, with
/// the rotation in representation `R` (matrix by default).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Se23<B: SimdBackend, R: So3Group<B> = So3Mat<B>> {
    /// The attitude.
    pub rotation: R,
    /// The velocity.
    pub velocity: V3<B>,
    /// The position.
    pub position: V3<B>,
}

/// Writes the 3×3 block `m` into `out` at block (`r`, `c`).
fn put<B: SimdBackend>(out: &mut Matrix9<S<B>>, r: usize, c: usize, m: M3<B>) {
    let e = ops::elems::<B>(m);
    for (i, row) in e.iter().enumerate() {
        out[3 * r + i][3 * c..3 * c + 3].copy_from_slice(row);
    }
}

/// `[[a, 0, b], [0, a, c], [0, 0, a]]`: the shape of the adjoint and of
/// the left Jacobian and its inverse.
fn upper<B: SimdBackend>(a: M3<B>, b: M3<B>, c: M3<B>) -> Matrix9<S<B>> {
    let mut out = [[S::<B>::zero(); 9]; 9];
    for k in 0..3 {
        put::<B>(&mut out, k, k, a);
    }
    put::<B>(&mut out, 0, 2, b);
    put::<B>(&mut out, 1, 2, c);
    out
}

impl<B: SimdBackend, R: So3Group<B>> Se23<B, R> {
    /// Builds an extended pose from its parts.
    #[inline]
    pub fn new(rotation: R, velocity: V3<B>, position: V3<B>) -> Self {
        Self {
            rotation,
            velocity,
            position,
        }
    }
    /// The identity: level, at rest, at the origin.
    #[inline]
    pub fn identity() -> Self {
        Self::new(R::identity(), ops::zero::<B>(), ops::zero::<B>())
    }
    /// `self·rhs`: `(R₁R₂, R₁v₂ + v₁, R₁x₂ + x₁)`.
    #[inline]
    pub fn compose(self, rhs: Self) -> Self {
        Self {
            rotation: self.rotation.compose(rhs.rotation),
            velocity: self.rotation.act(rhs.velocity) + self.velocity,
            position: self.rotation.act(rhs.position) + self.position,
        }
    }
    /// `(Rᵀ, −Rᵀv, −Rᵀx)`.
    #[inline]
    pub fn inverse(self) -> Self {
        Self {
            rotation: self.rotation.inverse(),
            velocity: -self.rotation.inverse_act(self.velocity),
            position: -self.rotation.inverse_act(self.position),
        }
    }
    /// `R p + x`: the point `p` given in the body frame, in the world frame.
    #[inline]
    pub fn act(self, p: V3<B>) -> V3<B> {
        self.rotation.act(p) + self.position
    }
    /// `Exp(ρ, ν, φ) = (Exp φ, J_l(φ) ν, J_l(φ) ρ)`.
    #[inline]
    pub fn exp(tau: ExtTwist<B>) -> Self {
        let jl = so3::left_jacobian::<B>(tau.phi);
        Self {
            rotation: R::exp(tau.phi),
            velocity: jl * tau.nu,
            position: jl * tau.rho,
        }
    }
    /// `φ = Log R`, `ν = J_l⁻¹(φ) v`, `ρ = J_l⁻¹(φ) x`. Valid up to and at
    /// rotation angle π, as SE(3)'s.
    #[inline]
    pub fn log(self) -> ExtTwist<B> {
        let phi = self.rotation.log();
        let jinv = so3::left_jacobian_inv::<B>(phi);
        ExtTwist {
            rho: jinv * self.position,
            nu: jinv * self.velocity,
            phi,
        }
    }
    /// The 9×9 adjoint `[[R, 0, x^R], [0, R, v^R], [0, 0, R]]`.
    pub fn adjoint(self) -> Matrix9<S<B>> {
        // SO(3)'s adjoint is its rotation matrix.
        let r = self.rotation.adjoint();
        upper::<B>(
            r,
            so3::hat::<B>(self.position) * r,
            so3::hat::<B>(self.velocity) * r,
        )
    }
    /// The 5×5 matrix `[[R, v, x], [0, 1, 0], [0, 0, 1]]`.
    pub fn to_matrix(self) -> Matrix5<S<B>> {
        let e = ops::elems::<B>(self.rotation.adjoint());
        let (v, x) = (
            B::vec3_to_array(self.velocity),
            B::vec3_to_array(self.position),
        );
        let (z, o) = (S::<B>::zero(), S::<B>::one());
        [
            [e[0][0], e[0][1], e[0][2], v[0], x[0]],
            [e[1][0], e[1][1], e[1][2], v[1], x[1]],
            [e[2][0], e[2][1], e[2][2], v[2], x[2]],
            [z, z, z, o, z],
            [z, z, z, z, o],
        ]
    }
}

impl<B: SimdBackend, R: So3Group<B>> core::ops::Mul for Se23<B, R> {
    type Output = Self;
    #[inline]
    fn mul(self, rhs: Self) -> Self {
        self.compose(rhs)
    }
}

/// The SE₂(3) left Jacobian: `Exp(τ + δ) ≈ Exp(J_l(τ) δ)·Exp(τ)`.
pub fn se23_left_jacobian<B: SimdBackend>(tau: ExtTwist<B>) -> Matrix9<S<B>> {
    upper::<B>(
        so3::left_jacobian::<B>(tau.phi),
        q_block::<B>(tau.rho, tau.phi),
        q_block::<B>(tau.nu, tau.phi),
    )
}

/// The inverse of the SE₂(3) left Jacobian, in closed form: with `J` the
/// SO(3) left Jacobian of `φ`, the off-diagonal blocks are `−J⁻¹ Q J⁻¹`.
pub fn se23_left_jacobian_inv<B: SimdBackend>(tau: ExtTwist<B>) -> Matrix9<S<B>> {
    let jinv = so3::left_jacobian_inv::<B>(tau.phi);
    let neg = S::<B>::simd_lit(-1.0);
    upper::<B>(
        jinv,
        jinv * q_block::<B>(tau.rho, tau.phi) * jinv * neg,
        jinv * q_block::<B>(tau.nu, tau.phi) * jinv * neg,
    )
}

/// `A·B` for 9×9 matrices.
pub fn mul9<T: SimdReal>(a: &Matrix9<T>, b: &Matrix9<T>) -> Matrix9<T> {
    core::array::from_fn(|i| {
        core::array::from_fn(|j| (0..9).fold(T::zero(), |s, k| s + a[i][k] * b[k][j]))
    })
}
