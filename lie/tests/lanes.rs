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

use lie::{
    NalgebraF32, NalgebraF32x8, NalgebraF64, NalgebraF64x4, Real, SimdBackend, SimdReal, So3Mat,
    So3Quat, left_jacobian, left_jacobian_inv, right_jacobian, right_jacobian_inv, series,
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
                worst = worst.max((w - g).abs() / w.abs().max(1.0));
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
        ); 10] = [
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
