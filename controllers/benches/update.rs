//! `cargo bench -p controllers`: one attitude-mode and one position-mode
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
    let p = RigidBodyParams::<B>::paper();
    let (pg, ag) = (PositionGains::<B>::paper(), AttitudeGains::<B>::paper());
    c.benchmark_group("position").bench_function(pair, |b| {
        b.iter(|| {
            let o = position_control(
                &p,
                &pg,
                &ag,
                black_box(&k.st),
                black_box(k.ei),
                black_box(k.e_att),
                black_box(&k.pref),
                AccelerationModel::Nominal,
            )
            .unwrap();
            black_box(o)
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
            black_box(o)
        })
    });
}

/// The same laws by hand on glam (same formulas, branches and checks as
/// `controllers`, written for one type).
macro_rules! hand {
    ($m:ident, $s:ty, $v:ty, $mat:ty) => {
        mod $m {
            pub struct In {
                pub x: $v,
                pub v: $v,
                pub r: $mat,
                pub w: $v,
                pub ei: $v,
                pub eatt: $v,
                pub xd: [$v; 5],
                pub b1d: [$v; 3],
            }
            const M: $s = 0.755;
            const G: $s = 9.81;
            const J: [$s; 3] = [0.43e-2, 0.43e-2, 1.02e-2];
            const KX: $s = 12.8;
            const KV: $s = 4.22;
            const KI: $s = 1.28;
            const C1: $s = 3.6;
            const SIG: $s = 1.0;
            const KR: $s = 0.65;
            const KW: $s = 0.11;
            const KIA: $s = 0.06;
            const C2: $s = 0.8;

            fn jmul(v: $v) -> $v {
                <$v>::new(J[0] * v.x, J[1] * v.y, J[2] * v.z)
            }
            fn fin(v: $v) -> bool {
                v.is_finite()
            }

            /// (M, e_R, e_Ω, Ψ, ė_I) against R_d with Ω_d, Ω̇_d.
            #[inline]
            pub fn attitude(
                r: $mat,
                w: $v,
                eatt: $v,
                rd: $mat,
                wd: $v,
                wdd: $v,
            ) -> ($v, $v, $v, $s, $v) {
                let e = rd.transpose() * r;
                let er = 0.5
                    * <$v>::new(
                        e.y_axis.z - e.z_axis.y,
                        e.z_axis.x - e.x_axis.z,
                        e.x_axis.y - e.y_axis.x,
                    );
                let psi = 0.5 * (3.0 - (e.x_axis.x + e.y_axis.y + e.z_axis.z));
                let wb = e.transpose() * wd;
                let wdb = e.transpose() * wdd;
                let ew = w - wb;
                let m = -KR * er - KW * ew - KIA * eatt + wb.cross(jmul(wb)) + jmul(wdb);
                (m, er, ew, psi, ew + C2 * er)
            }

            /// What the generic law returns (read through `black_box`).
            #[allow(dead_code)]
            pub struct Out {
                pub f: $s,
                pub m: $v,
                pub rc: $mat,
                pub wc: $v,
                pub wcd: $v,
                pub ex: $v,
                pub ev: $v,
                pub er: $v,
                pub ew: $v,
                pub psi: $s,
                pub ei_rate: $v,
                pub eatt_rate: $v,
            }

            #[inline]
            pub fn position(i: &In) -> Option<Out> {
                if !fin(i.ei) {
                    return None;
                }
                let e3 = <$v>::Z;
                let ex = i.x - i.xd[0];
                let ev = i.v - i.xd[1];
                let sat = i.ei.clamp(<$v>::splat(-SIG), <$v>::splat(SIG));
                let slope = <$v>::new(
                    if i.ei.x.abs() <= SIG { 1.0 } else { 0.0 },
                    if i.ei.y.abs() <= SIG { 1.0 } else { 0.0 },
                    if i.ei.z.abs() <= SIG { 1.0 } else { 0.0 },
                );
                let ei_rate = ev + C1 * ex;
                let ki_sat = KI * sat;
                let a = -KX * ex - KV * ev - ki_sat - (M * G) * e3 + M * i.xd[2];
                let (rb1, rb2, re3) = (i.r.x_axis, i.r.y_axis, i.r.z_axis);
                let f = -a.dot(re3);
                let ksr = KI * slope * ei_rate;
                let acc = G * e3 - (f / M) * re3 + ki_sat / M;
                let ev_dot = acc - i.xd[2];
                let ad = -KX * ev - KV * ev_dot - ksr + M * i.xd[3];
                let re3d = i.w.y * rb1 - i.w.x * rb2;
                let fd = -ad.dot(re3) - a.dot(re3d);
                let jerk = -(fd * re3 + f * re3d) / M + ksr / M;
                let ev_ddot = jerk - i.xd[3];
                let eir_dot = ev_dot + C1 * ev;
                let add = -KX * ev_dot - KV * ev_ddot - KI * slope * eir_dot + M * i.xd[4];
                let (u, ud, udd) = (-a, -ad, -add);
                let n = u.length();
                let thrust_defined = n > <$s>::EPSILON.sqrt() * M * G;
                if !thrust_defined {
                    return None; // the fallback is not benchmarked
                }
                let inv = 1.0 / n;
                let b3 = u * inv;
                let q = b3.dot(ud);
                let b3d = (ud - q * b3) * inv;
                let b3dd = (udd - (2.0 * q) * b3d - (b3d.dot(ud) + b3.dot(udd)) * b3) * inv;
                let [b1d, b1dd, b1ddd] = i.b1d;
                let c = b3.cross(b1d);
                let nc = c.length();
                let heading_defined = nc > <$s>::EPSILON.sqrt() * (1.0 + b1d.length());
                if !heading_defined {
                    return None;
                }
                let cd = b3d.cross(b1d) + b3.cross(b1dd);
                let cdd = b3dd.cross(b1d) + 2.0 * b3d.cross(b1dd) + b3.cross(b1ddd);
                let invc = 1.0 / nc;
                let b2 = c * invc;
                let qc = b2.dot(cd);
                let b1 = b2.cross(b3);
                let w1 = b3.dot(cd) * invc;
                let w3 = -b1.dot(cd) * invc;
                let w2 = b1.dot(b3d);
                let b3b2dd = (b3.dot(cdd) - 2.0 * qc * w1) * invc;
                let b1b2dd = (b1.dot(cdd) + 2.0 * qc * w3) * invc;
                let b1b3dd = (b1.dot(udd) - 2.0 * q * w2) * inv;
                let wc = <$v>::new(w1, w2, w3);
                let wcd = <$v>::new(b3b2dd - w2 * w3, b1b3dd - w3 * w1, -b1b2dd + w1 * w2);
                let rc = <$mat>::from_cols(b1, b2, b3);
                let (m, er, ew, psi, eatt_rate) = attitude(i.r, i.w, i.eatt, rc, wc, wcd);
                (f.is_finite() && fin(m)).then_some(Out {
                    f,
                    m,
                    rc,
                    wc,
                    wcd,
                    ex,
                    ev,
                    er,
                    ew,
                    psi,
                    ei_rate,
                    eatt_rate,
                })
            }
        }
    };
}
hand!(hand64, f64, glam::DVec3, glam::DMat3);
hand!(hand32, f32, glam::Vec3, glam::Mat3);

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
            let p = RigidBodyParams::<$b>::paper();
            let g = position_control(
                &p,
                &PositionGains::paper(),
                &AttitudeGains::paper(),
                &k.st,
                k.ei,
                k.e_att,
                &k.pref,
                AccelerationModel::Nominal,
            )
            .unwrap();
            let o = $m::position(&i).unwrap();
            // Same formulas in the same order up to the compiler's freedom:
            // agreement to a few ulps of O(10) quantities.
            let tol = 1e3
                * Real::to_f64_lossless(
                    <<$b as Backend>::Scalar as lie::num_traits::Float>::epsilon(),
                );
            assert!(((o.f - g.thrust) as f64).abs() < tol, "{} thrust", $name);
            assert!(((o.m - g.moment).length() as f64) < tol, "{} moment", $name);
            assert!(
                ((o.wcd - g.omega_c_dot).length() as f64) < tol,
                "{} Ω̇_c",
                $name
            );
            c.benchmark_group("position")
                .bench_function(concat!($name, "-hand"), |b| {
                    b.iter(|| black_box($m::position(black_box(&i))))
                });
            let a = k.aref;
            c.benchmark_group("attitude")
                .bench_function(concat!($name, "-hand"), |b| {
                    b.iter(|| {
                        black_box($m::attitude(
                            black_box(i.r),
                            black_box(i.w),
                            black_box(i.eatt),
                            a.rd.matrix(),
                            a.omega_d,
                            a.omega_d_dot,
                        ))
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
