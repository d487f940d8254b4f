//! The scalar bound shared by every formula, and the per-precision constants
//! (Taylor cut-offs) that the numerically delicate formulas switch on.

use crate::SimdReal;
use core::fmt::{Debug, Display};
use core::ops::{AddAssign, DivAssign, MulAssign, SubAssign};
use num_traits::{Float, FloatConst};

/// A real scalar: `f32` or `f64`.
///
/// Besides `num_traits::Float` it carries the Taylor cut-offs of the
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
    + Float
    + FloatConst
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
    /// dropped term, `θ⁶/5040`, is far below one ulp.
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
}

impl Real for f64 {
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
    const NAME: &'static str = "f32";
    const CUT_EXP: Self = 1e-2;
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
