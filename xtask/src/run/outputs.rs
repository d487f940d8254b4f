//! Where `cargo xtask run` writes: every output path checked before the
//! run starts.

use std::path::{Path, PathBuf};

use scenarios::output;

/// Checks the output paths before anything runs, so that no bad path is
/// found only after the run: each is a new file in an existing, writable
/// directory, a regular file (replaced when the run ends) or a stream
/// (`/dev/null`, a pipe: written in place); never a directory, a dangling
/// link, the scene file (also through a symlink), or both outputs at once.
/// The `--plot` directory is created now and must be writable.
pub fn check_outputs(
    csv: Option<&Path>,
    mcap: Option<&Path>,
    plot: Option<&Path>,
    scene_file: Option<&Path>,
) -> Result<(), String> {
    // The absolute form of a path: itself canonicalised when it exists
    // (through any symlink), else its directory canonicalised and its name.
    // `None` for a stream: two outputs to `/dev/null` are fine, and a pipe
    // behind `/dev/stdout` has no path to compare.
    let resolve = |opt: &str, p: &Path| -> Result<Option<PathBuf>, String> {
        let kind = output::classify_output(p).map_err(|e| format!("{opt}: {e}"))?;
        if kind == output::PathKind::Stream {
            return Ok(None);
        }
        let name = p
            .file_name()
            .ok_or_else(|| format!("{opt} {}: not a file name", p.display()))?;
        let dir = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => PathBuf::from("."),
        };
        let dir = dir
            .canonicalize()
            .map_err(|e| format!("{opt} {}: directory {}: {e}", p.display(), dir.display()))?;
        probe_writable(&dir).map_err(|e| format!("{opt} {}: {e}", p.display()))?;
        if kind == output::PathKind::Regular {
            return p
                .canonicalize()
                .map(Some)
                .map_err(|e| format!("{opt} {}: {e}", p.display()));
        }
        Ok(Some(dir.join(name)))
    };
    let c = csv.map(|p| resolve("--csv", p)).transpose()?.flatten();
    let m = mcap.map(|p| resolve("--mcap", p)).transpose()?.flatten();
    if let (Some(c), Some(m)) = (&c, &m)
        && c == m
    {
        return Err(format!(
            "--csv and --mcap are the same file ({}): one would overwrite the other",
            c.display()
        ));
    }
    if let Some(scene) = scene_file.and_then(|s| s.canonicalize().ok()) {
        for (opt, p) in [("--csv", &c), ("--mcap", &m)] {
            if p.as_ref() == Some(&scene) {
                return Err(format!(
                    "{opt} {} is the scene file itself",
                    scene.display()
                ));
            }
        }
    }
    if let Some(dir) = plot {
        if dir.exists() && !dir.is_dir() {
            return Err(format!(
                "--plot {}: exists and is not a directory",
                dir.display()
            ));
        }
        std::fs::create_dir_all(dir).map_err(|e| format!("--plot {}: {e}", dir.display()))?;
        probe_writable(dir).map_err(|e| format!("--plot {}: {e}", dir.display()))?;
    }
    Ok(())
}

/// Creates and removes a probe file in `dir`: permission bits alone do not
/// tell (root ignores them, a read-only mount does not show in them).
pub(super) fn probe_writable(dir: &Path) -> Result<(), String> {
    let probe = dir.join(format!(".gpid-write-probe-{}", std::process::id()));
    std::fs::write(&probe, b"").map_err(|e| format!("cannot write in {}: {e}", dir.display()))?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// Whether `p` is the file behind this process's standard output (the
/// same device and inode), e.g. `/dev/stdout` or `/proc/self/fd/1`.
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
        let csv = dir.join("a.csv");
        let mcap = dir.join("a.mcap");
        assert!(check_outputs(Some(&csv), Some(&mcap), None, None).is_ok());
        // Same file twice, spelled differently.
        let same = dir.join(".").join("a.csv");
        let e = check_outputs(Some(&csv), Some(&same), None, None).unwrap_err();
        assert!(e.contains("same file"), "{e}");
        // A missing directory is named with the option.
        let e =
            check_outputs(Some(&dir.join("nodir").join("x.csv")), None, None, None).unwrap_err();
        assert!(e.starts_with("--csv") && e.contains("nodir"), "{e}");
        // The scene file is not an output.
        let scene = dir.join("s.toml");
        std::fs::write(&scene, "x").unwrap();
        let e = check_outputs(None, Some(&scene), None, Some(&scene)).unwrap_err();
        assert!(e.contains("scene file"), "{e}");
        // ... nor through a symlink to it.
        std::os::unix::fs::symlink(&scene, dir.join("link.csv")).unwrap();
        let e = check_outputs(Some(&dir.join("link.csv")), None, None, Some(&scene)).unwrap_err();
        assert!(e.starts_with("--csv") && e.contains("scene file"), "{e}");
        // A directory is not an output file.
        let e = check_outputs(None, Some(&dir), None, None).unwrap_err();
        assert!(
            e.starts_with("--mcap") && e.contains("is a directory"),
            "{e}"
        );
        // Two streams to the same sink are fine (`/dev/null` twice).
        let null = std::path::Path::new("/dev/null");
        assert!(check_outputs(Some(null), Some(null), None, None).is_ok());
        // --plot: a file in the way, or a place that cannot be created.
        let e = check_outputs(None, None, Some(&scene), None).unwrap_err();
        assert!(
            e.starts_with("--plot") && e.contains("not a directory"),
            "{e}"
        );
        let e = check_outputs(None, None, Some(Path::new("/proc/gpid-figs")), None).unwrap_err();
        assert!(e.starts_with("--plot"), "{e}");
        std::fs::remove_dir_all(&dir).ok();
    }
}
