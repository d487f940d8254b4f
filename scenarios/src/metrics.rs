//! Metrics over recorded samples.

use crate::Sample;

/// The sample at time `t` (recorded exactly on the grid), if any.
pub fn at(samples: &[Sample], t: f64) -> Option<&Sample> {
    samples
        .iter()
        .find(|s| (s.t - t).abs() <= 1e-9 * t.max(1.0))
}

/// Largest difference between two runs over their common sample times in
/// x, v (and R entries), `(max |Δx|, max |Δv|, max |ΔR|)`.
pub fn max_difference(a: &[Sample], b: &[Sample]) -> (f64, f64, f64, usize) {
    let (mut dx, mut dv, mut dr, mut n) = (0.0f64, 0.0f64, 0.0f64, 0usize);
    for s in a {
        if let Some(o) = at(b, s.t) {
            n += 1;
            for k in 0..3 {
                dx = dx.max((s.x[k] - o.x[k]).abs());
                dv = dv.max((s.v[k] - o.v[k]).abs());
                for j in 0..3 {
                    dr = dr.max((s.r[k][j] - o.r[k][j]).abs());
                }
            }
        }
    }
    (dx, dv, dr, n)
}

/// Largest Ψ over samples with `t ≥ from`.
pub fn max_psi_after(samples: &[Sample], from: f64) -> f64 {
    samples
        .iter()
        .filter(|s| s.t >= from)
        .map(|s| s.psi)
        .fold(0.0, f64::max)
}

/// Largest ‖e_x‖ over samples with `t ≥ from`.
pub fn max_ex_after(samples: &[Sample], from: f64) -> f64 {
    samples
        .iter()
        .filter(|s| s.t >= from)
        .map(|s| s.ex)
        .fold(0.0, f64::max)
}
