//! The multi-rate loop: the position law's output held between its
//! instants against the controllers' own functions called at the recorded
//! states, its instants counted where the rates do not divide, equal rates
//! as the single-rate loop, and the estimator's own rate.

use controllers::{
    AccelerationModel, AttitudeGains, AttitudeReference, Mode, PositionGains, PositionInput,
    PositionMode, PositionReference, RigidBodyParams, VehicleState, attitude_control,
    position_control,
};
use dynamics::{Quadrotor, RigidBodyState, paper};
use lie::{NalgebraF64, So3Mat, V3};
use scenarios::{Control, LoopRates, RunOutput, Sample, Simulation, Until};
use sensors::{MocapEstimator, MocapSpec, SensorSuite};

type B = NalgebraF64;

fn v3(a: [f64; 3]) -> V3<B> {
    B::vec3(a[0], a[1], a[2])
}

fn params() -> RigidBodyParams<B> {
    RigidBodyParams::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY)
}

/// A 1 m circle at 1 rad/s at 1 m height (e3 down), heading e1: smooth to
/// the snap, so every term of the position law is in play.
fn circle(t: f64) -> PositionReference<B> {
    let (s, c) = t.sin_cos();
    let mut r = PositionReference::<B>::hold(B::vec3(c, s, -1.0), B::vec3(1.0, 0.0, 0.0));
    r.v = B::vec3(-s, c, 0.0);
    r.a = B::vec3(-c, -s, 0.0);
    r.jerk = B::vec3(s, -c, 0.0);
    r.snap = B::vec3(c, s, 0.0);
    r
}

fn circle_mode() -> PositionMode<B, fn(f64) -> PositionReference<B>> {
    PositionMode::new(
        params(),
        PositionGains::paper(),
        AttitudeGains::paper(),
        AccelerationModel::Nominal,
        circle as fn(f64) -> PositionReference<B>,
    )
}

fn start() -> RigidBodyState<B> {
    let mut s = RigidBodyState::<B>::at_rest();
    s.x = B::vec3(1.2, -0.1, -0.8);
    s
}

fn fly<M: Mode<B> + 'static>(mode: M, control: Control, duration: f64) -> RunOutput {
    fly_recorded(mode, control, duration, 0.002)
}

fn fly_recorded<M: Mode<B> + 'static>(
    mode: M,
    control: Control,
    duration: f64,
    record: f64,
) -> RunOutput {
    Simulation::<B>::builder(Box::new(Quadrotor::<B>::paper()))
        .mode(mode, Until::Never)
        .initial(start())
        .dt(1e-3)
        .duration(duration)
        .record_every(record)
        .control(control)
        .build()
        .unwrap()
        .run(Default::default())
        .unwrap()
}

fn state(s: &Sample) -> VehicleState<B, So3Mat<B>> {
    VehicleState {
        x: v3(s.x),
        v: v3(s.v),
        r: So3Mat::<B>::from_matrix_unchecked(B::mat3_transpose(B::mat3_from_cols(
            v3(s.r[0]),
            v3(s.r[1]),
            v3(s.r[2]),
        ))),
        omega: v3(s.omega),
    }
}

/// Attitude at 500 Hz, position at 100 Hz, recorded at every attitude
/// instant: at each one, the thrust is `position_control`'s at the state
/// and integrals recorded at the last position instant, and the moment is
/// `attitude_control`'s at the state now tracking that instant's `R_c,
/// Ω_c, Ω̇_c`, both bit for bit (the same functions on the same f64s);
/// the thrust changes only at position instants, and the loop tracks the
/// circle (‖e_x‖ under 5 cm after 4 s; single-rate at 500 Hz: the same
/// within 1 cm).
#[test]
fn the_position_law_is_held_between_its_instants() {
    let rates = LoopRates {
        estimator: 500.0,
        attitude: 500.0,
        position: 100.0,
    };
    let out = fly(circle_mode(), Control::MultiRate(rates), 5.0);
    let mut outer: Option<(&Sample, controllers::PositionOutput<B, So3Mat<B>>)> = None;
    let mut checked = 0;
    for (k, s) in out.samples.iter().enumerate() {
        // Sample k is attitude instant k (both are k · 2 ms).
        if k % 5 == 0 {
            let p = position_control(
                &params(),
                &PositionGains::paper(),
                &AttitudeGains::paper(),
                &PositionInput {
                    state: &state(s),
                    e_i_pos: v3(s.e_pos),
                    e_i_att: v3(s.e_att),
                    reference: &circle(s.t),
                    model: AccelerationModel::Nominal,
                },
            )
            .unwrap();
            outer = Some((s, p));
        } else if let Some(prev) = out.samples.get(k - 1) {
            assert_eq!(prev.thrust, s.thrust, "t = {}: held", s.t);
        }
        let (at, p) = outer.as_ref().unwrap();
        assert_eq!(s.thrust, p.thrust, "t = {} (outer {})", s.t, at.t);
        let now = state(s);
        let m = attitude_control(
            &params(),
            &AttitudeGains::paper(),
            now.r,
            now.omega,
            v3(s.e_att),
            &AttitudeReference {
                rd: p.rc,
                omega_d: p.omega_c,
                omega_d_dot: p.omega_c_dot,
            },
        )
        .unwrap();
        assert_eq!(
            s.moment,
            [m.moment[0], m.moment[1], m.moment[2]],
            "t = {}",
            s.t
        );
        checked += 1;
    }
    assert_eq!(checked, 2501);
    let single = fly(circle_mode(), Control::Sampled { rate: 500.0 }, 5.0);
    let tail = |o: &RunOutput| {
        o.samples
            .iter()
            .filter(|s| s.t >= 4.0)
            .fold(0.0f64, |a, s| a.max(s.ex))
    };
    let (multi_e, single_e) = (tail(&out), tail(&single));
    println!("max ‖e_x‖ over [4, 5] s: 500/100 Hz {multi_e:.3e} m, 500 Hz {single_e:.3e} m");
    assert!(multi_e < 0.05 && (multi_e - single_e).abs() < 0.01);
}

/// Rates that do not divide (attitude 300 Hz, position 70 Hz), recorded
/// at 10 kHz: the outer loop runs at each instant `k/70` (computed as
/// `k·(1/70)`, never summed) and the motor command, a zero-order hold
/// renewed by the attitude loop, takes its new thrust at the first
/// attitude instant `j/300` at or after it, `j = ⌈30k/7⌉`, as a flight
/// computer's attitude task reads the latest position setpoint at its own
/// tick. So the recorded thrust changes once per outer instant, 70 times
/// over 1 s, at those attitude instants only. A single-rate loop at 300
/// Hz changes it at every one of its own instants instead.
#[test]
fn outer_instants_where_the_rates_do_not_divide() {
    let rates = LoopRates {
        estimator: 300.0,
        attitude: 300.0,
        position: 70.0,
    };
    let changes = |control: Control, duration: f64| -> Vec<(f64, f64)> {
        let out = fly_recorded(circle_mode(), control, duration, 1e-4);
        out.samples
            .windows(2)
            .filter(|w| w[0].thrust != w[1].thrust)
            .map(|w| (w[0].t, w[1].t))
            .collect()
    };
    // An instant `c` is in `(a, b]`; 1e-12 s covers the rounding of the
    // recorded times, far below the 1e-4 s between samples.
    let inside = |(a, b): (f64, f64), c: f64| c > a + 1e-12 && c <= b + 1e-12;
    let multi = changes(Control::MultiRate(rates), 1.0);
    let takes: Vec<f64> = (1..=70)
        .map(|k| ((30 * k + 6) / 7) as f64 * (1.0 / 300.0))
        .collect();
    assert_eq!(multi.len(), takes.len(), "{multi:?}");
    for (k, (w, c)) in multi.iter().zip(&takes).enumerate() {
        assert!(inside(*w, *c), "change {k} at {w:?}, attitude instant {c}");
    }
    let single = changes(Control::Sampled { rate: 300.0 }, 0.2);
    assert_eq!(single.len(), 60, "{single:?}");
    for (k, w) in single.iter().enumerate() {
        assert!(
            inside(*w, (k + 1) as f64 * (1.0 / 300.0)),
            "change {k} at {w:?}"
        );
    }
}

/// Equal attitude and position rates are the single-rate loop, bit for
/// bit: every sample and the final state.
#[test]
fn equal_rates_are_the_single_rate_loop() {
    let rates = LoopRates {
        estimator: 250.0,
        attitude: 250.0,
        position: 250.0,
    };
    let multi = fly(circle_mode(), Control::MultiRate(rates), 2.0);
    let single = fly(circle_mode(), Control::Sampled { rate: 250.0 }, 2.0);
    assert_eq!(multi.samples.len(), single.samples.len());
    for (a, b) in multi.samples.iter().zip(&single.samples) {
        assert_eq!(
            (a.t, a.x, a.r, a.thrust, a.moment),
            (b.t, b.x, b.r, b.thrust, b.moment)
        );
    }
}

fn fly_estimated(estimator_rate: f64) -> RunOutput {
    let rates = LoopRates {
        estimator: estimator_rate,
        attitude: 500.0,
        position: 100.0,
    };
    let mut mocap = MocapSpec::perfect(100.0);
    mocap.latency = 0.004;
    Simulation::<B>::builder(Box::new(Quadrotor::<B>::paper()))
        .mode(circle_mode(), Until::Never)
        .initial(start())
        .dt(1e-3)
        .duration(2.0)
        .record_every(0.01)
        .control(Control::MultiRate(rates))
        .sensors(
            SensorSuite {
                mocap: Some(mocap),
                ..SensorSuite::default()
            },
            7,
        )
        .estimator(Box::new(MocapEstimator::<B>::new()))
        .build()
        .unwrap()
        .run(Default::default())
        .unwrap()
}

/// The estimator's rate: mocap frames every 10 ms arriving 4 ms late, so
/// a new estimate exists from `k·10 + 4` ms. An estimator at 250 Hz
/// (instants every 4 ms: 4, 8, 12, 16, … ms) sees frame `k` at `10k + 4`
/// only when that is a multiple of 4, later otherwise; at 1 kHz it sees
/// every frame on arrival, as the estimator at every control instant
/// does at 500 Hz (2 ms divides both 10 and 4): those two fly the same
/// trajectory bit for bit, the 250 Hz one another.
#[test]
fn the_estimate_is_taken_at_the_estimators_instants() {
    let fast = fly_estimated(1000.0);
    let every = fly_estimated(500.0);
    let slow = fly_estimated(250.0);
    assert_eq!(fast.last.x, every.last.x);
    assert_eq!(fast.last.r, every.last.r);
    let d = (0..3)
        .map(|i| (fast.last.x[i] - slow.last.x[i]).abs())
        .fold(0.0, f64::max);
    println!("final position, estimator at 1 kHz against 250 Hz: {d:.3e} m");
    assert!(d > 1e-9, "a later estimate changes the flight");
}

/// Bad rates are refused before the first step, naming the rate.
#[test]
fn bad_rates_are_refused() {
    for (rates, word) in [
        (
            LoopRates {
                position: 600.0,
                ..LoopRates::crazyflie()
            },
            "position rate 600",
        ),
        (
            LoopRates {
                attitude: f64::NAN,
                ..LoopRates::crazyflie()
            },
            "attitude rate NaN",
        ),
        (
            LoopRates {
                estimator: 0.0,
                ..LoopRates::crazyflie()
            },
            "estimator rate 0",
        ),
    ] {
        let err = Simulation::<B>::builder(Box::new(Quadrotor::<B>::paper()))
            .mode(circle_mode(), Until::Never)
            .control(Control::MultiRate(rates))
            .build()
            .err()
            .expect("refused");
        assert!(err.to_string().contains(word), "{err}");
    }
}
