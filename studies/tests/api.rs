//! The simulation API from the outside: closures as references give the
//! scene's results, bad settings are errors naming the field and value,
//! registered vehicle kinds are the only custom ones a scene may name.
//!
//! One pair (nalgebra-f64): these test the API's plumbing (closures as
//! references, builder errors, registration), which is the same generic
//! code on every pair; a scene on all four pairs is
//! `scenes::f32_glam_follows_f64_nalgebra`, and a registered kind is built
//! on all four by `Registry::vehicle`.

use controllers::{
    AccelerationModel, AttitudeGains, PositionGains, PositionMode, PositionReference,
    RigidBodyParams,
};
use dynamics::paper;
use dynamics::{Quadrotor, RigidBodyState, Vehicle};
use lie::{Backend, NalgebraF64, Real};
use scenarios::{SimError, Simulation, Until};
use scenes::reference::{derivative_mismatch, position_f64};
use scenes::scene::PositionRef;
use scenes::{FactoryError, Registry, Scene, VehicleFactory, builtin};

type B = NalgebraF64;

/// The figure-eight scene's reference rewritten by hand as a closure.
fn eight(t: f64) -> PositionReference<B> {
    let (a, b, w) = (1.0, 0.5, 1.0);
    let (s1, c1) = (w * t).sin_cos();
    let w2 = 2.0 * w;
    let (s2, c2) = (w2 * t).sin_cos();
    let v = |x: f64, y: f64, z: f64| B::vec3(x, y, z);
    let mut r = PositionReference::hold(v(a * s1, b * s2, -1.0), v(1.0, 0.0, 0.0));
    r.v = v(a * w * c1, b * w2 * c2, 0.0);
    r.a = v(-a * w * w * s1, -b * w2 * w2 * s2, 0.0);
    r.jerk = v(-a * w.powi(3) * c1, -b * w2.powi(3) * c2, 0.0);
    r.snap = v(a * w.powi(4) * s1, b * w2.powi(4) * s2, 0.0);
    r
}

#[test]
fn a_closure_reference_flies_exactly_as_the_scene_reference() {
    let scene = builtin::figure_eight();
    let from_scene = scenes::run(&scene, Default::default()).unwrap();
    let g = &scene.gains;
    let params = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let mut pg = PositionGains::<B>::uniform(g.k_x, g.k_v, g.k_i, g.c1, g.sigma);
    pg.clamp_integral = g.clamp_integral;
    let ag = AttitudeGains::<B>::uniform(g.k_r, g.k_omega, g.k_att_i, g.c2);
    let mut start = RigidBodyState::<B>::at_rest();
    start.x = B::vec3(0.0, 0.0, -1.0);
    let quad = Quadrotor::<B>::paper()
        .with_disturbance(Quadrotor::<B>::paper_disturbance())
        .unwrap();
    let out = Simulation::<B>::builder(Box::new(quad))
        .mode(
            PositionMode::new(params, pg, ag, AccelerationModel::Nominal, eight),
            Until::Never,
        )
        .initial(start)
        .dt(scene.integrator.dt)
        .duration(scene.duration)
        .record_every(scene.record.sample)
        .build()
        .unwrap()
        .run(Default::default())
        .unwrap();
    // Same arithmetic in the same order (the closure is the scene
    // generator's formula), so the runs agree to the bit but for the
    // logged x_d: the scene evaluates it in f64 as the closure does.
    let studies::metrics::Difference {
        x: dx,
        v: dv,
        r: dr,
        compared: n,
    } = studies::metrics::max_difference(&out.samples, &from_scene.samples);
    assert_eq!(n, from_scene.samples.len());
    assert_eq!((dx, dv, dr), (0.0, 0.0, 0.0));
    assert_eq!(out.last.ex, from_scene.last.ex);
    // The scene's generator agrees with the closure, and both pass the
    // derivative check; a wrong snap does not.
    let p = PositionRef::FigureEight {
        center: [0.0, 0.0, -1.0],
        a: 1.0,
        b: 0.5,
        omega: 1.0,
    };
    assert_eq!(
        position_f64(&p, 0.7).0[4],
        B::vec3_to_array(eight(0.7).snap)
    );
    let good = derivative_mismatch(&eight, 0.0, 10.0, 50);
    assert!(good.iter().all(|e| *e < 1e-7), "{good:?}");
    let wrong = |t: f64| {
        let mut r = eight(t);
        r.snap *= 0.5;
        r
    };
    let bad = derivative_mismatch(&wrong, 0.0, 10.0, 50);
    assert!(
        bad[3] > 0.1 && bad[..3].iter().all(|e| *e < 1e-7),
        "{bad:?}"
    );
    // The circle's derivatives too, turning either way.
    for omega in [1.2566, -1.2566] {
        let c = PositionRef::Circle {
            center: [0.0, 0.0, -1.0],
            radius: 1.0,
            omega,
        };
        let f = |t: f64| scenes::reference::position::<B>(&c, t);
        let m = derivative_mismatch(&f, 0.0, 10.0, 50);
        assert!(m.iter().all(|e| *e < 1e-7), "{m:?}");
        let x = position_f64(&c, std::f64::consts::FRAC_PI_2 / omega.abs()).0[0];
        assert!((x[0] - 0.0).abs() < 1e-12 && (x[1] - omega.signum()).abs() < 1e-12);
    }
    // Per-axis sinusoids: DiffTune's circle, its derivatives and its
    // closed form (2(1 − cos t), 2 sin t, 0.1 sin t).
    let s = PositionRef::Sinusoids {
        center: [2.0, 0.0, 0.0],
        amplitude: [2.0, 2.0, 0.1],
        omega: [1.0, 1.0, 1.0],
        phase: [-std::f64::consts::FRAC_PI_2, 0.0, 0.0],
    };
    let f = |t: f64| scenes::reference::position::<B>(&s, t);
    let m = derivative_mismatch(&f, 0.0, 10.0, 50);
    assert!(m.iter().all(|e| *e < 1e-7), "{m:?}");
    for t in [0.0, 0.7, 3.0] {
        let (d, b1d) = position_f64(&s, t);
        let closed = [2.0 * (1.0 - t.cos()), 2.0 * t.sin(), 0.1 * t.sin()];
        assert!(
            // A few ulps of 4: the phase −π/2 is rounded.
            (0..3).all(|i| (d[0][i] - closed[i]).abs() < 4e-15),
            "{:?} vs {closed:?}",
            d[0]
        );
        assert_eq!(b1d, [1.0, 0.0, 0.0]);
    }
}

#[test]
fn bad_settings_name_the_field_and_value() {
    let quad = || Box::new(Quadrotor::<B>::paper()) as Box<dyn Vehicle<B>>;
    let err = |r: Result<_, SimError>| match r {
        Err(e) => e.to_string(),
        Ok(_) => panic!("accepted"),
    };
    let e = err(Simulation::<B>::builder(quad())
        .dt(-1e-3)
        .build()
        .map(|_| ()));
    assert!(e.contains("`dt`") && e.contains("-0.001"), "{e}");
    let e = err(Simulation::<B>::builder(quad())
        .duration(f64::NAN)
        .build()
        .map(|_| ()));
    assert!(e.contains("`duration`") && e.contains("NaN"), "{e}");
    let mut s = RigidBodyState::<B>::at_rest();
    s.omega = B::vec3(0.0, f64::INFINITY, 0.0);
    let e = err(Simulation::<B>::builder(quad())
        .initial(s)
        .build()
        .map(|_| ()));
    assert!(e.contains("`initial`") && e.contains("omega"), "{e}");
    let e = err(Simulation::<B>::builder(quad())
        .control(scenarios::Control::Sampled { rate: 0.0 })
        .build()
        .map(|_| ()));
    assert!(e.contains("`control`") && e.contains("0 Hz"), "{e}");
    // A Ψ switch on the last segment has nothing to switch to.
    let m = PositionMode::new(
        RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        PositionGains::paper(),
        AttitudeGains::paper(),
        AccelerationModel::Nominal,
        eight,
    );
    let e = err(Simulation::<B>::builder(quad())
        .mode(m, Until::PsiBelow(0.1))
        .build()
        .map(|_| ()));
    assert!(e.contains("`plan`") && e.contains("segment 0"), "{e}");
    // Initial integrals beyond the plan's register.
    let e = err(Simulation::<B>::builder(quad())
        .integrals(&[1.0])
        .build()
        .map(|_| ()));
    assert!(e.contains("`integrals`") && e.contains("use 0"), "{e}");
}

struct Heavy;
impl VehicleFactory for Heavy {
    fn build<Bk: Backend>(&self, scene: &Scene) -> Result<Box<dyn Vehicle<Bk>>, FactoryError> {
        let extra = scene.vehicle.params.get("payload").copied().unwrap_or(0.0);
        if extra.is_nan() || extra < 0.0 {
            return Err(format!("`payload` = {extra}: must be ≥ 0 kg").into());
        }
        let q = Quadrotor::<Bk>::paper();
        let l = Bk::Scalar::lit;
        Ok(Box::new(Quadrotor::<Bk>::new(
            q.mass() + l(extra),
            q.inertia(),
            q.gravity(),
            l(scene.vehicle.arm),
            l(scene.vehicle.c_tau_f),
        )?))
    }
}

#[test]
fn scene_files_name_registered_kinds_only() {
    let text = builtin::hover_disturbed().to_toml().replace(
        "kind = \"quadrotor\"",
        "kind = \"heavy\"\nparams = { payload = 0.2 }",
    );
    // Unregistered: an error at the key, listing the kinds.
    let e = Scene::from_toml(&text, "heavy.toml").unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("heavy.toml:") && msg.contains("\"heavy\""),
        "{msg}"
    );
    assert!(msg.contains("quadrotor, pinned-quadrotor"), "{msg}");
    // Registered: it runs, and the factory's own validation reaches the user.
    let reg = Registry::new().vehicle("heavy", Heavy);
    assert_eq!(reg.kinds(), ["heavy"]);
    let mut scene = reg.from_toml(&text, "heavy.toml").unwrap();
    scene.duration = 1.0;
    let out = reg.run(&scene, Default::default()).unwrap();
    assert!(out.last.psi.is_finite());
    scene.vehicle.params.insert("payload".into(), -1.0);
    let e = reg.run(&scene, Default::default()).unwrap_err().to_string();
    assert!(
        e.contains("vehicle `heavy`") && e.contains("`payload` = -1"),
        "{e}"
    );
    // A vehicle error the factory passed on with `?` stays typed: the
    // run's error names the kind and has the vehicle's error as source.
    // (An infinite payload passes the factory's own check; the
    // quadrotor's constructor refuses the infinite mass.)
    scene.vehicle.params.insert("payload".into(), f64::INFINITY);
    let e = reg.run(&scene, Default::default()).unwrap_err();
    assert!(
        matches!(&e, scenes::Error::CustomVehicle { kind, .. } if kind == "heavy"),
        "{e}"
    );
    let source = std::error::Error::source(&e).expect("a source");
    assert!(
        source.downcast_ref::<dynamics::DynamicsError>().is_some(),
        "{source:?}"
    );
    // Built-in kinds take no params.
    let mut s = builtin::paper_flip();
    s.vehicle.params.insert("tau".into(), 0.1);
    let (key, msg) = s.check_kind(&[]).unwrap_err();
    assert_eq!(key, "vehicle.params");
    assert!(msg.contains("quadrotor"), "{msg}");
}

#[test]
fn a_stop_condition_ends_the_run_at_the_located_instant() {
    // Climb from 1 m to a 2 m hover; stop when 1.5 m is first reached.
    let params = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let hold = controllers::HoldPosition(PositionReference::hold(
        B::vec3(0.0, 0.0, -2.0),
        B::vec3(1.0, 0.0, 0.0),
    ));
    let mut start = RigidBodyState::<B>::at_rest();
    start.x = B::vec3(0.0, 0.0, -1.0);
    let out = Simulation::<B>::builder(Box::new(Quadrotor::<B>::paper()))
        .mode(
            PositionMode::new(
                params,
                PositionGains::paper(),
                AttitudeGains::paper(),
                AccelerationModel::Nominal,
                hold,
            ),
            Until::Never,
        )
        .initial(start)
        .duration(10.0)
        .dt(1e-3)
        .record_every(0.01)
        .stop_when(Box::new(|_, body, _| -B::vec3_to_array(body.x)[2] >= 1.5))
        .build()
        .unwrap()
        .run(Default::default())
        .unwrap();
    let tc = out.stopped_at().expect("stopped");
    let last = out.samples.last().unwrap();
    println!("stopped at t = {tc:.12} s, height {:.12} m", -last.x[2]);
    assert_eq!(last.t, tc);
    assert_eq!(out.last.t, tc);
    assert!(tc < 2.0, "{tc}");
    // Bisection to 1e-12 of a 1 ms step: the height is 1.5 m to ~v·1e-15.
    assert!((-last.x[2] - 1.5).abs() < 1e-9, "{}", last.x[2]);
    assert!(out.samples.iter().all(|s| s.t <= tc));
}

/// The health check tells rounding from a fault: Euler at 2 ms on the
/// flip (R off the group by 0.23) is off the group; a run whose Ψ is
/// −3e-11 with R off the group by 8e-11 (one hour of f64 hover) is
/// healthy; beyond that slack Ψ outside [0, 2] is reported; f32 has its
/// own bound.
#[test]
fn health_tells_faults_from_rounding() {
    use scenarios::Health;
    let mut s = scenes::builtin::paper_flip();
    s.integrator.kind = "euler".into();
    s.integrator.dt = 0.002;
    let out = scenes::run(&s, Default::default()).unwrap();
    match out.health()[..] {
        [Health::OffGroup { error, bound }] => assert!(error > 0.1 && bound == 1e-6, "{error}"),
        ref h => panic!("{h:?}"),
    }
    let mut fine = scenes::run(&scenes::builtin::paper_flip(), Default::default()).unwrap();
    assert!(fine.health().is_empty());
    fine.psi_range.min = -2.9e-11;
    fine.max_orthogonality_error = 8e-11;
    assert!(fine.health().is_empty());
    fine.psi_range.min = -1e-9;
    assert!(matches!(fine.health()[..], [Health::PsiOutOfRange { .. }]));
    let mut s32 = scenes::builtin::paper_flip();
    s32.scalar = scenes::scene::Scalar::F32;
    let o32 = scenes::run(&s32, Default::default()).unwrap();
    assert_eq!(o32.epsilon, f64::from(f32::EPSILON));
    assert!(o32.health().is_empty(), "{:?}", o32.health());
}
