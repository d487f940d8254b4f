//! The C examples compile against the generated header with the system C
//! compiler, link the static library this build made, and pass their own
//! checks: a hover command, and NaN/∞ in every float input refused with a
//! status and the output untouched (`hover.c`); both filters converging
//! from a wrong start on a hover's IMU and motion capture, and the law
//! flying on the estimate (`estimate.c`).

use std::path::{Path, PathBuf};
use std::process::Command;

/// The profile directory this test binary was built into
/// (`target/<profile>/deps/<test>` → `target/<profile>`), where cargo put
/// the `geopid_control` example, `libgeopid_control.a`, under `examples/`.
fn profile_dir() -> PathBuf {
    let exe = std::env::current_exe().expect("test binary path");
    exe.parent()
        .and_then(Path::parent)
        .expect("target/<profile>")
        .to_path_buf()
}

#[test]
fn c_example_builds_and_passes_its_checks() {
    build_and_run("hover");
}

#[test]
fn c_estimation_example_builds_and_passes_its_checks() {
    build_and_run("estimate");
}

fn build_and_run(name: &str) {
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lib = profile_dir().join("examples/libgeopid_control.a");
    assert!(
        lib.exists(),
        "static library not built at {}",
        lib.display()
    );
    let out = std::env::temp_dir().join(format!("gpc-{name}-{}", std::process::id()));
    let cc = std::env::var("CC").unwrap_or_else(|_| "cc".into());
    let status = Command::new(&cc)
        .args([
            "-std=c11",
            "-Wall",
            "-Wextra",
            "-Wpedantic",
            "-Werror",
            "-O1",
        ])
        .arg("-I")
        .arg(dir.join("include"))
        .arg(dir.join(format!("examples/c/{name}.c")))
        .arg(&lib)
        .args(["-lm", "-lpthread", "-ldl", "-o"])
        .arg(&out)
        .status()
        .unwrap_or_else(|e| panic!("cannot run the C compiler `{cc}`: {e}"));
    assert!(status.success(), "the C example did not compile");
    let run = Command::new(&out).output().expect("run the C example");
    let _ = std::fs::remove_file(&out);
    let stdout = String::from_utf8_lossy(&run.stdout);
    print!("{stdout}");
    assert!(
        run.status.success(),
        "the C example's checks failed:\n{stdout}"
    );
    assert!(stdout.contains("0 failures"), "{stdout}");
}
