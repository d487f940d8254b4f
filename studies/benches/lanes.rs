//! `cargo bench -p geopid-scenarios --features simd --bench lanes`: one RK4 step
//! of the closed loop (`scenarios::lanes::PositionLoop`: the position law,
//! the quadrotor's loads with Δ_x and Δ_R, six integral states) for a
//! batch of [`BATCH`] scenes, one scene per call on the scalar backends
//! and four or eight per call on the lane backends: the same generic code
//! each time. Criterion's throughput is the batch, so its time per element
//! is per scene and step.

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use integrators::State;
use integrators::lanes::rk4_step;
use lie::{Backend, NalgebraF32, NalgebraF32x8, NalgebraF64, NalgebraF64x4, SimdBackend, SimdReal};
use scenarios::lanes::PositionLoop;
use std::hint::black_box;

/// Scenes per timed iteration.
const BATCH: usize = 64;

/// Scene `i`: the position Monte Carlo's sample `i` (random attitude,
/// rates, position and velocity; integrals zero).
fn scene<S: Backend>(i: usize) -> State<S, 6> {
    State::new(
        studies::montecarlo::Setup::default()
            .initial(i as u64)
            .body::<S>(),
    )
}

fn bench_lanes<S, L>(c: &mut Criterion)
where
    S: Backend,
    L: SimdBackend<Scalar: SimdReal<Element = S::Scalar>>,
{
    let n = <L::Scalar as SimdReal>::LANES;
    let mut sys = PositionLoop::<L>::paper::<S>();
    let start: Vec<State<L, 6>> = (0..BATCH / n)
        .map(|g| integrators::lanes::state_from_fn::<S, L, 6>(|i| scene::<S>(g * n + i)))
        .collect();
    let (t, h) = (L::Scalar::simd_lit(0.0), L::Scalar::simd_lit(1e-3));
    let mut g = c.benchmark_group("lanes/step-rk4");
    g.throughput(Throughput::Elements(BATCH as u64));
    g.bench_function(L::NAME, |b| {
        b.iter(|| {
            let mut ys = start.clone();
            for y in ys.iter_mut() {
                rk4_step(&mut sys, t, h, black_box(y));
            }
            black_box(ys)
        })
    });
    g.finish();
}

fn benches(c: &mut Criterion) {
    bench_lanes::<NalgebraF64, NalgebraF64>(c);
    bench_lanes::<NalgebraF64, NalgebraF64x4>(c);
    bench_lanes::<NalgebraF32, NalgebraF32>(c);
    bench_lanes::<NalgebraF32, NalgebraF32x8>(c);
}

criterion_group!(lanes_bench, benches);
criterion_main!(lanes_bench);
