//! The known motion the estimator tests read: a body turning at a
//! constant rate while its centre moves on a smooth closed curve.

#![allow(dead_code)]

use lie::{NalgebraF64, So3Mat, V3};

pub type B = NalgebraF64;

pub fn v(a: [f64; 3]) -> V3<B> {
    B::vec3(a[0], a[1], a[2])
}

/// `(R, v, x, a, Ω)` at one instant.
pub type Truth = (So3Mat<B>, V3<B>, V3<B>, V3<B>, V3<B>);

/// The motion: `R = Exp(w t)`, `x = (cos ct, sin ct, 0.3 sin 2ct)` with
/// `c = 0.5`; returns `(R, v, x, a, Ω)`.
pub fn truth(t: f64) -> Truth {
    let w = [0.1, -0.05, 0.2];
    let c = 0.5;
    let (s1, c1) = (c * t).sin_cos();
    let (s2, c2) = (2.0 * c * t).sin_cos();
    let x = [c1, s1, 0.3 * s2];
    let vel = [-c * s1, c * c1, 0.6 * c * c2];
    let acc = [-c * c * c1, -c * c * s1, -1.2 * c * c * s2];
    (
        So3Mat::exp(v([w[0] * t, w[1] * t, w[2] * t])),
        v(vel),
        v(x),
        v(acc),
        v(w),
    )
}

pub const G: f64 = 9.81;
