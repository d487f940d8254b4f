//! What sensors and an estimator cost a run: the paper-flip (4 s, RK4 at
//! 1 ms, control sampled at 100 Hz, recording off) flown on the truth,
//! against the same run with the `crazyflie` suite's noise on an IMU at
//! 1 kHz and motion capture at 100 Hz, the modes reading the mocap
//! estimator. The ratio of the medians is what a user pays for flying on
//! measurements.
//!
//! The `estimation` group: `figure-eight-estimated` (RK4 at 1 ms, control
//! and the invariant EKF at every 1 kHz IMU sample, mocap at 100 Hz)
//! against the same scene without sensors or estimator.
//!
//! `cargo bench -p geopid-studies --bench sensing`.

use criterion::{Criterion, criterion_group, criterion_main};
use scenes::scene::{EstimatorKind, EstimatorSpec, SensorsSpec, Timing};
use scenes::{Scene, builtin};

fn flip(sensed: bool) -> Scene {
    let mut s = builtin::paper_flip();
    s.integrator.kind = "rk4".into();
    s.integrator.dt = 1e-3;
    s.control.timing = Timing::Sampled;
    s.control.rate = 100.0;
    if sensed {
        s.seed = 1;
        s.sensors = Some(SensorsSpec {
            preset: "crazyflie".into(),
            noise_scale: 1.0,
            mocap_latency: Some(0.0),
            mocap_rate: None,
            ..SensorsSpec::default()
        });
        s.estimator = Some(EstimatorSpec {
            kind: EstimatorKind::Mocap,
            ..EstimatorSpec::default()
        });
    }
    s
}

#[path = "shared/quiet.rs"]
mod shared;
use shared::quiet;

fn bench(c: &mut Criterion) {
    let (truth, sensed) = (flip(false), flip(true));
    let mut g = c.benchmark_group("sensing");
    g.bench_function("flip-100hz-truth", |b| b.iter(|| quiet(&truth)));
    g.bench_function("flip-100hz-imu1k-mocap100", |b| b.iter(|| quiet(&sensed)));
    g.finish();
    // The invariant EKF at every 1 kHz IMU sample in the loop, against
    // the same scene flown on the truth with no sensors at all.
    let est = builtin::figure_eight_estimated();
    let mut truth = est.clone();
    (truth.sensors, truth.estimator) = (None, None);
    let mut g = c.benchmark_group("estimation");
    g.bench_function("figure-eight-truth", |b| b.iter(|| quiet(&truth)));
    g.bench_function("figure-eight-iekf-imu1k", |b| b.iter(|| quiet(&est)));
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
