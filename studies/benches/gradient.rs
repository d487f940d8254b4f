//! What a gradient costs: the paper-flip as built in (4 s, RK4 at the
//! scene's h = 0.5 ms: 8 000 steps, a sample every 2 ms) as one
//! nalgebra-f64 run (recorded, as a user runs it, and unrecorded, as a
//! gradient flies it), and as one dual run with 12 seeded parameters (the
//! 9 gains and the initial position), in the same binary. Central
//! differences would take 25 plain runs for the same 12 derivatives.
//!
//! `cargo bench -p geopid-scenarios --bench gradient`.

use criterion::{Criterion, criterion_group, criterion_main};
use lie::{Dual, NalgebraF64};
use scenarios::RunOptions;
use scenes::{Registry, builtin};
use std::hint::black_box;
use studies::sensitivity;

/// The 9 gains (the first entries of `PARAMETERS`) and the initial
/// position (its entries 16 to 18).
fn seeds() -> [&'static str; 12] {
    let p = sensitivity::PARAMETERS;
    core::array::from_fn(|i| if i < 9 { p[i] } else { p[i + 7] })
}

fn bench(c: &mut Criterion) {
    let reg = Registry::new();
    let mut scene = builtin::paper_flip();
    scene.integrator.kind = "rk4".into();
    let mut g = c.benchmark_group("paper-flip-rk4");
    g.sample_size(10);
    g.bench_function("f64-run", |b| {
        b.iter(|| {
            let mut sim = reg.builder::<NalgebraF64>(&scene).unwrap().build().unwrap();
            sim.advance_to(scene.duration).unwrap();
            black_box(sim.state().body.x);
        })
    });
    // The plain run as a gradient flies it: no samples kept, no per-step
    // extrema (a gradient reads the state where it pauses), so the ratio
    // compares the same work; `f64-run` above is the run a user records.
    g.bench_function("f64-run-unrecorded", |b| {
        b.iter(|| {
            let mut sim = reg.builder::<NalgebraF64>(&scene).unwrap().build().unwrap();
            let bare = RunOptions {
                record: false,
                extrema: false,
                ..RunOptions::default()
            };
            sim.advance_to_with(scene.duration, bare).unwrap();
            black_box(sim.state().body.x);
        })
    });
    g.bench_function("gradient-12", |b| {
        b.iter(|| {
            let out = sensitivity::gradient(&reg, &scene, seeds(), scene.duration, |_, s| {
                s.body.x[2] * Dual::constant(1.0)
            })
            .unwrap();
            black_box(out.gradient);
        })
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
