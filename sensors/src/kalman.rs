//! Small fixed-size Kalman helpers on plain arrays: the crate has no heap
//! and glam has no matrices past 4×4, so covariances are `[[T; N]; N]`.

// Symmetric-matrix code reads (i, j) against (j, i): indices are clearer
// than iterator chains here.
#![allow(clippy::needless_range_loop)]

use lie::Real;

/// An `N × N` matrix, row-major.
pub type Mat<T, const N: usize> = [[T; N]; N];

/// One scalar measurement row `h` with residual `r` (predicted minus
/// measured) and noise variance `var`, applied to the covariance `p` and
/// accumulated into the correction `corr`.
///
/// Rows of one measurement with independent noise, taken one after
/// another at the same linearisation point, give exactly the batch update;
/// `r` is the row's residual at the prior, and the rows before it have
/// already moved the estimate by `corr`, so the row sees `r − h·corr`.
/// Returns the row's share of the normalised innovation squared, or `None`
/// (nothing changed) when the innovation variance is not a positive finite
/// number.
pub fn scalar_update<T: Real, const N: usize>(
    p: &mut Mat<T, N>,
    corr: &mut [T; N],
    h: &[T; N],
    r: T,
    var: T,
) -> Option<T> {
    let dot = |a: &[T; N], b: &[T; N]| (0..N).fold(T::zero(), |s, i| s + a[i] * b[i]);
    let ph: [T; N] = core::array::from_fn(|i| dot(&p[i], h));
    let s = dot(h, &ph) + var;
    if !(s.is_finite() && s > T::zero()) {
        return None;
    }
    let innov = r - dot(h, corr);
    let inv = T::one() / s;
    for i in 0..N {
        corr[i] += ph[i] * inv * innov;
        for j in 0..N {
            p[i][j] -= ph[i] * ph[j] * inv;
        }
    }
    Some(innov * innov * inv)
}

/// `(P + Pᵀ)/2`: rounding makes a propagated covariance drift from
/// symmetry, which the scalar updates would amplify.
pub fn symmetrize<T: Real, const N: usize>(p: &mut Mat<T, N>) {
    let half = T::lit(0.5);
    for i in 0..N {
        for j in 0..i {
            let m = (p[i][j] + p[j][i]) * half;
            p[i][j] = m;
            p[j][i] = m;
        }
    }
}

/// Whether `p` is symmetric (to `tol` relative to its diagonal) and
/// positive definite (its Cholesky factorisation succeeds).
pub fn is_spd<const N: usize>(p: &Mat<f64, N>, tol: f64) -> bool {
    let mut l = [[0.0f64; N]; N];
    for i in 0..N {
        for j in 0..N {
            let scale = (p[i][i].abs() * p[j][j].abs()).sqrt();
            if !p[i][j].is_finite() || (p[i][j] - p[j][i]).abs() > tol * scale {
                return false;
            }
        }
    }
    for j in 0..N {
        let d = p[j][j] - (0..j).map(|k| l[j][k] * l[j][k]).sum::<f64>();
        if d.is_nan() || d <= 0.0 {
            return false;
        }
        l[j][j] = d.sqrt();
        for i in j + 1..N {
            l[i][j] = (p[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<f64>()) / l[j][j];
        }
    }
    true
}

/// `A·B`.
pub fn mul<T: Real, const R: usize, const K: usize, const C: usize>(
    a: &[[T; K]; R],
    b: &[[T; C]; K],
) -> [[T; C]; R] {
    core::array::from_fn(|i| {
        core::array::from_fn(|j| (0..K).fold(T::zero(), |s, k| s + a[i][k] * b[k][j]))
    })
}

/// `A + B`.
pub fn add<T: Real, const R: usize, const C: usize>(
    a: &[[T; C]; R],
    b: &[[T; C]; R],
) -> [[T; C]; R] {
    core::array::from_fn(|i| core::array::from_fn(|j| a[i][j] + b[i][j]))
}

/// The `N×N` identity.
pub fn identity<T: Real, const N: usize>() -> Mat<T, N> {
    core::array::from_fn(|i| core::array::from_fn(|j| if i == j { T::one() } else { T::zero() }))
}

/// `Aᵀ`.
pub fn transpose<T: Real, const R: usize, const C: usize>(a: &[[T; C]; R]) -> [[T; R]; C] {
    core::array::from_fn(|i| core::array::from_fn(|j| a[j][i]))
}

/// `S⁻¹` of a symmetric positive definite `S` through its Cholesky
/// factor, or `None` when `S` is not positive definite (or not finite).
pub fn spd_inverse<T: Real, const N: usize>(s: &Mat<T, N>) -> Option<Mat<T, N>> {
    let mut l = [[T::zero(); N]; N];
    for j in 0..N {
        let d = s[j][j] - (0..j).fold(T::zero(), |a, k| a + l[j][k] * l[j][k]);
        if !(d.is_finite() && d > T::zero()) {
            return None;
        }
        l[j][j] = d.sqrt();
        for i in j + 1..N {
            l[i][j] = (s[i][j] - (0..j).fold(T::zero(), |a, k| a + l[i][k] * l[j][k])) / l[j][j];
        }
    }
    // Columns of L⁻¹ by forward substitution, then S⁻¹ = L⁻ᵀ L⁻¹.
    let mut li = [[T::zero(); N]; N];
    for c in 0..N {
        for i in c..N {
            let rhs = if i == c { T::one() } else { T::zero() };
            let acc = (c..i).fold(T::zero(), |a, k| a + l[i][k] * li[k][c]);
            li[i][c] = (rhs - acc) / l[i][i];
        }
    }
    Some(core::array::from_fn(|i| {
        core::array::from_fn(|j| (0..N).fold(T::zero(), |a, k| a + li[k][i] * li[k][j]))
    }))
}
