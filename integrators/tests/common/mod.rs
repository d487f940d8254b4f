#![allow(dead_code)]
//! Shared helpers: f64 views of generic states, the exact free body, order
//! fitting.

use dynamics::free_body::ExactFreeBody;
use integrators::{Integrator, State, integrate_fixed};
use lie::{Backend, Real, S, ops};

pub type M = [[f64; 3]; 3];

pub fn mat_f64<B: Backend>(m: lie::M3<B>) -> M {
    ops::elems::<B>(m).map(|r| r.map(|x| x.to_f64_lossless()))
}

pub fn vec_f64<B: Backend>(v: lie::V3<B>) -> [f64; 3] {
    B::vec3_to_array(v).map(|x| x.to_f64_lossless())
}

pub fn mat_dist(a: M, b: M) -> f64 {
    let mut s = 0.0;
    for i in 0..3 {
        for k in 0..3 {
            s += (a[i][k] - b[i][k]).powi(2);
        }
    }
    s.sqrt()
}

pub fn vec_dist(a: [f64; 3], b: [f64; 3]) -> f64 {
    (0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt()
}

/// The free-body test case: J = diag(1, 2, 3), a tilted start, Ω(0) with all
/// three components (so no closed-form shortcut hides an error).
pub const OMEGA0: [f64; 3] = [0.4, -0.8, -1.1];

/// R(0) of the shared free-body start.
pub fn r0<B: Backend>() -> lie::M3<B> {
    integrators::problems::free_body_start::<B>().r
}

pub fn exact() -> ExactFreeBody {
    ExactFreeBody::new(
        [1.0, 2.0, 3.0],
        OMEGA0,
        mat_f64::<lie::NalgebraF64>(r0::<lie::NalgebraF64>()),
    )
    .expect("major-axis regime")
}

pub fn free_start<B: Backend>() -> State<B, 0> {
    State::new(integrators::problems::free_body_start::<B>())
}

/// Runs `n` steps to `t_end` on the free body and returns the final state.
pub fn run_free<B: Backend, I: Integrator<B, 0>>(
    integ: &mut I,
    t_end: f64,
    n: usize,
) -> State<B, 0> {
    let mut sys = integrators::problems::Top::<B>::free_diag123();
    let mut y = free_start::<B>();
    let h = S::<B>::lit(t_end / n as f64);
    integrate_fixed(integ, &mut sys, S::<B>::lit(0.0), h, n, &mut y).expect("step");
    y
}

/// max(‖R − R_ref‖_F, |Ω − Ω_ref|).
pub fn state_error<B: Backend, const N: usize>(y: &State<B, N>, r: M, w: [f64; 3]) -> f64 {
    mat_dist(mat_f64::<B>(y.body.r), r).max(vec_dist(vec_f64::<B>(y.body.omega), w))
}

/// Least-squares slope of log(err) against log(h).
pub fn fitted_order(hs: &[f64], errs: &[f64]) -> f64 {
    let xs: Vec<f64> = hs.iter().map(|h| h.ln()).collect();
    let ys: Vec<f64> = errs.iter().map(|e| e.ln()).collect();
    let n = xs.len() as f64;
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx).powi(2)).sum();
    sxy / sxx
}
