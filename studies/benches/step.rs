//! Per-step cost of the closed loop, 1000 steps a run, recording off
//! (divide by 1000 for ns/step):
//! - `uses/<variant>`: a scene pays only for what it uses (attitude only on
//!   the pinned vehicle, the same plan translating, position with and
//!   without disturbance);
//! - `step-<integrator>/<pair>`: hover under Δ_x, Δ_R in position mode
//!   (continuous control, event location on) for every stepper on the four
//!   (backend, scalar) pairs, through the scene front end and the generic
//!   loop;
//! - `flip-rk4-1ms/<pair>`: the whole paper-flip (4 s, RK4 at h = 1 ms, a
//!   sample kept every 0.05 s) through the public `run`, after printing
//!   its final-state error against Dormand–Prince at 1e-12;
//! - `step-rk4/<glam-f32|glam-f64>-direct`: the same closed loop from the
//!   public pieces alone (RK4, `PositionMode`, `Hexarotor`, concrete types,
//!   no scene, plan, events or recording): full − direct is the cost of
//!   the `scenarios` layer, direct − hand that of the generic maths;
//! - `step-rk4/<glam-f32|glam-f64>-hand`: the same closed loop and RK4
//!   written by hand on glam (the controller of
//!   `controllers/benches/common/hand.rs`, the dynamics and the RK4
//!   combination inline): the baseline of the abstraction's cost.
//!
//! `cargo bench -p geopid-scenarios --bench step`; `cargo xtask bench` runs it and
//! tabulates the ratios.

use criterion::{Criterion, criterion_group, criterion_main};
use scenarios::RunOptions;
use scenes::scene::{BackendKind, Scalar, VehicleKind};
use scenes::{Scene, builtin, run};
use std::hint::black_box;

#[path = "../../controllers/benches/common/hand.rs"]
mod hand_twin;

#[path = "shared/quiet.rs"]
mod shared;
use shared::quiet;

/// The hand-written closed loop: state, vector field, RK4 step.
macro_rules! hand_loop {
    ($m:ident, $h:ident, $s:ty, $v:ty, $mat:ty) => {
        mod $m {
            use super::hand_twin::$h as c;
            #[derive(Copy, Clone)]
            pub struct X {
                pub r: $mat,
                pub x: $v,
                pub v: $v,
                pub w: $v,
                pub eatt: $v,
                pub ei: $v,
            }
            const DX: $v = <$v>::new(-0.5, 0.2, 1.0);
            const DR: $v = <$v>::new(0.2, -0.1, -0.02);

            /// The reference, read at run time (a hover point and heading
            /// given to the simulator, not compile-time constants LLVM
            /// could fold into the law).
            pub struct Ref {
                pub xd: [$v; 5],
                pub b1d: [$v; 3],
            }
            pub const HOVER: Ref = Ref {
                xd: [<$v>::ZERO; 5],
                b1d: [<$v>::X, <$v>::ZERO, <$v>::ZERO],
            };
            #[inline]
            fn field(y: &X, rf: &Ref) -> X {
                let i = c::In {
                    x: y.x,
                    v: y.v,
                    r: y.r,
                    w: y.w,
                    ei: y.ei,
                    eatt: y.eatt,
                    xd: rf.xd,
                    b1d: rf.b1d,
                };
                let o = c::position(&i).expect("regular state");
                let jw = <$v>::new(c::J[0] * y.w.x, c::J[1] * y.w.y, c::J[2] * y.w.z);
                let tq = o.m + DR - y.w.cross(jw);
                let wdot = <$v>::new(tq.x / c::J[0], tq.y / c::J[1], tq.z / c::J[2]);
                let wh = <$mat>::from_cols(
                    <$v>::new(0.0, y.w.z, -y.w.y),
                    <$v>::new(-y.w.z, 0.0, y.w.x),
                    <$v>::new(y.w.y, -y.w.x, 0.0),
                );
                X {
                    r: y.r * wh,
                    x: y.v,
                    v: c::G * <$v>::Z - (o.f / c::M) * y.r.z_axis + DX / c::M,
                    w: wdot,
                    eatt: o.eatt_rate,
                    ei: o.ei_rate,
                }
            }
            #[inline]
            fn axpy(y: &X, h: $s, k: &X) -> X {
                X {
                    r: y.r + k.r * h,
                    x: y.x + k.x * h,
                    v: y.v + k.v * h,
                    w: y.w + k.w * h,
                    eatt: y.eatt + k.eatt * h,
                    ei: y.ei + k.ei * h,
                }
            }
            /// One classical RK4 step on the embedding, as `integrators::Rk4`,
            /// and whether a component of e_i crossed ±σ in it (the generic
            /// loop checks for sat′ crossings after every step too).
            pub fn step(y: &X, h: $s, rf: &Ref) -> (X, bool) {
                let k1 = field(y, rf);
                let k2 = field(&axpy(y, 0.5 * h, &k1), rf);
                let k3 = field(&axpy(y, 0.5 * h, &k2), rf);
                let k4 = field(&axpy(y, h, &k3), rf);
                let (a, b) = (h / 6.0, h / 3.0);
                let mut n = axpy(y, a, &k1);
                n = axpy(&n, b, &k2);
                n = axpy(&n, b, &k3);
                n = axpy(&n, a, &k4);
                let inside = |e: $v| e.abs().cmple(<$v>::splat(c::SIG)).bitmask();
                let crossed = inside(y.ei) != inside(n.ei);
                (n, crossed)
            }
            pub fn start() -> X {
                X {
                    r: <$mat>::IDENTITY,
                    x: <$v>::ZERO,
                    v: <$v>::ZERO,
                    w: <$v>::ZERO,
                    eatt: <$v>::ZERO,
                    ei: <$v>::ZERO,
                }
            }
        }
    };
}
hand_loop!(loop64, hand64, f64, glam::DVec3, glam::DMat3);
hand_loop!(loop32, hand32, f32, glam::Vec3, glam::Mat3);

/// The same closed loop built from the public pieces alone: `integrators`'
/// RK4 stepping a `System` that calls `controllers::PositionMode` and
/// `dynamics::Hexarotor` directly (both concrete types, no scene, plan,
/// event checks or recording). Beside the full loop and the hand twin it
/// splits the abstraction's cost into the `scenarios` layer (full −
/// direct) and the generic maths itself (direct − hand).
mod direct {
    use controllers::{
        AccelerationModel, AttitudeGains, HoldPosition, Mode, PositionGains, PositionMode,
        PositionReference, RigidBodyParams,
    };
    use dynamics::{Hexarotor, Quadrotor, RigidBodyState, Vehicle, Wrench, paper};
    use integrators::{Integrator, Load, Rk4, State, System};
    use lie::{Backend, M3, Real, S};

    pub struct Loop<B: Backend> {
        vehicle: Hexarotor<B>,
        mode: PositionMode<B, HoldPosition<B>>,
        inertia_inv: M3<B>,
    }

    impl<B: Backend> Loop<B> {
        /// Hover-disturbed's loop: the paper's hexarotor under Δ_x, Δ_R,
        /// the paper's gains, holding `reference`.
        pub fn new(reference: PositionReference<B>) -> Self {
            let vehicle = Hexarotor::<B>::paper()
                .with_disturbance(Quadrotor::<B>::paper_disturbance())
                .expect("paper disturbance");
            let inertia_inv = lie::ops::inverse::<B>(vehicle.inertia()).expect("inertia");
            let mode = PositionMode::new(
                RigidBodyParams::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
                PositionGains::paper(),
                AttitudeGains::paper(),
                AccelerationModel::Nominal,
                HoldPosition(reference),
            );
            Self {
                vehicle,
                mode,
                inertia_inv,
            }
        }

        /// `steps` RK4 steps of `h` from rest.
        pub fn run(&mut self, steps: usize, h: f64) -> State<B, 6> {
            let mut y = State::new(RigidBodyState::at_rest());
            let mut rk4 = Rk4::default();
            for i in 0..steps {
                let t = S::<B>::lit(i as f64 * h);
                rk4.step(self, t, S::<B>::lit(h), &mut y)
                    .expect("regular step");
            }
            y
        }
    }

    impl<B: Backend> System<B, 6> for Loop<B> {
        fn mass(&self) -> S<B> {
            self.vehicle.mass()
        }
        fn inertia(&self) -> M3<B> {
            self.vehicle.inertia()
        }
        fn inertia_inv(&self) -> M3<B> {
            self.inertia_inv
        }
        fn load(&mut self, t: S<B>, y: &State<B, 6>) -> Load<B, 6> {
            let mut rates = [S::<B>::lit(0.0); 6];
            let st = y.body.group();
            let nan = S::<B>::nan();
            let Ok(out) = self.mode.command(t, &st, &y.extra, &mut rates) else {
                // The step then reports a non-finite load.
                return Load {
                    force: B::vec3(nan, nan, nan),
                    moment: B::vec3(nan, nan, nan),
                    extra_rate: rates,
                };
            };
            let w = Wrench {
                thrust: out.thrust,
                moment: out.moment,
            };
            let l = dynamics::loads(&self.vehicle, t, &y.body, &w);
            Load {
                force: l.force,
                moment: l.moment,
                extra_rate: rates,
            }
        }
    }
}

/// Hover under the paper's disturbance for 1 s at 1 ms: the scene of the
/// per-step benches.
fn hover_scene() -> Scene {
    let mut pos = builtin::hover_disturbed();
    pos.duration = 1.0;
    pos.integrator.dt = 1e-3;
    pos
}

fn bench(c: &mut Criterion) {
    bench_uses(c);
    bench_flip(c);
    bench_steppers(c);
}

/// What a scene pays for what it uses, and the twins checked against the
/// generic loop.
fn bench_uses(c: &mut Criterion) {
    let mut att = builtin::paper_attitude_experiment();
    att.duration = 1.0;
    let mut att_free = att.clone();
    att_free.vehicle.kind = VehicleKind::Quadrotor;
    let pos = hover_scene();
    let mut pos_clean = pos.clone();
    pos_clean.disturbance = None;
    let mut g = c.benchmark_group("uses");
    for (name, s) in [
        ("attitude-only", &att),
        ("attitude-translating", &att_free),
        ("position", &pos),
        ("position-no-disturbance", &pos_clean),
    ] {
        g.bench_function(name, |b| b.iter(|| quiet(s)));
    }
    g.finish();
    // The twin flies the generic loop's trajectory (same equations, same
    // RK4; they differ by rounding order only).
    let generic_run = run(&pos, RunOptions::default()).expect("run");
    let generic = generic_run.last;
    let mut y = loop64::start();
    let mut crossings = 0;
    for _ in 0..1000 {
        let (n, crossed) = loop64::step(&y, 1e-3, &loop64::HOVER);
        y = n;
        crossings += usize::from(crossed);
    }
    assert_eq!(
        crossings, generic_run.events,
        "the hand-written loop sees other sat′ crossings"
    );
    let dx = (0..3)
        .map(|k| (y.x[k] - generic.x[k]).abs())
        .fold(0.0, f64::max);
    assert!(
        dx < 1e-9,
        "hand-written loop differs from the generic one by {dx}"
    );
    let hover = controllers::PositionReference::hold(glam::DVec3::ZERO, glam::DVec3::X);
    let yd = direct::Loop::<lie::GlamF64>::new(hover).run(1000, 1e-3);
    let dd = (0..3)
        .map(|k| (yd.body.x[k] - generic.x[k]).abs())
        .fold(0.0, f64::max);
    assert!(
        dd < 1e-9,
        "the direct loop differs from the generic one by {dd}"
    );
}

/// The whole paper-flip on every pair, after its error is checked.
fn bench_flip(c: &mut Criterion) {
    // The whole-run figure the README quotes: paper-flip (4 s) by RK4 at h = 1 ms,
    // a sample kept every 0.05 s, on every pair; its final-state error
    // against Dormand–Prince at 1e-12 in f64 is printed first (and must
    // stay at the 1.1e-8 the regression suite knows, to rounding).
    let (flip, exact) = studies::metrics::flip_rk4_1ms();
    let truth = run(&exact, RunOptions::default()).expect("dopri run").last;
    let mut g = c.benchmark_group("flip-rk4-1ms");
    for (scalar, backend, name) in [
        (Scalar::F32, BackendKind::Nalgebra, "nalgebra-f32"),
        (Scalar::F64, BackendKind::Nalgebra, "nalgebra-f64"),
        (Scalar::F32, BackendKind::Glam, "glam-f32"),
        (Scalar::F64, BackendKind::Glam, "glam-f64"),
    ] {
        let mut s = flip.clone();
        s.scalar = scalar;
        s.backend = backend;
        let out = run(&s, RunOptions::default()).expect("flip run");
        let err = studies::metrics::final_state_error(&out.last, &truth);
        eprintln!(
            "paper-flip rk4 h = 1 ms, {name}: {} samples, final error {err:.2e} (vs dopri 1e-12 f64)",
            out.samples.len()
        );
        // 1.1e-8 is RK4's own error at 1 ms (f64); f32 is limited by
        // its ε (the stress suite's f32-vs-f64 bound is 1e-3).
        let bound = if scalar == Scalar::F64 { 2e-8 } else { 1e-3 };
        assert!(err < bound, "{name}: flip error {err:e} above {bound:e}");
        g.bench_function(name, |b| {
            b.iter(|| {
                let out = run(&s, RunOptions::default()).expect("flip run");
                black_box(out.samples.len())
            })
        });
    }
    g.finish();
}

/// Every stepper on every pair: 1000 steps of 1 ms (dopri: 1000 calls),
/// and RK4's hand-written and direct twins.
fn bench_steppers(c: &mut Criterion) {
    let pos = hover_scene();
    for kind in ["rk4", "rk4-projected", "rkmk4", "lgvi", "euler", "dopri"] {
        let mut g = c.benchmark_group(format!("step-{kind}"));
        for (scalar, backend, name) in [
            (Scalar::F32, BackendKind::Nalgebra, "nalgebra-f32"),
            (Scalar::F64, BackendKind::Nalgebra, "nalgebra-f64"),
            (Scalar::F32, BackendKind::Glam, "glam-f32"),
            (Scalar::F64, BackendKind::Glam, "glam-f64"),
        ] {
            let mut s = pos.clone();
            s.scalar = scalar;
            s.backend = backend;
            s.integrator.kind = kind.into();
            g.bench_function(name, |b| b.iter(|| quiet(&s)));
        }
        if kind == "rk4" {
            g.bench_function("glam-f64-hand", |b| {
                b.iter(|| {
                    let rf = black_box(&loop64::HOVER);
                    let mut y = loop64::start();
                    let mut crossings = 0u32;
                    for _ in 0..1000 {
                        let (n, crossed) = loop64::step(black_box(&y), 1e-3, rf);
                        y = n;
                        crossings += u32::from(crossed);
                    }
                    black_box((y.x, crossings))
                })
            });
            g.bench_function("glam-f64-direct", |b| {
                b.iter(|| {
                    let rf = *black_box(&controllers::PositionReference::hold(
                        glam::DVec3::ZERO,
                        glam::DVec3::X,
                    ));
                    let y = direct::Loop::<lie::GlamF64>::new(rf).run(1000, 1e-3);
                    black_box(y.body.x)
                })
            });
            g.bench_function("glam-f32-direct", |b| {
                b.iter(|| {
                    let rf = *black_box(&controllers::PositionReference::hold(
                        glam::Vec3::ZERO,
                        glam::Vec3::X,
                    ));
                    let y = direct::Loop::<lie::GlamF32>::new(rf).run(1000, 1e-3);
                    black_box(y.body.x)
                })
            });
            g.bench_function("glam-f32-hand", |b| {
                b.iter(|| {
                    let rf = black_box(&loop32::HOVER);
                    let mut y = loop32::start();
                    let mut crossings = 0u32;
                    for _ in 0..1000 {
                        let (n, crossed) = loop32::step(black_box(&y), 1e-3, rf);
                        y = n;
                        crossings += u32::from(crossed);
                    }
                    black_box((y.x, crossings))
                })
            });
        }
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
