//! The estimator a scene's `[estimator]` table names, built for its
//! sensors: the filters' noise matched to the suite's.

use lie::{Backend, Real, S, So3Mat};
use sensors::{Estimator, Measurement, NavState, SensorSet, SensorSuite};

use crate::Seeds;
use crate::scene::{EstimatorKind, EstimatorSpec};

/// Noise floors a filter assumes for a sensor the suite makes noiseless:
/// a filter that trusted it exactly would stop listening to the IMU.
const FLOOR_GYRO: f64 = 1e-5;
const FLOOR_ACCEL: f64 = 1e-4;
const FLOOR_POSITION: f64 = 1e-4;
const FLOOR_ATTITUDE: f64 = 1e-4;

/// The invariant EKF's settings matched to `suite` (densities and walks of
/// its IMU, σ of its mocap and GPS, each at least its floor).
pub fn iekf_config(spec: &EstimatorSpec, suite: &SensorSuite, gravity: f64) -> sensors::IekfConfig {
    let mut c = sensors::IekfConfig {
        gravity,
        ..sensors::IekfConfig::default()
    };
    if let Some(imu) = suite.imu {
        c.gyro_density = imu.gyro.noise_density.max(FLOOR_GYRO);
        c.accel_density = imu.accel.noise_density.max(FLOOR_ACCEL);
        c.gyro_walk = imu.gyro.random_walk;
        c.accel_walk = imu.accel.random_walk;
        c.mounting = imu.mounting;
        c.initial.gyro_bias = imu.gyro.turn_on_bias.max(c.initial.gyro_bias);
        c.initial.accel_bias = imu.accel.turn_on_bias.max(c.initial.accel_bias);
    }
    if let Some(m) = suite.mocap {
        c.mocap_position = m.position_sigma.max(FLOOR_POSITION);
        c.mocap_attitude = m.attitude_sigma.max(FLOOR_ATTITUDE);
    }
    if let Some(g) = suite.gps {
        c.gps_position = [
            g.horizontal_sigma.max(FLOOR_POSITION),
            g.vertical_sigma.max(FLOOR_POSITION),
        ];
        c.gps_velocity = g.velocity_sigma.max(FLOOR_POSITION);
    }
    let err = spec
        .attitude_error
        .map_or(0.0, |a| a.iter().map(|x| x * x).sum::<f64>().sqrt());
    c.initial.attitude = spec.attitude_sigma.unwrap_or(c.initial.attitude.max(err));
    c
}

/// An estimator behind a box, as the simulation takes it.
type Boxed<B> = Box<dyn Estimator<B>>;

/// The estimator of `spec` for `suite`, or `None` for the truth; the key
/// at fault and why otherwise. The invariant EKF's noise scales are
/// lifted through `seeds` (a gradient may name them).
pub fn build<B: Backend>(
    spec: &EstimatorSpec,
    suite: &SensorSuite,
    gravity: f64,
    seeds: Seeds<'_>,
) -> Result<Option<Boxed<B>>, (&'static str, String)> {
    let mounting = suite.imu.map(|i| i.mounting);
    let named = |e: sensors::SensorError| ("estimator.kind", format!("estimator: {e}"));
    let inner: Box<dyn Estimator<B>> = match spec.kind {
        EstimatorKind::None => return Ok(None),
        EstimatorKind::Mocap => match (spec.gyro_rates, mounting) {
            (true, Some(m)) => {
                let r_bs = lie::ops::from_elems::<B>(m.map(|r| r.map(S::<B>::lit)));
                Box::new(sensors::MocapEstimator::<B>::with_gyro_rates(r_bs))
            }
            _ => Box::new(sensors::MocapEstimator::<B>::new()),
        },
        EstimatorKind::Iekf => {
            let mut f =
                sensors::Iekf::<B>::new(iekf_config(spec, suite, gravity)).map_err(named)?;
            let (q, r) = (spec.q_scale.unwrap_or(1.0), spec.r_scale.unwrap_or(1.0));
            f.set_noise_scales(
                seeds.lift::<B>("estimator.q_scale", q),
                seeds.lift::<B>("estimator.r_scale", r),
            )
            .map_err(|e| ("estimator.q_scale", format!("estimator: {e}")))?;
            // The history spans the longest wait and a margin of a few
            // IMU periods for measurements taken between samples.
            let late = suite
                .mocap
                .map_or(0.0, |m| m.latency)
                .max(suite.gps.map_or(0.0, |g| g.delay));
            if late > 0.0 && spec.compensate_delay != Some(false) {
                Box::new(sensors::Delayed::new(f, late + 0.01).map_err(named)?)
            } else {
                Box::new(f)
            }
        }
        EstimatorKind::FdclEkf => {
            let cfg = sensors::FdclConfig {
                r_bi: mounting.unwrap_or(sensors::FdclConfig::default().r_bi),
                gravity,
                ..sensors::FdclConfig::default()
            };
            Box::new(sensors::FdclEkf::<B>::new(cfg))
        }
        EstimatorKind::Complementary => {
            let cfg = spec.complementary_config(mounting)?;
            Box::new(sensors::Complementary::<B>::new(cfg).map_err(named)?)
        }
    };
    Ok(Some(match spec.attitude_error {
        Some(err) => Box::new(WrongStart { inner, err }),
        None => inner,
    }))
}

/// An estimator told a wrong initial attitude: `R₀ Exp(err)`.
struct WrongStart<B: Backend> {
    inner: Box<dyn Estimator<B>>,
    err: [f64; 3],
}

impl<B: Backend> Estimator<B> for WrongStart<B> {
    fn name(&self) -> &'static str {
        self.inner.name()
    }
    fn needs(&self) -> SensorSet {
        self.inner.needs()
    }
    fn wants(&self) -> SensorSet {
        self.inner.wants()
    }
    fn reset(&mut self, t: f64, initial: &NavState<B>) {
        let e = B::vec3(
            S::<B>::lit(self.err[0]),
            S::<B>::lit(self.err[1]),
            S::<B>::lit(self.err[2]),
        );
        let r = So3Mat::<B>::from_matrix_unchecked(initial.r).compose(So3Mat::exp(e));
        self.inner.reset(
            t,
            &NavState {
                r: r.as_matrix(),
                ..*initial
            },
        );
    }
    fn update(&mut self, m: &Measurement<B>) {
        self.inner.update(m)
    }
    fn estimate(&self, t: f64) -> NavState<B> {
        self.inner.estimate(t)
    }
    fn diagnostics(&self) -> Option<sensors::Diagnostics> {
        self.inner.diagnostics()
    }
}
