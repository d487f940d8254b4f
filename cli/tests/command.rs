//! The `geopid` binary as a user meets it: its subcommands, its exit
//! statuses, and a run's CSV against the library's own writer.

use std::path::PathBuf;
use std::process::{Command, Output};

fn geopid(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_geopid"))
        .args(args)
        .output()
        .expect("the geopid binary starts")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("geopid-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

#[test]
fn help_lists_every_subcommand() {
    let out = geopid(&["--help"]);
    assert!(out.status.success());
    let help = String::from_utf8(out.stdout).unwrap();
    for sub in ["run", "scenes", "gains", "montecarlo", "tune", "sweep"] {
        assert!(
            help.lines().any(|l| l.trim_start().starts_with(sub)),
            "`geopid --help` lacks `{sub}`:\n{help}"
        );
    }
}

#[test]
fn scenes_lists_the_built_ins_one_a_line() {
    let out = geopid(&["scenes"]);
    assert!(out.status.success());
    let names: Vec<String> = scenes::builtin::all()
        .iter()
        .map(|s| s.name.clone())
        .collect();
    let listed: Vec<String> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(str::to_string)
        .collect();
    assert_eq!(listed, names);
}

#[test]
fn a_bad_scene_or_value_exits_2_naming_it() {
    let out = geopid(&["run", "no-such-scene"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("no scene `no-such-scene`"), "{err}");

    let out = geopid(&["run", "paper-flip", "--dt", "-1"]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("integrator.dt = -1"), "{err}");
}

#[test]
fn the_same_file_twice_is_refused_before_the_run() {
    let p = scratch("twice.csv");
    let p = p.to_str().unwrap();
    let out = geopid(&["run", "paper-flip", "--csv", p, "--mcap", p]);
    assert_eq!(out.status.code(), Some(2));
    let err = String::from_utf8(out.stderr).unwrap();
    assert!(err.contains("--mcap") && err.contains("same file"), "{err}");
}

#[test]
fn a_run_writes_the_bytes_the_library_writes() {
    let streamed = scratch("flip-cli.csv");
    let out = geopid(&[
        "run",
        "paper-flip",
        "--duration",
        "1",
        "--csv",
        streamed.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary = String::from_utf8(out.stdout).unwrap();
    assert!(
        summary.contains("wrote") && summary.contains("rows"),
        "{summary}"
    );

    let mut scene = scenes::load("paper-flip").unwrap();
    scene.duration = 1.0;
    let run = scenes::run(&scene, Default::default()).unwrap();
    let whole = scratch("flip-lib.csv");
    logs::write_csv(&whole, &run).unwrap();
    assert!(
        std::fs::read(&streamed).unwrap() == std::fs::read(&whole).unwrap(),
        "the command's CSV differs from write_csv's"
    );
}

#[test]
fn a_mission_s_figures_draw_its_path_and_the_report_names_its_phases() {
    let dir = scratch("mission-figures");
    let out = geopid(&[
        "run",
        "mission-takeoff-waypoints-land",
        "--plot",
        dir.to_str().unwrap(),
    ]);
    let text = String::from_utf8_lossy(&out.stdout);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    // The switches by name, and the touchdown with its speed.
    assert!(
        text.contains("switches: position at 6.000 s, land at 13.000 s, motors-off at"),
        "{text}"
    );
    assert!(text.contains("fastest touchdown 0.300 m/s"), "{text}");
    // The top view: the flown path (one blue line) and the reference
    // (red, drawn dash by dash: about a hundred over the loop's 7 m).
    let svg = std::fs::read_to_string(dir.join("path.svg")).unwrap();
    assert!(svg.contains("flown") && svg.contains("reference"));
    assert!(svg.matches("stroke=\"#1F77B4\"").count() >= 2, "{svg}");
    assert!(svg.matches("stroke=\"#D62728\"").count() > 50, "{svg}");
    // A run whose reference never moves draws no path.
    let still = scratch("hover-figures");
    let out = geopid(&[
        "run",
        "hover-disturbed",
        "--duration",
        "1",
        "--plot",
        still.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    assert!(!still.join("path.svg").exists());
}
