//! The lane steppers against the scalar ones: each lane of
//! `integrators::lanes::{rk4_step, DopriLanes}` on f64x4 must equal, to
//! the bit, the scalar `Rk4`, `Dopri` on that lane's initial state. Both
//! run the same generic stage functions with IEEE operations lane by lane
//! (this system has no transcendental function), so any difference is a
//! bug (a select that picked the wrong lane, a controller that mixed
//! lanes), not rounding. `rkmk4_step` calls `exp` and `J_r⁻¹`, whose lane
//! sin/cos are `wide`'s polynomials (within 2.2 ulp of libm, `lie`'s lane
//! tests): there the bound is 1e-12 after 300 steps.
//!
//! The system: a rigid body under a nonlinear, state-dependent load (a
//! spring–damper on the attitude, `M = −k e_R(R) − c Ω`, a force
//! `−x − v|v|`) with one extra state integrating `|Ω|²`, so that the
//! lanes' step sizes differ under Dormand–Prince.

use dynamics::RigidBodyState;
use integrators::lanes::{
    DopriLanes, LaneSystem, LgviLanes, rk4_projected_step, rk4_step, rkmk4_step, state_from_fn,
    state_lane,
};
use integrators::{Dopri, EndLoad, Integrator, Lgvi, Load, Rk4, Rkmk4, State, System};
use lie::{M3, NalgebraF64, NalgebraF64x4, S, SimdBackend, SimdReal, So3Mat, ops};

type E = NalgebraF64;
type L = NalgebraF64x4;

struct Spring<B: SimdBackend> {
    inertia: M3<B>,
    inertia_inv: M3<B>,
}

impl<B: SimdBackend> Spring<B> {
    fn new() -> Self {
        let l = S::<B>::simd_lit;
        Self {
            inertia: ops::diag::<B>(l(1.0), l(2.0), l(3.0)),
            inertia_inv: ops::diag::<B>(l(1.0), l(0.5), l(1.0 / 3.0)),
        }
    }

    /// Time enters as a polynomial push (plain arithmetic, so lanes and
    /// scalar round alike): a stage evaluated at the wrong time shows.
    fn loads(&self, t: S<B>, y: &State<B, 1>) -> Load<B, 1> {
        let l = S::<B>::simd_lit;
        let r = y.body.r;
        // e_R of R against I: ½ (R − Rᵀ)^∨.
        let e = lie::vee::<B>(r - B::mat3_transpose(r)) * l(0.5);
        let speed = ops::norm::<B>(y.body.v);
        let push = B::vec3(t * l(0.2), -(t * t) * l(0.1), l(0.0));
        Load {
            force: -(y.body.x + y.body.v * speed),
            moment: push - (e * l(4.0) + y.body.omega * l(0.3)),
            extra_rate: [B::dot(y.body.omega, y.body.omega) + t],
        }
    }
}

impl<B: SimdBackend> LaneSystem<B, 1> for Spring<B> {
    fn mass(&self) -> S<B> {
        S::<B>::simd_lit(1.5)
    }
    fn inertia(&self) -> M3<B> {
        self.inertia
    }
    fn inertia_inv(&self) -> M3<B> {
        self.inertia_inv
    }
    fn load(&mut self, t: S<B>, y: &State<B, 1>) -> Load<B, 1> {
        self.loads(t, y)
    }
}

impl System<E, 1> for Spring<E> {
    fn mass(&self) -> f64 {
        1.5
    }
    fn inertia(&self) -> M3<E> {
        self.inertia
    }
    fn inertia_inv(&self) -> M3<E> {
        self.inertia_inv
    }
    fn load(&mut self, t: f64, y: &State<E, 1>) -> Load<E, 1> {
        self.loads(t, y)
    }
}

/// Lane `i`'s start: attitudes from 0.3 to 2.9 rad, rates and offsets of
/// different sizes (lane 3 fast enough to need small steps).
fn start(i: usize) -> State<E, 1> {
    let k = i as f64;
    let v = |a: f64, b: f64, c: f64| E::vec3(a, b, c);
    State::new(RigidBodyState {
        r: So3Mat::<E>::exp(v(0.3 + 0.8 * k, -0.2 * k, 0.1)).as_matrix(),
        x: v(1.0 - k, 0.5, 0.2 * k),
        v: v(0.1, -0.3 * k, 0.0),
        omega: v(0.5 * k * k, -1.0, 2.0 * k),
    })
}

fn bits(y: &State<E, 1>) -> Vec<u64> {
    let b = &y.body;
    let mut out: Vec<u64> = ops::elems::<E>(b.r)
        .iter()
        .flatten()
        .map(|x| x.to_bits())
        .collect();
    for v in [b.x, b.v, b.omega] {
        out.extend(E::vec3_to_array(v).map(f64::to_bits));
    }
    out.push(y.extra[0].to_bits());
    out
}

/// A lane stepper: `(system, t, h, y)`.
type LaneStep<'a> = &'a mut dyn FnMut(&mut Spring<L>, S<L>, S<L>, &mut State<L, 1>);

/// The scalar stepper: `(t, y)`, one step of 0.01 s.
type ScalarStep<'a> = &'a mut dyn FnMut(f64, &mut State<E, 1>);

fn fixed_step(lane: LaneStep, scalar: ScalarStep, bound: f64) {
    let mut y = state_from_fn::<E, L, 1>(start);
    let mut sys = Spring::<L>::new();
    let h = <S<L> as SimdReal>::simd_lit(0.01);
    // Time summed step by step, as the scalar closures sum it: the LGVI
    // reuses its last load only when the next step starts at the time its
    // previous step ended.
    let mut t = <S<L> as SimdReal>::simd_lit(0.0);
    for _ in 0..300 {
        lane(&mut sys, t, h, &mut y);
        t += h;
    }
    for i in 0..4 {
        // Each lane from t = 0, time summed as the lanes sum it.
        let mut s = start(i);
        let mut ts = 0.0;
        for _ in 0..300 {
            scalar(ts, &mut s);
            ts += 0.01;
        }
        let (a, b) = (bits(&state_lane::<E, L, 1>(&y, i)), bits(&s));
        let worst = a
            .iter()
            .zip(&b)
            .map(|(x, y)| (f64::from_bits(*x) - f64::from_bits(*y)).abs())
            .fold(0.0, testkit::nan_max);
        assert!(worst <= bound, "lane {i}: {worst:e}");
    }
}

#[test]
fn rk4_lanes_equal_the_scalar_rk4() {
    let mut sys = Spring::<E>::new();
    let mut rk4 = Rk4::default();
    fixed_step(
        &mut rk4_step,
        &mut |t, s| {
            rk4.step(&mut sys, t, 0.01, s).unwrap();
        },
        0.0,
    );
}

/// The projection is the scalar one lane by lane (`lie`'s lane tests),
/// so the projected steps are equal to the bit too.
#[test]
fn rk4_projected_lanes_equal_the_scalar_rk4_projected() {
    let mut sys = Spring::<E>::new();
    let mut rk4 = Rk4::projected();
    fixed_step(
        &mut |sys, t, h, y| assert!(!lie::SimdMask::any(rk4_projected_step(sys, t, h, y))),
        &mut |t, s| {
            rk4.step(&mut sys, t, 0.01, s).unwrap();
        },
        0.0,
    );
}

/// The LGVI is rational (Cayley map, cofactor inverses, no sin/cos), so
/// its lanes equal the scalar stepper to the bit, with each lane's own
/// Newton and end-point iteration counts and the start load reused from
/// the previous step as the scalar stepper reuses it. The lanes start at
/// different rates, so their Newton solves stop at different passes in
/// most steps; iterated to rounding, so do their end-point iterations.
#[test]
fn lgvi_lanes_equal_the_scalar_lgvi() {
    for end_load in [
        EndLoad::Iterate { max: 50 },
        EndLoad::IterateToRounding { max: 50 },
        EndLoad::OneCorrection,
    ] {
        let mut sys = Spring::<E>::new();
        let mut lgvi = Lgvi::<E, 1>::default();
        lgvi.end_load = end_load;
        let mut lanes = LgviLanes::<L, 1>::default();
        lanes.end_load = end_load;
        fixed_step(
            &mut |sys, t, h, y| assert!(!lie::SimdMask::any(lanes.step(sys, t, h, y))),
            &mut |t, s| {
                let st = lgvi.step(&mut sys, t, 0.01, s).unwrap();
                assert_eq!(st.substeps, 1, "the scalar stepper halved a step");
            },
            0.0,
        );
    }
}

#[test]
fn rkmk4_lanes_equal_the_scalar_rkmk4() {
    let mut sys = Spring::<E>::new();
    fixed_step(
        &mut rkmk4_step,
        &mut |t, s| {
            Rkmk4.step(&mut sys, t, 0.01, s).unwrap();
        },
        1e-12,
    );
}

/// Per-lane step sizes: each lane takes its own accepted and rejected
/// substeps inside 0.05 s calls, as a scalar `Dopri` stepping call by call
/// on the grid `k·call` does (from `k·call` by `(k+1)·call − k·call`, as a
/// simulation's fixed grid calls it). After 3 s every lane's state and
/// accepted substeps equal the scalar run's.
#[test]
fn dopri_lanes_equal_the_scalar_dopri_lane_by_lane() {
    let (tol, call, calls) = (1e-8, 0.05, 60u64);
    let mut lanes = DopriLanes::<L, 1>::new(tol, call, 10_000);
    for i in 0..4 {
        lanes.start_lane::<E>(i, &start(i));
    }
    let mut sys = Spring::<L>::new();
    let mut substeps = 0;
    // Each lane's state and accepted substeps the moment it completes its
    // last call: a lane that gets there early goes on into the next call
    // (its neighbours still need substeps), so its state at the end of the
    // loop would be mid-call.
    let mut at_end: [Option<(Vec<u64>, u64)>; 4] = Default::default();
    while at_end.iter().any(Option::is_none) {
        let s = lanes.substep(&mut sys);
        assert!(!lie::SimdMask::any(s.failed));
        substeps += 1;
        assert!(substeps < 100_000, "no progress");
        for (i, end) in at_end.iter_mut().enumerate() {
            if end.is_none() && lanes.calls(i) == calls {
                *end = Some((
                    bits(&state_lane::<E, L, 1>(lanes.state(), i)),
                    lanes.accepted(i),
                ));
            }
        }
    }
    let mut differ = false;
    for (i, end) in at_end.iter().enumerate() {
        let (lane_bits, lane_accepted) = end.clone().expect("every lane finished");
        let mut sys = Spring::<E>::new();
        let mut dopri = Dopri::<E>::new(tol).max_substeps(100_000);
        let mut y = start(i);
        let mut accepted = 0;
        for k in 0..calls {
            let (t0, t1) = (k as f64 * call, (k + 1) as f64 * call);
            let st = dopri.step(&mut sys, t0, t1 - t0, &mut y).unwrap();
            accepted += u64::from(st.substeps);
        }
        assert_eq!(lane_bits, bits(&y), "lane {i}");
        assert_eq!(lane_accepted, accepted, "lane {i}: accepted substeps");
        differ |= lane_accepted != at_end[0].as_ref().unwrap().1;
    }
    assert!(
        differ,
        "every lane took the same substeps: the test does not exercise per-lane steps"
    );
}

/// The shared step: every lane takes the same substeps (the smallest
/// controlled size, accepted on the largest error), so all four lanes
/// accept as many substeps as the most demanding lane alone would, or
/// more, and each lane stays within its tolerance of the scalar stepper's
/// result. The bound: both hold the local error per substep below `tol`
/// (relative to the state's size, ≤ ~10 here), and the spring–damper is
/// contracting, so 60 calls (3 s) stay within 100 `tol`.
#[test]
fn shared_step_lanes_step_together_and_stay_within_tolerance() {
    let (tol, call, calls) = (1e-8, 0.05, 60u64);
    let mut lanes = DopriLanes::<L, 1>::new(tol, call, 10_000).shared_step(true);
    for i in 0..4 {
        lanes.start_lane::<E>(i, &start(i));
    }
    let mut sys = Spring::<L>::new();
    while (0..4).any(|i| lanes.calls(i) < calls) {
        let s = lanes.substep(&mut sys);
        assert!(!lie::SimdMask::any(s.failed));
    }
    let mut most = 0;
    for i in 0..4 {
        assert_eq!(lanes.accepted(i), lanes.accepted(0), "lane {i}");
        assert_eq!(lanes.calls(i), calls, "lane {i}");
        let mut sys = Spring::<E>::new();
        let mut dopri = Dopri::<E>::new(tol).max_substeps(100_000);
        let mut y = start(i);
        let mut accepted = 0;
        for k in 0..calls {
            let (t0, t1) = (k as f64 * call, (k + 1) as f64 * call);
            accepted += u64::from(dopri.step(&mut sys, t0, t1 - t0, &mut y).unwrap().substeps);
        }
        most = most.max(accepted);
        let diff = bits(&state_lane::<E, L, 1>(lanes.state(), i))
            .iter()
            .zip(bits(&y))
            .map(|(x, y)| (f64::from_bits(*x) - f64::from_bits(y)).abs())
            .fold(0.0, testkit::nan_max);
        assert!(diff < 100.0 * tol, "lane {i}: {diff:e}");
    }
    assert!(lanes.accepted(0) >= most, "{} < {most}", lanes.accepted(0));
}
