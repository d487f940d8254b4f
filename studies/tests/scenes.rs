//! Scenes as data: TOML round trips, errors that name key, value and
//! position, exact landing on sample and switch times, paying only for what
//! a scene uses.

use scenarios::RunOptions;
use scenes::scene::{BackendKind, Scalar};
use scenes::{Scene, builtin, load, run};

#[test]
fn every_builtin_round_trips_through_toml() {
    for s in builtin::all() {
        let text = s.to_toml();
        let back = Scene::from_toml(&text, "roundtrip.toml")
            .unwrap_or_else(|e| panic!("{}: {e}\n{text}", s.name));
        assert_eq!(back, s, "{}", s.name);
    }
}

#[test]
fn the_shipped_scene_file_is_the_builtin_flip() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/scenes/paper-flip.toml"
    );
    let s = load(path).unwrap();
    assert_eq!(s, builtin::paper_flip());
}

#[test]
fn the_shipped_wind_scene_file_is_the_builtin_gusty_hover() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/scenes/gusty-hover.toml"
    );
    assert_eq!(load(path).unwrap(), builtin::gusty_hover());
}

#[test]
fn a_multirotor_scene_takes_any_rotor_layout() {
    let six: Vec<String> = (0..6)
        .map(|k| {
            let a = k as f64 * std::f64::consts::PI / 3.0;
            format!("[{}, {}, 0.0]", 0.043 * a.cos(), 0.043 * a.sin())
        })
        .collect();
    let layout = format!(
        "[vehicle.multirotor]\npreset = \"crazyflie\"\nrotor_positions = [{}]\n\
         rotor_directions = [1.0, -1.0, 1.0, -1.0, 1.0, -1.0]\n",
        six.join(", ")
    );
    let text = builtin::gusty_hover()
        .to_toml()
        .replace("[vehicle.multirotor]\npreset = \"crazyflie\"\n", &layout)
        .replace("duration = 20.0", "duration = 5.0");
    let scene = Scene::from_toml(&text, "six.toml").unwrap();
    let out = scenes::run(&scene, scenarios::RunOptions::default()).unwrap();
    // Six rotor speeds, and the point held in the gusts.
    assert_eq!(out.last.vehicle_states.len(), 6);
    assert!(out.last.ex < 0.2, "{}", out.last.ex);
    let bad = text.replace(
        "rotor_directions = [1.0, -1.0, 1.0, -1.0, 1.0, -1.0]",
        "rotor_directions = [1.0, -1.0]",
    );
    let e = Scene::from_toml(&bad, "bad.toml").unwrap_err();
    assert_eq!(
        e.key.as_deref(),
        Some("vehicle.multirotor.rotor_directions"),
        "{e}"
    );
}

#[test]
fn unknown_key_names_key_and_position() {
    let text = "name = \"x\"\nduration = 1.0\n[integrator]\nkind = \"rk4\"\nstep = 0.01\n";
    let e = Scene::from_toml(text, "bad.toml").unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("step"), "{msg}");
    assert!(msg.starts_with("bad.toml:5:"), "{msg}");
}

#[test]
fn bad_values_name_key_value_and_position() {
    let text = "name = \"x\"\nduration = 1.0\n[integrator]\nkind = \"rk4\"\ndt = -0.5\n";
    let msg = Scene::from_toml(text, "bad.toml").unwrap_err().to_string();
    assert!(msg.contains("`integrator.dt` = -0.5"), "{msg}");
    assert!(msg.starts_with("bad.toml:5:"), "{msg}");
    // Keys are found in their own table: the integrator's `kind`, not the
    // vehicle's above it (both are `kind = …` at the start of a line).
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/scenes/paper-flip.toml"
    ))
    .unwrap()
    .replace("kind = \"rk4\"", "kind = \"rk5\"");
    let line = 1 + text
        .lines()
        .position(|l| l.starts_with("kind = \"rk5\""))
        .unwrap();
    let msg = Scene::from_toml(&text, "copy.toml")
        .unwrap_err()
        .to_string();
    assert!(
        msg.starts_with(&format!("copy.toml:{line}:")),
        "{msg} (line {line})"
    );
    assert!(
        line > 20,
        "the integrator's table is not the first in the file"
    );
    let text = "name = \"x\"\nduration = 1.0\n[integrator]\nkind = \"rk5\"\n";
    let msg = Scene::from_toml(text, "bad.toml").unwrap_err().to_string();
    assert!(
        msg.contains("rk5") && msg.starts_with("bad.toml:4:"),
        "{msg}"
    );
    let text = "name = \"x\"\nduration = \"long\"\n";
    let msg = Scene::from_toml(text, "bad.toml").unwrap_err().to_string();
    assert!(
        msg.starts_with("bad.toml:2:") && msg.contains("invalid type"),
        "{msg}"
    );
    let e = load("no-such-scene").unwrap_err().to_string();
    assert!(e.contains("paper-flip"), "lists the built-ins: {e}");
}

#[test]
fn samples_land_exactly_on_the_grid_and_the_switch() {
    let mut s = builtin::paper_flip();
    s.duration = 1.0;
    s.integrator.dt = 3e-4; // does not divide 2 ms or 0.4 s
    let out = run(&s, RunOptions::default()).unwrap();
    for (k, smp) in out.samples.iter().enumerate() {
        assert_eq!(smp.t, k as f64 * 0.002, "sample {k}");
    }
    assert_eq!(out.switches.len(), 1);
    assert_eq!(out.switches[0].t, 0.4);
}

#[test]
fn an_attitude_only_scene_never_touches_translation_and_recording_is_optional() {
    let s = builtin::paper_attitude_experiment();
    let out = run(&s, RunOptions::default()).unwrap();
    assert!(
        out.samples
            .iter()
            .all(|x| x.x == [0.0; 3] && x.v == [0.0; 3] && x.ex == 0.0)
    );
    let quiet = run(
        &s,
        RunOptions {
            record: false,
            ..Default::default()
        },
    )
    .unwrap();
    assert!(quiet.samples.is_empty());
    // The same final state, bit for bit, whether or not samples were
    // recorded: samples never move the steps.
    assert_eq!(quiet.last, out.last);
}

/// The same scene on every other (backend, scalar) pair follows the
/// f64/nalgebra run: glam-f64 to rounding (measured: identical, the same
/// operations in the same order; bound 1e-12), the f32 pairs to f32
/// rounding amplified by the closed loop over 4 s (measured 1.0e-5 in R;
/// bound 10× that).
#[test]
fn f32_glam_follows_f64_nalgebra() {
    let a = builtin::paper_flip();
    let ra = run(&a, RunOptions::default()).unwrap();
    for (scalar, backend, bound) in [
        (Scalar::F64, BackendKind::Glam, 1e-12),
        (Scalar::F32, BackendKind::Nalgebra, 1e-4),
        (Scalar::F32, BackendKind::Glam, 1e-4),
    ] {
        let mut b = a.clone();
        b.scalar = scalar;
        b.backend = backend;
        let rb = run(&b, RunOptions::default()).unwrap();
        let studies::metrics::Difference {
            x: dx,
            r: dr,
            compared: n,
            ..
        } = studies::metrics::max_difference(&ra.samples, &rb.samples);
        println!(
            "paper-flip {scalar:?}/{backend:?} vs f64/nalgebra over {n} samples: max|Δx| {dx:.2e}, max|ΔR| {dr:.2e}"
        );
        assert!(
            dx < bound && dr < bound,
            "{scalar:?}/{backend:?}: {dx:.2e} {dr:.2e}"
        );
    }
}

/// Sampled control holds the command between controller samples (zero-order
/// hold), and at a high rate it approaches continuous control: the ZOH
/// delay is O(1/rate), so 10 kHz stays within ~1e-3 of continuous over the
/// flip (measured, see the assertion message).
#[test]
fn sampled_control_holds_between_samples_and_converges_to_continuous() {
    let mut s = builtin::paper_flip();
    s.duration = 1.0;
    let cont = run(&s, RunOptions::default()).unwrap();
    s.control.timing = scenes::scene::Timing::Sampled;
    s.control.rate = 100.0;
    let slow = run(&s, RunOptions::default()).unwrap();
    // Within each 10 ms window (5 samples at 2 ms) the thrust is constant.
    for w in slow.samples.chunks(5) {
        let t0 = w[0].t;
        if (t0 / 0.01 - (t0 / 0.01).round()).abs() < 1e-9 {
            for x in &w[1..] {
                if x.t < t0 + 0.01 - 1e-9 && (x.t - 0.4).abs() > 1e-9 {
                    assert_eq!(x.thrust, w[0].thrust, "t = {}", x.t);
                }
            }
        }
    }
    s.control.rate = 10_000.0;
    let fast = run(&s, RunOptions::default()).unwrap();
    let studies::metrics::Difference { x: dx, r: dr, .. } =
        studies::metrics::max_difference(&fast.samples, &cont.samples);
    let studies::metrics::Difference { x: dx_slow, .. } =
        studies::metrics::max_difference(&slow.samples, &cont.samples);
    println!(
        "sampled 10 kHz vs continuous: max|Δx| {dx:.2e}, max|ΔR| {dr:.2e}; 100 Hz: max|Δx| {dx_slow:.2e}"
    );
    // Measured 3.3e-4 and 4.4e-4: bounds 3× and 23×.
    assert!(dx < 1e-3 && dr < 1e-2, "{dx:.2e} {dr:.2e}");
    // The hold's error is first order in the period: 100× the period,
    // ~100× the deviation (measured 97). From both sides: a hold whose
    // error did not scale with the period, or scaled with its square,
    // lands outside.
    let ratio = dx_slow / dx;
    assert!(
        ratio > 50.0 && ratio < 200.0,
        "100 Hz / 10 kHz deviation {ratio:.1}"
    );
}

/// A vehicle swap through the trait: the hexarotor with the paper's mass
/// and inertia and no rotor limits produces the same body wrench, so the
/// flip is the same trajectory (to rounding of the allocation round trip);
/// its six rotor thrusts sum to the commanded thrust.
#[test]
fn hexarotor_flies_the_same_flip() {
    let quad = builtin::paper_flip();
    let mut hex = quad.clone();
    hex.vehicle.kind = scenes::scene::VehicleKind::Hexarotor;
    let (a, b) = (
        run(&quad, RunOptions::default()).unwrap(),
        run(&hex, RunOptions::default()).unwrap(),
    );
    let studies::metrics::Difference { x: dx, r: dr, .. } =
        studies::metrics::max_difference(&a.samples, &b.samples);
    assert!(
        dx == 0.0 && dr == 0.0,
        "the body dynamics do not depend on the rotor layout: {dx:e} {dr:e}"
    );
    let s = &b.samples[500];
    assert_eq!(s.rotors.len(), 6);
    assert!((s.rotors.iter().sum::<f64>() - s.thrust).abs() < 1e-12);
}

/// f32 Dormand–Prince reaches what f32 can deliver: tolerance 2e-7 gives
/// 9e-7 on paper-flip against f64 dopri 1e-12 (the first tolerance floor,
/// 100 ε = 1.2e-5, silently capped every tolerance at an error of 5e-5),
/// and a tolerance below ε is reported, not silently raised.
#[test]
fn f32_dopri_reaches_the_scalar_floor_and_warns_below_it() {
    let mut base = builtin::paper_flip();
    base.integrator.kind = "dopri".into();
    // One dopri call per 0.1 s sample: its own step control inside.
    base.integrator.dt = 0.1;
    base.record.sample = 0.1;
    let mut reference = base.clone();
    reference.integrator.tol = 1e-12;
    let reference = run(&reference, RunOptions::default()).unwrap();
    assert!(reference.warnings.is_empty());
    let mut s = base.clone();
    s.scalar = Scalar::F32;
    s.backend = BackendKind::Glam;
    s.integrator.tol = 2e-7;
    let out = run(&s, RunOptions::default()).unwrap();
    let studies::metrics::Difference { x: dx, r: dr, .. } =
        studies::metrics::max_difference(&out.samples, &reference.samples);
    println!("f32 dopri tol 2e-7 vs f64 dopri 1e-12: |Δx| {dx:.2e}, |ΔR| {dr:.2e}");
    // 2× the measured 9.2e-7 (rounding of f32 states over ~200
    // substeps); 25× below what the old floor allowed.
    assert!(dx.max(dr) < 2e-6, "{dx} {dr}");
    assert!(out.warnings.is_empty());
    s.integrator.tol = 1e-10;
    let low = run(&s, RunOptions::default()).unwrap();
    assert_eq!(low.warnings.len(), 1);
    assert!(low.warnings[0].contains("1e-10") && low.warnings[0].contains("f32"));
}

/// Samples come from the steps' continuous extension, so a record grid
/// finer than `dt` leaves the steps at `dt` (it used to shorten them to the
/// sample interval: `--dt 0.032` on paper-flip's 2 ms samples ran 2006
/// steps of 2 ms). Control instants change the command, so the steps still
/// land on them, and a control grid finer than `dt` is a warning.
#[test]
fn a_sample_grid_finer_than_dt_is_a_warning() {
    let mut s = builtin::paper_flip();
    s.duration = 0.1;
    // The flip alone: its 0.4 s segment would outlast the run (a warning
    // of its own).
    s.plan.truncate(1);
    s.plan[0].until = None;
    s.integrator.dt = 0.01;
    s.record.sample = 0.002;
    let out = scenes::run(&s, Default::default()).unwrap();
    assert_eq!(out.steps, 10, "10 ms steps whatever the sampling");
    assert_eq!(out.samples.len(), 51, "every 2 ms sample, and t = 0");
    assert!(out.warnings.is_empty(), "{:?}", out.warnings);
    // Sampled control at 500 Hz caps the steps the same way.
    s.record.sample = 0.05;
    s.control.timing = scenes::scene::Timing::Sampled;
    s.control.rate = 500.0;
    let out = scenes::run(&s, Default::default()).unwrap();
    assert!(
        out.warnings.iter().any(|w| w.contains("control instant")),
        "{:?}",
        out.warnings
    );
    // A grid no finer than dt: no warning.
    s.control.timing = scenes::scene::Timing::Continuous;
    s.integrator.dt = 0.002;
    let out = scenes::run(&s, Default::default()).unwrap();
    assert!(out.warnings.is_empty(), "{:?}", out.warnings);
}

/// What a file may not say although TOML and the types allow it: principal
/// moments no rigid body has, a zero sample interval, a key an attitude
/// reference does not have. Each is an error at its line.
#[test]
fn impossible_or_meaningless_values_are_rejected_at_their_line() {
    let flip = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenes/scenes/paper-flip.toml"
    ))
    .unwrap();
    let line_of = |text: &str, start: &str| {
        1 + text
            .lines()
            .position(|l| l.trim_start().starts_with(start))
            .unwrap()
    };
    // J3 > J1 + J2 without the paper's explicit opt-in.
    let text = flip
        .replace(
            "inertia = [0.43e-2, 0.43e-2, 1.02e-2]",
            "inertia = [1.0, 1.0, 3.0]",
        )
        .replace("allow_nonphysical_inertia = true", "");
    let e = Scene::from_toml(&text, "j.toml").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("vehicle.inertia"));
    assert!(
        e.message.contains("J3 = 3") && e.message.contains("(2)"),
        "{e}"
    );
    let line = line_of(&text, "inertia =");
    assert!(e.to_string().starts_with(&format!("j.toml:{line}:")), "{e}");
    // The paper's own J needs the opt-in too, and says so.
    let text = flip.replace("allow_nonphysical_inertia = true", "");
    let e = Scene::from_toml(&text, "j.toml").unwrap_err();
    assert!(e.message.contains("allow_nonphysical_inertia"), "{e}");
    // A physical body is fine without it.
    let text = text.replace(
        "inertia = [0.43e-2, 0.43e-2, 1.02e-2]",
        "inertia = [0.6e-2, 0.6e-2, 1.02e-2]",
    );
    assert!(Scene::from_toml(&text, "j.toml").is_ok());
    // sample = 0 (the command line refuses --sample 0 too).
    let text = flip.replace("sample = 0.002", "sample = 0");
    assert_ne!(text, flip);
    let e = Scene::from_toml(&text, "s.toml").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("record.sample"));
    assert!(
        e.to_string()
            .starts_with(&format!("s.toml:{}:", line_of(&text, "sample ="))),
        "{e}"
    );
    // An unknown key beside `kind = "paper-flip"`, as beside `kind = "hold"`.
    let text = flip.replace(
        "attitude = { kind = \"paper-flip\" }",
        "attitude = { kind = \"paper-flip\", speed = 2.0 }",
    );
    assert_ne!(text, flip);
    let e = Scene::from_toml(&text, "k.toml").unwrap_err();
    assert!(e.message.contains("speed"), "{e}");
    assert!(
        e.to_string()
            .starts_with(&format!("k.toml:{}:", line_of(&text, "attitude ="))),
        "{e}"
    );
}

/// A segment that lasts past the end of the run leaves the next unused:
/// the run says so (a shortened `duration` is legitimate, so it is a
/// warning, not an error).
#[test]
fn a_segment_past_the_end_is_a_warning() {
    let mut s = builtin::paper_flip();
    s.plan[0].until = Some(10.0);
    let out = run(&s, RunOptions::default()).unwrap();
    assert_eq!(out.switches.len(), 0);
    assert!(
        out.warnings
            .iter()
            .any(|w| w.contains("segment 1 (position)") && w.contains("never run")),
        "{:?}",
        out.warnings
    );
}

/// `to_toml` is infallible and round-trips: every built-in scene, a scene
/// with non-finite numbers (written as `nan`/`inf`) and one with a
/// registered kind's parameters.
#[test]
fn every_scene_serialises() {
    for s in builtin::all() {
        let text = s.to_toml();
        assert_eq!(Scene::from_toml(&text, "rt.toml").unwrap(), s, "{}", s.name);
    }
    let mut odd = builtin::paper_flip();
    odd.initial.omega = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
    let text = odd.to_toml();
    assert!(text.contains("nan") && text.contains("inf"), "{text}");
    let mut custom = builtin::hover_disturbed();
    custom.vehicle.kind = scenes::scene::VehicleKind::Custom("heavy".into());
    custom.vehicle.params.insert("payload kg".into(), 0.2);
    let back = Scene::from_toml_with_kinds(&custom.to_toml(), "c.toml", &["heavy"]).unwrap();
    assert_eq!(back, custom);
}

/// The scene format: `format = 1` reads; a newer format is refused naming
/// the version; a value that is not the integer 1 is refused naming the key
/// and the value; a file without the key runs as format 1 with a note in
/// the run's warnings (and nowhere else); a scene written out says
/// `format = 1`.
#[test]
fn the_scene_format_is_checked_and_written() {
    let body = "name = \"x\"\nduration = 0.02\n[integrator]\nkind = \"rk4\"\ndt = 0.01\n";
    let with = |f: &str| format!("format = {f}\n{body}");
    let scene = Scene::from_toml(&with("1"), "ok.toml").unwrap();
    assert_eq!(scene.format, Some(scenes::scene::SCENE_FORMAT));
    let out = run(&scene, RunOptions::default()).unwrap();
    assert!(out.warnings.is_empty(), "{:?}", out.warnings);

    let msg = Scene::from_toml(&with("2"), "new.toml")
        .unwrap_err()
        .to_string();
    assert!(
        msg.starts_with("new.toml:1:") && msg.contains("format = 2") && msg.contains("newer"),
        "{msg}"
    );
    for (value, shown) in [
        ("0", "format = 0"),
        ("\"1\"", "format = \"1\""),
        ("1.5", "format = 1.5"),
        ("-3", "format = -3"),
    ] {
        let msg = Scene::from_toml(&with(value), "bad.toml")
            .unwrap_err()
            .to_string();
        assert!(
            msg.starts_with("bad.toml:1:")
                && msg.contains(shown)
                && msg.contains("expected the integer 1"),
            "{value}: {msg}"
        );
    }

    let old = Scene::from_toml(body, "old.toml").unwrap();
    assert_eq!(old.format, None);
    let out = run(&old, RunOptions::default()).unwrap();
    assert_eq!(
        out.warnings,
        vec![scenes::scene::missing_format_note()],
        "the missing key is a note in the run's warnings"
    );
    assert!(
        old.to_toml().starts_with("format = 1\n"),
        "{}",
        old.to_toml()
    );
    for s in builtin::all() {
        assert!(s.to_toml().starts_with("format = 1\n"), "{}", s.name);
        assert_eq!(Scene::from_toml(&s.to_toml(), "rt.toml").unwrap(), s);
    }
}

/// A scene whose step count is beyond a limit is refused before anything
/// runs, naming the key, the count and the time it would take; every
/// built-in is within the command line's limit of 10⁹ steps.
#[test]
fn a_runaway_step_count_is_refused_naming_duration() {
    for s in builtin::all() {
        assert!(s.check_size(1e9).is_ok(), "{}", s.name);
    }
    let mut s = builtin::paper_flip();
    s.duration = 1e12;
    let e = s.check_size(1e9).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("duration"));
    assert!(
        e.message
            .contains(&format!("{:.2e} steps", 1e12 / s.integrator.dt))
            && e.message.contains("years"),
        "{e}"
    );
    s.duration = 3600.0;
    s.integrator.dt = 1e-7;
    let e = s.check_size(1e9).unwrap_err();
    assert!(e.message.contains("hours"), "{e}");
    assert!(s.check_size(1e11).is_ok());
}
