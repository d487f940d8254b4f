//! The IMU against RotorPy 3.0.0's `Imu.measurement`, noise off, along its
//! crazyflie's 10 s circle with aerodynamics on: the state and its
//! derivative at each of 1001 samples, and RotorPy's readings, come from
//! `golden/rotorpy_imu.py` (run now when `python3` imports `rotorpy`, else
//! the stored `golden/rotorpy_imu.txt`). The IMU sits at the centre of mass
//! (RotorPy's lever-arm terms mix frames) with a mounting rotation.
//!
//! Frames: RotorPy's world and body are z up; ours are e3 down, related by
//! `P = diag(1, −1, −1)` on both, so `R = P R' P`, `Ω = P Ω'`, `a = P a'`,
//! and an IMU mounted by `R_BS = P R'_BS P` reads `P f'`.

use std::path::PathBuf;

use lie::NalgebraF64 as B;
use nalgebra::{Matrix3, Vector3};
use sensors::{Imu, ImuSpec, Kinematics, NoiseKey};

fn reference() -> (String, &'static str) {
    let dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/golden");
    match testkit::rotorpy_golden(&dir, "rotorpy_imu") {
        (text, true) => (text, "RotorPy, run now"),
        (text, false) => (text, "the stored golden (rotorpy not importable)"),
    }
}

/// The rotation of a unit quaternion (x, y, z, w), normalised first as
/// scipy's `Rotation.from_quat` does.
fn rotation(q: [f64; 4]) -> Matrix3<f64> {
    let n = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]).sqrt();
    let [x, y, z, w] = q.map(|c| c / n);
    Matrix3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - z * w),
        2.0 * (x * z + y * w),
        2.0 * (x * y + z * w),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - x * w),
        2.0 * (x * z - y * w),
        2.0 * (y * z + x * w),
        1.0 - 2.0 * (x * x + y * y),
    )
}

/// Specific force within 1e-10 m/s² of RotorPy's (both compute
/// `R_BSᵀ Rᵀ (a − g)` in f64 from the same numbers, a few roundings of
/// ~10 m/s² apart: ~1e-14; 1e-10 is the bound), and the gyroscope
/// equal to `R_BSᵀ Ω` (RotorPy's reads Ω unrotated, a defect we do not
/// copy: compared with its Ω turned by the mounting).
#[test]
fn imu_matches_rotorpy() {
    let (text, source) = reference();
    let p = Matrix3::from_diagonal(&Vector3::new(1.0, -1.0, -1.0));
    let mut r_bs_rp = Matrix3::identity();
    let mut rows = Vec::new();
    for line in text.lines().filter(|l| !l.starts_with('#')) {
        let mut it = line.split_whitespace();
        let tag = it.next();
        let nums: Vec<f64> = it.map(|w| w.parse().expect("a number")).collect();
        match tag {
            Some("r_bs") => r_bs_rp = Matrix3::from_row_slice(&nums),
            Some("s") => rows.push(nums),
            _ => {}
        }
    }
    assert_eq!(rows.len(), 1001, "{source}");
    let r_bs = p * r_bs_rp * p;
    let mounting: [[f64; 3]; 3] = std::array::from_fn(|i| std::array::from_fn(|j| r_bs[(i, j)]));
    let spec = ImuSpec {
        mounting,
        ..ImuSpec::rotorpy(100.0).noiseless()
    };
    let imu = Imu::<B>::new(spec, NoiseKey::new(0, 0)).unwrap();
    let v3 = |s: &[f64]| p * Vector3::new(s[0], s[1], s[2]);
    let (mut worst_f, mut worst_w, mut largest) = (0.0f64, 0.0f64, 0.0f64);
    for n in &rows {
        let q = [n[7], n[8], n[9], n[10]];
        let kin = Kinematics::<B> {
            r: p * rotation(q) * p,
            omega: v3(&n[11..14]),
            accel: v3(&n[14..17]),
            alpha: v3(&n[17..20]),
        };
        let (f, w) = imu.ideal(&kin, 9.81);
        let f_rp = v3(&n[20..23]);
        worst_f = worst_f.max((f - f_rp).abs().max());
        worst_w = worst_w.max((w - r_bs.transpose() * kin.omega).abs().max());
        largest = largest.max((kin.accel).norm());
    }
    println!(
        "against {source}: 1001 samples, |a| up to {largest:.2} m/s²; specific force within \
         {worst_f:.2e} m/s², gyro within {worst_w:.2e} rad/s"
    );
    assert!(largest > 1.0, "the flight accelerates: {largest}");
    assert!(worst_f < 1e-10, "{worst_f}");
    assert!(worst_w < 1e-15, "{worst_w}");
}
