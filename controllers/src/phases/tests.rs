use super::*;
use dynamics::paper;
use lie::NalgebraF64;

type B = NalgebraF64;

/// The step from its monomial coefficients (the expanded form, written
/// independently of the factored one under test): `p`, `p′ … p⁗`, `∫p`.
fn monomial(t: f64) -> ([f64; 5], f64) {
    let poly = |c: &[(f64, i32)]| c.iter().map(|(a, k)| a * t.powi(*k)).sum::<f64>();
    let p = poly(&[(126.0, 5), (-420.0, 6), (540.0, 7), (-315.0, 8), (70.0, 9)]);
    let p1 = poly(&[
        (630.0, 4),
        (-2520.0, 5),
        (3780.0, 6),
        (-2520.0, 7),
        (630.0, 8),
    ]);
    let p2 = poly(&[
        (2520.0, 3),
        (-12600.0, 4),
        (22680.0, 5),
        (-17640.0, 6),
        (5040.0, 7),
    ]);
    let p3 = poly(&[
        (7560.0, 2),
        (-50400.0, 3),
        (113400.0, 4),
        (-105840.0, 5),
        (35280.0, 6),
    ]);
    let p4 = poly(&[
        (15120.0, 1),
        (-151200.0, 2),
        (453600.0, 3),
        (-529200.0, 4),
        (211680.0, 5),
    ]);
    let int = poly(&[(21.0, 6), (-60.0, 7), (67.5, 8), (-35.0, 9), (7.0, 10)]);
    ([p, p1, p2, p3, p4], int)
}

#[test]
fn the_step_matches_its_expanded_form() {
    // The coefficients reach 5·10⁵ and cancel to O(1): 1e-9 absolute
    // covers the expanded form's rounding, and no coefficient slip.
    for i in 0..=200 {
        let t = i as f64 / 200.0;
        let (int, p) = step(t);
        let (q, qi) = monomial(t);
        for k in 0..5 {
            assert!(
                (p[k] - q[k]).abs() < 1e-9,
                "p^({k})({t}) {} vs {}",
                p[k],
                q[k]
            );
        }
        assert!((int - qi).abs() < 1e-12, "∫p({t})");
    }
    let (int, p) = step(1.0);
    assert_eq!((p[0], int), (1.0, 0.5));
}

#[test]
fn a_climb_peaks_at_its_rate_and_is_smooth_at_both_ends() {
    let v = Vertical::<B>::Climb {
        height: 1.2,
        rate: 0.4,
    };
    let duration = PEAK_SLOPE * 1.2 / 0.4;
    let peak = (0..=10_000)
        .map(|i| -v.offset(duration * i as f64 / 10_000.0)[1])
        .fold(0.0, f64::max);
    // The peak is at the grid's midpoint: the rate exactly, to rounding.
    assert!((peak - 0.4).abs() < 1e-14, "peak climb {peak}");
    // Derivatives 1–4 vanish at both ends, so the move joins the holds
    // before and after it to the snap (1e-9: a step 1e-9 s inside).
    for s in [1e-9, duration - 1e-9] {
        let o = v.offset(s);
        assert!(o[1..].iter().all(|d| d.abs() < 1e-6), "{o:?} at {s}");
    }
    assert_eq!(v.offset(duration)[0], -1.2);
    assert_eq!(v.offset(duration + 3.0), [-1.2, 0.0, 0.0, 0.0, 0.0]);
    assert_eq!(v.offset(-1.0), [0.0; 5]);
}

#[test]
fn the_moves_derivatives_match_central_differences() {
    let moves = [
        Vertical::<B>::Climb {
            height: 1.0,
            rate: 0.5,
        },
        Vertical::<B>::Descend {
            rate: 0.3,
            ramp: 0.8,
        },
    ];
    let h = 1e-5;
    for v in moves {
        for i in 1..60 {
            let s = 0.09 * i as f64;
            let (a, b, c) = (v.offset(s - h), v.offset(s), v.offset(s + h));
            for k in 0..4 {
                let fd = (c[k] - a[k]) / (2.0 * h);
                // O(h²)·(fifth derivative ≲ 10³) plus rounding ε·|x|/h.
                let tol = 1e-6 * (1.0 + b[k + 1].abs());
                assert!(
                    (fd - b[k + 1]).abs() < tol,
                    "{v:?} d{k} at {s}: {fd} vs {}",
                    b[k + 1]
                );
            }
        }
    }
}

#[test]
fn a_descent_keeps_its_rate_after_the_ramp_continuously() {
    let v = Vertical::<B>::Descend {
        rate: 0.25,
        ramp: 1.0,
    };
    let (a, b) = (v.offset(1.0 - 1e-9), v.offset(1.0 + 1e-9));
    for k in 0..5 {
        assert!((a[k] - b[k]).abs() < 1e-6, "d{k}: {} vs {}", a[k], b[k]);
    }
    // Past the ramp: half the ramp at the mean speed, then the rate.
    let o = v.offset(5.0);
    assert!((o[0] - 0.25 * (0.5 + 4.0)).abs() < 1e-15);
    assert_eq!(o[1..], [0.25, 0.0, 0.0, 0.0]);
}

#[test]
fn bad_numbers_are_named() {
    let v = |height, rate, ramp| {
        [
            Vertical::<B>::Climb { height, rate },
            Vertical::<B>::Descend { rate, ramp },
        ]
    };
    assert_eq!(v(0.0, 1.0, 1.0)[0].check(), Err(("height", 0.0)));
    assert_eq!(v(1.0, -1.0, 1.0)[0].check(), Err(("rate", -1.0)));
    assert_eq!(v(1.0, -1.0, 1.0)[1].check(), Err(("rate", -1.0)));
    assert!(matches!(v(1.0, 1.0, f64::NAN)[1].check(), Err(("ramp", r)) if r.is_nan()));
    assert_eq!(v(1.0, 1.0, 1.0)[1].check(), Ok(()));
}

fn phase(vertical: Vertical<B>) -> FlightPhase<B> {
    let params = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let zero = B::vec3(0.0, 0.0, 0.0);
    let rest = VehicleState {
        x: zero,
        v: zero,
        r: So3Mat::<B>::identity(),
        omega: zero,
    };
    FlightPhase::new(
        params,
        (PositionGains::paper(), AttitudeGains::paper()),
        AccelerationModel::Nominal,
        vertical,
        (&rest, 0.0),
    )
}

#[test]
fn entering_a_phase_anchors_it_where_the_vehicle_is() {
    let yawed = So3Mat::<B>::exp(B::vec3(0.0, 0.0, 0.7));
    let state = VehicleState {
        x: B::vec3(1.0, -2.0, -3.0),
        v: B::vec3(0.5, 0.0, 0.0),
        r: yawed,
        omega: B::vec3(0.0, 0.0, 0.0),
    };
    let mut ints = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
    let mut land = phase(Vertical::Descend {
        rate: 0.3,
        ramp: 1.0,
    });
    land.enter(4.0, &state, &mut ints);
    assert_eq!(land.name(), "land");
    assert_eq!(ints, [1.0, 2.0, 3.0, 4.0, 5.0, 6.0], "landing keeps e_i");
    let r = land.reference().position(4.0);
    assert_eq!(B::vec3_to_array(r.x), [1.0, -2.0, -3.0]);
    let b1 = B::vec3_to_array(r.b1d);
    assert!((b1[0] - 0.7f64.cos()).abs() < 1e-15 && (b1[1] - 0.7f64.sin()).abs() < 1e-15);
    assert_eq!(land.desired_position(14.0).unwrap()[2], -3.0 + 0.3 * 9.5);

    let mut up = phase(Vertical::Climb {
        height: 1.0,
        rate: 0.5,
    });
    up.enter(4.0, &state, &mut ints);
    assert_eq!(up.name(), "take-off");
    assert_eq!(ints, [1.0, 2.0, 3.0, 0.0, 0.0, 0.0], "take-off zeroes e_i");
    assert_eq!(up.desired_position(100.0), Some([1.0, -2.0, -4.0]));
    assert_eq!(phase(Vertical::Hold).name(), "hover");
}

#[test]
fn motors_off_commands_nothing() {
    let zero = B::vec3(0.0, 0.0, 0.0);
    let state = VehicleState {
        x: zero,
        v: B::vec3(0.0, 0.0, 1.0),
        r: So3Mat::<B>::exp(B::vec3(0.1, 0.2, 0.3)),
        omega: B::vec3(1.0, 0.0, 0.0),
    };
    let out = Mode::<B>::command(&MotorsOff, 0.0, &state, &[], &mut []).unwrap();
    assert_eq!(out.thrust, 0.0);
    assert_eq!(B::vec3_to_array(out.moment), [0.0; 3]);
    assert_eq!(Mode::<B>::integrals(&MotorsOff).count, 0);
}
