//! Explicit Runge–Kutta steppers: Euler and RK4 on the embedding (R as nine
//! numbers), RKMK4 on the group.

use lie::num_traits::Zero;
use lie::ops;
use lie::{
    Backend, LieGroup, M3, Real, RigidTangent, Rotation, S, SimdBackend, SimdReal, So3Mat, V3,
    right_jacobian_inv,
};

use crate::{Integrator, Load, State, StepError, StepStats, System};

/// Time derivative of a state on the embedding.
#[derive(Copy, Clone, Debug)]
pub(crate) struct Deriv<B: SimdBackend, const N: usize> {
    pub r: M3<B>,
    pub x: V3<B>,
    pub v: V3<B>,
    pub w: V3<B>,
    pub e: [S<B>; N],
}

/// Body constants a step needs, read once per step.
#[derive(Copy, Clone)]
pub(crate) struct Body<B: SimdBackend> {
    pub j: M3<B>,
    pub j_inv: M3<B>,
    /// The diagonals of `J` and `J⁻¹` when both matrices are diagonal (a
    /// body on its principal axes, as every shipped vehicle is): `Ω̇` then
    /// takes 3 products per matrix instead of 9 ([`Body::omega_dot`]).
    pub principal: Option<(V3<B>, V3<B>)>,
    pub inv_mass: S<B>,
    pub translates: bool,
    /// The extra slots in use ([`System::extra_in_use`]; the error norm
    /// clamps it to `N` where it reads it).
    pub extra_in_use: usize,
}

impl<B: Backend, const N: usize> Deriv<B, N> {
    /// The rates a load sets (`v̇`, `Ω̇`, the extras') are finite; `Ṙ`
    /// comes from the state alone.
    fn load_part_is_finite(&self) -> bool {
        ops::is_finite_vec::<B>(self.v)
            & ops::is_finite_vec::<B>(self.w)
            & self
                .e
                .iter()
                .fold(true, |ok, e| ok & lie::Real::is_finite(*e))
    }
}

impl<B: Backend> Body<B> {
    pub fn of<Sys: System<B, N> + ?Sized, const N: usize>(sys: &Sys) -> Self {
        Self::new(
            sys.inertia(),
            sys.inertia_inv(),
            S::<B>::lit(1.0) / sys.mass(),
            sys.translates(),
            sys.extra_in_use(),
        )
    }
}

impl<B: SimdBackend> Body<B> {
    /// The constants of a body with inertia `j` (inverse `j_inv`), the
    /// principal-axes test made here, once per step, not at every load.
    #[inline(always)]
    pub fn new(
        j: M3<B>,
        j_inv: M3<B>,
        inv_mass: S<B>,
        translates: bool,
        extra_in_use: usize,
    ) -> Self {
        Self {
            j,
            j_inv,
            principal: ops::diagonal::<B>(j).zip(ops::diagonal::<B>(j_inv)),
            inv_mass,
            translates,
            extra_in_use,
        }
    }

    /// `Ω̇ = J⁻¹(M − Ω × JΩ)`. On principal axes the products are
    /// element-wise, with the same values for a finite state: the terms
    /// the full products would add are exact zeros.
    #[inline(always)]
    pub fn omega_dot(&self, w: V3<B>, moment: V3<B>) -> V3<B> {
        match self.principal {
            Some((d, d_inv)) => ops::cmul::<B>(d_inv, moment - B::cross(w, ops::cmul::<B>(d, w))),
            None => B::mat3_mul_vec(self.j_inv, moment - B::cross(w, B::mat3_mul_vec(self.j, w))),
        }
    }

    #[inline(always)]
    pub fn deriv<const N: usize>(&self, y: &State<B, N>, l: &Load<B, N>) -> Deriv<B, N> {
        let b = &y.body;
        Deriv {
            r: mul_hat::<B>(b.r, b.omega),
            x: b.v,
            v: l.force * self.inv_mass,
            w: self.omega_dot(b.omega, l.moment),
            e: l.extra_rate,
        }
    }
}

/// `R Ω^` column by column: the matrix product `R · hat(Ω)` without its
/// nine products by the zeros of `hat(Ω)` (each column is the product's
/// sum with its zero term dropped and `x + y·(−z)` written `x − y·z`, so
/// the same numbers up to the sign of an exact zero).
#[inline(always)]
pub(crate) fn mul_hat<B: SimdBackend>(r: M3<B>, w: V3<B>) -> M3<B> {
    let [r0, r1, r2] = B::mat3_cols(r);
    let [a, b, c] = B::vec3_to_array(w);
    B::mat3_from_cols(r1 * c - r2 * b, r2 * a - r0 * c, r0 * b - r1 * a)
}

/// Evaluates the load, checking it is finite.
#[inline(always)]
pub(crate) fn eval<B: Backend, Sys: System<B, N> + ?Sized, const N: usize>(
    sys: &mut Sys,
    t: S<B>,
    y: &State<B, N>,
) -> Result<Load<B, N>, StepError> {
    let l = sys.load(t, y);
    if !l.is_finite() {
        return Err(StepError::NonFinite {
            field: "load",
            t: t.to_f64_lossless(),
        });
    }
    Ok(l)
}

/// `y + h Σ c_i k_i` on the embedding (R included); `x`, `v` untouched when
/// the body does not translate.
#[inline(always)]
pub(crate) fn combine<B: SimdBackend, const N: usize, const K: usize>(
    body: &Body<B>,
    y: &State<B, N>,
    h: S<B>,
    terms: [(S<B>, &Deriv<B, N>); K],
) -> State<B, N> {
    let ch: [S<B>; K] = core::array::from_fn(|i| terms[i].0 * h);
    // The nine numbers of R here; every other field as a group stage has it.
    let mut dr = terms[0].1.r * ch[0];
    for (c, k) in ch[1..].iter().zip(&terms[1..]) {
        dr = dr + k.1.r * *c;
    }
    let sum = |part: fn(&Deriv<B, N>) -> V3<B>| {
        let mut d = part(terms[0].1) * ch[0];
        for (c, k) in ch[1..].iter().zip(&terms[1..]) {
            d = d + part(k.1) * *c;
        }
        d
    };
    // Computed whether or not the body translates and chosen after, so
    // the stage is one straight run of arithmetic over the whole state.
    let (x, v) = (y.body.x + sum(|k| k.x), y.body.v + sum(|k| k.v));
    let (x, v) = if body.translates {
        (x, v)
    } else {
        (y.body.x, y.body.v)
    };
    State {
        body: lie::RigidState {
            r: y.body.r + dr,
            x,
            v,
            omega: y.body.omega + sum(|k| k.w),
        },
        extra: extras(y, h, &terms),
    }
}

/// `y + h Σ c_i k_i` for the extra states.
#[inline(always)]
fn extras<B: SimdBackend, const N: usize, const K: usize>(
    y: &State<B, N>,
    h: S<B>,
    terms: &[(S<B>, &Deriv<B, N>); K],
) -> [S<B>; N] {
    let extra = |i: usize| {
        let mut de = S::<B>::zero();
        for (c, k) in terms {
            de += *c * k.e[i];
        }
        y.extra[i] + h * de
    };
    if S::<B>::CARRIES_DERIVATIVES {
        // On the dual scalar `array::from_fn` left the closure out of line
        // and returned its array through memory; on `f32`/`f64` the loop
        // over a copy vectorised into stalls instead, so each scalar keeps
        // the form that is faster for it.
        let mut out = y.extra;
        for (i, o) in out.iter_mut().enumerate() {
            *o = extra(i);
        }
        out
    } else {
        core::array::from_fn(extra)
    }
}

/// `h Σ c_i k_i` for the vector parts of the body (the attitude part left
/// at zero for the caller) and `y + h Σ c_i k_i` for the extras: the
/// increment of a Runge–Kutta stage on the group, which never forms the
/// nine-number `R + h Σ c_i Ṙ_i` that [`combine`] does; `x`, `v` get no
/// increment when the body does not translate.
#[inline(always)]
pub(crate) fn increment<B: SimdBackend, const N: usize, const K: usize>(
    body: &Body<B>,
    y: &State<B, N>,
    h: S<B>,
    terms: [(S<B>, &Deriv<B, N>); K],
) -> (RigidTangent<B>, [S<B>; N]) {
    let sum = |part: fn(&Deriv<B, N>) -> V3<B>| {
        let mut d = part(terms[0].1) * (terms[0].0 * h);
        for (c, k) in &terms[1..] {
            d = d + part(k) * (*c * h);
        }
        d
    };
    let zero = lie::ops::zero::<B>();
    let (dx, dv) = if body.translates {
        (sum(|k| k.x), sum(|k| k.v))
    } else {
        (zero, zero)
    };
    let extra = extras(y, h, &terms);
    (RigidTangent::new(zero, dx, dv, sum(|k| k.w)), extra)
}

pub(crate) fn check_h<B: Backend>(h: S<B>) -> Result<(), StepError> {
    if !(lie::Real::is_finite(h) && h > S::<B>::zero()) {
        return Err(StepError::InvalidStep {
            h: h.to_f64_lossless(),
        });
    }
    Ok(())
}

// Inlined: out of line, the new state was copied into its frame and out
// again (two memcpy calls per step).
#[inline(always)]
pub(crate) fn finish<B: Backend, const N: usize>(
    t: S<B>,
    y: &mut State<B, N>,
    next: State<B, N>,
) -> Result<(), StepError> {
    if let Some(field) = next.non_finite_field() {
        return Err(StepError::NonFinite {
            field,
            t: t.to_f64_lossless(),
        });
    }
    *y = next;
    Ok(())
}

/// [`finish`] for an explicit stepper that evaluated its `stages` (each
/// stage's time and rates) without checking each load as it came: every
/// stage's rates enter `next` with a nonzero weight, so a non-finite load
/// shows in `next`, and only then are the stages searched for the first
/// one whose load was not finite (reported as `load` at its time, as a
/// check at each stage would have). One test per step instead of one per
/// stage: testing and branching on each load as it came cost 7–9 % of a
/// closed-loop RK4 step (f64, both backends; f32 within noise). The
/// stages after a non-finite one are evaluated
/// at non-finite states (the system must not assume finite input); a
/// body that does not translate ignores its force, finite or not.
#[inline(always)]
pub(crate) fn finish_stages<B: Backend, const N: usize, const K: usize>(
    t: S<B>,
    y: &mut State<B, N>,
    next: State<B, N>,
    stages: [(S<B>, &Deriv<B, N>); K],
) -> Result<(), StepError> {
    if !next.is_finite() {
        return Err(non_finite_stage(t, &next, &stages));
    }
    *y = next;
    Ok(())
}

/// What [`finish_stages`] reports for a non-finite `next`: the first stage
/// with a non-finite load, else the state's field.
#[cold]
#[inline(never)]
fn non_finite_stage<B: Backend, const N: usize, const K: usize>(
    t: S<B>,
    next: &State<B, N>,
    stages: &[(S<B>, &Deriv<B, N>); K],
) -> StepError {
    match stages.iter().find(|(_, k)| !k.load_part_is_finite()) {
        Some((ts, _)) => StepError::NonFinite {
            field: "load",
            t: ts.to_f64_lossless(),
        },
        None => StepError::NonFinite {
            field: next.non_finite_field().unwrap_or("state"),
            t: t.to_f64_lossless(),
        },
    }
}

/// [`finish_stages`]'s test ahead of a projection, which would otherwise
/// report a non-finite load as a failed projection.
fn check_stages<B: Backend, const N: usize, const K: usize>(
    t: S<B>,
    next: &State<B, N>,
    stages: &[(S<B>, &Deriv<B, N>); K],
) -> Result<(), StepError> {
    match next.non_finite_field() {
        Some(_) => Err(non_finite_stage(t, next, stages)),
        None => Ok(()),
    }
}

fn project<B: Backend, const N: usize>(t: S<B>, y: &mut State<B, N>) -> Result<(), StepError> {
    y.body.r = So3Mat::<B>::project(y.body.r)
        .map_err(|_| StepError::NonFinite {
            field: "r (projection onto SO(3) failed)",
            t: t.to_f64_lossless(),
        })?
        .matrix();
    Ok(())
}

/// Explicit Euler on the embedding, the first-order baseline. With
/// `projected`, R is projected back onto SO(3) after each step.
#[derive(Copy, Clone, Debug, Default)]
pub struct Euler {
    /// Project R onto SO(3) after each step.
    pub projected: bool,
}

impl<B: Backend, const N: usize> Integrator<B, N> for Euler {
    fn name(&self) -> &'static str {
        "euler"
    }
    fn order(&self) -> u32 {
        1
    }
    fn step<Sys: System<B, N> + ?Sized>(
        &mut self,
        sys: &mut Sys,
        t: S<B>,
        h: S<B>,
        y: &mut State<B, N>,
    ) -> Result<StepStats, StepError> {
        check_h::<B>(h)?;
        let body = Body::of(sys);
        let k1 = body.deriv(y, &sys.load(t, y));
        let mut next = combine(&body, y, h, [(S::<B>::lit(1.0), &k1)]);
        let stages = [(t, &k1)];
        if self.projected {
            check_stages(t, &next, &stages)?;
            project(t, &mut next)?;
        }
        finish_stages(t, y, next, stages)?;
        Ok(StepStats {
            evaluations: 1,
            substeps: 1,
            ..Default::default()
        })
    }
}

/// Classical RK4 on the embedding: R is advanced as nine numbers, so it
/// leaves SO(3) by `O(h⁵)` per step unless `projected` (polar projection,
/// [`So3Mat::project`], after each step).
#[derive(Copy, Clone, Debug, Default)]
pub struct Rk4 {
    /// Project R onto SO(3) after each step.
    pub projected: bool,
}

impl Rk4 {
    /// RK4 with projection after each step.
    pub fn projected() -> Self {
        Self { projected: true }
    }
}

impl<B: Backend, const N: usize> Integrator<B, N> for Rk4 {
    fn name(&self) -> &'static str {
        if self.projected {
            "rk4-projected"
        } else {
            "rk4"
        }
    }
    fn order(&self) -> u32 {
        4
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
        let half = h * l(0.5);
        // The loads are checked once, at the step's end (`finish_stages`).
        let k1 = body.deriv(y, &sys.load(t, y));
        let y2 = combine(&body, y, h, [(l(0.5), &k1)]);
        let k2 = body.deriv(&y2, &sys.load(t + half, &y2));
        let y3 = combine(&body, y, h, [(l(0.5), &k2)]);
        let k3 = body.deriv(&y3, &sys.load(t + half, &y3));
        let y4 = combine(&body, y, h, [(l(1.0), &k3)]);
        let k4 = body.deriv(&y4, &sys.load(t + h, &y4));
        let (sixth, third) = (l(1.0 / 6.0), l(1.0 / 3.0));
        let mut next = combine(
            &body,
            y,
            h,
            [(sixth, &k1), (third, &k2), (third, &k3), (sixth, &k4)],
        );
        let stages = [(t, &k1), (t + half, &k2), (t + half, &k3), (t + h, &k4)];
        if self.projected {
            check_stages(t, &next, &stages)?;
            project(t, &mut next)?;
        }
        finish_stages(t, y, next, stages)?;
        Ok(StepStats {
            evaluations: 4,
            substeps: 1,
            ..Default::default()
        })
    }
}

/// One classical RK4 step on the embedding from `(t, y)` for any
/// `SimdBackend` ([`crate::lanes::rk4_step`]): the stages and combination
/// of [`Rk4`]'s step, operation for operation (the lane tests check every
/// lane against it to the bit). `Rk4` keeps its own copy: routed through
/// this function the scalar step got slower (LLVM's SLP vectorizer packs
/// fewer of the stage combinations of this shape), and the scalar path
/// must not pay for lanes.
#[inline(always)]
pub(crate) fn rk4_stages<B: SimdBackend, E, const N: usize>(
    body: &Body<B>,
    mut load: impl FnMut(S<B>, &State<B, N>) -> Result<Load<B, N>, E>,
    t: S<B>,
    h: S<B>,
    y: &State<B, N>,
) -> Result<State<B, N>, E> {
    let l = S::<B>::simd_lit;
    let half = h * l(0.5);
    let k1 = body.deriv(y, &load(t, y)?);
    let y2 = combine(body, y, h, [(l(0.5), &k1)]);
    let k2 = body.deriv(&y2, &load(t + half, &y2)?);
    let y3 = combine(body, y, h, [(l(0.5), &k2)]);
    let k3 = body.deriv(&y3, &load(t + half, &y3)?);
    let y4 = combine(body, y, h, [(l(1.0), &k3)]);
    let k4 = body.deriv(&y4, &load(t + h, &y4)?);
    let (sixth, third) = (l(1.0 / 6.0), l(1.0 / 3.0));
    Ok(combine(
        body,
        y,
        h,
        [(sixth, &k1), (third, &k2), (third, &k3), (sixth, &k4)],
    ))
}

/// One RKMK4 step from `(t, y)` for any `SimdBackend`
/// ([`crate::lanes::rkmk4_step`]): [`Rkmk4`]'s step operation for
/// operation, kept apart from it for the reason [`rk4_stages`] gives
/// (5 % per step here).
#[inline(always)]
pub(crate) fn rkmk4_stages<B: SimdBackend, E, const N: usize>(
    body: &Body<B>,
    mut load: impl FnMut(S<B>, &State<B, N>) -> Result<Load<B, N>, E>,
    t: S<B>,
    h: S<B>,
    y: &State<B, N>,
) -> Result<State<B, N>, E> {
    let l = S::<B>::simd_lit;
    let half = h * l(0.5);
    // The step on the group SO(3) × ℝ⁹ (× ℝᴺ for the extras): stage i
    // is Y_k ⊕ δ_i with δ_i = h Σ a_ij K_j, where the slope K_j is the
    // state's rate, the attitude's trivialised as J_r⁻¹(u_j) Ω_j
    // (u_j = δ_j's attitude part); the vector parts and the extras
    // follow the RK4 tableau as they are.
    let (r0, b0) = (So3Mat::<B>::from_matrix_unchecked(y.body.r), y.body);
    let at = |u: V3<B>, (d, extra): (RigidTangent<B>, [S<B>; N])| State {
        body: lie::RigidState {
            r: r0.compose(So3Mat::<B>::exp(u)).as_matrix(),
            x: b0.x + d.x,
            v: b0.v + d.v,
            omega: b0.omega + d.omega,
        },
        extra,
    };
    let k1 = body.deriv(y, &load(t, y)?);
    let a1 = y.body.omega;
    let u2 = a1 * half;
    let y2 = at(u2, increment(body, y, h, [(l(0.5), &k1)]));
    let k2 = body.deriv(&y2, &load(t + half, &y2)?);
    let a2 = right_jacobian_inv::<B>(u2) * y2.body.omega;
    let u3 = a2 * half;
    let y3 = at(u3, increment(body, y, h, [(l(0.5), &k2)]));
    let k3 = body.deriv(&y3, &load(t + half, &y3)?);
    let a3 = right_jacobian_inv::<B>(u3) * y3.body.omega;
    let u4 = a3 * h;
    let y4 = at(u4, increment(body, y, h, [(l(1.0), &k3)]));
    let k4 = body.deriv(&y4, &load(t + h, &y4)?);
    let a4 = right_jacobian_inv::<B>(u4) * y4.body.omega;
    let (sixth, third) = (l(1.0 / 6.0), l(1.0 / 3.0));
    let u = (a1 * sixth + a2 * third + a3 * third + a4 * sixth) * h;
    Ok(at(
        u,
        increment(
            body,
            y,
            h,
            [(sixth, &k1), (third, &k2), (third, &k3), (sixth, &k4)],
        ),
    ))
}

/// Runge–Kutta–Munthe-Kaas of order 4 on SO(3) × Rⁿ (right form
/// `Ṙ = RΩ^`): the attitude is `R_k exp(u)` with `u` integrated by classical
/// RK4 from `u̇ = dexp⁻¹_{−u}(Ω) = J_r⁻¹(u) Ω`, `u(0) = 0`; the stages are
/// evaluated at `R_k exp(u_i)`. The vector part uses the same tableau. R
/// stays on SO(3) to rounding (one exp per stage).
#[derive(Copy, Clone, Debug, Default)]
pub struct Rkmk4;

impl<B: Backend, const N: usize> Integrator<B, N> for Rkmk4 {
    fn name(&self) -> &'static str {
        "rkmk4"
    }
    fn order(&self) -> u32 {
        4
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
        let half = h * l(0.5);
        // The step on the group SO(3) × ℝ⁹ (× ℝᴺ for the extras): stage i
        // is Y_k ⊕ δ_i with δ_i = h Σ a_ij K_j, where the slope K_j is the
        // state's rate, the attitude's trivialised as J_r⁻¹(u_j) Ω_j
        // (u_j = δ_j's attitude part); the vector parts and the extras
        // follow the RK4 tableau as they are.
        let g0 = y.body.group();
        let at = |u: V3<B>, (d, extra): (RigidTangent<B>, [S<B>; N])| State {
            body: lie::RigidState::from_group(g0.rplus(RigidTangent { phi: u, ..d })),
            extra,
        };
        let k1 = body.deriv(y, &eval(sys, t, y)?);
        let a1 = y.body.omega;
        let u2 = a1 * half;
        let y2 = at(u2, increment(&body, y, h, [(l(0.5), &k1)]));
        let k2 = body.deriv(&y2, &eval(sys, t + half, &y2)?);
        let a2 = right_jacobian_inv::<B>(u2) * y2.body.omega;
        let u3 = a2 * half;
        let y3 = at(u3, increment(&body, y, h, [(l(0.5), &k2)]));
        let k3 = body.deriv(&y3, &eval(sys, t + half, &y3)?);
        let a3 = right_jacobian_inv::<B>(u3) * y3.body.omega;
        let u4 = a3 * h;
        let y4 = at(u4, increment(&body, y, h, [(l(1.0), &k3)]));
        let k4 = body.deriv(&y4, &eval(sys, t + h, &y4)?);
        let a4 = right_jacobian_inv::<B>(u4) * y4.body.omega;
        let (sixth, third) = (l(1.0 / 6.0), l(1.0 / 3.0));
        let u = (a1 * sixth + a2 * third + a3 * third + a4 * sixth) * h;
        let next = at(
            u,
            increment(
                &body,
                y,
                h,
                [(sixth, &k1), (third, &k2), (third, &k3), (sixth, &k4)],
            ),
        );
        finish(t, y, next)?;
        Ok(StepStats {
            evaluations: 4,
            substeps: 1,
            ..Default::default()
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lie::{GlamF32, GlamF64, NalgebraF64, So3Mat, hat};

    /// `mul_hat` is the matrix product `R · hat(Ω)` the stages used to
    /// form: bit for bit wherever no entry of the product is an exact zero
    /// (the one place they may differ is the sign of such a zero), on
    /// the backends whose product sums in different ways.
    fn equals_the_product<B: Backend>() {
        let s = S::<B>::lit;
        let v = |a: f64, b: f64, c: f64| B::vec3(s(a), s(b), s(c));
        let mut checked = 0;
        for k in 0..200 {
            let x = f64::from(k);
            let r = So3Mat::<B>::exp(v(
                (0.7 * x).sin() * 3.0,
                (1.3 * x).cos() * 2.0,
                (0.3 * x).sin(),
            ))
            .matrix();
            let w = v((2.1 * x).cos() * 9.0, (0.9 * x).sin() * 4.0, -0.01 * x);
            let fast = lie::ops::elems::<B>(mul_hat::<B>(r, w));
            let full = lie::ops::elems::<B>(B::mat3_mul(r, hat::<B>(w)));
            for (i, j) in (0..3).flat_map(|i| (0..3).map(move |j| (i, j))) {
                let (a, b) = (fast[i][j], full[i][j]);
                assert!(a == b, "{} ({i}, {j}) at k = {k}: {a:?} ≠ {b:?}", B::NAME);
                if b != S::<B>::lit(0.0) {
                    assert_eq!(
                        a.to_f64_lossless().to_bits(),
                        b.to_f64_lossless().to_bits(),
                        "{} ({i}, {j}) at k = {k}",
                        B::NAME
                    );
                    checked += 1;
                }
            }
        }
        assert!(checked > 1700, "{checked} nonzero entries compared");
    }

    #[test]
    fn mul_hat_is_the_product_by_hat_to_the_bit() {
        equals_the_product::<GlamF64>();
        equals_the_product::<GlamF32>();
        equals_the_product::<NalgebraF64>();
    }

    /// `Ω̇` on principal axes (element-wise products) against the full
    /// matrix products, to the bit where the result is not an exact zero;
    /// and a body with a product of inertia (or a non-diagonal inverse)
    /// takes the full products.
    fn principal_axes_match_the_products<B: Backend>() {
        let s = S::<B>::lit;
        let v = |a: f64, b: f64, c: f64| B::vec3(s(a), s(b), s(c));
        let j = ops::diag::<B>(s(0.082), s(0.0845), s(0.1377));
        let j_inv = ops::inverse::<B>(j).expect("invertible");
        let body = Body::<B>::new(j, j_inv, s(1.0 / 4.34), true, 0);
        let Some((d, d_inv)) = body.principal else {
            panic!("{}: a diagonal inertia is on principal axes", B::NAME);
        };
        assert_eq!(B::vec3_to_array(d), [s(0.082), s(0.0845), s(0.1377)]);
        let e = ops::elems::<B>(j_inv);
        assert_eq!(B::vec3_to_array(d_inv), [e[0][0], e[1][1], e[2][2]]);
        let full = |w, m| B::mat3_mul_vec(j_inv, m - B::cross(w, B::mat3_mul_vec(j, w)));
        let mut checked = 0;
        for k in 0..200 {
            let x = f64::from(k);
            let w = v((2.1 * x).cos() * 9.0, (0.9 * x).sin() * 4.0, -0.01 * x);
            let m = v((1.7 * x).sin(), -(0.4 * x).cos() * 0.3, 0.02 * x - 1.0);
            let (a, b) = (
                B::vec3_to_array(body.omega_dot(w, m)),
                B::vec3_to_array(full(w, m)),
            );
            for (p, q) in a.into_iter().zip(b) {
                assert!(p == q, "{} at k = {k}: {p:?} ≠ {q:?}", B::NAME);
                if q != S::<B>::lit(0.0) {
                    assert_eq!(p.to_f64_lossless().to_bits(), q.to_f64_lossless().to_bits());
                    checked += 1;
                }
            }
        }
        assert!(checked > 590, "{checked} nonzero components compared");
        // A product of inertia: the full products, whatever its size.
        let mut e = ops::elems::<B>(j);
        e[0][1] = s(1e-30);
        e[1][0] = s(1e-30);
        let tilted = ops::from_elems::<B>(e);
        let tilted_inv = ops::inverse::<B>(tilted).expect("invertible");
        let body = Body::<B>::new(tilted, tilted_inv, s(1.0), true, 0);
        assert!(body.principal.is_none(), "{}", B::NAME);
    }

    #[test]
    fn principal_axes_omega_dot_is_the_full_product_to_the_bit() {
        principal_axes_match_the_products::<GlamF64>();
        principal_axes_match_the_products::<GlamF32>();
        principal_axes_match_the_products::<NalgebraF64>();
    }
}
