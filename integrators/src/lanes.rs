//! The steppers on SIMD lanes (`lie`'s lane backends, feature `simd`): one
//! call advances four or eight independent bodies, each lane with its own
//! time, step size and fate. The stages are those of the scalar steppers
//! ([`crate::Rk4`] plain and projected, [`crate::Rkmk4`], [`crate::Dopri`],
//! [`crate::Lgvi`]: [`rk4_step`], [`rk4_projected_step`], [`rkmk4_step`],
//! [`DopriLanes`], [`LgviLanes`]) operation for operation: RK4 and RKMK4
//! through the stage functions that are the scalar steps' twins, Dormand–
//! Prince through its trial-substep twin, the LGVI through its own solve
//! and end-point iteration. Each scalar stepper keeps its own code where
//! routing it through the lane code was measured slower for one lane; the
//! lane tests check every
//! lane against the scalar stepper to the bit. The drivers differ by
//! design, not for speed: [`DopriLanes`] gives each lane its own step
//! size and refills lanes one by one, and [`LgviLanes`] flags a lane
//! where [`crate::Lgvi`] halves the
//! step. What differs is failure: a lane whose
//! state turns non-finite, or whose step cannot be controlled, is
//! *flagged* and its neighbours go on, where the scalar steppers return an
//! error.
//!
//! [`DopriLanes`] is Dormand–Prince 5(4) with a step size *per lane*: each
//! lane accepts or rejects its own trial substep, so a lane in a fast
//! transient takes small steps while the others keep theirs (the accepted
//! state is selected lane by lane). Each lane advances in calls of a fixed
//! length, as [`crate::Dopri`] does inside a simulation's fixed grid, and
//! reports when it arrives at the end of one.

use lie::Real;
use lie::num_traits::{One, Zero};
use lie::{Backend, M3, S, SimdBackend, SimdMask, SimdReal, ops};

mod lgvi;
pub use lgvi::LgviLanes;

use crate::dopri::{error_norm, trial_lanes};
use crate::rk::{Body, Deriv, rk4_stages, rkmk4_stages};
use crate::{Load, State};

/// A rigid body with loads on lanes: [`crate::System`] for a lane backend,
/// without failure (a lane's non-finite load makes a non-finite state in
/// that lane only).
pub trait LaneSystem<B: SimdBackend, const N: usize> {
    /// Mass, kg (per lane).
    fn mass(&self) -> S<B>;
    /// Inertia, body frame.
    fn inertia(&self) -> M3<B>;
    /// `J⁻¹`.
    fn inertia_inv(&self) -> M3<B>;
    /// Whether `x` and `v` are integrated.
    fn translates(&self) -> bool {
        true
    }
    /// Whether [`LaneSystem::load`] reads `v`, `Ω` or the extra states
    /// (as [`crate::System::load_depends_on_rates`]).
    fn load_depends_on_rates(&self) -> bool {
        true
    }
    /// As [`crate::System::extra_in_use`].
    fn extra_in_use(&self) -> usize {
        N
    }
    /// Loads at time `t` (per lane) and state `y`.
    fn load(&mut self, t: S<B>, y: &State<B, N>) -> Load<B, N>;
}

fn body<B: SimdBackend, Sys: LaneSystem<B, N> + ?Sized, const N: usize>(sys: &Sys) -> Body<B> {
    Body::new(
        sys.inertia(),
        sys.inertia_inv(),
        S::<B>::one() / sys.mass(),
        sys.translates(),
        sys.extra_in_use(),
    )
}

/// One classical RK4 step of size `h` from `(t, y)` in every lane (the
/// stages of [`crate::Rk4`], on the embedding, R not projected).
pub fn rk4_step<B: SimdBackend, Sys: LaneSystem<B, N> + ?Sized, const N: usize>(
    sys: &mut Sys,
    t: S<B>,
    h: S<B>,
    y: &mut State<B, N>,
) {
    let b = body(sys);
    let Ok(next) =
        rk4_stages::<B, core::convert::Infallible, N>(&b, |t, y| Ok(sys.load(t, y)), t, h, y);
    *y = next;
}

/// One RK4 step with the attitude projected back onto SO(3) afterwards
/// (the stages and polar projection of [`crate::Rk4::projected`]) in every
/// lane. Returns the lanes whose projection failed (non-finite state,
/// `det R ≤ 0`, no convergence): their attitude is NaN, where the scalar
/// stepper returns [`crate::StepError::NonFinite`].
pub fn rk4_projected_step<B: SimdBackend, Sys: LaneSystem<B, N> + ?Sized, const N: usize>(
    sys: &mut Sys,
    t: S<B>,
    h: S<B>,
    y: &mut State<B, N>,
) -> LaneMask<B> {
    rk4_step(sys, t, h, y);
    let (r, ok) = lie::So3Mat::<B>::project_lanes(y.body.r);
    y.body.r = r.as_matrix();
    !ok
}

/// One RKMK4 step of size `h` from `(t, y)` in every lane (the stages of
/// [`crate::Rkmk4`]: the attitude stays on SO(3) to rounding).
pub fn rkmk4_step<B: SimdBackend, Sys: LaneSystem<B, N> + ?Sized, const N: usize>(
    sys: &mut Sys,
    t: S<B>,
    h: S<B>,
    y: &mut State<B, N>,
) {
    let b = body(sys);
    let Ok(next) =
        rkmk4_stages::<B, core::convert::Infallible, N>(&b, |t, y| Ok(sys.load(t, y)), t, h, y);
    *y = next;
}

/// `a` in the lanes of `mask`, `b` elsewhere.
pub fn select_state<B: SimdBackend, const N: usize>(
    mask: <S<B> as SimdReal>::Mask,
    a: &State<B, N>,
    b: &State<B, N>,
) -> State<B, N> {
    let v = |x, y| ops::select_vec::<B>(mask, x, y);
    State {
        body: lie::RigidState {
            r: ops::select_mat::<B>(mask, a.body.r, b.body.r),
            x: v(a.body.x, b.body.x),
            v: v(a.body.v, b.body.v),
            omega: v(a.body.omega, b.body.omega),
        },
        extra: core::array::from_fn(|i| S::<B>::simd_select(mask, a.extra[i], b.extra[i])),
    }
}

fn select_deriv<B: SimdBackend, const N: usize>(
    mask: <S<B> as SimdReal>::Mask,
    a: &Deriv<B, N>,
    b: &Deriv<B, N>,
) -> Deriv<B, N> {
    let v = |x, y| ops::select_vec::<B>(mask, x, y);
    Deriv {
        r: ops::select_mat::<B>(mask, a.r, b.r),
        x: v(a.x, b.x),
        v: v(a.v, b.v),
        w: v(a.w, b.w),
        e: core::array::from_fn(|i| S::<B>::simd_select(mask, a.e[i], b.e[i])),
    }
}

/// Lane `i` of `y` as a state of the scalar backend `E`.
pub fn state_lane<E, B, const N: usize>(y: &State<B, N>, i: usize) -> State<E, N>
where
    E: Backend,
    B: SimdBackend<Scalar: SimdReal<Element = E::Scalar>>,
{
    let v = |x| lie::lanes::vec3_lane::<E, B>(x, i);
    State {
        body: lie::RigidState {
            r: lie::lanes::mat3_lane::<E, B>(y.body.r, i),
            x: v(y.body.x),
            v: v(y.body.v),
            omega: v(y.body.omega),
        },
        extra: y.extra.map(|e| e.simd_extract(i)),
    }
}

/// Lane `i` is the scalar state `f(i)`.
pub fn state_from_fn<E, B, const N: usize>(f: impl Fn(usize) -> State<E, N>) -> State<B, N>
where
    E: Backend,
    B: SimdBackend<Scalar: SimdReal<Element = E::Scalar>>,
{
    let v =
        |part: fn(&State<E, N>) -> lie::V3<E>| lie::lanes::vec3_from_fn::<E, B>(|i| part(&f(i)));
    State {
        body: lie::RigidState {
            r: lie::lanes::mat3_from_fn::<E, B>(|i| f(i).body.r),
            x: v(|s| s.body.x),
            v: v(|s| s.body.v),
            omega: v(|s| s.body.omega),
        },
        extra: core::array::from_fn(|k| S::<B>::simd_from_fn(|i| f(i).extra[k])),
    }
}

/// `y` with lane `i` replaced by the scalar state `s`.
pub fn with_lane<E, B, const N: usize>(y: &State<B, N>, i: usize, s: &State<E, N>) -> State<B, N>
where
    E: Backend,
    B: SimdBackend<Scalar: SimdReal<Element = E::Scalar>>,
{
    let splat = state_from_fn::<E, B, N>(|_| *s);
    select_state(lie::lanes::mask_from_fn::<B>(|j| j == i), &splat, y)
}

/// Why a lane of [`DopriLanes`] stopped.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum LaneFailure {
    /// The error estimate was not finite (the state or a load went NaN/∞).
    NonFinite,
    /// The step size fell below rounding (16 ε relative to the time).
    StepTooSmall,
    /// One call took its cap of substeps (accepted and rejected).
    TooManySubsteps,
}

/// What one [`DopriLanes::substep`] did: the lanes that arrived at the end
/// of a call (their time is now a whole number of calls), and the lanes
/// that failed ([`DopriLanes::failure`] says why; their state is the last
/// accepted one).
#[derive(Copy, Clone, Debug)]
pub struct Substep<M> {
    /// Arrived at the end of a call.
    pub arrived: M,
    /// Failed in this substep.
    pub failed: M,
}

/// The lane mask type of backend `B`.
pub type LaneMask<B> = <S<B> as SimdReal>::Mask;

const MAX_LANES: usize = 16;

/// Dormand–Prince 5(4) with a step size per lane (see the module's
/// documentation). Lane calls end on the grid `n·call` (computed as
/// `n·call`, never summed), where a scalar [`crate::Dopri`] stepped
/// from `k·call` by `(k+1)·call − k·call` (a simulation's fixed grid)
/// ends its calls too; the stages, error norm, controller
/// `h ← h·clamp(0.9 err^(−1/5), 0.2, 5)`, tolerance floor and substep cap
/// of [`crate::Dopri`], lane by lane. Lanes are (re)started one at a
/// time from a scalar state with [`DopriLanes::start_lane`], so a driver
/// can refill a lane whose sample ended while the others go on.
#[derive(Clone, Debug)]
pub struct DopriLanes<B: SimdBackend, const N: usize> {
    tol: S<B>,
    call: f64,
    max_substeps: u32,
    y: State<B, N>,
    /// First stage of the next trial (first same as last).
    k1: Deriv<B, N>,
    t: S<B>,
    hs: S<B>,
    t_end: S<B>,
    /// Last controlled size (NaN before the first).
    h_next: S<B>,
    /// Lanes whose first stage is still to be evaluated.
    fresh: LaneMask<B>,
    count: [u32; MAX_LANES],
    calls: [u64; MAX_LANES],
    accepted: [u64; MAX_LANES],
    failure: [Option<LaneFailure>; MAX_LANES],
    /// One step size for every live lane (see [`DopriLanes::shared_step`]).
    shared: bool,
    /// Lanes started and neither stopped nor failed (bit `i` for lane `i`).
    live: u64,
}

impl<B: SimdBackend, const N: usize> DopriLanes<B, N> {
    /// Tolerance `tol` (relative and absolute, floored at the element's
    /// `ε` as [`crate::Dopri::new`] does), calls of `call` s, at most
    /// `max_substeps` substeps per call. Every lane holds the identity at
    /// rest until started.
    ///
    /// # Panics
    /// If the backend has more than 16 lanes.
    pub fn new(tol: f64, call: f64, max_substeps: u32) -> Self {
        assert!(<S<B> as SimdReal>::LANES <= MAX_LANES, "at most 16 lanes");
        let eps = <<S<B> as SimdReal>::Element as Real>::epsilon();
        let t = <<S<B> as SimdReal>::Element as lie::Real>::lit(tol);
        let tol = if Real::is_finite(t) && t > eps {
            t
        } else {
            eps
        };
        let z = S::<B>::zero();
        let zv = ops::zero::<B>();
        let i3 = ops::identity::<B>();
        Self {
            tol: S::<B>::simd_splat(tol),
            call,
            max_substeps,
            y: State {
                body: lie::RigidState {
                    r: i3,
                    x: zv,
                    v: zv,
                    omega: zv,
                },
                extra: [z; N],
            },
            k1: Deriv {
                r: i3 * z,
                x: zv,
                v: zv,
                w: zv,
                e: [z; N],
            },
            t: z,
            hs: S::<B>::simd_lit(call),
            t_end: S::<B>::simd_lit(call),
            h_next: S::<B>::simd_lit(f64::NAN),
            fresh: LaneMask::<B>::splat(true),
            count: [0; MAX_LANES],
            calls: [0; MAX_LANES],
            accepted: [0; MAX_LANES],
            failure: [None; MAX_LANES],
            shared: false,
            live: 0,
        }
    }

    /// With `on`, every live lane takes the same trial step (the smallest
    /// of their controlled sizes) and accepts or rejects it together, on
    /// the largest error norm among them: the ensemble solvers' way (a
    /// lane's result then depends on its neighbours, and every lane pays
    /// for any lane's transient). Off (the default), each lane controls its
    /// own step and equals the scalar [`crate::Dopri`]. A lane ending
    /// within a shared step (its call ends sooner) still stops at its own
    /// call end.
    pub fn shared_step(mut self, on: bool) -> Self {
        self.shared = on;
        self
    }

    /// Takes lane `i` out of the shared step's decisions (its sample
    /// ended and there is no next one); it goes on stepping, ignored,
    /// until [`DopriLanes::start_lane`] starts it again. No effect on the
    /// other lanes without [`DopriLanes::shared_step`].
    pub fn stop_lane(&mut self, i: usize) {
        self.live &= !(1 << i);
    }

    /// The states, every lane.
    pub fn state(&self) -> &State<B, N> {
        &self.y
    }

    /// The lanes' times.
    pub fn time(&self) -> S<B> {
        self.t
    }

    /// Calls lane `i` has completed since it started.
    pub fn calls(&self, i: usize) -> u64 {
        self.calls[i]
    }

    /// Accepted substeps of lane `i` since it started.
    pub fn accepted(&self, i: usize) -> u64 {
        self.accepted[i]
    }

    /// Why lane `i` failed, if it did.
    pub fn failure(&self, i: usize) -> Option<LaneFailure> {
        self.failure[i]
    }

    /// Starts lane `i` afresh from `y0` at `t = 0`; its neighbours keep
    /// their state. Its first stage is evaluated by the next substep.
    pub fn start_lane<E>(&mut self, i: usize, y0: &State<E, N>)
    where
        E: Backend,
        B: SimdBackend<Scalar: SimdReal<Element = E::Scalar>>,
    {
        self.y = with_lane(&self.y, i, y0);
        let lane = lie::lanes::mask_from_fn::<B>(|j| j == i);
        let call = S::<B>::simd_lit(self.call);
        self.t = S::<B>::simd_select(lane, S::<B>::zero(), self.t);
        self.hs = S::<B>::simd_select(lane, call, self.hs);
        self.t_end = S::<B>::simd_select(lane, call, self.t_end);
        self.h_next = S::<B>::simd_select(lane, S::<B>::simd_lit(f64::NAN), self.h_next);
        self.count[i] = 0;
        self.calls[i] = 0;
        self.accepted[i] = 0;
        self.failure[i] = None;
        self.live |= 1 << i;
        self.fresh = self.fresh | lane;
    }

    /// One trial substep in every lane: accepted lanes move on (and those
    /// whose substep ended their call arrive), rejected lanes shrink their
    /// step. A failed lane keeps failing until it is started again.
    pub fn substep<Sys: LaneSystem<B, N> + ?Sized>(
        &mut self,
        sys: &mut Sys,
    ) -> Substep<LaneMask<B>> {
        let b = body(sys);
        if self.fresh.any() {
            let k = b.deriv(&self.y, &sys.load(self.t, &self.y));
            self.k1 = select_deriv(self.fresh, &k, &self.k1);
            self.fresh = LaneMask::<B>::splat(false);
        }
        let l = S::<B>::simd_lit;
        if self.shared {
            self.hs = S::<B>::simd_splat(self.live_min(self.hs));
        }
        let remaining = self.t_end - self.t;
        let last = self.hs.simd_ge(remaining * l(1.0 - 1e-12));
        let hs = S::<B>::simd_select(last, remaining, self.hs);
        let zero = {
            let z = S::<B>::zero();
            let zv = ops::zero::<B>();
            State {
                body: lie::RigidState {
                    r: self.y.body.r * z,
                    x: zv,
                    v: zv,
                    omega: zv,
                },
                extra: [z; N],
            }
        };
        let Ok((next, k7, err)) = trial_lanes::<B, core::convert::Infallible, N>(
            &b,
            |t, y| Ok(sys.load(t, y)),
            (&self.y, &self.k1, &zero),
            (self.t, hs),
        );
        let mut en = error_norm(self.tol, self.tol, &b, (&self.y, &next, &err));
        let finite_en = en.simd_is_finite();
        // The live lane with the largest finite error, which decides a
        // shared step (a lane whose error is not finite fails on its own).
        let mut worst = None;
        if self.shared {
            let finite_bits = finite_en.bitmask();
            for i in 0..<S<B> as SimdReal>::LANES {
                let e = en.simd_extract(i);
                if (self.live & finite_bits) >> i & 1 == 1 && worst.is_none_or(|(_, w)| e > w) {
                    worst = Some((i, e));
                }
            }
            if let Some((_, w)) = worst {
                en = S::<B>::simd_select(finite_en, S::<B>::simd_splat(w), en);
            }
        }
        let worst = worst.map(|(i, _)| i);
        // The controller's power, lane by lane on the element type: the
        // same `powf` as the scalar stepper's.
        let fac = S::<B>::simd_from_fn(|i| {
            let e = en.simd_extract(i);
            let lit = <<S<B> as SimdReal>::Element as lie::Real>::lit;
            if e == lit(0.0) {
                lit(5.0)
            } else {
                (lit(0.9) * e.powf(lit(-0.2))).max(lit(0.2)).min(lit(5.0))
            }
        });
        let one = S::<B>::one();
        let accept = en.simd_le(one);
        self.y = select_state(accept, &next, &self.y);
        self.k1 = select_deriv(accept, &k7, &self.k1);
        let arrived = accept & last;
        let moving = accept & !last;
        self.t = S::<B>::simd_select(moving, self.t + hs, self.t);
        self.h_next = S::<B>::simd_select(moving, hs * fac, self.h_next);
        let rejected = S::<B>::simd_select(accept, hs, hs * fac.simd_min(one));
        self.hs = S::<B>::simd_select(moving, hs * fac, rejected);
        let floor = (self.t.simd_abs() + l(self.call))
            * S::<B>::simd_splat(<<S<B> as SimdReal>::Element as Real>::epsilon())
            * l(16.0);
        let too_small = self.hs.simd_le(floor).bitmask();
        let (finite, accept, arrived_bits) =
            (finite_en.bitmask(), accept.bitmask(), arrived.bitmask());
        let mut failed = 0u64;
        for i in 0..<S<B> as SimdReal>::LANES {
            let bit = |m: u64| m >> i & 1 == 1;
            if self.failure[i].is_some() {
                continue;
            }
            // Under a shared step the substep cap charges the lane that
            // decided the step: its neighbours' counts would otherwise
            // fail them for another lane's transient.
            if !self.shared || worst == Some(i) {
                self.count[i] += 1;
            }
            self.accepted[i] += u64::from(bit(accept));
            if bit(arrived_bits) {
                continue;
            }
            let why = if !bit(finite) {
                Some(LaneFailure::NonFinite)
            } else if self.count[i] >= self.max_substeps {
                Some(LaneFailure::TooManySubsteps)
            } else if bit(too_small) {
                Some(LaneFailure::StepTooSmall)
            } else {
                None
            };
            if why.is_some() {
                self.failure[i] = why;
                self.live &= !(1 << i);
                failed |= 1 << i;
            }
        }
        if arrived_bits != 0 {
            self.next_call(arrived, arrived_bits, hs);
        }
        let failed = lie::lanes::mask_from_fn::<B>(|j| failed >> j & 1 == 1);
        Substep { arrived, failed }
    }

    /// The smallest value of `x` among the live lanes (lane 0's when no
    /// lane is live: nothing then depends on it).
    fn live_min(&self, x: S<B>) -> <S<B> as SimdReal>::Element {
        let mut out = None;
        for i in 0..<S<B> as SimdReal>::LANES {
            if self.live >> i & 1 == 1 {
                let v = x.simd_extract(i);
                out = Some(out.map_or(v, |o: <S<B> as SimdReal>::Element| o.min(v)));
            }
        }
        out.unwrap_or_else(|| x.simd_extract(0))
    }

    /// The arrived lanes begin their next call: time on the call grid,
    /// the first trial the last controlled size (the shortened last
    /// substep's when there is none yet), capped at the call's length.
    fn next_call(&mut self, arrived: LaneMask<B>, bits: u64, hs: S<B>) {
        let lit = <<S<B> as SimdReal>::Element as lie::Real>::lit;
        for i in 0..<S<B> as SimdReal>::LANES {
            if bits >> i & 1 == 1 {
                self.calls[i] += 1;
                self.count[i] = 0;
            }
        }
        let calls = self.calls;
        let call = self.call;
        let t = S::<B>::simd_from_fn(|i| lit(calls[i] as f64 * call));
        let t_end = S::<B>::simd_from_fn(|i| lit((calls[i] + 1) as f64 * call));
        let had = self.h_next.simd_eq(self.h_next);
        let h_next = S::<B>::simd_select(had, self.h_next, hs);
        self.h_next = S::<B>::simd_select(arrived, h_next, self.h_next);
        self.t = S::<B>::simd_select(arrived, t, self.t);
        self.t_end = S::<B>::simd_select(arrived, t_end, self.t_end);
        let first = self.h_next.simd_min(S::<B>::simd_lit(call));
        self.hs = S::<B>::simd_select(arrived, first, self.hs);
    }
}
