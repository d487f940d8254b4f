//! `cargo xtask bench [--quick]`: the speed of the generic code against
//! hand-written twins, and run time against error for every stepper on
//! every (backend, scalar) pair.
//!
//! 1. Runs the criterion benches `controllers/benches/update.rs` (one
//!    attitude and one position update) and `studies/benches/step.rs`
//!    (1000 closed-loop steps per stepper and pair, and the hand-written
//!    glam RK4 loop), then reads their medians from criterion's
//!    `estimates.json` files and writes `target/bench/summary.csv`:
//!    `name,backend,scalar,median_ns,baseline_ns,ratio`, the baseline being
//!    the hand-written twin of the same group and pair (empty where there
//!    is none). Closed-loop rows are per step (the 1000-step median / 1000);
//!    the `paper-flip rk4 1 ms whole run` rows are the whole 4 s flight
//!    with a sample every 0.05 s (the bench prints its final error first).
//!    Then the `vs-native` group of `lie/benches/lie.rs` (each SO(3) and
//!    SE(3) operation beside nalgebra's and glam's own types), printed as a
//!    second table with its ratios.
//! 2. Sweeps every stepper over its steps (dopri over tolerances) on
//!    `paper-flip` and `free-rigid-body` for the four pairs
//!    (`xtask/src/sweep.rs`), writing `target/bench/work_precision.csv` and
//!    `.svg` (a panel per scene and scalar).
//! 3. Logs every point to `target/bench/bench.mcap`: channel
//!    `/bench/summary` (schema `gpid.BenchRow`) and `/bench/work_precision`
//!    (`gpid.WorkPrecisionPoint`), JSON with JSON schemas, so benchmark
//!    history reads with the same tools as the flight logs.
//!
//! `--quick`: short criterion passes (0.1 s warm-up, 0.3 s measurement;
//! rough medians, for a smoke run),
//! every other sweep point, the free body over 10 s instead of 100 s.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};

use scenes::scene::{BackendKind, Scalar};

mod extras;
mod lanes;
mod lie_table;
mod report;

pub use lie_table::lie_table;

use crate::workspace_root;
use geopid_cli::sweep::{Point, points};

/// Options of `cargo xtask bench`.
#[derive(clap::Args, Debug)]
pub struct BenchArgs {
    /// Short passes (under 3 minutes of benchmarking; CI runs it).
    #[arg(long)]
    pub quick: bool,
    /// Skip the criterion runs and tabulate the last results.
    #[arg(long)]
    pub no_run: bool,
    /// Only the position updates per second, one core and every core,
    /// one lane and lanes (to compare builds: run it from a binary built
    /// with `RUSTFLAGS="-C target-cpu=native"`, say).
    #[arg(long)]
    pub throughput: bool,
    /// Also write the guide's performance chapter: the tables of this run
    /// with the machine, date and commit at the top (default path: the
    /// guide's `12-performance.md`; with `--quick`, whose figures are
    /// rough, `target/bench/performance.md`).
    #[arg(long, value_name = "PATH", num_args = 0..=1)]
    pub report: Option<Option<PathBuf>>,
}

/// One row of `summary.csv`.
struct Row {
    name: String,
    backend: String,
    scalar: String,
    median_ns: f64,
    baseline_ns: Option<f64>,
}

const PAIRS: [(&str, BackendKind, Scalar); 4] = [
    ("nalgebra-f32", BackendKind::Nalgebra, Scalar::F32),
    ("nalgebra-f64", BackendKind::Nalgebra, Scalar::F64),
    ("glam-f32", BackendKind::Glam, Scalar::F32),
    ("glam-f64", BackendKind::Glam, Scalar::F64),
];

fn bar(len: u64, what: &str) -> indicatif::ProgressBar {
    let b = geopid_cli::progress(len, "{msg} [{bar:30}] {pos}/{len}");
    b.set_message(what.to_string());
    b
}

/// The packages and features of every bench build: one set for all, so
/// that one `cargo bench --no-run` compiles each library once. (Most of
/// the build is the bench binaries themselves, each instantiating every
/// pair and stepper: one build instead of four saved little of it.)
const BENCH_PACKAGES: [&str; 3] = ["geopid-lie", "geopid-controllers", "geopid-studies"];
const BENCH_FEATURES: &str = "geopid-lie/simd,geopid-controllers/simd,geopid-studies/simd";

/// The criterion passes: `(package folder, bench target, filter)`. `lie`'s own
/// `lanes` bench (per-rotation lane timings) is not one of them.
const PASSES: [(&str, &str, &str); 6] = [
    ("controllers", "update", ""),
    ("studies", "step", ""),
    ("studies", "gradient", ""),
    ("lie", "lie", "vs-native"),
    ("controllers", "lanes", ""),
    ("studies", "lanes", ""),
];

/// Builds every bench binary of [`PASSES`] in one `cargo bench --no-run`
/// and returns `(package, target) -> executable`.
fn build_benches() -> Result<BTreeMap<(String, String), PathBuf>, String> {
    let mut cmd = Command::new(env!("CARGO"));
    cmd.args([
        "bench",
        "-q",
        "--no-run",
        "--message-format=json-render-diagnostics",
    ]);
    for p in BENCH_PACKAGES {
        cmd.args(["-p", p]);
    }
    cmd.args(["--features", BENCH_FEATURES]);
    let mut targets: Vec<&str> = PASSES.iter().map(|p| p.1).collect();
    targets.sort_unstable();
    targets.dedup();
    for t in targets {
        cmd.args(["--bench", t]);
    }
    // Compiler messages (rendered) go to stderr, shown as they come.
    let out = cmd
        .current_dir(workspace_root())
        .stderr(Stdio::inherit())
        .output()
        .map_err(|e| format!("cargo bench --no-run: {e}"))?;
    if !out.status.success() {
        return Err("cargo bench --no-run failed (compiler output above)".into());
    }
    let mut exes = BTreeMap::new();
    for line in String::from_utf8_lossy(&out.stdout).lines() {
        let Ok(v) = serde_json::from_str::<serde_json::Value>(line) else {
            continue;
        };
        let (Some(exe), Some(name), Some(manifest)) = (
            v["executable"].as_str(),
            v["target"]["name"].as_str(),
            v["manifest_path"].as_str(),
        ) else {
            continue;
        };
        // The package is the folder of its manifest (workspace members).
        let package = Path::new(manifest)
            .parent()
            .and_then(|d| d.file_name())
            .map(|d| d.to_string_lossy().into_owned())
            .unwrap_or_default();
        exes.insert((package, name.to_string()), PathBuf::from(exe));
    }
    Ok(exes)
}

/// Runs one bench binary as `cargo bench` would (from its package's folder,
/// with `--bench`), with the filter and, under `--quick`, short passes.
fn criterion(exe: &Path, package: &str, filter: &str, quick: bool) -> Result<(), String> {
    let mut cmd = Command::new(exe);
    cmd.arg("--bench")
        .current_dir(workspace_root().join(package))
        .env("CARGO_TARGET_DIR", target_dir())
        .stdout(Stdio::null());
    // Quick: of `lie`'s operations against the backends' own types, exp
    // and compose only (every pair and representation still runs; the
    // whole group is 144 benchmarks, 46 of them these: 50 s of CI saved).
    let filter = if quick && filter == "vs-native" {
        "vs-native/(exp|compose)/"
    } else {
        filter
    };
    if !filter.is_empty() {
        cmd.arg(filter);
    }
    if quick {
        // About half a second per benchmark (about 130 of them): rough medians.
        cmd.args([
            "--warm-up-time",
            "0.1",
            "--measurement-time",
            "0.3",
            "--nresamples",
            "10000",
        ]);
    }
    // Criterion's progress goes to stderr; it is shown only on failure.
    let out = cmd
        .stderr(Stdio::piped())
        .output()
        .map_err(|e| format!("{}: {e}", exe.display()))?;
    if !out.status.success() {
        return Err(format!(
            "{} --bench {filter} failed:\n{}",
            exe.display(),
            String::from_utf8_lossy(&out.stderr)
        ));
    }
    Ok(())
}

/// Cargo's target folder (`CARGO_TARGET_DIR` when set).
fn target_dir() -> PathBuf {
    std::env::var_os("CARGO_TARGET_DIR")
        .map(PathBuf::from)
        .unwrap_or_else(|| workspace_root().join("target"))
}

/// What a criterion id `group/pair[-hand|-direct]` measured.
#[derive(Copy, Clone, PartialEq, Eq, Debug)]
enum Variant {
    /// The public generic code (scene front end, generic loop).
    Generic,
    /// The hand-written twin, the baseline.
    Hand,
    /// The closed loop from the public pieces alone, without the
    /// `scenarios` layer (`step-rk4` only).
    Direct,
}

/// `(group, pair, variant)` of a criterion id.
fn parse(id: &str) -> Option<(String, String, Variant)> {
    let (group, func) = id.split_once('/')?;
    let (pair, variant) = if let Some(p) = func.strip_suffix("-hand") {
        (p, Variant::Hand)
    } else if let Some(p) = func.strip_suffix("-direct") {
        (p, Variant::Direct)
    } else {
        (func, Variant::Generic)
    };
    Some((group.to_string(), pair.to_string(), variant))
}

fn summary_rows(root: &Path) -> Result<Vec<Row>, String> {
    let mut raw = Vec::new();
    crate::collect(root, &mut raw)?;
    let wanted = |g: &str| {
        g == "attitude" || g == "position" || g.starts_with("step-") || g == "flip-rk4-1ms"
    };
    // (group, pair) -> [generic, hand, direct]
    let mut t: BTreeMap<(String, String), [Option<f64>; 3]> = BTreeMap::new();
    for (id, median) in raw {
        let Some((group, pair, variant)) = parse(&id) else {
            continue;
        };
        if !wanted(&group) {
            continue;
        }
        // Closed-loop groups time 1000 steps.
        let per = if group.starts_with("step-") {
            median / 1000.0
        } else {
            median
        };
        t.entry((group, pair)).or_default()[variant as usize] = Some(per);
    }
    let mut rows = Vec::new();
    for ((group, pair), [g, h, d]) in t {
        let (backend, scalar) = pair.split_once('-').unwrap_or((&pair, ""));
        let name = if let Some(k) = group.strip_prefix("step-") {
            format!("closed-loop {k} step")
        } else if group == "flip-rk4-1ms" {
            "paper-flip rk4 1 ms whole run".to_string()
        } else {
            format!("{group} update")
        };
        let row = |name: String, median_ns| Row {
            name,
            backend: backend.to_string(),
            scalar: scalar.to_string(),
            median_ns,
            baseline_ns: h,
        };
        if let Some(g) = g {
            rows.push(row(name.clone(), g));
        }
        if let Some(d) = d {
            rows.push(row(format!("{name} without the scenarios layer"), d));
        }
    }
    Ok(rows)
}

/// The criterion medians beside their hand-written baselines, as CSV and
/// as a Markdown table (whole runs in ms).
fn summary_tables(rows: &[Row]) -> (String, String) {
    let mut csv = String::from("name,backend,scalar,median_ns,baseline_ns,ratio\n");
    let mut table = String::from(
        "| what | backend | scalar | median (ns) | hand-written (ns) | ratio |\n|---|---|---|---|---|---|\n",
    );
    for r in rows {
        let ratio = r.baseline_ns.map(|b| r.median_ns / b);
        csv += &format!(
            "{},{},{},{:.3},{},{}\n",
            r.name,
            r.backend,
            r.scalar,
            r.median_ns,
            r.baseline_ns.map_or(String::new(), |b| format!("{b:.3}")),
            ratio.map_or(String::new(), |x| format!("{x:.4}"))
        );
        // Whole runs read better in ms.
        let time = |ns: f64| {
            if ns >= 1e5 {
                format!("{:.3} ms", ns * 1e-6)
            } else {
                format!("{ns:.1}")
            }
        };
        table += &format!(
            "| {} | {} | {} | {} | {} | {} |\n",
            r.name,
            r.backend,
            r.scalar,
            time(r.median_ns),
            r.baseline_ns.map_or("–".into(), time),
            ratio.map_or("–".into(), |x| format!("{x:.2}"))
        );
    }
    (csv, table)
}

/// `cargo xtask bench`.
pub fn bench(a: BenchArgs) -> Result<(), String> {
    let root = workspace_root();
    let out_dir = root.join("target").join("bench");
    std::fs::create_dir_all(&out_dir).map_err(|e| format!("{}: {e}", out_dir.display()))?;
    let started = std::time::Instant::now();
    if a.throughput {
        lanes::throughput(a.quick);
        return Ok(());
    }
    if !a.no_run {
        eprintln!(
            "building the criterion benches (controllers update, scenarios step, lie vs the backends' own types, the lanes)…"
        );
        let exes = build_benches()?;
        let b = bar(PASSES.len() as u64, "criterion");
        for (package, target, filter) in PASSES {
            let exe = exes
                .get(&(package.to_string(), target.to_string()))
                .ok_or_else(|| format!("cargo built no bench `{target}` of {package}"))?;
            criterion(exe, package, filter, a.quick)?;
            b.inc(1);
        }
        b.finish_and_clear();
    }
    let crit = target_dir().join("criterion");
    let rows = summary_rows(&crit)?;
    if rows.is_empty() {
        return Err(format!(
            "no results under {}: run without --no-run",
            crit.display()
        ));
    }
    let (csv, table) = summary_tables(&rows);
    print!("{table}");
    let [e64, e32] = studies::metrics::flip_rk4_errors().map_err(|e| e.to_string())?;
    let flip_error = format!(
        "paper-flip rk4 1 ms whole run: final-state error (max |Δx|, |ΔR| against dopri 1e-12 f64) {e64:.2e} in f64, {e32:.2e} in f32"
    );
    println!("{flip_error}");
    let mut raw = Vec::new();
    crate::collect(&crit, &mut raw)?;
    let (native, _) = lie_table(&raw, true);
    let lanes_md = lanes::lanes_table(&raw);
    let throughput_md = lanes::throughput(a.quick);
    let gradient_md = extras::gradient_table(&raw);
    let outputs_md = extras::outputs_table(&out_dir, a.quick)?;
    let summary = out_dir.join("summary.csv");
    std::fs::write(&summary, &csv).map_err(|e| format!("{}: {e}", summary.display()))?;
    let summary_csv = csv;

    // Work-precision on every pair.
    let mut wp: Vec<(String, &str, Point)> = Vec::new();
    let scenes = ["paper-flip", "free-rigid-body"];
    let per_pair = if a.quick { 16 } else { 32 };
    let b = bar(
        (scenes.len() * PAIRS.len() * per_pair) as u64,
        "work-precision",
    );
    for scene_name in scenes {
        let mut base = scenes::load(scene_name).map_err(|e| e.to_string())?;
        if a.quick && scene_name == "free-rigid-body" {
            base.duration = 10.0;
        }
        for (pair, backend, scalar) in PAIRS {
            base.backend = backend;
            base.scalar = scalar;
            let pts = points(&base, a.quick, &mut |_| b.inc(1))?;
            wp.extend(pts.into_iter().map(|p| (scene_name.to_string(), pair, p)));
        }
    }
    b.finish_and_clear();
    let mut csv = format!("scene,backend,scalar,{}\n", Point::CSV_COLUMNS);
    for (scene, pair, p) in &wp {
        let (backend, scalar) = pair.split_once('-').unwrap_or((pair, ""));
        csv += &format!("{scene},{backend},{scalar},{}\n", p.csv_row());
    }
    let wp_csv = out_dir.join("work_precision.csv");
    std::fs::write(&wp_csv, &csv).map_err(|e| format!("{}: {e}", wp_csv.display()))?;
    let wp_svg = out_dir.join("work_precision.svg");
    studies::figures::work_precision_panels(&wp_svg, &wp).map_err(|e| e.to_string())?;
    let fastest = best_per_accuracy(&wp);
    print!("{fastest}");

    // The tables as a log, read with the same tools as the flight logs;
    // stamped with the time of the run, so that files of several runs line
    // up on one timeline.
    let mcap = out_dir.join("bench.mcap");
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos() as u64);
    let tables = [
        ("/bench/summary", "gpid.BenchRow", summary_csv.as_str()),
        ("/bench/work_precision", "gpid.WorkPrecisionPoint", &csv),
    ]
    .map(|(topic, schema, csv)| logs::Table { topic, schema, csv });
    logs::write_tables(&mcap, now, &tables).map_err(|e| e.to_string())?;
    println!(
        "wrote {}, {}, {}, {} in {:.0} s",
        summary.display(),
        wp_csv.display(),
        wp_svg.display(),
        mcap.display(),
        started.elapsed().as_secs_f64()
    );
    if let Some(path) = &a.report {
        let tables = report::Tables {
            summary: &table,
            flip_error: &flip_error,
            fastest: &fastest,
            native: &native,
            lanes: &lanes_md,
            throughput: &throughput_md,
            gradient: &gradient_md,
            outputs: &outputs_md,
            work_precision_svg: &wp_svg,
        };
        report::write(path.as_deref(), a.quick, &tables)?;
    }
    Ok(())
}

/// For each scene and pair, the fastest stepper to reach 1e-4, 1e-6, 1e-9
/// (when any does): the reading of the work-precision figure.
fn best_per_accuracy(wp: &[(String, &str, Point)]) -> String {
    let mut out = String::from(
        "\nfastest stepper to reach an accuracy (wall time, best of 3):\n| scene | pair | ≤ 1e-4 | ≤ 1e-6 | ≤ 1e-9 |\n|---|---|---|---|---|\n",
    );
    let mut keys: Vec<(String, &str)> = wp.iter().map(|(s, p, _)| (s.clone(), *p)).collect();
    keys.dedup();
    for (scene, pair) in keys {
        let of_pair = || wp.iter().filter(|(s, p, _)| *s == scene && *p == pair);
        let cell = |target: f64| {
            studies::metrics::fastest_within(of_pair().map(|w| &w.2), target)
                .map_or("none".to_string(), |x| {
                    format!("{} {:.2e} ({:.1} ms)", x.kind, x.param, x.wall * 1e3)
                })
        };
        let [a, b, c] = [1e-4, 1e-6, 1e-9].map(cell);
        out += &format!("| {scene} | {pair} | {a} | {b} | {c} |\n");
    }
    out
}

#[cfg(test)]
mod tests {
    use super::{Variant, parse};

    #[test]
    fn criterion_ids_split_into_group_pair_and_twin() {
        assert_eq!(
            parse("position/glam-f64-hand"),
            Some(("position".into(), "glam-f64".into(), Variant::Hand))
        );
        assert_eq!(
            parse("step-rk4/nalgebra-f32"),
            Some(("step-rk4".into(), "nalgebra-f32".into(), Variant::Generic))
        );
        assert_eq!(
            parse("step-rk4/glam-f32-direct"),
            Some(("step-rk4".into(), "glam-f32".into(), Variant::Direct))
        );
        assert_eq!(parse("nogroup"), None);
    }
}

#[cfg(test)]
mod report_flag {
    use clap::Parser;

    #[derive(Parser)]
    struct Cli {
        #[command(flatten)]
        bench: super::BenchArgs,
    }

    #[test]
    fn report_takes_an_optional_path() {
        let parse = |args: &[&str]| Cli::try_parse_from(args).map(|c| c.bench.report);
        assert_eq!(parse(&["x"]).unwrap(), None);
        assert_eq!(parse(&["x", "--quick", "--report"]).unwrap(), Some(None));
        assert_eq!(
            parse(&["x", "--report", "p.md"]).unwrap(),
            Some(Some(std::path::PathBuf::from("p.md")))
        );
    }
}
