//! Moving values between a scalar backend and a lane backend: build the
//! lanes of a vector, matrix or quaternion from one scalar value per lane,
//! and read one lane back as a scalar value. Every function is generic over
//! the pair (`S`: `f32`/`f64`, `L`: lanes of the same precision), so
//! `NalgebraF64` ↔ `NalgebraF64x4` and `NalgebraF32` ↔ `NalgebraF32x8` are
//! covered by the same code. The `*_from_fn` builders call `f` once per
//! lane and component (a lane's value is read where it is needed; nothing
//! is buffered, so they work without an allocator).
//!
//! ```
//! # #[cfg(feature = "simd")] {
//! use lie::{NalgebraF64, NalgebraF64x4, SimdBackend, So3Mat, lanes};
//!
//! let phis = [0.0, 0.5, 1.5, 3.0].map(|a| NalgebraF64::vec3(a, 0.0, 0.1));
//! let phi = lanes::vec3_from_fn::<NalgebraF64, NalgebraF64x4>(|i| phis[i]);
//! let r = So3Mat::<NalgebraF64x4>::exp(phi);
//! let third = lanes::mat3_lane::<NalgebraF64, NalgebraF64x4>(r.as_matrix(), 2);
//! assert!((third - So3Mat::<NalgebraF64>::exp(phis[2]).as_matrix()).norm() < 1e-15);
//! # }
//! ```

use crate::{Backend, M3, SimdBackend, SimdReal, V3};

/// Lane `i` is `f(i)`.
#[inline]
pub fn vec3_from_fn<S, L>(f: impl Fn(usize) -> V3<S>) -> V3<L>
where
    S: Backend,
    L: SimdBackend<Scalar: SimdReal<Element = S::Scalar>>,
{
    let lane = |k: usize| <L::Scalar as SimdReal>::simd_from_fn(|i| S::vec3_to_array(f(i))[k]);
    L::vec3(lane(0), lane(1), lane(2))
}

/// Lane `i` of `v`.
#[inline]
pub fn vec3_lane<S, L>(v: V3<L>, i: usize) -> V3<S>
where
    S: Backend,
    L: SimdBackend<Scalar: SimdReal<Element = S::Scalar>>,
{
    let [x, y, z] = L::vec3_to_array(v);
    S::vec3(x.simd_extract(i), y.simd_extract(i), z.simd_extract(i))
}

/// Lane `i` is `f(i)`.
#[inline]
pub fn mat3_from_fn<S, L>(f: impl Fn(usize) -> M3<S>) -> M3<L>
where
    S: Backend,
    L: SimdBackend<Scalar: SimdReal<Element = S::Scalar>>,
{
    let cols = |c: usize| vec3_from_fn::<S, L>(|i| S::mat3_cols(f(i))[c]);
    L::mat3_from_cols(cols(0), cols(1), cols(2))
}

/// Lane `i` of `m`.
#[inline]
pub fn mat3_lane<S, L>(m: M3<L>, i: usize) -> M3<S>
where
    S: Backend,
    L: SimdBackend<Scalar: SimdReal<Element = S::Scalar>>,
{
    let [c0, c1, c2] = L::mat3_cols(m);
    S::mat3_from_cols(
        vec3_lane::<S, L>(c0, i),
        vec3_lane::<S, L>(c1, i),
        vec3_lane::<S, L>(c2, i),
    )
}

/// Lane `i` is `f(i)`.
#[inline]
pub fn quat_from_fn<S, L>(f: impl Fn(usize) -> S::Quat) -> L::Quat
where
    S: Backend,
    L: SimdBackend<Scalar: SimdReal<Element = S::Scalar>>,
{
    let lane = |k: usize| <L::Scalar as SimdReal>::simd_from_fn(|i| S::quat_to_wxyz(f(i))[k]);
    L::quat_from_wxyz(lane(0), lane(1), lane(2), lane(3))
}

/// Lane `i` of `q`.
#[inline]
pub fn quat_lane<S, L>(q: L::Quat, i: usize) -> S::Quat
where
    S: Backend,
    L: SimdBackend<Scalar: SimdReal<Element = S::Scalar>>,
{
    let [w, x, y, z] = L::quat_to_wxyz(q);
    S::quat_from_wxyz(
        w.simd_extract(i),
        x.simd_extract(i),
        y.simd_extract(i),
        z.simd_extract(i),
    )
}

/// The mask whose lane `i` is `f(i)`.
#[inline]
pub fn mask_from_fn<L: SimdBackend>(f: impl Fn(usize) -> bool) -> <L::Scalar as SimdReal>::Mask {
    let one = <L::Scalar as num_traits::One>::one();
    let v = <L::Scalar as SimdReal>::simd_from_fn(|i| {
        if f(i) {
            <<L::Scalar as SimdReal>::Element as num_traits::One>::one()
        } else {
            <<L::Scalar as SimdReal>::Element as num_traits::Zero>::zero()
        }
    });
    v.simd_eq(one)
}
