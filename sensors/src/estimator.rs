//! What a flight computer knows: the [`Estimator`] trait, the
//! measurements it takes, and the simplest estimator, [`MocapEstimator`].

use lie::{Backend, M3, Real, V3};

use crate::{BaroSample, GpsSample, ImuSample, MocapSample};

/// The navigation state a flight mode reads: position and velocity in the
/// world frame, attitude (body to world), body rates.
#[derive(Clone, Copy, Debug)]
pub struct NavState<B: Backend> {
    /// Position, m.
    pub x: V3<B>,
    /// Velocity, m/s.
    pub v: V3<B>,
    /// Attitude.
    pub r: M3<B>,
    /// Body rates, rad/s.
    pub omega: V3<B>,
}

impl<B: Backend> NavState<B> {
    /// At the origin, level and at rest.
    pub fn at_rest() -> Self {
        let z = lie::ops::zero::<B>();
        Self {
            x: z,
            v: z,
            r: lie::ops::identity::<B>(),
            omega: z,
        }
    }
}

/// One measurement as it reaches the estimator: each carries the instant
/// it describes (its capture time), which comes before its arrival by the
/// sensor's latency.
#[derive(Clone, Copy, Debug)]
#[non_exhaustive]
pub enum Measurement<B: Backend> {
    /// An IMU sample.
    Imu(ImuSample<B>),
    /// A motion-capture frame.
    Mocap(MocapSample<B>),
    /// A GPS fix.
    Gps(GpsSample<B>),
    /// A barometer sample.
    Baro(BaroSample),
}

impl<B: Backend> Measurement<B> {
    /// Whether it is a motion-capture frame.
    pub fn is_mocap(&self) -> bool {
        matches!(self, Measurement::Mocap(_))
    }
    /// Whether it is a GPS fix.
    pub fn is_gps(&self) -> bool {
        matches!(self, Measurement::Gps(_))
    }
    /// The instant it describes, s.
    pub fn captured(&self) -> f64 {
        match self {
            Measurement::Imu(s) => s.t,
            Measurement::Mocap(s) => s.t,
            Measurement::Gps(s) => s.t,
            Measurement::Baro(s) => s.t,
        }
    }
}

/// The sensors a run has, or an estimator needs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SensorSet {
    /// An IMU.
    pub imu: bool,
    /// Motion capture.
    pub mocap: bool,
    /// GPS.
    pub gps: bool,
    /// A barometer.
    pub baro: bool,
}

impl SensorSet {
    /// The first sensor of `self` that `have` lacks, by its name.
    pub fn first_missing(&self, have: &SensorSet) -> Option<&'static str> {
        [
            (self.imu && !have.imu, "imu"),
            (self.mocap && !have.mocap, "mocap"),
            (self.gps && !have.gps, "gps"),
            (self.baro && !have.baro, "baro"),
        ]
        .into_iter()
        .find_map(|(missing, name)| missing.then_some(name))
    }
}

/// What a filter knows of its own accuracy: the standard deviations of its
/// error states (the first `states` of `sigma`, in its own coordinates and
/// order), its last correction's normalised innovation squared with that
/// correction's degrees of freedom, and that correction's innovation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diagnostics {
    /// Standard deviations; `NaN` past `states`.
    pub sigma: [f64; 15],
    /// How many of `sigma` are the filter's.
    pub states: usize,
    /// The last correction's NIS and degrees of freedom.
    pub nis: Option<(f64, usize)>,
    /// The last correction's innovation, the observation less its prediction, in the
    /// filter's measurement coordinates and order (the invariant EKF's
    /// mocap update: position, then attitude as `Log(R_m R̂ᵀ)`); its first
    /// `nis.1` entries, `NaN` past them and before the first correction.
    pub innovation: [f64; 6],
}

impl Diagnostics {
    /// From a covariance's diagonal, without an innovation.
    pub fn of_diagonal(diag: impl Iterator<Item = f64>, nis: Option<(f64, usize)>) -> Self {
        let mut sigma = [f64::NAN; 15];
        let mut states = 0;
        for (s, d) in sigma.iter_mut().zip(diag) {
            *s = Real::sqrt(d.max(0.0));
            states += 1;
        }
        Self {
            sigma,
            states,
            nis,
            innovation: [f64::NAN; 6],
        }
    }

    /// With the last correction's innovation (at most 6 entries).
    pub fn with_innovation(mut self, innovation: impl Iterator<Item = f64>) -> Self {
        for (slot, v) in self.innovation.iter_mut().zip(innovation) {
            *slot = v;
        }
        self
    }
}

/// A state estimator: it takes the measurements in the order they arrive
/// and gives, at a control instant, the state the flight mode reads.
///
/// The simulation calls [`Estimator::reset`] once with the state the run
/// starts from (a flight computer is told where it starts), then, at each
/// control instant, [`Estimator::update`] with every measurement that
/// arrived since the last one (in arrival order) and [`Estimator::estimate`]
/// once. Object safe.
pub trait Estimator<B: Backend>: Send {
    /// Short name for logs, e.g. `"mocap"`.
    fn name(&self) -> &'static str;
    /// The sensors it cannot work without (none by default): a run that
    /// lacks one is refused before its first step.
    fn needs(&self) -> SensorSet {
        SensorSet::default()
    }
    /// The sensors whose measurements it reads (every one by default): a
    /// simulation hands it no others, and does not keep them for it.
    fn wants(&self) -> SensorSet {
        SensorSet {
            imu: true,
            mocap: true,
            gps: true,
            baro: true,
        }
    }
    /// Starts from `initial` at time `t`.
    fn reset(&mut self, t: f64, initial: &NavState<B>);
    /// Takes one measurement.
    fn update(&mut self, m: &Measurement<B>);
    /// The state at `t` (a control instant, not before the last
    /// measurement's arrival).
    fn estimate(&self, t: f64) -> NavState<B>;
    /// Its covariance's standard deviations and last NIS, for a filter
    /// that keeps them (`None` by default).
    fn diagnostics(&self) -> Option<Diagnostics> {
        None
    }
}

/// The latest motion-capture frame as the state, as RotorPy's
/// `use_mocap=True` flies: position, velocity, attitude and rates from the
/// tracker, optionally the rates from the gyroscope instead (rotated into
/// the body frame by the IMU's mounting). Before the first frame arrives it
/// gives the state it was reset to.
#[derive(Clone, Debug)]
pub struct MocapEstimator<B: Backend> {
    state: NavState<B>,
    /// `R_BS` of the IMU whose gyro gives the rates, when it does.
    gyro: Option<M3<B>>,
}

impl<B: Backend> MocapEstimator<B> {
    /// Everything from the tracker.
    pub fn new() -> Self {
        Self {
            state: NavState::at_rest(),
            gyro: None,
        }
    }

    /// The rates from the gyroscope of an IMU mounted with `r_bs` (its
    /// columns the sensor's axes in the body frame).
    pub fn with_gyro_rates(r_bs: M3<B>) -> Self {
        Self {
            state: NavState::at_rest(),
            gyro: Some(r_bs),
        }
    }
}

impl<B: Backend> Default for MocapEstimator<B> {
    fn default() -> Self {
        Self::new()
    }
}

impl<B: Backend> Estimator<B> for MocapEstimator<B> {
    fn name(&self) -> &'static str {
        "mocap"
    }
    fn needs(&self) -> SensorSet {
        SensorSet {
            mocap: true,
            imu: self.gyro.is_some(),
            ..SensorSet::default()
        }
    }
    fn wants(&self) -> SensorSet {
        self.needs()
    }
    fn reset(&mut self, _t: f64, initial: &NavState<B>) {
        self.state = *initial;
    }
    fn update(&mut self, m: &Measurement<B>) {
        let s = &mut self.state;
        match (m, self.gyro) {
            (Measurement::Mocap(f), gyro) => {
                s.x = f.x;
                s.v = f.v;
                s.r = f.r;
                if gyro.is_none() {
                    s.omega = f.omega;
                }
            }
            (Measurement::Imu(i), Some(r_bs)) => s.omega = B::mat3_mul_vec(r_bs, i.gyro),
            _ => {}
        }
    }
    fn estimate(&self, _t: f64) -> NavState<B> {
        self.state
    }
}
