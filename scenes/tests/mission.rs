//! A whole flight from the ground and back (`mission-takeoff-waypoints-land`):
//! it lifts off, flies its loop, lands under its touchdown bound and comes
//! to rest on its feet; a landing too fast ends the run as a crash; bad
//! phase settings are refused naming the key.

use scenarios::Termination;
use scenes::builtin;
use scenes::scene::Scene;

/// The deepest foot below the ground in a sample, m (negative: above).
fn depth(s: &Scene, sample: &scenarios::Sample) -> f64 {
    let g = s.ground.as_ref().unwrap();
    g.feet(s.vehicle.arm)
        .iter()
        .map(|p| {
            let r = sample.r[2];
            sample.x[2] + r[0] * p[0] + r[1] * p[1] + r[2] * p[2] - g.height
        })
        .fold(f64::NEG_INFINITY, f64::max)
}

#[test]
fn the_mission_lands_under_its_bound_and_never_sinks_a_millimetre() {
    let mut s = builtin::mission_takeoff_waypoints_land();
    // Every 0.1 ms: the contact's heave period is 8.6 ms, so the deepest
    // sample is within 0.1 % of the deepest point.
    s.record.sample = 1e-4;
    let out = scenes::run(&s, Default::default()).unwrap();
    assert_eq!(out.termination, Termination::Completed);
    let names: Vec<_> = out.switches.iter().map(|w| out.mode_names[w.to]).collect();
    assert_eq!(names, ["position", "land", "motors-off"]);

    // Lift-off: the four feet let go early in the take-off, before the
    // climb has reached its peak speed (2.5 s in).
    let (ups, downs): (Vec<&scenarios::ContactChange>, Vec<_>) =
        out.contacts.iter().partition(|c| !c.pushing);
    let first_ups: Vec<_> = ups.iter().filter(|c| c.t < 6.0).collect();
    assert_eq!(first_ups.len(), 4, "{:?}", out.contacts);
    assert!(first_ups.iter().all(|c| c.t < 2.5), "{first_ups:?}");

    // Touchdown: level, the four feet touch within a few nanoseconds of
    // one another, and the motors are cut where the last one does (both
    // located on the same crossing); the first comes down at the descent
    // rate, and no foot faster than the scene's crash speed.
    let cut = out.switches[2].t;
    let first = downs.first().unwrap();
    let fourth = downs[3];
    assert!(fourth.t - first.t < 1e-6, "{downs:?}");
    assert!(
        (fourth.t - cut).abs() < 1e-9,
        "touchdown {} cut {cut}",
        fourth.t
    );
    assert!(
        (first.normal_speed - 0.3).abs() < 3e-3,
        "{}",
        first.normal_speed
    );
    let bound = s.ground.as_ref().unwrap().crash_speed;
    let fastest = downs.iter().map(|c| c.normal_speed).fold(0.0, f64::max);
    assert!(fastest < bound, "fastest touchdown {fastest} m/s");

    // Penetration under 1 mm throughout (the undamped bound v √(m/4k) at
    // 0.3 m/s is 0.41 mm).
    let deepest = out
        .samples
        .iter()
        .map(|x| depth(&s, x))
        .fold(f64::NEG_INFINITY, f64::max);
    assert!(deepest < 1e-3, "deepest {deepest:e} m");

    // At rest on its feet at the end: every foot carries mg/4k, level.
    let last = out.samples.last().unwrap();
    let still = last
        .v
        .iter()
        .chain(&last.omega)
        .fold(0.0f64, |a, c| a.max(c.abs()));
    assert!(still < 1e-9, "still moving {still:e}");
    let rest = s.vehicle.mass * s.vehicle.gravity / (4.0 * s.ground.as_ref().unwrap().stiffness);
    assert!((depth(&s, last) - rest).abs() < 1e-6, "{}", depth(&s, last));
    let e_i = out
        .samples
        .iter()
        .find(|x| x.t >= 6.0)
        .map(|x| x.e_pos)
        .unwrap();
    let ex = out.samples.iter().filter(|x| (6.0..13.0).contains(&x.t));
    let (n, sq) = ex.fold((0, 0.0), |(n, sq), x| (n + 1, sq + x.ex * x.ex));
    eprintln!(
        "mission: lift-offs {:?} s, e_i at 6 s {e_i:?}, loop RMS ‖e_x‖ {:.3} mm, \
         touchdown {:.4} m/s at {:.4} s, deepest {:.3} mm",
        first_ups.iter().map(|c| c.t).collect::<Vec<_>>(),
        1e3 * (sq / n as f64).sqrt(),
        first.normal_speed,
        first.t,
        1e3 * deepest
    );
}

#[test]
fn under_the_paper_s_disturbances_it_lands_tilted_and_cuts_on_the_last_foot() {
    // Δ_x pushes sideways: the vehicle hovers tilted by about 4°, so one
    // foot touches first. The motors are cut when the last foot is down,
    // after the landing law has pivoted the vehicle onto them; cut at the
    // first foot it would drop onto the others at 0.84 m/s.
    let mut s = builtin::mission_takeoff_waypoints_land();
    s.disturbance = Some(scenes::scene::DisturbanceSpec::paper());
    let out = scenes::run(&s, Default::default()).unwrap();
    assert_eq!(out.termination, Termination::Completed);
    let cut = out.switches[2].t;
    let downs: Vec<_> = out.contacts.iter().filter(|c| c.pushing).collect();
    let first = downs[0];
    assert!(cut - first.t > 1e-3, "one foot first: {downs:?}");
    assert!(
        downs.iter().any(|c| (c.t - cut).abs() < 1e-9),
        "cut on a touchdown"
    );
    let fastest = downs.iter().map(|c| c.normal_speed).fold(0.0, f64::max);
    assert!(
        fastest < s.ground.as_ref().unwrap().crash_speed,
        "{downs:?}"
    );
    eprintln!(
        "disturbed mission: first foot {:.4} s, last {cut:.4} s, fastest {fastest:.3} m/s",
        first.t
    );
}

#[test]
fn a_landing_faster_than_the_bound_is_a_crash() {
    let mut s = builtin::mission_takeoff_waypoints_land();
    s.plan[2].rate = Some(0.8);
    let out = scenes::run(&s, Default::default()).unwrap();
    let Termination::Crashed { t, point, speed } = out.termination else {
        panic!("{:?}", out.termination);
    };
    // The descent's 0.8 m/s, above the scene's 0.5: the run ends at the
    // located touchdown, its last sample there.
    assert!((speed - 0.8).abs() < 0.01, "{speed}");
    assert!(point < 4);
    assert_eq!(out.samples.last().unwrap().t, t);
    assert_eq!(out.contacts.last().unwrap().t, t);
    let text = scenes::RunReport::new(&s, &out).to_string();
    assert!(text.contains("crashed: foot"), "{text}");
}

fn with_plan(plan: &str) -> Result<Scene, scenes::SceneError> {
    let text = format!(
        "format = 1\nname = \"phases\"\nduration = 2.0\n[ground]\n[integrator]\nkind = \"rk4\"\n{plan}"
    );
    Scene::from_toml(&text, "phases.toml")
}

#[test]
fn bad_phase_settings_name_their_key() {
    let cases = [
        (
            "[[plan]]\nmode = \"take-off\"\nheight = -1.0\nuntil = 1.0\n[[plan]]\nmode = \"hover\"",
            "height",
            "-1",
        ),
        (
            "[[plan]]\nmode = \"land\"\nrate = nan\nuntil_clearance = 0.0\n[[plan]]\nmode = \"motors-off\"",
            "rate",
            "NaN",
        ),
        ("[[plan]]\nmode = \"land\"\nramp = 0.0", "ramp", "0"),
        (
            "[[plan]]\nmode = \"hover\"\nheight = 1.0",
            "height",
            "does not apply to `hover`",
        ),
        (
            "[[plan]]\nmode = \"take-off\"\n[plan.position]\nkind = \"hold\"\nx = [0.0, 0.0, -1.0]\nb1d = [1.0, 0.0, 0.0]",
            "mode",
            "takes no reference",
        ),
        (
            "[[plan]]\nmode = \"land\"\nuntil_clearance = -0.1\n[[plan]]\nmode = \"motors-off\"",
            "until_clearance",
            "-0.1",
        ),
        (
            "[[plan]]\nmode = \"land\"\nuntil_clearance = 0.0",
            "until_clearance",
            "last segment",
        ),
        (
            "[[plan]]\nmode = \"land\"\nuntil_clearance = 0.0\nuntil = 1.0\n[[plan]]\nmode = \"motors-off\"",
            "until_clearance",
            "give one",
        ),
    ];
    for (plan, key, says) in cases {
        let e = with_plan(plan).unwrap_err();
        assert!(
            e.key.as_deref().is_some_and(|k| k.ends_with(key)) && e.message.contains(says),
            "{plan}: {e}"
        );
    }
    // No ground to measure the clearance from.
    let text = "format = 1\nname = \"x\"\nduration = 1.0\n[[plan]]\nmode = \"land\"\n\
                until_clearance = 0.0\n[[plan]]\nmode = \"motors-off\"";
    let e = Scene::from_toml(text, "x.toml").unwrap_err();
    assert!(e.message.contains("[ground]"), "{e}");
}
