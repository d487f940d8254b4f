//! The scalar bound shared by every formula, and the per-precision constants
//! (Taylor cut-offs) that the numerically delicate formulas switch on.

use crate::SimdReal;
use core::fmt::{Debug, Display};
use core::ops::{AddAssign, DivAssign, MulAssign, SubAssign};

/// A real scalar: `f32` or `f64`.
///
/// It carries the elementary functions as its own methods rather than
/// through `num_traits::Float` as a supertrait: a scalar defined in another
/// crate that cannot implement `Float` (a dual number for forward-mode
/// derivatives has no meaningful `classify` or `integer_decode`, and the
/// orphan rule forbids adding the impl here) can still implement `Real`, as
/// this trait is local. For `f32` and `f64` every method is the one
/// `num_traits::Float` gives (the platform library under `std`, `libm`
/// without), so results are unchanged bit for bit.
///
/// Besides the elementary functions it carries the Taylor cut-offs of the
/// small-angle formulas. They are per precision because the cancellation in
/// a closed form like `(θ − sin θ)/θ³` costs `ε/θ²` relative accuracy while a
/// truncated series costs its first dropped term: the crossover of the two
/// moves to larger angles when `ε` is larger. The values and their derivation
/// are given on each constant; `tests/so3_suite.rs` evaluates every formula
/// just either side of its cut-off.
///
/// ```
/// use lie::Real;
///
/// /// `(1 − cos θ)/θ²`, written once for f32 and f64.
/// fn half_versine_ratio<T: Real>(theta: T) -> T {
///     let h = theta * T::lit(0.5);
///     let s = h.sin() / h;
///     T::lit(0.5) * s * s
/// }
/// assert!((half_versine_ratio(1e-3f64) - 0.5).abs() < 1e-7);
/// assert!((half_versine_ratio(1e-3f32).to_f64_lossless() - 0.5).abs() < 1e-6);
/// ```
pub trait Real:
    SimdReal<Element = Self, Mask = bool>
    + PartialOrd
    + Debug
    + Display
    + Default
    + Send
    + Sync
    + AddAssign
    + SubAssign
    + MulAssign
    + DivAssign
    + 'static
{
    /// Short name used in reports (`"f32"`, `"f64"`).
    const NAME: &'static str;

    /// Below this angle, `sin θ/θ`, `2 sin²(θ/2)/θ²` and `sin(θ/2)/θ` use
    /// three-term series. Their closed forms have no cancellation (the
    /// half-angle form is used for the second), so the cut-off only has to
    /// keep `θ²` away from underflow and `0/0`; it is set where the first
    /// dropped term, `θ⁶/5040`, is far below one ulp. In f32 that allows a
    /// cut-off high enough that an IMU step or a filter's correction never
    /// calls `sin_cos`, which libm evaluates in software `f64` on a CPU
    /// without a double-precision unit.
    const CUT_EXP: Self;
    /// Below this angle `C = (θ − sin θ)/θ³` and `D = 1/θ² − cot(θ/2)/(2θ)`
    /// use seven-term series. Measured against 50-digit references: in f64
    /// at θ = 0.5 the series is within 5e-16 (relative) and the closed forms
    /// within 2e-15, while at 0.1 the closed forms lose 1e-13; in f32 the
    /// closed forms lose 1e-6 up to θ ≈ 1.2, the series stays at rounding
    /// level to 1.5.
    const CUT_JAC: Self;
    /// Below this angle `E = (θ² + 2cos θ − 2)/(2θ⁴)` and
    /// `F = (2θ − 3 sin θ + θ cos θ)/(2θ⁵)` use seven-term series. Their
    /// closed forms cancel harder (`θ⁴` out of `θ²`-sized terms): in f64 F's
    /// closed form is 1e-13 off at 0.5 and 2e-14 at 1.0, where the series is
    /// 8e-15; in f32 the closed forms stay 1e-5 off until θ ≈ 1.2 and the
    /// series is at rounding level to θ = 2.
    const CUT_JAC_SE3: Self;
    /// Below this norm of the quaternion's vector part the logarithm uses
    /// `2/w − (2/3)|q_v|²/w³` instead of `2 atan2(|q_v|, w)/|q_v|`; the dropped
    /// term is `(2/5)|q_v|⁴`, far below one ulp at the cut-off.
    const CUT_LOG: Self;

    /// Converts an `f64` literal (rounding for `f32`).
    fn lit(x: f64) -> Self;
    /// Widens to `f64` (exact for both implementors).
    fn to_f64_lossless(self) -> f64;

    // Elementary functions (named as in `num_traits::Float`, so that
    // generic code reads the same).
    /// |x|.
    fn abs(self) -> Self;
    /// The square root (NaN below zero).
    fn sqrt(self) -> Self;
    /// The sine.
    fn sin(self) -> Self;
    /// The cosine.
    fn cos(self) -> Self;
    /// The tangent.
    fn tan(self) -> Self;
    /// The arcsine, in [−π/2, π/2].
    fn asin(self) -> Self;
    /// The arccosine, in [0, π].
    fn acos(self) -> Self;
    /// The arctangent.
    fn atan(self) -> Self;
    /// `e^x`.
    fn exp(self) -> Self;
    /// The natural logarithm.
    fn ln(self) -> Self;
    /// `ln(1 + x)`, accurate for small `x`.
    fn ln_1p(self) -> Self;
    /// The largest integer not above `x`.
    fn floor(self) -> Self;
    /// The smallest integer not below `x`.
    fn ceil(self) -> Self;
    /// The nearest integer, halves away from zero.
    fn round(self) -> Self;
    /// `1` with the sign of `x` (NaN for NaN).
    fn signum(self) -> Self;
    /// The cube root.
    fn cbrt(self) -> Self;
    /// `sin x` and `cos x` together.
    fn sin_cos(self) -> (Self, Self);
    /// The four-quadrant arctangent of `self / x`, in [−π, π].
    fn atan2(self, x: Self) -> Self;
    /// `self` to an integer power.
    fn powi(self, n: i32) -> Self;
    /// `self` to a real power.
    fn powf(self, n: Self) -> Self;
    /// `sqrt(self² + y²)` without overflow in the squares.
    fn hypot(self, y: Self) -> Self;
    /// The larger of the two; the other one if either is NaN.
    fn max(self, other: Self) -> Self;
    /// The smaller of the two; the other one if either is NaN.
    fn min(self, other: Self) -> Self;
    /// Neither infinite nor NaN.
    fn is_finite(self) -> bool;
    /// Not a number.
    fn is_nan(self) -> bool;
    /// The difference between 1 and the next representable number.
    fn epsilon() -> Self;
    /// A quiet NaN.
    fn nan() -> Self;
    /// Positive infinity.
    fn infinity() -> Self;
    /// The largest finite value.
    fn max_value() -> Self;
    /// The smallest positive normal value.
    fn min_positive_value() -> Self;
    /// π.
    fn pi() -> Self;

    /// `x` as an input the derivatives are taken with respect to: direction
    /// `i` of a scalar that carries derivatives (`Dual`, feature `dual`),
    /// `lit(x)` for `f32`/`f64`.
    #[inline(always)]
    fn seeded(x: f64, i: usize) -> Self {
        let _ = i;
        Self::lit(x)
    }
}

/// `f32`'s and `f64`'s elementary functions: `num_traits::Float`'s, which
/// are the platform library's under `std` and `libm`'s without.
macro_rules! float_methods {
    ($t:ty) => {
        #[inline(always)]
        fn abs(self) -> $t {
            num_traits::Float::abs(self)
        }
        #[inline(always)]
        fn sqrt(self) -> $t {
            num_traits::Float::sqrt(self)
        }
        #[inline(always)]
        fn sin(self) -> $t {
            num_traits::Float::sin(self)
        }
        #[inline(always)]
        fn cos(self) -> $t {
            num_traits::Float::cos(self)
        }
        #[inline(always)]
        fn tan(self) -> $t {
            num_traits::Float::tan(self)
        }
        #[inline(always)]
        fn asin(self) -> $t {
            num_traits::Float::asin(self)
        }
        #[inline(always)]
        fn acos(self) -> $t {
            num_traits::Float::acos(self)
        }
        #[inline(always)]
        fn atan(self) -> $t {
            num_traits::Float::atan(self)
        }
        #[inline(always)]
        fn exp(self) -> $t {
            num_traits::Float::exp(self)
        }
        #[inline(always)]
        fn ln(self) -> $t {
            num_traits::Float::ln(self)
        }
        #[inline(always)]
        fn ln_1p(self) -> $t {
            num_traits::Float::ln_1p(self)
        }
        #[inline(always)]
        fn floor(self) -> $t {
            num_traits::Float::floor(self)
        }
        #[inline(always)]
        fn ceil(self) -> $t {
            num_traits::Float::ceil(self)
        }
        #[inline(always)]
        fn round(self) -> $t {
            num_traits::Float::round(self)
        }
        #[inline(always)]
        fn signum(self) -> $t {
            num_traits::Float::signum(self)
        }
        #[inline(always)]
        fn cbrt(self) -> $t {
            num_traits::Float::cbrt(self)
        }
        #[inline(always)]
        fn sin_cos(self) -> ($t, $t) {
            num_traits::Float::sin_cos(self)
        }
        #[inline(always)]
        fn atan2(self, x: $t) -> $t {
            num_traits::Float::atan2(self, x)
        }
        #[inline(always)]
        fn powi(self, n: i32) -> $t {
            num_traits::Float::powi(self, n)
        }
        #[inline(always)]
        fn powf(self, n: $t) -> $t {
            num_traits::Float::powf(self, n)
        }
        #[inline(always)]
        fn hypot(self, y: $t) -> $t {
            num_traits::Float::hypot(self, y)
        }
        #[inline(always)]
        fn max(self, other: $t) -> $t {
            num_traits::Float::max(self, other)
        }
        #[inline(always)]
        fn min(self, other: $t) -> $t {
            num_traits::Float::min(self, other)
        }
        #[inline(always)]
        fn is_finite(self) -> bool {
            num_traits::Float::is_finite(self)
        }
        #[inline(always)]
        fn is_nan(self) -> bool {
            num_traits::Float::is_nan(self)
        }
        #[inline(always)]
        fn epsilon() -> $t {
            <$t>::EPSILON
        }
        #[inline(always)]
        fn nan() -> $t {
            <$t>::NAN
        }
        #[inline(always)]
        fn infinity() -> $t {
            <$t>::INFINITY
        }
        #[inline(always)]
        fn max_value() -> $t {
            <$t>::MAX
        }
        #[inline(always)]
        fn min_positive_value() -> $t {
            <$t>::MIN_POSITIVE
        }
        #[inline(always)]
        fn pi() -> $t {
            core::f64::consts::PI as $t
        }
    };
}

impl Real for f64 {
    float_methods!(f64);
    const NAME: &'static str = "f64";
    const CUT_EXP: Self = 1e-3;
    const CUT_JAC: Self = 0.5;
    const CUT_JAC_SE3: Self = 1.0;
    const CUT_LOG: Self = 1e-8;
    #[inline(always)]
    fn lit(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn to_f64_lossless(self) -> f64 {
        self
    }
}

impl Real for f32 {
    float_methods!(f32);
    const NAME: &'static str = "f32";
    const CUT_EXP: Self = 0.1;
    const CUT_JAC: Self = 1.5;
    const CUT_JAC_SE3: Self = 2.0;
    const CUT_LOG: Self = 1e-4;
    #[inline(always)]
    fn lit(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn to_f64_lossless(self) -> f64 {
        self as f64
    }
}
