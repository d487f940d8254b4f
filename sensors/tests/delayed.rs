//! Late measurements: the invariant EKF applying a mocap frame 20 ms late
//! and a GPS fix 0.2 s late at the instant each describes (`Delayed`),
//! against applying them when they arrive; and with nothing late, the
//! wrapper is the filter bit for bit.

mod motion;
use lie::{So3Mat, ops};
use motion::{B, G, truth, v};
use sensors::{
    Delayed, Estimator, Gps, GpsSpec, Iekf, IekfConfig, Imu, ImuSpec, Measurement, Mocap,
    MocapSpec, NavState, NoiseKey,
};

/// Every measurement of `secs` s with its arrival time, in arrival order
/// (ties in the order taken): IMU at 1 kHz, mocap at 100 Hz `latency` s
/// late when given, GPS at 10 Hz `delay` s late when given.
fn stream(secs: f64, mocap: Option<f64>, gps: Option<f64>) -> Vec<(f64, Measurement<B>)> {
    let mut imu = Imu::<B>::new(ImuSpec::crazyflie(), NoiseKey::new(9, 0)).unwrap();
    let mc = Mocap::new(MocapSpec::crazyflie(), NoiseKey::new(9, 1)).unwrap();
    let gp = Gps::new(gps_spec(), NoiseKey::new(9, 2)).unwrap();
    let mut out = vec![];
    for k in 0..=(secs * 1000.0) as u64 {
        let t = k as f64 / 1000.0;
        let (r, vel, x, a, w) = truth(t);
        let kin = sensors::Kinematics::<B> {
            r: r.as_matrix(),
            omega: w,
            accel: a,
            alpha: v([0.0; 3]),
        };
        out.push((t, Measurement::Imu(imu.sample(k, &kin, G).unwrap())));
        if let Some(late) = mocap
            && k % 10 == 0
            && let Some(m) = mc.frame::<B>(k / 10, x, vel, r.as_matrix(), w)
        {
            out.push((t + late, Measurement::Mocap(m)));
        }
        if let Some(late) = gps
            && k % 100 == 0
        {
            out.push((t + late, Measurement::Gps(gp.fix::<B>(k / 100, x, vel))));
        }
    }
    // Stable: equal arrivals keep the order they were taken in.
    out.sort_by(|a, b| a.0.total_cmp(&b.0));
    out
}

fn gps_spec() -> GpsSpec {
    GpsSpec {
        rate: 10.0,
        delay: 0.0,
        horizontal_sigma: 0.05,
        vertical_sigma: 0.1,
        velocity_sigma: 0.05,
    }
}

fn config() -> IekfConfig {
    let (imu, m, g) = (ImuSpec::crazyflie(), MocapSpec::crazyflie(), gps_spec());
    IekfConfig {
        gyro_density: imu.gyro.noise_density,
        accel_density: imu.accel.noise_density,
        gyro_walk: 1e-6,
        accel_walk: 1e-5,
        mocap_position: m.position_sigma,
        mocap_attitude: m.attitude_sigma,
        gps_position: [g.horizontal_sigma, g.vertical_sigma],
        gps_velocity: g.velocity_sigma,
        gravity: G,
        ..IekfConfig::default()
    }
}

fn start() -> NavState<B> {
    let (r, vel, x, _, _) = truth(0.0);
    NavState {
        x,
        v: vel,
        r: r.as_matrix(),
        omega: v([0.0; 3]),
    }
}

/// The estimate every 10 ms after delivering what has arrived; RMS
/// position and attitude errors after 2 s.
fn fly(est: &mut dyn Estimator<B>, events: &[(f64, Measurement<B>)], secs: f64) -> (f64, f64) {
    est.reset(0.0, &start());
    let (mut next, mut sp, mut sa, mut n) = (0usize, 0.0f64, 0.0f64, 0.0f64);
    for k in 1..=(secs * 100.0) as u64 {
        let t = k as f64 / 100.0;
        while next < events.len() && events[next].0 <= t + 1e-12 {
            est.update(&events[next].1);
            next += 1;
        }
        if t < 2.0 {
            continue;
        }
        let e = est.estimate(t);
        let (r, _, x, _, _) = truth(t);
        let dx = ops::vec3_f64::<B>(e.x - x);
        sp += dx.iter().map(|d| d * d).sum::<f64>();
        let da = So3Mat::<B>::from_matrix_unchecked(e.r)
            .inverse()
            .compose(r)
            .log();
        sa += ops::norm::<B>(da).powi(2);
        n += 1.0;
    }
    ((sp / n).sqrt(), (sa / n).sqrt())
}

#[test]
fn with_nothing_late_the_wrapper_is_the_filter_bit_for_bit() {
    let events = stream(3.0, Some(0.0), Some(0.0));
    let mut plain = Iekf::<B>::new(config()).unwrap();
    let mut wrapped = Delayed::new(Iekf::<B>::new(config()).unwrap(), 0.3).unwrap();
    plain.reset(0.0, &start());
    wrapped.reset(0.0, &start());
    for (i, (t, m)) in events.iter().enumerate() {
        plain.update(m);
        wrapped.update(m);
        if i % 7 == 0 {
            let (a, b) = (plain.estimate(*t + 3e-4), wrapped.estimate(*t + 3e-4));
            assert_eq!(ops::vec3_f64::<B>(a.x), ops::vec3_f64::<B>(b.x), "at {t}");
            assert_eq!(ops::mat3_f64::<B>(a.r), ops::mat3_f64::<B>(b.r), "at {t}");
        }
    }
    assert_eq!(plain.covariance(), wrapped.filter().covariance());
    assert_eq!(wrapped.replayed(), 0);
}

#[test]
fn late_measurements_applied_at_their_capture_time() {
    let secs = 20.0;
    let cases = [
        ("mocap 20 ms late", Some(0.02), None),
        ("GPS 0.2 s late", None, Some(0.2)),
        ("mocap 20 ms and GPS 0.2 s late", Some(0.02), Some(0.2)),
    ];
    for (name, mocap, gps) in cases {
        let events = stream(secs, mocap, gps);
        let mut on_arrival = Iekf::<B>::new(config()).unwrap();
        let mut compensated = Delayed::new(Iekf::<B>::new(config()).unwrap(), 0.25).unwrap();
        let (pa, aa) = fly(&mut on_arrival, &events, secs);
        let (pc, ac) = fly(&mut compensated, &events, secs);
        // And the reference: the same measurements on time.
        let on_time = stream(secs, mocap.map(|_| 0.0), gps.map(|_| 0.0));
        let (p0, a0) = fly(&mut Iekf::<B>::new(config()).unwrap(), &on_time, secs);
        println!(
            "{name}: RMS position / attitude error: on arrival {:.2} mm / {:.2} mrad, compensated {:.2} mm / {:.2} mrad (on time {:.2} mm / {:.2} mrad); {} replayed, {} refused",
            pa * 1e3,
            aa * 1e3,
            pc * 1e3,
            ac * 1e3,
            p0 * 1e3,
            a0 * 1e3,
            compensated.replayed(),
            compensated.rejections()
        );
        assert_eq!(compensated.rejections(), 0);
        // Compensated, the delay costs only the IMU's dead reckoning over
        // it; on arrival, a measurement of where the vehicle was is read
        // as where it is (0.5 m/s × 20 ms = 1 cm, × 0.2 s = 10 cm).
        assert!(pc < pa, "{name}: {pc} ≥ {pa}");
        assert!(pc < 2.0 * p0 + 1e-3, "{name}: {pc} against {p0} on time");
    }
}

#[test]
fn a_measurement_older_than_the_history_is_refused() {
    let mut f = Delayed::new(Iekf::<B>::new(config()).unwrap(), 0.1).unwrap();
    f.reset(0.0, &start());
    let events = stream(1.0, None, None);
    for (_, m) in &events {
        f.update(m);
    }
    let (r, vel, x, _, w) = truth(0.5);
    let old = Mocap::new(MocapSpec::crazyflie(), NoiseKey::new(9, 1))
        .unwrap()
        .frame::<B>(50, x, vel, r.as_matrix(), w)
        .unwrap();
    let before = f.estimate(1.0);
    f.update(&Measurement::Mocap(old));
    assert_eq!(f.rejections(), 1);
    assert_eq!(
        ops::vec3_f64::<B>(f.estimate(1.0).x),
        ops::vec3_f64::<B>(before.x)
    );
    let e = Delayed::new(Iekf::<B>::new(config()).unwrap(), -1.0).unwrap_err();
    assert_eq!(
        e.to_string(),
        "delayed.horizon = -1: must be finite and not negative (s)"
    );
}
