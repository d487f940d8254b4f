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

use scenes::Error;
use std::path::Path;

use crate::metrics::nan_max;
use crate::regress::SuiteError;
use logs::Sink;
use scenarios::{RunOptions, RunOutput, Sample, SimError, Simulation, Until};
use scenes::scene::{AttitudeRef, Scalar, Timing};
use scenes::{Scene, builtin};

mod horizon;
mod non_finite;
mod precision;
mod rates;

use crate::metrics::norm;
use controllers::{
    AccelerationModel, AttitudeGains, PositionGains, PositionMode, PositionReference,
    RigidBodyParams,
};
use dynamics::free_body::ExactFreeBody;
use dynamics::{Quadrotor, RigidBodyState};
use horizon::long_horizon;
use lie::GlamF64;
use non_finite::non_finite;
use precision::f32_vs_f64;
use rates::{free_body, high_rate, step_limit};

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

fn run(scene: &Scene) -> Result<RunOutput, Error> {
    scenes::run(scene, RunOptions::default())
}

/// A run that failed, as the suite's error.
fn failed(what: &str) -> impl FnOnce(Error) -> SuiteError + '_ {
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
            let named = matches!(e, Error::Run(SimError::Step { t, .. }) if t.is_finite());
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
        .fold(0.0, nan_max)
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
