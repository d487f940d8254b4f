//! What sensors and an estimator cost a run: the paper-flip (4 s, RK4 at
//! 1 ms, control sampled at 100 Hz, recording off) flown on the truth,
//! against the same run with the `crazyflie` suite's noise on an IMU at
//! 1 kHz and motion capture at 100 Hz, the modes reading the mocap
//! estimator. The ratio of the medians is what a user pays for flying on
//! measurements.
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
            gyro_rates: false,
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
}

criterion_group!(benches, bench);
criterion_main!(benches);
