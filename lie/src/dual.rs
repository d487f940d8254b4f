//! The forward-mode dual scalar (feature `dual`): see [`Dual`].

use crate::{Real, SimdReal};
use core::cmp::Ordering;
use core::fmt;
use core::ops::{Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Sub, SubAssign};
use num_traits::{One, Zero};

/// Forward-mode dual numbers as the scalar (feature `dual`): derivatives of
/// any formula of the workspace, computed by the same code that computes its
/// value.
///
/// A [`Dual<N>`] is a real part and `N` directional derivatives,
/// `x + Σ εᵢ ẋᵢ` with `εᵢ εⱼ = 0`. Every operation applies the chain rule to
/// the derivatives and computes the real part with **exactly the `f64`
/// operation** the plain run performs (`a / b` is a division, not `a · b⁻¹`;
/// `powi` and `hypot` are the library's own), so the real part of a dual run
/// is the `f64` run bit for bit. That is why this type is written here
/// rather than taken from `num-dual`: that crate computes the real part of a
/// quotient as `a · (1/b)` and of `powi` as `x^(n−3)·x·x·x`, which differ
/// from the `f64` results in the last bit, and the derivative of a closed
/// loop is only the derivative *of the flight that was flown* when the
/// primal run is that flight.
///
/// The derivatives are not bound to the same rule: where the build has FMA
/// (`target-cpu=x86-64-v3` or newer), the product and quotient rules fuse
/// their multiply-adds (a quarter off a gradient), so derivatives may
/// differ in the last bits from one build to another; the real part never
/// does.
///
/// Comparisons (`==`, `<`, and [`SimdReal::simd_lt`]) read the real part
/// only, so every branch, step-size decision and event takes the path the
/// `f64` run takes. [`SimdReal::simd_eq`] compares the derivatives too: it
/// guards exactness shortcuts (a diagonal matrix's product skipping its zero
/// off-diagonal terms), and a zero whose derivative is not zero must not be
/// skipped.
///
/// Where a function is not differentiable at a point the primal run can
/// reach — `√x` and `hypot` at 0, `atan2(0, 0)` — a zero derivative stays
/// exactly zero (the norm of a vector that is zero with all its derivatives,
/// e.g. the rotation vector of `exp(0 ⊕ δ)` when `δ` is not seeded), and a
/// nonzero one becomes infinite, so that a check of finiteness stops the run
/// instead of a NaN spreading. The formulas of this crate never take a square
/// root at zero with a live derivative: their small-angle branches are
/// polynomials in `θ²`.
///
/// ```
/// use lie::{Dual, NalgebraDual, NalgebraF64, So3Mat, so3};
/// use nalgebra::Vector3;
///
/// // ∂ exp(φ)/∂φₖ at φ = (0.3, −0.2, 0.1), the three components seeded.
/// let phi = [0.3, -0.2, 0.1];
/// let seeded = Vector3::from_fn(|k, _| Dual::<3>::variable(phi[k], k));
/// let r = So3Mat::<NalgebraDual<3>>::exp(seeded).as_matrix();
/// let value = r.map(|x| x.re);
/// // The real part is the f64 computation, bit for bit.
/// assert_eq!(value, So3Mat::<NalgebraF64>::exp(Vector3::from(phi)).as_matrix());
/// // Rᵀ ∂R/∂φₖ is the k-th column of the right Jacobian J_r(φ), hatted.
/// let jr = so3::right_jacobian::<NalgebraF64>(Vector3::from(phi));
/// for k in 0..3 {
///     let w = value.transpose() * r.map(|x| x.eps[k]);
///     let col = Vector3::new(w[(2, 1)], w[(0, 2)], w[(1, 0)]);
///     assert!((col - jr.column(k)).norm() < 1e-15);
/// }
/// ```
// The derivatives first and the whole aligned to 32 bytes: their vectors
// (four `f64` each) then never straddle a cache line, and the copies of a
// value are whole aligned vector moves (128 bytes for 12 directions
// instead of 104: the padding costs less than the split loads).
#[derive(Clone, Copy, Debug)]
#[repr(C, align(32))]
pub struct Dual<const N: usize> {
    /// The derivatives of the value along each seeded direction.
    pub eps: [f64; N],
    /// The value: bit for bit what the `f64` computation gives.
    pub re: f64,
}

impl<const N: usize> Dual<N> {
    /// A constant: all derivatives zero.
    #[inline(always)]
    pub const fn constant(re: f64) -> Self {
        Self { re, eps: [0.0; N] }
    }

    /// The `i`-th seeded input: derivative 1 along direction `i`, 0 along
    /// the others. Panics if `i ≥ N`.
    #[inline]
    pub fn variable(re: f64, i: usize) -> Self {
        assert!(i < N, "direction {i} of a dual number with {N} directions");
        let mut eps = [0.0; N];
        eps[i] = 1.0;
        Self { re, eps }
    }

    /// `f(x)` given `f(x)` and `f'(x)`: the chain rule.
    #[inline(always)]
    fn chain(self, f0: f64, f1: f64) -> Self {
        // Plain loops over the array: they vectorise (the closure forms
        // of `map`/`from_fn` were left as calls in the closed loop).
        let mut eps = self.eps;
        for e in &mut eps {
            *e *= f1;
        }
        Self { re: f0, eps }
    }

    /// The chain rule where `f'(x)` is infinite: zero derivatives stay
    /// zero, the others become ±∞ (see the type's docs).
    #[inline]
    fn chain_singular(self, f0: f64) -> Self {
        Self {
            re: f0,
            eps: self
                .eps
                .map(|e| if e == 0.0 { 0.0 } else { e * f64::INFINITY }),
        }
    }

    /// Every derivative is exactly zero.
    #[inline(always)]
    fn is_constant(&self) -> bool {
        // Folded without an early exit, as in `simd_eq`: it vectorises.
        self.eps.iter().fold(true, |all, &e| all & (e == 0.0))
    }
}

impl<const N: usize> Default for Dual<N> {
    #[inline(always)]
    fn default() -> Self {
        Self::constant(0.0)
    }
}

impl<const N: usize> From<f64> for Dual<N> {
    #[inline(always)]
    fn from(re: f64) -> Self {
        Self::constant(re)
    }
}

/// The real part only, as for `<`: branches compare values, not derivatives.
impl<const N: usize> PartialEq for Dual<N> {
    #[inline(always)]
    fn eq(&self, other: &Self) -> bool {
        self.re == other.re
    }
}

/// The real part only: branches compare values, not derivatives.
impl<const N: usize> PartialOrd for Dual<N> {
    #[inline(always)]
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        self.re.partial_cmp(&other.re)
    }
}

impl<const N: usize> fmt::Display for Dual<N> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        fmt::Display::fmt(&self.re, f)?;
        for (i, e) in self.eps.iter().enumerate() {
            if *e != 0.0 {
                write!(f, " {} {}ε{i}", if *e < 0.0 { '-' } else { '+' }, e.abs())?;
            }
        }
        Ok(())
    }
}

impl<const N: usize> Add for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn add(self, o: Self) -> Self {
        let mut eps = self.eps;
        for (e, d) in eps.iter_mut().zip(&o.eps) {
            *e += d;
        }
        Self {
            re: self.re + o.re,
            eps,
        }
    }
}

impl<const N: usize> Sub for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn sub(self, o: Self) -> Self {
        let mut eps = self.eps;
        for (e, d) in eps.iter_mut().zip(&o.eps) {
            *e -= d;
        }
        Self {
            re: self.re - o.re,
            eps,
        }
    }
}

impl<const N: usize> Mul for Dual<N> {
    type Output = Self;
    // The product rule adds.
    #[allow(clippy::suspicious_arithmetic_impl)]
    #[inline(always)]
    fn mul(self, o: Self) -> Self {
        let mut eps = self.eps;
        for (e, d) in eps.iter_mut().zip(&o.eps) {
            *e = madd(*e, o.re, d * self.re);
        }
        Self {
            re: self.re * o.re,
            eps,
        }
    }
}

/// `a·b + c`, fused where the build has FMA (derivatives only: the real
/// part never uses it, so it stays the `f64` run's).
#[inline(always)]
fn madd(a: f64, b: f64, c: f64) -> f64 {
    #[cfg(target_feature = "fma")]
    {
        a.mul_add(b, c)
    }
    #[cfg(not(target_feature = "fma"))]
    {
        a * b + c
    }
}

impl<const N: usize> Div for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn div(self, o: Self) -> Self {
        let re = self.re / o.re;
        let inv = 1.0 / o.re;
        let mut eps = self.eps;
        for (e, d) in eps.iter_mut().zip(&o.eps) {
            *e = madd(-re, *d, *e) * inv;
        }
        Self { re, eps }
    }
}

impl<const N: usize> Neg for Dual<N> {
    type Output = Self;
    #[inline(always)]
    fn neg(self) -> Self {
        let mut eps = self.eps;
        for e in &mut eps {
            *e = -*e;
        }
        Self { re: -self.re, eps }
    }
}

macro_rules! assign_op {
    ($tr:ident, $f:ident, $op:tt) => {
        impl<const N: usize> $tr for Dual<N> {
            #[inline(always)]
            fn $f(&mut self, o: Self) {
                *self = *self $op o;
            }
        }
    };
}
assign_op!(AddAssign, add_assign, +);
assign_op!(SubAssign, sub_assign, -);
assign_op!(MulAssign, mul_assign, *);
assign_op!(DivAssign, div_assign, /);

impl<const N: usize> Zero for Dual<N> {
    #[inline(always)]
    fn zero() -> Self {
        Self::constant(0.0)
    }
    #[inline(always)]
    fn is_zero(&self) -> bool {
        self.re == 0.0 && self.is_constant()
    }
}

impl<const N: usize> One for Dual<N> {
    #[inline(always)]
    fn one() -> Self {
        Self::constant(1.0)
    }
}

/// `f32`/`f64`'s library function on the real part.
macro_rules! re {
    ($f:ident, $($x:expr),+) => {
        num_traits::Float::$f($($x),+)
    };
}

impl<const N: usize> SimdReal for Dual<N> {
    type Element = Self;
    type Mask = bool;
    const LANES: usize = 1;
    const CARRIES_DERIVATIVES: bool = true;

    #[inline(always)]
    fn with_derivatives_of(self, other: Self) -> Self {
        Self {
            re: self.re,
            eps: other.eps,
        }
    }

    #[inline(always)]
    fn simd_splat(x: Self) -> Self {
        x
    }
    #[inline(always)]
    fn simd_extract(self, i: usize) -> Self {
        assert!(i == 0, "lane {i} of a one-lane scalar");
        self
    }
    #[inline(always)]
    fn simd_from_fn(mut f: impl FnMut(usize) -> Self) -> Self {
        f(0)
    }
    /// Value *and* derivatives equal (see the type's docs).
    #[inline(always)]
    fn simd_eq(self, other: Self) -> bool {
        // Every lane compared and the results and-ed, without the early
        // exit of `==` on arrays (a call per comparison in the laws'
        // diagonal-inertia test): the comparisons vectorise.
        let same = self
            .eps
            .iter()
            .zip(&other.eps)
            .fold(true, |all, (a, b)| all & (a == b));
        same & (self.re == other.re)
    }
    #[inline(always)]
    fn simd_lt(self, other: Self) -> bool {
        self.re < other.re
    }
    #[inline(always)]
    fn simd_le(self, other: Self) -> bool {
        self.re <= other.re
    }
    #[inline(always)]
    fn simd_select(mask: bool, a: Self, b: Self) -> Self {
        if mask { a } else { b }
    }
    #[inline(always)]
    fn simd_branch<const K: usize>(
        mask: bool,
        if_true: impl FnOnce() -> [Self; K],
        if_false: impl FnOnce() -> [Self; K],
    ) -> [Self; K] {
        if mask { if_true() } else { if_false() }
    }
    #[inline(always)]
    fn simd_sqrt(self) -> Self {
        Real::sqrt(self)
    }
    #[inline(always)]
    fn simd_abs(self) -> Self {
        Real::abs(self)
    }
    #[inline(always)]
    fn simd_sin(self) -> Self {
        Real::sin(self)
    }
    #[inline(always)]
    fn simd_cos(self) -> Self {
        Real::cos(self)
    }
    #[inline(always)]
    fn simd_sin_cos(self) -> (Self, Self) {
        Real::sin_cos(self)
    }
    #[inline(always)]
    fn simd_asin(self) -> Self {
        Real::asin(self)
    }
    #[inline(always)]
    fn simd_acos(self) -> Self {
        Real::acos(self)
    }
    #[inline(always)]
    fn simd_atan2(self, x: Self) -> Self {
        Real::atan2(self, x)
    }
    #[inline(always)]
    fn simd_max(self, other: Self) -> Self {
        Real::max(self, other)
    }
    #[inline(always)]
    fn simd_min(self, other: Self) -> Self {
        Real::min(self, other)
    }
    #[inline(always)]
    fn simd_is_finite(self) -> bool {
        Real::is_finite(self)
    }
}

impl<const N: usize> Real for Dual<N> {
    const NAME: &'static str = "dual";
    const CUT_EXP: Self = Self::constant(f64::CUT_EXP);
    const CUT_JAC: Self = Self::constant(f64::CUT_JAC);
    const CUT_JAC_SE3: Self = Self::constant(f64::CUT_JAC_SE3);
    const CUT_LOG: Self = Self::constant(f64::CUT_LOG);

    #[inline(always)]
    fn lit(x: f64) -> Self {
        Self::constant(x)
    }
    /// [`Dual::variable`].
    #[inline]
    fn seeded(x: f64, i: usize) -> Self {
        Self::variable(x, i)
    }
    /// The real part (the derivatives are dropped).
    #[inline(always)]
    fn to_f64_lossless(self) -> f64 {
        self.re
    }
    #[inline]
    fn abs(self) -> Self {
        // The sign bit, as `f64::abs` clears it: −0 and NaN with the sign
        // bit set flip to the same real part `abs` gives.
        if self.re.is_sign_negative() {
            -self
        } else {
            self
        }
    }
    #[inline]
    fn sqrt(self) -> Self {
        let s = re!(sqrt, self.re);
        if self.re == 0.0 {
            self.chain_singular(s)
        } else {
            self.chain(s, 0.5 / s)
        }
    }
    #[inline]
    fn sin(self) -> Self {
        self.chain(re!(sin, self.re), re!(cos, self.re))
    }
    #[inline]
    fn cos(self) -> Self {
        self.chain(re!(cos, self.re), -re!(sin, self.re))
    }
    #[inline]
    fn tan(self) -> Self {
        let t = re!(tan, self.re);
        self.chain(t, 1.0 + t * t)
    }
    #[inline]
    fn asin(self) -> Self {
        self.chain(re!(asin, self.re), 1.0 / re!(sqrt, 1.0 - self.re * self.re))
    }
    #[inline]
    fn acos(self) -> Self {
        self.chain(
            re!(acos, self.re),
            -1.0 / re!(sqrt, 1.0 - self.re * self.re),
        )
    }
    #[inline]
    fn atan(self) -> Self {
        self.chain(re!(atan, self.re), 1.0 / (1.0 + self.re * self.re))
    }
    #[inline]
    fn exp(self) -> Self {
        let e = re!(exp, self.re);
        self.chain(e, e)
    }
    #[inline]
    fn ln(self) -> Self {
        self.chain(re!(ln, self.re), 1.0 / self.re)
    }
    #[inline]
    fn ln_1p(self) -> Self {
        self.chain(re!(ln_1p, self.re), 1.0 / (1.0 + self.re))
    }
    #[inline]
    fn floor(self) -> Self {
        self.chain(re!(floor, self.re), 0.0)
    }
    #[inline]
    fn ceil(self) -> Self {
        self.chain(re!(ceil, self.re), 0.0)
    }
    #[inline]
    fn round(self) -> Self {
        self.chain(re!(round, self.re), 0.0)
    }
    #[inline]
    fn signum(self) -> Self {
        self.chain(re!(signum, self.re), 0.0)
    }
    #[inline]
    fn cbrt(self) -> Self {
        let c = re!(cbrt, self.re);
        if self.re == 0.0 {
            self.chain_singular(c)
        } else {
            self.chain(c, c / (3.0 * self.re))
        }
    }
    #[inline]
    fn sin_cos(self) -> (Self, Self) {
        let (s, c) = (re!(sin, self.re), re!(cos, self.re));
        (self.chain(s, c), self.chain(c, -s))
    }
    /// `atan2(y, x)`: `d = (x dy − y dx)/(x² + y²)`.
    #[inline]
    fn atan2(self, x: Self) -> Self {
        let re = re!(atan2, self.re, x.re);
        let r2 = x.re * x.re + self.re * self.re;
        let eps = core::array::from_fn(|i| {
            let num = x.re * self.eps[i] - self.re * x.eps[i];
            if r2 == 0.0 {
                if self.eps[i] == 0.0 && x.eps[i] == 0.0 {
                    0.0
                } else {
                    f64::NAN
                }
            } else {
                num / r2
            }
        });
        Self { re, eps }
    }
    #[inline]
    fn powi(self, n: i32) -> Self {
        let re = re!(powi, self.re, n);
        if n == 0 {
            return self.chain(re, 0.0);
        }
        self.chain(re, f64::from(n) * re!(powi, self.re, n - 1))
    }
    /// `xⁿ` with a real exponent that may carry derivatives too:
    /// `d = n x^(n−1) dx + xⁿ ln x dn` (the second term only where `dn`
    /// is not zero, so a constant exponent at `x = 0` stays finite).
    #[inline]
    fn powf(self, n: Self) -> Self {
        let re = re!(powf, self.re, n.re);
        let dx = n.re * re!(powf, self.re, n.re - 1.0);
        let ln = if n.is_constant() {
            0.0
        } else {
            re!(ln, self.re)
        };
        Self {
            re,
            eps: core::array::from_fn(|i| {
                let from_n = if n.eps[i] == 0.0 {
                    0.0
                } else {
                    re * ln * n.eps[i]
                };
                dx * self.eps[i] + from_n
            }),
        }
    }
    #[inline]
    fn hypot(self, y: Self) -> Self {
        let h = re!(hypot, self.re, y.re);
        if h == 0.0 {
            let live = core::array::from_fn(|i| self.eps[i] != 0.0 || y.eps[i] != 0.0);
            return Self {
                re: h,
                eps: live.map(|l: bool| if l { f64::INFINITY } else { 0.0 }),
            };
        }
        Self {
            re: h,
            eps: core::array::from_fn(|i| (self.re * self.eps[i] + y.re * y.eps[i]) / h),
        }
    }
    #[inline]
    fn max(self, other: Self) -> Self {
        // Whichever operand `f64::max` returns, derivatives and all.
        let m = re!(max, self.re, other.re);
        if m.to_bits() == self.re.to_bits() {
            self
        } else {
            other
        }
    }
    #[inline]
    fn min(self, other: Self) -> Self {
        let m = re!(min, self.re, other.re);
        if m.to_bits() == self.re.to_bits() {
            self
        } else {
            other
        }
    }
    /// The value and every derivative finite: a derivative that overflowed
    /// or met a singular point fails the same checks a NaN value fails.
    #[inline]
    fn is_finite(self) -> bool {
        // Folded without an early exit (the loads and the state are
        // checked at every stage): the tests vectorise.
        let eps = self.eps.iter().fold(true, |all, e| all & e.is_finite());
        eps & self.re.is_finite()
    }
    #[inline]
    fn is_nan(self) -> bool {
        let eps = self.eps.iter().fold(false, |any, e| any | e.is_nan());
        eps | self.re.is_nan()
    }
    #[inline(always)]
    fn epsilon() -> Self {
        Self::constant(f64::EPSILON)
    }
    #[inline(always)]
    fn nan() -> Self {
        Self::constant(f64::NAN)
    }
    #[inline(always)]
    fn infinity() -> Self {
        Self::constant(f64::INFINITY)
    }
    #[inline(always)]
    fn max_value() -> Self {
        Self::constant(f64::MAX)
    }
    #[inline(always)]
    fn min_positive_value() -> Self {
        Self::constant(f64::MIN_POSITIVE)
    }
    #[inline(always)]
    fn pi() -> Self {
        Self::constant(core::f64::consts::PI)
    }
}
