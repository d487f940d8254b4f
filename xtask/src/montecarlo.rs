//! `cargo xtask montecarlo`: the paper's "almost global" attractivity
//! (Propositions 2 and 3) checked over many random initial conditions.
//!
//! # Sampling
//! Each sample's random numbers come from a ChaCha8 stream keyed by the
//! seed, with the sample index as the stream number: sample `i` is the same
//! whatever the thread count, the shard or the order of evaluation.
//! - Attitude: a uniform unit quaternion by Shoemake's method (K. Shoemake,
//!   "Uniform random rotations", Graphics Gems III, 1992): with
//!   `u1, u2, u3 ~ U[0, 1)`, `q = (√(1−u1) sin 2πu2, √(1−u1) cos 2πu2,
//!   √u1 sin 2πu3, √u1 cos 2πu3)`. Its rotation angle θ has density
//!   `(1 − cos θ)/π` on `[0, π]` (a unit test checks this with a
//!   Kolmogorov–Smirnov test, and that the test rejects a naive sampler).
//! - Ω(0), e_x(0), v(0): uniform in a ball (rejection from the cube).
//!
//! # Convergence
//! A sample converges when Ψ < `psi_tol` (and, in position mode,
//! ‖e_x‖ < `x_tol`) holds for a hold time (`--hold`, 0.5 s by default)
//! before the deadline; its time to converge is the start of that stretch,
//! interpolated linearly inside the step where the worse of Ψ/psi_tol and
//! ‖e_x‖/x_tol crosses 1. The run stops when the hold is over
//! (`SimulationBuilder::stop_when`), so the tail is not integrated.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use controllers::ModeOutput;
use dynamics::RigidBodyState;
use lie::{Backend, GlamF64, Real};
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::{Rng, SeedableRng};
use rayon::prelude::*;
use scenarios::scene::{AttitudeRef, DisturbanceSpec, Mode, PositionRef, SegmentSpec, ThrustSpec};
use scenarios::{
    Divergence, DivergenceGuard, RunOptions, Sample, Scene, Simulation, SwitchRecord, Termination,
    builtin, output,
};

/// Which experiment.
#[derive(Copy, Clone, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Experiment {
    /// The pinned vehicle in attitude mode, R_d = I, Ω_d = 0, Δ_R.
    Attitude,
    /// The free quadrotor in position mode to hover at 0, b1d = e1, Δ_x, Δ_R.
    Position,
}

impl Experiment {
    fn name(self) -> &'static str {
        match self {
            Experiment::Attitude => "attitude",
            Experiment::Position => "position",
        }
    }
}

/// Options of `cargo xtask montecarlo`.
#[derive(clap::Args, Debug)]
#[command(args_conflicts_with_subcommands = true)]
pub struct McArgs {
    #[command(subcommand)]
    pub action: Option<McAction>,
    /// attitude or position.
    #[arg(long, value_enum, default_value = "position")]
    pub experiment: Experiment,
    /// Number of samples (indices 0 … N−1).
    #[arg(long, default_value_t = 1000)]
    pub samples: u64,
    /// Seed of every sample's random stream.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Run only the samples i with i mod N = K, as `K/N`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<String>,
    /// Output directory (default `target/montecarlo/<experiment>`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Run only this sample and print it (the slowest samples' replays).
    #[arg(long)]
    pub index: Option<u64>,
    /// Radius of the ball Ω(0) is drawn from, rad/s.
    #[arg(long, default_value_t = 2.0)]
    pub omega_max: f64,
    /// Radius of the ball e_x(0) is drawn from, m (position).
    #[arg(long, default_value_t = 2.0)]
    pub x_max: f64,
    /// Radius of the ball v(0) is drawn from, m/s (position).
    #[arg(long, default_value_t = 1.0)]
    pub v_max: f64,
    /// Ψ below which a sample counts as converged.
    #[arg(long, default_value_t = 1e-3)]
    pub psi_tol: f64,
    /// ‖e_x‖ below which a sample counts as converged (position), m.
    #[arg(long, default_value_t = 1e-2)]
    pub x_tol: f64,
    /// Simulated time a sample has to converge, s.
    #[arg(long, default_value_t = 60.0)]
    pub deadline: f64,
    /// How long the tolerances must hold before a sample counts as
    /// converged, s.
    #[arg(long, default_value_t = 0.5)]
    pub hold: f64,
    /// Integrator (see `cargo xtask run --help`). The default, dopri at
    /// 1e-6, classifies every sample of a 200-sample check as dopri at 1e-9
    /// does, with times to converge within 0.05 s, at a quarter of its
    /// cost; rk4 at 5e-3 misclassified 2 of 200 and at 2e-3 cost more
    /// (the position law's near-singular passages need small steps only
    /// briefly, which an adaptive step pays for only there).
    #[arg(long, default_value = "dopri")]
    pub integrator: String,
    /// Step, s (dopri: longest call).
    #[arg(long, default_value_t = 0.02)]
    pub dt: f64,
    /// dopri tolerance.
    #[arg(long, default_value_t = 1e-6)]
    pub tol: f64,
}

/// `merge` and `near-pi`.
#[derive(clap::Subcommand, Debug)]
pub enum McAction {
    /// Combine shard directories into the files one run writes.
    Merge {
        /// Shard directories (each written with --shard K/N).
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Output directory (default: `target/montecarlo/<experiment>`).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Time to converge from R(0) = exp((π − δ) â), δ = 10⁻ᵏ, against the
    /// unstable eigenvalue at the π equilibrium.
    NearPi {
        /// Output directory (default target/montecarlo).
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

/// Everything that defines a sample's result besides its index; written
/// into `run.json` so that `merge` refuses shards of different runs.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Setup {
    pub experiment: String,
    pub samples: u64,
    pub seed: u64,
    pub omega_max: f64,
    pub x_max: f64,
    pub v_max: f64,
    pub psi_tol: f64,
    pub x_tol: f64,
    pub deadline: f64,
    pub hold: f64,
    pub integrator: String,
    pub dt: f64,
    pub tol: f64,
}

impl Setup {
    fn from_args(a: &McArgs) -> Self {
        Self {
            experiment: a.experiment.name().into(),
            samples: a.samples,
            seed: a.seed,
            omega_max: a.omega_max,
            x_max: a.x_max,
            v_max: a.v_max,
            psi_tol: a.psi_tol,
            x_tol: a.x_tol,
            deadline: a.deadline,
            hold: a.hold,
            integrator: a.integrator.clone(),
            dt: a.dt,
            tol: a.tol,
        }
    }

    fn is_position(&self) -> bool {
        self.experiment == "position"
    }

    /// The flags that reproduce this setup on the command line.
    fn flags(&self) -> String {
        let mut f = format!("--experiment {} --seed {}", self.experiment, self.seed);
        let d = Setup::from_args(&default_args());
        let mut opt = |name: &str, v: f64, dv: f64| {
            if v != dv {
                let _ = write!(f, " --{name} {v}");
            }
        };
        opt("omega-max", self.omega_max, d.omega_max);
        opt("x-max", self.x_max, d.x_max);
        opt("v-max", self.v_max, d.v_max);
        opt("psi-tol", self.psi_tol, d.psi_tol);
        opt("x-tol", self.x_tol, d.x_tol);
        opt("deadline", self.deadline, d.deadline);
        opt("hold", self.hold, d.hold);
        opt("dt", self.dt, d.dt);
        if self.integrator != d.integrator {
            let _ = write!(f, " --integrator {}", self.integrator);
            if self.integrator == "dopri" {
                let _ = write!(f, " --tol {}", self.tol);
            }
        }
        f
    }
}

fn default_args() -> McArgs {
    use clap::Parser;
    #[derive(clap::Parser)]
    struct P {
        #[command(flatten)]
        a: McArgs,
    }
    P::parse_from(["montecarlo"]).a
}

/// A sample's random initial condition.
#[derive(Clone, Debug, PartialEq)]
pub struct Initial {
    /// Unit quaternion (w, x, y, z), w ≥ 0.
    pub q: [f64; 4],
    /// Body angular velocity, rad/s.
    pub omega: [f64; 3],
    /// Position (= e_x(0): x_d = 0), m.
    pub x: [f64; 3],
    /// Velocity, m/s.
    pub v: [f64; 3],
}

impl Initial {
    /// Rotation angle from R_d = I, in [0, π].
    pub fn angle(&self) -> f64 {
        let s = (self.q[1].powi(2) + self.q[2].powi(2) + self.q[3].powi(2)).sqrt();
        2.0 * s.atan2(self.q[0])
    }
    /// Rotation axis (e1 for the identity).
    pub fn axis(&self) -> [f64; 3] {
        let s = (self.q[1].powi(2) + self.q[2].powi(2) + self.q[3].powi(2)).sqrt();
        if s == 0.0 {
            [1.0, 0.0, 0.0]
        } else {
            [self.q[1] / s, self.q[2] / s, self.q[3] / s]
        }
    }
    /// Rotation vector (axis × angle), the scene format's attitude.
    pub fn rotation_vector(&self) -> [f64; 3] {
        let (a, th) = (self.axis(), self.angle());
        [a[0] * th, a[1] * th, a[2] * th]
    }
}

fn uniform(rng: &mut ChaCha8Rng) -> f64 {
    // 53 random bits: [0, 1) on the f64 grid.
    (rng.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A uniform random unit quaternion (Shoemake), `w ≥ 0`.
pub fn shoemake(rng: &mut ChaCha8Rng) -> [f64; 4] {
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
pub fn in_ball(rng: &mut ChaCha8Rng, r: f64) -> [f64; 3] {
    loop {
        let p = [
            2.0 * uniform(rng) - 1.0,
            2.0 * uniform(rng) - 1.0,
            2.0 * uniform(rng) - 1.0,
        ];
        if p.iter().map(|c| c * c).sum::<f64>() <= 1.0 {
            return p.map(|c| c * r);
        }
    }
}

/// Sample `index`'s random stream.
pub fn stream(seed: u64, index: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_stream(index);
    rng
}

/// Sample `index`'s initial condition: a function of (seed, index) alone.
pub fn initial(setup: &Setup, index: u64) -> Initial {
    let mut rng = stream(setup.seed, index);
    let q = shoemake(&mut rng);
    let omega = in_ball(&mut rng, setup.omega_max);
    let (x, v) = if setup.is_position() {
        (
            in_ball(&mut rng, setup.x_max),
            in_ball(&mut rng, setup.v_max),
        )
    } else {
        ([0.0; 3], [0.0; 3])
    };
    Initial { q, omega, x, v }
}

/// The experiment's scene with a sample's initial condition: what
/// `cargo xtask run` replays.
pub fn scene(setup: &Setup, init: &Initial) -> Scene {
    let mut s = if setup.is_position() {
        let mut s = builtin::hover_disturbed();
        s.plan = vec![SegmentSpec {
            mode: Mode::Position,
            until: None,
            until_psi: None,
            attitude: None,
            position: Some(PositionRef::Hold {
                x: [0.0; 3],
                b1d: [1.0, 0.0, 0.0],
            }),
            thrust: ThrustSpec::Hover,
        }];
        s
    } else {
        let mut s = builtin::large_attitude_error();
        s.disturbance = Some(DisturbanceSpec::paper());
        s.plan = vec![SegmentSpec {
            mode: Mode::Attitude,
            until: None,
            until_psi: None,
            attitude: Some(AttitudeRef::Hold { rotation: [0.0; 3] }),
            position: None,
            thrust: ThrustSpec::Hover,
        }];
        s
    };
    s.name = format!("montecarlo-{}", setup.experiment);
    s.description = format!(
        "A Monte Carlo sample of the {} experiment (cargo xtask montecarlo {}).",
        setup.experiment,
        setup.flags()
    );
    s.backend = scenarios::scene::BackendKind::Glam;
    s.initial.rotation = init.rotation_vector();
    s.initial.omega = init.omega;
    s.initial.x = init.x;
    s.initial.v = init.v;
    s.integrator.kind = setup.integrator.clone();
    s.integrator.dt = setup.dt;
    s.integrator.tol = setup.tol;
    s.duration = setup.deadline;
    // Peaks (thrust, rotor thrust) are taken over this grid; dopri's
    // calls end on it.
    s.record.sample = 0.02;
    s
}

/// |Ω| above which a sample counts as diverged, rad/s (100× the default
/// initial ball): the position law's computed attitude is singular where
/// b3c ∥ b1d, and a trajectory that passes near it spins up without bound.
pub const DIVERGED_OMEGA: f64 = 200.0;
/// ‖e_x‖ above which a sample counts as diverged, m.
pub const DIVERGED_X: f64 = 100.0;
/// ‖M‖ of the command above which a sample counts as diverged, N m: 40×
/// the largest moment any converging sample of a 10 000-sample run
/// commanded (rotor peaks to 2.4e4 N on the 0.02 s grid, ≈ 7.6e3 N m),
/// and ~10⁵× what the paper's rotors deliver. Without it, a diverging
/// sample spends ~4·10⁵ adaptive steps before |Ω| passes its bound.
pub const DIVERGED_MOMENT: f64 = 3e5;

/// Substeps one dopri call (one 0.02 s record interval) may take: converging
/// samples take a few; a blow-up near the computed attitude's singularity
/// took 4·10⁶ in one call before the cap.
pub const MAX_SUBSTEPS: u32 = 20_000;

/// How a sample ended.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Status {
    /// The tolerances held for the hold time before the deadline.
    Converged,
    /// The deadline came first.
    Deadline,
    /// |Ω|, ‖e_x‖ or ‖M‖ passed [`DIVERGED_OMEGA`] / [`DIVERGED_X`] /
    /// [`DIVERGED_MOMENT`], or a dopri call needed more than
    /// [`MAX_SUBSTEPS`].
    Diverged,
    /// The integrator stopped (a non-finite state at this step size).
    Error,
}

impl Status {
    fn name(self) -> &'static str {
        match self {
            Status::Converged => "converged",
            Status::Deadline => "deadline",
            Status::Diverged => "diverged",
            Status::Error => "error",
        }
    }
    fn parse(s: &str) -> Option<Self> {
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

/// One sample's result (a row of `samples.csv`).
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    pub index: u64,
    pub angle: f64,
    pub axis: [f64; 3],
    pub omega0: f64,
    pub ex0: f64,
    pub converged: bool,
    /// Time to converge, s (NaN when not converged).
    pub t_converge: f64,
    pub final_psi: f64,
    pub final_ex: f64,
    pub max_thrust: f64,
    pub max_rotor: f64,
    /// Integrator steps (0 when the integrator stopped the sample: the
    /// count is lost with the run).
    pub steps: u64,
    pub status: Status,
}

/// The header of `samples.csv`.
pub const SAMPLES_HEADER: &str = "index,angle,axis1,axis2,axis3,omega0,ex0,converged,t_converge,final_psi,final_ex,max_thrust,max_rotor,steps,status";

impl Outcome {
    fn csv(&self) -> String {
        format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}",
            self.index,
            self.angle,
            self.axis[0],
            self.axis[1],
            self.axis[2],
            self.omega0,
            self.ex0,
            u8::from(self.converged),
            self.t_converge,
            self.final_psi,
            self.final_ex,
            self.max_thrust,
            self.max_rotor,
            self.steps,
            self.status.name()
        )
    }

    fn parse(line: &str) -> Result<Self, String> {
        let f: Vec<&str> = line.split(',').collect();
        if f.len() != 15 {
            return Err(format!("{} fields, expected 15", f.len()));
        }
        let n = |k: usize| -> Result<f64, String> {
            f[k].parse::<f64>()
                .map_err(|e| format!("field {k} `{}`: {e}", f[k]))
        };
        let u = |k: usize| -> Result<u64, String> {
            f[k].parse::<u64>()
                .map_err(|e| format!("field {k} `{}`: {e}", f[k]))
        };
        Ok(Self {
            index: u(0)?,
            angle: n(1)?,
            axis: [n(2)?, n(3)?, n(4)?],
            omega0: n(5)?,
            ex0: n(6)?,
            converged: u(7)? == 1,
            t_converge: n(8)?,
            final_psi: n(9)?,
            final_ex: n(10)?,
            max_thrust: n(11)?,
            max_rotor: n(12)?,
            steps: u(13)?,
            status: Status::parse(f[14]).ok_or_else(|| format!("status `{}`", f[14]))?,
        })
    }
}

/// Largest commanded and rotor thrust over the samples a run takes.
#[derive(Default)]
struct Peaks {
    thrust: f64,
    rotor: f64,
}

impl output::Sink for Peaks {
    fn begin(&mut self, _: &[&'static str]) -> Result<(), output::OutputError> {
        Ok(())
    }
    fn switch(&mut self, _: &SwitchRecord, _: &str) -> Result<(), output::OutputError> {
        Ok(())
    }
    fn sample(&mut self, s: &Sample) -> Result<(), output::OutputError> {
        self.thrust = self.thrust.max(s.thrust.abs());
        self.rotor = s.rotors.iter().fold(self.rotor, |a, r| a.max(r.abs()));
        Ok(())
    }
}

/// The convergence predicate with its hold: `m(t) = max(Ψ/psi_tol,
/// ‖e_x‖/x_tol) < 1` from `entered` on, for `hold` seconds. Calls at
/// earlier times than the latest (the stop's bisection inside the last
/// step) read the state without changing it.
struct Hold {
    hold: f64,
    entered: Option<f64>,
    last: Option<(f64, f64)>,
}

impl Hold {
    fn check(&mut self, t: f64, m: f64) -> bool {
        let inside = m < 1.0;
        if let Some((tl, _)) = self.last
            && t <= tl
        {
            return inside && self.entered.is_some_and(|e| t - e >= self.hold);
        }
        if inside {
            if self.entered.is_none() {
                // Linear interpolation of m inside the step for the
                // crossing of 1.
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
}

/// Runs one sample.
pub fn run_sample(setup: &Setup, index: u64) -> Result<Outcome, String> {
    type B = GlamF64;
    let init = initial(setup, index);
    let sc = scene(setup, &init);
    let vehicle = scenarios::build_vehicle::<B>(&sc).map_err(|e| e.to_string())?;
    let plan = scenarios::plan::<B>(&sc, vehicle.as_ref());
    let kind: integrators::IntegratorKind = setup.integrator.parse().map_err(|e| format!("{e}"))?;
    let stepper =
        integrators::Stepper::<B, 6>::new(kind, integrators::StepperConfig { tol: setup.tol });
    let body = {
        let mut b = RigidBodyState::<B>::at_rest();
        let r = scenarios::reference::rotation_f64(sc.initial.rotation);
        b.r = lie::ops::from_elems::<B>(r);
        b.omega = B::vec3(init.omega[0], init.omega[1], init.omega[2]);
        b.x = B::vec3(init.x[0], init.x[1], init.x[2]);
        b.v = B::vec3(init.v[0], init.v[1], init.v[2]);
        b
    };
    let (psi_tol, x_tol, position) = (setup.psi_tol, setup.x_tol, setup.is_position());
    let mut hold = Hold {
        hold: setup.hold,
        entered: None,
        last: None,
    };
    let entered = std::cell::Cell::new(None);
    let stop = Box::new(
        |t: f64, st: &RigidBodyState<B>, out: &ModeOutput<B>| -> bool {
            let mut m = out.psi.to_f64_lossless() / psi_tol;
            if position {
                let x = B::vec3_to_array(st.x);
                m = m.max((x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt() / x_tol);
            }
            let done = hold.check(t, m);
            entered.set(hold.entered);
            done
        },
    );
    // A capped dopri: a call that needs more than MAX_SUBSTEPS substeps is
    // a solution blowing up between two checks of the state limits.
    let guard = DivergenceGuard {
        omega: Some(DIVERGED_OMEGA),
        position_error: Some(DIVERGED_X),
        moment: None,
        substeps: (kind == integrators::IntegratorKind::Dopri).then_some(MAX_SUBSTEPS),
    };
    let mut b = Simulation::<B, 6>::builder(vehicle)
        .initial(body)
        .dt(setup.dt)
        .duration(setup.deadline)
        .record_every(sc.record.sample)
        .stop_when(stop)
        .guard(guard);
    for seg in plan {
        b = b.segment(seg);
    }
    let mut peaks = Peaks::default();
    // The peaks come from the samples; the run's own per-step extrema
    // would cost a controller evaluation per step for nothing.
    let opts = RunOptions {
        record: false,
        sink: Some(&mut peaks),
        extrema: false,
        ..Default::default()
    };
    let result = b
        .integrator(stepper)
        .build()
        .map_err(|e| e.to_string())?
        .run(opts);
    let norm = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
    // A run cut off inside an integrator call (the substep cap) or by a
    // step that produced a non-finite state has no final figures worth
    // keeping: the row says NaN and 0 steps.
    let cut = |status| Outcome {
        index,
        angle: init.angle(),
        axis: init.axis(),
        omega0: norm(init.omega),
        ex0: norm(init.x),
        converged: false,
        t_converge: f64::NAN,
        final_psi: f64::NAN,
        final_ex: f64::NAN,
        max_thrust: peaks.thrust,
        max_rotor: peaks.rotor,
        steps: 0,
        status,
    };
    let out = match result {
        Ok(out) => out,
        // Any failed step (a non-finite state, an LGVI without a solution
        // at this step) is the sample's own result; the study goes on.
        Err(scenarios::SimError::Step { .. }) => return Ok(cut(Status::Error)),
        Err(e) => return Err(format!("sample {index}: {e}")),
    };
    let status = match out.termination {
        Termination::Diverged {
            what: Divergence::Substeps(_),
            ..
        } => return Ok(cut(Status::Diverged)),
        Termination::Diverged { .. } => Status::Diverged,
        Termination::StoppedBy { .. } => Status::Converged,
        Termination::Completed => Status::Deadline,
        Termination::Interrupted { t } => {
            return Err(format!("sample {index}: interrupted at t = {t}"));
        }
    };
    let converged = status == Status::Converged;
    Ok(Outcome {
        index,
        angle: init.angle(),
        axis: init.axis(),
        omega0: norm(init.omega),
        ex0: norm(init.x),
        converged,
        t_converge: if converged {
            entered.get().unwrap_or(f64::NAN)
        } else {
            f64::NAN
        },
        final_psi: out.last.psi,
        final_ex: out.last.ex,
        max_thrust: peaks.thrust,
        max_rotor: peaks.rotor,
        steps: out.steps,
        status,
    })
}

/// `K/N`.
fn parse_shard(s: &str) -> Result<(u64, u64), String> {
    let bad = || format!("--shard {s}: expected K/N with 0 ≤ K < N");
    let (k, n) = s.split_once('/').ok_or_else(bad)?;
    let (k, n) = (
        k.trim().parse::<u64>().map_err(|_| bad())?,
        n.trim().parse::<u64>().map_err(|_| bad())?,
    );
    if n == 0 || k >= n {
        return Err(bad());
    }
    Ok((k, n))
}

fn default_out(experiment: &str) -> PathBuf {
    crate::workspace_root()
        .join("target/montecarlo")
        .join(experiment)
}

/// Runs the indices of a shard on `threads` threads; results in index
/// order.
pub fn run_indices(
    setup: &Setup,
    indices: &[u64],
    threads: usize,
    progress: Option<&indicatif::ProgressBar>,
) -> Result<Vec<Outcome>, String> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| format!("--threads {threads}: {e}"))?;
    let done = AtomicU64::new(0);
    pool.install(|| {
        indices
            .par_iter()
            .map(|&i| {
                let r = run_sample(setup, i);
                let n = done.fetch_add(1, Ordering::Relaxed) + 1;
                if let Some(p) = progress
                    && (n.is_multiple_of(16) || n == indices.len() as u64)
                {
                    p.set_position(n);
                }
                r
            })
            .collect()
    })
}

fn write_samples(dir: &Path, rows: &[Outcome]) -> Result<(), String> {
    let mut text = String::with_capacity(rows.len() * 200);
    text.push_str(SAMPLES_HEADER);
    text.push('\n');
    for r in rows {
        text.push_str(&r.csv());
        text.push('\n');
    }
    write_atomic(&dir.join("samples.csv"), text.as_bytes())
}

/// Writes `<path>.partial`, then renames it.
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    let mut tmp = path.as_os_str().to_os_string();
    tmp.push(".partial");
    std::fs::write(&tmp, bytes).map_err(|e| format!("{}: {e}", path.display()))?;
    std::fs::rename(&tmp, path).map_err(|e| format!("{}: {e}", path.display()))
}

fn read_samples(dir: &Path) -> Result<Vec<Outcome>, String> {
    let path = dir.join("samples.csv");
    let text = std::fs::read_to_string(&path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut lines = text.lines();
    if lines.next() != Some(SAMPLES_HEADER) {
        return Err(format!("{}: not a samples.csv (header)", path.display()));
    }
    lines
        .enumerate()
        .map(|(k, l)| Outcome::parse(l).map_err(|e| format!("{}:{}: {e}", path.display(), k + 2)))
        .collect()
}

/// Percentile by the nearest-rank method over sorted values.
fn percentile(sorted: &[f64], p: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let rank = ((p / 100.0) * sorted.len() as f64).ceil().max(1.0) as usize;
    sorted[rank.min(sorted.len()) - 1]
}

/// The summary of a complete run (all indices present).
pub fn summarize(setup: &Setup, rows: &[Outcome], wall: Option<f64>) -> serde_json::Value {
    let n = rows.len();
    let conv: Vec<&Outcome> = rows.iter().filter(|r| r.converged).collect();
    let mut t: Vec<f64> = conv.iter().map(|r| r.t_converge).collect();
    t.sort_by(f64::total_cmp);
    let steps: u64 = rows.iter().map(|r| r.steps).sum();
    let mut slow: Vec<&Outcome> = rows.iter().collect();
    // Not converged first, then by time to converge, slowest first.
    slow.sort_by(|a, b| {
        b.converged
            .cmp(&a.converged)
            .reverse()
            .then(b.t_converge.total_cmp(&a.t_converge))
            .then(a.index.cmp(&b.index))
    });
    let slowest: Vec<serde_json::Value> = slow
        .iter()
        .take(5)
        .map(|r| {
            serde_json::json!({
                "index": r.index, "converged": r.converged, "status": r.status.name(), "t_converge": r.t_converge,
                "angle_deg": r.angle.to_degrees(), "axis": r.axis, "omega0": r.omega0, "ex0": r.ex0,
                "command": format!("cargo xtask montecarlo {} --index {}", setup.flags(), r.index),
            })
        })
        .collect();
    let mut v = serde_json::json!({
        "setup": setup,
        "samples": n,
        "converged": conv.len(),
        "deadline": rows.iter().filter(|r| r.status == Status::Deadline).count(),
        "diverged": rows.iter().filter(|r| r.status == Status::Diverged).count(),
        "errors": rows.iter().filter(|r| r.status == Status::Error).count(),
        "converged_fraction": conv.len() as f64 / n.max(1) as f64,
        "t_converge": {
            "median": percentile(&t, 50.0),
            "p95": percentile(&t, 95.0),
            "p99": percentile(&t, 99.0),
            "worst": t.last().copied().unwrap_or(f64::NAN),
        },
        "largest_angle_deg": rows.iter().map(|r| r.angle).fold(0.0, f64::max).to_degrees(),
        "max_rotor_thrust": rows.iter().map(|r| r.max_rotor).fold(0.0, f64::max),
        "integrator_steps": steps,
        "slowest": slowest,
    });
    if let Some(w) = wall {
        v["wall_s"] = serde_json::json!(w);
        v["samples_per_s"] = serde_json::json!(n as f64 / w);
        v["ns_per_step"] = serde_json::json!(w * 1e9 / steps.max(1) as f64);
    }
    v
}

fn print_summary(s: &serde_json::Value) {
    let f = |p: &str| s.pointer(p).and_then(|v| v.as_f64()).unwrap_or(f64::NAN);
    println!(
        "{} samples, {} converged ({:.4} %); largest initial angle {:.3}°",
        s["samples"],
        s["converged"],
        100.0 * f("/converged_fraction"),
        f("/largest_angle_deg"),
    );
    println!(
        "not converged: {} at the deadline, {} diverged (|Ω| > {DIVERGED_OMEGA} rad/s, ‖e_x‖ > {DIVERGED_X} m or ‖M‖ > {DIVERGED_MOMENT:e} N m), {} integrator errors",
        s["deadline"], s["diverged"], s["errors"]
    );
    println!(
        "time to converge: median {:.3} s, 95th {:.3} s, 99th {:.3} s, worst {:.3} s",
        f("/t_converge/median"),
        f("/t_converge/p95"),
        f("/t_converge/p99"),
        f("/t_converge/worst")
    );
    if let Some(w) = s.get("wall_s").and_then(|v| v.as_f64()) {
        println!(
            "wall {w:.2} s: {:.0} samples/s, {:.0} ns per integrator step ({} steps)",
            f("/samples_per_s"),
            f("/ns_per_step"),
            s["integrator_steps"]
        );
    }
    println!("slowest samples:");
    for r in s["slowest"].as_array().into_iter().flatten() {
        println!(
            "  #{:<6} {}, t = {:.3} s, from {:.2}° (axis {:.3?}), |Ω(0)| = {:.3}, ‖e_x(0)‖ = {:.3}\n          {}",
            r["index"],
            r["status"].as_str().unwrap_or("?"),
            r["t_converge"].as_f64().unwrap_or(f64::NAN),
            r["angle_deg"].as_f64().unwrap_or(f64::NAN),
            r["axis"]
                .as_array()
                .map(|a| a.iter().filter_map(|x| x.as_f64()).collect::<Vec<_>>())
                .unwrap_or_default(),
            r["omega0"].as_f64().unwrap_or(f64::NAN),
            r["ex0"].as_f64().unwrap_or(f64::NAN),
            r["command"].as_str().unwrap_or(""),
        );
    }
}

/// Writes samples.csv, summary.json, the figures and the worst sample's
/// scene into `dir`, and prints the summary.
fn finish(dir: &Path, setup: &Setup, rows: &[Outcome], wall: Option<f64>) -> Result<(), String> {
    write_samples(dir, rows)?;
    let summary = summarize(setup, rows, wall);
    let text = serde_json::to_string_pretty(&summary).map_err(|e| e.to_string())?;
    write_atomic(&dir.join("summary.json"), text.as_bytes())?;
    crate::plot::montecarlo(dir, rows)?;
    print_summary(&summary);
    // The replay is the slowest *converged* sample: a diverging one would
    // make `cargo xtask run` (uncapped dopri) grind through its blow-up;
    // those are re-run with their `--index` command instead.
    let worst = rows
        .iter()
        .filter(|r| r.converged)
        .max_by(|a, b| a.t_converge.total_cmp(&b.t_converge));
    if let Some(r) = worst {
        let mut sc = scene(setup, &initial(setup, r.index));
        // Long enough to see the convergence and a little after.
        sc.duration = (r.t_converge + setup.hold + 2.0).min(setup.deadline);
        sc.name = format!("montecarlo-{}-slowest-{}", setup.experiment, r.index);
        let path = dir.join("worst.toml");
        write_atomic(&path, sc.to_toml().as_bytes())?;
        println!(
            "slowest converged sample (#{}, {:.3} s) as a scene: cargo xtask run {} --mcap worst.mcap",
            r.index,
            r.t_converge,
            path.display()
        );
    }
    println!(
        "wrote {}/{{samples.csv, summary.json, angle_vs_time.svg, time_histogram.svg, worst.toml}}",
        dir.display()
    );
    Ok(())
}

/// `cargo xtask montecarlo`.
pub fn montecarlo(a: McArgs) -> Result<(), String> {
    match &a.action {
        Some(McAction::Merge { dirs, out }) => return merge(dirs, out.as_deref()),
        Some(McAction::NearPi { out }) => return near_pi(out.as_deref()),
        None => {}
    }
    let setup = Setup::from_args(&a);
    let checks = [
        ("--omega-max", setup.omega_max, true),
        ("--x-max", setup.x_max, true),
        ("--v-max", setup.v_max, true),
        ("--psi-tol", setup.psi_tol, false),
        ("--x-tol", setup.x_tol, false),
        ("--deadline", setup.deadline, false),
        ("--hold", setup.hold, true),
        ("--dt", setup.dt, false),
        ("--tol", setup.tol, false),
    ];
    for (name, v, zero_ok) in checks {
        if !(v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0))) {
            return Err(format!(
                "{name} {v}: must be finite and {}",
                if zero_ok { "≥ 0" } else { "> 0" }
            ));
        }
    }
    if setup.psi_tol >= 2.0 {
        return Err(format!("--psi-tol {}: must be below 2", setup.psi_tol));
    }
    setup
        .integrator
        .parse::<integrators::IntegratorKind>()
        .map_err(|e| format!("--integrator: {e}"))?;
    if setup.samples == 0 {
        return Err("--samples 0: nothing to run".into());
    }
    if let Some(i) = a.index {
        if i >= setup.samples {
            return Err(format!(
                "--index {i}: the run has {} samples",
                setup.samples
            ));
        }
        let r = run_sample(&setup, i)?;
        println!("{SAMPLES_HEADER}\n{}", r.csv());
        let dir = a
            .out
            .clone()
            .unwrap_or_else(|| default_out(&setup.experiment));
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let mut sc = scene(&setup, &initial(&setup, i));
        sc.name = format!("montecarlo-{}-{i}", setup.experiment);
        let path = dir.join(format!("sample-{i}.toml"));
        write_atomic(&path, sc.to_toml().as_bytes())?;
        println!(
            "its scene: cargo xtask run {} --mcap sample-{i}.mcap",
            path.display()
        );
        return Ok(());
    }
    let (k, n) = a
        .shard
        .as_deref()
        .map(parse_shard)
        .transpose()?
        .unwrap_or((0, 1));
    let indices: Vec<u64> = (k..setup.samples).step_by(n as usize).collect();
    let threads = a
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    if threads == 0 {
        return Err("--threads 0: need at least one".into());
    }
    let dir = a.out.clone().unwrap_or_else(|| {
        let d = default_out(&setup.experiment);
        if n > 1 {
            d.join(format!("shard-{k}-of-{n}"))
        } else {
            d
        }
    });
    std::fs::create_dir_all(&dir).map_err(|e| format!("--out {}: {e}", dir.display()))?;
    let bar = indicatif::ProgressBar::new(indices.len() as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{bar:40} {pos}/{len} samples, {per_sec}, {elapsed}<{eta}",
        )
        .expect("static template"),
    );
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        bar.set_draw_target(indicatif::ProgressDrawTarget::hidden());
    }
    let started = std::time::Instant::now();
    let rows = run_indices(&setup, &indices, threads, Some(&bar))?;
    bar.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();
    if n > 1 {
        write_shard(&dir, &setup, (k, n), &rows)?;
        println!(
            "shard {k}/{n}: {} samples in {wall:.2} s → {}/samples.csv (merge with `cargo xtask montecarlo merge DIR...`)",
            rows.len(),
            dir.display()
        );
        return Ok(());
    }
    write_run_json(&dir, &setup, (k, n))?;
    finish(&dir, &setup, &rows, Some(wall))
}

fn write_run_json(dir: &Path, setup: &Setup, shard: (u64, u64)) -> Result<(), String> {
    let run = serde_json::json!({"setup": setup, "shard": [shard.0, shard.1]});
    write_atomic(
        &dir.join("run.json"),
        serde_json::to_string_pretty(&run)
            .map_err(|e| e.to_string())?
            .as_bytes(),
    )
}

/// A shard's directory: `run.json` (the setup and `[K, N]`) and its rows
/// of `samples.csv`, what `merge` reads.
fn write_shard(
    dir: &Path,
    setup: &Setup,
    shard: (u64, u64),
    rows: &[Outcome],
) -> Result<(), String> {
    write_run_json(dir, setup, shard)?;
    write_samples(dir, rows)
}

/// `cargo xtask montecarlo merge DIR...`.
pub fn merge(dirs: &[PathBuf], out: Option<&Path>) -> Result<(), String> {
    let mut setup: Option<Setup> = None;
    let mut shards = Vec::new();
    let mut rows = Vec::new();
    for d in dirs {
        let p = d.join("run.json");
        let text = std::fs::read_to_string(&p).map_err(|e| format!("{}: {e}", p.display()))?;
        let v: serde_json::Value =
            serde_json::from_str(&text).map_err(|e| format!("{}: {e}", p.display()))?;
        let s: Setup = serde_json::from_value(v["setup"].clone())
            .map_err(|e| format!("{}: setup: {e}", p.display()))?;
        let shard = (v["shard"][0].as_u64(), v["shard"][1].as_u64());
        match &setup {
            None => setup = Some(s),
            Some(s0) if *s0 != s => {
                return Err(format!(
                    "{}: a different run (setup differs from {}'s)",
                    d.display(),
                    dirs[0].display()
                ));
            }
            _ => {}
        }
        shards.push(shard);
        rows.extend(read_samples(d)?);
    }
    let setup = setup.ok_or("merge: no directories")?;
    rows.sort_by_key(|r| r.index);
    for (k, r) in rows.iter().enumerate() {
        if r.index != k as u64 {
            return Err(format!(
                "merge: sample {} is {} (shards {shards:?})",
                k,
                if r.index > k as u64 {
                    "missing"
                } else {
                    "duplicated"
                }
            ));
        }
    }
    if rows.len() as u64 != setup.samples {
        return Err(format!(
            "merge: {} of {} samples present (shards {shards:?})",
            rows.len(),
            setup.samples
        ));
    }
    let dir = out.map_or_else(|| default_out(&setup.experiment), Path::to_path_buf);
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    finish(&dir, &setup, &rows, None)
}

/// The unstable root λ₊ of `J s³ + k_Ω s² + (k_I − k_R) s − k_I c2`: the
/// attitude loop linearised at the rotation by π about a principal axis
/// with moment of inertia `J` (see [`near_pi`]).
pub fn lambda_plus(j: f64, k_r: f64, k_omega: f64, k_i: f64, c2: f64) -> f64 {
    let p = |s: f64| ((j * s + k_omega) * s + (k_i - k_r)) * s - k_i * c2;
    // p(0) = −k_I c2 ≤ 0 and p → +∞: bisection on a bracket, then it is
    // the only positive root when k_R > k_I (Descartes: one sign change).
    let (mut lo, mut hi) = (0.0, 1.0);
    while p(hi) < 0.0 {
        hi *= 2.0;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if p(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// `cargo xtask montecarlo near-pi`.
///
/// Near the rotation by π about a principal axis `a` (moment of inertia
/// `J`), with R_d = I, Ω_d = 0 and no disturbance, the motion stays a
/// rotation about `a` by an angle θ: `e_R = sin θ a`, `e_Ω = θ̇ a`, and the
/// law (eqn:aM) with (eqn:eI) reads
/// `J θ̈ = −k_R sin θ − k_Ω θ̇ − k_I e_I`, `ė_I = θ̇ + c2 sin θ`.
/// With θ = π − φ, sin θ ≈ φ, and Laplace transforms,
/// `J s² Φ = k_R Φ − k_Ω s Φ + k_I E`, `s E = (c2 − s) Φ`, so
/// `J s³ + k_Ω s² + (k_I − k_R) s − k_I c2 = 0`: a third-order system whose
/// one positive root λ₊ drives φ(t) ≈ c δ e^{λ₊ t} away from π. The time to
/// reach any fixed Ψ grows as `ln(1/δ)/λ₊` plus a constant, so the slope of
/// t_converge against ln(1/δ) is 1/λ₊.
pub fn near_pi(out: Option<&Path>) -> Result<(), String> {
    type B = GlamF64;
    let dir = out.map_or_else(
        || crate::workspace_root().join("target/montecarlo"),
        Path::to_path_buf,
    );
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let base = builtin::large_attitude_error();
    let g = &base.gains;
    let mut csv = String::from("axis,delta,t_converge\n");
    let mut report = Vec::new();
    for (axis_name, axis, jk) in [("e1", [1.0, 0.0, 0.0], 0), ("e3", [0.0, 0.0, 1.0], 2)] {
        let j = base.vehicle.inertia[jk];
        let lam = lambda_plus(j, g.k_r, g.k_omega, g.k_att_i, g.c2);
        let mut pts = Vec::new();
        for k in 1..=10 {
            let delta = 10f64.powi(-k);
            let mut sc = base.clone();
            sc.disturbance = None;
            sc.initial = Default::default();
            let th = std::f64::consts::PI - delta;
            sc.initial.rotation = axis.map(|c: f64| c * th);
            sc.integrator.kind = "rk4".into();
            sc.integrator.dt = 1e-3;
            sc.duration = 60.0;
            let vehicle = scenarios::build_vehicle::<B>(&sc).map_err(|e| e.to_string())?;
            let plan = scenarios::plan::<B>(&sc, vehicle.as_ref());
            let mut body = RigidBodyState::<B>::at_rest();
            body.r =
                lie::ops::from_elems::<B>(scenarios::reference::rotation_f64(sc.initial.rotation));
            let stop = Box::new(|_: f64, _: &RigidBodyState<B>, o: &ModeOutput<B>| {
                o.psi.to_f64_lossless() < 1e-3
            });
            let mut b = Simulation::<B, 6>::builder(vehicle)
                .initial(body)
                .dt(sc.integrator.dt)
                .duration(sc.duration)
                .record_every(0.0)
                .stop_when(stop);
            for seg in plan {
                b = b.segment(seg);
            }
            let out = b
                .build()
                .map_err(|e| e.to_string())?
                .run(RunOptions {
                    record: false,
                    ..Default::default()
                })
                .map_err(|e| e.to_string())?;
            let t = out.stopped_at().ok_or_else(|| {
                format!("near-pi {axis_name} δ = {delta:e}: Ψ never dropped below 1e-3 in 60 s")
            })?;
            let _ = writeln!(csv, "{axis_name},{delta:e},{t}");
            pts.push(((1.0 / delta).ln(), t));
        }
        // Least squares over k = 4 … 10.
        let fit: Vec<(f64, f64)> = pts[3..].to_vec();
        let n = fit.len() as f64;
        let (sx, sy) = fit.iter().fold((0.0, 0.0), |(a, b), p| (a + p.0, b + p.1));
        let (mx, my) = (sx / n, sy / n);
        let (sxy, sxx) = fit.iter().fold((0.0, 0.0), |(a, b), p| {
            (a + (p.0 - mx) * (p.1 - my), b + (p.0 - mx).powi(2))
        });
        let slope = sxy / sxx;
        report.push((axis_name, j, lam, slope, pts));
    }
    write_atomic(&dir.join("near-pi.csv"), csv.as_bytes())?;
    println!(
        "time to Ψ < 1e-3 from R(0) = exp((π − δ) â), attitude mode, paper gains, no disturbance:"
    );
    let mut worst = 0.0f64;
    for (axis, j, lam, slope, pts) in &report {
        let t: Vec<String> = pts.iter().map(|p| format!("{:.3}", p.1)).collect();
        println!(
            "  a = {axis} (J = {j}): t_converge for δ = 1e-1 … 1e-10: {}",
            t.join(", ")
        );
        let rel = (slope * lam - 1.0).abs();
        worst = worst.max(rel);
        println!(
            "  a = {axis}: slope of t_converge against ln(1/δ) over k = 4…10: {slope:.5} s; 1/λ₊ = {:.5} s (λ₊ = {lam:.5} /s); ratio {:.5}",
            1.0 / lam,
            slope * lam
        );
    }
    println!("wrote {}", dir.join("near-pi.csv").display());
    if worst > 0.01 {
        return Err(format!(
            "the slope and 1/λ₊ differ by {:.2} % (> 1 %)",
            100.0 * worst
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Kolmogorov–Smirnov statistic of `xs` against the CDF `f`.
    fn ks(mut xs: Vec<f64>, f: impl Fn(f64) -> f64) -> f64 {
        xs.sort_by(f64::total_cmp);
        let n = xs.len() as f64;
        xs.iter()
            .enumerate()
            .map(|(i, &x)| {
                let c = f(x);
                (c - i as f64 / n).abs().max(((i + 1) as f64 / n - c).abs())
            })
            .fold(0.0, f64::max)
    }

    /// The rotation angle of a uniform rotation has density (1 − cos θ)/π,
    /// CDF (θ − sin θ)/π. With n = 20 000 the KS critical value at
    /// α = 0.001 is 1.949/√n = 0.0138; a naive sampler (a uniform
    /// rotation vector in the ball of radius π) must fail the same test.
    #[test]
    fn shoemake_angles_pass_kolmogorov_smirnov() {
        let n = 20_000;
        let cdf = |th: f64| (th - th.sin()) / std::f64::consts::PI;
        let crit = 1.949 / (n as f64).sqrt();
        let angles: Vec<f64> = (0..n)
            .map(|i| {
                let mut r = stream(7, i);
                Initial {
                    q: shoemake(&mut r),
                    omega: [0.0; 3],
                    x: [0.0; 3],
                    v: [0.0; 3],
                }
                .angle()
            })
            .collect();
        let d = ks(angles, cdf);
        println!("KS D = {d:.5} (critical {crit:.5} at α = 0.001, n = {n})");
        assert!(d < crit, "D = {d}");
        let naive: Vec<f64> = (0..n)
            .map(|i| {
                let p = in_ball(&mut stream(7, i), std::f64::consts::PI);
                (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt()
            })
            .collect();
        let dn = ks(naive, cdf);
        println!("naive sampler: KS D = {dn:.5}");
        assert!(
            dn > 5.0 * crit,
            "the test must reject a naive sampler: D = {dn}"
        );
    }

    /// A sample's numbers depend on (seed, index) only.
    #[test]
    fn streams_are_keyed_by_seed_and_index() {
        let s = Setup::from_args(&default_args());
        assert_eq!(initial(&s, 5), initial(&s, 5));
        assert_ne!(initial(&s, 5), initial(&s, 6));
        let mut s2 = s.clone();
        s2.seed = 2;
        assert_ne!(initial(&s, 5), initial(&s2, 5));
        // Balls are respected.
        for i in 0..200 {
            let p = initial(&s, i);
            let n = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
            assert!(n(p.omega) <= s.omega_max && n(p.x) <= s.x_max && n(p.v) <= s.v_max);
            let q = p.q;
            assert!((q.iter().map(|c| c * c).sum::<f64>() - 1.0).abs() < 1e-15);
        }
    }

    /// λ₊ against the cubic's value and the hand root for J = 0.0820:
    /// p(2.14) < 0 < p(2.15).
    #[test]
    fn lambda_plus_is_the_positive_root() {
        let (j, kr, kw, ki, c2) = (0.082, 0.65, 0.11, 0.06, 0.8);
        let l = lambda_plus(j, kr, kw, ki, c2);
        let p = |s: f64| j * s * s * s + kw * s * s + (ki - kr) * s - ki * c2;
        assert!(p(l).abs() < 1e-12);
        assert!(
            p(2.14) < 0.0 && p(2.15) > 0.0 && (2.14..2.15).contains(&l),
            "{l}"
        );
    }

    /// Two shards merged give the single run's samples.csv byte for byte,
    /// and one thread or two give the same rows.
    #[test]
    fn shards_merged_equal_one_run() {
        let mut setup = Setup::from_args(&default_args());
        setup.samples = 6;
        setup.deadline = 2.0;
        let base = std::env::temp_dir().join(format!("gpid-mc-{}", std::process::id()));
        let d = |n: &str| {
            let p = base.join(n);
            std::fs::create_dir_all(&p).unwrap();
            p
        };
        let all: Vec<u64> = (0..6).collect();
        let one = run_indices(&setup, &all, 1, None).unwrap();
        let two = run_indices(&setup, &all, 2, None).unwrap();
        // As text: NaN (not converged) is not equal to itself as f64.
        let text = |r: &[Outcome]| r.iter().map(Outcome::csv).collect::<Vec<_>>();
        assert_eq!(text(&one), text(&two));
        write_samples(&d("single"), &one).unwrap();
        let mut dirs = Vec::new();
        for k in 0..2u64 {
            let idx: Vec<u64> = (k..6).step_by(2).collect();
            let rows = run_indices(&setup, &idx, 2, None).unwrap();
            let dir = d(&format!("shard{k}"));
            write_shard(&dir, &setup, (k, 2), &rows).unwrap();
            dirs.push(dir);
        }
        merge(&dirs, Some(&d("merged"))).unwrap();
        assert_eq!(
            std::fs::read(base.join("merged/samples.csv")).unwrap(),
            std::fs::read(base.join("single/samples.csv")).unwrap()
        );
        // A missing shard is an error naming the gap.
        let e = merge(&dirs[..1], Some(&d("bad"))).unwrap_err();
        assert!(e.contains("missing"), "{e}");
        std::fs::remove_dir_all(&base).ok();
    }

    /// Sample 4331 of seed 1 blows up (|Ω| ~ 10⁵ rad/s within 2 s); the
    /// capped dopri stops it and it counts as diverged (before the cap it
    /// took 4.9·10⁶ steps; now it is one call's 20 000).
    #[test]
    fn a_blow_up_is_diverged_and_cheap() {
        let mut setup = Setup::from_args(&default_args());
        setup.samples = 10_000;
        let r = run_sample(&setup, 4331).unwrap();
        assert_eq!(r.status, Status::Diverged);
        assert!(!r.converged && r.t_converge.is_nan());
    }

    #[test]
    fn shards_parse() {
        assert_eq!(parse_shard("1/4"), Ok((1, 4)));
        assert!(parse_shard("4/4").is_err());
        assert!(parse_shard("0/0").is_err());
        assert!(parse_shard("x").is_err());
    }

    /// The convergence hold: enters at the interpolated crossing, resets
    /// when the tolerance is lost, and ignores earlier (bisection) times.
    #[test]
    fn hold_interpolates_and_resets() {
        let mut h = Hold {
            hold: 0.5,
            entered: None,
            last: None,
        };
        assert!(!h.check(0.0, 3.0));
        assert!(!h.check(1.0, 0.5)); // crossing of 1 at 0.8
        assert!((h.entered.unwrap() - 0.8).abs() < 1e-15);
        assert!(!h.check(1.2, 0.9));
        assert!(h.check(1.4, 0.8));
        // A bisection call inside the last step reads without changing.
        assert!(!h.check(1.25, 0.8));
        assert!(h.check(1.35, 0.8));
        assert!(!h.check(1.5, 1.5));
        assert_eq!(h.entered, None);
    }
}
