//! Planned references in scene files: each bad input is refused when the
//! scene is read, with the key, the waypoint or line, and the value.

use scenes::scene::Scene;

fn scene(position: &str) -> Result<Scene, scenes::SceneError> {
    let text = format!(
        "format = 1\nname = \"planned\"\nduration = 1.0\n[[plan]]\nmode = \"position\"\n\
         [plan.position]\n{position}\n"
    );
    Scene::from_toml(&text, "planned.toml")
}

fn refused(position: &str, key: &str, words: &[&str]) {
    let e = scene(position).expect_err(position);
    assert_eq!(e.key.as_deref(), Some(key), "{e}");
    for w in words {
        assert!(e.message.contains(w), "`{w}` not in: {e}");
    }
    // Located in the file: the reader points at the key's line.
    assert!(e.location.is_some(), "{e}");
}

#[test]
fn a_good_minsnap_reference_reads_and_flies_its_waypoints() {
    let s = scene(
        "kind = \"minsnap\"\nwaypoints = [[0.0, 0.0, -1.0], [1.0, 0.0, -1.0]]\nmean_speed = 0.5",
    )
    .unwrap();
    let p = s.plan[0].position.as_ref().unwrap();
    let (d, _) = scenes::reference::position_f64(p, 2.0);
    // 1 m at 0.5 m/s: at the second waypoint, at rest, at t = 2 s (the
    // planner's end conditions; rounding only).
    assert!(
        (d[0][0] - 1.0).abs() < 1e-12 && d[1][0].abs() < 1e-12,
        "{d:?}"
    );
}

#[test]
fn bad_minsnap_references_name_the_field() {
    let wp = "waypoints = [[0.0, 0.0, -1.0], [1.0, nan, -1.0]]";
    refused(
        &format!("kind = \"minsnap\"\n{wp}"),
        "waypoints",
        &["waypoints[1].y", "NaN"],
    );
    refused(
        "kind = \"minsnap\"\nwaypoints = [[0.0, 0.0, -1.0]]",
        "waypoints",
        &["at least two"],
    );
    let two = "waypoints = [[0.0, 0.0, -1.0], [1.0, 0.0, -1.0]]";
    refused(
        &format!("kind = \"minsnap\"\n{two}\ntimes = [0.0, 2.0]\nmean_speed = 1.0"),
        "times",
        &["at most one of `times`, `mean_speed` and `time_budget`"],
    );
    refused(
        &format!("kind = \"minsnap\"\n{two}\ntimes = [0.0, 0.0]"),
        "times",
        &["times[1]", "0"],
    );
    refused(
        &format!("kind = \"minsnap\"\n{two}\nyaw = [0.0]"),
        "yaw",
        &["one yaw per waypoint (2)"],
    );
    refused(
        &format!("kind = \"minsnap\"\n{two}\nmean_speed = -1.0"),
        "mean_speed",
        &["mean_speed", "-1"],
    );
    refused(
        &format!("kind = \"minsnap\"\n{two}\nstart = nan"),
        "start",
        &["start", "NaN"],
    );
    let same = "waypoints = [[0.0, 0.0, -1.0], [0.0, 0.0, -1.0]]";
    refused(
        &format!("kind = \"minsnap\"\n{same}"),
        "waypoints",
        &["waypoints[1]"],
    );
}

#[test]
fn bad_trajectory_files_name_the_file_and_the_line() {
    refused(
        "kind = \"trajectory-file\"\npath = \"/nonexistent/geopid/traj.csv\"",
        "path",
        &["/nonexistent/geopid/traj.csv"],
    );
    let dir = std::env::temp_dir().join(format!("geopid-planned-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("bad.csv");
    let header = missions::pptraj::columns().join(",");
    let mut row = vec!["1.0".to_string(); 33];
    row[9] = "x".into();
    std::fs::write(&file, format!("{header}\n{}\n", row.join(","))).unwrap();
    let e = scene(&format!(
        "kind = \"trajectory-file\"\npath = \"{}\"",
        file.display()
    ))
    .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("path"), "{e}");
    assert!(
        e.message.contains("line 2") && e.message.contains("y^0"),
        "{e}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
