//! Located sat′ crossings against crossings found without location.
//!
//! The reference is an independent fine run: RK4 at h = 5e-6 with event
//! location off and a sample at every step; the first time a component of
//! e_i reaches ±σ is read from those samples (a quadratic through the
//! bracketing pair and the next sample). Before the first crossing the law
//! is smooth, so this run is exact to RK4's error at that step plus the
//! interpolation's, O(h³): it agrees with the located runs below to 3e-13.
//! The located runs take steps of 0.1 ms (RK4) and calls of 10 and 50 ms
//! (Dormand–Prince at tol 1e-12), where the cubic Hermite estimate of the
//! crossing is only O(h⁴) accurate; the Newton refinement on redone steps
//! must bring them to the reference.

use scenarios::{RunOutput, Scene, builtin};

fn flip(kind: &str, dt: f64, tol: f64, locate: bool) -> Scene {
    let mut s = builtin::paper_flip();
    s.duration = 1.5;
    s.integrator.kind = kind.into();
    s.integrator.dt = dt;
    s.integrator.tol = tol;
    s.integrator.locate_events = locate;
    s.record.sample = if locate { 0.01 } else { dt };
    s
}

/// The first time |e_i,k| reaches σ = 1 after the switch to position mode
/// at 0.4 s, and which component, from the samples: the bracketing pair
/// and the sample after it give a quadratic (interpolation error O(h³)),
/// whose root in the bracket is found by bisection.
fn first_crossing(out: &RunOutput) -> (f64, usize) {
    let sigma = 1.0;
    let w = out.samples.windows(3).filter(|w| w[0].t >= 0.4);
    for w in w {
        for k in 0..3 {
            let g = |i: usize| w[i].e_pos[k].abs() - sigma;
            if (g(0) < 0.0) == (g(1) < 0.0) {
                continue;
            }
            let (t, y) = ([w[0].t, w[1].t, w[2].t], [g(0), g(1), g(2)]);
            let q = |x: f64| {
                y[0] * (x - t[1]) * (x - t[2]) / ((t[0] - t[1]) * (t[0] - t[2]))
                    + y[1] * (x - t[0]) * (x - t[2]) / ((t[1] - t[0]) * (t[1] - t[2]))
                    + y[2] * (x - t[0]) * (x - t[1]) / ((t[2] - t[0]) * (t[2] - t[1]))
            };
            let (mut lo, mut hi) = (t[0], t[1]);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if (q(mid) < 0.0) == (y[0] < 0.0) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            return (0.5 * (lo + hi), k);
        }
    }
    panic!("no crossing in {} samples", out.samples.len());
}

#[test]
fn located_crossings_match_an_unlocated_fine_run() {
    let fine = scenarios::run(&flip("rk4", 5e-6, 1e-10, false), Default::default()).unwrap();
    let (t_ref, k_ref) = first_crossing(&fine);
    println!("reference: e_i[{k_ref}] reaches ±σ at t = {t_ref:.15}");
    // Bounds from the measured |Δt| (rk4 1.1e-12, its own error at 1e-4;
    // dopri 3e-13 at both call lengths) with a margin of ~20–35×. With the
    // Newton step halved the 50 ms dopri calls land 1.8e-9 off; with the
    // Hermite estimate alone, further still.
    for (kind, dt, tol, bound) in [
        ("rk4", 1e-4, 1e-10, 2e-11),
        ("dopri", 1e-2, 1e-12, 1e-11),
        ("dopri", 5e-2, 1e-12, 1e-11),
    ] {
        let out = scenarios::run(&flip(kind, dt, tol, true), Default::default()).unwrap();
        let (t, k) = out
            .event_times
            .iter()
            .copied()
            .find(|(t, _)| *t >= 0.4)
            .expect("a located crossing");
        let err = (t - t_ref).abs();
        println!(
            "{kind} h = {dt} tol {tol:e}: located at {t:.15} (breakpoint {k}), |Δt| = {err:.2e}"
        );
        assert!(
            err <= bound,
            "{kind}: located {t}, reference {t_ref}: {err:e} > {bound:e}"
        );
    }
}
