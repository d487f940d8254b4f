//! The sensors of a run, what they measured and not yet delivered, and
//! the estimator: the state [`super::sense`] drives from the stepping loop.

use std::collections::VecDeque;

use integrators::{State, dense};
use lie::{Backend, Real, S};
use sensors::{
    Baro, Estimator, Gps, Imu, Kinematics, Measurement, Mocap, NavState, NoiseKey, SensorSuite,
};

use super::SimError;
use super::readout::{MeasurementRecord, NavSample, Readout};

/// The sensors' numbers in their noise keys (the seed's streams): fixed,
/// so a sensor's noise does not depend on which others are on.
pub(super) const IMU: usize = 0;
pub(super) const MOCAP: usize = 1;
pub(super) const GPS: usize = 2;
pub(super) const BARO: usize = 3;

/// What the builder was told of sensors and an estimator.
pub(super) struct Settings<'a, B: Backend> {
    pub suite: SensorSuite,
    pub seed: u64,
    pub estimator: Option<Box<dyn Estimator<B> + 'a>>,
}

impl<B: Backend> Default for Settings<'_, B> {
    fn default() -> Self {
        Self {
            suite: SensorSuite::default(),
            seed: 0,
            estimator: None,
        }
    }
}

impl<'a, B: Backend> Settings<'a, B> {
    /// The run's sensing (`None` without sensors or an estimator), every
    /// setting checked: the sensors' specs, latencies shorter than the
    /// run, an estimator under sampled control with the sensors it needs.
    pub fn build(
        self,
        control: super::Control,
        duration: f64,
    ) -> Result<Option<Box<Sensing<'a, B>>>, SimError> {
        let bad = |field, message| SimError::Setting { field, message };
        if self.suite.is_empty() && self.estimator.is_none() {
            return Ok(None);
        }
        self.suite
            .validate()
            .map_err(|source| SimError::Sensor { t: 0.0, source })?;
        let late = [
            ("mocap.latency", self.suite.mocap.map(|m| m.latency)),
            ("gps.delay", self.suite.gps.map(|g| g.delay)),
        ];
        for (field, d) in late {
            if let Some(d) = d
                && d >= duration
            {
                return Err(bad(
                    "sensors",
                    format!(
                        "{field} = {d} s is not shorter than the run ({duration} s): nothing would arrive"
                    ),
                ));
            }
        }
        if let Some(e) = &self.estimator {
            if control.command_rate().is_none() {
                return Err(bad(
                    "estimator",
                    format!(
                        "`{}` needs sampled control (the mode reads its estimate at the control instants): set a control rate",
                        e.name()
                    ),
                ));
            }
            if let Some(s) = e.needs().first_missing(&self.suite.set()) {
                return Err(bad(
                    "estimator",
                    format!("`{}` needs the sensor `{s}`, which the run lacks", e.name()),
                ));
            }
        }
        let mut s = Sensing::new(&self.suite, self.seed, self.estimator)
            .map_err(|source| SimError::Sensor { t: 0.0, source })?;
        if let super::Control::MultiRate(r) = control {
            s.estimator_period = 1.0 / r.estimator;
        }
        Ok(Some(Box::new(s)))
    }
}

/// The sensors of a run, what they have measured and not yet delivered,
/// and the estimator.
pub(crate) struct Sensing<'a, B: Backend> {
    imu: Option<Imu<B>>,
    mocap: Option<Mocap>,
    gps: Option<Gps>,
    baro: Option<Baro>,
    /// Each sensor's next sample index (IMU, mocap, GPS, barometer).
    next: [u64; 4],
    /// Each sensor's rate, Hz (0 without the sensor).
    rate: [f64; 4],
    /// Each sensor's next sample instant and its tolerance (∞ without
    /// the sensor).
    due: [(f64, f64); 4],
    /// Taken and not yet delivered: `(arrival, measurement)`, in arrival
    /// order (capture order among equal arrivals).
    queue: [VecDeque<(f64, Measurement<B>)>; 4],
    /// The sensors whose measurements the estimator reads (the others are
    /// not queued).
    wanted: [bool; 4],
    estimator: Option<Box<dyn Estimator<B> + 'a>>,
    /// The estimate of the last control instant.
    estimate: Option<NavState<B>>,
    /// A multi-rate loop's estimator period (0: the estimate is taken at
    /// each control instant).
    estimator_period: f64,
    /// The latest of each measurement and the estimate, in `f64`.
    pub latest: Readout,
    /// Every measurement taken (when the run keeps them).
    pub log: Vec<MeasurementRecord>,
    /// Whether the run records samples or feeds a sink: without either,
    /// the measurements are neither logged nor read out into `latest`
    /// (nothing would read them); the estimate always is.
    pub keep: bool,
}

impl<'a, B: Backend> Sensing<'a, B> {
    /// The sensors of `suite` keyed on `seed`, and `estimator`.
    pub fn new(
        suite: &SensorSuite,
        seed: u64,
        estimator: Option<Box<dyn Estimator<B> + 'a>>,
    ) -> Result<Self, sensors::SensorError> {
        let key = |s: usize| NoiseKey::new(seed, s as u64);
        let rate = [
            suite.imu.map(|s| s.rate),
            suite.mocap.map(|s| s.rate),
            suite.gps.map(|s| s.rate),
            suite.baro.map(|s| s.rate),
        ]
        .map(|r| r.unwrap_or(0.0));
        Ok(Self {
            rate,
            due: rate.map(|f| {
                if f > 0.0 {
                    (0.0, 1e-9 / f)
                } else {
                    (f64::INFINITY, 0.0)
                }
            }),
            imu: suite.imu.map(|s| Imu::new(s, key(IMU))).transpose()?,
            mocap: suite.mocap.map(|s| Mocap::new(s, key(MOCAP))).transpose()?,
            gps: suite.gps.map(|s| Gps::new(s, key(GPS))).transpose()?,
            baro: suite.baro.map(|s| Baro::new(s, key(BARO))).transpose()?,
            next: [0; 4],
            queue: Default::default(),
            wanted: match &estimator {
                Some(e) => {
                    let w = e.wants();
                    [w.imu, w.mocap, w.gps, w.baro]
                }
                None => [false; 4],
            },
            estimator,
            estimate: None,
            estimator_period: 0.0,
            latest: Readout::default(),
            log: Vec::new(),
            keep: true,
        })
    }

    /// Whether an estimator stands between the sensors and the mode.
    pub fn estimating(&self) -> bool {
        self.estimator.is_some()
    }

    /// The time of sensor `s`'s next sample and its tolerance (∞ without
    /// the sensor).
    #[inline]
    pub(super) fn due(&self, s: usize) -> (f64, f64) {
        self.due[s]
    }

    /// The earliest next sample instant of any sensor, less its tolerance.
    #[inline]
    pub(super) fn earliest(&self) -> f64 {
        self.due
            .iter()
            .fold(f64::INFINITY, |a, (t, tol)| a.min(t - tol))
    }

    /// Queues sensor `s`'s measurement `m`, arriving at `arrival`, when
    /// the estimator reads that sensor. A sensor's latency is constant, so
    /// its own queue is in arrival order.
    fn push(&mut self, s: usize, arrival: f64, m: Measurement<B>) {
        if self.wanted[s] {
            self.queue[s].push_back((arrival, m));
        }
    }

    /// Sensor `s`'s next sample of the true state `y` at its instant `tk`
    /// (`rates` the state's rates there, for the IMU).
    pub(super) fn take<const N: usize>(
        &mut self,
        s: usize,
        tk: f64,
        y: &State<B, N>,
        rates: Option<&dense::Rates<B, N>>,
        g: S<B>,
    ) -> Result<(), SimError> {
        let k = self.next[s];
        self.next[s] += 1;
        // A product, never a sum.
        self.due[s].0 = self.next[s] as f64 / self.rate[s];
        let b = &y.body;
        let sensor_error = |e| SimError::Sensor { t: tk, source: e };
        match s {
            IMU => {
                let (Some(imu), Some(r)) = (self.imu.as_mut(), rates) else {
                    return Ok(());
                };
                let kin = Kinematics {
                    r: b.r,
                    omega: b.omega,
                    accel: r.v_dot,
                    alpha: r.omega_dot,
                };
                let m = imu.sample(k, &kin, g).map_err(sensor_error)?;
                self.note(
                    |r| {
                        r.accel = Some(lie::ops::vec3_f64::<B>(m.accel));
                        r.gyro = Some(lie::ops::vec3_f64::<B>(m.gyro));
                    },
                    || MeasurementRecord::imu::<B>(&m),
                );
                self.push(IMU, tk, Measurement::Imu(m));
            }
            MOCAP => {
                let Some(mocap) = self.mocap.as_ref() else {
                    return Ok(());
                };
                let latency = mocap.spec().latency;
                if let Some(m) = mocap.frame::<B>(k, b.x, b.v, b.r, b.omega) {
                    self.note(
                        |r| r.mocap_x = Some(lie::ops::vec3_f64::<B>(m.x)),
                        || MeasurementRecord::mocap::<B>(&m, tk + latency),
                    );
                    self.push(MOCAP, tk + latency, Measurement::Mocap(m));
                }
            }
            GPS => {
                let Some(gps) = self.gps.as_ref() else {
                    return Ok(());
                };
                let delay = gps.spec().delay;
                let m = gps.fix::<B>(k, b.x, b.v);
                self.note(
                    |r| r.gps_x = Some(lie::ops::vec3_f64::<B>(m.x)),
                    || MeasurementRecord::gps::<B>(&m, tk + delay),
                );
                self.push(GPS, tk + delay, Measurement::Gps(m));
            }
            _ => {
                let Some(baro) = self.baro.as_mut() else {
                    return Ok(());
                };
                let height = -B::vec3_to_array(b.x)[2].to_f64_lossless();
                let m = baro.sample(k, height).map_err(sensor_error)?;
                self.note(
                    |r| r.baro = Some(m.height),
                    || MeasurementRecord::Baro {
                        t: m.t,
                        height: m.height,
                    },
                );
                self.push(BARO, tk, Measurement::Baro(m));
            }
        }
        Ok(())
    }

    /// A measurement's readout into `latest` and its log record, made only
    /// when the run keeps them.
    #[inline]
    fn note(
        &mut self,
        read: impl FnOnce(&mut Readout),
        record: impl FnOnce() -> MeasurementRecord,
    ) {
        if self.keep {
            read(&mut self.latest);
            self.log.push(record());
        }
    }

    /// Starts the estimator from the true state `y` at `t = 0`.
    pub fn reset<const N: usize>(&mut self, y: &State<B, N>) {
        if let Some(e) = self.estimator.as_mut() {
            e.reset(0.0, &nav(y));
        }
    }

    /// Hands the estimator every measurement arrived by `t` and keeps its
    /// estimate for the control instant `t`; in a multi-rate loop, by the
    /// last estimator instant `k / rate` at or before `t` instead.
    pub fn refresh(&mut self, t: f64) {
        let Some(e) = self.estimator.as_mut() else {
            return;
        };
        let p = self.estimator_period;
        let t = if p > 0.0 {
            // The instant's index from the quotient, rounded up when `t`
            // is on it to within rounding.
            let q = t / p;
            let k = if (q - q.round()).abs() <= 1e-9 * q.abs().max(1.0) {
                q.round()
            } else {
                q.floor()
            };
            k * p
        } else {
            t
        };
        let tol = 1e-9 * t.abs().max(1e-3);
        // Every queue's arrived measurements, merged in arrival order (by
        // capture time, then sensor, among equal arrivals).
        loop {
            let next = (0..4)
                .filter_map(|s| {
                    let (a, m) = self.queue[s].front()?;
                    (*a <= t + tol).then_some((*a, m.captured(), s))
                })
                .min_by(|x, y| x.0.total_cmp(&y.0).then(x.1.total_cmp(&y.1)));
            let Some((_, _, s)) = next else { break };
            if let Some((_, m)) = self.queue[s].pop_front() {
                e.update(&m);
            }
        }
        let est = e.estimate(t);
        self.latest.estimate = Some(NavSample::of::<B>(&est));
        // Only a record reads the filter's σ and NIS.
        if self.keep {
            self.latest.diagnostics = e.diagnostics();
        }
        self.estimate = Some(est);
    }

    /// `y` with its body replaced by the estimate (`y` itself without an
    /// estimator): what the flight mode reads.
    pub fn estimated<const N: usize>(&self, y: &State<B, N>) -> State<B, N> {
        let mut ye = *y;
        if let Some(e) = &self.estimate {
            ye.body.x = e.x;
            ye.body.v = e.v;
            ye.body.r = e.r;
            ye.body.omega = e.omega;
        }
        ye
    }
}

fn nav<B: Backend, const N: usize>(y: &State<B, N>) -> NavState<B> {
    NavState {
        x: y.body.x,
        v: y.body.v,
        r: y.body.r,
        omega: y.body.omega,
    }
}
