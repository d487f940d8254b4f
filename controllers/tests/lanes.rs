//! The attitude law on SIMD lanes against the same law on one vehicle at a
//! time: each lane of `attitude_law` on `NalgebraF64x4` / `NalgebraF32x8`
//! must equal, to the bit, the law on `NalgebraF64` / `NalgebraF32` for
//! that lane's inputs. The law has no branch and no transcendental
//! function (the inputs' rotations are built on the scalar side and packed),
//! so every lane performs the scalar's operations in the scalar's order.
#![cfg(feature = "simd")]

use controllers::{
    AttitudeGains, AttitudeOutput, AttitudeReference, RigidBodyParams, attitude_law,
};
use dynamics::paper;
use lie::{
    AttitudeErrors, Backend, NalgebraF32, NalgebraF32x8, NalgebraF64, NalgebraF64x4, Real,
    SimdBackend, SimdReal, So3Mat, So3Quat,
};

/// One vehicle's inputs to the law, as plain numbers.
#[derive(Clone, Copy)]
struct Case {
    r: [f64; 3],
    rd: [f64; 3],
    omega: [f64; 3],
    e_i: [f64; 3],
    omega_d: [f64; 3],
    omega_d_dot: [f64; 3],
}

/// A seeded xorshift stream of numbers in [−1, 1).
fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    }
}

fn cases(n: usize) -> Vec<Case> {
    let mut next = uniform(0x9e37_79b9_7f4a_7c15);
    let mut v = |k: f64| [k * next(), k * next(), k * next()];
    (0..n)
        .map(|i| Case {
            // Rotation vectors up to ~π·√3/1.8 (every regime of Ψ), one lane
            // of each call at the identity.
            r: if i % 5 == 0 { [0.0; 3] } else { v(1.8) },
            rd: v(1.8),
            omega: v(4.0),
            e_i: v(0.5),
            omega_d: v(2.0),
            omega_d_dot: v(10.0),
        })
        .collect()
}

/// The law's outputs as numbers, in a fixed order.
fn flat<B: SimdBackend>(o: &AttitudeOutput<B>) -> Vec<B::Scalar> {
    let mut v = Vec::new();
    for x in [o.moment, o.e_r, o.e_omega, o.e_i_rate] {
        v.extend(B::vec3_to_array(x));
    }
    v.push(o.psi);
    v
}

/// The law for one case on a scalar backend, with rotation type `R`.
fn scalar<B, R>(c: &Case, mk: fn(B::Vec3) -> R) -> Vec<f64>
where
    B: Backend,
    R: AttitudeErrors<B>,
{
    let s = |a: [f64; 3]| {
        B::vec3(
            B::Scalar::lit(a[0]),
            B::Scalar::lit(a[1]),
            B::Scalar::lit(a[2]),
        )
    };
    let reference = AttitudeReference {
        rd: mk(s(c.rd)),
        omega_d: s(c.omega_d),
        omega_d_dot: s(c.omega_d_dot),
    };
    let out = attitude_law(
        &RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        &AttitudeGains::<B>::paper(),
        mk(s(c.r)),
        s(c.omega),
        s(c.e_i),
        &reference,
    );
    flat::<B>(&out)
        .into_iter()
        .map(|x| x.to_f64_lossless())
        .collect()
}

/// Worst lane-vs-scalar difference, in units of the scalar's ulp at the
/// value, over 64 calls' worth of lanes.
macro_rules! compare {
    ($s:ty, $l:ty, $rot:ident, $from:expr) => {{
        type S = $s;
        type L = $l;
        let n = <<L as SimdBackend>::Scalar as SimdReal>::LANES;
        let lit = |x: f64| <S as SimdBackend>::Scalar::lit(x);
        let params = RigidBodyParams::<L>::splat(&RigidBodyParams::<S>::diagonal(
            paper::MASS,
            paper::INERTIA,
            paper::GRAVITY,
        ));
        let gains = AttitudeGains::<L>::splat(&AttitudeGains::<S>::paper());
        let mut worst = 0u64;
        for chunk in cases(64 * n).chunks(n) {
            // Each lane's rotation built on the scalar side, then packed.
            let pack_rot = |f: fn(&Case) -> [f64; 3]| {
                let rots: Vec<_> = chunk
                    .iter()
                    .map(|c| {
                        $rot::<S>::exp(<S as SimdBackend>::vec3(
                            lit(f(c)[0]),
                            lit(f(c)[1]),
                            lit(f(c)[2]),
                        ))
                    })
                    .collect();
                $from(&rots)
            };
            let pack = |f: fn(&Case) -> [f64; 3]| {
                lie::lanes::vec3_from_fn::<S, L>(|i| {
                    let a = f(&chunk[i]);
                    <S as SimdBackend>::vec3(lit(a[0]), lit(a[1]), lit(a[2]))
                })
            };
            let reference = AttitudeReference {
                rd: pack_rot(|c| c.rd),
                omega_d: pack(|c| c.omega_d),
                omega_d_dot: pack(|c| c.omega_d_dot),
            };
            let out = attitude_law(
                &params,
                &gains,
                pack_rot(|c| c.r),
                pack(|c| c.omega),
                pack(|c| c.e_i),
                &reference,
            );
            let got = flat::<L>(&out);
            for (i, c) in chunk.iter().enumerate() {
                let want = scalar::<S, $rot<S>>(c, $rot::<S>::exp);
                for (w, g) in want.iter().zip(&got) {
                    let g = g.simd_extract(i).to_f64_lossless();
                    let (w, g) = (lit(*w), lit(g));
                    let d = (w.to_bits() as i64 - g.to_bits() as i64).unsigned_abs();
                    worst = worst.max(d as u64);
                }
            }
        }
        worst
    }};
}

fn mat_lanes<S: Backend, L: SimdBackend<Scalar: SimdReal<Element = S::Scalar>>>(
    rots: &[So3Mat<S>],
) -> So3Mat<L> {
    So3Mat::from_matrix_unchecked(lie::lanes::mat3_from_fn::<S, L>(|i| rots[i].as_matrix()))
}

fn quat_lanes<S: Backend, L: SimdBackend<Scalar: SimdReal<Element = S::Scalar>>>(
    rots: &[So3Quat<S>],
) -> So3Quat<L> {
    So3Quat::from_quaternion_unchecked(lie::lanes::quat_from_fn::<S, L>(|i| {
        rots[i].as_quaternion()
    }))
}

#[test]
fn attitude_law_on_lanes_equals_the_scalar_law() {
    let results = [
        (
            "f64x4 matrix",
            compare!(
                NalgebraF64,
                NalgebraF64x4,
                So3Mat,
                mat_lanes::<NalgebraF64, NalgebraF64x4>
            ),
        ),
        (
            "f64x4 quaternion",
            compare!(
                NalgebraF64,
                NalgebraF64x4,
                So3Quat,
                quat_lanes::<NalgebraF64, NalgebraF64x4>
            ),
        ),
        (
            "f32x8 matrix",
            compare!(
                NalgebraF32,
                NalgebraF32x8,
                So3Mat,
                mat_lanes::<NalgebraF32, NalgebraF32x8>
            ),
        ),
        (
            "f32x8 quaternion",
            compare!(
                NalgebraF32,
                NalgebraF32x8,
                So3Quat,
                quat_lanes::<NalgebraF32, NalgebraF32x8>
            ),
        ),
    ];
    for (name, ulps) in results {
        println!("attitude_law {name}: worst {ulps} ulp from the scalar law");
        assert_eq!(ulps, 0, "{name}");
    }
}

/// One vehicle's inputs to the position law, as plain numbers; every tenth
/// has `A = 0` (no thrust direction) and every tenth another `b1d` along
/// the thrust (no heading), so lanes of one call take different fallbacks.
fn position_case(k: usize, next: &mut impl FnMut() -> f64) -> [[f64; 3]; 13] {
    let mut v = |s: f64| [s * next(), s * next(), s * next()];
    let mut c = [
        v(1.0), // x
        v(1.0), // v
        v(1.5), // rotation vector of R
        v(2.0), // Ω
        v(0.3), // e_i
        v(0.1), // e_I
        v(1.0), // x_d
        v(1.0), // ẋ_d
        v(2.0), // ẍ_d
        v(3.0), // x_d⁽³⁾
        v(5.0), // x_d⁽⁴⁾
        v(0.1), // ḃ1d
        v(0.1), // b̈1d
    ];
    match k % 10 {
        3 => {
            // e_x = e_v = e_i = 0 and ẍ_d = g e3: A = 0.
            c[0] = [0.0; 3];
            c[1] = [0.0; 3];
            c[4] = [0.0; 3];
            c[6] = [0.0; 3];
            c[7] = [0.0; 3];
            c[8] = [0.0, 0.0, 9.81];
        }
        7 => {
            // Hover with e_i = 0: b3c = −e3, along the b1d given below.
            c[6] = c[0];
            c[7] = c[1];
            c[8] = [0.0; 3];
            c[4] = [0.0; 3];
            c[11] = [0.0, 0.0, 1.0]; // marks b1d = e3 (read below)
        }
        _ => {}
    }
    c
}

macro_rules! compare_position {
    ($s:ty, $l:ty, $rot:ident, $from:expr) => {{
        type S = $s;
        type L = $l;
        let n = <<L as SimdBackend>::Scalar as SimdReal>::LANES;
        let lit = |x: f64| <S as SimdBackend>::Scalar::lit(x);
        let vs = |a: [f64; 3]| <S as SimdBackend>::vec3(lit(a[0]), lit(a[1]), lit(a[2]));
        let mut next = uniform(0x2545_f491_4f6c_dd1d);
        let all: Vec<[[f64; 3]; 13]> = (0..64 * n).map(|k| position_case(k, &mut next)).collect();
        let b1d_of = |c: &[[f64; 3]; 13]| {
            if c[11] == [0.0, 0.0, 1.0] {
                [0.0, 0.0, 1.0]
            } else {
                [1.0, 0.0, 0.0]
            }
        };
        let b1d_dot_of = |c: &[[f64; 3]; 13]| {
            if c[11] == [0.0, 0.0, 1.0] {
                [0.0; 3]
            } else {
                c[11]
            }
        };
        let scalar_ref = |c: &[[f64; 3]; 13]| PositionReference::<S> {
            x: vs(c[6]),
            v: vs(c[7]),
            a: vs(c[8]),
            jerk: vs(c[9]),
            snap: vs(c[10]),
            b1d: vs(b1d_of(c)),
            b1d_dot: vs(b1d_dot_of(c)),
            b1d_ddot: vs(c[12]),
        };
        let (pg, ag, pp) = (
            PositionGains::<S>::paper(),
            AttitudeGains::<S>::paper(),
            RigidBodyParams::<S>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        );
        let params = RigidBodyParams::<L>::splat(&pp);
        let pgl = PositionGains::<L>::splat(&pg);
        let agl = AttitudeGains::<L>::splat(&ag);
        let (mut worst, mut degenerate, mut checked) = (0u64, 0usize, 0usize);
        for chunk in all.chunks(n) {
            let pack = |k: usize| lie::lanes::vec3_from_fn::<S, L>(|i| vs(chunk[i][k]));
            let refs: Vec<PositionReference<S>> = chunk.iter().map(scalar_ref).collect();
            let rots: Vec<$rot<S>> = chunk.iter().map(|c| $rot::<S>::exp(vs(c[2]))).collect();
            let state = VehicleState::<L, $rot<L>> {
                x: pack(0),
                v: pack(1),
                r: $from(&rots),
                omega: pack(3),
            };
            let reference = PositionReference::<L>::from_lanes(|i| refs[i]);
            let input = PositionInput {
                state: &state,
                e_i_pos: pack(4),
                e_i_att: pack(5),
                reference: &reference,
                model: AccelerationModel::Nominal,
            };
            let out = position_law(&params, &pgl, &agl, &input);
            for (i, c) in chunk.iter().enumerate() {
                let st = VehicleState::<S, $rot<S>> {
                    x: vs(c[0]),
                    v: vs(c[1]),
                    r: rots[i],
                    omega: vs(c[3]),
                };
                let input = PositionInput {
                    state: &st,
                    e_i_pos: vs(c[4]),
                    e_i_att: vs(c[5]),
                    reference: &refs[i],
                    model: AccelerationModel::Nominal,
                };
                let want = position_control(&pp, &pg, &ag, &input).expect("finite inputs");
                let d = out.degeneracy;
                assert_eq!(
                    (
                        d.thrust_direction_undefined.extract(i),
                        d.heading_undefined.extract(i)
                    ),
                    (
                        want.degeneracy.thrust_direction_undefined,
                        want.degeneracy.heading_undefined
                    ),
                    "lane {i}"
                );
                degenerate += usize::from(
                    want.degeneracy.thrust_direction_undefined || want.degeneracy.heading_undefined,
                );
                let flat_s = |o: &PositionOutput<S, $rot<S>>| {
                    let mut v = vec![o.thrust, o.psi];
                    for x in [
                        o.moment,
                        o.omega_c,
                        o.omega_c_dot,
                        o.e_r,
                        o.e_omega,
                        o.e_i_pos_rate,
                        o.e_i_att_rate,
                    ] {
                        v.extend(<S as SimdBackend>::vec3_to_array(x));
                    }
                    v
                };
                let lane = PositionOutput::<S, $rot<S>> {
                    thrust: out.thrust.simd_extract(i),
                    psi: out.psi.simd_extract(i),
                    moment: lie::lanes::vec3_lane::<S, L>(out.moment, i),
                    omega_c: lie::lanes::vec3_lane::<S, L>(out.omega_c, i),
                    omega_c_dot: lie::lanes::vec3_lane::<S, L>(out.omega_c_dot, i),
                    e_r: lie::lanes::vec3_lane::<S, L>(out.e_r, i),
                    e_omega: lie::lanes::vec3_lane::<S, L>(out.e_omega, i),
                    e_i_pos_rate: lie::lanes::vec3_lane::<S, L>(out.e_i_pos_rate, i),
                    e_i_att_rate: lie::lanes::vec3_lane::<S, L>(out.e_i_att_rate, i),
                    e_x: want.e_x,
                    e_v: want.e_v,
                    rc: want.rc,
                    degeneracy: want.degeneracy,
                };
                for (w, g) in flat_s(&want).into_iter().zip(flat_s(&lane)) {
                    let d = (w.to_f64_lossless().to_bits() as i64
                        - g.to_f64_lossless().to_bits() as i64)
                        .unsigned_abs();
                    worst = worst.max(d);
                }
                checked += 1;
            }
        }
        (worst, degenerate, checked)
    }};
}

#[test]
fn position_law_on_lanes_equals_the_scalar_law() {
    use controllers::{
        AccelerationModel, PositionGains, PositionInput, PositionOutput, PositionReference,
        VehicleState, position_control, position_law,
    };
    use lie::SimdMask;
    let results = [
        (
            "f64x4 matrix",
            compare_position!(
                NalgebraF64,
                NalgebraF64x4,
                So3Mat,
                mat_lanes::<NalgebraF64, NalgebraF64x4>
            ),
        ),
        (
            "f64x4 quaternion",
            compare_position!(
                NalgebraF64,
                NalgebraF64x4,
                So3Quat,
                quat_lanes::<NalgebraF64, NalgebraF64x4>
            ),
        ),
        (
            "f32x8 matrix",
            compare_position!(
                NalgebraF32,
                NalgebraF32x8,
                So3Mat,
                mat_lanes::<NalgebraF32, NalgebraF32x8>
            ),
        ),
        (
            "f32x8 quaternion",
            compare_position!(
                NalgebraF32,
                NalgebraF32x8,
                So3Quat,
                quat_lanes::<NalgebraF32, NalgebraF32x8>
            ),
        ),
    ];
    for (name, (ulps, degenerate, checked)) in results {
        println!(
            "position_law {name}: worst {ulps} ulp from the scalar law over {checked} vehicles, {degenerate} on a fallback"
        );
        assert!(
            degenerate > checked / 10,
            "{name}: too few fallback lanes ({degenerate})"
        );
        assert_eq!(ulps, 0, "{name}");
    }
}
