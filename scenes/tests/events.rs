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

use scenarios::RunOutput;

use scenes::{Scene, builtin};

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
    let fine = scenes::run(&flip("rk4", 5e-6, 1e-10, false), Default::default()).unwrap();
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
        let out = scenes::run(&flip(kind, dt, tol, true), Default::default()).unwrap();
        let e = out
            .event_times
            .iter()
            .copied()
            .find(|e| e.t >= 0.4)
            .expect("a located crossing");
        let (t, k) = (e.t, e.component);
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

/// The Hermite estimate is O(h⁴) accurate, so at RK4's 0.1 ms steps
/// Newton needs a single redone step to land on the crossing (|g| ≤ 1e-13
/// after it): a located crossing costs one step more than the unlocated
/// run, and restarting the step grid at it one more step at most by the
/// end. Measured: 15 003 steps against 15 000 for two crossings. A seed
/// from a broken interpolation or bisection needs two or three more
/// Newton passes per crossing (15 007 with the bisection's midpoint
/// broken) while still landing on the crossing.
#[test]
fn newton_from_the_hermite_estimate_needs_one_redone_step() {
    let located = scenes::run(&flip("rk4", 1e-4, 1e-10, true), Default::default()).unwrap();
    let plain = scenes::run(&flip("rk4", 1e-4, 1e-10, false), Default::default()).unwrap();
    assert_eq!(located.events, 2, "{:?}", located.event_times);
    let extra = located.steps - plain.steps;
    println!(
        "{} steps located, {} without; {} crossings",
        located.steps, plain.steps, located.events
    );
    assert!(
        extra <= located.events as u64 + 1,
        "{extra} extra steps for {} crossings",
        located.events
    );
}

/// Two components of e_i crossing ±σ inside one step: both are located,
/// the earlier first, though it is the later breakpoint in index order.
/// Hover towards (3, 4, 0) m from the origin: e_i,y reaches σ at 0.0696 s
/// and e_i,x at 0.0928 s, both inside RK4's step [0.05, 0.1]. The
/// reference is the same scene at h = 1e-4 (its crossings agree with
/// h = 2e-3 to 6e-10 s); the long steps' own error moves the crossings
/// by 1.0e-5 and 1.3e-5 s (measured), so the bound is 5e-5 s, far below
/// the 0.023 s between them.
#[test]
fn the_earlier_of_two_crossings_in_one_step_is_located_first() {
    let scene = |dt: f64| {
        let mut s = builtin::hover_disturbed();
        s.duration = 0.5;
        s.disturbance = None;
        s.plan[0].position = Some(scenes::scene::PositionRef::Hold {
            x: [3.0, 4.0, 0.0],
            b1d: [1.0, 0.0, 0.0],
        });
        s.integrator.kind = "rk4".into();
        s.integrator.dt = dt;
        s.integrator.locate_events = true;
        s.record.sample = 0.05;
        s
    };
    let fine = scenes::run(&scene(1e-4), Default::default()).unwrap();
    let long = scenes::run(&scene(0.05), Default::default()).unwrap();
    println!("fine {:?}\nlong {:?}", fine.event_times, long.event_times);
    let order = |o: &RunOutput| {
        o.event_times
            .iter()
            .map(|e| e.component)
            .collect::<Vec<_>>()
    };
    assert_eq!(
        order(&fine)[..2],
        [1, 0],
        "the reference's first two crossings"
    );
    assert_eq!(order(&long), order(&fine), "crossings in the same order");
    for (a, b) in long.event_times.iter().zip(&fine.event_times).take(2) {
        assert!(
            (a.t - b.t).abs() < 5e-5,
            "located at {} s, the reference at {} s",
            a.t,
            b.t
        );
    }
}
