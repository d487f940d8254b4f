//! The SO(3) suite, written once and instantiated for the four (backend,
//! scalar) pairs and both representations (rotation matrix, unit
//! quaternion). Run with `--nocapture` to see the worst errors measured.
//!
//! Tolerances are in units of the scalar's ε (`e` below) unless the project
//! fixes an absolute figure (the log∘exp round trip: 1e-12 in f64, 2e-6 in
//! f32). Each says why it is that size.

mod common;
use common::*;

use lie::{Backend, Real, Rotation, V3};

const PI: f64 = std::f64::consts::PI;

fn tag<B: Backend, R: Rotation<B>>() -> String {
    format!("[{} {}]", B::NAME, R::REPR)
}
fn exp_b<B: Backend, R: Rotation<B>>(phi: A3) -> R {
    R::exp(vb::<B>(phi))
}
fn log64<B: Backend, R: Rotation<B>>(r: R) -> A3 {
    v64::<B>(r.log())
}
/// `φ` rounded to the backend's precision, so that errors measure the
/// formulas and not the rounding of the input.
fn rounded<B: Backend>(phi: A3) -> A3 {
    v64::<B>(vb::<B>(phi))
}

pub fn group_axioms<B: Backend, R: Rotation<B>>() {
    let e = eps::<B>();
    let mut rng = Rng::new(1);
    let mut worst = 0.0f64;
    for _ in 0..300 {
        let (a, b, c) = (
            exp_b::<B, R>(rng.rotvec(PI)),
            exp_b::<B, R>(rng.rotvec(PI)),
            exp_b::<B, R>(rng.rotvec(PI)),
        );
        let v = rng.unit();
        let vb_ = vb::<B>(v);
        // Associativity, identity, inverse, action of a product, isometry.
        worst = testkit::nan_max(
            worst,
            mdist(
                m64::<B>(((a * b) * c).matrix()),
                m64::<B>((a * (b * c)).matrix()),
            ),
        );
        worst = testkit::nan_max(
            worst,
            mdist(m64::<B>((a * R::identity()).matrix()), m64::<B>(a.matrix())),
        );
        worst = testkit::nan_max(worst, mdist(m64::<B>((a * a.inverse()).matrix()), I3));
        worst = testkit::nan_max(
            worst,
            dist(v64::<B>((a * b).act(vb_)), v64::<B>(a.act(b.act(vb_)))),
        );
        worst = testkit::nan_max(worst, dist(v64::<B>(a.inverse_act(a.act(vb_))), v)); // v is unit
        worst = testkit::nan_max(worst, (norm(v64::<B>(a.act(vb_))) - 1.0).abs());
        worst = testkit::nan_max(worst, a.orthogonality_error().to_f64_lossless());
    }
    println!(
        "{} group axioms: worst deviation {worst:.2e}",
        tag::<B, R>()
    );
    // A handful of products each adding ~1 ulp per element on 3×3 sums:
    // 30 ε bounds it with margin.
    assert!(worst < 30.0 * e, "{worst:e}");
}

pub fn hat_vee<B: Backend, R: Rotation<B>>() {
    let e = eps::<B>();
    let mut rng = Rng::new(2);
    for _ in 0..100 {
        let (x, y) = (scale(rng.unit(), 2.0), rng.unit());
        let hx = lie::hat::<B>(vb::<B>(x));
        assert!(
            dist(
                v64::<B>(hx * vb::<B>(y)),
                cross(rounded::<B>(x), rounded::<B>(y))
            ) < 8.0 * e
        );
        assert_eq!(v64::<B>(lie::vee::<B>(hx)), rounded::<B>(x));
    }
}

/// log∘exp and exp∘log on random elements and on the hard list.
pub fn exp_log_roundtrip<B: Backend, R: Rotation<B>>() {
    let tol = if is_f64::<B>() { 1e-12 } else { 2e-6 };
    let mut rng = Rng::new(3);
    let mut worst = 0.0f64;
    let mut worst_at = 0.0f64;
    let mut cases: Vec<A3> = (0..2000).map(|_| rng.rotvec(PI - 1e-6)).collect();
    for axis in axes() {
        for th in hard_angles::<lie::S<B>>() {
            cases.push(scale(axis, th));
            cases.push(scale(axis, -th));
        }
    }
    for phi in cases {
        let phi = rounded::<B>(phi);
        let err = dist(log64::<B, R>(exp_b::<B, R>(phi)), phi);
        if err > worst {
            (worst, worst_at) = (err, norm(phi));
        }
    }
    println!(
        "{} log∘exp worst error for angles ≤ π−1e-6: {worst:.2e} rad (at θ = {worst_at:.6}), bound {tol:e}",
        tag::<B, R>()
    );
    assert!(worst <= tol, "{worst:e} at θ = {worst_at}");

    // exp∘log on random rotations.
    let mut worst_el = 0.0f64;
    for _ in 0..1000 {
        let r = exp_b::<B, R>(rng.rotvec(PI));
        worst_el = worst_el.max(mdist(
            m64::<B>(R::exp(r.log()).matrix()),
            m64::<B>(r.matrix()),
        ));
    }
    println!(
        "{} exp∘log worst error on random rotations: {worst_el:.2e}",
        tag::<B, R>()
    );
    assert!(worst_el <= tol, "{worst_el:e}");
}

/// log at π − 1e-9 and at exactly π, about several axes: the angle must be
/// π and exp∘log must give back the rotation (the sign of the axis is free).
pub fn log_at_exactly_pi<B: Backend, R: Rotation<B>>() {
    let (tol_angle, tol_rot) = if is_f64::<B>() {
        (1e-12, 1e-12)
    } else {
        (1e-6, 1e-6)
    };
    let mut worst_angle = 0.0f64;
    let mut worst_rot = 0.0f64;
    let mut rng = Rng::new(4);
    let mut axes_ = axes();
    axes_.extend((0..50).map(|_| rng.unit()));
    for axis in axes_ {
        for th in [PI - 1e-9, PI] {
            let pi_b = <lie::S<B> as lie::Real>::pi().to_f64_lossless();
            let th_b = if th == PI { pi_b } else { th };
            let phi = vb::<B>(scale(axis, th_b));
            let r = R::exp(phi);
            let l = r.log();
            // Expected angle: the one the backend's exp actually encoded.
            let expected = (rounded::<B>([th_b, 0.0, 0.0])[0]).min(pi_b);
            worst_angle = worst_angle.max((norm(v64::<B>(l)) - expected).abs());
            worst_rot = worst_rot.max(mdist(m64::<B>(R::exp(l).matrix()), m64::<B>(r.matrix())));
        }
    }
    println!(
        "{} at angle π (and π−1e-9): |angle(log R) − π| ≤ {worst_angle:.2e}, ‖exp(log R) − R‖ ≤ {worst_rot:.2e}",
        tag::<B, R>()
    );
    assert!(worst_angle <= tol_angle, "{worst_angle:e}");
    assert!(worst_rot <= tol_rot, "{worst_rot:e}");
}

/// exp against a 30-term scaled-and-squared series of `hat(φ)`: catches
/// sign and coefficient errors in the small-angle branches, which round
/// trips cannot see.
pub fn exp_matches_series<B: Backend, R: Rotation<B>>() {
    let e = eps::<B>();
    let mut rng = Rng::new(5);
    let mut cases: Vec<A3> = (0..500).map(|_| rng.rotvec(PI)).collect();
    for axis in axes() {
        for th in hard_angles::<lie::S<B>>().into_iter().chain([PI]) {
            cases.push(scale(axis, th));
        }
    }
    let mut worst = 0.0f64;
    for phi in cases {
        let phi = rounded::<B>(phi);
        let reference = expm(hat64(phi));
        worst = testkit::nan_max(
            worst,
            mdist(m64::<B>(exp_b::<B, R>(phi).matrix()), reference),
        );
    }
    println!(
        "{} exp vs series matrix exponential: worst {worst:.2e}",
        tag::<B, R>()
    );
    // sin/cos are within 1 ulp and each element sums three terms (~4 ε);
    // the f64 reference carries ~6 ε of its own (measured 1.3e-15 against
    // the f64 backends). 16 ε covers both.
    assert!(worst < 16.0 * e, "{worst:e}");
}

/// Central finite differences step: balances truncation `h²` against
/// rounding `ε/h`.
fn fd_step<B: Backend>() -> f64 {
    if is_f64::<B>() { 1e-5 } else { 1e-2 }
}
/// FD tolerance: truncation `h²·|third derivative| ≲ h²` plus rounding
/// `ε/h` (f64: 1e-10 + 1e-11; f32: 1e-4 + 6e-6), times a safety factor.
fn fd_tol<B: Backend>() -> f64 {
    if is_f64::<B>() { 1e-8 } else { 2e-3 }
}

fn col_dist(j: A33, col: usize, v: A3) -> f64 {
    dist([j[0][col], j[1][col], j[2][col]], v)
}

/// Every SO(3) Jacobian against central finite differences, and J·J⁻¹ = I.
pub fn jacobians_match_finite_differences<B: Backend, R: Rotation<B>>() {
    let (h, tol, e) = (fd_step::<B>(), fd_tol::<B>(), eps::<B>());
    let mut rng = Rng::new(6);
    let mut cases: Vec<A3> = (0..60).map(|_| rng.rotvec(3.0)).collect();
    for axis in axes() {
        for th in [0.0, 1e-8, 1e-4, 0.3, 1.0, 1.5, 2.5] {
            cases.push(scale(axis, th));
        }
    }
    let (mut w_l, mut w_r, mut w_li, mut w_ri, mut w_inv) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for phi in cases {
        let phi = rounded::<B>(phi);
        let pb: V3<B> = vb::<B>(phi);
        let r = R::exp(pb);
        let jl = m64::<B>(lie::left_jacobian::<B>(pb));
        let jr = m64::<B>(lie::right_jacobian::<B>(pb));
        let jli = m64::<B>(lie::left_jacobian_inv::<B>(pb));
        let jri = m64::<B>(lie::right_jacobian_inv::<B>(pb));
        for i in 0..3 {
            let mut d = [0.0; 3];
            d[i] = h;
            let (pp, pm) = (vb::<B>(add(phi, d)), vb::<B>(sub(phi, d)));
            let (dp, dm) = (vb::<B>(d), vb::<B>(scale(d, -1.0)));
            // exp(φ + δ) ≈ exp(J_l δ) exp(φ)
            let fd_l = scale(
                sub(
                    log64::<B, R>(R::exp(pp) * r.inverse()),
                    log64::<B, R>(R::exp(pm) * r.inverse()),
                ),
                0.5 / h,
            );
            // exp(φ + δ) ≈ exp(φ) exp(J_r δ)
            let fd_r = scale(
                sub(
                    log64::<B, R>(r.inverse() * R::exp(pp)),
                    log64::<B, R>(r.inverse() * R::exp(pm)),
                ),
                0.5 / h,
            );
            // log(exp(δ) R) ≈ φ + J_l⁻¹ δ,  log(R exp(δ)) ≈ φ + J_r⁻¹ δ
            let fd_li = scale(
                sub(log64::<B, R>(R::exp(dp) * r), log64::<B, R>(R::exp(dm) * r)),
                0.5 / h,
            );
            let fd_ri = scale(
                sub(log64::<B, R>(r * R::exp(dp)), log64::<B, R>(r * R::exp(dm))),
                0.5 / h,
            );
            w_l = w_l.max(col_dist(jl, i, fd_l));
            w_r = w_r.max(col_dist(jr, i, fd_r));
            w_li = w_li.max(col_dist(jli, i, fd_li));
            w_ri = w_ri.max(col_dist(jri, i, fd_ri));
        }
        w_inv = w_inv
            .max(mdist(mmul(jl, jli), I3))
            .max(mdist(mmul(jr, jri), I3));
    }
    println!(
        "{} Jacobians vs central FD: J_l {w_l:.1e}, J_r {w_r:.1e}, J_l⁻¹ {w_li:.1e}, J_r⁻¹ {w_ri:.1e}; ‖J J⁻¹ − I‖ {w_inv:.1e}",
        tag::<B, R>()
    );
    for w in [w_l, w_r, w_li, w_ri] {
        assert!(w < tol, "{w:e}");
    }
    // J⁻¹ grows like 1/(2π − θ); at θ ≤ 3 its entries are ≲ 3, so the
    // product's rounding is a few ε times that.
    assert!(w_inv < 64.0 * e, "{w_inv:e}");
}

/// Proposition 1 of the paper: (i) Ψ ≥ 0 with equality at R = R_d,
/// (ii) e_R is the left-trivialised derivative of Ψ, (iii) critical points
/// at rotations by π, (iv) ½‖e_R‖² ≤ Ψ, (v) Ψ ≤ ‖e_R‖²/(2 − ψ) (here in the
/// sharp form ‖e_R‖² = Ψ(2 − Ψ)), (vi) Ψ̇ = e_R·e_Ω.
pub fn attitude_error_proposition_1<B: Backend, R: Rotation<B>>() {
    let e = eps::<B>();
    let (h, tol_fd) = (fd_step::<B>(), fd_tol::<B>());
    let mut rng = Rng::new(7);
    let mut worst_identity = 0.0f64;
    let (mut worst_lb, mut worst_deriv, mut worst_dot, mut worst_crit) =
        (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for _ in 0..300 {
        let r = exp_b::<B, R>(rng.rotvec(PI));
        let rd = exp_b::<B, R>(rng.rotvec(PI));
        let psi = r.psi(rd).to_f64_lossless();
        let er = v64::<B>(r.e_r(rd));
        assert!(psi >= -4.0 * e && psi <= 2.0 + 4.0 * e);
        // Ψ(R, R) = ½(3 − ‖R‖²_F) for a matrix: it inherits R's own
        // orthogonality error from exp (a few ε per element).
        assert!(r.psi(r).to_f64_lossless().abs() <= 16.0 * e);
        worst_lb = worst_lb.max(0.5 * dot(er, er) - psi);
        worst_identity = worst_identity.max((dot(er, er) - psi * (2.0 - psi)).abs());
        // (ii): d/dε Ψ(R exp(ε η), R_d) = e_R · η.
        let eta = rng.unit();
        let fd = (r * exp_b::<B, R>(scale(eta, h))).psi(rd).to_f64_lossless()
            - (r * exp_b::<B, R>(scale(eta, -h)))
                .psi(rd)
                .to_f64_lossless();
        worst_deriv = worst_deriv.max((fd / (2.0 * h) - dot(er, eta)).abs());
        // (vi): along R(t) = R exp(tΩ), R_d(t) = R_d exp(tΩ_d).
        let (w, wd) = (scale(rng.unit(), 2.0), scale(rng.unit(), 2.0));
        let eo = v64::<B>(lie::e_omega::<B, R>(r, vb::<B>(w), rd, vb::<B>(wd)));
        let at = |t: f64| {
            (r * exp_b::<B, R>(scale(w, t)))
                .psi(rd * exp_b::<B, R>(scale(wd, t)))
                .to_f64_lossless()
        };
        worst_dot = worst_dot.max(((at(h) - at(-h)) / (2.0 * h) - dot(er, eo)).abs());
        // (iii): e_R = 0 and Ψ = 2 at R_d exp(π s^).
        let crit = rd * exp_b::<B, R>(scale(rng.unit(), PI));
        worst_crit = worst_crit
            .max(norm(v64::<B>(crit.e_r(rd))))
            .max((crit.psi(rd).to_f64_lossless() - 2.0).abs());
    }
    println!(
        "{} Prop. 1: max(½‖e_R‖² − Ψ) = {worst_lb:.1e}, |‖e_R‖² − Ψ(2−Ψ)| ≤ {worst_identity:.1e}, \
         ∂Ψ vs e_R {worst_deriv:.1e}, Ψ̇ vs e_R·e_Ω {worst_dot:.1e}, critical points {worst_crit:.1e}",
        tag::<B, R>()
    );
    // Rounding of a 3×3 product and a trace: 16 ε.
    assert!(worst_lb <= 16.0 * e, "{worst_lb:e}");
    assert!(worst_identity <= 16.0 * e, "{worst_identity:e}");
    assert!(
        worst_deriv < tol_fd && worst_dot < tol_fd * 10.0,
        "{worst_deriv:e} {worst_dot:e}"
    );
    // sin(π) in floating point is ~ε; composing adds a few more.
    assert!(worst_crit <= 32.0 * e, "{worst_crit:e}");
}

pub fn adjoint_by_conjugation<B: Backend, R: Rotation<B>>() {
    let e = eps::<B>();
    let mut rng = Rng::new(8);
    let mut worst = 0.0f64;
    for _ in 0..200 {
        let r = exp_b::<B, R>(rng.rotvec(PI));
        let phi = vb::<B>(rng.rotvec(2.0));
        let lhs = R::exp(r.adjoint() * phi);
        let rhs = r * R::exp(phi) * r.inverse();
        worst = testkit::nan_max(worst, mdist(m64::<B>(lhs.matrix()), m64::<B>(rhs.matrix())));
    }
    assert!(worst < 30.0 * e, "{worst:e}");
}

pub fn slerp_is_geodesic<B: Backend, R: Rotation<B>>() {
    let tol = if is_f64::<B>() { 1e-12 } else { 4e-6 };
    let mut rng = Rng::new(9);
    for _ in 0..200 {
        let a = exp_b::<B, R>(rng.rotvec(PI));
        let b = exp_b::<B, R>(rng.rotvec(PI));
        let total = (a.inverse() * b).angle().to_f64_lossless();
        if total > PI - 1e-3 {
            continue; // the shorter arc is ambiguous at π
        }
        assert!(
            mdist(
                m64::<B>(a.slerp(b, s::<B>(0.0)).matrix()),
                m64::<B>(a.matrix())
            ) < tol
        );
        assert!(
            mdist(
                m64::<B>(a.slerp(b, s::<B>(1.0)).matrix()),
                m64::<B>(b.matrix())
            ) < tol
        );
        for t in [0.25, 0.5, 0.8] {
            let m = a.slerp(b, s::<B>(t));
            let from_a = (a.inverse() * m).angle().to_f64_lossless();
            let to_b = (m.inverse() * b).angle().to_f64_lossless();
            assert!((from_a - t * total).abs() < tol && (to_b - (1.0 - t) * total).abs() < tol);
        }
    }
}

/// Representation conversions agree: matrix ↔ quaternion, and Ψ, e_R, log
/// computed in either representation.
pub fn representations_agree<B: Backend, R: Rotation<B>>() {
    let e = eps::<B>();
    let mut rng = Rng::new(10);
    for _ in 0..300 {
        let (p1, p2) = (rounded::<B>(rng.rotvec(PI)), rounded::<B>(rng.rotvec(PI)));
        let (r, rd) = (exp_b::<B, R>(p1), exp_b::<B, R>(p2));
        let (m, md) = (
            lie::So3Mat::<B>::from_matrix(r.matrix()),
            lie::So3Mat::<B>::from_matrix(rd.matrix()),
        );
        let (q, qd) = (
            lie::So3Quat::<B>::from_matrix(r.matrix()),
            lie::So3Quat::<B>::from_matrix(rd.matrix()),
        );
        assert!(
            mdist(
                m64::<B>(R::from_quaternion(r.quaternion()).matrix()),
                m64::<B>(r.matrix())
            ) < 16.0 * e
        );
        assert!((m.psi(md).to_f64_lossless() - q.psi(qd).to_f64_lossless()).abs() < 16.0 * e);
        assert!(dist(v64::<B>(m.e_r(md)), v64::<B>(q.e_r(qd))) < 16.0 * e);
    }
}

/// Projection onto SO(3) gives the polar factor (checked against an SVD in
/// f64) and rejects det ≤ 0 and non-finite input with an error.
pub fn projection_onto_group<B: Backend, R: Rotation<B>>() {
    let e = eps::<B>();
    let mut rng = Rng::new(11);
    let mut worst_orth = 0.0f64;
    let mut worst_polar = 0.0f64;
    for _ in 0..200 {
        let mut a = m64::<B>(exp_b::<B, R>(rng.rotvec(PI)).matrix());
        for row in a.iter_mut() {
            for x in row.iter_mut() {
                *x += rng.range(-1e-2, 1e-2);
            }
        }
        let p = lie::So3Mat::<B>::project(mb::<B>(a)).expect("near-orthogonal matrix projects");
        worst_orth = worst_orth.max(p.orthogonality_error().to_f64_lossless());
        let svd = nalgebra::Matrix3::from_fn(|i, j| m64::<B>(mb::<B>(a))[i][j]).svd(true, true);
        let polar = svd.u.unwrap() * svd.v_t.unwrap();
        let polar = [0, 1, 2].map(|i| [0, 1, 2].map(|j| polar[(i, j)]));
        worst_polar = worst_polar.max(mdist(m64::<B>(p.matrix()), polar));
    }
    println!(
        "{} projection: ‖RᵀR − I‖ ≤ {worst_orth:.1e}, distance to SVD polar factor ≤ {worst_polar:.1e}",
        tag::<B, R>()
    );
    assert!(
        worst_orth < 16.0 * e && worst_polar < 16.0 * e,
        "{worst_orth:e} {worst_polar:e}"
    );
    let reflection = mb::<B>([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]);
    assert!(matches!(
        lie::So3Mat::<B>::project(reflection),
        Err(lie::LieError::NotProjectable { .. })
    ));
    // `normalized` cannot fail: where the projection does, it returns NaN
    // (caught by the next finiteness check), never the input as if it
    // were a rotation.
    let n = lie::So3Mat::<B>::from_matrix_unchecked(reflection).normalized();
    assert!(m64::<B>(n.matrix()).iter().flatten().all(|x| x.is_nan()));
    let nan = mb::<B>([[f64::NAN, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    assert!(matches!(
        lie::So3Mat::<B>::project(nan),
        Err(lie::LieError::NonFinite { .. })
    ));
}

/// Unit-norm drift over 10⁵ products, and its repair by `normalized`.
pub fn drift_and_renormalisation<B: Backend, R: Rotation<B>>() {
    let e = eps::<B>();
    let mut rng = Rng::new(12);
    let steps: Vec<R> = (0..64).map(|_| exp_b::<B, R>(rng.rotvec(0.1))).collect();
    let mut r = R::identity();
    for k in 0..100_000 {
        r = r * steps[k % steps.len()];
    }
    let drift = r.orthogonality_error().to_f64_lossless();
    let fixed = r.normalized().orthogonality_error().to_f64_lossless();
    println!(
        "{} ‖RᵀR − I‖ after 1e5 products: {drift:.1e}; after normalized(): {fixed:.1e}",
        tag::<B, R>()
    );
    // What remains after normalising is the rounding of forming R from q
    // (or of the polar iteration) and of RᵀR: a few ε in each of the nine
    // entries, 16 ε in the Frobenius norm.
    assert!(fixed < 16.0 * e, "{fixed:e}");
}

/// Ψ is never negative and exact near 0: at angles 1e-9 … 1e-2 between R
/// and R_d (in the scalar's representable range) it matches the closed
/// form `1 − cos θ = 2 sin²(θ/2)` to a relative error of a few ε, where
/// `½(3 − tr RdᵀR)` would leave an absolute error of a few ε of either
/// sign (a relative error of 1e7 at θ = 1e-9 in f64).
pub fn psi_is_nonnegative_and_exact_near_zero<B: Backend, R: Rotation<B>>() {
    let e = eps::<B>();
    let mut rng = Rng::new(11);
    let mut worst = 0.0f64;
    for _ in 0..200 {
        let rd = exp_b::<B, R>(rng.rotvec(PI));
        assert!(rd.psi(rd).to_f64_lossless() >= 0.0);
        for theta in [1e-9, 1e-7, 1e-5, 1e-3, 1e-2] {
            // Small angles that the scalar resolves: f32 keeps its
            // relative precision down to θ ≈ 1e-3 only, since R itself is
            // stored to ε ≈ 6e-8 per entry.
            if theta * theta < 1e2 * e {
                continue;
            }
            let r = rd * exp_b::<B, R>(scale(rng.unit(), theta));
            let psi = r.psi(rd).to_f64_lossless();
            assert!(psi >= 0.0, "Ψ = {psi:e} at θ = {theta:e}");
            let exact = 2.0 * (theta / 2.0).sin().powi(2);
            // R·Exp(θ) carries the rounding of a product (a few ε per
            // entry) against a difference of size θ: relative ≲ ε/θ².
            worst = testkit::nan_max(worst, (psi / exact - 1.0).abs() / (e / (theta * theta)));
        }
    }
    println!(
        "{} Ψ near 0: worst relative error {worst:.2} × ε/θ²",
        tag::<B, R>()
    );
    assert!(worst < 1.0, "{worst:e}");
}

macro_rules! so3_suite {
    ($($modname:ident: $backend:ty, $rep:ident;)*) => {$(
        mod $modname {
            type B = $backend;
            type R = lie::$rep<B>;
            #[test] fn group_axioms() { super::group_axioms::<B, R>() }
            #[test] fn hat_vee() { super::hat_vee::<B, R>() }
            #[test] fn exp_log_roundtrip() { super::exp_log_roundtrip::<B, R>() }
            #[test] fn log_at_exactly_pi() { super::log_at_exactly_pi::<B, R>() }
            #[test] fn exp_matches_series() { super::exp_matches_series::<B, R>() }
            #[test] fn jacobians_match_finite_differences() { super::jacobians_match_finite_differences::<B, R>() }
            #[test] fn attitude_error_proposition_1() { super::attitude_error_proposition_1::<B, R>() }
            #[test] fn psi_is_nonnegative_and_exact_near_zero() { super::psi_is_nonnegative_and_exact_near_zero::<B, R>() }
            #[test] fn adjoint_by_conjugation() { super::adjoint_by_conjugation::<B, R>() }
            #[test] fn slerp_is_geodesic() { super::slerp_is_geodesic::<B, R>() }
            #[test] fn representations_agree() { super::representations_agree::<B, R>() }
            #[test] fn projection_onto_group() { super::projection_onto_group::<B, R>() }
            #[test] fn drift_and_renormalisation() { super::drift_and_renormalisation::<B, R>() }
        }
    )*};
}

so3_suite! {
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
