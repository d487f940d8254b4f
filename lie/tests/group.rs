//! The `LieGroup` trait on SO(3) (matrix and quaternion), SE(3) and the
//! rigid-body state SO(3) × ℝ⁹ (over both), every backend and scalar:
//! each Jacobian against central finite differences at random points and
//! at the hard cases, the group identities, and f32 against f64.
//!
//! A test without the libtest harness (`harness = false`), so that
//! `cargo test -p geopid-lie` shows its table: the worst finite-difference error
//! per operation and pair, the identities' residuals, f32 against f64. A
//! failed check panics, which fails the test.

use std::f64::consts::PI;

use lie::{
    Backend, GlamF32, GlamF32A, GlamF64, LieGroup, NalgebraF32, NalgebraF64, Real, RigidState, S,
    Se3, Se23, So3Mat, So3Quat,
};

/// A small deterministic generator (no dependency): uniform in [−1, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

/// Tangent coordinates, the group's `DOF` first and zeros after (12 is
/// the largest `DOF` here, the rigid-body state's).
type C = [f64; 12];

fn coords<B: Backend, G: LieGroup<B>>(t: G::Tangent) -> C {
    core::array::from_fn(|i| {
        if i < G::DOF {
            G::tangent_coord(&t, i).to_f64_lossless()
        } else {
            0.0
        }
    })
}

fn tangent<B: Backend, G: LieGroup<B>>(c: C) -> G::Tangent {
    G::tangent_from_fn(|i| S::<B>::lit(c[i]))
}

/// A point's coordinates padded to a tangent's.
fn pad3(q: [f64; 3]) -> C {
    core::array::from_fn(|i| if i < 3 { q[i] } else { 0.0 })
}

fn jac<B: Backend, G: LieGroup<B>>(j: &G::Jacobian) -> Vec<Vec<f64>> {
    (0..G::DOF)
        .map(|r| {
            (0..G::DOF)
                .map(|c| G::jacobian_entry(j, r, c).to_f64_lossless())
                .collect()
        })
        .collect()
}

/// `e_k · h`.
fn unit(k: usize, h: f64) -> C {
    let mut c = [0.0; 12];
    c[k] = h;
    c
}

/// A tangent with rotation angle `angle` about a random axis and, for
/// SE(3), a translation part of norm `trans` in a random direction (and
/// for the rigid-body state velocity and rate parts of that norm too), in
/// the order `(ρ, φ, v, Ω)`.
fn tangent_at(rng: &mut Rng, angle: f64, trans: f64) -> C {
    let unit3 = |rng: &mut Rng| {
        let v = [rng.next(), rng.next(), rng.next()];
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|x| x / n)
    };
    let (a, t, v, w) = (unit3(rng), unit3(rng), unit3(rng), unit3(rng));
    core::array::from_fn(|i| match i / 3 {
        0 => t[i] * trans,
        1 => a[i - 3] * angle,
        2 => v[i - 6] * trans,
        _ => w[i - 9] * trans,
    })
}

/// The tangent coordinates of `c` for group `G`: SO(3) takes the angle
/// part, SE(3) `(ρ, φ)`, SE₂(3) `(ρ, ν, φ)` (ν the velocity part), the
/// rigid-body state `(φ, x, v, Ω)`.
fn for_group<B: Backend, G: LieGroup<B>>(c: C) -> C {
    core::array::from_fn(|i| match (G::DOF, i) {
        (3, 0..3) | (12, 0..3) => c[i + 3],
        (6, 0..6) | (9, 0..3) => c[i],
        (9, 3..6) => c[i + 3],
        (9, 6..9) => c[i - 3],
        (12, 3..6) => c[i - 3],
        (12, _) => c[i],
        _ => 0.0,
    })
}

/// `max |A − B| / max(1, max |B|)`.
fn rel(a: &[Vec<f64>], b: &[Vec<f64>]) -> f64 {
    let scale = b.iter().flatten().fold(1.0f64, |m, x| m.max(x.abs()));
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// Central differences of `f` (tangent → tangent coordinates) at 0,
/// column by column.
fn fd(dof: usize, h: f64, f: impl Fn(C) -> C) -> Vec<Vec<f64>> {
    let cols: Vec<C> = (0..dof)
        .map(|k| {
            let (p, m) = (f(unit(k, h)), f(unit(k, -h)));
            core::array::from_fn(|i| (p[i] - m[i]) / (2.0 * h))
        })
        .collect();
    (0..dof)
        .map(|r| (0..dof).map(|c| cols[c][r]).collect())
        .collect()
}

/// The worst errors per operation over all points, for group `G` on `B`.
fn jacobians<B: Backend, G: LieGroup<B>>(points: &[Point]) -> Vec<(&'static str, f64, f64)> {
    let n = G::DOF;
    let mut worst: Vec<(&'static str, f64, f64)> = Vec::new();
    for &Point {
        x: cx,
        y: cy,
        t: ct,
        h,
        floor,
    } in points
    {
        // The worst raw error, and the worst error above the point's
        // rounding floor (see `Point::floor`), which the test bounds.
        let mut note = |name: &'static str, e: f64| {
            let above = (e - floor).max(0.0);
            match worst.iter_mut().find(|(k, _, _)| *k == name) {
                Some((_, w, a)) => {
                    *w = w.max(e);
                    *a = a.max(above);
                }
                None => worst.push((name, e, above)),
            }
        };
        let x = G::exp(tangent::<B, G>(for_group::<B, G>(cx)));
        let t = tangent::<B, G>(for_group::<B, G>(ct));
        let y = match cy {
            Some(cy) => G::exp(tangent::<B, G>(for_group::<B, G>(cy))),
            None => x.rplus(t),
        };
        let tc = coords::<B, G>(t);
        let plus = |a: C, b: C| -> C { core::array::from_fn(|i| a[i] + b[i]) };
        // A group-valued f at X, differenced in the tangent at f(X).
        let dg = |f: &dyn Fn(G) -> G, at: G| {
            let f0 = f(at);
            fd(n, h, |d| {
                coords::<B, G>(f(at.rplus(tangent::<B, G>(d))).rminus(f0))
            })
        };
        let (_, jx, jt) = x.rplus_jac(t);
        note("rplus/X", rel(&dg(&|a| a.rplus(t), x), &jac::<B, G>(&jx)));
        let f_t = |d: C| coords::<B, G>(x.rplus(tangent::<B, G>(plus(tc, d))).rminus(x.rplus(t)));
        note("rplus/tau", rel(&fd(n, h, f_t), &jac::<B, G>(&jt)));
        let (_, jy, jx2) = y.rminus_jac(x);
        let z = coords::<B, G>(y.rminus(x));
        let minus = |a: C| -> C { core::array::from_fn(|i| a[i] - z[i]) };
        let f_y = |d: C| minus(coords::<B, G>(y.rplus(tangent::<B, G>(d)).rminus(x)));
        note("rminus/Y", rel(&fd(n, h, f_y), &jac::<B, G>(&jy)));
        let f_x = |d: C| minus(coords::<B, G>(y.rminus(x.rplus(tangent::<B, G>(d)))));
        note("rminus/X", rel(&fd(n, h, f_x), &jac::<B, G>(&jx2)));
        let (_, ja, jb) = x.compose_jac(y);
        note(
            "compose/X",
            rel(&dg(&|a| a.compose(y), x), &jac::<B, G>(&ja)),
        );
        note(
            "compose/Y",
            rel(&dg(&|b| x.compose(b), y), &jac::<B, G>(&jb)),
        );
        let (_, ji) = x.inverse_jac();
        note("inverse", rel(&dg(&|a| a.inverse(), x), &jac::<B, G>(&ji)));
        let (_, ja, jb) = x.between_jac(y);
        note(
            "between/X",
            rel(&dg(&|a| a.between(y), x), &jac::<B, G>(&ja)),
        );
        note(
            "between/Y",
            rel(&dg(&|b| x.between(b), y), &jac::<B, G>(&jb)),
        );
        let jr = G::right_jacobian(t);
        let f_exp = |d: C| coords::<B, G>(G::exp(tangent::<B, G>(plus(tc, d))).rminus(G::exp(t)));
        note("Jr", rel(&fd(n, h, f_exp), &jac::<B, G>(&jr)));
        // The action: a point of size 1, and one of 1e3 where SE(3)'s
        // translation is large.
        let p = B::vec3(S::<B>::lit(0.3), S::<B>::lit(-1.2), S::<B>::lit(0.8));
        let (_, jax, jap) = x.act_jac(p);
        let pc = B::vec3_to_array(x.act(p)).map(|c| c.to_f64_lossless());
        let f_ax = |d: C| -> C {
            let q =
                B::vec3_to_array(x.rplus(tangent::<B, G>(d)).act(p)).map(|c| c.to_f64_lossless());
            pad3([q[0] - pc[0], q[1] - pc[1], q[2] - pc[2]])
        };
        let fd_ax = fd(n, h, f_ax);
        let an_ax: Vec<Vec<f64>> = (0..3)
            .map(|r| {
                (0..n)
                    .map(|c| G::act_jacobian_entry(&jax, r, c).to_f64_lossless())
                    .collect()
            })
            .collect();
        note("act/X", rel(&fd_ax[..3], &an_ax));
        let f_ap = |d: C| -> C {
            let dp = B::vec3(S::<B>::lit(d[0]), S::<B>::lit(d[1]), S::<B>::lit(d[2]));
            let q = B::vec3_to_array(x.act(p + dp)).map(|c| c.to_f64_lossless());
            pad3([q[0] - pc[0], q[1] - pc[1], q[2] - pc[2]])
        };
        let fd_ap = fd(3, h, f_ap);
        let e = lie::ops::elems::<B>(jap);
        let an_ap: Vec<Vec<f64>> = e
            .iter()
            .map(|r| r.iter().map(|c| c.to_f64_lossless()).collect())
            .collect();
        note("act/p", rel(&fd_ap, &an_ap));
        let jl = G::left_jacobian(t);
        let f_l = |d: C| coords::<B, G>(G::exp(tangent::<B, G>(plus(tc, d))).lminus(G::exp(t)));
        note("Jl", rel(&fd(n, h, f_l), &jac::<B, G>(&jl)));
    }
    worst
}

/// Where the Jacobians are checked: `X = Exp(x)`, `Y = Exp(y)` or, without
/// `y`, `Y = X ⊕ t` (so that `Y ⊖ X = t` is at the hard case too), the
/// tangent `t`, and the difference step `h`.
#[derive(Copy, Clone)]
struct Point {
    x: C,
    y: Option<C>,
    t: C,
    h: f64,
    /// The rounding floor of a difference quotient at this point,
    /// `4 ε (1 + ‖values‖) / h`: with translations of 1e3 and the step
    /// near π held at 1e-7, no Jacobian can be checked closer than that.
    floor: f64,
}

/// Random points, and the hard cases of the rotation angle of `t` (0,
/// 1e-9, 1e-4, π/2, π − 1e-6) with translations 0 and 1e3; near π the
/// step must not cross π, where Log jumps.
fn points() -> Vec<Point> {
    let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
    let mut out = Vec::new();
    for _ in 0..20 {
        let r = |rng: &mut Rng| {
            let (angle, trans) = (3.0 * rng.next().abs(), 2.0 * rng.next().abs());
            tangent_at(rng, angle, trans)
        };
        let (x, y, t) = (r(&mut rng), r(&mut rng), r(&mut rng));
        // Values of order 1–5 here.
        out.push(Point {
            x,
            y: Some(y),
            t,
            h: 1e-6,
            floor: 4.0 * f64::EPSILON * 5.0 / 1e-6,
        });
    }
    for angle in [0.0, 1e-9, 1e-4, PI / 2.0, PI - 1e-6] {
        for trans in [0.0, 1e3] {
            // Near π the step must not cross π; with large translations a
            // larger step keeps the rounding floor down.
            let h = match (angle > 3.0, trans > 1.0) {
                (true, _) => 1e-7,
                (false, true) => 1e-5,
                (false, false) => 1e-6,
            };
            let x = tangent_at(&mut rng, 0.7, 0.5);
            let t = tangent_at(&mut rng, angle, trans);
            let floor = 4.0 * f64::EPSILON * (5.0 + trans) / h;
            out.push(Point {
                x,
                y: None,
                t,
                h,
                floor,
            });
        }
    }
    out
}

fn check<B: Backend, G: LieGroup<B>>(pair: &str, tol: f64) -> f64 {
    let worst = jacobians::<B, G>(&points());
    let cells: Vec<String> = worst
        .iter()
        .map(|(name, e, _)| format!("{name} {e:.0e}"))
        .collect();
    println!("{pair:<26} {}", cells.join(", "));
    let all = worst.iter().fold(0.0f64, |m, (_, _, above)| m.max(*above));
    assert!(
        all < tol,
        "{pair}: worst FD error above the floor {all:.2e} ≥ {tol:.0e}"
    );
    all
}

/// The identities, to rounding: `X ⊕ (Y ⊖ X) = Y`, `Adj(X)·τ =
/// Log(X·Exp(τ)·X⁻¹)`, `J_r(τ) = J_l(−τ)`, `J_r⁻¹·J_r = I`,
/// `X ⊖ X = 0`, `X·X⁻¹ = I`; returns the worst of each.
fn identities<B: Backend, G: LieGroup<B>>(pair: &str) -> [f64; 5] {
    let mut w = [0.0f64; 5];
    let norm = |c: C| c.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for pt in points() {
        let x = G::exp(tangent::<B, G>(for_group::<B, G>(pt.x)));
        let t = tangent::<B, G>(for_group::<B, G>(pt.t));
        let y = pt.y.map_or(x.rplus(t), |c| {
            G::exp(tangent::<B, G>(for_group::<B, G>(c)))
        });
        let scale = 1.0 + norm(coords::<B, G>(y.log())) + norm(coords::<B, G>(x.log()));
        w[0] = w[0].max(norm(coords::<B, G>(x.rplus(y.rminus(x)).rminus(y))) / scale);
        // Away from π, where Log's branch is well defined for X·Exp(τ)·X⁻¹.
        let tc = coords::<B, G>(t);
        if tc[..].iter().any(|v| v.abs() > 0.0)
            && pt.t[3..6].iter().map(|v| v * v).sum::<f64>() < 9.0
        {
            let a = coords::<B, G>(G::jacobian_apply(&x.adjoint(), t));
            let b = coords::<B, G>(x.compose(G::exp(t)).compose(x.inverse()).log());
            let d: C = core::array::from_fn(|i| a[i] - b[i]);
            w[1] = w[1].max(norm(d) / (1.0 + norm(a)));
        }
        let (jr, jl) = (
            jac::<B, G>(&G::right_jacobian(t)),
            jac::<B, G>(&G::left_jacobian(G::tangent_neg(t))),
        );
        w[2] = w[2].max(rel(&jr, &jl));
        let ii = G::jacobian_mul(G::right_jacobian_inv(t), G::right_jacobian(t));
        w[3] = w[3].max(rel(
            &jac::<B, G>(&ii),
            &jac::<B, G>(&G::jacobian_identity()),
        ));
        w[4] = w[4].max(
            norm(coords::<B, G>(x.compose(x.inverse()).log())) + norm(coords::<B, G>(x.rminus(x))),
        );
    }
    println!(
        "{pair:<26} X⊕(Y⊖X)=Y {:.1e}, Adj {:.1e}, Jr=Jl(-t) {:.1e}, Jr⁻¹Jr=I {:.1e}, X·X⁻¹ {:.1e}",
        w[0], w[1], w[2], w[3], w[4]
    );
    w
}

fn group_identities_to_rounding() {
    // f64: a few hundred ε (1e-13) — translations of 1e3 scale the
    // absolute error, hence the relative measures; the 1e-9 rotation and
    // π − 1e-6 points included.
    let f64_tol = 1e-11;
    for w in [
        identities::<NalgebraF64, So3Mat<NalgebraF64>>("nalgebra f64 So3Mat"),
        identities::<NalgebraF64, So3Quat<NalgebraF64>>("nalgebra f64 So3Quat"),
        identities::<GlamF64, So3Mat<GlamF64>>("glam f64 So3Mat"),
        identities::<GlamF64, So3Quat<GlamF64>>("glam f64 So3Quat"),
        identities::<NalgebraF64, Se3<NalgebraF64, So3Mat<NalgebraF64>>>(
            "nalgebra f64 Se3<So3Mat>",
        ),
        identities::<GlamF64, Se3<GlamF64, So3Quat<GlamF64>>>("glam f64 Se3<So3Quat>"),
        identities::<NalgebraF64, RigidState<NalgebraF64, So3Mat<NalgebraF64>>>(
            "nalgebra f64 Rigid<So3Mat>",
        ),
        identities::<GlamF64, RigidState<GlamF64, So3Quat<GlamF64>>>("glam f64 Rigid<So3Quat>"),
        identities::<NalgebraF64, Se23<NalgebraF64, So3Mat<NalgebraF64>>>(
            "nalgebra f64 Se23<So3Mat>",
        ),
        identities::<GlamF64, Se23<GlamF64, So3Quat<GlamF64>>>("glam f64 Se23<So3Quat>"),
    ] {
        assert!(w.iter().all(|e| *e < f64_tol), "{w:?}");
    }
    // f32: ε = 1.2e-7; J_r⁻¹·J_r of SE(3) at translations of 1e3 has
    // off-diagonal entries of 1e3·ε (measured 8.8e-5), the rest are within
    // a few ε.
    let f32_tol = 5e-4;
    for w in [
        identities::<NalgebraF32, So3Mat<NalgebraF32>>("nalgebra f32 So3Mat"),
        identities::<GlamF32, So3Quat<GlamF32>>("glam f32 So3Quat"),
        identities::<NalgebraF32, Se3<NalgebraF32, So3Quat<NalgebraF32>>>(
            "nalgebra f32 Se3<So3Quat>",
        ),
        identities::<GlamF32, Se3<GlamF32, So3Mat<GlamF32>>>("glam f32 Se3<So3Mat>"),
        identities::<GlamF32, RigidState<GlamF32, So3Mat<GlamF32>>>("glam f32 Rigid<So3Mat>"),
        identities::<GlamF32A, Se3<GlamF32A, So3Mat<GlamF32A>>>("glam f32a Se3<So3Mat>"),
        identities::<GlamF32A, So3Quat<GlamF32A>>("glam f32a So3Quat"),
        identities::<NalgebraF32, Se23<NalgebraF32, So3Quat<NalgebraF32>>>(
            "nalgebra f32 Se23<So3Quat>",
        ),
        identities::<GlamF32, Se23<GlamF32, So3Mat<GlamF32>>>("glam f32 Se23<So3Mat>"),
    ] {
        assert!(w.iter().all(|e| *e < f32_tol), "{w:?}");
    }
}

/// f32 against f64, away from the singular points (angles in [0.1, 2.5],
/// translations ≤ 2): every value and Jacobian of rplus and rminus
/// within 1e-5 relative.
fn f32_vs_f64<B32: Backend, G32: LieGroup<B32>, B64: Backend, G64: LieGroup<B64>>() -> f64 {
    let mut rng = Rng(7);
    let mut worst = 0.0f64;
    for _ in 0..50 {
        let r = |rng: &mut Rng| {
            let (a, t) = (0.1 + 2.4 * rng.next().abs(), 2.0 * rng.next().abs());
            tangent_at(rng, a, t)
        };
        let (cx, cy, ct) = (r(&mut rng), r(&mut rng), r(&mut rng));
        let x32 = G32::exp(tangent::<B32, G32>(for_group::<B32, G32>(cx)));
        let x64 = G64::exp(tangent::<B64, G64>(for_group::<B64, G64>(cx)));
        let y32 = G32::exp(tangent::<B32, G32>(for_group::<B32, G32>(cy)));
        let y64 = G64::exp(tangent::<B64, G64>(for_group::<B64, G64>(cy)));
        let t32 = tangent::<B32, G32>(for_group::<B32, G32>(ct));
        let t64 = tangent::<B64, G64>(for_group::<B64, G64>(ct));
        let (p32, a32, b32) = x32.rplus_jac(t32);
        let (p64, a64, b64) = x64.rplus_jac(t64);
        let (m32, c32, d32) = y32.rminus_jac(x32);
        let (m64, c64, d64) = y64.rminus_jac(x64);
        let v = |a: C, b: C| {
            let s = b.iter().fold(1.0f64, |m, x| m.max(x.abs()));
            (0..12).fold(0.0f64, |m, i| m.max((a[i] - b[i]).abs())) / s
        };
        worst = worst
            .max(v(
                coords::<B32, G32>(p32.log()),
                coords::<B64, G64>(p64.log()),
            ))
            .max(v(coords::<B32, G32>(m32), coords::<B64, G64>(m64)));
        for (j32, j64) in [(a32, a64), (b32, b64), (c32, c64), (d32, d64)] {
            worst = testkit::nan_max(worst, rel(&jac::<B32, G32>(&j32), &jac::<B64, G64>(&j64)));
        }
    }
    worst
}

fn f32_agrees_with_f64_away_from_singular_points() {
    let w = [
        f32_vs_f64::<NalgebraF32, So3Mat<NalgebraF32>, NalgebraF64, So3Mat<NalgebraF64>>(),
        f32_vs_f64::<GlamF32, So3Quat<GlamF32>, GlamF64, So3Quat<GlamF64>>(),
        f32_vs_f64::<
            NalgebraF32,
            Se3<NalgebraF32, So3Mat<NalgebraF32>>,
            NalgebraF64,
            Se3<NalgebraF64, So3Mat<NalgebraF64>>,
        >(),
        f32_vs_f64::<
            GlamF32,
            Se3<GlamF32, So3Quat<GlamF32>>,
            GlamF64,
            Se3<GlamF64, So3Quat<GlamF64>>,
        >(),
        f32_vs_f64::<
            GlamF32A,
            Se3<GlamF32A, So3Mat<GlamF32A>>,
            GlamF64,
            Se3<GlamF64, So3Mat<GlamF64>>,
        >(),
        f32_vs_f64::<
            NalgebraF32,
            Se23<NalgebraF32, So3Mat<NalgebraF32>>,
            NalgebraF64,
            Se23<NalgebraF64, So3Mat<NalgebraF64>>,
        >(),
        f32_vs_f64::<
            GlamF32,
            Se23<GlamF32, So3Quat<GlamF32>>,
            GlamF64,
            Se23<GlamF64, So3Quat<GlamF64>>,
        >(),
        f32_vs_f64::<
            NalgebraF32,
            RigidState<NalgebraF32, So3Quat<NalgebraF32>>,
            NalgebraF64,
            RigidState<NalgebraF64, So3Quat<NalgebraF64>>,
        >(),
    ];
    let shown: Vec<String> = w.iter().map(|e| format!("{e:.1e}")).collect();
    println!("f32 vs f64, worst relative difference: {}", shown.join(" "));
    // ε_f32 = 1.2e-7 times the conditioning of log away from π (≲ 50).
    assert!(w.iter().all(|e| *e < 1e-5), "{w:?}");
}

fn jacobians_against_finite_differences() {
    println!(
        "worst |J_fd − J| / max(1, |J|) per operation (central differences; see `Point::floor`):"
    );
    // Central differences with h = 1e-6 (1e-7 near π): truncation h² ≈ 1e-12
    // relative, rounding ε/h ≈ 2e-10 per unit of the values (translations
    // of 1e3 included, against Jacobian entries of the same size).
    let tol = 1e-7;
    check::<NalgebraF64, So3Mat<NalgebraF64>>("nalgebra f64 So3Mat", tol);
    check::<NalgebraF64, So3Quat<NalgebraF64>>("nalgebra f64 So3Quat", tol);
    check::<GlamF64, So3Mat<GlamF64>>("glam f64 So3Mat", tol);
    check::<GlamF64, So3Quat<GlamF64>>("glam f64 So3Quat", tol);
    check::<NalgebraF64, Se3<NalgebraF64, So3Mat<NalgebraF64>>>("nalgebra f64 Se3<So3Mat>", tol);
    check::<NalgebraF64, Se3<NalgebraF64, So3Quat<NalgebraF64>>>("nalgebra f64 Se3<So3Quat>", tol);
    check::<GlamF64, Se3<GlamF64, So3Mat<GlamF64>>>("glam f64 Se3<So3Mat>", tol);
    check::<GlamF64, Se3<GlamF64, So3Quat<GlamF64>>>("glam f64 Se3<So3Quat>", tol);
    check::<NalgebraF64, RigidState<NalgebraF64, So3Mat<NalgebraF64>>>(
        "nalgebra f64 Rigid<So3Mat>",
        tol,
    );
    check::<NalgebraF64, RigidState<NalgebraF64, So3Quat<NalgebraF64>>>(
        "nalgebra f64 Rigid<So3Quat>",
        tol,
    );
    check::<GlamF64, RigidState<GlamF64, So3Mat<GlamF64>>>("glam f64 Rigid<So3Mat>", tol);
    check::<GlamF64, RigidState<GlamF64, So3Quat<GlamF64>>>("glam f64 Rigid<So3Quat>", tol);
    check::<NalgebraF64, Se23<NalgebraF64, So3Mat<NalgebraF64>>>("nalgebra f64 Se23<So3Mat>", tol);
    check::<NalgebraF64, Se23<NalgebraF64, So3Quat<NalgebraF64>>>(
        "nalgebra f64 Se23<So3Quat>",
        tol,
    );
    check::<GlamF64, Se23<GlamF64, So3Mat<GlamF64>>>("glam f64 Se23<So3Mat>", tol);
    check::<GlamF64, Se23<GlamF64, So3Quat<GlamF64>>>("glam f64 Se23<So3Quat>", tol);
}

fn main() {
    testkit::run(&[
        (
            "jacobians_against_finite_differences",
            jacobians_against_finite_differences,
        ),
        ("group_identities_to_rounding", group_identities_to_rounding),
        (
            "f32_agrees_with_f64_away_from_singular_points",
            f32_agrees_with_f64_away_from_singular_points,
        ),
    ]);
}
