//! The Lie group variational integrator of Lee, Leok & McClamroch in its
//! trapezoidal (symmetric, order 2) form.

use lie::num_traits::One;
use lie::{Backend, M3, Real, S, V3, hat, ops};

use crate::rk::{Body, check_h, eval, finish};
use crate::{Integrator, Load, State, StepError, StepStats, System};

/// How the LGVI treats the loads at the end of the step.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum EndLoad {
    /// Iterate `load(t + h, y_{k+1})` to a fixed point (at most `max`
    /// passes). For loads that depend only on the configuration (free body,
    /// heavy top, held control) this is one evaluation and the scheme is the
    /// variational integrator exactly; with continuous feedback (loads that
    /// read `Ω`, `v`, integral states) it is the implicit trapezoidal
    /// treatment of the forcing, which keeps the closed loop at order 2.
    ///
    /// The iteration stops when a pass changes `Ω`, `v` and the extra
    /// states by less than 10⁻⁴ of what the first pass changed (relative,
    /// and never below 4ε): the first change is the O(h²) correction of the
    /// explicit predictor, so what is left is far below the step's O(h³)
    /// truncation error. It takes fewer load evaluations a step than
    /// [`EndLoad::IterateToRounding`], with the same error to 3 digits
    /// (`integrators/tests/closed_loop.rs` checks it).
    Iterate {
        /// Most passes before [`StepError::EndLoadDiverged`].
        max: u32,
    },
    /// [`EndLoad::Iterate`] continued until a pass changes the state by
    /// less than 4ε (relative): the exact fixed point to rounding, at a few
    /// more evaluations a step in f64.
    IterateToRounding {
        /// Most passes before [`StepError::EndLoadDiverged`].
        max: u32,
    },
    /// One corrector pass from an explicit predictor: still order 2, one
    /// load evaluation per step, but not symmetric for rate-dependent loads.
    OneCorrection,
}

/// The LGVI (Lee, Leok & McClamroch), trapezoidal form:
///
/// ```text
/// a_k = h (JΩ_k + h/2 M_k),   â_k = F_k J_d − J_d F_kᵀ,   J_d = ½tr(J) I − J
/// R_{k+1} = R_k F_k
/// JΩ_{k+1} = F_kᵀ (JΩ_k + h/2 M_k) + h/2 M_{k+1}
/// x_{k+1} = x_k + h v_k + h²/(2m) f_k,   v_{k+1} = v_k + h/(2m)(f_k + f_{k+1})
/// e_{k+1} = e_k + h/2 (ė_k + ė_{k+1})
/// ```
///
/// `F_k` is found with the Cayley parametrisation `F = cay(f)`, for which
/// the matrix equation is exactly `G(f) = a + a × f + (a·f) f − 2Jf = 0`,
/// solved by Newton's method (`∇G = â + (a·f)I + f aᵀ − 2J`, start
/// `f₀ = (2J − â)⁻¹a`) to a step below `4ε(1 + |f|)`. R is advanced by the
/// group element `F`, so it stays on SO(3) to rounding; unforced, the scheme
/// is the discrete Moser–Veselov map, symplectic and momentum preserving,
/// with energy error bounded (no drift).
///
/// **Step limit.** For spin about a principal axis the update reads
/// `sin θ = h‖Ω‖`: there is no solution once `h‖Ω‖ > 1`, and Newton stalls
/// near it. A solve that does not converge within `max_newton` iterations,
/// or converges to a rotation of more than 90° (the far root), is treated as
/// failed: the step is split in two halves, up to `max_halvings` times, and
/// then [`StepError::NoSolution`] is returned with the state untouched.
///
/// **Controls.** A control held over the step (a sampled controller, zero-
/// order hold) enters like `M` and is reproduced exactly. A continuous
/// feedback law evaluated only at `t_k` would make the loop first order;
/// [`EndLoad::Iterate`] (the default) evaluates it at the end point too,
/// keeping order 2 at the cost of a few load evaluations a step.
#[derive(Clone, Debug)]
pub struct Lgvi<B: Backend, const N: usize> {
    /// Newton iteration cap for the attitude solve.
    pub max_newton: u32,
    /// How many times a failed step may be halved.
    pub max_halvings: u32,
    /// End-point load treatment.
    pub end_load: EndLoad,
    cache: Option<(S<B>, State<B, N>, Load<B, N>)>,
}

impl EndLoad {
    /// How many end-point passes at most, and the stopping tolerance
    /// relative to the first pass's change (`None`: to rounding), for
    /// loads that do or do not read the rates (then one pass is exact).
    #[inline]
    pub(crate) fn plan(self, depends_on_rates: bool) -> (u32, Option<f64>) {
        let passes = match self {
            _ if !depends_on_rates => 1,
            EndLoad::OneCorrection => 1,
            EndLoad::Iterate { max } | EndLoad::IterateToRounding { max } => max.max(1),
        };
        // What is left of the iteration once a pass changes the state by
        // 1e-4 of the first (predictor) correction is O(h²)·1e-4: far below
        // the O(h³) truncation error at the steps anyone takes.
        let relative = match self {
            EndLoad::Iterate { .. } => Some(1e-4),
            _ => None,
        };
        (passes, relative)
    }
}

/// The Newton iteration cap of [`Lgvi::default`] (and of the lane LGVI's).
pub(crate) const DEFAULT_MAX_NEWTON: u32 = 20;
/// The end-load treatment of [`Lgvi::default`] (and of the lane LGVI's).
pub(crate) const DEFAULT_END_LOAD: EndLoad = EndLoad::Iterate { max: 50 };

impl<B: Backend, const N: usize> Default for Lgvi<B, N> {
    fn default() -> Self {
        Self {
            max_newton: DEFAULT_MAX_NEWTON,
            max_halvings: 8,
            end_load: DEFAULT_END_LOAD,
            cache: None,
        }
    }
}

/// Outcome of the Cayley–Newton solve.
pub(crate) struct Solve<B: Backend> {
    pub f: V3<B>,
    pub iterations: u32,
    pub residual: S<B>,
    pub converged: bool,
}

/// `max |v_i|`, lane-wise on lane backends (for `f32`/`f64` these are
/// `Real::abs` and `Real::max`).
#[inline(always)]
pub(crate) fn inf_norm<B: lie::SimdBackend>(v: V3<B>) -> S<B> {
    use lie::SimdReal as _;
    let a = B::vec3_to_array(v);
    a[0].simd_abs()
        .simd_max(a[1].simd_abs())
        .simd_max(a[2].simd_abs())
}

/// Solves `a + a × f + (a·f) f − 2Jf = 0` for the Cayley vector `f`.
pub(crate) fn solve_cayley<B: Backend>(j: M3<B>, a: V3<B>, max_iter: u32) -> Solve<B> {
    let two = S::<B>::lit(2.0);
    let eps = S::<B>::epsilon();
    let a_hat = hat::<B>(a);
    let id = ops::identity::<B>();
    let g = |f: V3<B>| a + B::cross(a, f) + f * B::dot(a, f) - B::mat3_mul_vec(j, f) * two;
    let mut f = match ops::inverse::<B>(j * two - a_hat) {
        Some(m) => B::mat3_mul_vec(m, a),
        None => {
            return Solve {
                f: a,
                iterations: 0,
                residual: S::<B>::infinity(),
                converged: false,
            };
        }
    };
    let mut converged = false;
    let mut iterations = 0;
    let mut prev_step = S::<B>::infinity();
    let jacobian = |f: V3<B>| {
        let [a0, a1, a2] = B::vec3_to_array(a);
        let outer = B::mat3_from_cols(f * a0, f * a1, f * a2);
        a_hat + id * B::dot(a, f) + outer - j * two
    };
    for it in 1..=max_iter {
        iterations = it;
        let Some(jinv) = ops::inverse::<B>(jacobian(f)) else {
            break;
        };
        let df = B::mat3_mul_vec(jinv, g(f));
        f = f - df;
        let step = inf_norm::<B>(df);
        let scale = S::<B>::one() + inf_norm::<B>(f);
        if !Real::is_finite(step) {
            break;
        }
        // Converged: at the rounding floor, or stalled there (Newton on a
        // well-posed root halves the digits it lacks each pass; a step that
        // stops shrinking while already tiny is rounding noise).
        if step <= eps * S::<B>::lit(4.0) * scale
            || (step >= prev_step * S::<B>::lit(0.5) && step <= eps * S::<B>::lit(1e3) * scale)
        {
            converged = true;
            break;
        }
        prev_step = step;
    }
    // Newton stops on the value. One more step from the root, applied to
    // the derivatives alone, gives them exactly (the implicit function
    // theorem: f′ = −g_f⁻¹ g_a a′ at g = 0) whatever the iterations left.
    if <S<B> as lie::SimdReal>::CARRIES_DERIVATIVES
        && converged
        && let Some(jinv) = ops::inverse::<B>(jacobian(f))
    {
        f = ops::with_derivatives_of::<B>(f, f - jinv * g(f));
    }
    let an = ops::norm::<B>(a);
    let residual = ops::norm::<B>(g(f)) / (an + S::<B>::min_positive_value());
    // |f| = tan(θ/2) < 1 on the near root (θ < 90°); the far root is a
    // different, wrong motion.
    let near_root = ops::norm::<B>(f) < S::<B>::one();
    Solve {
        f,
        iterations,
        residual,
        converged: converged && near_root && Real::is_finite(residual),
    }
}

/// `cay(f) − I = 2/(1 + fᵀf) (f^ + f^²)` (on lanes too).
#[inline]
pub(crate) fn cayley_minus_identity<B: lie::SimdBackend>(f: V3<B>) -> M3<B> {
    let fh = hat::<B>(f);
    let c = <S<B> as lie::SimdReal>::simd_lit(2.0) / (S::<B>::one() + B::dot(f, f));
    (fh + fh * fh) * c
}

/// `cay(f) = I + 2/(1 + fᵀf) (f^ + f^²)`.
#[cfg(test)]
pub(crate) fn cayley<B: Backend>(f: V3<B>) -> M3<B> {
    ops::identity::<B>() + cayley_minus_identity::<B>(f)
}

impl<B: Backend, const N: usize> Lgvi<B, N> {
    fn single<Sys: System<B, N> + ?Sized>(
        &mut self,
        sys: &mut Sys,
        body: &Body<B>,
        t: S<B>,
        h: S<B>,
        y: &State<B, N>,
        stats: &mut StepStats,
    ) -> Result<State<B, N>, StepError> {
        let l = S::<B>::lit;
        let half_h = h * l(0.5);
        let l0 = match &self.cache {
            Some((tc, yc, lc)) if *tc == t && yc == y => *lc,
            _ => {
                stats.evaluations += 1;
                eval(sys, t, y)?
            }
        };
        let b = &y.body;
        let p = B::mat3_mul_vec(body.j, b.omega) + l0.moment * half_h;
        let a = p * h;
        let sol = solve_cayley::<B>(body.j, a, self.max_newton);
        if sol.converged {
            // Only accepted solves count; a failed attempt that was then
            // halved is visible in `substeps`.
            stats.newton_iterations = stats.newton_iterations.max(sol.iterations);
            stats.residual = stats.residual.max(sol.residual.to_f64_lossless());
        } else {
            return Err(StepError::NoSolution {
                t: t.to_f64_lossless(),
                h: h.to_f64_lossless(),
                h_omega: (h * ops::norm::<B>(b.omega)).to_f64_lossless(),
                iterations: sol.iterations,
                residual: sol.residual.to_f64_lossless(),
            });
        }
        // Increment form: D = F − I = c(f^ + f^²) is formed without adding
        // it to I, and R, JΩ are updated as `R + R D`, `Ω + J⁻¹(Dᵀp + …)`.
        // Forming F = I + D and recomputing JΩ = Fᵀp from scratch each step
        // makes the rounding of consecutive steps correlated (F barely
        // changes), and it then accumulates linearly: measured on the free
        // body, |ΔE/E| after 10⁵ steps in f32 fell from 6.3e-3 to the
        // conservation suite's bounds, ‖RᵀR − I‖ likewise.
        let d_mat = cayley_minus_identity::<B>(sol.f);
        let dtp = B::mat3_tr_mul_vec(d_mat, p);
        let mut next = *y;
        next.body.r = b.r + B::mat3_mul(b.r, d_mat);
        if body.translates {
            next.body.x = b.x + b.v * h + l0.force * (h * half_h * body.inv_mass);
            next.body.v = b.v + l0.force * (h * body.inv_mass);
        }
        // JΩ_{k+1} = Fᵀp + h/2 M_{k+1} = JΩ_k + Dᵀp + h/2 (M_k + M_{k+1}).
        let omega_from = |m_end: V3<B>| {
            b.omega + B::mat3_mul_vec(body.j_inv, dtp + (l0.moment + m_end) * half_h)
        };
        next.body.omega = omega_from(l0.moment);
        for i in 0..N {
            next.extra[i] = y.extra[i] + h * l0.extra_rate[i];
        }
        let (passes, relative) = self.end_load.plan(sys.load_depends_on_rates());
        let relative = relative.map(l);
        let floor = S::<B>::epsilon() * l(4.0);
        let mut tol = floor;
        let mut converged = passes == 1;
        let mut l1 = l0;
        for pass in 0..passes {
            stats.evaluations += 1;
            l1 = eval(sys, t + h, &next)?;
            let w = omega_from(l1.moment);
            let mut change =
                inf_norm::<B>(w - next.body.omega) / (S::<B>::one() + inf_norm::<B>(w));
            next.body.omega = w;
            if body.translates {
                let v = b.v + (l0.force + l1.force) * (half_h * body.inv_mass);
                change =
                    change.max(inf_norm::<B>(v - next.body.v) / (S::<B>::one() + inf_norm::<B>(v)));
                next.body.v = v;
            }
            for i in 0..N {
                let e = y.extra[i] + half_h * (l0.extra_rate[i] + l1.extra_rate[i]);
                change = change.max((e - next.extra[i]).abs() / (S::<B>::one() + e.abs()));
                next.extra[i] = e;
            }
            if change <= tol {
                converged = true;
                break;
            }
            if pass == 0
                && let Some(r) = relative
            {
                tol = (change * r).max(floor);
            }
        }
        if !converged {
            return Err(StepError::EndLoadDiverged {
                t: t.to_f64_lossless(),
                h: h.to_f64_lossless(),
            });
        }
        // The last load was evaluated at the previous iterate, which differs
        // from `next` by at most the tolerance: reuse it as the next step's
        // start load (exact when loads ignore rates).
        self.cache = Some((t + h, next, l1));
        Ok(next)
    }

    /// One step of `h` from `(t, y)`, halved (recursively, `depth` deep so
    /// far) while the implicit equations have no solution.
    fn advance<Sys: System<B, N> + ?Sized>(
        &mut self,
        sys: &mut Sys,
        body: &Body<B>,
        (t, h): (S<B>, S<B>),
        y: &State<B, N>,
        depth: u32,
        stats: &mut StepStats,
    ) -> Result<State<B, N>, StepError> {
        match self.single(sys, body, t, h, y, stats) {
            Ok(next) => {
                stats.substeps += 1;
                Ok(next)
            }
            Err(StepError::NoSolution { .. } | StepError::EndLoadDiverged { .. })
                if depth < self.max_halvings =>
            {
                let half = h * S::<B>::lit(0.5);
                let mid = self.advance(sys, body, (t, half), y, depth + 1, stats)?;
                self.advance(sys, body, (t + half, half), &mid, depth + 1, stats)
            }
            Err(e) => Err(e),
        }
    }
}

impl<B: Backend, const N: usize> Integrator<B, N> for Lgvi<B, N> {
    fn name(&self) -> &'static str {
        "lgvi"
    }
    fn order(&self) -> u32 {
        2
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
        let mut stats = StepStats::default();
        let start = *y;
        match self.advance(sys, &body, (t, h), &start, 0, &mut stats) {
            Ok(next) => {
                finish(t, y, next)?;
                Ok(stats)
            }
            Err(e) => {
                self.cache = None;
                Err(e)
            }
        }
    }
    fn reset(&mut self) {
        self.cache = None;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use lie::{NalgebraF64, Rotation, So3Mat};

    type B = NalgebraF64;

    /// The Cayley solution satisfies the original matrix equation
    /// `â = F J_d − J_d Fᵀ` to rounding.
    #[test]
    fn cayley_root_solves_the_matrix_equation() {
        let j = ops::diag::<B>(1.0, 2.0, 3.0);
        let jd = ops::identity::<B>() * 3.0 - j;
        for a in [
            B::vec3(0.01, -0.02, 0.03),
            B::vec3(0.3, 0.5, -0.7),
            B::vec3(-0.6, 0.2, 0.8),
        ] {
            let s = solve_cayley::<B>(j, a, 20);
            assert!(s.converged, "{a:?}");
            let f = cayley::<B>(s.f);
            let lhs = f * jd - jd * f.transpose();
            let err = (lhs - hat::<B>(a)).norm();
            assert!(err < 1e-14 * (1.0 + a.norm()), "{err}");
            assert!(So3Mat::<B>::from_matrix_unchecked(f).orthogonality_error() < 1e-15);
        }
    }

    /// Spin about a principal axis: sin θ = h‖Ω‖, so h‖Ω‖ = 1.2 has no root.
    #[test]
    fn an_unfinished_solve_is_not_a_root() {
        // Newton from f = 0 needs 3–4 passes here (|a| = 0.9 of the
        // limit); cut off after one, the iterate is near the root
        // (|f| < 1, residual finite) but not on it, and must not count.
        let j = ops::diag::<B>(1.0, 2.0, 3.0);
        let a = j * B::vec3(0.3, -0.5, 0.6);
        let one = solve_cayley::<B>(j, a, 1);
        assert!(one.f.norm() < 1.0 && one.residual.is_finite() && one.residual > 1e-6);
        assert!(
            !one.converged,
            "one pass reported as a root: residual {}",
            one.residual
        );
        let full = solve_cayley::<B>(j, a, 20);
        assert!(full.converged && full.residual < 1e-15, "{}", full.residual);
    }

    #[test]
    fn no_root_past_the_step_limit_is_detected() {
        let j = ops::diag::<B>(1.0, 2.0, 3.0);
        let ok = solve_cayley::<B>(j, j * B::vec3(0.0, 0.0, 0.9), 20);
        assert!(ok.converged);
        let theta = 2.0 * ok.f.norm().atan();
        assert!((theta.sin() - 0.9).abs() < 1e-14, "sin θ = {}", theta.sin());
        let bad = solve_cayley::<B>(j, j * B::vec3(0.0, 0.0, 1.2), 20);
        assert!(
            !bad.converged,
            "a root was reported past the limit: {:?}",
            bad.f
        );
    }
}
