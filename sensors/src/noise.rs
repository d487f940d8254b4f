//! The key of a sensor's noise.

use lie::noise::{mix, normal_pair};

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
        normal_pair(mix(self.base ^ mix(k.wrapping_mul(64).wrapping_add(j))))
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
