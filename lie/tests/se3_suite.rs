//! The SE(3) suite for the four (backend, scalar) pairs and both rotation
//! representations, plus the f32-against-f64 comparison of every SO(3) and
//! SE(3) formula on the same inputs.

mod common;
use common::*;
use lie::{Backend, Real, Rotation, Se3, Twist, V3};

const PI: f64 = std::f64::consts::PI;

type A6 = [f64; 6];
fn tw<B: Backend>(a: A6) -> Twist<B> {
    Twist::from_array(a.map(s::<B>))
}
fn tw64<B: Backend>(t: Twist<B>) -> A6 {
    t.to_array().map(|x| x.to_f64_lossless())
}
fn rand_twist(rng: &mut Rng, max_angle: f64) -> A6 {
    let (r, p) = (
        scale(rng.unit(), rng.range(0.0, 3.0)),
        rng.rotvec(max_angle),
    );
    [r[0], r[1], r[2], p[0], p[1], p[2]]
}
fn d6(a: A6, b: A6) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}
fn h4<B: Backend, R: Rotation<B>>(x: Se3<B, R>) -> [[f64; 4]; 4] {
    x.to_homogeneous().map(|r| r.map(|v| v.to_f64_lossless()))
}
fn d44(a: [[f64; 4]; 4], b: [[f64; 4]; 4]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).powi(2))
        .sum::<f64>()
        .sqrt()
}
fn tag<B: Backend, R: Rotation<B>>() -> String {
    format!("[{} {}]", B::NAME, R::REPR)
}

pub fn se3_group_and_exp_log<B: Backend, R: Rotation<B>>() {
    let e = eps::<B>();
    let mut rng = Rng::new(21);
    let (mut w_ax, mut w_rt, mut w_series, mut w_v) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for _ in 0..300 {
        let xi = rand_twist(&mut rng, PI - 1e-3);
        let xi = tw64::<B>(tw::<B>(xi)); // rounded to the backend's precision
        let x = Se3::<B, R>::exp(tw::<B>(xi));
        let y = Se3::<B, R>::exp(tw::<B>(rand_twist(&mut rng, PI)));
        let z = Se3::<B, R>::exp(tw::<B>(rand_twist(&mut rng, PI)));
        let p = rng.unit();
        w_ax = w_ax
            .max(d44(h4((x * y) * z), h4(x * (y * z))))
            .max(d44(h4(x * x.inverse()), h4(Se3::<B, R>::identity())))
            .max(dist(
                v64::<B>((x * y).act(vb::<B>(p))),
                v64::<B>(x.act(y.act(vb::<B>(p)))),
            ));
        // log∘exp, relative to the twist's size (the translation is up to 3).
        w_rt = w_rt.max(d6(tw64::<B>(x.log()), xi) / (1.0 + d6(xi, [0.0; 6])));
        // exp against the series exponential of the 4×4 ξ^.
        let hat = tw::<B>(xi).hat().map(|r| r.map(|v| v.to_f64_lossless()));
        w_series = w_series.max(d44(h4(x), expm(hat)));
        // the V matrix: translation of exp(ξ^) = J_l(φ) ρ
        let jl = m64::<B>(lie::left_jacobian::<B>(vb::<B>([xi[3], xi[4], xi[5]])));
        let t_ref = expm(hat);
        let jr = mmul(
            jl,
            [[xi[0], 0.0, 0.0], [xi[1], 0.0, 0.0], [xi[2], 0.0, 0.0]],
        );
        w_v = w_v.max(dist(
            [jr[0][0], jr[1][0], jr[2][0]],
            [t_ref[0][3], t_ref[1][3], t_ref[2][3]],
        ));
        // hat/vee round trip
        assert_eq!(tw64::<B>(Twist::<B>::vee(tw::<B>(xi).hat())), xi);
    }
    println!(
        "{} SE(3): axioms {w_ax:.1e}, log∘exp (relative) {w_rt:.1e}, exp vs 4×4 series {w_series:.1e}, J_l ρ vs series translation {w_v:.1e}",
        tag::<B, R>()
    );
    // Translations up to ~6 after composing: 64 ε absolute.
    assert!(
        w_ax < 64.0 * e && w_series < 64.0 * e && w_v < 64.0 * e,
        "{w_ax:e} {w_series:e} {w_v:e}"
    );
    // The project's round-trip targets for SO(3) (1e-12 in f64, 2e-6 in f32),
    // relative to the twist's size since J_l⁻¹ scales errors by |ρ|.
    let tol_rt = if is_f64::<B>() { 1e-12 } else { 2e-6 };
    assert!(w_rt < tol_rt, "{w_rt:e}");
}

pub fn se3_adjoint_and_jacobian<B: Backend, R: Rotation<B>>() {
    let e = eps::<B>();
    let (h, tol) = if is_f64::<B>() {
        (1e-5, 1e-8)
    } else {
        (1e-2, 3e-3)
    };
    let mut rng = Rng::new(22);
    let (mut w_ad, mut w_j) = (0.0f64, 0.0f64);
    let mut cases: Vec<A6> = (0..60).map(|_| rand_twist(&mut rng, 2.5)).collect();
    for th in [0.0, 1e-6, 0.3, 1.0] {
        let (r, p) = (rng.unit(), rng.unit());
        cases.push([r[0], r[1], r[2], p[0] * th, p[1] * th, p[2] * th]);
    }
    for xi in cases {
        let xi = tw64::<B>(tw::<B>(xi));
        let x = Se3::<B, R>::exp(tw::<B>(xi));
        // Ad by conjugation: exp((Ad η)^) = X exp(η^) X⁻¹
        let eta = rand_twist(&mut rng, 1.0);
        let ad = x.adjoint().map(|r| r.map(|v| v.to_f64_lossless()));
        let mut ad_eta = [0.0; 6];
        for (i, row) in ad.iter().enumerate() {
            ad_eta[i] = row.iter().zip(eta).map(|(a, b)| a * b).sum();
        }
        let lhs = Se3::<B, R>::exp(tw::<B>(ad_eta));
        let rhs = x * Se3::<B, R>::exp(tw::<B>(eta)) * x.inverse();
        w_ad = w_ad.max(d44(h4(lhs), h4(rhs)));
        // Left Jacobian: exp(ξ + δ) ≈ exp(J δ) exp(ξ), central differences.
        let j = lie::se3_left_jacobian::<B>(tw::<B>(xi)).map(|r| r.map(|v| v.to_f64_lossless()));
        for c in 0..6 {
            let mut d = [0.0; 6];
            d[c] = h;
            let plus: A6 = core::array::from_fn(|i| xi[i] + d[i]);
            let minus: A6 = core::array::from_fn(|i| xi[i] - d[i]);
            let lp = tw64::<B>((Se3::<B, R>::exp(tw::<B>(plus)) * x.inverse()).log());
            let lm = tw64::<B>((Se3::<B, R>::exp(tw::<B>(minus)) * x.inverse()).log());
            for r in 0..6 {
                w_j = w_j.max(((lp[r] - lm[r]) / (2.0 * h) - j[r][c]).abs());
            }
        }
    }
    println!(
        "{} SE(3): adjoint by conjugation {w_ad:.1e}, left Jacobian vs central FD {w_j:.1e}",
        tag::<B, R>()
    );
    // Translations up to ~10 after conjugation, a few roundings each.
    assert!(w_ad < 64.0 * e, "{w_ad:e}");
    assert!(w_j < tol, "{w_j:e}");
}

macro_rules! se3_suite {
    ($($modname:ident: $backend:ty, $rep:ident;)*) => {$(
        mod $modname {
            type B = $backend;
            type R = lie::$rep<B>;
            #[test] fn se3_group_and_exp_log() { super::se3_group_and_exp_log::<B, R>() }
            #[test] fn se3_adjoint_and_jacobian() { super::se3_adjoint_and_jacobian::<B, R>() }
        }
    )*};
}

se3_suite! {
    nalgebra_f32_matrix: lie::NalgebraF32, So3Mat;
    nalgebra_f32_quaternion: lie::NalgebraF32, So3Quat;
    nalgebra_f64_matrix: lie::NalgebraF64, So3Mat;
    nalgebra_f64_quaternion: lie::NalgebraF64, So3Quat;
    glam_f32_matrix: lie::GlamF32, So3Mat;
    glam_f32_quaternion: lie::GlamF32, So3Quat;
    glam_f64_matrix: lie::GlamF64, So3Mat;
    glam_f64_quaternion: lie::GlamF64, So3Quat;
    glam_f32a_matrix: lie::GlamF32A, So3Mat;
    glam_f32a_quaternion: lie::GlamF32A, So3Quat;
}

/// The same inputs through an f32 pair and its f64 twin; the worst
/// differences are printed in the test output.
fn f32_against_f64<B32: Backend, B64: Backend, R32: Rotation<B32>, R64: Rotation<B64>>() {
    let mut rng = Rng::new(23);
    let mut w = [0.0f64; 7];
    for i in 0..3000 {
        let max_angle = if i % 3 == 0 { 0.05 } else { PI - 1e-3 };
        let phi = v64::<B32>(vb::<B32>(rng.rotvec(max_angle))); // exactly representable in f32
        let rho = v64::<B32>(vb::<B32>(rng.unit()));
        let (p32, p64): (V3<B32>, V3<B64>) = (vb::<B32>(phi), vb::<B64>(phi));
        let (r32, r64) = (R32::exp(p32), R64::exp(p64));
        w[0] = w[0].max(mdist(m64::<B32>(r32.matrix()), m64::<B64>(r64.matrix())));
        w[1] = w[1].max(dist(v64::<B32>(r32.log()), v64::<B64>(r64.log())));
        w[2] = w[2].max(mdist(
            m64::<B32>(lie::left_jacobian::<B32>(p32)),
            m64::<B64>(lie::left_jacobian::<B64>(p64)),
        ));
        w[3] = w[3].max(mdist(
            m64::<B32>(lie::right_jacobian_inv::<B32>(p32)),
            m64::<B64>(lie::right_jacobian_inv::<B64>(p64)),
        ));
        let q32 = m64::<B32>(lie::q_block::<B32>(vb::<B32>(rho), p32));
        let q64 = m64::<B64>(lie::q_block::<B64>(vb::<B64>(rho), p64));
        w[4] = w[4].max(mdist(q32, q64));
        let rd = rng.rotvec(PI);
        let (d32, d64) = (R32::exp(vb::<B32>(rd)), R64::exp(vb::<B64>(rd)));
        w[5] = w[5].max((r32.psi(d32).to_f64_lossless() - r64.psi(d64).to_f64_lossless()).abs());
        w[6] = w[6].max(dist(v64::<B32>(r32.e_r(d32)), v64::<B64>(r64.e_r(d64))));
    }
    println!(
        "[{} vs {} {}] worst f32−f64: exp {:.1e}, log {:.1e}, J_l {:.1e}, J_r⁻¹ {:.1e}, SE(3) Q {:.1e}, Ψ {:.1e}, e_R {:.1e}",
        B32::NAME,
        B64::NAME,
        R32::REPR,
        w[0],
        w[1],
        w[2],
        w[3],
        w[4],
        w[5],
        w[6]
    );
    // f32 rounding (6e-8) through a handful of operations: ~16 ε of f32;
    // the log gets the f32 target of 2e-6 rad.
    let bounds = [2e-6, 2e-6, 2e-6, 2e-6, 2e-6, 2e-6, 2e-6];
    for (k, (wk, bk)) in w.iter().zip(bounds).enumerate() {
        assert!(wk <= &bk, "quantity {k}: {wk:e} > {bk:e}");
    }
}

#[test]
fn f32_vs_f64_nalgebra_matrix() {
    f32_against_f64::<lie::NalgebraF32, lie::NalgebraF64, lie::So3Mat<_>, lie::So3Mat<_>>();
}
#[test]
fn f32_vs_f64_nalgebra_quaternion() {
    f32_against_f64::<lie::NalgebraF32, lie::NalgebraF64, lie::So3Quat<_>, lie::So3Quat<_>>();
}
#[test]
fn f32_vs_f64_glam_matrix() {
    f32_against_f64::<lie::GlamF32, lie::GlamF64, lie::So3Mat<_>, lie::So3Mat<_>>();
}
#[test]
fn f32_vs_f64_glam_quaternion() {
    f32_against_f64::<lie::GlamF32, lie::GlamF64, lie::So3Quat<_>, lie::So3Quat<_>>();
}
#[test]
fn f32_vs_f64_glam_simd_matrix() {
    f32_against_f64::<lie::GlamF32A, lie::GlamF64, lie::So3Mat<_>, lie::So3Mat<_>>();
}
