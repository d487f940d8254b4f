//! Modes that command rotor speeds instead of a wrench
//! (`ModeOutput::rotor_speeds`): the same command through either path
//! flies the same trajectory bit for bit, such a mode is asked once per
//! control instant, a recorded
//! speed sequence replayed open loop reproduces the run it came from bit
//! for bit, and a vehicle without rotor speeds refuses them with a typed
//! error.

use std::collections::BTreeMap;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

use controllers::{ControlError, IntegralLayout, Mode, ModeOutput, RotorSpeeds, VehicleState};
use dynamics::{
    DrydenSpec, DrydenWind, Multirotor, MultirotorParams, Quadrotor, RigidBodyState, Wrench,
};
use lie::{NalgebraF64, S, So3Mat};
use scenarios::{Control, RunOutput, SimError, Simulation, Until};

type B = NalgebraF64;

#[path = "../../scenarios/tests/common/idle.rs"]
mod idle;
use idle::Idle;

/// Recorded speed commands by control instant (`t` as bits, exact).
type Log = Arc<Mutex<BTreeMap<u64, Vec<f64>>>>;

/// Any mode, its wrench turned into rotor speeds by the vehicle's own
/// mixer (what the `multirotor` vehicle does to a commanded wrench), so
/// the speeds path must reproduce the wrench path exactly; the speeds
/// are logged by time and the calls counted.
struct Speeds {
    inner: Box<dyn Mode<B>>,
    mixer: Multirotor<B>,
    log: Log,
    calls: Arc<AtomicUsize>,
}

impl Mode<B> for Speeds {
    fn name(&self) -> &'static str {
        "speeds"
    }
    fn integrals(&self) -> IntegralLayout<'_, B> {
        self.inner.integrals()
    }
    fn command(
        &self,
        t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        integrals: &[S<B>],
        rates: &mut [S<B>],
    ) -> Result<ModeOutput<B>, ControlError> {
        self.calls.fetch_add(1, Ordering::Relaxed);
        let out = self.inner.command(t, state, integrals, rates)?;
        let wrench = Wrench {
            thrust: out.thrust,
            moment: out.moment,
        };
        let mut speeds = [0.0; 4];
        self.mixer.speed_commands(&wrench, &mut speeds);
        if let Ok(mut log) = self.log.lock() {
            log.insert(t.to_bits(), speeds.to_vec());
        }
        Ok(ModeOutput {
            rotor_speeds: RotorSpeeds::new(&speeds),
            ..out
        })
    }
}

fn crazyflie() -> Multirotor<B> {
    Multirotor::new(MultirotorParams::crazyflie()).expect("preset")
}

/// gusty-hover's vehicle, plan (wrapped by `wrap`), turbulence and
/// settings, RK4 at 1 ms, for 3 s, with control sampled at 100 Hz if
/// `sampled`.
fn fly(
    vehicle: Box<dyn dynamics::Vehicle<B>>,
    wrap: &dyn Fn(Box<dyn Mode<B>>) -> Box<dyn Mode<B>>,
    sampled: bool,
) -> Result<RunOutput, SimError> {
    let scene = scenes::load("gusty-hover").expect("built in");
    let mixer = crazyflie();
    let plan = scenes::plan::<B>(&scene, &mixer);
    let mut start = RigidBodyState::<B>::at_rest();
    start.x = B::vec3(0.3, -0.2, -1.2);
    let mut b = Simulation::<B>::builder(vehicle)
        .initial(start)
        .dt(1e-3)
        .duration(3.0)
        .record_every(0.01)
        .wind(Box::new(
            DrydenWind::new(DrydenSpec::gusty()).expect("valid"),
        ));
    if sampled {
        b = b.control(Control::Sampled { rate: 100.0 });
    }
    for seg in plan {
        b = b.segment(scenarios::Segment {
            mode: wrap(seg.mode),
            until: Until::Never,
        });
    }
    b.build()?.run(Default::default())
}

fn assert_same_flight(a: &RunOutput, b: &RunOutput) {
    assert_eq!(a.samples.len(), b.samples.len());
    for (x, y) in a.samples.iter().zip(&b.samples) {
        assert_eq!(
            (x.t, x.x, x.v, x.r, x.omega),
            (y.t, y.x, y.v, y.r, y.omega),
            "at t = {}",
            x.t
        );
        assert_eq!(
            x.vehicle_states, y.vehicle_states,
            "rotor speeds at t = {}",
            x.t
        );
    }
}

/// Wraps a plan's mode.
type Wrap = Box<dyn Fn(Box<dyn Mode<B>>) -> Box<dyn Mode<B>>>;

fn speeds_of(log: &Log, calls: &Arc<AtomicUsize>) -> Wrap {
    let (log, calls) = (log.clone(), calls.clone());
    Box::new(move |inner| {
        Box::new(Speeds {
            inner,
            mixer: crazyflie(),
            log: log.clone(),
            calls: calls.clone(),
        })
    })
}

#[test]
fn rotor_speed_commands_fly_like_the_wrench_they_mix() {
    let (log, calls) = (Log::default(), Arc::default());
    let wrench = fly(Box::new(crazyflie()), &|m| m, false).expect("run");
    let speeds = fly(Box::new(crazyflie()), &speeds_of(&log, &calls), false).expect("run");
    assert_same_flight(&wrench, &speeds);
    // The motors lag: the rotor speeds moved, so the path was exercised.
    let w: Vec<f64> = speeds.samples.iter().map(|s| s.vehicle_states[0]).collect();
    let spread =
        w.iter().cloned().fold(f64::MIN, f64::max) - w.iter().cloned().fold(f64::MAX, f64::min);
    assert!(spread > 1.0, "rotor 1 speed varied by {spread} rad/s");
}

#[test]
fn a_rotor_speed_mode_is_asked_once_per_control_instant() {
    let (log, calls) = (Log::default(), Arc::default());
    let wrench = fly(Box::new(crazyflie()), &|m| m, true).expect("run");
    let speeds = fly(Box::new(crazyflie()), &speeds_of(&log, &calls), true).expect("run");
    assert_same_flight(&wrench, &speeds);
    let instants = log.lock().expect("log").len();
    assert!(instants >= 300, "{instants} control instants");
    // Sampled at 100 Hz: one answer per control instant (the one at t = 0
    // serves the held command and the rotors' initial speeds alike).
    assert_eq!(calls.load(Ordering::Relaxed), instants);
}

#[test]
fn a_recorded_speed_sequence_replays_open_loop() {
    let (log, calls) = (Log::default(), Arc::default());
    let closed = fly(Box::new(crazyflie()), &speeds_of(&log, &calls), true).expect("run");
    let recorded: Vec<(f64, Vec<f64>)> = log
        .lock()
        .expect("log")
        .iter()
        .map(|(t, s)| (f64::from_bits(*t), s.clone()))
        .collect();
    assert!(recorded.len() >= 300, "{} control instants", recorded.len());
    let replay = Idle {
        psi: 0.0,
        speeds: recorded,
    };
    let slot = Mutex::new(Some(replay));
    let open = fly(
        Box::new(crazyflie()),
        &|_| Box::new(slot.lock().expect("slot").take().expect("one segment")),
        true,
    )
    .expect("run");
    assert_same_flight(&closed, &open);
    assert!(open.samples.iter().all(|s| s.mode == "idle"));
}

#[test]
fn a_vehicle_without_rotor_speeds_refuses_them() {
    let (log, calls) = (Log::default(), Arc::default());
    let quad = Quadrotor::<B>::paper();
    let e = fly(Box::new(quad), &speeds_of(&log, &calls), false)
        .expect_err("the paper's quadrotor has no rotor speeds");
    let source = match &e {
        SimError::Step { control, .. } => *control,
        SimError::Control { source, .. } => Some(*source),
        other => panic!("unexpected error {other}"),
    };
    assert_eq!(
        source,
        Some(ControlError::RotorSpeedsUnsupported { mode: "speeds" }),
        "{e}"
    );
}

/// Three speeds to a four-rotor vehicle: the mode's error, with both
/// counts, not three rotors driven and one left as it was.
#[test]
fn a_wrong_number_of_rotor_speeds_is_the_modes_error() {
    let three = Idle {
        psi: 0.0,
        speeds: vec![(0.0, vec![2000.0; 3])],
    };
    let slot = Mutex::new(Some(three));
    let e = fly(
        Box::new(crazyflie()),
        &|_| Box::new(slot.lock().expect("slot").take().expect("one segment")),
        false,
    )
    .expect_err("three speeds for four rotors");
    let want = ControlError::RotorSpeedCount {
        mode: "idle",
        given: 3,
        rotors: 4,
    };
    match &e {
        SimError::Control { source, .. } => assert_eq!(*source, want, "{e}"),
        SimError::Step { control, .. } => assert_eq!(*control, Some(want), "{e}"),
        other => panic!("unexpected error {other}"),
    }
    assert!(e.to_string().contains("3 rotor speeds"), "{e}");
}

/// The crazyflie idling (no thrust, no moment) for 0.1 s from rest, with
/// the rotors' initial speeds given to the builder or not.
fn idle_from(speeds: Option<&[f64]>) -> Result<RunOutput, SimError> {
    let mut b = Simulation::<B>::builder(Box::new(crazyflie()))
        .dt(1e-3)
        .duration(0.1)
        .record_every(0.01)
        .mode(
            Idle {
                psi: 0.0,
                speeds: Vec::new(),
            },
            Until::Never,
        );
    if let Some(s) = speeds {
        b = b.vehicle_states(s);
    }
    b.build()?.run(Default::default())
}

#[test]
fn initial_rotor_speeds_given_to_the_builder_are_where_the_run_starts() {
    // Hover speed of the crazyflie is about 2 300 rad/s; any value will do.
    let given = [2000.0, 2100.0, 2200.0, 2300.0];
    let run = idle_from(Some(&given)).expect("run");
    assert_eq!(run.samples[0].vehicle_states, given.to_vec());
    // Commanded to zero thrust, the motors spin down from there: every
    // rotor slower at 0.1 s, none stopped yet (first-order lag).
    let last = &run.samples.last().expect("samples").vehicle_states;
    for (k, (w, w0)) in last.iter().zip(&given).enumerate() {
        assert!(*w < *w0 && *w > 0.0, "rotor {k}: {w0} → {w} rad/s");
    }
    // Without them, the run starts where the first command puts the rotors
    // (zero thrust: at rest), and stays there.
    let default = idle_from(None).expect("run");
    assert!(default.samples[0].vehicle_states.iter().all(|w| *w == 0.0));
}

#[test]
fn bad_initial_rotor_speeds_are_refused_naming_the_field() {
    for (speeds, says) in [
        (&[1.0, 2.0, 3.0][..], "3 initial values given, the vehicle"),
        (&[1.0, f64::NAN, 3.0, 4.0][..], "must be finite"),
    ] {
        match idle_from(Some(speeds)) {
            Err(SimError::Setting { field, message }) => {
                assert_eq!(field, "vehicle_states");
                assert!(message.contains(says), "{message}");
            }
            other => panic!("{speeds:?}: expected a setting error, got {other:?}"),
        }
    }
}
