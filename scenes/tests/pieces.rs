//! A run advanced in pieces is the run advanced in one call, bit for bit:
//! pausing never moves the step grid.

use lie::GlamF64;
use scenarios::{RunOutput, Termination};
use scenes::{Scene, builtin};

const STEPPERS: [(&str, f64); 6] = [
    ("lgvi", 1e-3),
    ("rk4", 1e-3),
    ("rk4-projected", 1e-3),
    ("rkmk4", 1e-3),
    ("euler", 1e-4),
    ("dopri", 1e-2),
];

/// The paper's flip (a time switch at 0.4 s, sat′ crossings after it) and
/// the tumble recovery (a switch when Ψ drops below 0.1).
fn scenes(kind: &str, dt: f64) -> Vec<Scene> {
    let mut flip = builtin::paper_flip();
    flip.duration = 1.5;
    let mut tumble = builtin::tumble_recovery();
    tumble.duration = 2.0;
    let mut out = vec![flip, tumble];
    for s in &mut out {
        s.backend = scenes::scene::BackendKind::Glam;
        s.integrator.kind = kind.into();
        s.integrator.dt = dt;
        s.integrator.tol = 1e-9;
        s.record.sample = 0.0017;
    }
    out
}

fn in_pieces(scene: &Scene, pieces: usize) -> RunOutput {
    let mut sim = scenes::builder::<GlamF64>(scene).unwrap().build().unwrap();
    for k in 1..=pieces {
        let t = scene.duration * k as f64 / pieces as f64;
        sim.advance_to(t).unwrap();
        assert!(sim.time() <= t + 1e-9, "{} > {t}", sim.time());
    }
    assert_eq!(sim.termination(), Some(Termination::Completed));
    sim.finish().unwrap()
}

#[test]
fn any_number_of_pieces_gives_the_same_run() {
    let (mut events, mut psi_switches) = (0, 0);
    for (kind, dt) in STEPPERS {
        for scene in scenes(kind, dt) {
            let one = scenes::run_generic::<GlamF64>(&scene, Default::default()).unwrap();
            events += one.events;
            if scene.plan.iter().any(|s| s.until_psi.is_some()) {
                psi_switches += one.switches.len();
            }
            for pieces in [1, 7, 1000] {
                let p = in_pieces(&scene, pieces);
                let what = format!("{} {kind} in {pieces} pieces", scene.name);
                assert_eq!(p.samples.len(), one.samples.len(), "{what}");
                for (a, b) in p.samples.iter().zip(&one.samples) {
                    assert_eq!(a, b, "{what}: sample at t = {}", b.t);
                }
                assert_eq!(p.last, one.last, "{what}");
                assert_eq!(
                    (p.steps, p.evaluations, p.events, &p.switches),
                    (one.steps, one.evaluations, one.events, &one.switches),
                    "{what}"
                );
                assert_eq!(p.event_times, one.event_times, "{what}");
                assert_eq!(
                    (p.max_thrust, p.max_rotor, p.psi_range),
                    (one.max_thrust, one.max_rotor, one.psi_range),
                    "{what}"
                );
            }
        }
    }
    // The pieces did cut through what the test is about.
    assert!(events >= 12, "{events} sat′ crossings over the steppers");
    assert!(
        psi_switches >= 6,
        "{psi_switches} Ψ switches over the steppers"
    );
}

/// A perturbation between two pieces takes effect from there on, and a
/// run finished early says where.
#[test]
fn a_perturbed_run_resumes_from_the_changed_state() {
    let mut scene = builtin::hover_disturbed();
    scene.backend = scenes::scene::BackendKind::Glam;
    scene.duration = 4.0;
    let calm = scenes::run_generic::<GlamF64>(&scene, Default::default()).unwrap();
    let mut sim = scenes::builder::<GlamF64>(&scene).unwrap().build().unwrap();
    sim.advance_to(1.0).unwrap();
    let t = sim.time();
    assert!((t - 1.0).abs() < 1e-12, "{t}");
    let before = sim.state().body.omega;
    sim.state_mut().body.omega = before + glam::DVec3::new(4.0, 0.0, 0.0);
    // One step later (1 ms; the law damps Ω at about 100 /s) most of the
    // 4 rad/s added about b1 is still there.
    sim.advance_to(t + 1e-3).unwrap();
    let w = sim.state().body.omega;
    assert!(w.x - before.x > 3.0, "Ω₁ {} from {}", w.x, before.x);
    sim.advance_to(1.2).unwrap();
    let after = |o: &[scenarios::Sample]| o.iter().find(|s| s.t > t).unwrap().omega[0];
    let (kicked, calm_then) = (after(&sim.output().samples), after(&calm.samples));
    assert!(kicked != calm_then, "Ω₁ {kicked} vs {calm_then}");
    let out = sim.finish().unwrap();
    let Termination::Interrupted { t: end } = out.termination else {
        panic!("{:?}", out.termination)
    };
    // The last sample is the record instant the run paused on, labelled
    // k·0.01 (which may differ from the step's end in the last bit).
    assert!((end - 1.2).abs() < 1e-12 && (out.last.t - end).abs() < 1e-12);
    assert!(out.samples.iter().all(|s| s.t <= out.last.t));
}

/// Pausing backwards does nothing, a NaN time is an error naming the call,
/// and a time past the duration stops at the end.
#[test]
fn advance_to_edges() {
    let mut scene = builtin::hover_disturbed();
    scene.backend = scenes::scene::BackendKind::Glam;
    scene.duration = 0.5;
    let mut sim = scenes::builder::<GlamF64>(&scene).unwrap().build().unwrap();
    assert_eq!(sim.time(), 0.0);
    assert_eq!(sim.termination(), None);
    sim.advance_to(0.2).unwrap();
    let t = sim.time();
    sim.advance_to(0.1).unwrap();
    assert_eq!(sim.time(), t, "a pause in the past does not move the run");
    match sim.advance_to(f64::NAN) {
        Err(scenarios::SimError::Setting { field, .. }) => assert_eq!(field, "advance_to"),
        other => panic!("{other:?}"),
    }
    sim.advance_to(1e9).unwrap();
    assert_eq!(sim.time(), 0.5);
    assert_eq!(sim.termination(), Some(Termination::Completed));
    let out = sim.finish().unwrap();
    assert_eq!(out.last.t, 0.5);
}

/// The divergence guard ends a run at the located instant a limit is
/// passed: a kick of 6 rad/s against a 5 rad/s limit on |Ω| ends it at
/// once, with the value that passed.
#[test]
fn the_guard_ends_a_run_where_a_limit_is_passed() {
    let mut scene = builtin::hover_disturbed();
    scene.backend = scenes::scene::BackendKind::Glam;
    scene.initial.omega = [0.0, 0.0, 4.0];
    let guard = scenarios::DivergenceGuard {
        omega: Some(5.0),
        ..Default::default()
    };
    let mut sim = scenes::builder::<GlamF64>(&scene)
        .unwrap()
        .guard(guard)
        .build()
        .unwrap();
    sim.advance_to(0.1).unwrap();
    assert_eq!(sim.termination(), None, "4 rad/s is under the limit");
    sim.state_mut().body.omega = glam::DVec3::new(0.0, 0.0, 6.0);
    sim.advance_to(0.2).unwrap();
    match sim.termination() {
        Some(Termination::Diverged {
            what: scenarios::Divergence::Omega(w),
            t,
        }) => {
            assert!(w > 5.0 && w < 6.0 + 1e-9, "|Ω| = {w}");
            // Located inside the first step after the kick.
            assert!(t > 0.1 && t <= 0.1 + 1e-3 + 1e-12, "t = {t}");
        }
        other => panic!("{other:?}"),
    }
    let out = sim.finish().unwrap();
    assert!(out.diverged().is_some());
    let bad = scenes::builder::<GlamF64>(&scene)
        .unwrap()
        .guard(scenarios::DivergenceGuard {
            omega: Some(-1.0),
            ..Default::default()
        })
        .build();
    assert!(matches!(
        bad,
        Err(scenarios::SimError::Setting { field: "guard", .. })
    ));
}
