//! The numerical stress suite: each case measures figures against bounds,
//! each bound with its reason, PASS or FAIL.
//!
//! Cases: long horizon (hover under Δ at 1 kHz, every stepper, f32 and
//! f64), the free rigid body for 10⁴ s (energy and momentum drift), the
//! step-size limit of every stepper on paper-flip and what happens just past
//! it, high rates (a body spinning at 100 rad/s against the exact solution,
//! a fast attitude command against a tight reference), f32 against f64 on
//! every built-in scene, and a non-finite reference injected mid-run with
//! the CSV and MCAP read back. `quick` shortens the horizons (CI).

use std::path::Path;

use crate::output::{self, Sink};
use crate::regress::SuiteError;
use crate::scene::{AttitudeRef, Scalar, Timing};
use crate::{RunOptions, RunOutput, Sample, Scene, SimError, Simulation, Until, builtin};
use controllers::{
    AccelerationModel, AttitudeGains, PositionGains, PositionMode, PositionReference,
    RigidBodyParams,
};
use dynamics::free_body::ExactFreeBody;
use dynamics::{Quadrotor, RigidBodyState};
use lie::{Backend, GlamF64};

const STEPPERS: [&str; 6] = ["lgvi", "rk4", "rk4-projected", "rkmk4", "euler", "dopri"];

/// One figure against its bound.
#[derive(Clone, Debug, PartialEq)]
pub struct Check {
    /// The case (`long-horizon`, `free-body`, …).
    pub case: &'static str,
    /// What was measured, with its context.
    pub what: String,
    /// The figure (1 or 0 for a yes/no outcome).
    pub value: f64,
    /// Its bound.
    pub bound: f64,
    /// Why the bound is that size.
    pub reason: &'static str,
    /// Whether it holds.
    pub pass: bool,
}

/// What the suite reports as it goes.
#[derive(Debug)]
pub enum Event<'a> {
    /// A case starts.
    Case(&'static str),
    /// A check was made.
    Check(&'a Check),
    /// A figure worth showing that is not a check.
    Note(String),
}

struct Report<'a> {
    checks: Vec<Check>,
    on: &'a mut dyn FnMut(Event<'_>),
}

impl Report<'_> {
    fn note(&mut self, s: String) {
        (self.on)(Event::Note(s));
    }

    /// `value ≤ bound` (a NaN fails).
    fn le(&mut self, case: &'static str, what: String, value: f64, bound: f64, why: &'static str) {
        self.push(case, what, value, bound, why, value <= bound);
    }

    fn push(
        &mut self,
        case: &'static str,
        what: String,
        value: f64,
        bound: f64,
        reason: &'static str,
        pass: bool,
    ) {
        let c = Check {
            case,
            what,
            value,
            bound,
            reason,
            pass,
        };
        (self.on)(Event::Check(&c));
        self.checks.push(c);
    }

    /// A yes/no outcome (value 1 = holds).
    fn holds(&mut self, case: &'static str, what: String, ok: bool, why: &'static str) {
        self.push(case, what, f64::from(u8::from(ok)), 1.0, why, ok);
    }
}

/// The run's health findings, as sentences.
fn health(out: &RunOutput) -> Vec<String> {
    out.health().iter().map(ToString::to_string).collect()
}

fn run(scene: &Scene) -> Result<RunOutput, SimError> {
    crate::run(scene, RunOptions::default())
}

/// A run that failed, as the suite's error.
fn failed(what: &str) -> impl FnOnce(SimError) -> SuiteError + '_ {
    move |source| SuiteError::Run {
        scene: what.to_string(),
        source,
    }
}

/// A file the suite wrote that it could not read back.
fn unreadable<E: std::error::Error + Send + Sync + 'static>(
    path: &Path,
) -> impl FnOnce(E) -> SuiteError + '_ {
    move |e| SuiteError::Read {
        path: path.to_path_buf(),
        source: Box::new(e),
    }
}

fn eps(s: Scalar) -> f64 {
    match s {
        Scalar::F32 => f64::from(f32::EPSILON),
        Scalar::F64 => f64::EPSILON,
    }
}

fn scalar_name(s: Scalar) -> &'static str {
    match s {
        Scalar::F32 => "f32",
        Scalar::F64 => "f64",
    }
}

/// A tolerance the scalar can deliver for dopri.
fn dopri_tol(s: Scalar) -> f64 {
    match s {
        Scalar::F32 => 1e-5,
        Scalar::F64 => 1e-9,
    }
}

fn finite(out: &RunOutput) -> bool {
    out.samples.iter().chain([&out.last]).all(|s| {
        s.x.iter()
            .chain(&s.v)
            .chain(&s.omega)
            .chain(s.r.iter().flatten())
            .all(|c| c.is_finite())
    })
}

/// Entry point.
/// The case names, in the order [`cases`] runs them.
pub const CASES: [&str; 6] = [
    "long-horizon",
    "non-finite",
    "free-body",
    "step-limit",
    "high-rate",
    "f32-vs-f64",
];

/// Runs the cases `want` accepts (`quick`: short horizons; `horizon`: the
/// long-horizon case's simulated time, default 3600 s or 60 s quick), the
/// non-finite case's files written into `dir`; `on` sees each case start,
/// each check and each note as they come.
pub fn cases(
    quick: bool,
    want: &dyn Fn(&str) -> bool,
    horizon: Option<f64>,
    dir: &Path,
    on: &mut dyn FnMut(Event<'_>),
) -> Result<Vec<Check>, SuiteError> {
    type Case = fn(&mut Report<'_>, bool, &Path) -> Result<(), SuiteError>;
    let mut r = Report {
        checks: Vec::new(),
        on,
    };
    if want("long-horizon") {
        (r.on)(Event::Case("long-horizon"));
        long_horizon(&mut r, quick, horizon)?;
    }
    let cases: [(&'static str, Case); 5] = [
        ("non-finite", non_finite),
        ("free-body", free_body),
        ("step-limit", step_limit),
        ("high-rate", high_rate),
        ("f32-vs-f64", f32_vs_f64),
    ];
    for (name, case) in cases {
        if want(name) {
            (r.on)(Event::Case(name));
            case(&mut r, quick, dir)?;
        }
    }
    Ok(r.checks)
}

/// Runs `s`. For euler, which is expected to blow up on the hard cases, an
/// error is an outcome: checked to name the time, and `None` returned.
fn run_or_told(
    r: &mut Report<'_>,
    case: &'static str,
    name: &str,
    s: &Scene,
    why: &str,
) -> Result<Option<RunOutput>, SuiteError> {
    match run(s) {
        Ok(o) => Ok(Some(o)),
        Err(e) if s.integrator.kind == "euler" => {
            let named = matches!(e, SimError::Step { t, .. } if t.is_finite());
            r.holds(
                case,
                format!("{name}: {why}; the run says so: {e}"),
                named,
                "an unstable stepper must end in a clear error naming the time, not a silent answer",
            );
            Ok(None)
        }
        Err(e) => Err(failed(name)(e)),
    }
}

fn ortho(s: &Sample) -> f64 {
    let mut e = 0.0f64;
    for i in 0..3 {
        for k in 0..3 {
            let rtr: f64 = (0..3).map(|j| s.r[j][i] * s.r[j][k]).sum();
            let d = rtr - if i == k { 1.0 } else { 0.0 };
            e += d * d;
        }
    }
    e.sqrt()
}

/// Hover under constant Δ for an hour (a minute with `--quick`) at 1 kHz,
/// against dopri at 1e-12 in f64.
fn long_horizon(r: &mut Report<'_>, quick: bool, horizon: Option<f64>) -> Result<(), SuiteError> {
    let duration = horizon.unwrap_or(if quick { 60.0 } else { 3600.0 });
    let scene = |kind: &str, scalar: Scalar| {
        let mut s = builtin::hover_disturbed();
        s.duration = duration;
        s.scalar = scalar;
        s.integrator.kind = kind.into();
        s.integrator.dt = 1e-3;
        s.integrator.tol = dopri_tol(scalar);
        s.record.sample = (duration / 600.0).max(0.1);
        s
    };
    let mut tight = scene("dopri", Scalar::F64);
    tight.integrator.tol = 1e-12;
    let tight = run(&tight).map_err(failed("long-horizon reference"))?;
    for scalar in [Scalar::F64, Scalar::F32] {
        for kind in STEPPERS {
            let s = scene(kind, scalar);
            let name = format!("{kind} {} {duration} s", scalar_name(scalar));
            let out = match run(&s) {
                Ok(o) => o,
                Err(e) => {
                    r.holds("long-horizon", format!("{name}: runs ({e})"), false, "");
                    continue;
                }
            };
            r.holds(
                "long-horizon",
                format!("{name}: every sample finite"),
                finite(&out),
                "a NaN anywhere is a failure",
            );
            let threshold = match scalar {
                Scalar::F64 => 1e-6,
                Scalar::F32 => 1e-3,
            };
            let health = health(&out);
            if kind == "euler" {
                // Explicit Euler on the matrix leaves SO(3) at O(h) per unit
                // time: what matters is that the run says so.
                r.holds(
                    "long-horizon",
                    format!(
                        "{name}: max ‖RᵀR − I‖ = {:.2e}, within {threshold:.0e} or warned ({})",
                        out.max_orthogonality_error,
                        health.first().map_or("no warning", String::as_str)
                    ),
                    out.max_orthogonality_error <= threshold || !health.is_empty(),
                    "euler leaves the group; past the threshold the health check must report it",
                );
            } else {
                r.le(
                    "long-horizon",
                    format!("{name}: max ‖RᵀR − I‖"),
                    out.max_orthogonality_error,
                    threshold,
                    "the run's own health threshold (1e-6 f64, 1e-3 f32)",
                );
            }
            // Growth: the drift off the group over the second half against
            // the first.
            let half = duration / 2.0;
            let first = out
                .samples
                .iter()
                .filter(|x| x.t <= half)
                .map(ortho)
                .fold(0.0, f64::max);
            let second = out
                .samples
                .iter()
                .filter(|x| x.t > half)
                .map(ortho)
                .fold(0.0, f64::max);
            // Below ~5000 ε the figure is rounding noise, not a drift.
            let floor = 5000.0 * eps(scalar);
            r.le(
                "long-horizon",
                format!("{name}: ‖RᵀR − I‖ growth, second half / first half (floor {floor:.0e})"),
                second.max(floor) / first.max(floor),
                2.5,
                "a rounding random walk grows √2 from half to end, a linear drift 2; more is an instability",
            );
            // Against the tight f64 reference, sample by sample.
            let (mut dex, mut dpsi) = (0.0f64, 0.0f64);
            for x in &out.samples {
                if let Some(o) = crate::metrics::at(&tight.samples, x.t) {
                    dex = dex.max((x.ex - o.ex).abs());
                    dpsi = dpsi.max((x.psi - o.psi).abs());
                }
            }
            let (bound, why) = long_bound(kind, scalar);
            r.le(
                "long-horizon",
                format!("{name}: max |Δ‖e_x‖| vs dopri 1e-12 f64, m"),
                dex,
                bound,
                why,
            );
            r.le(
                "long-horizon",
                format!("{name}: max |ΔΨ| vs dopri 1e-12 f64"),
                dpsi,
                bound,
                why,
            );
        }
    }
    Ok(())
}

fn long_bound(kind: &str, scalar: Scalar) -> (f64, &'static str) {
    match (kind, scalar) {
        ("euler", _) => (
            1e-2,
            "first order at h = 1e-3 and off the group: only bounded (1 cm, Ψ 1e-2)",
        ),
        (_, Scalar::F32) => (
            1e-3,
            "f32: the state carries ~1e-7 relative rounding per step; the loop contracts it to a noise floor (≤ 1e-3)",
        ),
        ("lgvi", _) => (
            1e-5,
            "second order at h = 1e-3 in a contracting loop: h² = 1e-6 times the loop's gains (k_x/m ≈ 17)",
        ),
        _ => (
            1e-9,
            "fourth/fifth order at h = 1e-3 in a contracting loop: h⁴ ≈ 1e-12, with margin",
        ),
    }
}

fn energy_momentum(s: &Sample, j: [f64; 3]) -> (f64, [f64; 3]) {
    let w = s.omega;
    let e = 0.5 * (0..3).map(|k| j[k] * w[k] * w[k]).sum::<f64>();
    let body = [j[0] * w[0], j[1] * w[1], j[2] * w[2]];
    let mut pi = [0.0; 3];
    for (i, p) in pi.iter_mut().enumerate() {
        *p = (0..3).map(|k| s.r[i][k] * body[k]).sum();
    }
    (e, pi)
}

/// Largest entry-wise difference of two matrices.
fn max_abs_diff(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> f64 {
    a.iter()
        .flatten()
        .zip(b.iter().flatten())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// Largest relative drift of energy and spatial angular momentum over the
/// recorded samples.
fn drifts(out: &RunOutput, j: [f64; 3]) -> (f64, f64) {
    let (e0, p0) = energy_momentum(&out.samples[0], j);
    let (mut de, mut dp) = (0.0f64, 0.0f64);
    for s in out.samples.iter().chain([&out.last]) {
        let (e, p) = energy_momentum(s, j);
        de = de.max(((e - e0) / e0).abs());
        dp = dp.max(norm([p[0] - p0[0], p[1] - p0[1], p[2] - p0[2]]) / norm(p0));
    }
    (de, dp)
}

/// The free rigid body for 10⁴ s (10³ with `--quick`), h = 0.01.
fn free_body(r: &mut Report<'_>, quick: bool, _: &Path) -> Result<(), SuiteError> {
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

/// The final-state error of a paper-flip run against a reference run: the
/// largest of ‖Δx‖ (m) and ‖ΔR‖ (entries).
fn flip_error(out: &RunOutput, reference: &Sample) -> f64 {
    let l = &out.last;
    let dx = norm([
        l.x[0] - reference.x[0],
        l.x[1] - reference.x[1],
        l.x[2] - reference.x[2],
    ]);
    dx.max(max_abs_diff(&l.r, &reference.r))
}

/// Every stepper on paper-flip at doubling steps: the largest step whose
/// final error stays under 1 cm / 0.01 against dopri at 1e-12, and what
/// happens past it: an error or a health warning is fine, a finite wrong
/// answer with no warning fails.
fn step_limit(r: &mut Report<'_>, _quick: bool, _: &Path) -> Result<(), SuiteError> {
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
fn high_rate(r: &mut Report<'_>, quick: bool, _: &Path) -> Result<(), SuiteError> {
    let duration = if quick { 2.0 } else { 10.0 };
    let omega0 = [3.0, -2.0, 100.0];
    let mut base = builtin::free_rigid_body();
    base.duration = duration;
    base.initial.omega = omega0;
    base.integrator.dt = 1e-3;
    base.record.sample = duration; // the end only: the exact solution is compared there
    let rows = crate::reference::rotation_f64(base.initial.rotation);
    let exact = ExactFreeBody::new(base.vehicle.inertia, omega0, rows)
        .map_err(|e| failed("exact free body")(SimError::Vehicle(e)))?;
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

/// Every built-in scene in f32 against f64: the largest state difference
/// over the run.
fn f32_vs_f64(r: &mut Report<'_>, _quick: bool, _: &Path) -> Result<(), SuiteError> {
    for scene in builtin::all() {
        let mut s64 = scene.clone();
        s64.scalar = Scalar::F64;
        let mut s32 = scene.clone();
        s32.scalar = Scalar::F32;
        if s32.integrator.kind == "dopri" {
            s32.integrator.tol = s32.integrator.tol.max(1e-6);
        }
        let a = run(&s64).map_err(failed(&format!("{} f64", scene.name)))?;
        let b = run(&s32).map_err(failed(&format!("{} f32", scene.name)))?;
        let (dx, dv, dr, n) = crate::metrics::max_difference(&a.samples, &b.samples);
        let mut dw = 0.0f64;
        for s in &a.samples {
            if let Some(o) = crate::metrics::at(&b.samples, s.t) {
                dw = dw.max(norm([
                    s.omega[0] - o.omega[0],
                    s.omega[1] - o.omega[1],
                    s.omega[2] - o.omega[2],
                ]));
            }
        }
        println!(
            "    {}: {n} samples, max |Δx| {dx:.2e} m, |Δv| {dv:.2e} m/s, |ΔR| {dr:.2e}, ‖ΔΩ‖ {dw:.2e} rad/s",
            scene.name
        );
        let (bound, why) = f32_bound(&scene.name);
        r.le(
            "f32-vs-f64",
            format!("{}: max |ΔR| f32 vs f64", scene.name),
            dr,
            bound,
            why,
        );
        r.le(
            "f32-vs-f64",
            format!("{}: max |Δx| f32 vs f64, m", scene.name),
            dx,
            bound,
            why,
        );
    }
    Ok(())
}

fn f32_bound(name: &str) -> (f64, &'static str) {
    match name {
        "free-rigid-body" => (
            1e-3,
            "no feedback: f32 rounding (~10 ε per step over 10⁴ steps ≈ 1e-2 worst case, ~√n typical: 1e-4) drifts the phase",
        ),
        _ => (
            1e-3,
            "f32 rounds each step at ε ≈ 1.2e-7; the closed loop contracts it, so f32 stays within ~10⁴ ε of f64",
        ),
    }
}

/// Position mode hovering at 1 m, its reference turning NaN at t = 1.5 s;
/// the run streams to CSV and MCAP.
fn non_finite(r: &mut Report<'_>, _quick: bool, dir: &Path) -> Result<(), SuiteError> {
    type B = GlamF64;
    const T_BAD: f64 = 1.5;
    let reference = |t: f64| {
        let z = B::vec3(0.0, 0.0, 0.0);
        let x = if t < T_BAD {
            B::vec3(0.0, 0.0, -1.0)
        } else {
            B::vec3(0.0, f64::NAN, -1.0)
        };
        PositionReference::<B> {
            x,
            v: z,
            a: z,
            jerk: z,
            snap: z,
            b1d: B::vec3(1.0, 0.0, 0.0),
            b1d_dot: z,
            b1d_ddot: z,
        }
    };
    let mode = PositionMode::new(
        RigidBodyParams::<B>::paper(),
        PositionGains::paper(),
        AttitudeGains::paper(),
        AccelerationModel::Nominal,
        reference,
    );
    let quad = Quadrotor::<B>::paper()
        .with_disturbance(Quadrotor::<B>::paper_disturbance())
        .map_err(|e| failed("non-finite vehicle")(SimError::Vehicle(e)))?;
    let csv_path = dir.join("non-finite.csv");
    let mcap_path = dir.join("non-finite.mcap");
    let mut csv = output::CsvWriter::create(&csv_path).map_err(SuiteError::Output)?;
    let mut mcap = output::McapWriter::create(&mcap_path).map_err(SuiteError::Output)?;
    let sim = Simulation::<B>::builder(Box::new(quad))
        .mode(mode, Until::Never)
        .initial(RigidBodyState::<B>::at_rest())
        .dt(1e-3)
        .duration(4.0)
        .record_every(0.01)
        .build()
        .map_err(failed("non-finite"))?;
    let mut last_t = None;
    let result = {
        let mut tee = output::Tee(vec![&mut csv as &mut dyn Sink, &mut mcap]);
        let mut sink = LastTime {
            inner: &mut tee,
            t: &mut last_t,
        };
        sim.run(RunOptions {
            record: false,
            sink: Some(&mut sink),
            ..Default::default()
        })
    };
    let message = match &result {
        Ok(_) => String::new(),
        Err(e) => e.to_string(),
    };
    r.note(format!("    the run says: {message}"));
    let held = last_t.unwrap_or(0.0);
    let rows = csv.finish().map_err(SuiteError::Output)?;
    let stopped = output::Stopped {
        t: held,
        reason: format!("error: {message}"),
    };
    let messages = mcap
        .finish(&[], Some(&stopped))
        .map_err(SuiteError::Output)?;
    r.holds(
        "non-finite",
        "the run stops with an error".into(),
        result.is_err(),
        "a NaN reference must not fly on",
    );
    // What went wrong, from the error's variant and fields; then that the
    // message the user reads shows the same.
    let (field, t_err) = match &result {
        Err(SimError::Step {
            t,
            control: Some(controllers::ControlError::NonFiniteReference { field }),
            ..
        }) => (Some(*field), Some(*t)),
        _ => (None, None),
    };
    r.holds(
        "non-finite",
        format!("the error is the reference's and names the field (`reference.x`): {field:?}"),
        field == Some("reference.x"),
        "the user must learn which input went bad",
    );
    r.holds(
        "non-finite",
        format!("the error names the time, within one step of {T_BAD} s: {t_err:?}"),
        t_err.is_some_and(|t| (t - T_BAD).abs() <= 1e-3 + 1e-12),
        "the user must learn when it went bad",
    );
    let shown = t_err
        .is_some_and(|t| shows(&message, "reference.x") && shows(&message, &format!("t = {t}")));
    r.holds(
        "non-finite",
        format!("the message shows the field and the time: {message:?}"),
        shown,
        "the typed error reaches the user as a sentence",
    );
    // Read both files back.
    let (n, t_last) = csv_read_back(r, &csv_path, rows, T_BAD)?;
    mcap_read_back(r, &mcap_path, messages, n, t_last)?;
    Ok(())
}

/// Whether a message shown to the user contains `what` (a check of the
/// message itself; nothing is decided from it).
fn shows(text: &str, what: &str) -> bool {
    text.contains(what)
}

/// The non-finite case's CSV, read back: whole rows, increasing times, as
/// many as the writer said, the last one just before the NaN at `t_bad`.
/// Returns the row count and the last time.
fn csv_read_back(
    r: &mut Report<'_>,
    csv_path: &Path,
    rows: u64,
    t_bad: f64,
) -> Result<(u64, f64), SuiteError> {
    let text = std::fs::read_to_string(csv_path).map_err(unreadable(csv_path))?;
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default();
    let width = header.split(',').count();
    let (mut n, mut whole, mut t_last) = (0u64, true, f64::NAN);
    let mut increasing = true;
    for l in lines {
        let cells: Vec<&str> = l.split(',').collect();
        whole &= cells.len() == width;
        let t: f64 = cells[0].parse().unwrap_or(f64::NAN);
        // The first row compares against NaN: true.
        increasing &= t_last.is_nan() || t > t_last;
        t_last = t;
        n += 1;
    }
    r.holds(
        "non-finite",
        format!(
            "CSV: {n} rows (writer said {rows}), all whole, times increasing, last t = {t_last}"
        ),
        whole && increasing && n == rows && n > 0 && (t_bad - 0.011..t_bad).contains(&t_last),
        "everything sampled before the NaN is on disk, up to the last sample before it",
    );
    Ok((n, t_last))
}

/// The non-finite case's MCAP, read back: finished and indexed, every pose
/// decodes, one pose per CSV row (`n`) up to `t_last`, and a `stopped`
/// record there.
fn mcap_read_back(
    r: &mut Report<'_>,
    mcap_path: &Path,
    messages: u64,
    n: u64,
    t_last: f64,
) -> Result<(), SuiteError> {
    let bytes = std::fs::read(mcap_path).map_err(unreadable(mcap_path))?;
    let summary = mcap::Summary::read(&bytes)
        .map_err(unreadable(mcap_path))?
        .and_then(|s| s.stats)
        .map(|s| s.message_count);
    let (mut count, mut last_pose, mut poses) = (0u64, 0u64, 0u64);
    let mut all_decode = true;
    for m in mcap::MessageStream::new(&bytes).map_err(unreadable(mcap_path))? {
        let m = m.map_err(unreadable(mcap_path))?;
        if m.channel.topic == "/vehicle/pose" {
            use foxglove::Decode;
            all_decode &= foxglove::messages::PoseInFrame::decode(&m.data[..]).is_ok();
            poses += 1;
            last_pose = m.log_time;
        }
        count += 1;
    }
    let mut stopped_t = None;
    for rec in mcap::read::LinearReader::new(&bytes).map_err(unreadable(mcap_path))? {
        if let Ok(mcap::records::Record::Metadata(m)) = rec
            && m.name == "stopped"
        {
            stopped_t = m.metadata.get("t").and_then(|v| v.parse::<f64>().ok());
        }
    }
    r.holds(
        "non-finite",
        format!(
            "MCAP: {count} messages (writer said {messages}, summary {summary:?}), {poses} poses, last at {} s, `stopped` at {stopped_t:?}",
            last_pose as f64 * 1e-9
        ),
        summary == Some(count)
            && count == messages
            && all_decode
            && poses == n
            && last_pose == (t_last * 1e9).round() as u64
            && stopped_t == Some(t_last),
        "the MCAP is finished and indexed, readable to the last sample, and says where and why it stopped",
    );
    Ok(())
}

/// Remembers the time of the last sample passed on.
struct LastTime<'a, 'b> {
    inner: &'a mut dyn Sink,
    t: &'b mut Option<f64>,
}

impl Sink for LastTime<'_, '_> {
    fn begin(&mut self, mode_names: &[&'static str]) -> Result<(), output::OutputError> {
        self.inner.begin(mode_names)
    }
    fn switch(&mut self, s: &crate::SwitchRecord, mode: &str) -> Result<(), output::OutputError> {
        self.inner.switch(s, mode)
    }
    fn sample(&mut self, s: &Sample) -> Result<(), output::OutputError> {
        *self.t = Some(s.t);
        self.inner.sample(s)
    }
}
