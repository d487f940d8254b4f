//! The key of a sensor's noise.

use lie::noise::mix;

/// The standard normal quantile at `p` in (0, 1) by Acklam's rational
/// approximation (relative error below 1.2e-9, far under any statistic a
/// simulation can resolve): one uniform in, one normal out, a logarithm
/// and a square root only in the tails (4.85 % of draws). Box–Muller
/// takes a logarithm, a square root and a sine and cosine for every pair.
#[inline]
fn quantile(p: f64) -> f64 {
    const A: [f64; 6] = [
        -3.969_683_028_665_376e1,
        2.209_460_984_245_205e2,
        -2.759_285_104_469_687e2,
        1.383_577_518_672_69e2,
        -3.066_479_806_614_716e1,
        2.506_628_277_459_239,
    ];
    const B: [f64; 5] = [
        -5.447_609_879_822_406e1,
        1.615_858_368_580_409e2,
        -1.556_989_798_598_866e2,
        6.680_131_188_771_972e1,
        -1.328_068_155_288_572e1,
    ];
    const C: [f64; 6] = [
        -7.784_894_002_430_293e-3,
        -3.223_964_580_411_365e-1,
        -2.400_758_277_161_838,
        -2.549_732_539_343_734,
        4.374_664_141_464_968,
        2.938_163_982_698_783,
    ];
    const D: [f64; 4] = [
        7.784_695_709_041_462e-3,
        3.224_671_290_700_398e-1,
        2.445_134_137_142_996,
        3.754_408_661_907_416,
    ];
    const LOW: f64 = 0.02425;
    let tail = |q: f64| {
        (((((C[0] * q + C[1]) * q + C[2]) * q + C[3]) * q + C[4]) * q + C[5])
            / ((((D[0] * q + D[1]) * q + D[2]) * q + D[3]) * q + 1.0)
    };
    if p < LOW {
        tail(lie::Real::sqrt(-2.0 * lie::Real::ln(p)))
    } else if p <= 1.0 - LOW {
        let q = p - 0.5;
        let r = q * q;
        (((((A[0] * r + A[1]) * r + A[2]) * r + A[3]) * r + A[4]) * r + A[5]) * q
            / (((((B[0] * r + B[1]) * r + B[2]) * r + B[3]) * r + B[4]) * r + 1.0)
    } else {
        -tail(lie::Real::sqrt(-2.0 * lie::Real::ln(1.0 - p)))
    }
}

/// A standard normal from a mixed key: the quantile of a uniform in
/// (0, 1) (never 0 or 1).
#[inline]
fn normal(z: u64) -> f64 {
    quantile(((z >> 11) as f64 + 0.5) / (1u64 << 53) as f64)
}

/// Where a sensor's random numbers come from: the run's seed and the
/// sensor's own number (two sensors of a run differ in `sensor`). Sample
/// `k`'s numbers are a function of `(seed, sensor, k, channel)` alone.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NoiseKey {
    base: u64,
}

impl NoiseKey {
    /// The key of sensor `sensor` in a run seeded with `seed`.
    pub fn new(seed: u64, sensor: u64) -> Self {
        Self {
            base: mix(seed ^ mix(sensor.wrapping_add(0x9e37_79b9_7f4a_7c15))),
        }
    }

    /// Two independent standard normals: pair `j` of sample `k`.
    #[inline]
    pub fn pair(&self, k: u64, j: u64) -> [f64; 2] {
        let z = mix(self.base ^ mix(k.wrapping_mul(64).wrapping_add(j)));
        [normal(z), normal(mix(z ^ 0xd1b5_4a32_d192_ed03))]
    }

    /// Six independent standard normals of sample `k`, pairs `j0..j0+3`.
    #[inline]
    pub(crate) fn six(&self, k: u64, j0: u64) -> [f64; 6] {
        let [a, b] = self.pair(k, j0);
        let [c, d] = self.pair(k, j0 + 1);
        let [e, f] = self.pair(k, j0 + 2);
        [a, b, c, d, e, f]
    }
}

impl NoiseKey {
    /// A uniform number in [0, 1): number `j` of sample `k`, independent
    /// of the normals (its own part of the key space).
    #[inline]
    pub fn uniform(&self, k: u64, j: u64) -> f64 {
        let z =
            mix(self.base ^ mix(k.wrapping_mul(64).wrapping_add(32 + j)) ^ 0x5851_f42d_4c95_7f2d);
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The quantile against Φ⁻¹ at points where it is known to 16 digits
    /// (Φ(1) = 0.841344746068543, Φ(−3) = 0.00134989803163009, Φ(0) = ½,
    /// Φ(−6) = 9.86587645037698e-10, a point of the far tail given
    /// exactly, where 1 − p would lose digits): within Acklam's 1.2e-9
    /// relative.
    #[test]
    fn the_quantile_inverts_the_normal_cdf() {
        for (p, x) in [
            (0.5, 0.0),
            (0.841_344_746_068_543, 1.0),
            (0.001_349_898_031_630_09, -3.0),
            (9.865_876_450_376_98e-10, -6.0),
        ] {
            let q = quantile(p);
            assert!(
                (q - x).abs() <= 1.2e-9 * x.abs().max(1e-9) + 1e-12,
                "Φ⁻¹({p}) = {q}, not {x}"
            );
        }
    }
}
