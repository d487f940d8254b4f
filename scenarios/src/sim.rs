//! The simulation loop, generic over the backend.

use std::time::Instant;

use controllers::{
    AccelerationModel, AttitudeGains, AttitudeReference, ControlCommand, FlightMode,
    IntegralStates, PositionGains, PositionReference, RigidBodyParams, SatBranch, Scheduler,
    Segment, SwitchWhen, ThrustCommand, VehicleState,
};
use dynamics::{
    AttitudeStand, Disturbance, FreeRigidBody, Hexarotor, Quadrotor, RigidBodyState, Vehicle,
    Wrench, loads,
};
use integrators::{Integrator, Load, State, Stepper, StepperConfig, System};
use lie::num_traits::Float;
use lie::{Backend, Real, Rotation, S, So3Mat, V3, ops};

use crate::reference::{self, m, v};
use crate::scene::{AccelModel, AttitudeRef, Mode, Scene, ThrustSpec, Timing, VehicleKind};

/// One recorded sample, in f64 whatever the simulation scalar.
#[derive(Clone, Debug, PartialEq)]
pub struct Sample {
    /// Time, s.
    pub t: f64,
    /// Position (0 when not translating).
    pub x: [f64; 3],
    /// Velocity.
    pub v: [f64; 3],
    /// Attitude, rows.
    pub r: [[f64; 3]; 3],
    /// Body angular velocity.
    pub omega: [f64; 3],
    /// Ψ against the active desired attitude.
    pub psi: f64,
    /// ‖x − x_d‖ (0 without a position reference).
    pub ex: f64,
    /// Commanded thrust.
    pub thrust: f64,
    /// Commanded moment.
    pub moment: [f64; 3],
    /// Position mode active.
    pub position_mode: bool,
    /// Active segment.
    pub segment: usize,
    /// Desired attitude (R_d or R_c), rows.
    pub rd: [[f64; 3]; 3],
    /// Desired angular velocity (Ω_d or Ω_c).
    pub omega_d: [f64; 3],
    /// Desired position (0 without one).
    pub xd: [f64; 3],
    /// Attitude integral e_I.
    pub e_att: [f64; 3],
    /// Position integral e_i.
    pub e_pos: [f64; 3],
    /// Rotor thrusts from the allocation inverse (empty without rotors).
    pub rotors: Vec<f64>,
}

/// A mode switch.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct SwitchRecord {
    /// Time, s.
    pub t: f64,
    /// Segment left.
    pub from: usize,
    /// Segment entered.
    pub to: usize,
}

/// What a run produced.
#[derive(Clone, Debug)]
pub struct RunOutput {
    /// Samples every `record.sample` seconds, plus t = 0 and the end.
    pub samples: Vec<Sample>,
    /// Mode switches.
    pub switches: Vec<SwitchRecord>,
    /// Located sat′ discontinuities (e_i crossing ±σ).
    pub events: usize,
    /// Their times and components.
    pub event_times: Vec<(f64, usize)>,
    /// Integrator steps (accepted substeps for dopri and halved LGVI
    /// steps, redone steps at events included).
    pub steps: u64,
    /// Load (vector-field) evaluations.
    pub evaluations: u64,
    /// Largest commanded thrust over the recorded samples (and t = 0, the
    /// end).
    pub max_thrust: f64,
    /// Largest rotor thrust magnitude over the same samples.
    pub max_rotor: f64,
    /// Wall time of the loop, s.
    pub wall: f64,
    /// The final state.
    pub last: Sample,
}

/// Why a run stopped.
#[derive(Clone, Debug, PartialEq)]
pub enum SimError {
    /// The scene is invalid.
    Scene(String),
    /// The integrator failed.
    Step(String),
    /// The controller rejected its input.
    Control(String),
}

impl std::fmt::Display for SimError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SimError::Scene(s) => write!(f, "scene: {s}"),
            SimError::Step(s) => write!(f, "integrator: {s}"),
            SimError::Control(s) => write!(f, "controller: {s}"),
        }
    }
}

impl std::error::Error for SimError {}

/// Options of one run.
pub struct RunOptions<'a> {
    /// Record samples (CSV, MCAP, plots, metrics over time). Off: only the
    /// final state is kept and nothing is formatted.
    pub record: bool,
    /// Called with the fraction done, at most ~200 times a run.
    pub progress: Option<&'a mut dyn FnMut(f64)>,
}

impl Default for RunOptions<'_> {
    fn default() -> Self {
        Self {
            record: true,
            progress: None,
        }
    }
}

struct Loop<'a, B: Backend> {
    vehicle: &'a dyn Vehicle<B>,
    sched: Option<Scheduler<'a, B, So3Mat<B>>>,
    params: RigidBodyParams<B>,
    pg: PositionGains<B>,
    ag: AttitudeGains<B>,
    model: AccelerationModel<B>,
    /// Sampled control: the held command.
    held: Option<ControlCommand<B, So3Mat<B>>>,
    sampled: bool,
    /// Cancel the vehicle's configuration moment in the command.
    compensate: bool,
    inertia_inv: lie::M3<B>,
    evaluations: u64,
    error: Option<String>,
}

fn ints<B: Backend>(e: &[S<B>; 6]) -> IntegralStates<B> {
    IntegralStates {
        e_att: B::vec3(e[0], e[1], e[2]),
        e_pos: B::vec3(e[3], e[4], e[5]),
    }
}

impl<B: Backend> Loop<'_, B> {
    fn command(&mut self, t: S<B>, y: &State<B, 6>) -> Option<ControlCommand<B, So3Mat<B>>> {
        let sched = self.sched.as_mut()?;
        let st = VehicleState {
            x: y.body.x,
            v: y.body.v,
            r: So3Mat::from_matrix_unchecked(y.body.r),
            omega: y.body.omega,
        };
        match sched.command(
            &self.params,
            &self.pg,
            &self.ag,
            t,
            &st,
            &ints::<B>(&y.extra),
            self.model,
        ) {
            Ok(mut c) => {
                if self.compensate
                    && let Some(m) = self.vehicle.configuration_moment(&y.body)
                {
                    c.moment = c.moment - m;
                }
                Some(c)
            }
            Err(e) => {
                // A non-finite state: report it after the step (the
                // integrator sees NaN loads and stops).
                self.error.get_or_insert_with(|| e.to_string());
                None
            }
        }
    }
}

impl<B: Backend> System<B, 6> for Loop<'_, B> {
    fn mass(&self) -> S<B> {
        self.vehicle.mass()
    }
    fn inertia(&self) -> lie::M3<B> {
        self.vehicle.inertia()
    }
    fn inertia_inv(&self) -> lie::M3<B> {
        self.inertia_inv
    }
    fn translates(&self) -> bool {
        self.vehicle.translates()
    }
    fn load_depends_on_rates(&self) -> bool {
        self.sched.is_some() && !self.sampled
    }
    fn load(&mut self, t: S<B>, y: &State<B, 6>) -> Load<B, 6> {
        self.evaluations += 1;
        let nan = S::<B>::nan();
        let cmd = if self.sched.is_none() {
            None
        } else if self.sampled {
            self.held
        } else {
            match self.command(t, y) {
                Some(c) => Some(c),
                None => {
                    let n = B::vec3(nan, nan, nan);
                    return Load {
                        force: n,
                        moment: n,
                        extra_rate: [nan; 6],
                    };
                }
            }
        };
        let (w, rates) = match cmd {
            Some(c) => (
                Wrench {
                    thrust: c.thrust,
                    moment: c.moment,
                },
                [c.e_att_rate, c.e_pos_rate],
            ),
            None => (Wrench::zero(), [ops::zero::<B>(); 2]),
        };
        let l = loads(self.vehicle, t, &y.body, &w);
        let (a, p) = (B::vec3_to_array(rates[0]), B::vec3_to_array(rates[1]));
        Load {
            force: l.force,
            moment: l.moment,
            extra_rate: [a[0], a[1], a[2], p[0], p[1], p[2]],
        }
    }
}

fn f3<B: Backend>(x: V3<B>) -> [f64; 3] {
    B::vec3_to_array(x).map(|c| c.to_f64_lossless())
}

fn fm<B: Backend>(x: lie::M3<B>) -> [[f64; 3]; 3] {
    ops::elems::<B>(x).map(|r| r.map(|c| c.to_f64_lossless()))
}

/// Builds the vehicle of a scene.
pub fn build_vehicle<B: Backend>(scene: &Scene) -> Result<Box<dyn Vehicle<B>>, SimError> {
    let l = S::<B>::lit;
    let ve = &scene.vehicle;
    let j = ops::diag::<B>(l(ve.inertia[0]), l(ve.inertia[1]), l(ve.inertia[2]));
    let err = |e: dynamics::DynamicsError| SimError::Scene(e.to_string());
    let mut quad =
        Quadrotor::<B>::new(l(ve.mass), j, l(ve.gravity), l(ve.arm), l(ve.c_tau_f)).map_err(err)?;
    if let Some(d) = &scene.disturbance {
        quad = quad
            .with_disturbance(Disturbance {
                force: v::<B>(d.force),
                moment: v::<B>(d.moment),
            })
            .map_err(err)?;
    }
    Ok(match ve.kind {
        VehicleKind::Quadrotor => Box::new(quad),
        VehicleKind::PinnedQuadrotor => Box::new(AttitudeStand::new(quad, l(0.0)).map_err(err)?),
        VehicleKind::AttitudeStand => {
            Box::new(AttitudeStand::new(quad, l(ve.stand_height)).map_err(err)?)
        }
        VehicleKind::FreeRigidBody => Box::new(FreeRigidBody::new(j).map_err(err)?),
        VehicleKind::Hexarotor => {
            let mut hex =
                Hexarotor::<B>::new(l(ve.mass), j, l(ve.gravity), l(ve.arm), l(ve.c_tau_f))
                    .map_err(err)?;
            if let Some(d) = quad.fixed_disturbance() {
                hex = hex.with_disturbance(d).map_err(err)?;
            }
            Box::new(hex)
        }
    })
}

/// Runs `scene` on backend `B`.
pub fn run_generic<B: Backend>(
    scene: &Scene,
    mut opts: RunOptions<'_>,
) -> Result<RunOutput, SimError> {
    scene.validate().map_err(|(_, msg)| SimError::Scene(msg))?;
    let l = S::<B>::lit;
    let vehicle = build_vehicle::<B>(scene)?;
    let g = &scene.gains;
    let ve = &scene.vehicle;
    let params = RigidBodyParams {
        mass: l(ve.mass),
        inertia: vehicle.inertia(),
        gravity: l(ve.gravity),
    };
    let mut pg = PositionGains::<B>::uniform(l(g.k_x), l(g.k_v), l(g.k_i), l(g.c1), l(g.sigma));
    pg.clamp_integral = g.clamp_integral;
    let ag = AttitudeGains::<B>::uniform(l(g.k_r), l(g.k_omega), l(g.k_att_i), l(g.c2));
    let model = match g.acceleration_model {
        AccelModel::Nominal => AccelerationModel::Nominal,
        AccelModel::NominalWithoutEstimate => AccelerationModel::NominalWithoutEstimate,
    };

    // Reference closures, then the plan borrowing them.
    type AttF<'r, B> = Box<dyn Fn(S<B>) -> AttitudeReference<B, So3Mat<B>> + 'r>;
    type PosF<'r, B> = Box<dyn Fn(S<B>) -> PositionReference<B> + 'r>;
    let att_refs: Vec<Option<AttF<'_, B>>> = scene
        .plan
        .iter()
        .map(|s| {
            s.attitude.clone().map(|a| match a {
                // A constant reference is computed once, not per evaluation.
                AttitudeRef::Hold { rotation } => {
                    let rd = m::<B>(reference::rotation_f64(rotation));
                    let z = ops::zero::<B>();
                    Box::new(move |_t: S<B>| AttitudeReference {
                        rd,
                        omega_d: z,
                        omega_d_dot: z,
                    }) as AttF<'_, B>
                }
                other => {
                    Box::new(move |t: S<B>| reference::attitude::<B>(&other, t)) as AttF<'_, B>
                }
            })
        })
        .collect();
    let pos_refs: Vec<Option<PosF<'_, B>>> = scene
        .plan
        .iter()
        .map(|s| {
            s.position
                .clone()
                .map(|p| Box::new(move |t: S<B>| reference::position::<B>(&p, t)) as PosF<'_, B>)
        })
        .collect();
    let hover = params.mass * params.gravity;
    let plan: Vec<Segment<'_, B, So3Mat<B>>> = scene
        .plan
        .iter()
        .enumerate()
        .map(|(k, s)| Segment {
            mode: match s.mode {
                Mode::Attitude => FlightMode::Attitude {
                    reference: att_refs[k].as_deref().expect("validated"),
                    thrust: match s.thrust {
                        ThrustSpec::Hover => ThrustCommand::Constant(hover),
                        ThrustSpec::PdProjection => {
                            ThrustCommand::PdProjection(pos_refs[k].as_deref().expect("validated"))
                        }
                    },
                },
                Mode::Position => FlightMode::Position {
                    reference: pos_refs[k].as_deref().expect("validated"),
                },
            },
            until: match (s.until, s.until_psi) {
                (Some(u), _) => SwitchWhen::Time(l(u)),
                (None, Some(p)) => SwitchWhen::PsiBelow(l(p)),
                (None, None) => SwitchWhen::Never,
            },
        })
        .collect();
    let sampled = scene.control.timing == Timing::Sampled && !plan.is_empty();
    let mut sys = Loop {
        vehicle: vehicle.as_ref(),
        sched: (!plan.is_empty()).then(|| Scheduler::new(&plan)),
        params,
        pg,
        ag,
        model,
        held: None,
        sampled,
        compensate: scene.control.compensate_configuration_moment,
        inertia_inv: ops::inverse::<B>(vehicle.inertia())
            .ok_or_else(|| SimError::Scene("inertia is singular".into()))?,
        evaluations: 0,
        error: None,
    };

    let i = &scene.initial;
    let mut body = RigidBodyState::<B>::at_rest();
    body.r = m::<B>(reference::rotation_f64(i.rotation)).matrix();
    body.omega = v::<B>(i.omega);
    if vehicle.translates() {
        body.x = v::<B>(i.x);
        body.v = v::<B>(i.v);
    }
    let mut y = State::<B, 6>::new(body);
    let kind = scene
        .integrator
        .kind
        .parse()
        .map_err(|e: integrators::UnknownIntegrator| SimError::Scene(e.to_string()))?;
    let mut stepper = Stepper::<B, 6>::new(
        kind,
        StepperConfig {
            tol: scene.integrator.tol,
        },
    );

    let dt = scene.integrator.dt;
    let t_end = scene.duration;
    let rec = if opts.record {
        scene.record.sample
    } else {
        0.0
    };
    let ctrl = if sampled {
        1.0 / scene.control.rate
    } else {
        0.0
    };
    let switch_times: Vec<f64> = scene
        .plan
        .iter()
        .filter_map(|s| s.until)
        .filter(|u| *u < t_end)
        .collect();
    let (mut k_rec, mut k_ctrl, mut k_sw) = (0u64, 0u64, 0usize);
    let sigma = g.sigma;
    let sat_events = scene.integrator.locate_events
        && g.k_i > 0.0
        && plan
            .iter()
            .any(|s| matches!(s.mode, FlightMode::Position { .. }));

    let mut out = RunOutput {
        samples: Vec::new(),
        switches: Vec::new(),
        events: 0,
        event_times: Vec::new(),
        steps: 0,
        evaluations: 0,
        max_thrust: 0.0,
        max_rotor: 0.0,
        wall: 0.0,
        last: empty_sample(),
    };
    let start = Instant::now();
    let mut t = 0.0f64;
    if sampled {
        sys.held = sys.command(l(0.0), &y);
    }
    let s0 = sample(&mut sys, &*vehicle, scene, 0.0, &y)?;
    track(&mut out, &s0);
    if opts.record {
        out.samples.push(s0);
    }
    let mut progress_next = 0.0;
    let mut forced_for_next_step = false;
    while t < t_end {
        // Next checkpoint: record sample, control sample, switch, end —
        // each a multiple or a listed time, never an accumulated sum.
        let mut t_next = t_end;
        if rec > 0.0 {
            t_next = t_next.min((k_rec + 1) as f64 * rec);
        }
        if ctrl > 0.0 {
            t_next = t_next.min((k_ctrl + 1) as f64 * ctrl);
        }
        if let Some(&ts) = switch_times.get(k_sw) {
            t_next = t_next.min(ts);
        }
        // Steps of dt from t, the last one shortened to land on t_next.
        let mut seg_start = t;
        let mut j = 0u64;
        while t < t_next {
            let mut ts = seg_start + (j + 1) as f64 * dt;
            if ts > t_next - 1e-12 * dt.max(t_next) {
                ts = t_next;
            }
            let h = ts - t;
            let before = y;
            let stats = stepper
                .step(&mut sys, l(t), l(h), &mut y)
                .map_err(|e| {
                    SimError::Step(match sys.error.take() {
                        // The controller saw a non-finite state first: the
                        // step before diverged (step too large?).
                        Some(c) => format!(
                            "in the step from t = {t} (h = {h}): {c}; the state diverged — try a smaller --dt"
                        ),
                        None => e.to_string(),
                    })
                })?;
            out.steps += u64::from(stats.substeps.max(1));
            if sat_events && let Some((tc, comp)) = crossing(&mut sys, t, h, &before, &y, sigma) {
                // Split the step at the crossing: redo [t, tc], restart the
                // dt grid from tc. The Hermite estimate of tc is refined by
                // Newton on the integrated e_i (the interpolant is only
                // O(h⁴) accurate, and for dopri's long calls that error,
                // times ė_i, was 1e-7 in the state).
                let (mut tc, comp, target) = (tc, comp.0, comp.1);
                let was_inside = before.extra[3 + comp].to_f64_lossless().abs() < sigma;
                let (pre, post) = if was_inside {
                    (SatBranch::Inside, SatBranch::Outside)
                } else {
                    (SatBranch::Outside, SatBranch::Inside)
                };
                sys.pg.sat_branch[comp] = pre;
                for _ in 0..8 {
                    y = before;
                    stepper.reset();
                    let hc = tc - t;
                    if hc > 0.0 {
                        let stats = stepper
                            .step(&mut sys, l(t), l(hc), &mut y)
                            .map_err(|e| SimError::Step(e.to_string()))?;
                        out.steps += u64::from(stats.substeps.max(1));
                    }
                    let g = y.extra[3 + comp].to_f64_lossless() - target;
                    if g.abs() <= 1e-13 * sigma.max(1.0) {
                        break;
                    }
                    let rate = sys.load(l(tc), &y).extra_rate[3 + comp].to_f64_lossless();
                    if rate == 0.0 || !rate.is_finite() {
                        break;
                    }
                    tc = (tc - g / rate).clamp(t, t + h);
                }
                // Land the component on ±σ exactly and integrate the next
                // step on the far side's branch of sat′ (stages a rounding
                // error from the boundary would otherwise pick either side).
                y.extra[3 + comp] = l(target);
                sys.pg.sat_branch[comp] = post;
                forced_for_next_step = true;
                stepper.reset();
                out.events += 1;
                out.event_times.push((tc, comp));
                t = tc;
                seg_start = t;
                j = 0;
                continue;
            }
            if forced_for_next_step {
                sys.pg.sat_branch = [SatBranch::Auto; 3];
                forced_for_next_step = false;
            }
            // A Ψ-triggered switch: when Ψ drops below the threshold inside
            // this step, bisect on redone steps for the crossing and switch
            // there (the scheduler reads the Ψ of the latest command).
            let psi_threshold = sys
                .sched
                .as_ref()
                .and_then(|sc| scene.plan.get(sc.active()))
                .and_then(|sg| sg.until_psi);
            if let Some(th) = psi_threshold {
                let psi_at = |sys: &mut Loop<'_, B>, tt: f64, yy: &State<B, 6>| {
                    sys.command(l(tt), yy).map(|c| c.psi.to_f64_lossless())
                };
                if psi_at(&mut sys, ts, &y).is_some_and(|p| p < th) {
                    let (mut lo, mut hi) = (0.0, h);
                    let mut y_hi = y;
                    while hi - lo > 1e-12 * h.max(1e-300) && hi - lo > f64::EPSILON * ts {
                        let mid = 0.5 * (lo + hi);
                        let mut ym = before;
                        stepper.reset();
                        stepper
                            .step(&mut sys, l(t), l(mid), &mut ym)
                            .map_err(|e| SimError::Step(e.to_string()))?;
                        if psi_at(&mut sys, t + mid, &ym).is_some_and(|p| p < th) {
                            hi = mid;
                            y_hi = ym;
                        } else {
                            lo = mid;
                        }
                    }
                    let tc = t + hi;
                    y = y_hi;
                    // The latest command (at tc) has Ψ < threshold.
                    psi_at(&mut sys, tc, &y);
                    if let Some(s) = sys.sched.as_mut() {
                        let mut it = ints::<B>(&y.extra);
                        if let Some(sw) = s.advance(l(tc), &mut it) {
                            out.switches.push(SwitchRecord {
                                t: tc,
                                from: sw.from,
                                to: sw.to,
                            });
                            let (a, p) = (B::vec3_to_array(it.e_att), B::vec3_to_array(it.e_pos));
                            y.extra = [a[0], a[1], a[2], p[0], p[1], p[2]];
                        }
                    }
                    if sampled {
                        sys.held = sys.command(l(tc), &y);
                    }
                    stepper.reset();
                    t = tc;
                    seg_start = t;
                    j = 0;
                    continue;
                }
            }
            t = ts;
            j += 1;
        }
        t = t_next;
        let mut changed = false;
        if switch_times.get(k_sw).is_some_and(|&ts| ts <= t) {
            k_sw += 1;
            if let Some(s) = sys.sched.as_mut() {
                let mut it = ints::<B>(&y.extra);
                if let Some(sw) = s.advance(l(t), &mut it) {
                    out.switches.push(SwitchRecord {
                        t,
                        from: sw.from,
                        to: sw.to,
                    });
                    let (a, p) = (B::vec3_to_array(it.e_att), B::vec3_to_array(it.e_pos));
                    y.extra = [a[0], a[1], a[2], p[0], p[1], p[2]];
                    changed = true;
                }
            }
        }
        if ctrl > 0.0 && ((k_ctrl + 1) as f64 * ctrl - t).abs() <= 1e-9 * ctrl {
            k_ctrl += 1;
        }
        if sampled && (changed || ((k_ctrl as f64) * ctrl - t).abs() <= 1e-9 * ctrl) {
            sys.held = sys.command(l(t), &y);
            changed = true;
        }
        if changed {
            stepper.reset();
        }
        let on_record = rec > 0.0 && ((k_rec + 1) as f64 * rec - t).abs() <= 1e-9 * rec;
        if on_record {
            k_rec += 1;
        }
        if on_record || t >= t_end {
            let s = sample(&mut sys, &*vehicle, scene, t, &y)?;
            track(&mut out, &s);
            if opts.record && (out.samples.last().map(|p| p.t) != Some(s.t)) {
                out.samples.push(s.clone());
            }
            out.last = s;
        }
        if let Some(p) = opts.progress.as_deref_mut()
            && t / t_end >= progress_next
        {
            p(t / t_end);
            progress_next += 0.005;
        }
    }
    out.evaluations = sys.evaluations;
    out.wall = start.elapsed().as_secs_f64();
    Ok(out)
}

fn track(out: &mut RunOutput, s: &Sample) {
    out.max_thrust = out.max_thrust.max(s.thrust.abs());
    out.max_rotor = s.rotors.iter().fold(out.max_rotor, |a, r| a.max(r.abs()));
}

/// A component of e_i that crossed ±σ inside the step, with the crossing
/// time from cubic Hermite interpolation of e_i and ė_i over the step.
fn crossing<B: Backend>(
    sys: &mut Loop<'_, B>,
    t: f64,
    h: f64,
    before: &State<B, 6>,
    after: &State<B, 6>,
    sigma: f64,
) -> Option<(f64, (usize, f64))> {
    // Without a controller there is no sat′ (e_i's rate is zero in
    // attitude mode, so no crossing is seen there either).
    sys.sched.as_ref()?;
    let mut found: Option<(f64, (usize, f64))> = None;
    let mut rates: Option<([f64; 3], [f64; 3])> = None;
    for k in 0..3 {
        let e0 = before.extra[3 + k].to_f64_lossless();
        let e1 = after.extra[3 + k].to_f64_lossless();
        let (g0, g1) = (e0.abs() - sigma, e1.abs() - sigma);
        // A component sitting on ±σ (just located) is not a new crossing.
        if g0.abs() <= 1e-12 * sigma || g0.signum() == g1.signum() || g1 == 0.0 {
            continue;
        }
        let target = if g0 < 0.0 {
            sigma.copysign(e1)
        } else {
            sigma.copysign(e0)
        };
        let (d0, d1) = *rates.get_or_insert_with(|| {
            let l0 = sys.load(S::<B>::lit(t), before);
            let l1 = sys.load(S::<B>::lit(t + h), after);
            let f = |l: &Load<B, 6>| [3, 4, 5].map(|i| l.extra_rate[i].to_f64_lossless());
            (f(&l0), f(&l1))
        });
        let p = |s: f64| {
            let (s2, s3) = (s * s, s * s * s);
            (2.0 * s3 - 3.0 * s2 + 1.0) * e0
                + (s3 - 2.0 * s2 + s) * h * d0[k]
                + (-2.0 * s3 + 3.0 * s2) * e1
                + (s3 - s2) * h * d1[k]
                - target
        };
        let (mut lo, mut hi) = (0.0, 1.0);
        let plo = p(lo);
        if plo.signum() == p(hi).signum() {
            // The cubic disagrees with the endpoints (should not happen for
            // a smooth e_i): fall back to linear interpolation.
            lo = (target - e0) / (e1 - e0);
            hi = lo;
        } else {
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if p(mid).signum() == plo.signum() {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
        }
        let tc = t + h * 0.5 * (lo + hi);
        if found.is_none_or(|(tf, _)| tc < tf) {
            found = Some((tc, (k, target)));
        }
    }
    found
}

fn empty_sample() -> Sample {
    Sample {
        t: 0.0,
        x: [0.0; 3],
        v: [0.0; 3],
        r: [[0.0; 3]; 3],
        omega: [0.0; 3],
        psi: 0.0,
        ex: 0.0,
        thrust: 0.0,
        moment: [0.0; 3],
        position_mode: false,
        segment: 0,
        rd: [[0.0; 3]; 3],
        omega_d: [0.0; 3],
        xd: [0.0; 3],
        e_att: [0.0; 3],
        e_pos: [0.0; 3],
        rotors: Vec::new(),
    }
}

fn sample<B: Backend>(
    sys: &mut Loop<'_, B>,
    vehicle: &dyn Vehicle<B>,
    scene: &Scene,
    t: f64,
    y: &State<B, 6>,
) -> Result<Sample, SimError> {
    let cmd = if sys.sampled {
        sys.held
    } else {
        sys.command(S::<B>::lit(t), y)
    };
    if let Some(e) = sys.error.take() {
        return Err(SimError::Control(e));
    }
    let mut s = empty_sample();
    s.t = t;
    s.x = f3::<B>(y.body.x);
    s.v = f3::<B>(y.body.v);
    s.r = fm::<B>(y.body.r);
    s.omega = f3::<B>(y.body.omega);
    let ex: [f64; 6] = y.extra.map(|c| c.to_f64_lossless());
    s.e_att = [ex[0], ex[1], ex[2]];
    s.e_pos = [ex[3], ex[4], ex[5]];
    if let Some(c) = cmd {
        s.thrust = c.thrust.to_f64_lossless();
        s.moment = f3::<B>(c.moment);
        s.position_mode = c.position_mode;
        s.segment = c.segment;
        s.rd = fm::<B>(c.desired.matrix());
        s.omega_d = f3::<B>(c.desired_omega);
        // Ψ against the desired attitude at *this* state (the held command
        // may be older in sampled mode).
        let r = So3Mat::<B>::from_matrix_unchecked(y.body.r);
        s.psi = r.psi(c.desired).to_f64_lossless();
        if let Some(p) = &scene.plan[c.segment].position
            && vehicle.translates()
        {
            let (d, _) = reference::position_f64(p, t);
            s.xd = d[0];
            s.ex = (0..3)
                .map(|k| (s.x[k] - d[0][k]).powi(2))
                .sum::<f64>()
                .sqrt();
        }
        let n = vehicle.actuator_count();
        if n > 0 {
            // At most 8 rotors on the stack; more would need a bigger buffer.
            let mut buf = [S::<B>::lit(0.0); 8];
            let rotors = &mut buf[..n.min(8)];
            let w = vehicle.saturate(Wrench {
                thrust: c.thrust,
                moment: c.moment,
            });
            vehicle
                .actuators_from_wrench(&w, rotors)
                .map_err(|e| SimError::Scene(e.to_string()))?;
            s.rotors = rotors.iter().map(|r| r.to_f64_lossless()).collect();
        }
    } else {
        s.rd = s.r;
    }
    Ok(s)
}
