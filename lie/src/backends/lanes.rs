//! SIMD lanes as the scalar (feature `simd`): simba's `WideF64x4` and
//! `WideF32x8` implement [`SimdReal`], and nalgebra, generic over simba's
//! scalars, gives the lane backends [`NalgebraF64x4`](crate::NalgebraF64x4)
//! and [`NalgebraF32x8`](crate::NalgebraF32x8):
//! a `Vector3<WideF64x4>` is four 3-vectors, one per lane, and every formula
//! of this crate written over [`SimdBackend`](crate::SimdBackend) runs on four (or eight) inputs
//! per instruction stream.
//!
//! The transcendental functions are `wide`'s vectorised polynomials, not the
//! platform's `libm`: each lane agrees with the scalar `f64`/`f32` result to
//! a few ulp (the lane tests state the measured bounds), not to the bit.
//!
//! glam has no lane backend: its vector types fix their scalar (`Vec3` is
//! three `f32`, `DVec3` three `f64`), so there is no `Vec3` of lanes to be
//! had from it without writing a vector library of our own.

use crate::simd::{SimdMask, SimdReal};
use simba::simd::{SimdBool, SimdPartialOrd, SimdValue};
use simba::simd::{WideBoolF32x8, WideBoolF64x4, WideF32x8, WideF64x4};

macro_rules! lane_mask {
    ($m:ty) => {
        impl SimdMask for $m {
            #[inline(always)]
            fn all(self) -> bool {
                SimdBool::all(self)
            }
            #[inline(always)]
            fn any(self) -> bool {
                SimdBool::any(self)
            }
            #[inline(always)]
            fn splat(b: bool) -> Self {
                <Self as SimdValue>::splat(b)
            }
            #[inline(always)]
            fn extract(self, i: usize) -> bool {
                SimdValue::extract(&self, i)
            }
            #[inline(always)]
            fn bitmask(self) -> u64 {
                SimdBool::bitmask(self)
            }
        }
    };
}
lane_mask!(WideBoolF64x4);
lane_mask!(WideBoolF32x8);

macro_rules! lane_real {
    ($t:ident, $m:ident, $e:ty, $n:literal) => {
        impl SimdReal for $t {
            type Element = $e;
            type Mask = $m;
            const LANES: usize = $n;

            #[inline(always)]
            fn simd_splat(x: $e) -> Self {
                <Self as SimdValue>::splat(x)
            }
            #[inline(always)]
            fn simd_extract(self, i: usize) -> $e {
                <[$e; $n]>::from(self)[i]
            }
            #[inline(always)]
            fn simd_from_fn(f: impl FnMut(usize) -> $e) -> Self {
                Self::from(core::array::from_fn::<$e, $n, _>(f))
            }
            #[inline(always)]
            fn simd_eq(self, other: Self) -> $m {
                SimdPartialOrd::simd_eq(self, other)
            }
            #[inline(always)]
            fn simd_lt(self, other: Self) -> $m {
                SimdPartialOrd::simd_lt(self, other)
            }
            #[inline(always)]
            fn simd_le(self, other: Self) -> $m {
                SimdPartialOrd::simd_le(self, other)
            }
            #[inline(always)]
            fn simd_select(mask: $m, a: Self, b: Self) -> Self {
                a.select(mask, b)
            }
            #[inline(always)]
            fn simd_sqrt(self) -> Self {
                $t(self.0.sqrt())
            }
            #[inline(always)]
            fn simd_abs(self) -> Self {
                $t(self.0.abs())
            }
            #[inline(always)]
            fn simd_sin(self) -> Self {
                $t(self.0.sin())
            }
            #[inline(always)]
            fn simd_cos(self) -> Self {
                $t(self.0.cos())
            }
            #[inline(always)]
            fn simd_sin_cos(self) -> (Self, Self) {
                let (s, c) = self.0.sin_cos();
                ($t(s), $t(c))
            }
            #[inline(always)]
            fn simd_asin(self) -> Self {
                $t(self.0.asin())
            }
            #[inline(always)]
            fn simd_acos(self) -> Self {
                $t(self.0.acos())
            }
            #[inline(always)]
            fn simd_atan2(self, x: Self) -> Self {
                $t(self.0.atan2(x.0))
            }
            #[inline(always)]
            fn simd_is_finite(self) -> $m {
                $m(self.0.is_finite())
            }
        }
    };
}
lane_real!(WideF64x4, WideBoolF64x4, f64, 4);
lane_real!(WideF32x8, WideBoolF32x8, f32, 8);
