//! The wind scenes are reproducible from their seed and independent of
//! the step: the same scene twice writes byte-identical CSV, another seed
//! another flight, and RK4 at 1 ms and 0.5 ms agree to the integrator's
//! own error. The turbulence is step-size independent by construction:
//! its noise is drawn on a fixed 5 ms grid keyed by (seed, index) and the
//! forming filters are solved exactly between grid points, so the gust
//! field is a function of (seed, t) that every stepper samples alike.

use scenarios::{RunOptions, RunOutput};
use scenes::Scene;
use scenes::scene::WindSpec;
use studies::metrics::nan_max;

fn run(scene: &Scene) -> RunOutput {
    scenes::run(scene, RunOptions::default()).expect("run")
}

fn csv(scene: &Scene, dir: &std::path::Path, name: &str) -> Vec<u8> {
    let path = dir.join(name);
    logs::write_csv(&path, &run(scene)).expect("csv");
    std::fs::read(&path).expect("read back")
}

fn max_dx(a: &RunOutput, b: &RunOutput) -> f64 {
    assert_eq!(a.samples.len(), b.samples.len());
    a.samples
        .iter()
        .zip(&b.samples)
        .flat_map(|(p, q)| (0..3).map(move |k| (p.x[k] - q.x[k]).abs()))
        .fold(0.0, nan_max)
}

#[test]
fn wind_scenes_repeat_byte_for_byte_and_do_not_depend_on_the_step() {
    let dir = std::env::temp_dir().join(format!("wind-scenes-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    for name in ["gusty-hover", "figure-eight-wind"] {
        let mut scene = scenes::load(name).expect("built in");
        scene.duration = 10.0;
        let a = csv(&scene, &dir, "a.csv");
        let b = csv(&scene, &dir, "b.csv");
        assert!(a == b, "{name}: two runs of the same seed differ");
        let mut other = scene.clone();
        if let Some(WindSpec::Dryden { seed, .. }) = other.wind.as_mut() {
            *seed += 1;
        }
        let c = csv(&other, &dir, "c.csv");
        assert!(a != c, "{name}: another seed flew the same flight");
        let at = |dt: f64| {
            let mut s = scene.clone();
            s.integrator.dt = dt;
            run(&s)
        };
        let (h1, h2, h4) = (at(1e-3), at(5e-4), at(2.5e-4));
        let (d12, d24) = (max_dx(&h1, &h2), max_dx(&h2, &h4));
        let gust = h1
            .samples
            .iter()
            .flat_map(|s| s.wind)
            .fold(0.0f64, |m, w| m.max(w.abs()));
        println!(
            "{name}: RK4 max |Δx| 1 ms vs 0.5 ms {d12:.2e} m, 0.5 ms vs 0.25 ms {d24:.2e} m \
             (ratio {:.1}; gusts up to {gust:.2} m/s)",
            d12 / d24
        );
        // The differences are the integrator's own error: below a
        // micrometre and, where they stand above rounding, shrinking with
        // the step (measured ratio 9.1 per halving on figure-eight-wind, an
        // observed order of 3.2 where RK4's is 4: the located sat′ events
        // and the kinks of the held noise at grid points cost a little; 4,
        // order 2, is the bound). A field that depended on the steps would
        // move the vehicle by the gusts' effect, centimetres, whatever the
        // step.
        assert!(d12 < 1e-6, "{name}: {d12:e}");
        if d12 > 1e-10 {
            // From both sides: above 4 (order 2) and below 32 (order 5,
            // more than RK4 can give: a ratio there means the two finer
            // runs agree by accident, not by convergence).
            let ratio = d12 / d24;
            assert!(ratio > 4.0 && ratio < 32.0, "{name}: {d12:e} then {d24:e}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// A ladder's jumps are checkpoints: RK4 steps land on them, so a jump
/// between two steps of the 1 ms grid costs RK4 no accuracy against
/// Dormand–Prince (which lands on them too). Straddled, a jump of 3 m/s
/// in the wind (a drag step of ~0.1 m/s²) would leave an error of order
/// h²·Δa ≈ 1e-7 m in that step alone.
#[test]
fn steps_land_on_a_ladders_jumps() {
    let mut scene = scenes::load("gusty-hover").expect("built in");
    scene.duration = 4.0;
    scene.wind = Some(WindSpec::Ladder {
        times: vec![0.0, 1.0003, 2.5007],
        velocities: vec![[0.0; 3], [3.0, 0.0, 0.0], [-2.0, 1.0, 0.0]],
    });
    let rk4 = run(&scene);
    let mut exact = scene.clone();
    exact.integrator.kind = "dopri".into();
    exact.integrator.tol = 1e-12;
    exact.integrator.dt = 0.01;
    let dx = max_dx(&rk4, &run(&exact));
    println!("ladder wind, RK4 1 ms vs Dormand–Prince 1e-12: max |Δx| = {dx:.2e} m");
    assert!(dx < 1e-8, "{dx:e}");
    // The wind the samples report is the ladder's.
    let at = |t: f64| {
        rk4.samples
            .iter()
            .find(|s| (s.t - t).abs() < 1e-9)
            .map(|s| s.wind)
    };
    assert_eq!(at(1.0), Some([0.0; 3]));
    assert_eq!(at(1.01), Some([3.0, 0.0, 0.0]));
    assert_eq!(at(3.0), Some([-2.0, 1.0, 0.0]));
}
