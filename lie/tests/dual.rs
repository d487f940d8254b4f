//! The dual scalar: its real part is the `f64` computation bit for bit, and
//! its derivatives are the ones the group's closed-form Jacobians and
//! central differences give.
//!
//! Every group of the crate is checked the same way. With `τ̄` drawn at
//! random (angles up to π − 0.05, and exactly zero), the tangent is seeded
//! along its `DOF` coordinates and `Log(Exp(τ̄)⁻¹ · Exp(τ̄ + δ))` is
//! differentiated at `δ = 0`: by the definition of the right Jacobian the
//! result is `J_r(τ̄)`, which the crate computes in closed form, with no
//! dual number involved. The same with `Log(X̄ · Exp(δ))` gives `J_r⁻¹` at
//! `Log X̄`, through the logarithm near π.

use lie::{
    Dual, LieGroup, NalgebraDual, NalgebraF64, Real, RigidState, Se3, Se23, SimdReal, So3Mat,
    So3Quat,
};

mod common;
use common::Rng;

/// Enough directions for the largest group here (the rigid-body state, 12).
const D: usize = 12;
type Bd = NalgebraDual<D>;
type Bf = NalgebraF64;

fn angles(rng: &mut Rng, n: usize) -> Vec<f64> {
    // Zero, tiny (inside the series branches), moderate, near π.
    let mut out = vec![0.0, 1e-9, 1e-4, 0.3, 2.0, std::f64::consts::PI - 0.05];
    out.extend((0..n).map(|_| rng.range(0.0, std::f64::consts::PI - 0.05)));
    out
}

/// A tangent of `G` whose rotational parts have angle `angle` (the other
/// coordinates uniform in [−1, 1]).
fn tangent(rng: &mut Rng, dof: usize, angle: f64) -> Vec<f64> {
    let mut t: Vec<f64> = (0..dof).map(|_| rng.range(-1.0, 1.0)).collect();
    // Every group here keeps a rotation vector in coordinates 0..3 (SO(3)),
    // 3..6 (SE(3): ρ then φ) or 0..3 (the rigid-body state: φ, x, v, Ω).
    let r = if dof == 6 { 3 } else { 0 };
    let u = rng.unit();
    for k in 0..3 {
        t[r + k] = u[k] * angle;
    }
    t
}

/// The checks for one group: `Gf` on `f64`, `Gd` the same group on duals.
fn group_checks<Gf, Gd>(name: &str)
where
    Gf: LieGroup<Bf>,
    Gd: LieGroup<Bd>,
{
    let dof = Gf::DOF;
    let mut rng = Rng::new(0x5eed_d0a1);
    let (mut worst_jr, mut worst_inv) = (0.0f64, 0.0f64);
    for angle in angles(&mut rng, 40) {
        let t = tangent(&mut rng, dof, angle);
        let tf = Gf::tangent_from_fn(|i| t[i]);
        let seeded = Gd::tangent_from_fn(|i| Dual::variable(t[i], i));
        let fixed = Gd::tangent_from_fn(|i| Dual::constant(t[i]));

        // The real part of every operation is the f64 result, bit for bit.
        let (xf, xd) = (Gf::exp(tf), Gd::exp(fixed));
        let p = [0.3, -1.2, 2.5];
        let pf = NalgebraF64::vec3(p[0], p[1], p[2]);
        let pd = nalgebra::Vector3::from(p.map(Dual::constant));
        let (af, ad) = (xf.act(pf), xd.act(pd));
        for k in 0..3 {
            assert_eq!(
                ad[k].re.to_bits(),
                af[k].to_bits(),
                "{name}: act, angle {angle}"
            );
        }
        let (lf, ld) = (xf.log(), xd.log());
        let (jf, jd) = (Gf::right_jacobian(tf), Gd::right_jacobian(fixed));
        let (kf, kd) = (Gf::right_jacobian_inv(tf), Gd::right_jacobian_inv(fixed));
        for i in 0..dof {
            let (a, b) = (Gd::tangent_coord(&ld, i).re, Gf::tangent_coord(&lf, i));
            assert_eq!(a.to_bits(), b.to_bits(), "{name}: log[{i}], angle {angle}");
            for j in 0..dof {
                let (a, b) = (
                    Gd::jacobian_entry(&jd, i, j).re,
                    Gf::jacobian_entry(&jf, i, j),
                );
                assert_eq!(
                    a.to_bits(),
                    b.to_bits(),
                    "{name}: J_r[{i}][{j}], angle {angle}"
                );
                let (a, b) = (
                    Gd::jacobian_entry(&kd, i, j).re,
                    Gf::jacobian_entry(&kf, i, j),
                );
                assert_eq!(
                    a.to_bits(),
                    b.to_bits(),
                    "{name}: J_r⁻¹[{i}][{j}], angle {angle}"
                );
            }
        }

        // ∂/∂δ Log(Exp(τ̄)⁻¹ Exp(τ̄ + δ)) = J_r(τ̄).
        let rel = Gd::exp(seeded).rminus(xd);
        // ∂/∂δ Log(X̄ Exp(δ)) = J_r⁻¹(Log X̄).
        let delta = Gd::tangent_from_fn(|i| Dual::variable(0.0, i));
        let log_plus = xd.rplus(delta).log();
        let log_bar = Gf::tangent_from_fn(|i| Gd::tangent_coord(&ld, i).re);
        let jinv = Gf::right_jacobian_inv(log_bar);
        for i in 0..dof {
            let (c, l) = (Gd::tangent_coord(&rel, i), Gd::tangent_coord(&log_plus, i));
            assert!(
                c.is_finite() && l.is_finite(),
                "{name}: non-finite derivative at angle {angle}"
            );
            for j in 0..dof {
                let want = Gf::jacobian_entry(&jf, i, j);
                worst_jr = worst_jr.max((c.eps[j] - want).abs() / want.abs().max(1.0));
                let want = Gf::jacobian_entry(&jinv, i, j);
                worst_inv = worst_inv.max((l.eps[j] - want).abs() / want.abs().max(1.0));
            }
            for j in dof..D {
                assert_eq!(c.eps[j], 0.0, "{name}: unseeded direction {j} moved");
            }
        }
    }
    println!("{name}: worst |dual − J_r| {worst_jr:.1e}, |dual − J_r⁻¹| {worst_inv:.1e}");
    // Both sides are sums of a few dozen products of O(1) terms (J_r⁻¹
    // reaches 1/(π − θ) = 20 at the largest angle, hence the relative
    // measure), each rounded once: measured at 1e-15, and 100 ε leaves
    // room for other platforms' libm while a wrong derivative of any
    // elementary function (an O(1) error) fails by fourteen orders.
    assert!(
        worst_jr < 2e-14,
        "{name}: dual derivative of Exp vs J_r: {worst_jr:e}"
    );
    assert!(
        worst_inv < 2e-14,
        "{name}: dual derivative of Log vs J_r⁻¹: {worst_inv:e}"
    );
}

#[test]
fn so3_matrix() {
    group_checks::<So3Mat<Bf>, So3Mat<Bd>>("SO(3) matrix");
}

#[test]
fn so3_quaternion() {
    group_checks::<So3Quat<Bf>, So3Quat<Bd>>("SO(3) quaternion");
}

#[test]
fn se3_matrix() {
    group_checks::<Se3<Bf, So3Mat<Bf>>, Se3<Bd, So3Mat<Bd>>>("SE(3) matrix");
}

#[test]
fn se3_quaternion() {
    group_checks::<Se3<Bf, So3Quat<Bf>>, Se3<Bd, So3Quat<Bd>>>("SE(3) quaternion");
}

#[test]
fn se23_matrix() {
    group_checks::<Se23<Bf, So3Mat<Bf>>, Se23<Bd, So3Mat<Bd>>>("SE₂(3) matrix");
    group_checks::<Se23<Bf, So3Quat<Bf>>, Se23<Bd, So3Quat<Bd>>>("SE₂(3) quaternion");
}

#[test]
fn rigid_state() {
    group_checks::<RigidState<Bf, So3Mat<Bf>>, RigidState<Bd, So3Mat<Bd>>>("SO(3)×ℝ⁹ matrix");
    group_checks::<RigidState<Bf, So3Quat<Bf>>, RigidState<Bd, So3Quat<Bd>>>("SO(3)×ℝ⁹ quaternion");
}

/// Central difference of `f` at `x` with step `h`.
fn central(f: impl Fn(f64) -> f64, x: f64, h: f64) -> f64 {
    (f(x + h) - f(x - h)) / (2.0 * h)
}

/// Each elementary function: the real part is `f64`'s (bit for bit), and
/// the derivative matches a central difference (step 1e-6: truncation
/// `h² f‴/6` ≈ 1e-12 and rounding `ε|f|/h` ≈ 1e-10 for these arguments).
#[test]
fn elementary_functions() {
    type F = fn(Dual<1>) -> Dual<1>;
    type P = fn(f64) -> f64;
    let cases: [(&str, F, P, &[f64]); 14] = [
        ("sqrt", |x| x.sqrt(), f64::sqrt, &[0.3, 2.0, 1e6]),
        ("sin", |x| x.sin(), f64::sin, &[0.0, 0.7, -3.0]),
        ("cos", |x| x.cos(), f64::cos, &[0.0, 0.7, -3.0]),
        ("tan", |x| x.tan(), f64::tan, &[0.0, 0.7, -1.2]),
        ("asin", |x| x.asin(), f64::asin, &[0.0, 0.5, -0.9]),
        ("acos", |x| x.acos(), f64::acos, &[0.0, 0.5, -0.9]),
        ("atan", |x| x.atan(), f64::atan, &[0.0, 2.0, -0.4]),
        ("exp", |x| x.exp(), f64::exp, &[0.0, 1.5, -4.0]),
        ("ln", |x| x.ln(), f64::ln, &[0.1, 1.0, 30.0]),
        ("ln_1p", |x| x.ln_1p(), f64::ln_1p, &[1e-9, 0.5, 9.0]),
        ("cbrt", |x| x.cbrt(), f64::cbrt, &[-8.0, 0.3, 27.0]),
        ("powi 3", |x| x.powi(3), |x| x.powi(3), &[-1.3, 0.4, 2.0]),
        (
            "powf 2.5",
            |x| x.powf(Dual::constant(2.5)),
            |x| x.powf(2.5),
            &[0.4, 2.0, 7.0],
        ),
        ("abs", |x| x.abs(), f64::abs, &[-2.0, 3.0]),
    ];
    for (name, fd, ff, points) in cases {
        for &x in points {
            let y = fd(Dual::variable(x, 0));
            assert_eq!(y.re.to_bits(), ff(x).to_bits(), "{name}({x}): real part");
            let fdiff = central(ff, x, 1e-6);
            let tol = 1e-8 * fdiff.abs().max(1.0);
            assert!(
                (y.eps[0] - fdiff).abs() < tol,
                "{name}({x}): {} vs {fdiff}",
                y.eps[0]
            );
        }
    }
    // Two arguments, both seeded.
    let (y, x) = (Dual::<2>::variable(0.4, 0), Dual::<2>::variable(-1.1, 1));
    let a = y.atan2(x);
    assert_eq!(a.re.to_bits(), 0.4f64.atan2(-1.1).to_bits());
    let (dy, dx) = (
        central(|t| t.atan2(-1.1), 0.4, 1e-6),
        central(|t| 0.4f64.atan2(t), -1.1, 1e-6),
    );
    assert!(
        (a.eps[0] - dy).abs() < 1e-9 && (a.eps[1] - dx).abs() < 1e-9,
        "atan2: {a}"
    );
    let h = y.hypot(x);
    assert_eq!(h.re.to_bits(), 0.4f64.hypot(-1.1).to_bits());
    let (dy, dx) = (
        central(|t| t.hypot(-1.1), 0.4, 1e-6),
        central(|t| 0.4f64.hypot(t), -1.1, 1e-6),
    );
    assert!(
        (h.eps[0] - dy).abs() < 1e-9 && (h.eps[1] - dx).abs() < 1e-9,
        "hypot: {h}"
    );
    let p = y.powf(x);
    assert_eq!(p.re.to_bits(), 0.4f64.powf(-1.1).to_bits());
    let (dy, dx) = (
        central(|t| t.powf(-1.1), 0.4, 1e-6),
        central(|t| 0.4f64.powf(t), -1.1, 1e-6),
    );
    assert!(
        (p.eps[0] - dy).abs() < 1e-8 && (p.eps[1] - dx).abs() < 1e-8,
        "powf: {p}"
    );
    // Arithmetic: the quotient's real part is a division, not a · (1/b).
    let (a, b) = (Dual::<1>::variable(1.0, 0), Dual::<1>::constant(3.0));
    assert_eq!((a / b).re.to_bits(), (1.0f64 / 3.0).to_bits());
    assert_eq!((a / b).eps[0], 1.0 / 3.0);
}

/// Where the derivative does not exist, a live one becomes infinite (and
/// fails `is_finite`) while a zero one stays zero; branches and `max`
/// follow the real part.
#[test]
fn singular_points_and_branches() {
    let zero_live = Dual::<2>::variable(0.0, 0);
    let zero_dead = Dual::<2>::constant(0.0);
    assert_eq!(zero_dead.sqrt().eps, [0.0, 0.0]);
    assert!(zero_dead.sqrt().is_finite());
    assert!(!zero_live.sqrt().is_finite());
    assert_eq!(
        zero_live.sqrt().eps[1],
        0.0,
        "an unseeded direction stays exactly zero"
    );
    assert!(!zero_live.hypot(zero_dead).is_finite());
    assert!(zero_dead.hypot(zero_dead).is_finite());
    assert!(zero_dead.atan2(zero_dead).is_finite());
    assert!(!zero_live.atan2(zero_dead).is_finite());
    // Comparisons read the real part; `simd_eq` reads the derivatives too.
    let (a, b) = (Dual::<2>::variable(1.0, 0), Dual::<2>::variable(1.0, 1));
    assert!(a == b && a >= b && a <= b);
    assert!(!a.simd_eq(b) && a.simd_eq(a));
    // Every direction is read (the last one of three vectors' worth too),
    // and the value; a NaN derivative is equal to nothing.
    let c = Dual::<12>::variable(1.0, 11);
    let mut d = c;
    d.eps[11] = 0.5;
    assert!(!c.simd_eq(d) && c.simd_eq(c));
    assert!(!c.simd_eq(Dual::variable(1.5, 11)));
    d.eps[11] = f64::NAN;
    assert!(!d.simd_eq(d));
    // The checks of finiteness and the zero test read the last direction.
    assert!(Real::is_nan(d) && !Real::is_finite(d) && Real::is_finite(c));
    assert!(!Real::is_nan(c));
    let mut z = Dual::<12>::constant(0.0);
    assert!(num_traits::Zero::is_zero(&z));
    z.eps[11] = 1e-300;
    assert!(!num_traits::Zero::is_zero(&z));
    let m = Real::max(Dual::<2>::variable(2.0, 1), a);
    assert_eq!((m.re, m.eps), (2.0, [0.0, 1.0]));
    let nan = Dual::<2>::nan();
    assert_eq!(
        Real::max(nan, a).eps,
        a.eps,
        "max ignores a NaN operand, as f64::max"
    );
    assert!(Dual::<2>::variable(1.0, 0).is_finite());
    assert!(
        !Dual::<2> {
            re: 1.0,
            eps: [f64::NAN, 0.0]
        }
        .is_finite()
    );
}

/// The dual backend writes its matrix products out instead of calling
/// nalgebra's operators (which stay out of line for a scalar this wide):
/// the results must be the operators' own, bit for bit, in the real part
/// (against `f64`) and in every derivative (against the operator on duals).
#[test]
fn explicit_products_are_the_operators() {
    use nalgebra::{Matrix3, Vector3};
    let mut rng = Rng::new(7);
    let dual = |rng: &mut Rng| {
        let mut d = Dual::<D>::constant(rng.range(-3.0, 3.0));
        for e in &mut d.eps {
            *e = rng.range(-2.0, 2.0);
        }
        d
    };
    let same = |a: Dual<D>, b: Dual<D>| {
        a.re.to_bits() == b.re.to_bits() && a.eps.iter().zip(&b.eps).all(|(x, y)| x == y)
    };
    for _ in 0..200 {
        let a = Matrix3::from_fn(|_, _| dual(&mut rng));
        let b = Matrix3::from_fn(|_, _| dual(&mut rng));
        let v = Vector3::from_fn(|_, _| dual(&mut rng));
        let (af, bf, vf) = (a.map(|x| x.re), b.map(|x| x.re), v.map(|x| x.re));
        let ab = Bd::mat3_mul(a, b);
        let av = Bd::mat3_mul_vec(a, v);
        let atv = Bd::mat3_tr_mul_vec(a, v);
        assert!(
            ab.iter()
                .zip((af * bf).iter())
                .all(|(d, f)| d.re.to_bits() == f.to_bits())
        );
        assert!(
            av.iter()
                .zip((af * vf).iter())
                .all(|(d, f)| d.re.to_bits() == f.to_bits())
        );
        assert!(
            atv.iter()
                .zip(af.tr_mul(&vf).iter())
                .all(|(d, f)| d.re.to_bits() == f.to_bits())
        );
        assert!(ab.iter().zip((a * b).iter()).all(|(x, y)| same(*x, *y)));
        assert!(av.iter().zip((a * v).iter()).all(|(x, y)| same(*x, *y)));
        assert!(
            atv.iter()
                .zip(a.tr_mul(&v).iter())
                .all(|(x, y)| same(*x, *y))
        );
    }
}
