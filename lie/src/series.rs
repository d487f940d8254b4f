//! The scalar coefficient functions of the SO(3)/SE(3) exponential, its
//! Jacobians and their inverses, each with a Taylor branch below a cut-off
//! chosen per formula and per precision (see [`Real`]).
//!
//! With `θ = |φ|` (Barfoot & Furgale 2014 notation):
//! `A = sin θ/θ`, `B = (1 − cos θ)/θ²`, `C = (θ − sin θ)/θ³`,
//! `D = 1/θ² − (1 + cos θ)/(2θ sin θ)`, `E = (θ² + 2cos θ − 2)/(2θ⁴)`,
//! `F = (2θ − 3 sin θ + θ cos θ)/(2θ⁵)`.

use crate::{Real, SimdReal};

#[inline(always)]
fn l<S: SimdReal>(x: f64) -> S {
    S::simd_lit(x)
}

/// `θ < cut`, lane-wise, for a cut-off constant of [`Real`].
#[inline(always)]
fn below<S: SimdReal>(theta: S, cut: S::Element) -> S::Mask {
    theta.simd_lt(S::simd_splat(cut))
}

/// `Σ c_k t2^k` by Horner's rule; the coefficients are the Taylor series in
/// `θ²`, seven terms, so the first dropped term is `O(θ¹⁴)`.
#[inline(always)]
fn horner<S: SimdReal>(t2: S, c: &[f64; 7]) -> S {
    let mut acc = l::<S>(c[6]);
    for k in (0..6).rev() {
        acc = acc * t2 + l::<S>(c[k]);
    }
    acc
}

/// `(A, B, cos θ)`. `B` uses the half-angle form `2 sin²(θ/2)/θ²`, which has
/// no cancellation (the naive `(1 − cos θ)/θ²` loses half the digits at
/// θ = 1e-4), and all three come from one `sin_cos(θ/2)`.
#[inline(always)]
pub fn exp_coeffs<S: SimdReal>(theta: S) -> (S, S, S) {
    let [a, b, c] = S::simd_branch(
        below(theta, S::Element::CUT_EXP),
        || {
            let t2 = theta * theta;
            let a = S::one() - t2 * (l::<S>(1.0 / 6.0) - t2 * l::<S>(1.0 / 120.0));
            let b = l::<S>(0.5) - t2 * (l::<S>(1.0 / 24.0) - t2 * l::<S>(1.0 / 720.0));
            [a, b, S::one() - t2 * b]
        },
        || {
            let (sh, ch) = (theta * l::<S>(0.5)).simd_sin_cos();
            let two = l::<S>(2.0);
            let a = two * sh * ch / theta;
            let b = two * sh * sh / (theta * theta);
            [a, b, S::one() - two * sh * sh]
        },
    );
    (a, b, c)
}

/// `(cos(θ/2), sin(θ/2)/θ)`: the unit quaternion `exp(φ)` is
/// `(cos(θ/2), sin(θ/2)/θ · φ)`.
#[inline(always)]
pub fn quat_exp_coeffs<S: SimdReal>(theta: S) -> (S, S) {
    let [w, k] = S::simd_branch(
        below(theta, S::Element::CUT_EXP),
        || {
            let t2 = theta * theta;
            let k = l::<S>(0.5) - t2 * (l::<S>(1.0 / 48.0) - t2 * l::<S>(1.0 / 3840.0));
            [
                S::one() - t2 * (l::<S>(1.0 / 8.0) - t2 * l::<S>(1.0 / 384.0)),
                k,
            ]
        },
        || {
            let (sh, ch) = (theta * l::<S>(0.5)).simd_sin_cos();
            [ch, sh / theta]
        },
    );
    (w, k)
}

/// `C = (θ − sin θ)/θ³`.
#[inline(always)]
pub fn c_coeff<S: SimdReal>(theta: S) -> S {
    let [v] = S::simd_branch(
        below(theta, S::Element::CUT_JAC),
        || {
            let t2 = theta * theta;
            [horner(
                t2,
                &[
                    1.0 / 6.0,
                    -1.0 / 120.0,
                    1.0 / 5040.0,
                    -1.0 / 362880.0,
                    1.0 / 39916800.0,
                    -1.0 / 6227020800.0,
                    1.0 / 1307674368000.0,
                ],
            )]
        },
        || [(theta - theta.simd_sin()) / (theta * theta * theta)],
    );
    v
}

/// `D = 1/θ² − cot(θ/2)/(2θ)`, the coefficient of `φ^²` in `J_l⁻¹`. The
/// cotangent form stays finite at θ = π (where `(1 + cos θ)/sin θ` is 0/0).
#[inline(always)]
pub fn d_coeff<S: SimdReal>(theta: S) -> S {
    let [v] = S::simd_branch(
        below(theta, S::Element::CUT_JAC),
        || {
            let t2 = theta * theta;
            [horner(
                t2,
                &[
                    1.0 / 12.0,
                    1.0 / 720.0,
                    1.0 / 30240.0,
                    1.0 / 1209600.0,
                    1.0 / 47900160.0,
                    691.0 / 1307674368000.0,
                    1.0 / 74724249600.0,
                ],
            )]
        },
        || {
            let (sh, ch) = (theta * l::<S>(0.5)).simd_sin_cos();
            [S::one() / (theta * theta) - ch / (l::<S>(2.0) * theta * sh)]
        },
    );
    v
}

/// `E = (θ² + 2cos θ − 2)/(2θ⁴)` (SE(3) left Jacobian, `Q` block).
#[inline(always)]
pub fn e_coeff<S: SimdReal>(theta: S) -> S {
    let [v] = S::simd_branch(
        below(theta, S::Element::CUT_JAC_SE3),
        || {
            let t2 = theta * theta;
            [horner(
                t2,
                &[
                    1.0 / 24.0,
                    -1.0 / 720.0,
                    1.0 / 40320.0,
                    -1.0 / 3628800.0,
                    1.0 / 479001600.0,
                    -1.0 / 87178291200.0,
                    1.0 / 20922789888000.0,
                ],
            )]
        },
        || {
            let t2 = theta * theta;
            [(t2 + l::<S>(2.0) * theta.simd_cos() - l::<S>(2.0)) / (l::<S>(2.0) * t2 * t2)]
        },
    );
    v
}

/// `F = (2θ − 3 sin θ + θ cos θ)/(2θ⁵)` (SE(3) left Jacobian, `Q` block).
#[inline(always)]
pub fn f_coeff<S: SimdReal>(theta: S) -> S {
    let [v] =
        S::simd_branch(
            below(theta, S::Element::CUT_JAC_SE3),
            || {
                let t2 = theta * theta;
                [horner(
                    t2,
                    &[
                        1.0 / 120.0,
                        -1.0 / 2520.0,
                        1.0 / 120960.0,
                        -1.0 / 9979200.0,
                        1.0 / 1245404160.0,
                        -1.0 / 217945728000.0,
                        1.0 / 50812489728000.0,
                    ],
                )]
            },
            || {
                let (s, c) = theta.simd_sin_cos();
                let t2 = theta * theta;
                [(l::<S>(2.0) * theta - l::<S>(3.0) * s + theta * c)
                    / (l::<S>(2.0) * t2 * t2 * theta)]
            },
        );
    v
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The series and the closed forms must agree at each cut-off: a sign
    /// or coefficient error in a series term shows up as a jump there. The
    /// tolerance is the larger of the two branches' error estimates at the
    /// cut-off (documented on `Real`), times a safety factor of 10.
    #[test]
    fn branches_meet_at_cutoffs_f64() {
        let t = f64::CUT_JAC;
        let (below, above) = (t * (1.0 - 1e-12), t * (1.0 + 1e-12));
        assert!((c_coeff(below) - c_coeff(above)).abs() < 1e-14);
        assert!((d_coeff(below) - d_coeff(above)).abs() < 1e-14);
        let t = f64::CUT_JAC_SE3;
        let (below, above) = (t * (1.0 - 1e-12), t * (1.0 + 1e-12));
        assert!((e_coeff(below) - e_coeff(above)).abs() < 1e-14);
        assert!((f_coeff(below) - f_coeff(above)).abs() < 1e-14);
        let t = f64::CUT_EXP;
        let (below, above) = (t * (1.0 - 1e-12), t * (1.0 + 1e-12));
        let (a0, b0, c0) = exp_coeffs(below);
        let (a1, b1, c1) = exp_coeffs(above);
        assert!((a0 - a1).abs() < 1e-15 && (b0 - b1).abs() < 1e-15 && (c0 - c1).abs() < 1e-15);
        let (w0, k0) = quat_exp_coeffs(below);
        let (w1, k1) = quat_exp_coeffs(above);
        assert!((w0 - w1).abs() < 1e-15 && (k0 - k1).abs() < 1e-15);
    }

    /// The f32 evaluations against the f64 ones over the whole range
    /// [0, π]: a cut-off too low shows as cancellation error above it, one
    /// too high as truncation error below it. The bound, 16 ε of f32
    /// relative to the coefficient's size at zero, is what one sin/cos and
    /// the few operations after it can cost (measured: 7 ε, for D).
    #[test]
    fn f32_coefficients_track_f64() {
        let mut worst = [0.0f64; 4];
        for i in 1..=4000 {
            let th = core::f64::consts::PI * (i as f64) / 4000.0;
            let th32 = th as f32;
            let th_r = th32 as f64; // evaluate f64 at the same rounded angle
            let pairs = [
                (c_coeff(th32) as f64, c_coeff(th_r), 1.0 / 6.0),
                (d_coeff(th32) as f64, d_coeff(th_r), 1.0 / 12.0),
                (e_coeff(th32) as f64, e_coeff(th_r), 1.0 / 24.0),
                (f_coeff(th32) as f64, f_coeff(th_r), 1.0 / 120.0),
            ];
            for (k, (a, b, scale)) in pairs.into_iter().enumerate() {
                worst[k] = worst[k].max((a - b).abs() / scale);
            }
        }
        println!("f32 vs f64 coefficient worst relative error C,D,E,F: {worst:?}");
        for w in worst {
            assert!(w < 16.0 * f32::EPSILON as f64, "{worst:?}");
        }
    }
}
