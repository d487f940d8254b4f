//! One piece of a piecewise-polynomial trajectory: four degree-7
//! polynomials (x, y, z, yaw) in the time since the piece began.

use lie::Real;

/// Coefficients per polynomial: degree 7, the lowest that makes snap
/// optimal and what the Crazyflie's `pptraj` stores.
pub const COEFFS: usize = 8;

/// A piece of `duration` seconds: `coeffs[a][j]` multiplies `τʲ` in axis
/// `a` (x, y, z, yaw), `τ` the time since the piece began.
#[derive(Clone, Debug, PartialEq)]
pub struct Piece {
    /// Its length in time, s (positive).
    pub duration: f64,
    /// x, y, z (m) and yaw (rad) coefficients, lowest power first.
    pub coeffs: [[f64; COEFFS]; 4],
}

/// `j!/(j−d)!`, the factor the `d`-th derivative puts on `τʲ` (0 when
/// `d > j`).
pub(crate) fn falling(j: usize, d: usize) -> f64 {
    if d > j {
        return 0.0;
    }
    ((j - d + 1)..=j).fold(1.0, |p, k| p * k as f64)
}

/// The `d`-th derivative of `Σ c_j τʲ` at `tau`, by Horner's rule, in any
/// scalar (so a dual time carries its derivative through).
pub(crate) fn derivative<T: Real>(c: &[f64; COEFFS], d: usize, tau: T) -> T {
    let mut acc = T::lit(0.0);
    for j in (d..COEFFS).rev() {
        acc = acc * tau + T::lit(c[j] * falling(j, d));
    }
    acc
}

impl Piece {
    /// The `d`-th derivative of axis `a` (0 x, 1 y, 2 z, 3 yaw) at `tau`
    /// seconds into the piece.
    pub fn eval(&self, a: usize, d: usize, tau: f64) -> f64 {
        derivative(&self.coeffs[a], d, tau)
    }
}
