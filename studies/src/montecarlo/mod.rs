//! Monte Carlo studies: many runs from random initial conditions, each
//! classified as converged, out of time, diverged or failed, with summary
//! statistics.
//!
//! # Sampling
//! Each sample's random numbers come from its own ChaCha8 [`stream`] keyed
//! by the study's seed, with the sample index as the stream number: sample
//! `i` is the same whatever the thread count, the shard or the order of
//! evaluation. [`shoemake`] draws a uniform rotation (K. Shoemake,
//! "Uniform random rotations", Graphics Gems III, 1992: with
//! `u1, u2, u3 ~ U[0, 1)`, `q = (√(1−u1) sin 2πu2, √(1−u1) cos 2πu2,
//! √u1 sin 2πu3, √u1 cos 2πu3)`, whose angle θ has density
//! `(1 − cos θ)/π` on `[0, π]`), [`in_ball`] a uniform point in a ball.
//!
//! # Convergence
//! A [`Study`]'s settle metric `m(t)` (any function of the time, the body
//! state and the command) says how far a sample is from where it should
//! end; the sample has settled once `m < 1` has held for the study's hold
//! time, and its time to settle is the start of that stretch ([`Settled`]).
//! The run stops there (a stop condition), so the tail is not integrated.
//! A [`DivergenceGuard`](scenarios::DivergenceGuard) on the simulation ends a
//! blow-up early; such a sample is [`Status::Diverged`].
//!
//! # Example
//! A hexarotor from uniformly random attitudes (at rest, level hover
//! commanded), settled when Ψ < 10⁻³ for 0.2 s:
//! ```
//! use controllers::{AttitudeGains, AttitudeMode, AttitudeThrust, HoldAttitude, HoldPosition, RigidBodyParams};
//! use dynamics::{Hexarotor, RigidBodyState, paper};
//! use lie::{Backend, GlamF64, Real, Rotation, So3Mat};
//! use studies::montecarlo::{Status, Study, Summary, shoemake};
//! use scenarios::{Simulation, Until};
//! type B = GlamF64;
//!
//! let study = Study::new(
//!     7,
//!     0.2,
//!     |rng| shoemake(rng),
//!     |q: &[f64; 4]| {
//!         let hex = Hexarotor::<B>::paper();
//!         let params = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
//!         let mode = AttitudeMode::<B, _, HoldPosition<B>>::new(
//!             params,
//!             AttitudeGains::paper(),
//!             HoldAttitude::new(So3Mat::<B>::identity()),
//!             AttitudeThrust::Constant(params.mass * params.gravity),
//!         );
//!         let mut start = RigidBodyState::<B>::at_rest();
//!         let q = B::quat_from_wxyz(q[0], q[1], q[2], q[3]);
//!         start.r = lie::So3Quat::<B>::from_quaternion_unchecked(q).matrix();
//!         Ok(Simulation::<B>::builder(Box::new(hex))
//!             .mode(mode, Until::Never)
//!             .initial(start)
//!             .duration(10.0)
//!             .dt(2e-3))
//!     },
//!     |_t, _body, cmd| cmd.psi.to_f64_lossless() / 1e-3,
//! );
//! let trials = study.run(&(0..8).collect::<Vec<u64>>(), None, None)?;
//! let summary = Summary::of(&trials);
//! assert_eq!(summary.samples, 8);
//! assert!(trials.iter().all(|t| t.status != Status::Error));
//! # Ok::<(), scenes::Error>(())
//! ```

mod experiments;
#[cfg(feature = "simd")]
mod lanes;
mod near_pi;
mod report;
pub mod shards;

pub use experiments::{
    DIVERGED_OMEGA, DIVERGED_X, Experiment, Initial, MAX_SUBSTEPS, Outcome, SAMPLES_HEADER, Setup,
    parse_samples, write_samples,
};
#[cfg(feature = "simd")]
pub use lanes::LaneUse;
pub use near_pi::{NearPiAxis, near_pi, near_pi_csv};
pub use rand_chacha::ChaCha8Rng as Stream;
pub use rand_chacha::rand_core;
pub use report::{Cost, Report, SlowSample};

use scenes::Error;
use std::marker::PhantomData;
use std::sync::atomic::{AtomicBool, Ordering};

use controllers::ModeOutput;
use dynamics::RigidBodyState;
use integrators::Method;
use lie::Backend;
use rand_chacha::rand_core::{Rng, SeedableRng};

use logs::{OutputError, Sink};
use scenarios::{Divergence, Termination};
use scenarios::{RunOptions, RunOutput, Sample, SimError, SimulationBuilder, SwitchRecord};

/// Sample `index`'s random stream under `seed`.
pub fn stream(seed: u64, index: u64) -> Stream {
    let mut rng = Stream::seed_from_u64(seed);
    rng.set_stream(index);
    rng
}

/// A uniform number in `[0, 1)` on the f64 grid (53 random bits).
pub fn uniform(rng: &mut Stream) -> f64 {
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A uniform random unit quaternion `(w, x, y, z)`, `w ≥ 0` (Shoemake).
pub fn shoemake(rng: &mut Stream) -> [f64; 4] {
    let (u1, u2, u3) = (uniform(rng), uniform(rng), uniform(rng));
    let tau = std::f64::consts::TAU;
    let (a, b) = ((1.0 - u1).sqrt(), u1.sqrt());
    let (x, y, z, w) = (
        a * (tau * u2).sin(),
        a * (tau * u2).cos(),
        b * (tau * u3).sin(),
        b * (tau * u3).cos(),
    );
    if w < 0.0 {
        [-w, -x, -y, -z]
    } else {
        [w, x, y, z]
    }
}

/// A uniform point in the ball of radius `r` (rejection from the cube).
///
/// # Panics
/// If 1 000 draws in a row miss the ball. Each lands in it with
/// probability π/6, so that happens only with a broken generator, and a
/// panic then beats an endless loop.
pub fn in_ball(rng: &mut Stream, r: f64) -> [f64; 3] {
    for _ in 0..1000 {
        let p = [
            2.0 * uniform(rng) - 1.0,
            2.0 * uniform(rng) - 1.0,
            2.0 * uniform(rng) - 1.0,
        ];
        if p.iter().map(|c| c * c).sum::<f64>() <= 1.0 {
            return p.map(|c| c * r);
        }
    }
    panic!("1 000 points drawn from the cube all missed the unit ball: `uniform` is broken")
}

/// The settle predicate with its hold: `m(t) < 1` from `entered` on, for
/// `hold` seconds. It is a stop condition, so the simulation's bisection
/// calls it again at earlier times inside the last step: such calls read
/// the state without changing it, so the located instant is where the
/// hold first completes.
#[derive(Clone, Debug)]
pub struct Settled {
    hold: f64,
    entered: Option<f64>,
    last: Option<(f64, f64)>,
}

impl Settled {
    /// A hold of `hold` seconds.
    pub fn new(hold: f64) -> Self {
        Self {
            hold,
            entered: None,
            last: None,
        }
    }

    /// Whether the hold is complete at `t` with metric `m`. The start of
    /// the stretch below 1 is interpolated linearly inside the step where
    /// `m` crosses 1.
    pub fn check(&mut self, t: f64, m: f64) -> bool {
        let inside = m < 1.0;
        if let Some((tl, _)) = self.last
            && t <= tl
        {
            return inside && self.entered.is_some_and(|e| t - e >= self.hold);
        }
        if inside {
            if self.entered.is_none() {
                let te = match self.last {
                    Some((tl, ml)) if ml > 1.0 && ml.is_finite() => {
                        tl + (t - tl) * (ml - 1.0) / (ml - m)
                    }
                    _ => t,
                };
                self.entered = Some(te);
            }
        } else {
            self.entered = None;
        }
        self.last = Some((t, m));
        inside && self.entered.is_some_and(|e| t - e >= self.hold)
    }

    /// The start of the current stretch below 1, if in one.
    pub fn entered(&self) -> Option<f64> {
        self.entered
    }
}

/// How a sample ended.
#[derive(Copy, Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// The settle metric stayed below 1 for the hold time before the
    /// duration ran out.
    Converged,
    /// The duration ran out first.
    Deadline,
    /// The simulation's divergence guard ended it.
    Diverged,
    /// A step failed (a non-finite state at this step size, an implicit
    /// stepper without a solution), or the law rejected a non-finite
    /// state.
    Error,
}

impl Status {
    /// The name in `samples.csv`.
    pub fn name(self) -> &'static str {
        match self {
            Status::Converged => "converged",
            Status::Deadline => "deadline",
            Status::Diverged => "diverged",
            Status::Error => "error",
        }
    }

    /// The status called `s`.
    pub fn parse(s: &str) -> Option<Self> {
        [
            Status::Converged,
            Status::Deadline,
            Status::Diverged,
            Status::Error,
        ]
        .into_iter()
        .find(|x| x.name() == s)
    }
}

/// One sample of a [`Study`].
#[derive(Clone, Debug)]
pub struct Trial<D> {
    /// Its index.
    pub index: u64,
    /// What was drawn for it.
    pub draw: D,
    /// How it ended.
    pub status: Status,
    /// When it settled (the start of the held stretch), s; converged
    /// samples only.
    pub t_settled: Option<f64>,
    /// Largest commanded thrust over its samples (on the simulation's
    /// record grid), N.
    pub max_thrust: f64,
    /// Largest rotor thrust over the same samples, N.
    pub max_rotor: f64,
    /// The run's output (its last sample, steps, termination); the step's
    /// error for [`Status::Error`].
    pub run: Result<RunOutput, Error>,
}

impl<D> Trial<D> {
    /// Integrator steps (0 when a step failed: the count is lost with the
    /// run).
    pub fn steps(&self) -> u64 {
        self.run.as_ref().map_or(0, |o| o.steps)
    }

    /// What the guard caught, for a diverged sample.
    pub fn divergence(&self) -> Option<Divergence> {
        self.run
            .as_ref()
            .ok()
            .and_then(|o| o.diverged())
            .map(|(d, _)| d)
    }
}

/// A Monte Carlo study: `draw` makes a sample's parameters from its
/// random stream, `build` its simulation (any vehicle, plan, integrator,
/// guard), and `settle` the metric whose staying below 1 for `hold`
/// seconds counts as converged. Run one sample with [`Study::sample`],
/// many (on threads, with the `parallel` feature) with [`Study::run`].
pub struct Study<D, S, G, M> {
    /// Seed of every sample's stream.
    pub seed: u64,
    /// How long the settle metric must stay below 1, s.
    pub hold: f64,
    /// Draws a sample's parameters.
    pub draw: S,
    /// Builds a sample's simulation from them.
    pub build: G,
    /// The settle metric at `(t, body state, command)`.
    pub settle: M,
    _draw: PhantomData<fn() -> D>,
}

impl<D, S, G, M> Study<D, S, G, M> {
    /// A study of `seed` with a hold of `hold` seconds.
    pub fn new<B, I>(seed: u64, hold: f64, draw: S, build: G, settle: M) -> Self
    where
        B: Backend,
        I: Method<B>,
        S: Fn(&mut Stream) -> D,
        G: Fn(&D) -> Result<SimulationBuilder<'static, B, I>, Error>,
        M: Fn(f64, &RigidBodyState<B>, &ModeOutput<B>) -> f64,
    {
        Self {
            seed,
            hold,
            draw,
            build,
            settle,
            _draw: PhantomData,
        }
    }

    /// Flies sample `index`. A failed step is the sample's result
    /// ([`Status::Error`]); any other error (a setting `build` got wrong,
    /// a full disk) is the study's and returned.
    pub fn sample<B, I>(&self, index: u64) -> Result<Trial<D>, Error>
    where
        B: Backend,
        I: Method<B>,
        S: Fn(&mut Stream) -> D,
        G: Fn(&D) -> Result<SimulationBuilder<'static, B, I>, Error>,
        M: Fn(f64, &RigidBodyState<B>, &ModeOutput<B>) -> f64,
    {
        self.fly(index, None)?
            .ok_or_else(|| Error::setting("study", format!("sample {index} was interrupted")))
    }

    /// [`Study::sample`], or `None` when `cancel` is set before it ends.
    fn fly<B, I>(&self, index: u64, cancel: Option<&AtomicBool>) -> Result<Option<Trial<D>>, Error>
    where
        B: Backend,
        I: Method<B>,
        S: Fn(&mut Stream) -> D,
        G: Fn(&D) -> Result<SimulationBuilder<'static, B, I>, Error>,
        M: Fn(f64, &RigidBodyState<B>, &ModeOutput<B>) -> f64,
    {
        if cancel.is_some_and(|c| c.load(Ordering::Relaxed)) {
            return Ok(None);
        }
        let draw = (self.draw)(&mut stream(self.seed, index));
        let mut settled = Settled::new(self.hold);
        let mut peaks = Peaks::default();
        let run = {
            let settle = &self.settle;
            let settled = &mut settled;
            let stop = Box::new(move |t: f64, st: &RigidBodyState<B>, out: &ModeOutput<B>| {
                settled.check(t, settle(t, st, out))
            });
            // The peaks come from the samples; the run's own per-step
            // extrema would cost a controller evaluation per step.
            let opts = RunOptions {
                record: false,
                sink: Some(&mut peaks),
                extrema: false,
                cancel,
                ..Default::default()
            };
            (self.build)(&draw)?
                .stop_when(stop)
                .build()?
                .run(opts)
                .map_err(Error::Run)
        };
        let status = match &run {
            Ok(out) => match out.termination {
                Termination::Diverged { .. } => Status::Diverged,
                Termination::StoppedBy { .. } => Status::Converged,
                Termination::Completed => Status::Deadline,
                Termination::Interrupted { .. } => return Ok(None),
                // A way of ending this study does not know is no success.
                _ => Status::Error,
            },
            // A state gone non-finite is the sample's failure, whether the
            // step noticed it or the law did at a record time in between.
            Err(Error::Run(SimError::Step { .. } | SimError::Control { .. })) => Status::Error,
            Err(e) => return Err(e.clone()),
        };
        Ok(Some(Trial {
            index,
            draw,
            status,
            t_settled: (status == Status::Converged)
                .then(|| settled.entered())
                .flatten(),
            max_thrust: peaks.thrust,
            max_rotor: peaks.rotor,
            run,
        }))
    }

    /// Flies the samples `indices` on `threads` threads (default: one per
    /// core; one without the `parallel` feature), calling `progress` with
    /// the count done now and then; the trials come back in the order of
    /// `indices`, the same whatever the thread count.
    pub fn run<B, I>(
        &self,
        indices: &[u64],
        threads: Option<usize>,
        progress: Option<&(dyn Fn(u64) + Sync)>,
    ) -> Result<Vec<Trial<D>>, Error>
    where
        B: Backend,
        I: Method<B>,
        D: Send,
        S: Fn(&mut Stream) -> D + Sync,
        G: Fn(&D) -> Result<SimulationBuilder<'static, B, I>, Error> + Sync,
        M: Fn(f64, &RigidBodyState<B>, &ModeOutput<B>) -> f64 + Sync,
    {
        self.run_until_cancelled(indices, threads, progress, &AtomicBool::new(false))
    }

    /// [`Study::run`] that stops early once `cancel` is set (by a signal
    /// handler, a UI): samples not started are skipped and the ones in
    /// flight stop at their current step and are dropped. The trials that
    /// finished come back in index order; fewer than `indices` says the
    /// study was cancelled.
    pub fn run_until_cancelled<B, I>(
        &self,
        indices: &[u64],
        threads: Option<usize>,
        progress: Option<&(dyn Fn(u64) + Sync)>,
        cancel: &AtomicBool,
    ) -> Result<Vec<Trial<D>>, Error>
    where
        B: Backend,
        I: Method<B>,
        D: Send,
        S: Fn(&mut Stream) -> D + Sync,
        G: Fn(&D) -> Result<SimulationBuilder<'static, B, I>, Error> + Sync,
        M: Fn(f64, &RigidBodyState<B>, &ModeOutput<B>) -> f64 + Sync,
    {
        let done = std::sync::atomic::AtomicU64::new(0);
        let one = |&i: &u64| {
            let r = self.fly(i, Some(cancel));
            let n = done.fetch_add(1, Ordering::Relaxed) + 1;
            if let Some(p) = progress
                && (n.is_multiple_of(16) || n == indices.len() as u64)
            {
                p(n);
            }
            r
        };
        let trials = parallel_map(indices, threads, one)?;
        Ok(trials.into_iter().flatten().collect())
    }
}

/// `f` over `indices`, in order: on a pool of `threads` threads (all
/// cores for `None`) with the `parallel` feature, in turn without it. One
/// body for both, so that the default build's tests cover it.
pub(crate) fn parallel_map<T: Send>(
    indices: &[u64],
    threads: Option<usize>,
    f: impl Fn(&u64) -> Result<T, Error> + Sync + Send,
) -> Result<Vec<T>, Error> {
    #[cfg(feature = "parallel")]
    {
        use rayon::prelude::*;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads.unwrap_or(0))
            .build()
            .map_err(|e| SimError::Setting {
                field: "threads",
                message: format!("{threads:?}: {e}"),
            })?;
        pool.install(|| indices.par_iter().map(f).collect())
    }
    #[cfg(not(feature = "parallel"))]
    {
        let _ = threads;
        indices.iter().map(f).collect()
    }
}

/// Largest commanded and rotor thrust over the samples a run takes.
#[derive(Default)]
struct Peaks {
    thrust: f64,
    rotor: f64,
}

impl Sink for Peaks {
    fn begin(&mut self, _: &[&'static str]) -> Result<(), OutputError> {
        Ok(())
    }
    fn switch(&mut self, _: &SwitchRecord, _: &str) -> Result<(), OutputError> {
        Ok(())
    }
    fn sample(&mut self, s: &Sample) -> Result<(), OutputError> {
        self.thrust = self.thrust.max(s.thrust.abs());
        self.rotor = s.rotors.iter().fold(self.rotor, |a, r| a.max(r.abs()));
        Ok(())
    }
}

/// Percentile by the nearest-rank method over sorted values (NaN for
/// none).
pub fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let rank = ((p / 100.0) * sorted.len() as f64).ceil().max(1.0) as usize;
    sorted[rank.min(sorted.len()) - 1]
}

/// Times to settle: median, 95th and 99th percentiles and the worst, s
/// (nearest rank; NaN without converged samples).
#[derive(Copy, Clone, Debug, PartialEq, serde::Serialize)]
pub struct Percentiles {
    /// 50th percentile.
    pub median: f64,
    /// 95th percentile.
    pub p95: f64,
    /// 99th percentile.
    pub p99: f64,
    /// The largest.
    pub worst: f64,
}

/// Counts by status and the times to settle of a set of samples.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Summary {
    /// Samples.
    pub samples: usize,
    /// [`Status::Converged`].
    pub converged: usize,
    /// [`Status::Deadline`].
    pub deadline: usize,
    /// [`Status::Diverged`].
    pub diverged: usize,
    /// [`Status::Error`].
    pub errors: usize,
    /// `converged / samples`.
    pub converged_fraction: f64,
    /// Times to settle of the converged samples.
    pub t_converge: Percentiles,
    /// Integrator steps, summed.
    pub integrator_steps: u64,
}

impl Summary {
    /// The summary of `trials`.
    pub fn of<D>(trials: &[Trial<D>]) -> Self {
        Self::from_rows(
            trials
                .iter()
                .map(|t| (t.status, t.t_settled.unwrap_or(f64::NAN), t.steps())),
        )
    }

    /// The summary of `(status, time to settle, steps)` rows.
    pub fn from_rows(rows: impl IntoIterator<Item = (Status, f64, u64)>) -> Self {
        let mut counts = [0usize; 4];
        let (mut t, mut steps) = (Vec::new(), 0u64);
        for (status, ts, n) in rows {
            counts[status as usize] += 1;
            if status == Status::Converged {
                t.push(ts);
            }
            steps += n;
        }
        t.sort_by(f64::total_cmp);
        let samples = counts.iter().sum::<usize>();
        Self {
            samples,
            converged: counts[Status::Converged as usize],
            deadline: counts[Status::Deadline as usize],
            diverged: counts[Status::Diverged as usize],
            errors: counts[Status::Error as usize],
            converged_fraction: counts[Status::Converged as usize] as f64 / samples.max(1) as f64,
            t_converge: Percentiles {
                median: percentile(&t, 50.0),
                p95: percentile(&t, 95.0),
                p99: percentile(&t, 99.0),
                worst: t.last().copied().unwrap_or(f64::NAN),
            },
            integrator_steps: steps,
        }
    }
}

#[cfg(test)]
mod tests;
