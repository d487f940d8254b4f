//! The two built-in experiments, the paper's "almost global" attractivity
//! (its Propositions 2 and 3) over random initial conditions: the pinned
//! vehicle in attitude mode from uniform random attitudes, and the free
//! quadrotor in position mode from random attitudes, positions and
//! velocities. Each is a [`Study`] with fixed draws, simulation and settle
//! metric; [`Outcome`] is a row of their `samples.csv`.

use controllers::ModeOutput;
use dynamics::RigidBodyState;
use lie::{Backend, GlamF64, Real, S};
use scenes::Error;

use super::{Status, Stream, Study, in_ball, shoemake};
use crate::metrics::norm;
use scenarios::Divergence;
use scenarios::{DivergenceGuard, SimError, Simulation, SimulationBuilder};
use scenes::scene::{AttitudeRef, DisturbanceSpec, PositionRef, SegmentSpec, ThrustSpec};
use scenes::{Scene, builtin};

type B = GlamF64;

/// Which built-in experiment.
#[derive(Copy, Clone, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Experiment {
    /// The pinned vehicle in attitude mode, R_d = I, Ω_d = 0, with the
    /// paper's disturbance Δ_R.
    Attitude,
    /// The free quadrotor in position mode to hover at 0, b1d = e1, with
    /// Δ_x and Δ_R.
    Position,
}

impl Experiment {
    /// `attitude` or `position`.
    pub fn name(self) -> &'static str {
        match self {
            Experiment::Attitude => "attitude",
            Experiment::Position => "position",
        }
    }
}

/// |Ω| above which a sample counts as diverged, rad/s (100× the default
/// initial ball): the position law's computed attitude is singular where
/// b3c ∥ b1d, and a trajectory that passes near it spins up without bound.
pub const DIVERGED_OMEGA: f64 = 200.0;
/// ‖e_x‖ above which a sample counts as diverged, m.
pub const DIVERGED_X: f64 = 100.0;
/// Substeps one dopri call (one 0.02 s record interval) may take:
/// converging samples take a few; a blow-up near the computed attitude's
/// singularity took 4·10⁶ in one call before the cap.
pub const MAX_SUBSTEPS: u32 = 20_000;

/// Everything that defines a sample's result besides its index (what a
/// shard's `run.toml` records so that shards of different runs are not
/// merged).
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Setup {
    /// `attitude` or `position`.
    pub experiment: String,
    /// Number of samples (indices 0 … N−1).
    pub samples: u64,
    /// Seed of every sample's stream.
    pub seed: u64,
    /// Radius of the ball Ω(0) is drawn from, rad/s.
    pub omega_max: f64,
    /// Radius of the ball e_x(0) is drawn from, m (position).
    pub x_max: f64,
    /// Radius of the ball v(0) is drawn from, m/s (position).
    pub v_max: f64,
    /// Ψ below which a sample counts as settled.
    pub psi_tol: f64,
    /// ‖e_x‖ below which a sample counts as settled (position), m.
    pub x_tol: f64,
    /// Simulated time a sample has to converge, s.
    pub deadline: f64,
    /// How long the tolerances must hold, s.
    pub hold: f64,
    /// Integrator name.
    pub integrator: String,
    /// Step, s (dopri: longest call).
    pub dt: f64,
    /// dopri tolerance.
    pub tol: f64,
    /// Locate the sat′ crossings of `e_i` and split steps there (the
    /// scenes' default). Off, a step integrates across the kink: 50 of the
    /// 10 000 samples of seed 1 change class (near-singular passages
    /// decided by it), the others keep their time to converge within
    /// 0.006 s (99th percentile). The lane path runs with it off.
    #[serde(default = "locate_by_default")]
    pub locate_events: bool,
    /// On the lane path (`Setup::run_lanes`, feature `simd`), one dopri step size shared
    /// by the four lanes of an instruction stream (the worst lane's error
    /// decides), instead of a step size per lane. Off by default: on the
    /// position study the shared step is slower and its rows no longer
    /// equal the scalar path's.
    /// The scalar path refuses it.
    #[serde(default)]
    pub shared_step: bool,
}

fn locate_by_default() -> bool {
    true
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

    /// The body state on backend `B`: the attitude through its rotation
    /// vector, as a scene file would give it (what a sample starts from).
    pub fn body<B: Backend>(&self) -> RigidBodyState<B> {
        let v = |a: [f64; 3]| B::vec3(S::<B>::lit(a[0]), S::<B>::lit(a[1]), S::<B>::lit(a[2]));
        let r = scenes::reference::rotation_f64(self.rotation_vector());
        RigidBodyState {
            r: lie::ops::from_elems::<B>(r.map(|row| row.map(S::<B>::lit))),
            x: v(self.x),
            v: v(self.v),
            omega: v(self.omega),
        }
    }
}

impl Default for Setup {
    /// The position experiment as the command line runs it: 1000 samples
    /// of seed 1, |Ω(0)| ≤ 2 rad/s, ‖x(0)‖ ≤ 2 m, ‖v(0)‖ ≤ 1 m/s, settled
    /// when Ψ < 1e-3 and ‖e_x‖ < 1 cm hold for 0.5 s before 60 s, dopri at
    /// tolerance 1e-6 from a 0.02 s first step.
    fn default() -> Self {
        Self {
            experiment: "position".into(),
            samples: 1000,
            seed: 1,
            omega_max: 2.0,
            x_max: 2.0,
            v_max: 1.0,
            psi_tol: 1e-3,
            x_tol: 1e-2,
            deadline: 60.0,
            hold: 0.5,
            integrator: "dopri".into(),
            dt: 0.02,
            tol: 1e-6,
            locate_events: true,
            shared_step: false,
        }
    }
}

impl Setup {
    /// The experiment.
    pub fn experiment(&self) -> Result<Experiment, Error> {
        match self.experiment.as_str() {
            "attitude" => Ok(Experiment::Attitude),
            "position" => Ok(Experiment::Position),
            e => Err(Error::Run(SimError::Setting {
                field: "experiment",
                message: format!("`{e}`: expected attitude or position"),
            })),
        }
    }

    /// Checks every setting before a sample runs: radii and `hold` finite
    /// and ≥ 0, tolerances, `deadline`, `dt` and `tol` finite and > 0
    /// (a zero step would never end, a zero tolerance never settle),
    /// `psi_tol` < 2 (Ψ ≤ 2 always: a larger bound settles at once), a
    /// known integrator and experiment. The error names the field.
    ///
    /// ```
    /// use studies::montecarlo::Setup;
    /// let bad = Setup { dt: 0.0, ..Setup::default() };
    /// let e = bad.validate().unwrap_err();
    /// assert!(matches!(e, scenes::Error::Run(scenarios::SimError::Setting { field: "dt", .. })), "{e}");
    /// ```
    pub fn validate(&self) -> Result<(), Error> {
        let fail = |field, message: String| Err(Error::Run(SimError::Setting { field, message }));
        let values = [
            ("omega_max", self.omega_max, true),
            ("x_max", self.x_max, true),
            ("v_max", self.v_max, true),
            ("hold", self.hold, true),
            ("psi_tol", self.psi_tol, false),
            ("x_tol", self.x_tol, false),
            ("deadline", self.deadline, false),
            ("dt", self.dt, false),
            ("tol", self.tol, false),
        ];
        for (field, v, zero_ok) in values {
            if !(v.is_finite() && (v > 0.0 || (zero_ok && v == 0.0))) {
                let want = if zero_ok { "≥ 0" } else { "> 0" };
                return fail(field, format!("{v}: must be finite and {want}"));
            }
        }
        if self.psi_tol >= 2.0 {
            return fail("psi_tol", format!("{}: must be below 2", self.psi_tol));
        }
        if let Err(e) = self.integrator.parse::<integrators::IntegratorKind>() {
            return fail("integrator", e.to_string());
        }
        self.experiment().map(|_| ())
    }

    /// [`Setup::validate`], and the settings only the lane path has off.
    fn validate_scalar(&self) -> Result<(), Error> {
        self.validate()?;
        if self.shared_step {
            return Err(Error::Run(SimError::Setting {
                field: "shared_step",
                message: "true: a step size shared between lanes applies to the lane path (run_lanes) only".into(),
            }));
        }
        Ok(())
    }

    fn is_position(&self) -> bool {
        self.experiment == "position"
    }

    /// Draws an initial condition from a sample's stream.
    pub fn draw(&self, rng: &mut Stream) -> Initial {
        let q = shoemake(rng);
        let omega = in_ball(rng, self.omega_max);
        let (x, v) = if self.is_position() {
            (in_ball(rng, self.x_max), in_ball(rng, self.v_max))
        } else {
            ([0.0; 3], [0.0; 3])
        };
        Initial { q, omega, x, v }
    }

    /// Sample `index`'s initial condition: a function of (seed, index)
    /// alone.
    pub fn initial(&self, index: u64) -> Initial {
        self.draw(&mut super::stream(self.seed, index))
    }

    /// The experiment's scene with a sample's initial condition, to replay
    /// it (its description names the experiment).
    pub fn scene(&self, init: &Initial) -> Scene {
        let mut s = if self.is_position() {
            let mut s = builtin::hover_disturbed();
            s.plan = vec![SegmentSpec::position(PositionRef::Hold {
                x: [0.0; 3],
                b1d: [1.0, 0.0, 0.0],
            })];
            s
        } else {
            let mut s = builtin::large_attitude_error();
            s.disturbance = Some(DisturbanceSpec::paper());
            s.plan = vec![SegmentSpec::attitude(
                AttitudeRef::Hold { rotation: [0.0; 3] },
                ThrustSpec::Hover,
            )];
            s
        };
        s.name = format!("montecarlo-{}", self.experiment);
        s.description = format!(
            "A Monte Carlo sample of the {} experiment.",
            self.experiment
        );
        s.backend = scenes::scene::BackendKind::Glam;
        s.initial.rotation = init.rotation_vector();
        s.initial.omega = init.omega;
        s.initial.x = init.x;
        s.initial.v = init.v;
        s.integrator.kind = self.integrator.clone();
        s.integrator.dt = self.dt;
        s.integrator.tol = self.tol;
        s.integrator.locate_events = self.locate_events;
        s.duration = self.deadline;
        // Peaks (thrust, rotor thrust) are taken over this grid; dopri's
        // calls end on it.
        s.record.sample = 0.02;
        s
    }

    /// A sample's simulation: the scene's vehicle and plan from `init`, the
    /// divergence guard ([`DIVERGED_OMEGA`], [`DIVERGED_X`], and for dopri
    /// [`MAX_SUBSTEPS`]: a call that needs more is a solution blowing up
    /// between two checks of the state limits).
    pub fn builder(&self, init: &Initial) -> Result<SimulationBuilder<'static, B>, Error> {
        let sc = self.scene(init);
        let vehicle = scenes::build_vehicle::<B>(&sc)?;
        let plan = scenes::plan::<B>(&sc, vehicle.as_ref());
        let kind: integrators::IntegratorKind = self.integrator.parse()?;
        let stepper =
            integrators::Stepper::<B>::new(kind, integrators::StepperConfig { tol: self.tol });
        let body = init.body::<B>();
        let guard = DivergenceGuard {
            omega: Some(DIVERGED_OMEGA),
            position_error: Some(DIVERGED_X),
            moment: None,
            substeps: (kind == integrators::IntegratorKind::Dopri).then_some(MAX_SUBSTEPS),
        };
        let mut b = Simulation::<B>::builder(vehicle)
            .initial(body)
            .dt(self.dt)
            .duration(self.deadline)
            .record_every(sc.record.sample)
            .guard(guard)
            .locate_events(self.locate_events);
        for seg in plan {
            b = b.segment(seg);
        }
        Ok(b.integrator(stepper))
    }

    /// The settle metric: `max(Ψ/psi_tol, ‖x‖/x_tol)` (Ψ alone in the
    /// attitude experiment).
    pub fn metric(&self, st: &RigidBodyState<B>, out: &ModeOutput<B>) -> f64 {
        let m = out.psi.to_f64_lossless() / self.psi_tol;
        if self.is_position() {
            m.max(norm(B::vec3_to_array(st.x)) / self.x_tol)
        } else {
            m
        }
    }

    /// The experiment as a [`Study`].
    #[allow(clippy::type_complexity)]
    pub fn study(
        &self,
    ) -> Study<
        Initial,
        impl Fn(&mut Stream) -> Initial + Sync + '_,
        impl Fn(&Initial) -> Result<SimulationBuilder<'static, B>, Error> + Sync + '_,
        impl Fn(f64, &RigidBodyState<B>, &ModeOutput<B>) -> f64 + Sync + '_,
    > {
        Study::new(
            self.seed,
            self.hold,
            |rng| self.draw(rng),
            |init| self.builder(init),
            |_, st, out| self.metric(st, out),
        )
    }

    /// Runs the samples `indices` on `threads` threads; rows in index order.
    pub fn run(
        &self,
        indices: &[u64],
        threads: Option<usize>,
        progress: Option<&(dyn Fn(u64) + Sync)>,
    ) -> Result<Vec<Outcome>, Error> {
        self.validate_scalar()?;
        let trials = self.study().run(indices, threads, progress)?;
        Ok(trials.into_iter().map(Outcome::from).collect())
    }

    /// [`Setup::run`] that stops when `cancel` is set
    /// ([`Study::run_until_cancelled`]): the rows of the samples finished
    /// by then, in index order.
    pub fn run_until_cancelled(
        &self,
        indices: &[u64],
        threads: Option<usize>,
        progress: Option<&(dyn Fn(u64) + Sync)>,
        cancel: &std::sync::atomic::AtomicBool,
    ) -> Result<Vec<Outcome>, Error> {
        self.validate_scalar()?;
        let trials = self
            .study()
            .run_until_cancelled(indices, threads, progress, cancel)?;
        Ok(trials.into_iter().map(Outcome::from).collect())
    }

    /// Runs sample `index`.
    pub fn run_sample(&self, index: u64) -> Result<Outcome, Error> {
        self.validate_scalar()?;
        self.study().sample(index).map(Outcome::from)
    }
}

/// One sample's result (a row of `samples.csv`).
#[derive(Clone, Debug, PartialEq)]
pub struct Outcome {
    /// Sample index.
    pub index: u64,
    /// Initial rotation angle from R_d = I, rad.
    pub angle: f64,
    /// Its axis.
    pub axis: [f64; 3],
    /// |Ω(0)|, rad/s.
    pub omega0: f64,
    /// ‖e_x(0)‖, m.
    pub ex0: f64,
    /// Whether it converged.
    pub converged: bool,
    /// Time to converge, s (NaN when not converged).
    pub t_converge: f64,
    /// Ψ at the end (NaN when the run was cut off inside a step).
    pub final_psi: f64,
    /// ‖e_x‖ at the end (NaN likewise).
    pub final_ex: f64,
    /// Largest commanded thrust over the 0.02 s samples, N.
    pub max_thrust: f64,
    /// Largest rotor thrust over them, N.
    pub max_rotor: f64,
    /// Integrator steps (0 when the run was cut off inside a step: a
    /// failed step or the substep cap).
    pub steps: u64,
    /// How it ended.
    pub status: Status,
}

impl From<super::Trial<Initial>> for Outcome {
    fn from(t: super::Trial<Initial>) -> Self {
        let init = &t.draw;
        // A run cut off inside an integrator call (the substep cap) or by a
        // step that failed has no final figures worth keeping.
        let cut =
            t.status == Status::Error || matches!(t.divergence(), Some(Divergence::Substeps(_)));
        let (final_psi, final_ex, steps) = match &t.run {
            Ok(o) if !cut => (o.last.psi, o.last.ex, o.steps),
            _ => (f64::NAN, f64::NAN, 0),
        };
        Outcome {
            index: t.index,
            angle: init.angle(),
            axis: init.axis(),
            omega0: norm(init.omega),
            ex0: norm(init.x),
            converged: t.status == Status::Converged,
            t_converge: t.t_settled.unwrap_or(f64::NAN),
            final_psi,
            final_ex,
            max_thrust: t.max_thrust,
            max_rotor: t.max_rotor,
            steps,
            status: t.status,
        }
    }
}

/// The header of `samples.csv`.
pub const SAMPLES_HEADER: &str = "index,angle,axis1,axis2,axis3,omega0,ex0,converged,t_converge,final_psi,final_ex,max_thrust,max_rotor,steps,status";

impl Outcome {
    /// The row, without its newline.
    pub fn csv(&self) -> String {
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

    /// Parses a row.
    pub fn parse(line: &str) -> Result<Self, String> {
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

/// `samples.csv` of `rows`: the header and one line each.
pub fn write_samples(rows: &[Outcome]) -> String {
    let mut text = String::with_capacity(rows.len() * 200);
    text.push_str(SAMPLES_HEADER);
    text.push('\n');
    for r in rows {
        text.push_str(&r.csv());
        text.push('\n');
    }
    text
}

/// The rows of a `samples.csv`; the error names the line.
pub fn parse_samples(text: &str) -> Result<Vec<Outcome>, String> {
    let mut lines = text.lines();
    if lines.next() != Some(SAMPLES_HEADER) {
        return Err("not a samples.csv (header)".into());
    }
    lines
        .enumerate()
        .map(|(k, l)| Outcome::parse(l).map_err(|e| format!("line {}: {e}", k + 2)))
        .collect()
}
