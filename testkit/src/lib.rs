//! Helpers for the workspace's own tests (not published).
//!
//! Some test binaries run without the libtest harness so that a plain
//! `cargo test` prints their figures (fitted orders, worst errors, the
//! reference a comparison used). Without the harness they print no
//! `test result:` line, so a count of passed and failed tests taken from
//! those lines would skip them. [`run`] runs such a binary's checks one by
//! one, each caught on its own, and ends with libtest's summary line, so
//! every check is counted and a failing one does not hide the others.

use std::panic::{AssertUnwindSafe, catch_unwind};
use std::time::Instant;

/// Runs the named checks in order, prints `test NAME ... ok|FAILED` for
/// each and libtest's `test result:` line, and exits with status 101 if
/// any failed (as libtest does). A check fails by panicking.
pub fn run(checks: &[(&str, fn())]) {
    let t0 = Instant::now();
    println!("\nrunning {} tests", checks.len());
    let mut failed = Vec::new();
    for (name, check) in checks {
        let ok = catch_unwind(AssertUnwindSafe(check)).is_ok();
        println!("test {name} ... {}", if ok { "ok" } else { "FAILED" });
        if !ok {
            failed.push(*name);
        }
    }
    let passed = checks.len() - failed.len();
    if !failed.is_empty() {
        println!("\nfailures:");
        for name in &failed {
            println!("    {name}");
        }
    }
    println!(
        "\ntest result: {}. {passed} passed; {} failed; 0 ignored; 0 measured; 0 filtered out; finished in {:.2}s\n",
        if failed.is_empty() { "ok" } else { "FAILED" },
        failed.len(),
        t0.elapsed().as_secs_f64()
    );
    if !failed.is_empty() {
        std::process::exit(101);
    }
}

/// `max` that keeps a NaN from either side (`f64::max` returns the other
/// operand): fold with it wherever a maximum decides a check, so a NaN
/// anywhere fails the bound instead of vanishing.
pub fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// The text of the golden `NAME.txt` in `dir`, written afresh by its
/// script `NAME.py` when `python3` can import `rotorpy` (the comparison
/// then runs against RotorPy itself), else the stored file; and whether it
/// was written now.
pub fn rotorpy_golden(dir: &std::path::Path, name: &str) -> (String, bool) {
    use std::process::Command;
    let has_rotorpy = Command::new("python3")
        .args(["-c", "import rotorpy"])
        .output()
        .is_ok_and(|o| o.status.success());
    if has_rotorpy {
        let out = std::env::temp_dir().join(format!("{name}_{}.txt", std::process::id()));
        let ok = Command::new("python3")
            .arg(dir.join(format!("{name}.py")))
            .arg(&out)
            .status()
            .is_ok_and(|s| s.success());
        if ok && let Ok(text) = std::fs::read_to_string(&out) {
            let _ = std::fs::remove_file(&out);
            return (text, true);
        }
    }
    let path = dir.join(format!("{name}.txt"));
    let text = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("the golden {}: {e}", path.display()));
    (text, false)
}

/// The pieces of a Crazyflie `pptraj` CSV, parsed here independently of
/// the reader under test: one row of 33 numbers (duration, then x, y, z
/// and yaw coefficients in ascending powers) per piece.
pub fn pptraj_rows(text: &str) -> Vec<Vec<f64>> {
    text.lines()
        .skip(1)
        .map(|l| {
            l.trim_end_matches(',')
                .split(',')
                .map(|c| c.parse().expect("a number"))
                .collect()
        })
        .collect()
}

/// `[x, y, z, yaw]` of `rows` (from [`pptraj_rows`]) at `t`, in the file's
/// own z-up frame, by summing the powers of each piece's local time.
pub fn pptraj_eval(rows: &[Vec<f64>], t: f64) -> [f64; 4] {
    let (mut start, mut i) = (0.0, 0);
    while i + 1 < rows.len() && t >= start + rows[i][0] {
        start += rows[i][0];
        i += 1;
    }
    let tau = t - start;
    std::array::from_fn(|a| {
        (0..8)
            .map(|j| rows[i][1 + 8 * a + j] * tau.powi(j as i32))
            .sum()
    })
}

#[cfg(test)]
mod tests {
    use super::nan_max;

    #[test]
    fn nan_max_keeps_a_nan_from_either_side() {
        assert!(nan_max(f64::NAN, 1.0).is_nan() && nan_max(1.0, f64::NAN).is_nan());
        assert_eq!(nan_max(1.0, 2.0), 2.0);
        let worst = [0.5, f64::NAN, 3.0].into_iter().fold(0.0, nan_max);
        assert!(worst.is_nan());
    }
}
