//! SE(3): rigid motions `(R, t)` acting on points as `p ↦ R p + t`.
//!
//! Tangent vectors are twists `ξ = (ρ, φ)`, translation part first (the
//! Barfoot–Furgale ordering), with `ξ^ = [[φ^, ρ], [0, 0]]`. Six-vectors and
//! 6×6 matrices are plain row-major arrays so the crate needs no 6-D type
//! from either backend.

use crate::backend::ops;
use crate::{M3, S, SimdBackend, SimdReal, So3Group, So3Mat, V3, series, so3};
use num_traits::{One, Zero};

/// A 6×6 matrix, row-major, indices `[row][col]`, twist order `(ρ, φ)`.
pub type Matrix6<T> = [[T; 6]; 6];
/// A 4×4 matrix, row-major, indices `[row][col]`.
pub type Matrix4<T> = [[T; 4]; 4];

/// A twist `(ρ, φ)`: `ρ` the translational part, `φ` the rotational part.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Twist<B: SimdBackend> {
    /// Translational part.
    pub rho: V3<B>,
    /// Rotational part.
    pub phi: V3<B>,
}

impl<B: SimdBackend> Twist<B> {
    /// Builds a twist from its parts.
    #[inline]
    pub fn new(rho: V3<B>, phi: V3<B>) -> Self {
        Self { rho, phi }
    }
    /// `[ρ1, ρ2, ρ3, φ1, φ2, φ3]`.
    #[inline]
    pub fn to_array(self) -> [S<B>; 6] {
        let (r, p) = (B::vec3_to_array(self.rho), B::vec3_to_array(self.phi));
        [r[0], r[1], r[2], p[0], p[1], p[2]]
    }
    /// From `[ρ1, ρ2, ρ3, φ1, φ2, φ3]`.
    #[inline]
    pub fn from_array(a: [S<B>; 6]) -> Self {
        Self {
            rho: B::vec3(a[0], a[1], a[2]),
            phi: B::vec3(a[3], a[4], a[5]),
        }
    }
    /// `ξ^`, the 4×4 matrix in se(3).
    pub fn hat(self) -> Matrix4<S<B>> {
        let p = ops::elems::<B>(so3::hat::<B>(self.phi));
        let r = B::vec3_to_array(self.rho);
        let z = S::<B>::zero();
        [
            [p[0][0], p[0][1], p[0][2], r[0]],
            [p[1][0], p[1][1], p[1][2], r[1]],
            [p[2][0], p[2][1], p[2][2], r[2]],
            [z, z, z, z],
        ]
    }
    /// The inverse of [`Twist::hat`] (reads the skew part of the rotation block).
    pub fn vee(m: Matrix4<S<B>>) -> Self {
        let blk = ops::from_elems::<B>([
            [m[0][0], m[0][1], m[0][2]],
            [m[1][0], m[1][1], m[1][2]],
            [m[2][0], m[2][1], m[2][2]],
        ]);
        Self {
            rho: B::vec3(m[0][3], m[1][3], m[2][3]),
            phi: so3::vee::<B>(blk),
        }
    }
}

/// A rigid motion with the rotation in representation `R` (matrix by default).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Se3<B: SimdBackend, R: So3Group<B> = So3Mat<B>> {
    /// The rotation part.
    pub rotation: R,
    /// The translation part.
    pub translation: V3<B>,
}

/// Writes the 3×3 block `m` into `out` at (`r0`, `c0`).
fn put_block<B: SimdBackend>(out: &mut Matrix6<S<B>>, r0: usize, c0: usize, m: M3<B>) {
    let e = ops::elems::<B>(m);
    for (i, row) in e.iter().enumerate() {
        out[r0 + i][c0..c0 + 3].copy_from_slice(row);
    }
}

/// `[[a, b], [0, a]]`, the shape of both the adjoint and the left Jacobian.
fn upper_block<B: SimdBackend>(a: M3<B>, b: M3<B>) -> Matrix6<S<B>> {
    let mut out = [[S::<B>::zero(); 6]; 6];
    put_block::<B>(&mut out, 0, 0, a);
    put_block::<B>(&mut out, 0, 3, b);
    put_block::<B>(&mut out, 3, 3, a);
    out
}

/// The block `Q(ρ, φ)` of the SE(3) left Jacobian (Barfoot & Furgale 2014):
/// `½ρ^ + C(φ^ρ^ + ρ^φ^ + φ^ρ^φ^) + E(φ^²ρ^ + ρ^φ^² − 3φ^ρ^φ^)
///  + F(φ^ρ^φ^² + φ^²ρ^φ^)`, coefficients in [`series`](crate::series).
pub fn q_block<B: SimdBackend>(rho: V3<B>, phi: V3<B>) -> M3<B> {
    let theta = ops::norm::<B>(phi);
    let (c, e, f) = (
        series::c_coeff(theta),
        series::e_coeff(theta),
        series::f_coeff(theta),
    );
    let p = so3::hat::<B>(phi);
    let r = so3::hat::<B>(rho);
    let pr = p * r;
    let rp = r * p;
    let prp = pr * p;
    let pp = p * p;
    r * S::<B>::simd_lit(0.5)
        + (pr + rp + prp) * c
        + (pp * r + rp * p - prp * S::<B>::simd_lit(3.0)) * e
        + (prp * p + p * prp) * f
}

impl<B: SimdBackend, R: So3Group<B>> Se3<B, R> {
    /// Builds a motion from its parts.
    #[inline]
    pub fn new(rotation: R, translation: V3<B>) -> Self {
        Self {
            rotation,
            translation,
        }
    }
    /// The identity motion.
    #[inline]
    pub fn identity() -> Self {
        Self {
            rotation: R::identity(),
            translation: ops::zero::<B>(),
        }
    }
    /// `self ∘ rhs`: `(R1 R2, R1 t2 + t1)`.
    #[inline]
    pub fn compose(self, rhs: Self) -> Self {
        Self {
            rotation: self.rotation.compose(rhs.rotation),
            translation: self.rotation.act(rhs.translation) + self.translation,
        }
    }
    /// `(Rᵀ, −Rᵀ t)`.
    #[inline]
    pub fn inverse(self) -> Self {
        Self {
            rotation: self.rotation.inverse(),
            translation: -self.rotation.inverse_act(self.translation),
        }
    }
    /// `R p + t`.
    #[inline]
    pub fn act(self, p: V3<B>) -> V3<B> {
        self.rotation.act(p) + self.translation
    }
    /// `exp(ξ^) = (exp(φ^), J_l(φ) ρ)`; `J_l` is the "V matrix".
    #[inline]
    pub fn exp(xi: Twist<B>) -> Self {
        Self {
            rotation: R::exp(xi.phi),
            translation: so3::left_jacobian::<B>(xi.phi) * xi.rho,
        }
    }
    /// `φ = log R`, `ρ = J_l⁻¹(φ) t`. Valid for rotation angles below π
    /// (`J_l⁻¹` is finite up to 2π, so angle π itself is fine too).
    #[inline]
    pub fn log(self) -> Twist<B> {
        let phi = self.rotation.log();
        Twist {
            rho: so3::left_jacobian_inv::<B>(phi) * self.translation,
            phi,
        }
    }
    /// The 6×6 adjoint `[[R, t^ R], [0, R]]`: `exp((Ad ξ)^) = X exp(ξ^) X⁻¹`.
    pub fn adjoint(self) -> Matrix6<S<B>> {
        // SO(3)'s adjoint is its rotation matrix.
        let r = self.rotation.adjoint();
        upper_block::<B>(r, so3::hat::<B>(self.translation) * r)
    }
    /// The homogeneous 4×4 matrix.
    pub fn to_homogeneous(self) -> Matrix4<S<B>> {
        let e = ops::elems::<B>(self.rotation.adjoint());
        let t = B::vec3_to_array(self.translation);
        let (z, o) = (S::<B>::zero(), S::<B>::one());
        [
            [e[0][0], e[0][1], e[0][2], t[0]],
            [e[1][0], e[1][1], e[1][2], t[1]],
            [e[2][0], e[2][1], e[2][2], t[2]],
            [z, z, z, o],
        ]
    }
}

impl<B: SimdBackend, R: So3Group<B>> core::ops::Mul for Se3<B, R> {
    type Output = Self;
    #[inline]
    fn mul(self, rhs: Self) -> Self {
        self.compose(rhs)
    }
}

/// The SE(3) left Jacobian `[[J_l(φ), Q(ρ, φ)], [0, J_l(φ)]]`:
/// `exp((ξ + δ)^) ≈ exp((J δ)^) exp(ξ^)`.
pub fn se3_left_jacobian<B: SimdBackend>(xi: Twist<B>) -> Matrix6<S<B>> {
    upper_block::<B>(
        so3::left_jacobian::<B>(xi.phi),
        q_block::<B>(xi.rho, xi.phi),
    )
}

/// The inverse of the SE(3) left Jacobian: with `J_l = [[J, Q], [0, J]]`
/// (`J` the SO(3) left Jacobian of `φ`), `J_l⁻¹ = [[J⁻¹, −J⁻¹QJ⁻¹], [0, J⁻¹]]`.
pub fn se3_left_jacobian_inv<B: SimdBackend>(xi: Twist<B>) -> Matrix6<S<B>> {
    let jinv = so3::left_jacobian_inv::<B>(xi.phi);
    let q = q_block::<B>(xi.rho, xi.phi);
    upper_block::<B>(jinv, jinv * q * jinv * S::<B>::simd_lit(-1.0))
}
