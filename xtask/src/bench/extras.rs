//! The gradient's cost and the outputs' cost, the last two tables of
//! `cargo xtask bench`.

use std::collections::BTreeMap;
use std::io::Write as _;
use std::path::Path;
use std::process::Command;
use std::time::Instant;

/// The `gradient` bench (paper-flip, RK4, nalgebra f64): one recorded run,
/// one unrecorded run and one dual run with 12 seeded parameters, with the
/// gradient's cost in plain runs and against the 25 runs of central
/// differences. Empty when the bench did not run.
pub fn gradient_table(raw: &[(String, f64)]) -> String {
    let m: BTreeMap<&str, f64> = raw.iter().map(|(id, v)| (id.as_str(), *v)).collect();
    let get = |k: &str| m.get(format!("paper-flip-rk4/{k}").as_str()).copied();
    let (Some(run), Some(bare), Some(grad)) = (
        get("f64-run"),
        get("f64-run-unrecorded"),
        get("gradient-12"),
    ) else {
        return String::new();
    };
    let ms = |ns: f64| ns * 1e-6;
    let md = format!(
        "| paper-flip, RK4, nalgebra f64 | ms | in unrecorded runs |\n|---|---|---|\n\
         | one run, recorded | {:.3} | {:.2} |\n\
         | one run, unrecorded | {:.3} | 1.00 |\n\
         | gradient of 12 parameters (dual numbers) | {:.3} | {:.2} |\n\
         | the same by central differences (25 runs) | {:.3} | 25.00 |\n",
        ms(run),
        run / bare,
        ms(bare),
        ms(grad),
        grad / bare,
        25.0 * ms(bare),
    );
    println!("\n{md}");
    md
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

/// Wall seconds of this binary's `run hover-disturbed` over `duration`
/// simulated seconds sampled at 1 kHz, with `flags`.
fn timed_run(duration: f64, flags: &[&str]) -> Result<f64, String> {
    let exe = std::env::current_exe().map_err(|e| format!("this program's path: {e}"))?;
    let started = Instant::now();
    let out = Command::new(&exe)
        .args(["run", "hover-disturbed", "--sample", "0.001", "--duration"])
        .arg(duration.to_string())
        .args(flags)
        .output()
        .map_err(|e| format!("{}: {e}", exe.display()))?;
    let secs = started.elapsed().as_secs_f64();
    if !out.status.success() {
        return Err(format!(
            "{} run hover-disturbed {flags:?}: {}",
            exe.display(),
            String::from_utf8_lossy(&out.stderr).trim()
        ));
    }
    Ok(secs)
}

/// Seconds to write `bytes` zeros to `path` in 1 MiB blocks and fsync, as
/// `dd if=/dev/zero bs=1M conv=fsync` does.
fn dd(path: &Path, bytes: u64) -> Result<f64, String> {
    let block = vec![0u8; 1 << 20];
    let started = Instant::now();
    let mut f = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut left = bytes;
    while left > 0 {
        let n = left.min(block.len() as u64) as usize;
        f.write_all(&block[..n])
            .map_err(|e| format!("{}: {e}", path.display()))?;
        left -= n as u64;
    }
    f.sync_all()
        .map_err(|e| format!("{}: {e}", path.display()))?;
    let secs = started.elapsed().as_secs_f64();
    drop(f);
    std::fs::remove_file(path).map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(secs)
}

/// What the CSV and MCAP outputs cost: `hover-disturbed` at 1 kHz (60 s
/// simulated with `quick`, 600 s otherwise) without outputs, with each
/// and with both, alternated over three rounds; then the same bytes
/// written and fsynced as `dd` would. Medians; the outputs' cost is the
/// run with both minus the run with none.
pub fn outputs_table(out_dir: &Path, quick: bool) -> Result<String, String> {
    let duration = if quick { 60.0 } else { 600.0 };
    let dir = out_dir.join("output-cost");
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let (csv, mcap) = (dir.join("run.csv"), dir.join("run.mcap"));
    let (csv_s, mcap_s) = (csv.to_string_lossy(), mcap.to_string_lossy());
    let kinds: [(&str, Vec<&str>); 4] = [
        ("none", vec![]),
        ("CSV", vec!["--csv", &csv_s]),
        ("MCAP", vec!["--mcap", &mcap_s]),
        ("both", vec!["--csv", &csv_s, "--mcap", &mcap_s]),
    ];
    let mut walls: Vec<Vec<f64>> = vec![Vec::new(); kinds.len()];
    for _ in 0..3 {
        for (i, (_, flags)) in kinds.iter().enumerate() {
            // New files each time, as dd's below: replacing old ones adds
            // the kernel's freeing of their pages to the run.
            let _ = std::fs::remove_file(&csv);
            let _ = std::fs::remove_file(&mcap);
            walls[i].push(timed_run(duration, flags)?);
        }
    }
    let size = |p: &Path| {
        std::fs::metadata(p)
            .map(|m| m.len())
            .map_err(|e| format!("{}: {e}", p.display()))
    };
    let (csv_b, mcap_b) = (size(&csv)?, size(&mcap)?);
    std::fs::remove_file(&csv).map_err(|e| format!("{}: {e}", csv.display()))?;
    std::fs::remove_file(&mcap).map_err(|e| format!("{}: {e}", mcap.display()))?;
    let dd_s = median(
        (0..3)
            .map(|_| dd(&dir.join("dd"), csv_b + mcap_b))
            .collect::<Result<_, _>>()?,
    );
    let med: Vec<f64> = walls.into_iter().map(median).collect();
    let mut md = format!(
        "`hover-disturbed`, {duration} s simulated at 1 kHz; medians of 3 alternated runs.\n\n\
         | outputs | wall (s) | over none (s) |\n|---|---|---|\n"
    );
    for ((name, _), w) in kinds.iter().zip(&med) {
        md += &format!("| {name} | {w:.2} | {:.2} |\n", w - med[0]);
    }
    let cost = med[3] - med[0];
    md += &format!(
        "\nCSV {:.1} MB + MCAP {:.1} MB; `dd` with fsync of as many bytes: {dd_s:.2} s; \
         the outputs cost {cost:.2} s = {:.2}× dd.\n",
        csv_b as f64 * 1e-6,
        mcap_b as f64 * 1e-6,
        cost / dd_s,
    );
    println!("\n{md}");
    Ok(md)
}

#[cfg(test)]
mod tests {
    #[test]
    fn the_gradient_table_needs_all_three_benches_and_states_the_ratios() {
        let raw = |ids: &[(&str, f64)]| -> Vec<(String, f64)> {
            ids.iter()
                .map(|(k, v)| (format!("paper-flip-rk4/{k}"), *v))
                .collect()
        };
        assert_eq!(super::gradient_table(&raw(&[("f64-run", 2e6)])), "");
        let t = super::gradient_table(&raw(&[
            ("f64-run", 3e6),
            ("f64-run-unrecorded", 2e6),
            ("gradient-12", 9e6),
        ]));
        assert!(t.contains("| one run, recorded | 3.000 | 1.50 |"), "{t}");
        assert!(t.contains("(dual numbers) | 9.000 | 4.50 |"), "{t}");
        assert!(t.contains("(25 runs) | 50.000 | 25.00 |"), "{t}");
    }

    #[test]
    fn medians_of_odd_and_even_counts() {
        assert_eq!(super::median(vec![3.0, 1.0, 2.0]), 2.0);
        assert_eq!(super::median(vec![4.0, 1.0, 2.0, 3.0]), 2.5);
    }
}
