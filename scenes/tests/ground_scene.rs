//! `[ground]` in a scene file: the vehicle rests on it, and bad numbers or
//! a stepper that cannot step the contact are refused naming the key.

use scenes::scene::Scene;

fn scene(extra: &str) -> Result<Scene, scenes::SceneError> {
    let text = format!(
        "format = 1\nname = \"grounded\"\nduration = 2.0\n[initial]\nx = [0.0, 0.0, -0.1]\n{extra}\n"
    );
    Scene::from_toml(&text, "grounded.toml")
}

#[test]
fn a_vehicle_dropped_on_a_scene_ground_rests_on_its_feet() {
    // Default feet 0.1 m below the centre of mass: started with them
    // touching, the idle vehicle sinks to the resting depth mg/(4k) and
    // stays, level.
    let s = scene("[ground]\nheight = 0.0").unwrap();
    let out = scenes::run(&s, Default::default()).unwrap();
    let last = out.samples.last().unwrap();
    let (m, g) = (s.vehicle.mass, s.vehicle.gravity);
    let depth = m * g / (4.0 * s.ground.as_ref().unwrap().stiffness);
    // Settled to rounding after 2 s at ζ ≈ 0.73.
    assert!((last.x[2] + 0.1 - depth).abs() < 1e-9, "{:?}", last.x);
    assert!(
        last.x[0].abs() < 1e-12 && last.x[1].abs() < 1e-12,
        "{:?}",
        last.x
    );
    // Without the ground it falls freely: ½ g t² = 19.6 m in 2 s.
    let free = scenes::run(&scene("").unwrap(), Default::default()).unwrap();
    assert!(free.samples.last().unwrap().x[2] > 19.0);
}

#[test]
fn bad_ground_settings_name_the_key() {
    let e = scene("[ground]\nstiffness = -1.0").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("ground.stiffness"), "{e}");
    assert!(e.message.contains("-1"), "{e}");
    let e = scene("[ground]\nfeet = [[0.0, 0.0, nan]]").unwrap_err();
    assert_eq!(e.key.as_deref(), Some("ground.feet"), "{e}");
    for kind in ["euler", "lgvi"] {
        let e = scene(&format!("[ground]\n[integrator]\nkind = \"{kind}\"")).unwrap_err();
        assert_eq!(e.key.as_deref(), Some("integrator.kind"), "{e}");
        assert!(e.message.contains(kind) && e.message.contains("rk4"), "{e}");
    }
}

/// A take-off from the ground: position mode holding 1 m up lifts the
/// vehicle off its feet; the four lift-offs are located, at the same
/// times whatever the recording, and it arrives.
#[test]
fn a_take_off_locates_the_lift_off_whatever_the_recording() {
    let text = "[ground]\n[[plan]]\nmode = \"position\"\n[plan.position]\nkind = \"hold\"\n\
                x = [0.0, 0.0, -1.0]\nb1d = [1.0, 0.0, 0.0]";
    let mut s = scene(text).unwrap();
    s.duration = 6.0;
    // Resting on its feet at the start.
    let k = s.ground.as_ref().unwrap().stiffness;
    s.initial.x[2] = -0.1 + s.vehicle.mass * s.vehicle.gravity / (4.0 * k);
    let out = scenes::run(&s, Default::default()).unwrap();
    s.record.sample = 0.37;
    let sparse = scenes::run(&s, Default::default()).unwrap();
    assert_eq!(out.contacts, sparse.contacts);
    let off: Vec<_> = out.contacts.iter().filter(|c| !c.pushing).collect();
    assert!(off.len() >= 4, "{:?}", out.contacts);
    // Lifted off within the first half second, and none pushes at the end.
    println!(
        "lift-off at {:.6} s, {} contact changes",
        off[0].t,
        out.contacts.len()
    );
    assert!(off[0].t < 0.5, "{:?}", off[0]);
    let last = out.samples.last().unwrap();
    assert!((last.x[2] + 1.0).abs() < 0.05, "{:?}", last.x);
}
