//! `cargo bench -p geopid-lie --features simd --bench lanes`: the same generic
//! formulas on one scalar per call (`NalgebraF64`, `NalgebraF32`) and on
//! lanes (`NalgebraF64x4`, `NalgebraF32x8`), over one batch of
//! [`BATCH`] rotation vectors; criterion's throughput is the batch size, so
//! its time per element is the time per rotation ("per scene").
//!
//! Two batches: `typical` (angles 0.1–1.6 rad, every lane on the same
//! branch of each formula) and `mixed` (a quarter of the inputs below the
//! exp cut-off and a quarter beyond 2π/3, shuffled, so most lane groups
//! evaluate both sides of a branch and blend them).

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use lie::{
    NalgebraF32, NalgebraF32x8, NalgebraF64, NalgebraF64x4, Real, SimdBackend, SimdReal, So3Mat,
    So3Quat, right_jacobian_inv,
};
use std::hint::black_box;

/// Rotations per timed iteration.
const BATCH: usize = 64;

fn batch(mixed: bool) -> Vec<[f64; 3]> {
    (0..BATCH)
        .map(|i| {
            let f = i as f64 / BATCH as f64;
            let angle = match (mixed, i % 4) {
                (true, 1) => 1e-4 * (1.0 + f),
                (true, 3) => 2.2 + 0.9 * f,
                _ => 0.1 + 1.5 * f,
            };
            let (a, b) = (7.0 * f, 3.0 * f);
            let axis = [a.cos() * b.sin(), a.sin() * b.sin(), b.cos()];
            axis.map(|x| x * angle)
        })
        .collect()
}

/// The batch as `LANES`-wide vectors of backend `L` (one lane per input).
fn packed<L: SimdBackend>(inputs: &[[f64; 3]]) -> Vec<L::Vec3> {
    let n = <L::Scalar as SimdReal>::LANES;
    inputs
        .chunks(n)
        .map(|c| {
            let lane = |k: usize| {
                <L::Scalar as SimdReal>::simd_from_fn(|i| {
                    <<L::Scalar as SimdReal>::Element as Real>::lit(c[i][k])
                })
            };
            L::vec3(lane(0), lane(1), lane(2))
        })
        .collect()
}

fn group<L: SimdBackend>(c: &mut Criterion, label: &str) {
    for mixed in [false, true] {
        let inputs = packed::<L>(&batch(mixed));
        let rots: Vec<So3Mat<L>> = inputs.iter().map(|p| So3Mat::<L>::exp(*p)).collect();
        let kind = if mixed { "mixed" } else { "typical" };
        let mut g = c.benchmark_group(format!("lanes/{kind}"));
        g.throughput(Throughput::Elements(BATCH as u64));
        g.bench_function(format!("exp/{label}"), |b| {
            b.iter(|| {
                for p in black_box(&inputs) {
                    black_box(So3Mat::<L>::exp(*p));
                }
            })
        });
        g.bench_function(format!("quat-exp/{label}"), |b| {
            b.iter(|| {
                for p in black_box(&inputs) {
                    black_box(So3Quat::<L>::exp(*p));
                }
            })
        });
        g.bench_function(format!("log/{label}"), |b| {
            b.iter(|| {
                for r in black_box(&rots) {
                    black_box(r.log());
                }
            })
        });
        g.bench_function(format!("jr-inv/{label}"), |b| {
            b.iter(|| {
                for p in black_box(&inputs) {
                    black_box(right_jacobian_inv::<L>(*p));
                }
            })
        });
        g.finish();
    }
}

fn benches(c: &mut Criterion) {
    group::<NalgebraF64>(c, "nalgebra-f64");
    group::<NalgebraF64x4>(c, "nalgebra-f64x4");
    group::<NalgebraF32>(c, "nalgebra-f32");
    group::<NalgebraF32x8>(c, "nalgebra-f32x8");
}

criterion_group!(lanes, benches);
criterion_main!(lanes);
