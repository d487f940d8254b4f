//! The scalar bound shared by every formula, and the per-precision constants
//! (Taylor cut-offs) that the numerically delicate formulas switch on.

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
pub trait Real:
    Float
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
    /// use five-term series. The closed forms lose `≈ 12 ε/θ²` (relative);
    /// the series' dropped term is `≈ 12 θ¹⁰/1.9·10⁹`; the cut-off is near the
    /// crossover (f64: 0.3, where both are ~1e-14; f32: 1.0).
    const CUT_JAC: Self;
    /// Below this angle `E = (θ² + 2 cos θ − 2)/(2θ⁴)` and
    /// `F = (2θ − 3 sin θ + θ cos θ)/(2θ⁵)` use five-term series. Their closed
    /// forms lose `≈ 24 ε/θ⁴` and `≈ 360 ε/θ⁴`; the crossover with the series'
    /// dropped term is at θ ≈ 0.45–0.5 in f64 and beyond 1.5 in f32.
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
    const CUT_JAC: Self = 0.3;
    const CUT_JAC_SE3: Self = 0.5;
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
    const CUT_JAC: Self = 1.0;
    const CUT_JAC_SE3: Self = 1.5;
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
