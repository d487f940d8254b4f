//! Convergence orders on the closed loop with continuous control: the
//! paper's quadrotor with Δ_x, Δ_R under the geometric PID position
//! controller tracking a smooth circle, integral states e_I, e_i integrated
//! with the body (N = 6). Reference: Dormand–Prince at tol 1e-12.
//!
//! In f64 only, for the reason given in `orders.rs`: fitted orders need
//! errors far above f32's rounding.

mod common;

use common::*;
use controllers::{
    AccelerationModel, AttitudeGains, PositionGains, PositionReference, RigidBodyParams,
    VehicleState, position_control,
};
use dynamics::paper;
use dynamics::{Quadrotor, RigidBodyState, Vehicle, Wrench, loads};
use integrators::{
    Dopri, EndLoad, Euler, Integrator, Lgvi, Load, Rk4, Rkmk4, State, System, integrate_fixed,
};
use lie::{M3, NalgebraF64, S, So3Mat, V3, ops};

type B = NalgebraF64;

struct ClosedLoop {
    quad: Quadrotor<B>,
    params: RigidBodyParams<B>,
    pg: PositionGains<B>,
    ag: AttitudeGains<B>,
}

/// x_d = (r cos wt, r sin wt, −1 + 0.2 sin wt): smooth, with every derivative
/// up to snap in closed form.
fn reference(t: f64) -> PositionReference<B> {
    let (r, w) = (0.5, 1.5);
    let (s, c) = (w * t).sin_cos();
    let v3 = |x: f64, y: f64, z: f64| B::vec3(x, y, z);
    let mut p = PositionReference::<B>::hold(v3(0.0, 0.0, 0.0), v3(1.0, 0.0, 0.0));
    p.x = v3(r * c, r * s, -1.0 + 0.2 * s);
    p.v = v3(-r * w * s, r * w * c, 0.2 * w * c);
    p.a = v3(-r * w * w * c, -r * w * w * s, -0.2 * w * w * s);
    p.jerk = v3(r * w.powi(3) * s, -r * w.powi(3) * c, -0.2 * w.powi(3) * c);
    p.snap = v3(r * w.powi(4) * c, r * w.powi(4) * s, 0.2 * w.powi(4) * s);
    p
}

fn split(e: &[f64; 6]) -> (V3<B>, V3<B>) {
    (B::vec3(e[0], e[1], e[2]), B::vec3(e[3], e[4], e[5]))
}

impl System<B, 6> for ClosedLoop {
    fn mass(&self) -> S<B> {
        self.quad.mass()
    }
    fn inertia(&self) -> M3<B> {
        self.quad.inertia()
    }
    fn load(&mut self, t: f64, y: &State<B, 6>) -> Load<B, 6> {
        let (e_att, e_pos) = split(&y.extra);
        let st = VehicleState::<B, So3Mat<B>> {
            x: y.body.x,
            v: y.body.v,
            r: So3Mat::from_matrix_unchecked(y.body.r),
            omega: y.body.omega,
        };
        let out = position_control(
            &self.params,
            &self.pg,
            &self.ag,
            &controllers::PositionInput {
                state: &st,
                e_i_pos: e_pos,
                e_i_att: e_att,
                reference: &reference(t),
                model: AccelerationModel::Nominal,
            },
        )
        .expect("finite");
        let w = Wrench {
            thrust: out.thrust,
            moment: out.moment,
        };
        let l = loads(&self.quad, t, &y.body, &w);
        let (a, p) = (out.e_i_att_rate, out.e_i_pos_rate);
        Load {
            force: l.force,
            moment: l.moment,
            extra_rate: [a[0], a[1], a[2], p[0], p[1], p[2]],
        }
    }
}

fn system() -> ClosedLoop {
    ClosedLoop {
        quad: Quadrotor::<B>::paper()
            .with_disturbance(Quadrotor::<B>::paper_disturbance())
            .unwrap(),
        params: RigidBodyParams::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        pg: PositionGains::paper(),
        ag: AttitudeGains::paper(),
    }
}

fn run<I: Integrator<B, 6>>(integ: &mut I, t_end: f64, n: usize) -> State<B, 6> {
    let mut sys = system();
    let mut y = State::<B, 6>::new(RigidBodyState::at_rest());
    integrate_fixed(integ, &mut sys, 0.0, t_end / n as f64, n, &mut y).unwrap();
    y
}

fn error(y: &State<B, 6>, r: &State<B, 6>) -> f64 {
    let v = |a: V3<B>, b: V3<B>| ops::norm::<B>(a - b);
    let mut e = state_error::<B, 6>(y, mat_f64::<B>(r.body.r), vec_f64::<B>(r.body.omega));
    e = e.max(v(y.body.x, r.body.x)).max(v(y.body.v, r.body.v));
    for k in 0..6 {
        e = e.max((y.extra[k] - r.extra[k]).abs());
    }
    e
}

fn closed_loop_orders_with_continuous_control() {
    let t_end = 2.0;
    let mut reference = State::<B, 6>::new(RigidBodyState::at_rest());
    let mut sys = system();
    // Capped far above what the reference needs, so that a broken step
    // control fails instead of running on.
    let mut dp = Dopri::<B>::new(1e-12).max_substeps(100_000);
    for k in 0..20 {
        dp.step(&mut sys, 0.1 * k as f64, 0.1, &mut reference)
            .unwrap();
    }
    let mut out = format!(
        "closed loop (paper quadrotor, Δ_x, Δ_R, PID tracking a circle), T = {t_end} s, error in (R, x, v, Ω, e_I, e_i) vs dopri(1e-12)\n"
    );
    let mut fit = |name: &str,
                   expected: f64,
                   ns: [usize; 3],
                   f: &mut dyn FnMut(usize) -> State<B, 6>| {
        let hs: Vec<f64> = ns.iter().map(|&n| t_end / n as f64).collect();
        let errs: Vec<f64> = ns.iter().map(|&n| error(&f(n), &reference)).collect();
        let p = fitted_order(&hs, &errs);
        out += &format!(
            "{name:<14} h = {:.3e} {:.3e} {:.3e}  err = {:.3e} {:.3e} {:.3e}  fitted order {p:.3} (expected {expected})\n",
            hs[0], hs[1], hs[2], errs[0], errs[1], errs[2]
        );
        (name.to_string(), p, expected)
    };
    let results = [
        fit("euler", 1.0, [4000, 8000, 16000], &mut |n| {
            run(&mut Euler::default(), t_end, n)
        }),
        fit("lgvi", 2.0, [400, 800, 1600], &mut |n| {
            run(&mut Lgvi::<B, 6>::default(), t_end, n)
        }),
        fit("rk4", 4.0, [200, 400, 800], &mut |n| {
            run(&mut Rk4::default(), t_end, n)
        }),
        fit("rkmk4", 4.0, [200, 400, 800], &mut |n| {
            run(&mut Rkmk4, t_end, n)
        }),
    ];
    print!("{out}");
    for (name, p, expected) in results {
        assert!(
            (p - expected).abs() <= 0.3,
            "{name}: fitted {p:.3}, expected {expected}"
        );
    }
}

/// The LGVI's end-load iteration stops at 1e-4 of its first correction
/// (`EndLoad::Iterate`): the state it reaches differs from the fixed point
/// to rounding (`EndLoad::IterateToRounding`) by a small fraction of the
/// method's own error, with fewer load evaluations.
fn lgvi_end_load_stops_below_the_truncation_error() {
    let (t_end, n) = (2.0, 800);
    let h = t_end / n as f64;
    let mut reference = State::<B, 6>::new(RigidBodyState::at_rest());
    let mut sys = system();
    // Capped far above what the reference needs, so that a broken step
    // control fails instead of running on.
    let mut dp = Dopri::<B>::new(1e-12).max_substeps(100_000);
    for k in 0..20 {
        dp.step(&mut sys, 0.1 * k as f64, 0.1, &mut reference)
            .unwrap();
    }
    let go = |end_load: EndLoad| {
        let mut integ = Lgvi::<B, 6>::default();
        integ.end_load = end_load;
        let mut sys = system();
        let mut y = State::<B, 6>::new(RigidBodyState::at_rest());
        let mut evals = 0u64;
        for k in 0..n {
            let st = integ.step(&mut sys, k as f64 * h, h, &mut y).unwrap();
            evals += u64::from(st.evaluations);
        }
        (y, evals as f64 / n as f64)
    };
    let (fast, fast_evals) = go(EndLoad::Iterate { max: 50 });
    let (exact, exact_evals) = go(EndLoad::IterateToRounding { max: 50 });
    let own = error(&exact, &reference);
    let gap = error(&fast, &exact);
    println!(
        "lgvi h = {h:.1e}: error {own:.3e}; stopping at 1e-4 of the first correction moves the result by {gap:.1e} ({:.1e} of it), {fast_evals:.2} load evaluations per step instead of {exact_evals:.2}",
        gap / own
    );
    // 1e-3 of the method's error: the iteration is not what limits it.
    assert!(gap < 1e-3 * own, "gap {gap:e}, error {own:e}");
    assert!(
        fast_evals < exact_evals - 1.0,
        "{fast_evals} vs {exact_evals}"
    );
}

/// Harness-less so that a plain `cargo test` prints the fitted orders
/// (they are part of what the tests report); a failed fit panics, which fails
/// the test binary.
fn main() {
    testkit::run(&[
        (
            "closed_loop_orders_with_continuous_control",
            closed_loop_orders_with_continuous_control,
        ),
        (
            "lgvi_end_load_stops_below_the_truncation_error",
            lgvi_end_load_stops_below_the_truncation_error,
        ),
    ]);
}
