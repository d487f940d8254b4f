//! Metrics over recorded samples, and the work-precision sweep (run time
//! and cost against error, every stepper over a range of step sizes).

use scenarios::{RunOptions, RunOutput, Sample};
use scenes::Error;

use scenes::{Scene, run};

/// The sample at time `t` (recorded exactly on the grid), if any.
pub fn at(samples: &[Sample], t: f64) -> Option<&Sample> {
    samples
        .iter()
        .find(|s| (s.t - t).abs() <= 1e-9 * t.max(1.0))
}

/// The largest differences between two runs over their common sample
/// times ([`max_difference`]).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Difference {
    /// max |Δx| over the components, m.
    pub x: f64,
    /// max |Δv| over the components, m/s.
    pub v: f64,
    /// max |ΔR| over the matrix entries.
    pub r: f64,
    /// How many samples of `a` found one of `b` at their time.
    pub compared: usize,
}

/// Largest difference between two runs over their common sample times in
/// x, v and the entries of R.
///
/// A NaN anywhere in a compared sample makes the figure NaN (`f64::max`
/// would drop it), and no common sample at all gives NaN for all three:
/// "nothing compared" must not read as "no difference", so a bound
/// `d < tol` fails in both cases. Callers that expect every sample to be
/// compared should also check `compared`.
pub fn max_difference(a: &[Sample], b: &[Sample]) -> Difference {
    let (mut dx, mut dv, mut dr, mut n) = (0.0f64, 0.0f64, 0.0f64, 0usize);
    for s in a {
        if let Some(o) = at(b, s.t) {
            n += 1;
            for k in 0..3 {
                dx = nan_max(dx, (s.x[k] - o.x[k]).abs());
                dv = nan_max(dv, (s.v[k] - o.v[k]).abs());
                for j in 0..3 {
                    dr = nan_max(dr, (s.r[k][j] - o.r[k][j]).abs());
                }
            }
        }
    }
    if n == 0 {
        (dx, dv, dr) = (f64::NAN, f64::NAN, f64::NAN);
    }
    Difference {
        x: dx,
        v: dv,
        r: dr,
        compared: n,
    }
}

/// The Euclidean norm of a vector in f64 components (what samples, logs
/// and studies hold), summed in the order x, y, z.
pub fn norm(v: [f64; 3]) -> f64 {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

/// `max` that keeps a NaN from either side (`f64::max` drops it): fold
/// with it wherever a maximum decides a check.
pub fn nan_max(a: f64, b: f64) -> f64 {
    if a.is_nan() || b.is_nan() {
        f64::NAN
    } else {
        a.max(b)
    }
}

/// The RMS of ‖x − x_d‖ over `samples`, m (`NaN` without samples).
pub fn rms_position_error(samples: &[Sample]) -> f64 {
    let n = samples.len() as f64;
    (samples.iter().map(|s| s.ex * s.ex).sum::<f64>() / n).sqrt()
}

/// Largest Ψ over samples with `t ≥ from`.
pub fn max_psi_after(samples: &[Sample], from: f64) -> f64 {
    samples
        .iter()
        .filter(|s| s.t >= from)
        .map(|s| s.psi)
        .fold(0.0, nan_max)
}

/// Largest ‖e_x‖ over samples with `t ≥ from`.
pub fn max_ex_after(samples: &[Sample], from: f64) -> f64 {
    samples
        .iter()
        .filter(|s| s.t >= from)
        .map(|s| s.ex)
        .fold(0.0, nan_max)
}

/// One point of a work-precision sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct WorkPoint {
    /// Stepper name.
    pub kind: String,
    /// Step size, or tolerance for dopri.
    pub param: f64,
    /// Steps taken.
    pub steps: u64,
    /// Load evaluations.
    pub evals: u64,
    /// Best-of-three wall time, s (the machine may be shared: the best of
    /// three is the least disturbed).
    pub wall: f64,
    /// Largest |Δx|, |ΔR| over the 0.1 s samples against dopri at 1e-12
    /// in f64.
    pub error: f64,
}

impl WorkPoint {
    /// The columns of [`WorkPoint::csv_row`], comma-separated.
    pub const CSV_COLUMNS: &'static str = "integrator,param,steps,evaluations,wall_s,error";

    /// The point as one CSV row (no newline), in the order of
    /// [`WorkPoint::CSV_COLUMNS`]; numbers in the shortest form that reads
    /// back the same value.
    pub fn csv_row(&self) -> String {
        format!(
            "{},{},{},{},{},{}",
            self.kind, self.param, self.steps, self.evals, self.wall, self.error
        )
    }
}

/// A work-precision sweep: the points, and the settings that failed
/// (a step size too coarse for a stepper, say) with why.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The points that ran, grid order.
    pub points: Vec<WorkPoint>,
    /// `(stepper, dt or tol, error)` of those that did not.
    pub failures: Vec<(String, f64, Error)>,
}

/// The step sizes (dopri: tolerances) of [`work_precision`], per stepper.
pub const GRID: [(&str, &[f64]); 6] = [
    ("euler", &[1e-3, 3e-4, 1e-4, 3e-5]),
    ("lgvi", &[4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4, 1e-4]),
    ("rk4", &[8e-3, 4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4]),
    ("rk4-projected", &[8e-3, 4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4]),
    ("rkmk4", &[8e-3, 4e-3, 2e-3, 1e-3, 5e-4, 2.5e-4]),
    ("dopri", &[1e-4, 1e-5, 1e-6, 3e-7, 1e-8, 1e-10]),
];

/// The run of `s` with the best wall time of three.
fn timed(s: &Scene) -> Result<(RunOutput, f64), Error> {
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..3 {
        let out = run(s, RunOptions::default())?;
        best = best.min(out.wall);
        last = Some(out);
    }
    Ok((last.expect("three runs"), best))
}

/// Every stepper over its [`GRID`] on `base` (with its scalar and
/// backend), the error measured against Dormand–Prince at tol 1e-12 in f64
/// (independent of the stepper under test except for dopri itself) over a
/// 0.1 s sample grid; `quick` takes every other grid point. `tick` is
/// called after each point. The reference run's error is the sweep's.
pub fn work_precision(
    base: &Scene,
    quick: bool,
    tick: &mut dyn FnMut(&WorkPoint),
) -> Result<Sweep, Error> {
    let mut base = base.clone();
    base.record.sample = 0.1;
    let mut reference = base.clone();
    reference.scalar = scenes::scene::Scalar::F64;
    reference.integrator.kind = "dopri".into();
    reference.integrator.tol = 1e-12;
    reference.integrator.dt = 0.1;
    let reference = run(&reference, RunOptions::default())?;
    let mut sweep = Sweep {
        points: Vec::new(),
        failures: Vec::new(),
    };
    for (kind, params) in GRID {
        for (i, &p) in params.iter().enumerate() {
            if quick && i % 2 == 1 {
                continue;
            }
            let mut s = base.clone();
            s.integrator.kind = kind.to_string();
            if kind == "dopri" {
                s.integrator.tol = p;
                s.integrator.dt = 0.1;
            } else {
                s.integrator.dt = p;
            }
            let (out, wall) = match timed(&s) {
                Ok(x) => x,
                Err(e) => {
                    sweep.failures.push((kind.to_string(), p, e));
                    continue;
                }
            };
            let Difference { x: dx, r: dr, .. } = max_difference(&out.samples, &reference.samples);
            let pt = WorkPoint {
                kind: kind.to_string(),
                param: p,
                steps: out.steps,
                evals: out.evaluations,
                wall,
                error: dx.max(dr),
            };
            tick(&pt);
            sweep.points.push(pt);
        }
    }
    Ok(sweep)
}

/// The whole-run figure the benches time: paper-flip (4 s) by RK4 at
/// h = 1 ms with a sample every 0.05 s, and its reference, the same scene
/// by Dormand–Prince at tol 1e-12 (f64). One set-up for the step bench and
/// `cargo xtask bench`, so that both time and check the same run.
pub fn flip_rk4_1ms() -> (Scene, Scene) {
    let mut flip = scenes::builtin::paper_flip();
    flip.integrator.kind = "rk4".into();
    flip.integrator.dt = 1e-3;
    flip.record.sample = 0.05;
    let mut exact = flip.clone();
    exact.integrator.kind = "dopri".into();
    exact.integrator.tol = 1e-12;
    (flip, exact)
}

/// [`flip_rk4_1ms`]'s final-state error ([`final_state_error`]) against
/// its reference, in f64 and in f32 (nalgebra; the backends agree to
/// rounding).
pub fn flip_rk4_errors() -> Result<[f64; 2], Error> {
    let (mut flip, exact) = flip_rk4_1ms();
    let truth = run(&exact, RunOptions::default())?.last;
    let mut err = |scalar| {
        flip.scalar = scalar;
        run(&flip, RunOptions::default()).map(|o| final_state_error(&o.last, &truth))
    };
    Ok([
        err(scenes::scene::Scalar::F64)?,
        err(scenes::scene::Scalar::F32)?,
    ])
}

/// The point of `points` with the least wall time among those with an
/// error at most `target`: the reading of a work-precision figure.
pub fn fastest_within<'p>(
    points: impl IntoIterator<Item = &'p WorkPoint>,
    target: f64,
) -> Option<&'p WorkPoint> {
    points
        .into_iter()
        .filter(|p| p.error <= target)
        .min_by(|a, b| a.wall.total_cmp(&b.wall))
}

/// The largest component of |Δx| and |ΔR| between two samples (a run's
/// final state against a reference's).
pub fn final_state_error(a: &Sample, b: &Sample) -> f64 {
    let dx = (0..3).map(|k| (a.x[k] - b.x[k]).abs());
    let dr = (0..9).map(|k| (a.r[k / 3][k % 3] - b.r[k / 3][k % 3]).abs());
    dx.chain(dr).fold(0.0, f64::max)
}
