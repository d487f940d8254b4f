//! The LGVI on lanes: [`crate::Lgvi`]'s Cayley–Newton solve and end-point
//! load iteration, each lane iterating until it meets the scalar stepper's
//! stopping test and then keeping its value while the other lanes go on,
//! so each lane is the scalar step to the bit (the lane tests check it).
//!
//! [`crate::Lgvi`] keeps its own code: on one lane this one does more
//! work, the cost of carrying masks where one lane needs a branch, and it
//! has no step halving to give.

use lie::Real;
use lie::num_traits::One;
use lie::{M3, S, SimdBackend, SimdMask, SimdReal, V3, hat, ops};

use super::{LaneMask, LaneSystem, body, select_state};
use crate::lgvi::{DEFAULT_END_LOAD, DEFAULT_MAX_NEWTON, cayley_minus_identity, inf_norm};
use crate::rk::Body;
use crate::{EndLoad, Load, State};

type Elem<B> = <S<B> as SimdReal>::Element;

fn splat<B: SimdBackend>(x: Elem<B>) -> S<B> {
    S::<B>::simd_splat(x)
}

/// `crate::lgvi::solve_cayley` in every lane: the Cayley vector and the
/// lanes where the solve converged to the near root.
fn solve_cayley<B: SimdBackend>(j: M3<B>, a: V3<B>, max_iter: u32) -> (V3<B>, LaneMask<B>) {
    let l = S::<B>::simd_lit;
    let two = l(2.0);
    let eps = splat::<B>(Elem::<B>::epsilon());
    let a_hat = hat::<B>(a);
    let id = ops::identity::<B>();
    let g = |f: V3<B>| a + B::cross(a, f) + f * B::dot(a, f) - j * f * two;
    let (start, ok) = ops::inverse_lanes::<B>(j * two - a_hat);
    let mut f = ops::select_vec::<B>(ok, start * a, a);
    // Lanes whose iteration has ended, by convergence or by a break.
    let mut stopped = !ok;
    let mut converged = LaneMask::<B>::splat(false);
    let mut prev_step = splat::<B>(Elem::<B>::infinity());
    for _ in 1..=max_iter {
        if stopped.all() {
            break;
        }
        let [a0, a1, a2] = B::vec3_to_array(a);
        let outer = B::mat3_from_cols(f * a0, f * a1, f * a2);
        let jac = a_hat + id * B::dot(a, f) + outer - j * two;
        let (jinv, invertible) = ops::inverse_lanes::<B>(jac);
        stopped = stopped | !invertible;
        let running = !stopped;
        let df = jinv * g(f);
        f = ops::select_vec::<B>(running, f - df, f);
        let step = inf_norm::<B>(df);
        let scale = S::<B>::one() + inf_norm::<B>(f);
        let finite = step.simd_is_finite();
        stopped = stopped | !finite;
        let running = running & finite;
        let settled = step.simd_le(eps * l(4.0) * scale)
            | (step.simd_ge(prev_step * l(0.5)) & step.simd_le(eps * l(1e3) * scale));
        converged = converged | (running & settled);
        stopped = stopped | (running & settled);
        prev_step = S::<B>::simd_select(running, step, prev_step);
    }
    let residual =
        ops::norm::<B>(g(f)) / (ops::norm::<B>(a) + splat::<B>(Elem::<B>::min_positive_value()));
    let near_root = ops::norm::<B>(f).simd_lt(S::<B>::one());
    (f, converged & near_root & residual.simd_is_finite())
}

fn select_load<B: SimdBackend, const N: usize>(
    mask: LaneMask<B>,
    a: &Load<B, N>,
    b: &Load<B, N>,
) -> Load<B, N> {
    Load {
        force: ops::select_vec::<B>(mask, a.force, b.force),
        moment: ops::select_vec::<B>(mask, a.moment, b.moment),
        extra_rate: core::array::from_fn(|i| {
            S::<B>::simd_select(mask, a.extra_rate[i], b.extra_rate[i])
        }),
    }
}

/// Lanes where `a` and `b` are equal in every component (NaN never is).
fn state_eq<B: SimdBackend, const N: usize>(a: &State<B, N>, b: &State<B, N>) -> LaneMask<B> {
    let vec_eq = |x: V3<B>, y: V3<B>| {
        let (x, y) = (B::vec3_to_array(x), B::vec3_to_array(y));
        x[0].simd_eq(y[0]) & x[1].simd_eq(y[1]) & x[2].simd_eq(y[2])
    };
    let (ra, rb) = (B::mat3_cols(a.body.r), B::mat3_cols(b.body.r));
    let mut eq = vec_eq(ra[0], rb[0]) & vec_eq(ra[1], rb[1]) & vec_eq(ra[2], rb[2]);
    eq = eq & vec_eq(a.body.x, b.body.x) & vec_eq(a.body.v, b.body.v);
    eq = eq & vec_eq(a.body.omega, b.body.omega);
    for i in 0..N {
        eq = eq & a.extra[i].simd_eq(b.extra[i]);
    }
    eq
}

/// Lanes whose state has no NaN or ±∞.
fn state_finite<B: SimdBackend, const N: usize>(y: &State<B, N>) -> LaneMask<B> {
    let mut ok = ops::finite_mat::<B>(y.body.r);
    ok = ok & ops::finite_vec::<B>(y.body.x) & ops::finite_vec::<B>(y.body.v);
    ok = ok & ops::finite_vec::<B>(y.body.omega);
    for e in &y.extra {
        ok = ok & e.simd_is_finite();
    }
    ok
}

/// `JΩ_{k+1} = JΩ_k + Dᵀp + h/2 (M_k + M_{k+1})`, solved for `Ω_{k+1}`,
/// as the scalar stepper forms it.
#[inline]
fn omega_end<B: SimdBackend, const N: usize>(
    b: &Body<B>,
    y: &State<B, N>,
    dtp: V3<B>,
    (m0, m1): (V3<B>, V3<B>),
    half_h: S<B>,
) -> V3<B> {
    y.body.omega + b.j_inv * (dtp + (m0 + m1) * half_h)
}

/// The trapezoidal LGVI of [`crate::Lgvi`] on lanes, one step of a common
/// `h` for every lane. Where the scalar stepper halves a step whose
/// implicit equations have no solution (`h‖Ω‖` near 1) or whose end-point
/// load iteration does not settle, a lane is *flagged* instead and keeps
/// its state: halving would give that lane a step size of its own. With
/// no lane flagged, every lane equals the scalar step to the bit (start
/// load reused from the previous step's last evaluation where the scalar
/// stepper reuses it).
#[derive(Clone, Debug)]
pub struct LgviLanes<B: SimdBackend, const N: usize> {
    /// Newton iteration cap for the attitude solve (as [`crate::Lgvi`]).
    pub max_newton: u32,
    /// End-point load treatment (as [`crate::Lgvi`]).
    pub end_load: EndLoad,
    cache: Option<(S<B>, State<B, N>, Load<B, N>)>,
}

impl<B: SimdBackend, const N: usize> Default for LgviLanes<B, N> {
    /// The scalar stepper's defaults: 20 Newton iterations, the end-point
    /// load iterated up to 50 times.
    fn default() -> Self {
        Self {
            max_newton: DEFAULT_MAX_NEWTON,
            end_load: DEFAULT_END_LOAD,
            cache: None,
        }
    }
}

impl<B: SimdBackend, const N: usize> LgviLanes<B, N> {
    /// One step of `h` from `(t, y)` in every lane. Returns the lanes that
    /// failed (no Cayley root, end-point iteration not settled, or a
    /// non-finite result); those lanes keep their state.
    pub fn step<Sys: LaneSystem<B, N> + ?Sized>(
        &mut self,
        sys: &mut Sys,
        t: S<B>,
        h: S<B>,
        y: &mut State<B, N>,
    ) -> LaneMask<B> {
        let b = body(sys);
        let half_h = h * S::<B>::simd_lit(0.5);
        let l0 = self.start_load(sys, t, y);
        let yb = &y.body;
        let p = b.j * yb.omega + l0.moment * half_h;
        let (f, solved) = solve_cayley::<B>(b.j, p * h, self.max_newton);
        // The increment form of the scalar stepper (its comment says why).
        let d_mat = cayley_minus_identity::<B>(f);
        let dtp = B::mat3_tr_mul_vec(d_mat, p);
        let mut next = *y;
        next.body.r = yb.r + yb.r * d_mat;
        if b.translates {
            next.body.x = yb.x + yb.v * h + l0.force * (h * half_h * b.inv_mass);
            next.body.v = yb.v + l0.force * (h * b.inv_mass);
        }
        next.body.omega = omega_end(&b, y, dtp, (l0.moment, l0.moment), half_h);
        for i in 0..N {
            next.extra[i] = y.extra[i] + h * l0.extra_rate[i];
        }
        let (next, l1, settled) = self.end_point(sys, &b, (t + h, h), (y, dtp), &l0, next);
        let ok = solved & settled & state_finite(&next);
        *y = select_state(ok, &next, y);
        self.cache = Some((t + h, next, l1));
        !ok
    }

    /// The start load: the previous step's last evaluation in the lanes
    /// that continue from where it left them (same time and state, as the
    /// scalar stepper checks), a fresh evaluation in the others.
    fn start_load<Sys: LaneSystem<B, N> + ?Sized>(
        &self,
        sys: &mut Sys,
        t: S<B>,
        y: &State<B, N>,
    ) -> Load<B, N> {
        match &self.cache {
            Some((tc, yc, lc)) => {
                let hit = tc.simd_eq(t) & state_eq(yc, y);
                if hit.all() {
                    *lc
                } else {
                    select_load(hit, lc, &sys.load(t, y))
                }
            }
            None => sys.load(t, y),
        }
    }

    /// The end-point load iteration of the scalar stepper, lane by lane:
    /// a lane stops iterating when its pass changes the state by less
    /// than its tolerance, and keeps that state and its last load.
    fn end_point<Sys: LaneSystem<B, N> + ?Sized>(
        &self,
        sys: &mut Sys,
        b: &Body<B>,
        (t1, h): (S<B>, S<B>),
        (y, dtp): (&State<B, N>, V3<B>),
        l0: &Load<B, N>,
        mut next: State<B, N>,
    ) -> (State<B, N>, Load<B, N>, LaneMask<B>) {
        let l = S::<B>::simd_lit;
        let half_h = h * l(0.5);
        let (passes, relative) = self.end_load.plan(sys.load_depends_on_rates());
        let relative = relative.map(l);
        let floor = splat::<B>(Elem::<B>::epsilon()) * l(4.0);
        let mut tol = floor;
        let mut done = LaneMask::<B>::splat(false);
        let mut l1 = *l0;
        let one = S::<B>::one();
        for pass in 0..passes {
            if done.all() {
                break;
            }
            let running = !done;
            let lp = sys.load(t1, &next);
            let mut cand = next;
            let w = omega_end(b, y, dtp, (l0.moment, lp.moment), half_h);
            let mut change = inf_norm::<B>(w - next.body.omega) / (one + inf_norm::<B>(w));
            cand.body.omega = w;
            if b.translates {
                let v = y.body.v + (l0.force + lp.force) * (half_h * b.inv_mass);
                change = change.simd_max(inf_norm::<B>(v - next.body.v) / (one + inf_norm::<B>(v)));
                cand.body.v = v;
            }
            for i in 0..N {
                let e = y.extra[i] + half_h * (l0.extra_rate[i] + lp.extra_rate[i]);
                change = change.simd_max((e - next.extra[i]).simd_abs() / (one + e.simd_abs()));
                cand.extra[i] = e;
            }
            next = select_state(running, &cand, &next);
            l1 = select_load(running, &lp, &l1);
            done = done | (running & change.simd_le(tol));
            if pass == 0
                && let Some(r) = relative
            {
                tol = (change * r).simd_max(floor);
            }
        }
        let settled = if passes == 1 {
            LaneMask::<B>::splat(true)
        } else {
            done
        };
        (next, l1, settled)
    }
}
