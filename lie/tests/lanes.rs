//! The lane backends against the scalar ones: every lane of an operation on
//! `NalgebraF64x4` / `NalgebraF32x8` must agree with the same operation on
//! `NalgebraF64` / `NalgebraF32` for that lane's input, near 0, near π and
//! in between, and with lanes that take different branches of a formula
//! (series and closed form, `asin` and `acos`, Shepperd's four pivots) in
//! one call, where the lane code blends both sides.
//!
//! The lanes' sin/cos/asin/acos are `wide`'s vectorised polynomials, not
//! the platform's libm, so agreement is to a few ulp, not to the bit. The
//! bounds are relative to the quantity's size (1 for rotation matrices and
//! Jacobians, the angle for rotation vectors) and are 8 ulp of the scalar
//! type: measured worst cases are printed by each test and stay below half
//! of that.
#![cfg(feature = "simd")]

use lie::num_traits::{One, Zero};
use lie::{
    LieGroup, NalgebraF32, NalgebraF32x8, NalgebraF64, NalgebraF64x4, Real, RigidState, Se3,
    SimdBackend, SimdReal, So3Mat, So3Quat, left_jacobian, left_jacobian_inv, right_jacobian,
    right_jacobian_inv, series,
};

/// Rotation vectors covering every branch: zero, below and above each
/// Taylor cut-off, π/4 and 2π/3 (where the matrix log changes formula),
/// near π and π itself, about several axes.
fn inputs() -> Vec<[f64; 3]> {
    let pi = core::f64::consts::PI;
    let angles = [
        0.0,
        1e-9,
        1e-6,
        1e-4,
        9e-3,
        0.011,
        0.3,
        0.49,
        0.51,
        0.9,
        pi / 4.0 - 1e-3,
        pi / 4.0 + 1e-3,
        1.4,
        1.6,
        pi / 2.0,
        1.9,
        2.0 * pi / 3.0 - 1e-3,
        2.0 * pi / 3.0 + 1e-3,
        2.5,
        3.0,
        pi - 1e-3,
        pi - 1e-6,
        pi,
    ];
    let axes = [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.6, 0.0, -0.8],
        [0.48, -0.6, 0.64],
        [-0.36, 0.48, 0.8],
        [0.0, 0.6, 0.8],
    ];
    let mut v = Vec::new();
    for a in angles {
        for x in axes {
            v.push([x[0] * a, x[1] * a, x[2] * a]);
        }
    }
    v
}

/// The inputs in a fixed shuffled order, so each call's lanes mix regimes.
fn shuffled(n: usize) -> Vec<[f64; 3]> {
    let base = inputs();
    let len = base.len();
    // A stride coprime with the length visits every input once.
    let stride = (1..len)
        .rev()
        .find(|s| gcd(*s, len) == 1 && *s > len / 3)
        .unwrap_or(1);
    let mut out: Vec<[f64; 3]> = (0..len).map(|i| base[(i * stride) % len]).collect();
    while !out.len().is_multiple_of(n) {
        out.push(base[out.len() % len]);
    }
    out
}

fn gcd(a: usize, b: usize) -> usize {
    if b == 0 { a } else { gcd(b, a % b) }
}

/// What one operation maps an input to, flattened, on a scalar backend.
type ScalarOp<B> = fn(<B as SimdBackend>::Vec3) -> Vec<<B as SimdBackend>::Scalar>;
/// The same on a lane backend.
type LaneOp<L> = fn(<L as SimdBackend>::Vec3) -> Vec<<L as SimdBackend>::Scalar>;

/// The worst lane-vs-scalar difference of `lane_op` against `scalar_op`
/// over the inputs, relative to `max(1, |scalar|)` per component.
fn worst<B, L>(scalar_op: ScalarOp<B>, lane_op: LaneOp<L>) -> f64
where
    B: SimdBackend,
    B::Scalar: Real,
    L: SimdBackend<Scalar: SimdReal<Element = B::Scalar>>,
{
    let n = <L::Scalar as SimdReal>::LANES;
    let mut worst = 0.0f64;
    for chunk in shuffled(n).chunks(n) {
        let lane = |k: usize| {
            <L::Scalar as SimdReal>::simd_from_fn(|i| <B::Scalar as Real>::lit(chunk[i][k]))
        };
        let got = lane_op(L::vec3(lane(0), lane(1), lane(2)));
        for (i, p) in chunk.iter().enumerate() {
            let l = |x: f64| <B::Scalar as Real>::lit(x);
            let want = scalar_op(B::vec3(l(p[0]), l(p[1]), l(p[2])));
            assert_eq!(want.len(), got.len());
            for (w, g) in want.iter().zip(&got) {
                let (w, g) = (w.to_f64_lossless(), g.simd_extract(i).to_f64_lossless());
                assert!(
                    w.is_finite() && g.is_finite(),
                    "non-finite at {p:?}: {w} vs {g}"
                );
                worst = testkit::nan_max(worst, (w - g).abs() / w.abs().max(1.0));
            }
        }
    }
    worst
}

fn flat_vec<B: SimdBackend>(v: B::Vec3) -> Vec<B::Scalar> {
    B::vec3_to_array(v).to_vec()
}

fn flat_mat<B: SimdBackend>(m: B::Mat3) -> Vec<B::Scalar> {
    B::mat3_cols(m)
        .into_iter()
        .flat_map(|c| B::vec3_to_array(c))
        .collect()
}

/// Each operation, as a function of a rotation vector, for any backend.
macro_rules! ops_of {
    ($b:ty) => {{
        let ops: [(
            &str,
            fn(<$b as SimdBackend>::Vec3) -> Vec<<$b as SimdBackend>::Scalar>,
        ); 12] = [
            ("So3Mat::exp", |p| {
                flat_mat::<$b>(So3Mat::<$b>::exp(p).as_matrix())
            }),
            ("So3Mat::log∘exp", |p| {
                flat_vec::<$b>(So3Mat::<$b>::exp(p).log())
            }),
            ("So3Quat::exp", |p| {
                let q = So3Quat::<$b>::exp(p).as_quaternion();
                <$b as SimdBackend>::quat_to_wxyz(q).to_vec()
            }),
            ("So3Quat::log∘exp", |p| {
                flat_vec::<$b>(So3Quat::<$b>::exp(p).log())
            }),
            ("shepperd∘exp", |p| {
                lie::shepperd::<$b>(So3Mat::<$b>::exp(p).as_matrix()).to_vec()
            }),
            ("So3Mat errors_to_identity", |p| {
                let (e, psi) = So3Mat::<$b>::exp(p).errors_to_identity();
                let mut out = flat_vec::<$b>(e);
                out.push(psi);
                out
            }),
            ("So3Quat errors_to_identity", |p| {
                let (e, psi) = So3Quat::<$b>::exp(p).errors_to_identity();
                let mut out = flat_vec::<$b>(e);
                out.push(psi);
                out
            }),
            ("J_l", |p| flat_mat::<$b>(left_jacobian::<$b>(p))),
            ("J_r", |p| flat_mat::<$b>(right_jacobian::<$b>(p))),
            ("J_l⁻¹", |p| flat_mat::<$b>(left_jacobian_inv::<$b>(p))),
            ("J_r⁻¹", |p| flat_mat::<$b>(right_jacobian_inv::<$b>(p))),
            ("C, D, E, F", |p| {
                let t = lie::ops::norm::<$b>(p);
                vec![
                    series::c_coeff(t),
                    series::d_coeff(t),
                    series::e_coeff(t),
                    series::f_coeff(t),
                ]
            }),
        ];
        ops
    }};
}

#[test]
fn f64x4_lanes_agree_with_f64() {
    let scalar = ops_of!(NalgebraF64);
    let lanes = ops_of!(NalgebraF64x4);
    for ((name, s), (_, l)) in scalar.into_iter().zip(lanes) {
        let w = worst::<NalgebraF64, NalgebraF64x4>(s, l);
        println!("f64x4 {name}: worst {:.2} ulp", w / f64::EPSILON);
        assert!(w <= 8.0 * f64::EPSILON, "{name}: {w:e}");
    }
}

#[test]
fn f32x8_lanes_agree_with_f32() {
    let scalar = ops_of!(NalgebraF32);
    let lanes = ops_of!(NalgebraF32x8);
    for ((name, s), (_, l)) in scalar.into_iter().zip(lanes) {
        let w = worst::<NalgebraF32, NalgebraF32x8>(s, l);
        println!("f32x8 {name}: worst {:.2} ulp", w / f32::EPSILON as f64);
        assert!(w <= 8.0 * f32::EPSILON as f64, "{name}: {w:e}");
    }
}

/// The agreement tests above only test the blend if some call's lanes take
/// different branches: check that the shuffled order gives such calls, for
/// the exp cut-off and for the matrix log's 2π/3 switch, at both widths.
#[test]
fn lanes_of_one_call_take_different_branches() {
    for n in [4, 8] {
        let (mut exp_mixed, mut log_mixed) = (0, 0);
        for chunk in shuffled(n).chunks(n) {
            let t: Vec<f64> = chunk
                .iter()
                .map(|p| (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt())
                .collect();
            let below = |c: f64| t.iter().filter(|x| **x < c).count();
            exp_mixed += usize::from((1..n).contains(&below(f64::CUT_EXP)));
            log_mixed += usize::from((1..n).contains(&below(2.1)));
        }
        assert!(
            exp_mixed > 0 && log_mixed > 0,
            "{n} lanes: {exp_mixed} {log_mixed}"
        );
    }
}

/// A NaN in one lane stays in that lane: the others get their scalar
/// results, the NaN lane NaN (never a finite value that could pass as a
/// rotation).
#[test]
fn a_nan_lane_does_not_leak() {
    type L = NalgebraF64x4;
    let lane = |v: [f64; 4]| <L as SimdBackend>::Scalar::simd_from_fn(|i| v[i]);
    let phi = L::vec3(
        lane([0.3, f64::NAN, 1e-9, 3.0]),
        lane([0.1, 0.2, 0.0, 0.1]),
        lane([-0.2, 0.3, 0.0, 0.05]),
    );
    for (name, out) in [
        ("exp", flat_mat::<L>(So3Mat::<L>::exp(phi).as_matrix())),
        ("log∘exp", flat_vec::<L>(So3Mat::<L>::exp(phi).log())),
        ("J_r⁻¹", flat_mat::<L>(right_jacobian_inv::<L>(phi))),
    ] {
        for x in &out {
            let l: [f64; 4] = core::array::from_fn(|i| x.simd_extract(i));
            assert!(l[1].is_nan(), "{name}: NaN lane gave {}", l[1]);
            assert!(
                l[0].is_finite() && l[2].is_finite() && l[3].is_finite(),
                "{name}: {l:?}"
            );
        }
    }
}

/// The README's lane example, as written there.
#[test]
fn readme_example() {
    use lie::lanes;
    use std::f64::consts::{FRAC_PI_2, PI};

    // Four rotation vectors about x, one per lane: 0, 1e-6, π/2 and π.
    let angles = [0.0, 1e-6, FRAC_PI_2, PI];
    let phi = lanes::vec3_from_fn::<NalgebraF64, NalgebraF64x4>(|i| {
        NalgebraF64::vec3(angles[i], 0.0, 0.0)
    });
    let back = So3Mat::<NalgebraF64x4>::exp(phi).log();
    let last = lanes::vec3_lane::<NalgebraF64, NalgebraF64x4>(back, 3);
    assert!((last.x - PI).abs() < 1e-15);
}

// ---------------------------------------------------------------------------
// Every operation of the `LieGroup` trait (⊕, ⊖, `between`, the adjoint, the
// Jacobians and the Jacobians of each composite) on SO(3) in both
// representations, SE(3) over each, and the rigid-body state, lanes against
// scalar.

/// One test case: six 3-vectors, read by [`tangent_of`] as the tangents of
/// `X` and `Y` (rotation parts first two, the rest their other parts) and
/// the point `p` (the last).
type Case = [[f64; 3]; 6];

/// Cases around 0 and π for `X`, `Y` and, which is what ⊖ and `between`
/// see, for `X⁻¹Y`: every third case puts `Y` within 1e-7 of `X`, every
/// third one `π − 1e-4` from it (a rotation about the axis of `X`, so the
/// relative angle is known), the rest pair unrelated inputs.
fn group_cases(n: usize) -> Vec<Case> {
    let base = shuffled(n);
    let len = base.len();
    let pick = |i: usize| base[i % len];
    let scaled = |v: [f64; 3], s: f64| v.map(|x| x * s);
    (0..len)
        .map(|k| {
            let pa = pick(k);
            let norm = (pa[0] * pa[0] + pa[1] * pa[1] + pa[2] * pa[2]).sqrt();
            let axis = if norm > 0.0 {
                scaled(pa, 1.0 / norm)
            } else {
                [0.0, 0.6, 0.8]
            };
            let pb = match k % 3 {
                0 => core::array::from_fn(|i| pa[i] + 1e-7 * (i as f64 - 1.0)),
                1 => core::array::from_fn(|i| pa[i] + (core::f64::consts::PI - 1e-4) * axis[i]),
                _ => pick(7 * k + 3),
            };
            [
                pa,
                scaled(pick(11 * k + 5), 0.7),
                pb,
                scaled(pick(13 * k + 1), -1.3),
                scaled(pick(5 * k + 2), 0.9),
                scaled(pick(3 * k + 4), 2.0),
            ]
        })
        .collect()
}

/// The lanes of `cases` (as many as `B` has) as backend vectors.
fn load<B: SimdBackend>(cases: &[Case]) -> [B::Vec3; 6] {
    core::array::from_fn(|j| {
        let c = |k: usize| {
            <B::Scalar as SimdReal>::simd_from_fn(|i| {
                <<B::Scalar as SimdReal>::Element as Real>::lit(cases[i][j][k])
            })
        };
        B::vec3(c(0), c(1), c(2))
    })
}

/// A tangent of `G` from a case's vectors: SO(3) takes `φ`, SE(3) `(ρ, φ)`,
/// the rigid-body state `(φ, x, v, Ω)`.
fn tangent_of<B: SimdBackend, G: LieGroup<B>>(phi: B::Vec3, rest: [B::Vec3; 3]) -> G::Tangent {
    let parts: [B::Vec3; 4] = match G::DOF {
        3 | 12 => [phi, rest[0], rest[1], rest[2]],
        6 => [rest[0], phi, rest[1], rest[2]],
        d => panic!("no case layout for {d} degrees of freedom"),
    };
    G::tangent_from_fn(|i| B::vec3_to_array(parts[i / 3])[i % 3])
}

/// A group element as numbers: its action on 0 and on the three axes
/// (the whole of an SO(3) or SE(3) element) and its log's coordinates
/// (the rigid-body state's vector parts).
fn element<B: SimdBackend, G: LieGroup<B>>(x: G) -> Vec<B::Scalar> {
    let (z, o) = (B::Scalar::zero(), B::Scalar::one());
    let mut out = Vec::new();
    for p in [
        B::vec3(z, z, z),
        B::vec3(o, z, z),
        B::vec3(z, o, z),
        B::vec3(z, z, o),
    ] {
        out.extend(B::vec3_to_array(x.act(p)));
    }
    out.extend(tangent::<B, G>(&x.log()));
    out
}

fn tangent<B: SimdBackend, G: LieGroup<B>>(t: &G::Tangent) -> Vec<B::Scalar> {
    (0..G::DOF).map(|i| G::tangent_coord(t, i)).collect()
}

fn jacobian<B: SimdBackend, G: LieGroup<B>>(j: &G::Jacobian) -> Vec<B::Scalar> {
    let d = G::DOF;
    (0..d * d)
        .map(|k| G::jacobian_entry(j, k / d, k % d))
        .collect()
}

/// Every `LieGroup` operation of `G` on one case (or one lane group of
/// cases), each flattened to numbers, in a fixed order with its name.
fn group_ops<B: SimdBackend, G: LieGroup<B>>(
    v: [B::Vec3; 6],
) -> Vec<(&'static str, Vec<B::Scalar>)> {
    let ta = tangent_of::<B, G>(v[0], [v[1], v[3], v[4]]);
    let tb = tangent_of::<B, G>(v[2], [v[3], v[1], v[5]]);
    let (x, y, p) = (G::exp(ta), G::exp(tb), v[5]);
    let el = element::<B, G>;
    let tg = |t: G::Tangent| tangent::<B, G>(&t);
    let jc = |j: G::Jacobian| jacobian::<B, G>(&j);
    let (acted, j_act, j_p) = x.act_jac(p);
    let mut act = B::vec3_to_array(acted).to_vec();
    act.extend((0..3 * G::DOF).map(|k| G::act_jacobian_entry(&j_act, k / G::DOF, k % G::DOF)));
    act.extend(flat_mat::<B>(j_p));
    let jac2 = |(e, a, b): (Vec<B::Scalar>, G::Jacobian, G::Jacobian)| {
        let mut out = e;
        out.extend(jc(a));
        out.extend(jc(b));
        out
    };
    vec![
        ("exp", el(x)),
        ("log∘exp", tg(x.log())),
        ("compose", el(x.compose(y))),
        ("inverse", el(x.inverse())),
        ("act_jac", act),
        ("adjoint", jc(x.adjoint())),
        ("J_r", jc(G::right_jacobian(ta))),
        ("J_r⁻¹", jc(G::right_jacobian_inv(ta))),
        ("J_l", jc(G::left_jacobian(ta))),
        ("J_l⁻¹", jc(G::left_jacobian_inv(ta))),
        ("rplus", el(x.rplus(tb))),
        ("lplus", el(x.lplus(tb))),
        ("rminus", tg(y.rminus(x))),
        ("lminus", tg(y.lminus(x))),
        ("between", el(x.between(y))),
        (
            "compose_jac",
            jac2({
                let (c, a, b) = x.compose_jac(y);
                (el(c), a, b)
            }),
        ),
        ("inverse_jac", {
            let (i, a) = x.inverse_jac();
            let mut out = el(i);
            out.extend(jc(a));
            out
        }),
        (
            "rplus_jac",
            jac2({
                let (c, a, b) = x.rplus_jac(tb);
                (el(c), a, b)
            }),
        ),
        (
            "rminus_jac",
            jac2({
                let (t, a, b) = y.rminus_jac(x);
                (tg(t), a, b)
            }),
        ),
        (
            "between_jac",
            jac2({
                let (c, a, b) = x.between_jac(y);
                (el(c), a, b)
            }),
        ),
    ]
}

/// The worst relative lane-vs-scalar difference of each operation of
/// `group_ops` for group `G` on backend `B` and `H` on lanes `L`, over the
/// cases; each component is compared relative to `max(1, |scalar|)`.
fn group_worst<B, L, G, H>() -> Vec<(&'static str, f64)>
where
    B: SimdBackend<Scalar: Real>,
    L: SimdBackend<Scalar: SimdReal<Element = B::Scalar>>,
    G: LieGroup<B>,
    H: LieGroup<L>,
{
    let n = <L::Scalar as SimdReal>::LANES;
    let cases = group_cases(n);
    let mut worst: Vec<(&'static str, f64)> = Vec::new();
    for chunk in cases.chunks_exact(n) {
        let got = group_ops::<L, H>(load::<L>(chunk));
        for (i, case) in chunk.iter().enumerate() {
            let want = group_ops::<B, G>(load::<B>(core::slice::from_ref(case)));
            for (k, ((name, w), (_, g))) in want.iter().zip(&got).enumerate() {
                if worst.len() <= k {
                    worst.push((name, 0.0));
                }
                assert_eq!(w.len(), g.len(), "{name}");
                for (w, g) in w.iter().zip(g) {
                    let (w, g) = (w.to_f64_lossless(), g.simd_extract(i).to_f64_lossless());
                    assert!(
                        w.is_finite() && g.is_finite(),
                        "{name} at {case:?}: {w} vs {g}"
                    );
                    worst[k].1 = worst[k].1.max((w - g).abs() / w.abs().max(1.0));
                }
            }
        }
    }
    worst
}

/// Runs `group_worst` for one group on both lane widths and checks each
/// operation against `ulps` units of the scalar type's ε.
macro_rules! group_agreement {
    ($test:ident, $g:ident, $ulps:expr) => {
        #[test]
        fn $test() {
            let f64x4 =
                group_worst::<NalgebraF64, NalgebraF64x4, $g<NalgebraF64>, $g<NalgebraF64x4>>();
            let f32x8 =
                group_worst::<NalgebraF32, NalgebraF32x8, $g<NalgebraF32>, $g<NalgebraF32x8>>();
            let mut failed = Vec::new();
            for ((name, w64), (_, w32)) in f64x4.iter().zip(&f32x8) {
                let (u64, u32) = (w64 / f64::EPSILON, w32 / f32::EPSILON as f64);
                println!(
                    "{}: {name}: f64x4 {u64:.2} ulp, f32x8 {u32:.2} ulp",
                    stringify!($g)
                );
                if u64 > $ulps || u32 > $ulps {
                    failed.push(*name);
                }
            }
            assert!(failed.is_empty(), "over {} ulp: {failed:?}", $ulps);
        }
    };
}

// The bound: a case's `X` and `Y` come from each backend's own `exp`, a
// few ulp apart already (≤ 4.5 measured: "exp" rows), and a composite
// (⊖, `between`, their Jacobians) composes, inverts and logs them again;
// the worst measured is 14.5 ulp (SE(3) over quaternions, `rminus_jac`,
// f64x4), so 32 ulp is about twice that and still far below any real
// disagreement (a wrong branch moves an entry by O(1)).
type So3MatG<B> = So3Mat<B>;
type So3QuatG<B> = So3Quat<B>;
type Se3Mat<B> = Se3<B, So3Mat<B>>;
type Se3Quat<B> = Se3<B, So3Quat<B>>;
type Rigid<B> = RigidState<B, So3Mat<B>>;

group_agreement!(so3_matrix_group_ops_on_lanes, So3MatG, 32.0);
group_agreement!(so3_quaternion_group_ops_on_lanes, So3QuatG, 32.0);
group_agreement!(se3_group_ops_on_lanes, Se3Mat, 32.0);
group_agreement!(se3_over_quaternions_group_ops_on_lanes, Se3Quat, 32.0);
group_agreement!(rigid_state_group_ops_on_lanes, Rigid, 32.0);

/// The lane polar projection against `So3Mat::project`, lane by lane: the
/// same rotation to the bit where the scalar succeeds (the iteration is the
/// same arithmetic, each lane stopping where the scalar one stops), and
/// failure, as NaN, exactly where it fails. The matrices are rotations at
/// every angle of the inputs plus perturbations from 1e-12 to 0.3 (one to
/// four Newton steps), every sixth one a reflection (`det < 0`) and every
/// eleventh one NaN.
#[test]
fn polar_projection_on_lanes_is_the_scalar_one() {
    fn check<E, L>() -> usize
    where
        E: lie::Backend,
        L: SimdBackend<Scalar: SimdReal<Element = E::Scalar>>,
    {
        let n = <L::Scalar as SimdReal>::LANES;
        let cases = shuffled(n);
        let matrix = |k: usize| {
            let p = cases[k];
            let r = So3Mat::<E>::exp(E::vec3(Real::lit(p[0]), Real::lit(p[1]), Real::lit(p[2])))
                .as_matrix();
            let size = [1e-12, 1e-6, 1e-3, 0.05, 0.3][k % 5];
            let noise = lie::ops::from_elems::<E>(core::array::from_fn(|i| {
                core::array::from_fn(|j| {
                    Real::lit(size * (((3 * i + j + k) % 7) as f64 - 3.0) / 3.0)
                })
            }));
            let sign = match (k % 6, k % 11) {
                (_, 10) => f64::NAN,
                (5, _) => -1.0,
                _ => 1.0,
            };
            (r + noise) * <E::Scalar as Real>::lit(sign)
        };
        let mut failures = 0;
        for start in (0..cases.len()).step_by(n) {
            let m = lie::lanes::mat3_from_fn::<E, L>(|i| matrix(start + i));
            let (got, ok) = So3Mat::<L>::project_lanes(m);
            for i in 0..n {
                let want = So3Mat::<E>::project(matrix(start + i));
                let lane = lie::lanes::mat3_lane::<E, L>(got.as_matrix(), i);
                assert_eq!(
                    want.is_ok(),
                    lie::SimdMask::extract(ok, i),
                    "case {}",
                    start + i
                );
                match want {
                    Ok(r) => assert_eq!(
                        lie::ops::elems::<E>(r.as_matrix()),
                        lie::ops::elems::<E>(lane),
                        "case {}",
                        start + i
                    ),
                    Err(_) => {
                        failures += 1;
                        assert!(
                            lie::ops::elems::<E>(lane)
                                .iter()
                                .flatten()
                                .all(|x| x.to_f64_lossless().is_nan())
                        );
                    }
                }
            }
        }
        failures
    }
    let f64_failures = check::<NalgebraF64, NalgebraF64x4>();
    let f32_failures = check::<NalgebraF32, NalgebraF32x8>();
    // The reflections fail; without them the test would not reach the
    // failure branch.
    assert!(
        f64_failures > 10 && f32_failures > 10,
        "{f64_failures} {f32_failures}"
    );
}
