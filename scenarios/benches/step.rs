//! Per-step cost of the closed loop, showing that a scene pays only for
//! what it uses: 1000 rk4 steps (1 s at 1 ms) with recording off, for
//! - `attitude-only`: the paper's attitude experiment on the pinned vehicle
//!   (no translation integrated),
//! - `attitude-translating`: the same plan on the free quadrotor,
//! - `position`: hover in position mode under Δ_x, Δ_R,
//! - `position-no-disturbance`: the same without disturbances.
//!
//! and the `position` loop on each (backend, scalar) pair (`pair/…`).
//!
//! `cargo bench -p scenarios --bench step`; divide by 1000 for ns/step.

use criterion::{Criterion, criterion_group, criterion_main};
use scenarios::scene::{BackendKind, Scalar, VehicleKind};
use scenarios::{RunOptions, Scene, builtin, run};

fn quiet(s: &Scene) {
    let out = run(
        s,
        RunOptions {
            record: false,
            progress: None,
        },
    )
    .expect("run");
    std::hint::black_box(out.last.psi);
}

fn bench(c: &mut Criterion) {
    let mut att = builtin::paper_attitude_experiment();
    att.duration = 1.0;
    let mut att_free = att.clone();
    att_free.vehicle.kind = VehicleKind::Quadrotor;
    let mut pos = builtin::hover_disturbed();
    pos.duration = 1.0;
    pos.integrator.dt = 1e-3;
    let mut pos_clean = pos.clone();
    pos_clean.disturbance = None;
    let mut g = c.benchmark_group("step");
    for (name, s) in [
        ("attitude-only", &att),
        ("attitude-translating", &att_free),
        ("position", &pos),
        ("position-no-disturbance", &pos_clean),
    ] {
        g.bench_function(name, |b| b.iter(|| quiet(s)));
    }
    g.finish();
    // The same closed loop on each (backend, scalar) pair.
    let mut g = c.benchmark_group("pair");
    for (scalar, backend, name) in [
        (Scalar::F64, BackendKind::Nalgebra, "nalgebra-f64"),
        (Scalar::F64, BackendKind::Glam, "glam-f64"),
        (Scalar::F32, BackendKind::Nalgebra, "nalgebra-f32"),
        (Scalar::F32, BackendKind::Glam, "glam-f32"),
    ] {
        let mut s = pos.clone();
        s.scalar = scalar;
        s.backend = backend;
        g.bench_function(name, |b| b.iter(|| quiet(&s)));
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
