//! Shared helpers for the generic test suites: a seeded RNG, conversions
//! to plain `f64` arrays, and reference maths (series matrix exponentials)
//! that shares no code with the crate under test.
#![allow(dead_code)]

use lie::{Backend, M3, Real, S, V3};

pub type A3 = [f64; 3];
pub type A33 = [[f64; 3]; 3];

/// SplitMix64: deterministic, no dependency.
pub struct Rng(u64);
impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed)
    }
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E3779B97F4A7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58476D1CE4E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D049BB133111EB);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
    pub fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.uniform()
    }
    /// Uniform on the unit sphere.
    pub fn unit(&mut self) -> A3 {
        let z = self.range(-1.0, 1.0);
        let a = self.range(0.0, 2.0 * std::f64::consts::PI);
        let r = (1.0 - z * z).sqrt();
        [r * a.cos(), r * a.sin(), z]
    }
    /// A rotation vector with angle uniform in [0, max_angle].
    pub fn rotvec(&mut self, max_angle: f64) -> A3 {
        scale(self.unit(), self.range(0.0, max_angle))
    }
}

pub fn eps<B: Backend>() -> f64 {
    S::<B>::epsilon().to_f64_lossless()
}
pub fn is_f64<B: Backend>() -> bool {
    eps::<B>() < 1e-10
}
pub fn s<B: Backend>(x: f64) -> S<B> {
    S::<B>::lit(x)
}
pub fn v64<B: Backend>(v: V3<B>) -> A3 {
    B::vec3_to_array(v).map(|x| x.to_f64_lossless())
}
pub fn vb<B: Backend>(a: A3) -> V3<B> {
    B::vec3(s::<B>(a[0]), s::<B>(a[1]), s::<B>(a[2]))
}
pub fn m64<B: Backend>(m: M3<B>) -> A33 {
    let c = B::mat3_cols(m).map(v64::<B>);
    [
        [c[0][0], c[1][0], c[2][0]],
        [c[0][1], c[1][1], c[2][1]],
        [c[0][2], c[1][2], c[2][2]],
    ]
}
pub fn mb<B: Backend>(a: A33) -> M3<B> {
    B::mat3_from_cols(
        vb::<B>([a[0][0], a[1][0], a[2][0]]),
        vb::<B>([a[0][1], a[1][1], a[2][1]]),
        vb::<B>([a[0][2], a[1][2], a[2][2]]),
    )
}

pub fn scale(a: A3, k: f64) -> A3 {
    a.map(|x| x * k)
}
pub fn add(a: A3, b: A3) -> A3 {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
pub fn sub(a: A3, b: A3) -> A3 {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub fn dot(a: A3, b: A3) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub fn cross(a: A3, b: A3) -> A3 {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub fn norm(a: A3) -> f64 {
    dot(a, a).sqrt()
}
pub fn dist(a: A3, b: A3) -> f64 {
    norm(sub(a, b))
}
pub fn mdist(a: A33, b: A33) -> f64 {
    let mut s = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            s += (a[i][j] - b[i][j]).powi(2);
        }
    }
    s.sqrt()
}
pub fn mmul(a: A33, b: A33) -> A33 {
    let mut c = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                c[i][j] += a[i][k] * b[k][j];
            }
        }
    }
    c
}
pub fn hat64(x: A3) -> A33 {
    [[0.0, -x[2], x[1]], [x[2], 0.0, -x[0]], [-x[1], x[0], 0.0]]
}
pub const I3: A33 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// Matrix exponential of an n×n matrix by its plain Taylor series (60
/// terms, no scaling and squaring, whose repeated squarings would amplify
/// rounding): a reference independent of every closed form and small-angle
/// branch in the crate. For ‖a‖ ≤ 4 the dropped terms are below 4⁶⁰/60! ≈
/// 1e-46 and the rounding is a few ε times the largest term (≈ π³/6).
pub fn expm<const N: usize>(a: [[f64; N]; N]) -> [[f64; N]; N] {
    let mut result = [[0.0; N]; N];
    let mut term = [[0.0; N]; N];
    for i in 0..N {
        result[i][i] = 1.0;
        term[i][i] = 1.0;
    }
    for n in 1..60 {
        let mut next = [[0.0; N]; N];
        for i in 0..N {
            for j in 0..N {
                for l in 0..N {
                    next[i][j] += term[i][l] * a[l][j];
                }
                next[i][j] /= n as f64;
            }
        }
        term = next;
        for i in 0..N {
            for j in 0..N {
                result[i][j] += term[i][j];
            }
        }
    }
    result
}

/// Axes the hard cases are taken about: the coordinate axes and two
/// oblique ones.
pub fn axes() -> Vec<A3> {
    let n = |a: A3| scale(a, 1.0 / norm(a));
    vec![
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        n([1.0, 1.0, 1.0]),
        n([0.3, -2.0, 0.7]),
    ]
}

/// The hard angles below π − 1e-6: zero, tiny, and each cut-off ± 1e-6
/// relative (for the log cut-off, the angle whose |q_v| is at it).
pub fn hard_angles<T: Real>() -> Vec<f64> {
    let mut v = vec![0.0, 1e-12, 1e-8, 1e-4, 0.5, 1.0, 2.0, 3.0];
    for c in [T::CUT_EXP, T::CUT_JAC, T::CUT_JAC_SE3] {
        let c = c.to_f64_lossless();
        v.extend([c * (1.0 - 1e-6), c, c * (1.0 + 1e-6)]);
    }
    let cl = 2.0 * T::CUT_LOG.to_f64_lossless().asin();
    v.extend([cl * (1.0 - 1e-3), cl * (1.0 + 1e-3)]);
    v.push(std::f64::consts::PI - 1e-6);
    v
}
