//! Crazyflie trajectory files: a planned trajectory written and read back
//! with the same coefficients bit for bit; a hand-written file in the
//! Crazyflie's layout (header, `%.6f` cells, a trailing comma, z-up)
//! evaluated here equal to its polynomials; malformed rows named.

use missions::{MinSnap, pptraj};

/// Written, read back: every duration and coefficient identical (Rust's
/// shortest round-trip formatting), and the frame flip undone exactly.
#[test]
fn a_planned_trajectory_round_trips_bit_for_bit() {
    let traj = MinSnap::through(&[
        [0.0, 0.0, -0.5],
        [1.0, 0.3, -1.0],
        [0.4, 1.7, -1.2],
        [0.0, 0.0, -0.5],
    ])
    .yaw(&[0.0, 0.7, -1.1, 0.2])
    .mean_speed(0.8)
    .solve()
    .unwrap();
    let text = pptraj::write(&traj);
    assert_eq!(text.lines().count(), 1 + traj.pieces().len());
    assert_eq!(pptraj::read(&text).unwrap(), traj);
    // Through a file, written whole.
    let path = std::env::temp_dir().join(format!("pptraj-{}.csv", std::process::id()));
    pptraj::write_file(&path, &traj).unwrap();
    assert_eq!(pptraj::read_file(&path).unwrap(), traj);
    let _ = std::fs::remove_file(&path);
}

/// The file's polynomials, evaluated here as power sums of its own cells
/// and turned from z-up (y, z and yaw negated), against the trajectory
/// read from it at 1 000 times: equal to 1e-12 (Horner against power sums
/// differ by rounding of terms up to about 10).
#[test]
fn a_crazyflie_file_is_its_polynomials() {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/tests/data/three_pieces.csv"
    ))
    .unwrap();
    let rows = testkit::pptraj_rows(&text);
    assert_eq!(rows.len(), 3);
    let traj = pptraj::read(&text).unwrap();
    let total: f64 = rows.iter().map(|r| r[0]).sum();
    assert!((traj.duration() - total).abs() < 1e-15);
    let mut worst = 0.0f64;
    for k in 0..1000 {
        let t = total * k as f64 / 999.0;
        let [px, py, pz, pyaw] = testkit::pptraj_eval(&rows, t);
        let f = traj.flat(t);
        let want = [px, -py, -pz];
        for (got, want) in f.x[0].iter().zip(want) {
            worst = testkit::nan_max(worst, (got - want).abs());
        }
        worst = testkit::nan_max(worst, (f.yaw[0] + pyaw).abs());
    }
    println!("three-piece file: largest difference from its polynomials {worst:.1e}");
    assert!(worst < 1e-12, "{worst}");
}

/// A malformed file: the error names the line, the column and the text.
#[test]
fn malformed_rows_are_named() {
    let good = "1.0".to_string() + &",0".repeat(32);
    let cases = [
        (
            format!("duration\n{}", good.replacen(",0", ",x", 1)),
            "line 2, column x^0: `x`: must be a number",
        ),
        (
            good.replacen("1.0", "-2", 1),
            "line 1, column duration: `-2`: must be positive",
        ),
        (format!("{good}\n1.0,2,3"), "line 2, column count (3)"),
        (
            good.replacen(",0", ",inf", 1),
            "column x^0: `inf`: must be finite",
        ),
        ("# nothing\n".to_string(), "at least one piece"),
    ];
    for (text, want) in cases {
        let got = pptraj::read(&text).unwrap_err().to_string();
        assert!(got.contains(want), "{got:?} lacks {want:?}");
    }
    let missing = pptraj::read_file(std::path::Path::new("/nonexistent/traj.csv")).unwrap_err();
    assert!(std::error::Error::source(&missing).is_some());
    assert!(missing.to_string().starts_with("/nonexistent/traj.csv: "));
}
