//! The SE₂(3) suite for every (backend, scalar) pair and both rotation
//! representations: the group against its 5×5 matrices (product, inverse,
//! the series exponential of `τ^`), log∘exp from zero angle to π, hat and
//! vee, the adjoint by conjugation, and the left Jacobian and its closed-form
//! inverse against each other and against central differences at the hard
//! angles. The trait-level checks (every Jacobian of ⊕, ⊖, compose, inverse,
//! between and the action against finite differences, f32 against f64,
//! dual derivatives) run in `group.rs` and `dual.rs` with the other groups.

mod common;
use common::*;
use lie::{Backend, ExtTwist, LieGroup, Real, Rotation, Se23};

const PI: f64 = std::f64::consts::PI;

type A9 = [f64; 9];
type M5 = [[f64; 5]; 5];

fn tw<B: Backend>(a: A9) -> ExtTwist<B> {
    ExtTwist::from_array(a.map(s::<B>))
}
fn tw64<B: Backend>(t: ExtTwist<B>) -> A9 {
    t.to_array().map(|x| x.to_f64_lossless())
}
fn m5<B: Backend, R: Rotation<B>>(x: Se23<B, R>) -> M5 {
    x.to_matrix().map(|r| r.map(|v| v.to_f64_lossless()))
}
fn mul5(a: M5, b: M5) -> M5 {
    core::array::from_fn(|i| core::array::from_fn(|j| (0..5).map(|k| a[i][k] * b[k][j]).sum()))
}
fn d55(a: M5, b: M5) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}
fn dmax(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}
/// A tangent with rotation angle `angle` about a random axis and position
/// and velocity parts of norm up to 3.
fn tangent(rng: &mut Rng, angle: f64) -> A9 {
    let (r, n, a) = (
        scale(rng.unit(), rng.range(0.0, 3.0)),
        scale(rng.unit(), rng.range(0.0, 3.0)),
        scale(rng.unit(), angle),
    );
    [r[0], r[1], r[2], n[0], n[1], n[2], a[0], a[1], a[2]]
}
fn tag<B: Backend, R: Rotation<B>>() -> String {
    format!("[{} {}]", B::NAME, R::REPR)
}

fn matrices_and_exp_log<B: Backend, R: Rotation<B>>() {
    let e = eps::<B>();
    let mut rng = Rng::new(31);
    let (mut w_mat, mut w_series, mut w_rt) = (0.0f64, 0.0f64, 0.0f64);
    let mut angles: Vec<f64> = (0..200).map(|_| rng.range(0.0, PI - 1e-3)).collect();
    angles.extend(hard_angles::<S<B>>());
    for angle in angles {
        let xi = tw64::<B>(tw::<B>(tangent(&mut rng, angle)));
        let x = Se23::<B, R>::exp(tw::<B>(xi));
        let ay = rng.range(0.0, PI);
        let y = Se23::<B, R>::exp(tw::<B>(tangent(&mut rng, ay)));
        // The group is the 5×5 matrices: product and inverse.
        w_mat = w_mat.max(d55(m5(x * y), mul5(m5(x), m5(y)))).max(d55(
            mul5(m5(x.inverse()), m5(x)),
            m5(Se23::<B, R>::identity()),
        ));
        // exp against the Taylor series of the 5×5 τ^ (independent of
        // every closed form and small-angle branch).
        let hat = tw::<B>(xi).hat().map(|r| r.map(|v| v.to_f64_lossless()));
        w_series = w_series.max(d55(m5(x), expm(hat)));
        // log∘exp, relative to the tangent's size (J_l⁻¹ scales the
        // translation parts' errors by their size).
        let size = 1.0 + xi.iter().map(|v| v * v).sum::<f64>().sqrt();
        w_rt = w_rt.max(dmax(&tw64::<B>(x.log()), &xi) / size);
        assert_eq!(tw64::<B>(ExtTwist::<B>::vee(tw::<B>(xi).hat())), xi);
    }
    println!(
        "{} SE₂(3): 5×5 product/inverse {w_mat:.1e}, exp vs 5×5 series {w_series:.1e}, log∘exp (relative) {w_rt:.1e}",
        tag::<B, R>()
    );
    // Entries up to ~10 after composing, a few roundings each.
    assert!(
        w_mat < 64.0 * e && w_series < 64.0 * e,
        "{w_mat:e} {w_series:e}"
    );
    // SO(3)'s round-trip targets (1e-12 in f64, 2e-6 in f32), relative.
    let tol = if is_f64::<B>() { 1e-12 } else { 2e-6 };
    assert!(w_rt < tol, "{w_rt:e}");
}

/// Log at and next to π: the rotation part's log is SO(3)'s (a unit axis
/// up to sign at π), and the translation parts come back through J_l⁻¹,
/// finite up to 2π.
fn log_near_pi<B: Backend, R: Rotation<B>>() {
    let mut rng = Rng::new(32);
    let mut worst = 0.0f64;
    for axis in axes() {
        for gap in [1e-3, 1e-6, 0.0] {
            let a = scale(axis, PI - gap);
            let mut xi = tangent(&mut rng, 1.0);
            xi[6..].copy_from_slice(&a);
            let xi = tw64::<B>(tw::<B>(xi));
            let x = Se23::<B, R>::exp(tw::<B>(xi));
            let back = Se23::<B, R>::exp(x.log());
            worst = worst.max(d55(m5(back), m5(x)));
        }
    }
    println!(
        "{} SE₂(3): Exp(Log X) = X at π − {{1e-3, 1e-6, 0}}: {worst:.1e}",
        tag::<B, R>()
    );
    // Exp∘Log as matrices is well conditioned even where Log's sign
    // flips at π: entries of size ~3, a few dozen roundings.
    let tol = if is_f64::<B>() { 1e-13 } else { 4e-6 };
    assert!(worst < tol, "{worst:e}");
}

fn adjoint_and_jacobians<B: Backend, R: Rotation<B>>() {
    let e = eps::<B>();
    let (h, tol) = if is_f64::<B>() {
        (1e-5, 1e-8)
    } else {
        (1e-2, 3e-3)
    };
    let mut rng = Rng::new(33);
    let (mut w_ad, mut w_j, mut w_inv) = (0.0f64, 0.0f64, 0.0f64);
    let mut angles: Vec<f64> = (0..40).map(|_| rng.range(0.0, 2.5)).collect();
    angles.extend([0.0, 1e-6, 0.3, 1.0]);
    for angle in angles {
        let xi = tw64::<B>(tw::<B>(tangent(&mut rng, angle)));
        let x = Se23::<B, R>::exp(tw::<B>(xi));
        // Ad by conjugation: Exp(Ad η) = X Exp(η) X⁻¹.
        let eta = tangent(&mut rng, 1.0);
        let ad_eta = tw64::<B>(Se23::<B, R>::jacobian_apply(&x.adjoint(), tw::<B>(eta)));
        let lhs = Se23::<B, R>::exp(tw::<B>(ad_eta));
        let rhs = x * Se23::<B, R>::exp(tw::<B>(eta)) * x.inverse();
        w_ad = w_ad.max(d55(m5(lhs), m5(rhs)));
        // The left Jacobian: Exp(ξ + δ) ≈ Exp(J δ) Exp(ξ), central
        // differences of the 5×5-matrix-free group operations.
        let j = lie::se23_left_jacobian::<B>(tw::<B>(xi));
        let jf = j.map(|r| r.map(|v| v.to_f64_lossless()));
        for c in 0..9 {
            let step = |sign: f64| -> A9 {
                let d: A9 = core::array::from_fn(|i| xi[i] + if i == c { sign * h } else { 0.0 });
                tw64::<B>((Se23::<B, R>::exp(tw::<B>(d)) * x.inverse()).log())
            };
            let (lp, lm) = (step(1.0), step(-1.0));
            for (r, row) in jf.iter().enumerate() {
                w_j = w_j.max(((lp[r] - lm[r]) / (2.0 * h) - row[c]).abs());
            }
        }
        // The closed-form inverse against the product.
        let ii = lie::mul9(&lie::se23_left_jacobian_inv::<B>(tw::<B>(xi)), &j);
        for (r, row) in ii.iter().enumerate() {
            for (c, v) in row.iter().enumerate() {
                let want = if r == c { 1.0 } else { 0.0 };
                w_inv = w_inv.max((v.to_f64_lossless() - want).abs());
            }
        }
    }
    println!(
        "{} SE₂(3): adjoint by conjugation {w_ad:.1e}, J_l vs central FD {w_j:.1e}, J_l⁻¹·J_l − I {w_inv:.1e}",
        tag::<B, R>()
    );
    // Translations up to ~10 after conjugation, a few roundings each.
    assert!(w_ad < 64.0 * e, "{w_ad:e}");
    assert!(w_j < tol, "{w_j:e}");
    // Off-diagonal blocks of size ~|ρ| ≤ 3 times a few ε.
    assert!(w_inv < 64.0 * e, "{w_inv:e}");
}

type S<B> = <B as lie::SimdBackend>::Scalar;

macro_rules! se23_suite {
    ($($modname:ident: $backend:ty, $rep:ident;)*) => {$(
        mod $modname {
            type B = $backend;
            type R = lie::$rep<B>;
            #[test] fn matrices_and_exp_log() { super::matrices_and_exp_log::<B, R>() }
            #[test] fn log_near_pi() { super::log_near_pi::<B, R>() }
            #[test] fn adjoint_and_jacobians() { super::adjoint_and_jacobians::<B, R>() }
        }
    )*};
}

se23_suite! {
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
