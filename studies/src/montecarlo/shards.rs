//! A run split into shards (`i mod N = K`) and merged back: what a cluster
//! job array writes, one directory per shard, and what its merge reads.
//!
//! A shard's directory holds `run.toml` (the [`Setup`] and `[K, N]`) and
//! its rows of `samples.csv`. Every sample is keyed by (seed, index), so the
//! merged rows equal one run's, byte for byte; [`merge`] refuses shards of
//! different runs, a missing or duplicated sample and a short count, each
//! naming what it found. Files are written to `<name>.partial` and renamed:
//! a job killed mid-write leaves no truncated file for the merge to read.

use std::fmt;
use std::path::{Path, PathBuf};
use std::str::FromStr;

use super::{Outcome, Setup, parse_samples, write_samples as samples_text};

/// Which samples a shard runs: indices `i` with `i mod n = k`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub struct Shard {
    /// This shard's residue, `0 ≤ k < n`.
    pub k: u64,
    /// The number of shards.
    pub n: u64,
}

impl Shard {
    /// The whole run as one shard.
    pub const WHOLE: Shard = Shard { k: 0, n: 1 };

    /// The shard's indices among `0 … samples−1`, ascending.
    pub fn indices(self, samples: u64) -> Vec<u64> {
        (self.k..samples).step_by(self.n as usize).collect()
    }
}

impl FromStr for Shard {
    type Err = ShardError;

    /// `K/N` with `0 ≤ K < N`.
    fn from_str(s: &str) -> Result<Self, ShardError> {
        let bad = || ShardError::Spec(s.to_owned());
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k = k.trim().parse::<u64>().map_err(|_| bad())?;
        let n = n.trim().parse::<u64>().map_err(|_| bad())?;
        if n == 0 || k >= n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

/// Why shards could not be written or merged.
#[derive(Debug)]
pub enum ShardError {
    /// A shard given as text that is not `K/N` with `0 ≤ K < N`.
    Spec(String),
    /// Reading or writing a file.
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: std::io::Error,
    },
    /// A `run.toml` or `samples.csv` that does not parse.
    Parse {
        /// The file.
        path: PathBuf,
        /// What is wrong, with its line where known.
        message: String,
    },
    /// No directories to merge.
    Empty,
    /// A shard of another run: its setup differs from the first shard's.
    DifferentRun {
        /// The shard that differs.
        dir: PathBuf,
        /// The first shard.
        first: PathBuf,
    },
    /// Sample `index` is absent (or present twice) in the shards read.
    Gap {
        /// The sample missing or repeated.
        index: u64,
        /// `true`: a duplicate; `false`: missing.
        duplicated: bool,
        /// The shards read, as `(K, N)`.
        shards: Vec<(u64, u64)>,
    },
    /// Fewer samples than the run has.
    Short {
        /// Samples present.
        present: u64,
        /// Samples of the run.
        expected: u64,
        /// The shards read, as `(K, N)`.
        shards: Vec<(u64, u64)>,
    },
}

impl fmt::Display for ShardError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ShardError::Spec(s) => write!(f, "shard {s:?}: expected K/N with 0 ≤ K < N"),
            ShardError::Io { path, source } => write!(f, "{}: {source}", path.display()),
            ShardError::Parse { path, message } => write!(f, "{}: {message}", path.display()),
            ShardError::Empty => write!(f, "merge: no directories"),
            ShardError::DifferentRun { dir, first } => write!(
                f,
                "{}: a different run (setup differs from {}'s)",
                dir.display(),
                first.display()
            ),
            ShardError::Gap {
                index,
                duplicated,
                shards,
            } => write!(
                f,
                "merge: sample {index} is {} (shards {shards:?})",
                if *duplicated { "duplicated" } else { "missing" }
            ),
            ShardError::Short {
                present,
                expected,
                shards,
            } => write!(
                f,
                "merge: {present} of {expected} samples present (shards {shards:?})"
            ),
        }
    }
}

impl std::error::Error for ShardError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            ShardError::Io { source, .. } => Some(source),
            _ => None,
        }
    }
}

/// Writes `<path>.partial`, then renames it over `path`.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), ShardError> {
    let io = |source| ShardError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut tmp = path.as_os_str().to_os_string();
    tmp.push(".partial");
    std::fs::write(&tmp, bytes).map_err(io)?;
    std::fs::rename(&tmp, path).map_err(io)
}

/// `dir/samples.csv`.
pub fn write_samples(dir: &Path, rows: &[Outcome]) -> Result<(), ShardError> {
    write_atomic(&dir.join("samples.csv"), samples_text(rows).as_bytes())
}

#[derive(serde::Serialize, serde::Deserialize)]
struct RunFile {
    shard: Shard,
    setup: Setup,
}

/// `dir/run.toml`: the setup and the shard, what [`merge`] checks.
pub fn write_run(dir: &Path, setup: &Setup, shard: Shard) -> Result<(), ShardError> {
    let text = toml::to_string(&RunFile {
        shard,
        setup: setup.clone(),
    })
    .map_err(|e| ShardError::Parse {
        path: dir.join("run.toml"),
        message: e.to_string(),
    })?;
    write_atomic(&dir.join("run.toml"), text.as_bytes())
}

/// A shard's directory: `run.toml` and its rows of `samples.csv`.
pub fn write_shard(
    dir: &Path,
    setup: &Setup,
    shard: Shard,
    rows: &[Outcome],
) -> Result<(), ShardError> {
    write_run(dir, setup, shard)?;
    write_samples(dir, rows)
}

fn read(path: &Path) -> Result<String, ShardError> {
    std::fs::read_to_string(path).map_err(|source| ShardError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// A shard directory's setup, shard and rows.
pub fn read_shard(dir: &Path) -> Result<(Setup, Shard, Vec<Outcome>), ShardError> {
    let parse = |path: PathBuf| move |message: String| ShardError::Parse { path, message };
    let run = dir.join("run.toml");
    let file: RunFile = toml::from_str(&read(&run)?).map_err(|e| parse(run)(e.to_string()))?;
    let samples = dir.join("samples.csv");
    let rows = parse_samples(&read(&samples)?).map_err(parse(samples))?;
    Ok((file.setup, file.shard, rows))
}

/// The shards in `dirs` as one run: its setup and every row in index
/// order, or the first inconsistency found.
pub fn merge(dirs: &[PathBuf]) -> Result<(Setup, Vec<Outcome>), ShardError> {
    let first = dirs.first().ok_or(ShardError::Empty)?;
    let mut setup: Option<Setup> = None;
    let mut shards = Vec::new();
    let mut rows = Vec::new();
    for d in dirs {
        let (s, shard, r) = read_shard(d)?;
        match &setup {
            Some(s0) if *s0 != s => {
                return Err(ShardError::DifferentRun {
                    dir: d.clone(),
                    first: first.clone(),
                });
            }
            Some(_) => {}
            None => setup = Some(s),
        }
        shards.push((shard.k, shard.n));
        rows.extend(r);
    }
    let setup = setup.ok_or(ShardError::Empty)?;
    rows.sort_by_key(|r| r.index);
    for (k, r) in (0u64..).zip(&rows) {
        if r.index != k {
            // Sorted: an index below its place is a repeat of the one
            // before; above it, the place's index is absent.
            return Err(ShardError::Gap {
                index: r.index.min(k),
                duplicated: r.index < k,
                shards,
            });
        }
    }
    if rows.len() as u64 != setup.samples {
        return Err(ShardError::Short {
            present: rows.len() as u64,
            expected: setup.samples,
            shards,
        });
    }
    Ok((setup, rows))
}
