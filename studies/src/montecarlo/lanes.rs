//! The Monte Carlo experiments on SIMD lanes (feature `simd`): four
//! samples per instruction stream (`f64x4`), each lane with its own
//! Dormand–Prince step size ([`integrators::lanes::DopriLanes`]), and a
//! lane whose sample ends refilled at once from the queue of sample
//! indices.
//!
//! A lane runs what the scalar path runs for its sample — the same scene
//! (vehicle, Δ_x, Δ_R, gains), the same law ([`scenarios::lanes::PositionLoop`],
//! [`scenarios::lanes::AttitudeLoop`]: `controllers::position_law` and
//! `attitude_law` lane-wise), the same stepper and tolerance on the same
//! 0.02 s calls, the same guard, hold and settle metric — with two
//! differences: the sat′ crossings of `e_i` are not located (the scalar
//! path splits a step there; [`Setup::locate_events`] must be off), and
//! the run's end (converged or diverged) is taken at the end of the call
//! where it holds instead of being bisected inside it. The first is why a
//! lane's row equals the scalar path's with `locate_events` off; the
//! second changes only the final Ψ, ‖e_x‖ and a diverged sample's peaks,
//! not the class, the time to converge (interpolated as before) or the
//! step count.

use scenes::Error;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use controllers::{
    AccelerationModel, AttitudeGains, PositionGains, PositionReference, RigidBodyParams,
};
use dynamics::{Disturbance, Vehicle, Wrench};
use integrators::State;
use integrators::lanes::{DopriLanes, LaneFailure, LaneSystem};
use lie::{GlamF64, NalgebraF64x4, S, SimdMask, SimdReal, V3};

use super::experiments::{
    DIVERGED_OMEGA, DIVERGED_X, Experiment, Initial, MAX_SUBSTEPS, Outcome, Setup,
};
use super::{Settled, Status};
use scenarios::SimError;
use scenarios::lanes::{AttitudeLoop, Command, Commanded, PositionLoop};

/// The scalar backend of the scalar path, whose lanes these are.
type E = GlamF64;
/// Four f64 lanes.
type L = NalgebraF64x4;
const LANES: usize = <S<L> as SimdReal>::LANES;

/// How the lanes were used: lane-substeps with a sample in them and
/// without (the queue ran dry at the end of a worker's share).
#[derive(Copy, Clone, Debug, Default, PartialEq, serde::Serialize)]
pub struct LaneUse {
    /// Lane-substeps that advanced a sample.
    pub busy: u64,
    /// Lane-substeps of an empty lane.
    pub idle: u64,
    /// Of those, the ones taken while the queue still held samples: zero
    /// unless refilling is broken (a lane is refilled in the substep its
    /// sample ends).
    pub idle_while_queued: u64,
}

impl LaneUse {
    /// `idle / (busy + idle)` (0 when nothing ran).
    pub fn idle_fraction(&self) -> f64 {
        let all = self.busy + self.idle;
        if all == 0 {
            0.0
        } else {
            self.idle as f64 / all as f64
        }
    }
}

/// The experiment's vehicle (what judges a lane's sample: its rotor
/// thrusts for the peaks) and the pieces of its closed loop.
struct Model {
    vehicle: Box<dyn Vehicle<E>>,
    /// The scene's fixed disturbance (Δ_x, Δ_R), which the vehicle adds.
    disturbance: Option<Disturbance<E>>,
    params: RigidBodyParams<E>,
    pos: PositionGains<E>,
    att: AttitudeGains<E>,
    model: AccelerationModel<E>,
}

fn singular() -> Error {
    Error::Run(SimError::Setting {
        field: "vehicle",
        message: "its inertia is singular".into(),
    })
}

impl Model {
    fn new(setup: &Setup) -> Result<Self, Error> {
        let scene = setup.scene(&setup.initial(0));
        let vehicle = scenes::build_vehicle::<E>(&scene)?;
        let (params, pos, att, model) =
            scenes::gains::<E>(&scene, vehicle.as_ref(), scenes::Seeds::NONE);
        let disturbance = scene.disturbance.as_ref().map(|d| Disturbance {
            force: E::vec3(d.force[0], d.force[1], d.force[2]),
            moment: E::vec3(d.moment[0], d.moment[1], d.moment[2]),
        });
        Ok(Self {
            vehicle,
            disturbance,
            params,
            pos,
            att,
            model,
        })
    }

    fn disturbance(&self) -> Option<Disturbance<E>> {
        self.disturbance
    }

    /// The position experiment's loop on `B` (one lane for `B = E`):
    /// hover at the origin, `b1d = e1`.
    fn position<B>(&self) -> Result<PositionLoop<B>, Error>
    where
        B: lie::SimdBackend<Scalar: SimdReal<Element = f64>>,
    {
        let hold = PositionReference::<E>::hold(E::vec3(0.0, 0.0, 0.0), E::vec3(1.0, 0.0, 0.0));
        PositionLoop::splat(
            &self.params,
            &self.pos,
            &self.att,
            self.model,
            &hold,
            self.disturbance(),
        )
        .ok_or_else(singular)
    }

    /// The attitude experiment's loop on `B`: `R_d = I`, hover thrust.
    fn attitude<B>(&self) -> Result<AttitudeLoop<B>, Error>
    where
        B: lie::SimdBackend<Scalar: SimdReal<Element = f64>>,
    {
        let rd = lie::ops::from_elems::<E>(scenes::reference::rotation_f64([0.0; 3]));
        let hover = self.params.mass * self.params.gravity;
        AttitudeLoop::splat(
            &self.params,
            &self.att,
            rd,
            hover,
            self.disturbance().map(|d| d.moment),
        )
        .ok_or_else(singular)
    }
}

/// How a sample ended: its status and, unless cut off inside a call, its
/// final Ψ, ‖e_x‖ and step count.
type End = (Status, Option<(f64, f64, u64)>);

/// One lane's sample while it flies.
struct Flight {
    index: u64,
    init: Initial,
    settled: Settled,
    thrust: f64,
    rotor: f64,
}

impl Flight {
    /// The peaks with the command `(thrust, moment)` (the rotor thrusts of
    /// the vehicle's allocation, as the scalar path's samples have them).
    fn peaks(&mut self, vehicle: &dyn Vehicle<E>, thrust: f64, moment: V3<E>) {
        let mut rotors = [0.0; 4];
        if vehicle
            .actuators_from_wrench(&Wrench { thrust, moment }, &mut rotors)
            .is_ok()
        {
            self.rotor = rotors.iter().fold(self.rotor, |a, r| a.max(r.abs()));
        }
        self.thrust = self.thrust.max(thrust.abs());
    }

    /// The row, with the end figures (NaN and 0 steps for a lane cut off
    /// inside a call, as the scalar path reports it).
    fn outcome(self, (status, end): End) -> Outcome {
        let (final_psi, final_ex, steps) = end.unwrap_or((f64::NAN, f64::NAN, 0));
        let n = |a: [f64; 3]| (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        Outcome {
            index: self.index,
            angle: self.init.angle(),
            axis: self.init.axis(),
            omega0: n(self.init.omega),
            ex0: n(self.init.x),
            converged: status == Status::Converged,
            t_converge: if status == Status::Converged {
                self.settled.entered().unwrap_or(f64::NAN)
            } else {
                f64::NAN
            },
            final_psi,
            final_ex,
            max_thrust: self.thrust,
            max_rotor: self.rotor,
            steps,
            status,
        }
    }
}

/// What a worker shares with the others.
struct Shared<'a> {
    setup: &'a Setup,
    model: &'a Model,
    indices: &'a [u64],
    next: AtomicUsize,
    done: AtomicUsize,
    progress: Option<&'a (dyn Fn(u64) + Sync)>,
    rows: Mutex<Vec<Outcome>>,
    usage: Mutex<LaneUse>,
    cancel: Option<&'a AtomicBool>,
}

impl Shared<'_> {
    /// The next sample from the queue: its flight and initial state.
    fn take(&self) -> Option<(Flight, State<E, 6>)> {
        if self.cancelled() {
            return None;
        }
        let k = self.next.fetch_add(1, Ordering::Relaxed);
        let index = *self.indices.get(k)?;
        let init = self.setup.initial(index);
        let body = init.body::<E>();
        let f = Flight {
            index,
            init,
            settled: Settled::new(self.setup.hold),
            thrust: 0.0,
            rotor: 0.0,
        };
        Some((f, State::new(body)))
    }

    fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }

    fn finish(&self, rows: &mut Vec<Outcome>, row: Outcome) {
        rows.push(row);
        let n = self.done.fetch_add(1, Ordering::Relaxed) + 1;
        if let Some(p) = self.progress
            && n.is_multiple_of(64)
        {
            p(n as u64);
        }
    }

    /// The next sample started in lane `i`, with its command at t = 0 in
    /// its peaks (the scalar path's first sample) from `one`, the same
    /// loop on one lane.
    fn refill<One>(&self, dopri: &mut DopriLanes<L, 6>, one: &mut One, i: usize) -> Option<Flight>
    where
        One: LaneSystem<E, 6> + Commanded<E>,
    {
        let (mut f, y0) = self.take()?;
        one.load(0.0, &y0);
        let c = one.last();
        f.peaks(self.model.vehicle.as_ref(), c.thrust, c.moment);
        dopri.start_lane::<E>(i, &y0);
        Some(f)
    }

    /// A worker: fills its lanes from the queue and flies them until the
    /// queue and the lanes are empty.
    fn work<Sys, One>(&self, mut sys: Sys, mut one: One) -> Result<(), Error>
    where
        Sys: LaneSystem<L, 6> + Commanded<L>,
        One: LaneSystem<E, 6> + Commanded<E>,
    {
        let setup = self.setup;
        let mut dopri = DopriLanes::<L, 6>::new(setup.tol, setup.dt, MAX_SUBSTEPS)
            .shared_step(setup.shared_step);
        let mut lanes: [Option<Flight>; LANES] = Default::default();
        let mut rows = Vec::new();
        let mut usage = LaneUse::default();
        for (i, lane) in lanes.iter_mut().enumerate() {
            *lane = self.refill(&mut dopri, &mut one, i);
        }
        let vehicle = self.model.vehicle.as_ref();
        // A cancelled run keeps the rows of the samples finished so far.
        while lanes.iter().any(Option::is_some) && !self.cancelled() {
            let step = dopri.substep(&mut sys);
            let busy = lanes.iter().filter(|l| l.is_some()).count() as u64;
            usage.busy += busy;
            usage.idle += LANES as u64 - busy;
            if self.next.load(Ordering::Relaxed) < self.indices.len() {
                usage.idle_while_queued += LANES as u64 - busy;
            }
            let (arrived, failed) = (step.arrived.bitmask(), step.failed.bitmask());
            if arrived | failed == 0 {
                continue;
            }
            for (i, lane) in lanes.iter_mut().enumerate() {
                let Some(f) = lane.as_mut() else { continue };
                let end = if failed >> i & 1 == 1 {
                    let status = match dopri.failure(i) {
                        Some(LaneFailure::TooManySubsteps) => Status::Diverged,
                        _ => Status::Error,
                    };
                    Some((status, None))
                } else if arrived >> i & 1 == 1 {
                    arrive(f, setup, vehicle, &dopri, sys.last(), i)
                } else {
                    None
                };
                if let Some((status, figures)) = end {
                    let row = lane.take().map(|f| f.outcome((status, figures)));
                    if let Some(row) = row {
                        self.finish(&mut rows, row);
                    }
                    *lane = self.refill(&mut dopri, &mut one, i);
                    if lane.is_none() {
                        dopri.stop_lane(i);
                    }
                }
            }
        }
        self.rows.lock().expect("rows").extend(rows);
        let mut u = self.usage.lock().expect("usage");
        u.busy += usage.busy;
        u.idle += usage.idle;
        u.idle_while_queued += usage.idle_while_queued;
        Ok(())
    }
}

/// Lane `i` at the end of a call: the guard, the hold, the peaks and the
/// deadline, in the scalar path's order. `Some` when its sample ends.
fn arrive(
    f: &mut Flight,
    setup: &Setup,
    vehicle: &dyn Vehicle<E>,
    dopri: &DopriLanes<L, 6>,
    last: Command<L>,
    i: usize,
) -> Option<End> {
    let body = &dopri.state().body;
    let t = dopri.calls(i) as f64 * setup.dt;
    let norm = |v: V3<L>| {
        let a = E::vec3_to_array(lie::lanes::vec3_lane::<E, L>(v, i));
        (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
    };
    let (omega, ex) = (norm(body.omega), norm(body.x));
    let psi = last.psi.simd_extract(i);
    let figures = Some((psi, ex, dopri.accepted(i)));
    if omega > DIVERGED_OMEGA || ex > DIVERGED_X {
        return Some((Status::Diverged, figures));
    }
    let thrust = last.thrust.simd_extract(i);
    let moment = lie::lanes::vec3_lane::<E, L>(last.moment, i);
    f.peaks(vehicle, thrust, moment);
    let metric = if setup.experiment == "position" {
        (psi / setup.psi_tol).max(ex / setup.x_tol)
    } else {
        psi / setup.psi_tol
    };
    if f.settled.check(t, metric) {
        return Some((Status::Converged, figures));
    }
    if t >= setup.deadline * (1.0 - 1e-12) {
        return Some((Status::Deadline, figures));
    }
    None
}

impl Setup {
    /// [`Setup::run`] on SIMD lanes (four f64 samples per instruction
    /// stream, a lane refilled from the queue as soon as its sample ends)
    /// on `threads` threads (default: one per core), with the `dopri`
    /// integrator and [`Setup::locate_events`] off (errors naming the
    /// field otherwise). Each lane has its own step size; a run's end is
    /// taken at the end of the 0.02 s call where it holds (see the
    /// module). Rows in index order, and how busy the lanes were.
    pub fn run_lanes(
        &self,
        indices: &[u64],
        threads: Option<usize>,
        progress: Option<&(dyn Fn(u64) + Sync)>,
    ) -> Result<(Vec<Outcome>, LaneUse), Error> {
        self.lanes_until(indices, threads, progress, None)
    }

    /// [`Setup::run_lanes`] that stops when `cancel` is set: the rows of
    /// the samples finished by then, in index order.
    pub fn run_lanes_until_cancelled(
        &self,
        indices: &[u64],
        threads: Option<usize>,
        progress: Option<&(dyn Fn(u64) + Sync)>,
        cancel: &AtomicBool,
    ) -> Result<(Vec<Outcome>, LaneUse), Error> {
        self.lanes_until(indices, threads, progress, Some(cancel))
    }

    fn lanes_until(
        &self,
        indices: &[u64],
        threads: Option<usize>,
        progress: Option<&(dyn Fn(u64) + Sync)>,
        cancel: Option<&AtomicBool>,
    ) -> Result<(Vec<Outcome>, LaneUse), Error> {
        self.validate()?;
        if self.integrator != "dopri" {
            return Err(Error::Run(SimError::Setting {
                field: "integrator",
                message: format!(
                    "`{}`: the lane path integrates with dopri only (a fixed-step rk4, even at 0.0025 s, classified 1.4 % of samples differently from dopri: a stiff first transient that its step control resolves)",
                    self.integrator
                ),
            }));
        }
        if self.locate_events {
            return Err(Error::Run(SimError::Setting {
                field: "locate_events",
                message: "true: the lane path does not locate sat′ crossings; set it to false (its rows then equal the scalar path's with the same setup)".into(),
            }));
        }
        let model = Model::new(self)?;
        let shared = Shared {
            setup: self,
            model: &model,
            indices,
            next: AtomicUsize::new(0),
            done: AtomicUsize::new(0),
            progress,
            rows: Mutex::new(Vec::with_capacity(indices.len())),
            usage: Mutex::new(LaneUse::default()),
            cancel,
        };
        let threads = threads
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
            .max(1);
        std::thread::scope(|s| {
            let workers: Vec<_> = (0..threads)
                .map(|_| {
                    s.spawn(|| match self.experiment()? {
                        Experiment::Position => {
                            shared.work(model.position::<L>()?, model.position::<E>()?)
                        }
                        Experiment::Attitude => {
                            shared.work(model.attitude::<L>()?, model.attitude::<E>()?)
                        }
                    })
                })
                .collect();
            workers
                .into_iter()
                .try_for_each(|w| w.join().expect("a lane worker panicked"))
        })?;
        let order: std::collections::HashMap<u64, usize> =
            indices.iter().enumerate().map(|(k, i)| (*i, k)).collect();
        let mut rows = shared.rows.into_inner().expect("rows");
        rows.sort_by_key(|r| order[&r.index]);
        let usage = shared.usage.into_inner().expect("usage");
        Ok((rows, usage))
    }
}
