//! `cargo bench -p geopid-controllers`: one attitude-mode and one position-mode
//! update through the generic code on the four (backend, scalar) pairs,
//! beside the same maths written by hand on glam's own types (f32 and
//! f64), so the abstraction's cost is a ratio measured in one run.
//!
//! Ids: `attitude/<pair>`, `position/<pair>` (generic), and
//! `attitude/<glam-f32|glam-f64>-hand`, `position/<…>-hand`. The pairs of
//! one group sit side by side in criterion's report.

use controllers::{
    AccelerationModel, AttitudeGains, AttitudeReference, PositionGains, PositionReference,
    RigidBodyParams, VehicleState, attitude_control, position_control,
};
use criterion::{Criterion, criterion_group, criterion_main};
use lie::{Backend, GlamF32, GlamF64, NalgebraF32, NalgebraF64, Real, Rotation, So3Mat};
use std::hint::black_box;

/// The inputs, a generic mid-flight state (no fallback taken).
struct Case<B: Backend> {
    st: VehicleState<B, So3Mat<B>>,
    ei: lie::V3<B>,
    e_att: lie::V3<B>,
    pref: PositionReference<B>,
    aref: AttitudeReference<B, So3Mat<B>>,
}

fn case<B: Backend>() -> Case<B> {
    let s = lie::S::<B>::lit;
    let l = |a: f64, b: f64, c: f64| B::vec3(s(a), s(b), s(c));
    let st = VehicleState {
        x: l(0.3, -0.2, -1.1),
        v: l(0.5, 0.1, -0.3),
        r: So3Mat::<B>::exp(l(0.2, 0.1, -0.3)),
        omega: l(0.4, -0.7, 0.2),
    };
    let pref = PositionReference {
        x: l(0.1, 0.0, -1.0),
        v: l(0.2, 0.1, 0.0),
        a: l(-0.1, 0.3, 0.0),
        jerk: l(0.2, -0.1, 0.0),
        snap: l(-0.3, 0.1, 0.0),
        b1d: l(1.0, 0.1, 0.0),
        b1d_dot: l(0.0, 0.2, 0.0),
        b1d_ddot: l(-0.1, 0.0, 0.0),
    };
    let aref = AttitudeReference {
        rd: So3Mat::<B>::exp(l(-0.1, 0.3, 0.2)),
        omega_d: l(0.3, -0.2, 0.5),
        omega_d_dot: l(0.1, 0.4, -0.2),
    };
    Case {
        st,
        ei: l(0.1, -0.2, 0.3),
        e_att: l(0.05, 0.02, -0.01),
        pref,
        aref,
    }
}

fn generic<B: Backend>(c: &mut Criterion, pair: &str) {
    let k = case::<B>();
    let p = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let (pg, ag) = (PositionGains::<B>::paper(), AttitudeGains::<B>::paper());
    c.benchmark_group("position").bench_function(pair, |b| {
        b.iter(|| {
            let o = position_control(
                &p,
                &pg,
                &ag,
                &controllers::PositionInput {
                    state: black_box(&k.st),
                    e_i_pos: black_box(k.ei),
                    e_i_att: black_box(k.e_att),
                    reference: black_box(&k.pref),
                    model: AccelerationModel::Nominal,
                },
            )
            .unwrap();
            // By reference: returning the ~300-byte output by value
            // would time a memcpy of it as well.
            black_box(&o);
        })
    });
    c.benchmark_group("attitude").bench_function(pair, |b| {
        b.iter(|| {
            let o = attitude_control(
                &p,
                &ag,
                black_box(k.st.r),
                black_box(k.st.omega),
                black_box(k.e_att),
                black_box(&k.aref),
            )
            .unwrap();
            black_box(&o);
        })
    });
}

#[path = "common/hand.rs"]
mod hand_twin;
use dynamics::paper;
use hand_twin::{hand32, hand64};

fn hand_benches(c: &mut Criterion) {
    macro_rules! one {
        ($m:ident, $b:ty, $name:expr) => {{
            let k = case::<$b>();
            let i = $m::In {
                x: k.st.x,
                v: k.st.v,
                r: k.st.r.matrix(),
                w: k.st.omega,
                ei: k.ei,
                eatt: k.e_att,
                xd: [k.pref.x, k.pref.v, k.pref.a, k.pref.jerk, k.pref.snap],
                b1d: [k.pref.b1d, k.pref.b1d_dot, k.pref.b1d_ddot],
            };
            // The twin computes what the generic law does.
            let p = RigidBodyParams::<$b>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
            let g = position_control(
                &p,
                &PositionGains::paper(),
                &AttitudeGains::paper(),
                &controllers::PositionInput {
                    state: &k.st,
                    e_i_pos: k.ei,
                    e_i_att: k.e_att,
                    reference: &k.pref,
                    model: AccelerationModel::Nominal,
                },
            )
            .unwrap();
            let o = $m::position(&i).unwrap();
            // Same formulas in the same order up to the compiler's freedom:
            // agreement to a few ulps of O(10) quantities.
            let tol = 1e3 * Real::to_f64_lossless(<lie::S<$b> as lie::Real>::epsilon());
            assert!(((o.f - g.thrust) as f64).abs() < tol, "{} thrust", $name);
            assert!(((o.m - g.moment).length() as f64) < tol, "{} moment", $name);
            assert!(
                ((o.wcd - g.omega_c_dot).length() as f64) < tol,
                "{} Ω̇_c",
                $name
            );
            assert!(((o.psi - g.psi) as f64).abs() < tol, "{} Ψ", $name);
            c.benchmark_group("position")
                .bench_function(concat!($name, "-hand"), |b| {
                    b.iter(|| {
                        black_box(&$m::position(black_box(&i)));
                    })
                });
            let a = k.aref;
            c.benchmark_group("attitude")
                .bench_function(concat!($name, "-hand"), |b| {
                    // The reference through black_box too, as the
                    // generic law's: constants would be folded in. The
                    // moment checked for finiteness, as `attitude_control`
                    // checks it (and the position twin its output).
                    b.iter(|| {
                        let out = $m::attitude(
                            black_box(i.r),
                            black_box(i.w),
                            black_box(i.eatt),
                            black_box(a.rd.matrix()),
                            black_box(a.omega_d),
                            black_box(a.omega_d_dot),
                        );
                        black_box(&out.0.is_finite().then_some(out));
                    })
                });
        }};
    }
    one!(hand64, GlamF64, "glam-f64");
    one!(hand32, GlamF32, "glam-f32");
}

fn benches(c: &mut Criterion) {
    generic::<NalgebraF32>(c, "nalgebra-f32");
    generic::<NalgebraF64>(c, "nalgebra-f64");
    generic::<GlamF32>(c, "glam-f32");
    generic::<GlamF64>(c, "glam-f64");
    hand_benches(c);
}

criterion_group!(group, benches);
criterion_main!(group);
