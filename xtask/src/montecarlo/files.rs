//! The files of a Monte Carlo run: `samples.csv` and `run.json` written
//! atomically, shards and their merge.

use std::path::{Path, PathBuf};

use scenarios::montecarlo::{Outcome, Setup};

use super::finish;

/// `K/N`.
pub fn parse_shard(s: &str) -> Result<(u64, u64), String> {
    let bad = || format!("--shard {s}: expected K/N with 0 ≤ K < N");
    let (k, n) = s.split_once('/').ok_or_else(bad)?;
    let (k, n) = (
        k.trim().parse::<u64>().map_err(|_| bad())?,
        n.trim().parse::<u64>().map_err(|_| bad())?,
    );
    if n == 0 || k >= n {
        return Err(bad());
    }
    Ok((k, n))
}

pub fn default_out(experiment: &str) -> PathBuf {
    crate::workspace_root()
        .join("target/montecarlo")
        .join(experiment)
}

pub fn write_samples(dir: &Path, rows: &[Outcome]) -> Result<(), String> {
    let text = scenarios::montecarlo::write_samples(rows);
    write_atomic(&dir.join("samples.csv"), text.as_bytes())
}

/// Writes `<path>.partial`, then renames it.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let mut tmp = path.as_os_str().to_os_string();
    tmp.push(".partial");
    std::fs::write(&tmp, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))
}

fn read_samples(dir: &Path) -> Result<Vec<Outcome>, String> {
    let path = dir.join("samples.csv");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    scenarios::montecarlo::parse_samples(&text).map_err(|e| format!("{}: {e}", path.display()))
}

pub fn write_run_json(dir: &Path, setup: &Setup, shard: (u64, u64)) -> Result<(), String> {
    let run = serde_json::json!({"setup": setup, "shard": [shard.0, shard.1]});
    write_atomic(
        &dir.join("run.json"),
        serde_json::to_string_pretty(&run)
            .map_err(|e| e.to_string())?
            .as_bytes(),
    )
}

/// A shard's directory: `run.json` (the setup and `[K, N]`) and its rows
/// of `samples.csv`, what `merge` reads.
pub fn write_shard(
    dir: &Path,
    setup: &Setup,
    shard: (u64, u64),
    rows: &[Outcome],
) -> Result<(), String> {
    write_run_json(dir, setup, shard)?;
    write_samples(dir, rows)
}

/// `cargo xtask montecarlo merge DIR...`.
pub fn merge(dirs: &[PathBuf], out: Option<&Path>) -> Result<(), String> {
    let mut setup: Option<Setup> = None;
    let mut shards = Vec::new();
    let mut rows = Vec::new();
    for d in dirs {
        let p = d.join("run.json");
        let text = std::fs::read_to_string(&p).map_err(|e| format!("{}: {e}", p.display()))?;
        let v: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", p.display()))?;
        let s: Setup = serde_json::from_value(v["setup"].clone())
            .map_err(|e| format!("{}: setup: {e}", p.display()))?;
        let shard = (v["shard"][0].as_u64(), v["shard"][1].as_u64());
        match &setup {
            None => setup = Some(s),
            Some(s0) if *s0 != s => {
                return Err(format!(
                    "{}: a different run (setup differs from {}'s)",
                    d.display(),
                    dirs[0].display()
                ));
            }
            _ => {}
        }
        shards.push(shard);
        rows.extend(read_samples(d)?);
    }
    let setup = setup.ok_or("merge: no directories")?;
    rows.sort_by_key(|r| r.index);
    for (k, r) in rows.iter().enumerate() {
        if r.index != k as u64 {
            return Err(format!(
                "merge: sample {} is {} (shards {shards:?})",
                k,
                if r.index > k as u64 {
                    "missing"
                } else {
                    "duplicated"
                }
            ));
        }
    }
    if rows.len() as u64 != setup.samples {
        return Err(format!(
            "merge: {} of {} samples present (shards {shards:?})",
            rows.len(),
            setup.samples
        ));
    }
    let dir = out.map_or_else(|| default_out(&setup.experiment), Path::to_path_buf);
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    finish(&dir, &setup, &rows, None)
}
