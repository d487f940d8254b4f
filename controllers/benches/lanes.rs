//! `cargo bench -p geopid-controllers --features simd --bench lanes`: the attitude
//! law (`attitude_law`, the unchecked law both flight modes share) and the
//! position law (`position_law`) for a batch of [`BATCH`] vehicles, one
//! vehicle per call on the scalar backends and four or eight per call on
//! the lane backends. Criterion's throughput is the batch, so its time per
//! element is per vehicle. The checked laws (`attitude_control`,
//! `position_control`) are the scalar rows of `cargo bench -p geopid-controllers`.

use controllers::{
    AccelerationModel, AttitudeGains, AttitudeReference, PositionGains, PositionInput,
    PositionReference, RigidBodyParams, VehicleState, attitude_law, position_law,
};
use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use dynamics::paper;
use lie::{
    Backend, GlamF32, GlamF64, NalgebraF32, NalgebraF32x8, NalgebraF64, NalgebraF64x4, Real,
    SimdBackend, SimdReal, So3Mat, V3, lanes,
};
use std::hint::black_box;

/// Vehicles per timed iteration.
const BATCH: usize = 64;

/// One vehicle's inputs on backend `B`.
#[derive(Clone, Copy)]
struct Inputs<B: SimdBackend> {
    r: So3Mat<B>,
    omega: V3<B>,
    e_i: V3<B>,
    reference: AttitudeReference<B, So3Mat<B>>,
    x: V3<B>,
    v: V3<B>,
    e_i_pos: V3<B>,
    position: PositionReference<B>,
}

/// Vehicle `i`'s inputs on a scalar backend (mid-flight, all different).
fn vehicle<S: Backend>(i: usize) -> Inputs<S> {
    let t = i as f64 * 0.37;
    let v =
        |a: f64, b: f64, c: f64| S::vec3(S::Scalar::lit(a), S::Scalar::lit(b), S::Scalar::lit(c));
    Inputs {
        r: So3Mat::<S>::exp(v(0.3 * t.sin(), 0.2 * t.cos(), -0.4 * (2.0 * t).sin())),
        omega: v(0.4 * t.cos(), -0.7, 0.2 * t.sin()),
        e_i: v(0.01, -0.02 * t.sin(), 0.005),
        reference: AttitudeReference {
            rd: So3Mat::<S>::exp(v(-0.1, 0.2 * t.sin(), 0.3)),
            omega_d: v(0.1, 0.0, -0.2 * t.cos()),
            omega_d_dot: v(0.0, 0.5 * t.sin(), 0.1),
        },
        x: v(0.3 * t.cos(), -0.2, -1.1),
        v: v(0.5, 0.1 * t.sin(), -0.3),
        e_i_pos: v(0.02, -0.01, 0.03 * t.cos()),
        position: PositionReference {
            x: v(0.1, 0.0, -1.0),
            v: v(0.2, 0.1, 0.0),
            a: v(-0.1, 0.3 * t.sin(), 0.0),
            jerk: v(0.2, -0.1, 0.0),
            snap: v(0.0, 0.1, 0.0),
            b1d: v(t.cos(), t.sin(), 0.0),
            b1d_dot: v(-0.1 * t.sin(), 0.1 * t.cos(), 0.0),
            b1d_ddot: v(-0.01 * t.cos(), -0.01 * t.sin(), 0.0),
        },
    }
}

/// The batch packed into lanes of `L` (one vehicle per lane).
fn packed<S, L>() -> Vec<Inputs<L>>
where
    S: Backend,
    L: SimdBackend<Scalar: SimdReal<Element = S::Scalar>>,
{
    let n = <L::Scalar as SimdReal>::LANES;
    (0..BATCH / n)
        .map(|g| {
            let at = |i: usize| vehicle::<S>(g * n + i);
            Inputs {
                r: So3Mat::from_matrix_unchecked(lanes::mat3_from_fn::<S, L>(|i| {
                    at(i).r.as_matrix()
                })),
                omega: lanes::vec3_from_fn::<S, L>(|i| at(i).omega),
                e_i: lanes::vec3_from_fn::<S, L>(|i| at(i).e_i),
                reference: AttitudeReference {
                    rd: So3Mat::from_matrix_unchecked(lanes::mat3_from_fn::<S, L>(|i| {
                        at(i).reference.rd.as_matrix()
                    })),
                    omega_d: lanes::vec3_from_fn::<S, L>(|i| at(i).reference.omega_d),
                    omega_d_dot: lanes::vec3_from_fn::<S, L>(|i| at(i).reference.omega_d_dot),
                },
                x: lanes::vec3_from_fn::<S, L>(|i| at(i).x),
                v: lanes::vec3_from_fn::<S, L>(|i| at(i).v),
                e_i_pos: lanes::vec3_from_fn::<S, L>(|i| at(i).e_i_pos),
                position: PositionReference::from_lanes(|i| at(i).position),
            }
        })
        .collect()
}

/// What one bench row needs: the laws' constants and the batch.
struct Setup<B: SimdBackend> {
    params: RigidBodyParams<B>,
    gains: AttitudeGains<B>,
    position_gains: PositionGains<B>,
    batch: Vec<Inputs<B>>,
}

fn run<B: SimdBackend>(c: &mut Criterion, id: &str, s: Setup<B>) {
    let mut g = c.benchmark_group("lanes/attitude");
    g.throughput(Throughput::Elements(BATCH as u64));
    g.bench_function(id, |b| {
        b.iter(|| {
            for x in black_box(&s.batch) {
                black_box(attitude_law(
                    &s.params,
                    &s.gains,
                    x.r,
                    x.omega,
                    x.e_i,
                    &x.reference,
                ));
            }
        })
    });
    g.finish();
    let mut g = c.benchmark_group("lanes/position");
    g.throughput(Throughput::Elements(BATCH as u64));
    g.bench_function(id, |b| {
        b.iter(|| {
            for x in black_box(&s.batch) {
                let state = VehicleState {
                    x: x.x,
                    v: x.v,
                    r: x.r,
                    omega: x.omega,
                };
                let input = PositionInput {
                    state: &state,
                    e_i_pos: x.e_i_pos,
                    e_i_att: x.e_i,
                    reference: &x.position,
                    model: AccelerationModel::Nominal,
                };
                black_box(position_law(&s.params, &s.position_gains, &s.gains, &input));
            }
        })
    });
    g.finish();
}

fn scalar<S: Backend>(c: &mut Criterion) {
    let setup = Setup {
        params: RigidBodyParams::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        gains: AttitudeGains::paper(),
        position_gains: PositionGains::paper(),
        batch: (0..BATCH).map(vehicle::<S>).collect(),
    };
    run::<S>(c, S::NAME, setup);
}

fn lanes_of<S, L>(c: &mut Criterion)
where
    S: Backend,
    L: SimdBackend<Scalar: SimdReal<Element = S::Scalar>>,
{
    let setup = Setup {
        params: RigidBodyParams::splat(&RigidBodyParams::<S>::diagonal(
            paper::MASS,
            paper::INERTIA,
            paper::GRAVITY,
        )),
        gains: AttitudeGains::splat(&AttitudeGains::<S>::paper()),
        position_gains: PositionGains::splat(&PositionGains::<S>::paper()),
        batch: packed::<S, L>(),
    };
    run::<L>(c, L::NAME, setup);
}

fn benches(c: &mut Criterion) {
    scalar::<GlamF32>(c);
    scalar::<GlamF64>(c);
    scalar::<NalgebraF32>(c);
    scalar::<NalgebraF64>(c);
    lanes_of::<NalgebraF64, NalgebraF64x4>(c);
    lanes_of::<NalgebraF32, NalgebraF32x8>(c);
}

criterion_group!(lanes_bench, benches);
criterion_main!(lanes_bench);
