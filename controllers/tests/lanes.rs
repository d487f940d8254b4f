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

fn cases(n: usize) -> Vec<Case> {
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
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
        &RigidBodyParams::<B>::paper(),
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
        let params = {
            let p = RigidBodyParams::<S>::paper();
            RigidBodyParams::<L> {
                mass: SimdReal::simd_splat(p.mass),
                inertia: p.inertia.map(SimdReal::simd_splat),
                gravity: SimdReal::simd_splat(p.gravity),
            }
        };
        let gains = {
            let g = AttitudeGains::<S>::paper();
            AttitudeGains::<L> {
                k_r: g.k_r.map(SimdReal::simd_splat),
                k_omega: g.k_omega.map(SimdReal::simd_splat),
                k_i: g.k_i.map(SimdReal::simd_splat),
                c2: SimdReal::simd_splat(g.c2),
            }
        };
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
