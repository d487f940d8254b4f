//! Small vector helpers the controllers need on top of `lie`'s backend
//! primitives: element-wise products (diagonal gains) and the derivatives
//! of a normalised vector.

use lie::num_traits::Float;
use lie::{Backend, S, V3};

#[inline(always)]
pub(crate) fn cmul<B: lie::SimdBackend>(a: V3<B>, b: V3<B>) -> V3<B> {
    let (a, b) = (B::vec3_to_array(a), B::vec3_to_array(b));
    B::vec3(a[0] * b[0], a[1] * b[1], a[2] * b[2])
}

#[inline(always)]
pub(crate) fn norm<B: lie::SimdBackend>(a: V3<B>) -> S<B> {
    lie::SimdReal::simd_sqrt(B::dot(a, a))
}

#[inline(always)]
pub(crate) fn is_finite<B: Backend>(a: V3<B>) -> bool {
    // Branch-free (`&`, not `all`): the law checks its output every call.
    let [x, y, z] = B::vec3_to_array(a);
    x.is_finite() & y.is_finite() & z.is_finite()
}

#[inline(always)]
pub(crate) fn zero<B: lie::SimdBackend>() -> V3<B> {
    let z = <S<B> as lie::SimdReal>::simd_lit(0.0);
    B::vec3(z, z, z)
}

/// `u/|u|` and its first two time derivatives given `u, u̇, ü`:
/// `ḃ = u̇/n − u (u·u̇)/n³`,
/// `b̈ = ü/n − (2u̇ (u·u̇) + u (u̇·u̇ + u·ü))/n³ + 3u (u·u̇)²/n⁵`.
/// Kept for the reference implementation the tests compare against.
#[cfg(test)]
#[inline]
pub(crate) fn unit_derivs<B: Backend>(u: V3<B>, ud: V3<B>, udd: V3<B>) -> (V3<B>, V3<B>, V3<B>) {
    use lie::Real;
    let n = norm::<B>(u);
    let inv = S::<B>::lit(1.0) / n;
    let inv3 = inv * inv * inv;
    let uud = B::dot(u, ud);
    let b = u * inv;
    let bd = ud * inv - u * (uud * inv3);
    let bdd = udd * inv
        - (ud * (S::<B>::lit(2.0) * uud) + u * (B::dot(ud, ud) + B::dot(u, udd))) * inv3
        + u * (S::<B>::lit(3.0) * uud * uud * inv3 * inv * inv);
    (b, bd, bdd)
}
