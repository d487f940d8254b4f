//! Adaptive embedded Dormand–Prince 5(4) on the embedding, for reference
//! solutions.

use lie::num_traits::Zero;
use lie::{Backend, Real, S, SimdBackend, SimdReal, ops};

use crate::Load;
use crate::rk::{Body, Deriv, check_h, combine, eval, finish};
use crate::{Integrator, State, StepError, StepStats, System};

// Dormand & Prince (1980), the 5th-order weights (= last stage row) and the
// difference 5th − 4th for the error estimate.
const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];
const A2: [f64; 1] = [0.2];
const A3: [f64; 2] = [3.0 / 40.0, 9.0 / 40.0];
const A4: [f64; 3] = [44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0];
const A5: [f64; 4] = [
    19372.0 / 6561.0,
    -25360.0 / 2187.0,
    64448.0 / 6561.0,
    -212.0 / 729.0,
];
const A6: [f64; 5] = [
    9017.0 / 3168.0,
    -355.0 / 33.0,
    46732.0 / 5247.0,
    49.0 / 176.0,
    -5103.0 / 18656.0,
];
const B5: [f64; 6] = [
    35.0 / 384.0,
    0.0,
    500.0 / 1113.0,
    125.0 / 192.0,
    -2187.0 / 6784.0,
    11.0 / 84.0,
];
const E: [f64; 7] = [
    71.0 / 57600.0,
    0.0,
    -71.0 / 16695.0,
    71.0 / 1920.0,
    -17253.0 / 339200.0,
    22.0 / 525.0,
    -1.0 / 40.0,
];

/// Dormand–Prince 5(4) with step-size control, advancing the embedding (R as
/// nine numbers, not projected, so that the reference is a plain ODE
/// solution whose error is set by the tolerance alone).
///
/// [`Integrator::step`] integrates exactly from `t` to `t + h` (the last
/// substep is shortened to land on `t + h`), taking as many internal
/// substeps as the tolerance needs; the last accepted substep size is kept
/// as the next call's first guess. The error of a substep is the RMS over
/// all components of `err_i / (atol + rtol·max(|y_i|, |y_new_i|))`, accepted
/// when ≤ 1; the controller is `h ← h·clamp(0.9 err^(−1/5), 0.2, 5)`.
/// Tolerances below the scalar's `ε` are raised to it ([`Dopri::floor`]):
/// f32 cannot deliver 1e-12. The error estimate is formed directly as
/// `h Σ eᵢ kᵢ` (not as a difference of two solutions), so it stays
/// meaningful down to `ε`; what limits the accuracy there is the rounding
/// of the state itself. (The floor was `100 ε` at first, which in f32
/// silently turned every tolerance below 1.2e-5 into 1.2e-5: paper-flip
/// stopped at an error of 5e-5 where tolerance 1e-7 now reaches 4.8e-7.)
#[derive(Clone, Debug)]
pub struct Dopri<B: Backend> {
    rtol: S<B>,
    atol: S<B>,
    h_next: Option<S<B>>,
    max_substeps: u32,
    /// The accepted substeps' sizes, when asked for ([`Dopri::logging_substeps`]).
    log: Option<Vec<f64>>,
    /// Substep sizes to take instead of the controller's, and the next one
    /// ([`Dopri::replaying_substeps`]).
    replay: Option<(Vec<f64>, usize)>,
}

impl<B: Backend> Dopri<B> {
    /// The smallest tolerance the scalar supports, its `ε` (1.2e-7 in f32,
    /// 2.2e-16 in f64). Callers that take a tolerance from a user should
    /// warn when it is below this (see [`Dopri::new`]).
    pub fn floor() -> S<B> {
        S::<B>::epsilon()
    }

    /// Relative and absolute tolerance `tol` (> 0); one below
    /// [`Dopri::floor`] is raised to it.
    pub fn new(tol: S<B>) -> Self {
        let floor = Self::floor();
        let tol = if Real::is_finite(tol) && tol > floor {
            tol
        } else {
            floor
        };
        Self {
            rtol: tol,
            atol: tol,
            h_next: None,
            max_substeps: u32::MAX,
            log: None,
            replay: None,
        }
    }

    /// Takes the substeps `sizes` in order (as [`Dopri::take_substep_log`]
    /// gave them) instead of the controller's, accepting each: the logged
    /// run's steps at fixed sizes, so that a run with changed parameters
    /// takes the same steps (the derivative a dual run computes, whose
    /// step-size control reads values only). Once `sizes` runs out the
    /// controller takes over.
    pub fn replaying_substeps(mut self, sizes: Vec<f64>) -> Self {
        self.replay = Some((sizes, 0));
        self
    }

    /// The next replayed substep size, if replaying.
    fn replayed(&mut self) -> Option<S<B>> {
        let (sizes, next) = self.replay.as_mut()?;
        let h = *sizes.get(*next)?;
        *next += 1;
        Some(S::<B>::lit(h))
    }

    /// Keeps the size of every accepted substep (in order, the last of a
    /// call shortened as taken), for [`Dopri::take_substep_log`]: what a
    /// replay of this run's step sequence at fixed sizes needs (comparing
    /// derivatives of a run with finite differences of runs that take the
    /// same steps).
    pub fn logging_substeps(mut self) -> Self {
        self.log = Some(Vec::new());
        self
    }

    /// The substep sizes logged since the last call (empty unless
    /// [`Dopri::logging_substeps`]).
    pub fn take_substep_log(&mut self) -> Vec<f64> {
        self.log.as_mut().map(std::mem::take).unwrap_or_default()
    }

    /// Fail a call with [`StepError::TooManySubsteps`] once it has taken
    /// `n` substeps (accepted or rejected). A solution that blows up in
    /// finite time otherwise makes one call grind through millions of
    /// ever smaller substeps before anything outside can look at it; a
    /// Monte Carlo driver classifies such a sample as diverged instead.
    pub fn max_substeps(mut self, n: u32) -> Self {
        self.max_substeps = n;
        self
    }

    /// The tolerance in use (after the floor).
    pub fn tolerance(&self) -> S<B> {
        self.rtol
    }
}

impl<B: Backend, const N: usize> Integrator<B, N> for Dopri<B> {
    fn name(&self) -> &'static str {
        "dopri"
    }
    fn order(&self) -> u32 {
        5
    }
    fn step<Sys: System<B, N> + ?Sized>(
        &mut self,
        sys: &mut Sys,
        t: S<B>,
        h: S<B>,
        y: &mut State<B, N>,
    ) -> Result<StepStats, StepError> {
        check_h::<B>(h)?;
        let l = S::<B>::lit;
        let body = Body::of(sys);
        let t_end = t + h;
        let mut stats = StepStats::default();
        let mut cur = *y;
        let mut tc = t;
        // Step-size control reads values only (`with_derivatives_of(0)`
        // drops derivatives, and is nothing for f32/f64): a run on a scalar
        // with derivatives takes the plain run's substeps, as constants.
        let value = |x: S<B>| lie::SimdReal::with_derivatives_of(x, S::<B>::zero());
        let mut hs = match self.replayed() {
            Some(r) => r,
            None => value(self.h_next.unwrap_or(h).min(h)),
        };
        let mut k1 = body.deriv(&cur, &eval(sys, tc, &cur)?);
        stats.evaluations += 1;
        let zero_state = {
            let mut z = cur;
            z.body.r = z.body.r * S::<B>::zero();
            z.body.x = z.body.x * S::<B>::zero();
            z.body.v = z.body.v * S::<B>::zero();
            z.body.omega = z.body.omega * S::<B>::zero();
            z.extra = [S::<B>::zero(); N];
            z
        };
        loop {
            let remaining = t_end - tc;
            let last = hs >= remaining * l(1.0 - 1e-12);
            if last {
                hs = remaining;
            }
            let (next, k7, err) = trial(sys, &body, &cur, &k1, &zero_state, (tc, hs), &mut stats)?;
            let en = value(error_norm(self.atol, self.rtol, &body, (&cur, &next, &err)));
            if !Real::is_finite(en) {
                return Err(StepError::NonFinite {
                    field: "dopri error estimate",
                    t: tc.to_f64_lossless(),
                });
            }
            let fac = if en == S::<B>::zero() {
                l(5.0)
            } else {
                (l(0.9) * en.powf(l(-0.2))).max(l(0.2)).min(l(5.0))
            };
            if en <= S::<B>::one() || self.replay.is_some() {
                stats.substeps += 1;
                if let Some(log) = &mut self.log {
                    log.push(hs.to_f64_lossless());
                }
                cur = next;
                k1 = k7;
                if last {
                    break;
                }
                tc += hs;
                // The next guess: controlled size, but not beyond the end.
                if !last {
                    self.h_next = Some(hs * fac);
                }
                hs = match self.replayed() {
                    Some(r) => r,
                    None => hs * fac,
                };
            } else {
                stats.rejected += 1;
                hs *= fac.min(S::<B>::one());
            }
            if stats.substeps.saturating_add(stats.rejected) >= self.max_substeps {
                return Err(StepError::TooManySubsteps {
                    t: tc.to_f64_lossless(),
                    h: hs.to_f64_lossless(),
                    substeps: self.max_substeps,
                });
            }
            if hs <= (tc.abs() + h) * S::<B>::epsilon() * l(16.0) {
                return Err(StepError::StepTooSmall {
                    t: tc.to_f64_lossless(),
                    h: hs.to_f64_lossless(),
                });
            }
        }
        // A shortened last substep says nothing about the controlled size;
        // keep the last unshortened proposal.
        if self.h_next.is_none() {
            self.h_next = Some(hs);
        }
        finish(t, y, cur)?;
        Ok(stats)
    }
    fn reset(&mut self) {}
    fn resampler(&self) -> Option<Self> {
        Some(self.clone())
    }
    fn limit_substeps(&mut self, cap: u32) {
        self.max_substeps = cap;
    }
}

/// [`Dopri`]'s error norm, one function for one lane and many (the scalar
/// and the lane stepper's): the RMS over all components of
/// `err_i / (atol + rtol·max(|y_i|, |y_new_i|))` (`x`, `v` only when the
/// body translates; the extra slots the system uses, not the idle ones,
/// whose zeros would dilute the mean and lengthen the steps), lane by lane
/// on a lane backend: each lane's step is judged on its own components
/// alone.
#[inline(always)]
pub(crate) fn error_norm<B: SimdBackend, const N: usize>(
    atol: S<B>,
    rtol: S<B>,
    body: &Body<B>,
    (y, next, err): (&State<B, N>, &State<B, N>, &State<B, N>),
) -> S<B> {
    let mut sum = S::<B>::zero();
    let mut count = 0usize;
    let mut add = |e: S<B>, a: S<B>, b: S<B>| {
        let sc = atol + rtol * a.simd_abs().simd_max(b.simd_abs());
        let r = e / sc;
        sum += r * r;
        count += 1;
    };
    let (ey, en, ee) = (
        ops::elems::<B>(y.body.r),
        ops::elems::<B>(next.body.r),
        ops::elems::<B>(err.body.r),
    );
    for i in 0..3 {
        for k in 0..3 {
            add(ee[i][k], ey[i][k], en[i][k]);
        }
    }
    let mut vecs = |a: lie::V3<B>, b: lie::V3<B>, e: lie::V3<B>| {
        let (a, b, e) = (
            B::vec3_to_array(a),
            B::vec3_to_array(b),
            B::vec3_to_array(e),
        );
        for i in 0..3 {
            add(e[i], a[i], b[i]);
        }
    };
    vecs(y.body.omega, next.body.omega, err.body.omega);
    if body.translates {
        vecs(y.body.x, next.body.x, err.body.x);
        vecs(y.body.v, next.body.v, err.body.v);
    }
    for i in 0..body.extra_in_use.min(N) {
        add(err.extra[i], y.extra[i], next.extra[i]);
    }
    (sum / S::<B>::simd_lit(count as f64)).simd_sqrt()
}

/// A trial substep's solution, last stage and error estimate.
type Trial<B, const N: usize> = (State<B, N>, Deriv<B, N>, State<B, N>);

/// One Dormand–Prince trial substep of size `hs` from `(tc, cur)` whose
/// first stage is `k1`: the fifth-order solution, its last stage (the next
/// substep's first: first same as last) and the embedded error estimate
/// (`zero_state` carries the shape of a state with every entry zero).
fn trial<B: Backend, const N: usize, Sys: System<B, N> + ?Sized>(
    sys: &mut Sys,
    body: &Body<B>,
    cur: &State<B, N>,
    k1: &Deriv<B, N>,
    zero_state: &State<B, N>,
    (tc, hs): (S<B>, S<B>),
    stats: &mut StepStats,
) -> Result<Trial<B, N>, StepError> {
    let l = S::<B>::lit;
    let stage = |sys: &mut Sys,
                 c: f64,
                 ys: State<B, N>,
                 stats: &mut StepStats|
     -> Result<Deriv<B, N>, StepError> {
        stats.evaluations += 1;
        Ok(body.deriv(&ys, &eval(sys, tc + hs * l(c), &ys)?))
    };
    let k2 = stage(sys, C[1], combine(body, cur, hs, [(l(A2[0]), k1)]), stats)?;
    let k3 = stage(
        sys,
        C[2],
        combine(body, cur, hs, [(l(A3[0]), k1), (l(A3[1]), &k2)]),
        stats,
    )?;
    let k4 = stage(
        sys,
        C[3],
        combine(
            body,
            cur,
            hs,
            [(l(A4[0]), k1), (l(A4[1]), &k2), (l(A4[2]), &k3)],
        ),
        stats,
    )?;
    let k5 = stage(
        sys,
        C[4],
        combine(
            body,
            cur,
            hs,
            [
                (l(A5[0]), k1),
                (l(A5[1]), &k2),
                (l(A5[2]), &k3),
                (l(A5[3]), &k4),
            ],
        ),
        stats,
    )?;
    let k6 = stage(
        sys,
        C[5],
        combine(
            body,
            cur,
            hs,
            [
                (l(A6[0]), k1),
                (l(A6[1]), &k2),
                (l(A6[2]), &k3),
                (l(A6[3]), &k4),
                (l(A6[4]), &k5),
            ],
        ),
        stats,
    )?;
    let next = combine(
        body,
        cur,
        hs,
        [
            (l(B5[0]), k1),
            (l(B5[2]), &k3),
            (l(B5[3]), &k4),
            (l(B5[4]), &k5),
            (l(B5[5]), &k6),
        ],
    );
    let k7 = stage(sys, C[6], next, stats)?;
    let err = combine(
        body,
        zero_state,
        hs,
        [
            (l(E[0]), k1),
            (l(E[2]), &k3),
            (l(E[3]), &k4),
            (l(E[4]), &k5),
            (l(E[5]), &k6),
            (l(E[6]), &k7),
        ],
    );
    Ok((next, k7, err))
}

/// [`Dopri`]'s trial substep for any `SimdBackend` (the lane stepper's),
/// operation for operation (the lane tests check it to the bit). The
/// scalar stepper keeps its own copy: routing it through this function
/// (a closure for the load) cost 2–3 % per step in f64 in the `scenarios`
/// step bench, and the scalar path must not pay for lanes.
///
/// One Dormand–Prince trial substep of size `hs` from `(tc, cur)` whose
/// first stage is `k1`: the fifth-order solution, its last stage (the next
/// substep's first: first same as last) and the embedded error estimate
/// (`zero_state` carries the shape of a state with every entry zero).
pub(crate) fn trial_lanes<B: SimdBackend, E, const N: usize>(
    body: &Body<B>,
    mut load: impl FnMut(S<B>, &State<B, N>) -> Result<Load<B, N>, E>,
    (cur, k1, zero_state): (&State<B, N>, &Deriv<B, N>, &State<B, N>),
    (tc, hs): (S<B>, S<B>),
) -> Result<Trial<B, N>, E> {
    let l = S::<B>::simd_lit;
    let mut stage = |c: f64, ys: State<B, N>| -> Result<Deriv<B, N>, E> {
        Ok(body.deriv(&ys, &load(tc + hs * l(c), &ys)?))
    };
    let k2 = stage(C[1], combine(body, cur, hs, [(l(A2[0]), k1)]))?;
    let k3 = stage(
        C[2],
        combine(body, cur, hs, [(l(A3[0]), k1), (l(A3[1]), &k2)]),
    )?;
    let k4 = stage(
        C[3],
        combine(
            body,
            cur,
            hs,
            [(l(A4[0]), k1), (l(A4[1]), &k2), (l(A4[2]), &k3)],
        ),
    )?;
    let k5 = stage(
        C[4],
        combine(
            body,
            cur,
            hs,
            [
                (l(A5[0]), k1),
                (l(A5[1]), &k2),
                (l(A5[2]), &k3),
                (l(A5[3]), &k4),
            ],
        ),
    )?;
    let k6 = stage(
        C[5],
        combine(
            body,
            cur,
            hs,
            [
                (l(A6[0]), k1),
                (l(A6[1]), &k2),
                (l(A6[2]), &k3),
                (l(A6[3]), &k4),
                (l(A6[4]), &k5),
            ],
        ),
    )?;
    let next = combine(
        body,
        cur,
        hs,
        [
            (l(B5[0]), k1),
            (l(B5[2]), &k3),
            (l(B5[3]), &k4),
            (l(B5[4]), &k5),
            (l(B5[5]), &k6),
        ],
    );
    let k7 = stage(C[6], next)?;
    let err = combine(
        body,
        zero_state,
        hs,
        [
            (l(E[0]), k1),
            (l(E[2]), &k3),
            (l(E[3]), &k4),
            (l(E[4]), &k5),
            (l(E[5]), &k6),
            (l(E[6]), &k7),
        ],
    );
    Ok((next, k7, err))
}

use lie::num_traits::One;

#[cfg(test)]
mod tests {
    use super::*;

    /// The tableau, written as a full lower-triangular matrix, with the
    /// 5th-order weights `b` (the seventh row, first same as last) and the
    /// 4th-order weights `b − E`.
    fn tableau() -> ([[f64; 7]; 7], [f64; 7], [f64; 7]) {
        let mut a = [[0.0; 7]; 7];
        let rows: [&[f64]; 6] = [&A2, &A3, &A4, &A5, &A6, &B5];
        for (i, row) in rows.iter().enumerate() {
            a[i + 1][..row.len()].copy_from_slice(row);
        }
        let b = [B5[0], B5[1], B5[2], B5[3], B5[4], B5[5], 0.0];
        let b4 = core::array::from_fn(|i| b[i] - E[i]);
        (a, b, b4)
    }

    fn dot(x: &[f64; 7], y: &[f64; 7]) -> f64 {
        (0..7).map(|i| x[i] * y[i]).sum()
    }

    fn mul(a: &[[f64; 7]; 7], x: &[f64; 7]) -> [f64; 7] {
        core::array::from_fn(|i| dot(&a[i], x))
    }

    fn pw(x: &[f64; 7], y: &[f64; 7]) -> [f64; 7] {
        core::array::from_fn(|i| x[i] * y[i])
    }

    /// The Runge–Kutta order conditions (one per rooted tree), as
    /// (value, expected) for weights `b`, up to `order`.
    fn conditions(a: &[[f64; 7]; 7], b: &[f64; 7], order: usize) -> Vec<(f64, f64)> {
        let one = [1.0; 7];
        let c = C;
        let c2 = pw(&c, &c);
        let c3 = pw(&c2, &c);
        let ac = mul(a, &c);
        let aac = mul(a, &ac);
        let mut v = vec![(dot(b, &one), 1.0), (dot(b, &c), 0.5)];
        v.extend([(dot(b, &c2), 1.0 / 3.0), (dot(b, &ac), 1.0 / 6.0)]);
        if order >= 4 {
            v.extend([
                (dot(b, &c3), 0.25),
                (dot(b, &pw(&c, &ac)), 1.0 / 8.0),
                (dot(b, &mul(a, &c2)), 1.0 / 12.0),
                (dot(b, &aac), 1.0 / 24.0),
            ]);
        }
        if order >= 5 {
            v.extend([
                (dot(b, &pw(&c3, &c)), 0.2),
                (dot(b, &pw(&c2, &ac)), 0.1),
                (dot(b, &pw(&c, &mul(a, &c2))), 1.0 / 15.0),
                (dot(b, &pw(&c, &aac)), 1.0 / 30.0),
                (dot(b, &pw(&ac, &ac)), 1.0 / 20.0),
                (dot(b, &mul(a, &c3)), 1.0 / 20.0),
                (dot(b, &mul(a, &pw(&c, &ac))), 1.0 / 40.0),
                (dot(b, &mul(a, &mul(a, &c2))), 1.0 / 60.0),
                (dot(b, &mul(a, &aac)), 1.0 / 120.0),
            ]);
        }
        v
    }

    /// Dormand–Prince 5(4) by its defining properties: each stage's row
    /// sums to its node, the 5th-order weights meet all 17 conditions up
    /// to order 5, the 4th-order ones all 8 up to order 4 and *not* the
    /// first of order 5 (else the error estimate would vanish). A wrong
    /// digit in any coefficient breaks one of them; the sums of these
    /// rationals are exact to a few ε of the largest entry (~10): measured
    /// 2.2e-16, bound 45×.
    #[test]
    fn tableau_meets_the_order_conditions() {
        let (a, b, b4) = tableau();
        let mut worst = 0.0f64;
        for i in 0..7 {
            worst = worst.max((a[i].iter().sum::<f64>() - C[i]).abs());
        }
        for (got, want) in conditions(&a, &b, 5)
            .into_iter()
            .chain(conditions(&a, &b4, 4))
        {
            worst = worst.max((got - want).abs());
        }
        println!("Dormand–Prince order conditions: worst residual {worst:.1e}");
        assert!(worst < 1e-14, "{worst:e}");
        let c4 = pw(&pw(&C, &C), &pw(&C, &C));
        assert!(
            (dot(&b4, &c4) - 0.2).abs() > 1e-4,
            "the embedded pair must differ at order 5"
        );
    }
}
