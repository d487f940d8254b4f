//! Gradients through sensors and an estimator: a run's noise is a
//! constant of its seed, so the dual run's real part is the `f64` run bit
//! for bit, and its derivatives (through the measurements of the true
//! state, the invariant EKF and its noise scales) equal central
//! differences of plain runs with the same seed.

use scenes::{Registry, Scene, builtin};
use studies::sensitivity::{self, Cost, Tracking};

/// The gains of the position loop and the filter's two noise scales.
const SEEDS: [&str; 4] = [
    "gains.k_x",
    "gains.k_v",
    "estimator.q_scale",
    "estimator.r_scale",
];

/// The tracking cost's sampling interval, s.
const EVERY: f64 = 0.01;

fn plain(scene: &Scene) -> f64 {
    let mut cost = Tracking::of(scene, EVERY).unwrap();
    sensitivity::plain_cost(&Registry::new(), scene, EVERY, &mut cost).unwrap()
}

/// The worst difference between the gradient and central differences of
/// plain runs, relative to the gradient's norm, best over `steps`
/// (relative to each parameter's value), that step, and there each
/// component's difference relative to the component itself.
fn fd_agreement(
    scene: &Scene,
    g: &sensitivity::Gradient<4>,
    steps: &[f64],
) -> (f64, f64, [f64; 4]) {
    let norm = g.gradient.iter().map(|d| d * d).sum::<f64>().sqrt();
    let mut best = (f64::INFINITY, 0.0, [0.0; 4]);
    for &rel in steps {
        let (mut worst, mut own) = (0.0f64, [0.0; 4]);
        for (i, name) in g.parameters.iter().enumerate() {
            let mut base = scene.clone();
            let p0 = *sensitivity::parameter_mut(&mut base, name).unwrap();
            let h = rel * p0;
            let at = |d: f64| {
                let mut s = base.clone();
                *sensitivity::parameter_mut(&mut s, name).unwrap() = p0 + d;
                plain(&s)
            };
            let fd = (at(h) - at(-h)) / (2.0 * h);
            worst = worst.max((g.gradient[i] - fd).abs() / norm);
            own[i] = ((g.gradient[i] - fd) / g.gradient[i]).abs();
        }
        if worst < best.0 {
            best = (worst, rel, own);
        }
    }
    best
}

fn check(scene: &Scene, what: &str) {
    let reg = Registry::new();
    let mut cost = Tracking::of(scene, EVERY).unwrap();
    let g = sensitivity::gradient(&reg, scene, SEEDS, EVERY, |t, s| cost.at(t, s)).unwrap();
    assert_eq!(g.value.to_bits(), plain(scene).to_bits(), "{what}: value");
    // The filter's settings move the flight: their derivatives are not
    // zero, and the comparison below measures them.
    assert!(
        g.gradient[2] != 0.0 && g.gradient[3] != 0.0,
        "{what}: {:?}",
        g.gradient
    );
    let (worst, step, own) = fd_agreement(scene, &g, &[1e-4, 1e-5, 1e-6]);
    println!(
        "{what}: ∂cost/∂(k_x, k_v, q_scale, r_scale) = {}; central differences within {worst:.1e} of the norm (step {step:.0e} relative)",
        g.gradient.map(|d| format!("{d:.6e}")).join(", ")
    );
    // The costs are smooth only piecewise, at ~1e-5 relative (a noise
    // sample's effect through a saturation crossing appears or vanishes);
    // central differences with steps well inside a piece are good to
    // ~1e-9 of the norm here, and a wrong derivative shows at 1e-3 or more.
    assert!(worst < 1e-6, "{what}: {worst:e} at step {step:e}");
    // The noise scales' derivatives are small beside the gains' (the
    // filter's tuning moves the flight less than its gains do): each is
    // checked against its own size too, at 1e-3.
    println!(
        "{what}: each against its own size: {:?}",
        own.map(|x| format!("{x:.1e}"))
    );
    assert!(own[2] < 1e-3 && own[3] < 1e-3, "{what}: {own:?}");
}

#[test]
fn gradient_through_the_iekf_equals_central_differences() {
    let mut scene = builtin::figure_eight_estimated();
    scene.duration = 1.5;
    check(&scene, "figure-eight-estimated, 1.5 s");
}

#[test]
fn gradient_through_late_measurements_equals_central_differences() {
    // 20 ms of mocap latency: the filter applies each frame at its
    // capture time and replays the IMU samples since.
    let mut scene = builtin::hover_estimated();
    scene.duration = 1.0;
    scene.sensors.as_mut().unwrap().mocap_latency = Some(0.02);
    check(&scene, "hover-estimated, 20 ms mocap latency, 1 s");
}

#[test]
fn estimator_parameters_need_an_iekf() {
    let scene = builtin::figure_eight();
    let err = sensitivity::gradient(
        &Registry::new(),
        &scene,
        ["estimator.q_scale"],
        1.0,
        |_, s| s.body.x[0],
    )
    .unwrap_err()
    .to_string();
    assert!(
        err.contains("estimator.q_scale") && err.contains("iekf"),
        "{err}"
    );
}

#[test]
fn tuning_over_noise_seeds_lowers_the_held_out_cost() {
    // The gains tuned on the mean of 3 noise realisations, then flown with
    // the starting gains on 12 seeds the tuning never saw: the paired 95 %
    // interval of the cost's drop lies above zero.
    let mut scene = builtin::figure_eight_estimated();
    scene.duration = 2.0;
    let reg = Registry::new();
    let spec = sensitivity::GainTuning {
        factor: 4.0,
        every: EVERY,
        max_gradients: 3,
        max_thrust: None,
        noise_seeds: 3,
    };
    let out = sensitivity::tune_gains(&reg, &scene, &spec, &mut |_| {}).unwrap();
    // The reported cost is the mean over the three seeds.
    let mean = (0..3)
        .map(|i| {
            let mut s = scene.clone();
            s.seed += i;
            plain(&s)
        })
        .sum::<f64>()
        / 3.0;
    assert!(
        (out.history[0].cost - mean).abs() <= 1e-12 * mean,
        "{} vs {mean}",
        out.history[0].cost
    );
    let seeds = studies::held_out::held_out_seeds(&scene, 12);
    assert!(
        seeds.iter().all(|s| *s >= scene.seed + 3),
        "disjoint from the tuning's"
    );
    let h = studies::held_out::held_out_tracking(&reg, &scene, &out.scene, &seeds, EVERY).unwrap();
    println!(
        "held out: cost {:.4e} -> {:.4e} (mean), drop {:.3e}, 95 % [{:.3e}, {:.3e}]",
        h.start.iter().sum::<f64>() / 12.0,
        h.tuned.iter().sum::<f64>() / 12.0,
        h.improvement.mean,
        h.improvement.low,
        h.improvement.high
    );
    assert!(h.improvement.low > 0.0, "{:?}", h.improvement);
}
