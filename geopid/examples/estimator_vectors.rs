//! Writes the firmware test's estimator stream: the IMU samples and
//! motion-capture frames of the first 0.3 s of `tumble-recovery-estimated`
//! (the vehicle upside down and turning fast, the BMI088's noise at 1 kHz,
//! motion capture at 100 Hz), in arrival order, as `f32`, after a start
//! event whose attitude is the truth's turned 90° about b1: the filters on
//! the flight CPU then make large corrections as well as small ones.
//!
//! Run: `cargo run -p geopid --example estimator_vectors -- firmware/vectors/estimators-f32.bin`

use geopid_control::vectors::Event;
use geopid_control::{GpcImuSample, GpcMocapSample, GpcState};
use scenarios::RunOptions;
use sensors::Measurement;

/// Seconds of flight: 300 IMU predicts and 30 frames keep the image's run
/// under QEMU's single-stepping (every instruction traced) within seconds.
const SECONDS: f64 = 0.3;

fn f32s<const N: usize>(a: [f64; N]) -> [f32; N] {
    a.map(|x| x as f32)
}

fn rows(m: [[f64; 3]; 3]) -> [[f32; 3]; 3] {
    m.map(f32s)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .ok_or("usage: estimator_vectors <output.bin>")?;
    let mut scene = scenes::builtin::tumble_recovery_estimated();
    scene.duration = SECONDS;
    let out = scenes::run(&scene, RunOptions::default())?;
    let first = out.samples.first().ok_or("the run recorded no sample")?;
    // R · Rx(π/2): the body's b2 and b3 swapped, one negated.
    let r = first.r;
    let turned: [[f64; 3]; 3] = std::array::from_fn(|i| [r[i][0], r[i][2], -r[i][1]]);
    let mut events = vec![Event::Start(
        first.t,
        GpcState {
            x: f32s(first.x),
            v: f32s(first.v),
            r: rows(turned),
            omega: f32s(first.omega),
        },
    )];
    let v = |a: lie::V3<lie::NalgebraF64>| [a.x as f32, a.y as f32, a.z as f32];
    for (_, m) in studies::estimation::arrivals(&out) {
        match m {
            Measurement::Imu(s) => events.push(Event::Imu(GpcImuSample {
                t: s.t,
                accel: v(s.accel),
                gyro: v(s.gyro),
            })),
            Measurement::Mocap(s) => events.push(Event::Mocap(GpcMocapSample {
                t: s.t,
                x: v(s.x),
                v: v(s.v),
                r: std::array::from_fn(|i| std::array::from_fn(|j| s.r[(i, j)] as f32)),
            })),
            _ => {}
        }
    }
    let bytes: Vec<u8> = events.iter().flat_map(|e| e.encode()).collect();
    std::fs::write(&path, &bytes)?;
    let imu = events.iter().filter(|e| matches!(e, Event::Imu(_))).count();
    println!(
        "wrote {path}: {} events ({imu} IMU samples, {} frames), {} bytes",
        events.len(),
        events.len() - imu - 1,
        bytes.len()
    );
    Ok(())
}
