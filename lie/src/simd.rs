//! The lane-wise scalar: one trait for a real number and for a SIMD vector of
//! them, so that one formula advances one scene or four or eight.
//!
//! [`Real`] (`f32`, `f64`) is the one-lane case: its mask is `bool` and a
//! branch is an `if`. A lane type (`simba::simd::WideF64x4`, `WideF32x8`,
//! behind the `simd` feature) compares to a mask of lanes, and a branch
//! becomes: the one side when every lane takes it, the other when none
//! does, and both sides blended lane by lane otherwise. A formula written
//! with [`SimdReal::simd_branch`] therefore compiles, for `f32`/`f64`, to the
//! same `if`/`else` it was written as before, with the same results to the
//! bit, and for lanes to straight-line code that pays for both sides only
//! when its lanes disagree.
//!
//! The methods carry a `simd_` prefix (as simba's do) so that, on `f32`/`f64`,
//! they never clash with `num_traits::Float`'s of the same name.

use crate::Real;
use core::fmt::Debug;
use core::ops::SubAssign;
use core::ops::{Add, AddAssign, BitAnd, BitOr, Div, DivAssign, Mul, MulAssign, Neg, Not, Sub};
use num_traits::{One, Zero};

/// The result of a lane-wise comparison: `bool` for one lane.
pub trait SimdMask:
    Copy + Debug + PartialEq + BitAnd<Output = Self> + BitOr<Output = Self> + Not<Output = Self>
{
    /// Every lane is set.
    fn all(self) -> bool;
    /// At least one lane is set.
    fn any(self) -> bool;
    /// Every lane set to `b`.
    fn splat(b: bool) -> Self;
    /// Lane `i` (`i` < the number of lanes; panics otherwise).
    fn extract(self, i: usize) -> bool;
    /// Bit `i` set for each set lane `i`: one read of every lane, for a
    /// loop over the lanes of a mask that is rarely all-clear.
    fn bitmask(self) -> u64;
}

impl SimdMask for bool {
    #[inline(always)]
    fn extract(self, i: usize) -> bool {
        assert!(i == 0, "lane {i} of a one-lane mask");
        self
    }
    #[inline(always)]
    fn splat(b: bool) -> Self {
        b
    }
    #[inline(always)]
    fn all(self) -> bool {
        self
    }
    #[inline(always)]
    fn any(self) -> bool {
        self
    }
    #[inline(always)]
    fn bitmask(self) -> u64 {
        u64::from(self)
    }
}

/// A real number, or a fixed number of them computed in lock step.
///
/// ```
/// use lie::{Real, SimdReal};
///
/// /// `sin θ/θ` with its series below 1e-3, written once.
/// fn sinc<T: SimdReal>(theta: T) -> T {
///     let [s] = T::simd_branch(
///         theta.simd_lt(T::simd_lit(1e-3)),
///         || [T::one() - theta * theta * T::simd_lit(1.0 / 6.0)],
///         || [theta.simd_sin_cos().0 / theta],
///     );
///     s
/// }
/// assert_eq!(sinc(0.5f64), 0.5f64.sin() / 0.5);
/// assert_eq!(sinc(0.0f64), 1.0);
/// ```
pub trait SimdReal:
    Copy
    + Debug
    + PartialEq
    + Send
    + Sync
    + 'static
    + Zero
    + One
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
{
    /// The number in each lane, `f32` or `f64`.
    type Element: Real;
    /// What a comparison gives: `bool` for one lane.
    type Mask: SimdMask;
    /// Number of lanes (1 for `f32`/`f64`).
    const LANES: usize;

    /// Every lane set to `x`.
    fn simd_splat(x: Self::Element) -> Self;
    /// Every lane set to the literal `x` (rounded for `f32`).
    #[inline(always)]
    fn simd_lit(x: f64) -> Self {
        Self::simd_splat(<Self::Element as Real>::lit(x))
    }
    /// Lane `i`'s value (`i < LANES`; panics otherwise).
    fn simd_extract(self, i: usize) -> Self::Element;
    /// Lane `i` is `f(i)`.
    fn simd_from_fn(f: impl FnMut(usize) -> Self::Element) -> Self;

    /// Lane-wise `self == other`.
    fn simd_eq(self, other: Self) -> Self::Mask;
    /// Lane-wise `self < other`.
    fn simd_lt(self, other: Self) -> Self::Mask;
    /// Lane-wise `self ≤ other`.
    fn simd_le(self, other: Self) -> Self::Mask;
    /// Lane-wise `self > other`.
    #[inline(always)]
    fn simd_gt(self, other: Self) -> Self::Mask {
        other.simd_lt(self)
    }
    /// Lane-wise `self ≥ other`.
    #[inline(always)]
    fn simd_ge(self, other: Self) -> Self::Mask {
        other.simd_le(self)
    }
    /// Lane-wise: `a` where `mask` is set, else `b`.
    fn simd_select(mask: Self::Mask, a: Self, b: Self) -> Self;
    /// `if_true()` where `mask` is set, else `if_false()`, for a group of
    /// `N` values. One lane: an `if`. Lanes: only the side every lane takes,
    /// or both blended when they disagree.
    #[inline(always)]
    fn simd_branch<const N: usize>(
        mask: Self::Mask,
        if_true: impl FnOnce() -> [Self; N],
        if_false: impl FnOnce() -> [Self; N],
    ) -> [Self; N] {
        if mask.all() {
            if_true()
        } else if !mask.any() {
            if_false()
        } else {
            let (a, b) = (if_true(), if_false());
            core::array::from_fn(|i| Self::simd_select(mask, a[i], b[i]))
        }
    }

    /// Whether every element of `xs` equals zero (±0) in every lane.
    #[inline(always)]
    fn simd_all_zero<const N: usize>(xs: [Self; N]) -> bool {
        xs.iter().all(|x| x.simd_eq(Self::zero()).all())
    }

    /// Square root.
    fn simd_sqrt(self) -> Self;
    /// Absolute value.
    fn simd_abs(self) -> Self;
    /// Sine.
    fn simd_sin(self) -> Self;
    /// Cosine.
    fn simd_cos(self) -> Self;
    /// `(sin, cos)`.
    fn simd_sin_cos(self) -> (Self, Self);
    /// Inverse sine.
    fn simd_asin(self) -> Self;
    /// Inverse cosine.
    fn simd_acos(self) -> Self;
    /// Four-quadrant inverse tangent of `self / x`.
    fn simd_atan2(self, x: Self) -> Self;
    /// Lane-wise maximum.
    #[inline(always)]
    fn simd_max(self, other: Self) -> Self {
        Self::simd_select(self.simd_lt(other), other, self)
    }
    /// Lane-wise minimum.
    #[inline(always)]
    fn simd_min(self, other: Self) -> Self {
        Self::simd_select(other.simd_lt(self), other, self)
    }
    /// Lanes that are neither NaN nor ±∞.
    fn simd_is_finite(self) -> Self::Mask;

    /// Whether the scalar carries derivatives along (a dual number): code
    /// that only moves derivatives (the correction a located event makes
    /// to a forward-mode run) is compiled out for `f32`/`f64` and their lanes.
    const CARRIES_DERIVATIVES: bool = false;
    /// `self`'s value with `other`'s derivatives. A located event moves the
    /// derivatives of a state but not its value, which must stay the plain
    /// run's bit for bit. For `f32`/`f64` and lanes of them: `self`.
    #[inline(always)]
    fn with_derivatives_of(self, other: Self) -> Self {
        let _ = other;
        self
    }
}

/// `√x` for one `f32`. On an Arm core with a floating-point unit built
/// without `std` (a Cortex-M4F firmware), the FPU's `vsqrt.f32` (14 cycles
/// there) instead of libm's software square root (`sqrtf`: a call and ~60
/// integer instructions); both are the correctly rounded IEEE square root,
/// so no result changes (the firmware test compares the Cortex-M4F's
/// outputs with the host's bit for bit).
#[inline(always)]
fn sqrt_f32(x: f32) -> f32 {
    #[cfg(all(target_arch = "arm", target_feature = "fpregs", not(feature = "std")))]
    {
        let bits: u32;
        // SAFETY: moves through the caller-saved `s14`, declared clobbered;
        // no memory or stack access. (The `sreg` operand class would need
        // the double-precision `vfp2` feature, which a Cortex-M4F lacks.)
        unsafe {
            core::arch::asm!(
                "vmov s14, {0}",
                "vsqrt.f32 s14, s14",
                "vmov {0}, s14",
                inout(reg) x.to_bits() => bits,
                out("s14") _,
                options(pure, nomem, nostack),
            )
        };
        f32::from_bits(bits)
    }
    #[cfg(not(all(target_arch = "arm", target_feature = "fpregs", not(feature = "std"))))]
    {
        num_traits::Float::sqrt(x)
    }
}

macro_rules! one_lane {
    ($t:ty, $sqrt:path) => {
        impl SimdReal for $t {
            type Element = $t;
            type Mask = bool;
            const LANES: usize = 1;

            #[inline(always)]
            fn simd_splat(x: $t) -> $t {
                x
            }
            #[inline(always)]
            fn simd_extract(self, i: usize) -> $t {
                assert!(i == 0, "lane {i} of a one-lane scalar");
                self
            }
            #[inline(always)]
            fn simd_from_fn(mut f: impl FnMut(usize) -> $t) -> $t {
                f(0)
            }
            #[inline(always)]
            fn simd_eq(self, other: $t) -> bool {
                self == other
            }
            #[inline(always)]
            fn simd_lt(self, other: $t) -> bool {
                self < other
            }
            #[inline(always)]
            fn simd_le(self, other: $t) -> bool {
                self <= other
            }
            #[inline(always)]
            fn simd_gt(self, other: $t) -> bool {
                self > other
            }
            #[inline(always)]
            fn simd_ge(self, other: $t) -> bool {
                self >= other
            }
            #[inline(always)]
            fn simd_select(mask: bool, a: $t, b: $t) -> $t {
                if mask { a } else { b }
            }
            // An `if`, not the blend: exactly the branch the formulas had
            // when they were written for `f32`/`f64` alone.
            #[inline(always)]
            fn simd_branch<const N: usize>(
                mask: bool,
                if_true: impl FnOnce() -> [$t; N],
                if_false: impl FnOnce() -> [$t; N],
            ) -> [$t; N] {
                if mask { if_true() } else { if_false() }
            }
            // One OR of the bit patterns and one test instead of a
            // compare and two jumps per element: ±0 are the patterns
            // whose bits other than the sign are all clear.
            #[inline(always)]
            fn simd_all_zero<const N: usize>(xs: [$t; N]) -> bool {
                xs.iter().fold(0, |acc, x| acc | x.to_bits()) << 1 == 0
            }
            #[inline(always)]
            fn simd_sqrt(self) -> $t {
                $sqrt(self)
            }
            #[inline(always)]
            fn simd_abs(self) -> $t {
                num_traits::Float::abs(self)
            }
            #[inline(always)]
            fn simd_sin(self) -> $t {
                num_traits::Float::sin(self)
            }
            #[inline(always)]
            fn simd_cos(self) -> $t {
                num_traits::Float::cos(self)
            }
            #[inline(always)]
            fn simd_sin_cos(self) -> ($t, $t) {
                num_traits::Float::sin_cos(self)
            }
            #[inline(always)]
            fn simd_asin(self) -> $t {
                num_traits::Float::asin(self)
            }
            #[inline(always)]
            fn simd_acos(self) -> $t {
                num_traits::Float::acos(self)
            }
            #[inline(always)]
            fn simd_atan2(self, x: $t) -> $t {
                num_traits::Float::atan2(self, x)
            }
            #[inline(always)]
            fn simd_max(self, other: $t) -> $t {
                num_traits::Float::max(self, other)
            }
            #[inline(always)]
            fn simd_min(self, other: $t) -> $t {
                num_traits::Float::min(self, other)
            }
            #[inline(always)]
            fn simd_is_finite(self) -> bool {
                num_traits::Float::is_finite(self)
            }
        }
    };
}

one_lane!(f32, sqrt_f32);
one_lane!(f64, num_traits::Float::sqrt);
