//! The continuous extension reproduces what a cubic Hermite interpolant
//! must reproduce exactly: states whose position, velocity, angular
//! velocity and extra states are cubics in time, and an attitude
//! `R(t) = R₀ Exp(ξ(t))` with `ξ` a cubic in the Lie algebra (its angular
//! velocity `Ω = J_r(ξ) ξ̇`). Any wrong weight or sign in the Hermite basis,
//! a slope taken from the wrong end, or a slope of `R` without `J_r⁻¹`,
//! leaves an error of the size of the data, not of rounding.

use dynamics::RigidBodyState;
use integrators::State;
use integrators::dense::{Rates, interpolate};
use lie::{NalgebraF64, So3Mat, V3, right_jacobian};

type B = NalgebraF64;

fn v(a: [f64; 3]) -> V3<B> {
    B::vec3(a[0], a[1], a[2])
}

/// `c0 + c1 t + c2 t² + c3 t³` per component, and its first and second
/// derivatives.
struct Cubic([[f64; 3]; 4]);
impl Cubic {
    fn at(&self, t: f64) -> [V3<B>; 3] {
        let c = &self.0;
        let p = |k: usize| c[0][k] + t * (c[1][k] + t * (c[2][k] + t * c[3][k]));
        let d = |k: usize| c[1][k] + t * (2.0 * c[2][k] + t * 3.0 * c[3][k]);
        let dd = |k: usize| 2.0 * c[2][k] + 6.0 * t * c[3][k];
        [
            v([p(0), p(1), p(2)]),
            v([d(0), d(1), d(2)]),
            v([dd(0), dd(1), dd(2)]),
        ]
    }
}

#[test]
fn cubic_data_are_reproduced_to_rounding() {
    let x = Cubic([
        [1.0, -2.0, 0.5],
        [0.3, 0.8, -1.1],
        [-0.7, 0.2, 0.9],
        [0.4, -0.6, 0.25],
    ]);
    let w = Cubic([
        [0.2, -0.4, 1.5],
        [1.1, 0.3, -0.2],
        [-0.5, 0.9, 0.1],
        [0.3, 0.2, -0.7],
    ]);
    // ξ(0) = 0, so the attitude starts at R₀.
    let xi = Cubic([
        [0.0; 3],
        [0.9, -0.3, 0.6],
        [-0.4, 0.5, 0.2],
        [0.3, -0.2, -0.5],
    ]);
    let r0 = So3Mat::<B>::exp(v([0.4, -1.2, 2.0]));
    let extra = |t: f64| -> ([f64; 2], [f64; 2]) {
        (
            [1.0 - t + 2.0 * t * t - 0.5 * t * t * t, 3.0 * t * t * t],
            [-1.0 + 4.0 * t - 1.5 * t * t, 9.0 * t * t],
        )
    };
    let (t0, h) = (0.3, 0.7);
    let state = |t: f64| -> (State<B, 2>, Rates<B, 2>) {
        let s = (t - t0) / h;
        // ξ is a cubic in the step's own time s·h from its start.
        let [xs, xsd, _] = xi.at(s * h);
        let [p, pd, pdd] = x.at(t);
        let [om, omd, _] = w.at(t);
        let r = r0.compose(So3Mat::<B>::exp(xs));
        let omega_r = right_jacobian::<B>(xs) * xsd;
        let (e, ed) = extra(t);
        let body = RigidBodyState::<B> {
            r: r.as_matrix(),
            x: p,
            v: pd,
            omega: omega_r,
        };
        // Ω for the attitude's own slope; the Ω *component* interpolated
        // as a cubic is checked separately below with `w`.
        let _ = (om, omd);
        (
            State { body, extra: e },
            Rates {
                v_dot: pdd,
                omega_dot: v([0.0; 3]),
                extra: ed,
            },
        )
    };
    let (y0, r0s) = state(t0);
    let (y1, r1s) = state(t0 + h);
    let mut worst = 0.0f64;
    for theta in [0.0, 0.2, 0.5, 0.77, 1.0] {
        let t = t0 + theta * h;
        let got = interpolate(&y0, &r0s, &y1, &r1s, h, theta);
        let (want, _) = state(t);
        let d = (got.body.r - want.body.r).norm()
            + (got.body.x - want.body.x).norm()
            + (got.body.v - want.body.v).norm()
            + (0..2)
                .map(|k| (got.extra[k] - want.extra[k]).abs())
                .sum::<f64>();
        assert!(d.is_finite());
        worst = testkit::nan_max(worst, d);
    }
    // Ω as a cubic: the same interpolant through Ω and Ω̇ data.
    let with_w = |t: f64| {
        let (mut y, mut r) = state(t);
        let [om, omd, _] = w.at(t);
        y.body.omega = om;
        r.omega_dot = omd;
        (y, r)
    };
    let ((a0, ra), (a1, rb)) = (with_w(t0), with_w(t0 + h));
    for theta in [0.2, 0.5, 0.77] {
        let got = interpolate(&a0, &ra, &a1, &rb, h, theta);
        let [want, _, _] = w.at(t0 + theta * h);
        worst = testkit::nan_max(worst, (got.body.omega - want).norm());
    }
    println!("cubic data through the continuous extension: worst error {worst:.1e}");
    // Rounding of O(1) data through a dozen operations and one exp/log
    // pair: measured 1.0e-15; a wrong basis weight costs O(0.1).
    assert!(worst < 1e-13, "{worst:e}");
}
