//! The free body over 10⁴ s, the step-size limit of every stepper, and
//! high rates.

use super::*;
use scenes::Error;

/// The free rigid body for 10⁴ s (10³ with `--quick`), h = 0.01.
pub(super) fn free_body(r: &mut Report<'_>, quick: bool, _: &Path) -> Result<(), SuiteError> {
    let duration = if quick { 1e3 } else { 1e4 };
    for scalar in [Scalar::F64, Scalar::F32] {
        for kind in STEPPERS {
            let mut s = builtin::free_rigid_body();
            s.duration = duration;
            s.scalar = scalar;
            s.integrator.kind = kind.into();
            s.integrator.tol = dopri_tol(scalar);
            s.record.sample = duration / 1000.0;
            let name = format!("{kind} {} {duration} s h 0.01", scalar_name(scalar));
            let Some(out) = run_or_told(
                r,
                "free-body",
                &name,
                &s,
                "explicit Euler gains energy every step and blows up",
            )?
            else {
                continue;
            };
            let (de, dp) = drifts(&out, s.vehicle.inertia);
            let steps = duration / s.integrator.dt;
            let (e_bound, e_why, p_bound, p_why) = free_body_bounds(
                kind,
                scalar,
                steps,
                s.integrator.dt,
                norm(s.initial.omega),
                duration,
            );
            r.le(
                "free-body",
                format!("{name}: max |ΔE|/E"),
                de,
                e_bound,
                e_why,
            );
            r.le(
                "free-body",
                format!("{name}: max ‖ΔΠ‖/‖Π‖"),
                dp,
                p_bound,
                p_why,
            );
        }
    }
    Ok(())
}

/// Bounds on the free body's drifts, from each stepper's structure.
fn free_body_bounds(
    kind: &str,
    scalar: Scalar,
    steps: f64,
    h: f64,
    w: f64,
    t: f64,
) -> (f64, &'static str, f64, &'static str) {
    // Rounding in a conserving method walks randomly: ~ε√n per invariant,
    // with a factor 100 for the ~10² operations of a step.
    let walk = 100.0 * eps(scalar) * steps.sqrt();
    // A fourth-order method's local error (h|Ω|)⁵/120 per step, summed.
    let rk = 3.0 * (h * w).powi(4) / 120.0 * w * t;
    match kind {
        "lgvi" => (
            walk.max(1e-4),
            "LGVI is symplectic: energy oscillates with amplitude ~h² (1e-4 at h = 0.01, J = diag(1,2,3)) and does not drift",
            walk,
            "LGVI conserves spatial momentum exactly; only rounding (100 ε √n) remains",
        ),
        "euler" => (
            0.5,
            "Lie–Euler is first order and not symplectic: the energy drifts secularly; bounded only to stay a rigid body (< 50 %)",
            0.5,
            "first order: momentum drifts; bounded only to stay a rigid body",
        ),
        "dopri" => (
            walk.max(1e-5),
            "adaptive 5(4) at the tolerance (1e-9 f64, 1e-5 f32): the global error stays near it",
            walk.max(1e-5),
            "same as the energy",
        ),
        _ => (
            walk + rk,
            "3 × (h|Ω|)⁴|Ω| t/120 (a fourth-order method's accumulated local error) + 100 ε √n",
            walk + rk,
            "same as the energy",
        ),
    }
}

/// Every stepper on paper-flip at doubling steps: the largest step whose
/// final error stays under 1 cm / 0.01 against dopri at 1e-12, and what
/// happens past it: an error or a health warning is fine, a finite wrong
/// answer with no warning fails.
pub(super) fn step_limit(r: &mut Report<'_>, _quick: bool, _: &Path) -> Result<(), SuiteError> {
    let mut reference = builtin::paper_flip();
    reference.integrator.kind = "dopri".into();
    reference.integrator.tol = 1e-12;
    let reference = run(&reference)
        .map_err(failed("paper-flip reference"))?
        .last;
    // Doubling steps from 1/4 ms to 1/4 s, the same with `--quick` (cheap:
    // the flip lasts 4 s).
    let ladder: Vec<f64> = (0..11).map(|k| 2.5e-4 * f64::from(1u32 << k)).collect();
    const BOUND: f64 = 1e-2;
    for kind in STEPPERS {
        let mut limit = None;
        for &dt in &ladder {
            let mut s = builtin::paper_flip();
            s.integrator.kind = kind.into();
            s.integrator.dt = dt;
            s.integrator.tol = 1e-9;
            // Samples are checkpoints the steps land on: record at the
            // ladder's largest step so that `dt` is the step taken.
            s.record.sample = 0.256;
            let outcome = run(&s);
            let (err, warnings, failure) = match &outcome {
                Ok(o) => {
                    let health = health(o);
                    let e = flip_error(o, &reference);
                    (e, health, None)
                }
                Err(e) => (f64::NAN, Vec::new(), Some(e.to_string())),
            };
            let good = err <= BOUND;
            if good {
                limit = Some(dt);
                r.note(format!("    {kind} dt {dt}: error {err:.2e}"));
                continue;
            }
            // Past the limit: say what the user sees.
            let (seen, ok) = if let Some(f) = &failure {
                (format!("error: {f}"), true)
            } else if !warnings.is_empty() {
                (format!("warning: {}", warnings[0]), true)
            } else if !err.is_finite() {
                ("non-finite state without an error".into(), false)
            } else {
                (
                    format!("finite wrong answer (error {err:.2e}), no warning"),
                    false,
                )
            };
            r.note(format!("    {kind} dt {dt}: {seen}"));
            r.holds(
                "step-limit",
                format!("{kind} dt {dt} (past the limit): told, not silent"),
                ok,
                "past the largest good step the user gets an error or a warning, never a silent wrong answer",
            );
        }
        match limit {
            Some(dt) => r.note(format!(
                "    {kind}: largest step with error ≤ {BOUND}: {dt}"
            )),
            None => r.note(format!(
                "    {kind}: no step of the ladder has error ≤ {BOUND}"
            )),
        }
        r.holds(
            "step-limit",
            format!("{kind}: some step of the ladder completes paper-flip within 1e-2"),
            limit.is_some(),
            "the smallest step of the ladder must be usable",
        );
    }
    Ok(())
}

/// A body spinning at 100 rad/s (exact solution), and attitude tracking of
/// a 2 Hz command against a tight reference.
pub(super) fn high_rate(r: &mut Report<'_>, quick: bool, _: &Path) -> Result<(), SuiteError> {
    let duration = if quick { 2.0 } else { 10.0 };
    let omega0 = [3.0, -2.0, 100.0];
    let mut base = builtin::free_rigid_body();
    base.duration = duration;
    base.initial.omega = omega0;
    base.integrator.dt = 1e-3;
    base.record.sample = duration; // the end only: the exact solution is compared there
    let rows = scenes::reference::rotation_f64(base.initial.rotation);
    let exact = ExactFreeBody::new(base.vehicle.inertia, omega0, rows)
        .map_err(|e| failed("exact free body")(Error::Run(SimError::Vehicle(e))))?;
    let re = exact.attitude(duration);
    let we = exact.omega(duration);
    let w = norm(omega0);
    let (h, t) = (base.integrator.dt, duration);
    let hw = h * w;
    for scalar in [Scalar::F64, Scalar::F32] {
        for kind in STEPPERS {
            let mut s = base.clone();
            s.scalar = scalar;
            s.integrator.kind = kind.into();
            s.integrator.tol = dopri_tol(scalar);
            let name = format!(
                "{kind} {} spin {w:.0} rad/s {duration} s h {h}",
                scalar_name(scalar)
            );
            // Phase error of an order-p method on a rotation at rate Ω:
            // C (hΩ)^p · Ω t (C from the method's leading error term), plus
            // rounding, ~10 ε per step in phase. Bound: 3× that.
            let rounding = 10.0 * eps(scalar) * t / h;
            let (phase, why): (f64, &'static str) = match kind {
                "lgvi" => (
                    hw * hw / 12.0 * w * t,
                    "3 × [(hΩ)²/12 · Ω t (second order, Cayley) + 10 ε per step]",
                ),
                "rk4" | "rk4-projected" | "rkmk4" => (
                    hw.powi(4) / 120.0 * w * t,
                    "3 × [(hΩ)⁴/120 · Ω t (fourth order) + 10 ε per step]",
                ),
                "dopri" => (
                    dopri_tol(scalar) * w * t,
                    "3 × [tol · Ω t (the adaptive step holds the local error at tol) + 10 ε per step]",
                ),
                _ => (f64::INFINITY, ""),
            };
            let bound = (3.0 * (phase + rounding)).min(2.0);
            let Some(out) = run_or_told(
                r,
                "high-rate",
                &name,
                &s,
                "explicit Euler amplifies by √(1 + (hΩ)²) per step and blows up",
            )?
            else {
                continue;
            };
            let l = &out.last;
            let dr = max_abs_diff(&l.r, &re);
            let dw = norm([l.omega[0] - we[0], l.omega[1] - we[1], l.omega[2] - we[2]]) / norm(we);
            if kind == "euler" {
                let health = health(&out);
                r.holds(
                    "high-rate",
                    format!(
                        "{name}: |ΔR| = {dr:.2e}; warned ({})",
                        health.first().map_or("no warning", String::as_str)
                    ),
                    !health.is_empty() || dr < 1e-2,
                    "euler: a wrong answer must come with a warning",
                );
                continue;
            }
            r.le(
                "high-rate",
                format!("{name}: max |ΔR| vs exact"),
                dr,
                bound,
                why,
            );
            r.le(
                "high-rate",
                format!("{name}: ‖ΔΩ‖/‖Ω‖ vs exact"),
                dw,
                bound,
                why,
            );
        }
    }
    // Attitude tracking of a 2 Hz command: the paper's experiment reference
    // at four times the frequency, rk4 at 1 ms against dopri at 1e-12.
    let mut fast = builtin::paper_attitude_experiment();
    fast.duration = if quick { 2.0 } else { 5.0 };
    for seg in &mut fast.plan {
        if let Some(AttitudeRef::EulerExperiment { frequency, .. }) = &mut seg.attitude {
            *frequency = 4.0 * std::f64::consts::PI;
        }
    }
    fast.control.timing = Timing::Continuous;
    fast.record.sample = 0.01;
    let mut tight = fast.clone();
    tight.integrator.kind = "dopri".into();
    tight.integrator.tol = 1e-12;
    let tight = run(&tight).map_err(failed("fast command reference"))?;
    let mut rk4 = fast.clone();
    rk4.integrator.kind = "rk4".into();
    rk4.integrator.dt = 1e-3;
    let rk4 = run(&rk4).map_err(failed("fast command rk4"))?;
    let (mut dpsi, mut dw) = (0.0f64, 0.0f64);
    for s in &rk4.samples {
        if let Some(o) = crate::metrics::at(&tight.samples, s.t) {
            dpsi = dpsi.max((s.psi - o.psi).abs());
            dw = dw.max(norm([
                s.omega[0] - o.omega[0],
                s.omega[1] - o.omega[1],
                s.omega[2] - o.omega[2],
            ]));
        }
    }
    let track = crate::metrics::max_psi_after(&tight.samples, 1.0);
    r.note(format!(
        "    2 Hz command: tracking Ψ after 1 s (tight run) peaks at {track:.3e}"
    ));
    r.le(
        "high-rate",
        "2 Hz attitude command, rk4 1e-3 vs dopri 1e-12: max |ΔΨ|".into(),
        dpsi,
        1e-6,
        "fourth order at hω ≈ 0.0126: (hω)⁴ ≈ 2.5e-8 per unit, with margin",
    );
    r.le(
        "high-rate",
        "2 Hz attitude command, rk4 1e-3 vs dopri 1e-12: max ‖ΔΩ‖, rad/s".into(),
        dw,
        1e-4,
        "Ω carries the command's 2 Hz derivatives: the Ψ bound times ω² ≈ 160",
    );
    Ok(())
}
