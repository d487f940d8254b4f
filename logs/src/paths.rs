//! Output paths checked before a run starts, so that no bad path is found
//! only after an hour of simulation.

use std::path::{Path, PathBuf};

use super::{PathKind, classify_output};

/// An output path that cannot be used, naming the setting it came from
/// (`--csv`, `csv`, …) and the path.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct PathError {
    /// The setting that named the path, as the caller spells it.
    pub field: String,
    /// The path as given.
    pub path: PathBuf,
    /// Why it cannot be used.
    pub message: String,
}

impl std::fmt::Display for PathError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} {}: {}",
            self.field,
            self.path.display(),
            self.message
        )
    }
}

impl std::error::Error for PathError {}

fn fail(field: &str, path: &Path, message: impl std::fmt::Display) -> PathError {
    PathError {
        field: field.to_string(),
        path: path.to_path_buf(),
        message: message.to_string(),
    }
}

/// Checks output files and an output directory before anything runs.
///
/// Each file given (`(field, Some(path))`; `None`, an output not asked
/// for, is skipped) must be a new file in an existing, writable
/// directory, a regular file (replaced when the run ends) or a stream
/// (`/dev/null`, a pipe: written in place); never a directory, a dangling
/// link, the `input` file (also through a symlink), or the same file as
/// another output. The directory (`--plot`, say) is created now and must
/// be writable. Writability is tried with a probe file: permission bits
/// alone do not tell (root ignores them, a read-only mount does not show
/// in them).
///
/// ```
/// use std::path::Path;
/// let dir = std::env::temp_dir();
/// let (csv, mcap) = (dir.join("run.csv"), dir.join(".").join("run.csv"));
/// let files = [("csv", Some(csv.as_path())), ("mcap", Some(mcap.as_path()))];
/// let e = logs::check_paths(&files, None, None)
///     .unwrap_err();
/// assert_eq!(e.field, "mcap");
/// assert!(e.message.contains("same file as csv"));
/// ```
pub fn check_paths(
    files: &[(&str, Option<&Path>)],
    dir: Option<(&str, &Path)>,
    input: Option<&Path>,
) -> Result<(), PathError> {
    let input = input.and_then(|s| s.canonicalize().ok());
    let mut seen: Vec<(&str, PathBuf)> = Vec::new();
    for &(field, p) in files {
        let Some(p) = p else {
            continue;
        };
        // Two outputs to `/dev/null` are fine, and a pipe behind
        // `/dev/stdout` has no path to compare.
        let Some(abs) = resolve(field, p)? else {
            continue;
        };
        if let Some((other, _)) = seen.iter().find(|(_, q)| *q == abs) {
            return Err(fail(
                field,
                p,
                format!(
                    "the same file as {other} ({}): one would overwrite the other",
                    abs.display()
                ),
            ));
        }
        if input.as_ref() == Some(&abs) {
            return Err(fail(field, p, "is the input file itself"));
        }
        seen.push((field, abs));
    }
    if let Some((field, d)) = dir {
        if d.exists() && !d.is_dir() {
            return Err(fail(field, d, "exists and is not a directory"));
        }
        std::fs::create_dir_all(d).map_err(|e| fail(field, d, e))?;
        probe_writable(d).map_err(|e| fail(field, d, e))?;
    }
    Ok(())
}

/// The absolute form of an output path: itself canonicalised when it
/// exists (through any symlink), else its directory canonicalised and its
/// name; `None` for a stream.
fn resolve(field: &str, p: &Path) -> Result<Option<PathBuf>, PathError> {
    let kind = classify_output(p).map_err(|e| fail(field, p, e.message))?;
    if kind == PathKind::Stream {
        return Ok(None);
    }
    let name = p
        .file_name()
        .ok_or_else(|| fail(field, p, "not a file name"))?;
    let dir = match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let dir = dir
        .canonicalize()
        .map_err(|e| fail(field, p, format!("directory {}: {e}", dir.display())))?;
    probe_writable(&dir).map_err(|e| fail(field, p, e))?;
    if kind == PathKind::Regular {
        return p.canonicalize().map(Some).map_err(|e| fail(field, p, e));
    }
    Ok(Some(dir.join(name)))
}

/// Creates and removes a probe file in `dir`.
fn probe_writable(dir: &Path) -> Result<(), String> {
    let probe = dir.join(format!(".gpid-write-probe-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(|e| format!("cannot write in {}: {e}", dir.display()))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// Whether `p` is the file behind this process's standard output (the
/// same device and inode), e.g. `/dev/stdout` or `/proc/self/fd/1`: a
/// report printed beside such an output belongs on standard error.
pub fn is_stdout(p: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (std::fs::metadata(p), std::fs::metadata("/proc/self/fd/1")) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn output_paths_are_checked_before_running() {
        let dir = std::env::temp_dir().join(format!("gpid-run-paths-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (csv, mcap) = (dir.join("a.csv"), dir.join("a.mcap"));
        let check = |files: &[(&str, &Path)], plot: Option<&Path>, input: Option<&Path>| {
            let files: Vec<_> = files.iter().map(|&(f, p)| (f, Some(p))).collect();
            check_paths(&files, plot.map(|p| ("--plot", p)), input)
        };
        assert!(check(&[("--csv", &csv), ("--mcap", &mcap)], None, None).is_ok());
        // Same file twice, spelled differently.
        let same = dir.join(".").join("a.csv");
        let e = check(&[("--csv", &csv), ("--mcap", &same)], None, None).unwrap_err();
        assert!(
            e.field == "--mcap" && e.message.contains("same file as --csv"),
            "{e}"
        );
        // A missing directory is named with the setting.
        let e = check(&[("--csv", &dir.join("nodir").join("x.csv"))], None, None).unwrap_err();
        assert!(e.field == "--csv" && e.to_string().contains("nodir"), "{e}");
        // The input file is not an output ...
        let scene = dir.join("s.toml");
        std::fs::write(&scene, "x").unwrap();
        let e = check(&[("--mcap", &scene)], None, Some(&scene)).unwrap_err();
        assert!(e.message.contains("input file"), "{e}");
        // ... nor through a symlink to it.
        std::os::unix::fs::symlink(&scene, dir.join("link.csv")).unwrap();
        let e = check(&[("--csv", &dir.join("link.csv"))], None, Some(&scene)).unwrap_err();
        assert!(
            e.field == "--csv" && e.message.contains("input file"),
            "{e}"
        );
        // A directory is not an output file.
        let e = check(&[("--mcap", &dir)], None, None).unwrap_err();
        assert!(
            e.field == "--mcap" && e.message.contains("is a directory"),
            "{e}"
        );
        // Two streams to the same sink are fine (`/dev/null` twice).
        let null = Path::new("/dev/null");
        assert!(check(&[("--csv", null), ("--mcap", null)], None, None).is_ok());
        // The directory: a file in the way, or a place that cannot be created.
        let e = check(&[], Some(&scene), None).unwrap_err();
        assert!(
            e.field == "--plot" && e.message.contains("not a directory"),
            "{e}"
        );
        let e = check(&[], Some(Path::new("/proc/gpid-figs")), None).unwrap_err();
        assert_eq!(e.field, "--plot");
        std::fs::remove_dir_all(&dir).ok();
    }
}
