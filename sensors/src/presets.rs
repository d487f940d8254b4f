//! The IMUs of the parts and simulators users compare with.

use crate::{ImuSpec, TriadErrors};

/// Standard gravity, m/s², for densities given in µg/√Hz.
const G0: f64 = 9.806_65;
const IDENTITY: [[f64; 3]; 3] = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
const DEG: f64 = core::f64::consts::PI / 180.0;

impl ImuSpec {
    /// An IMU at the centre of mass, aligned with the body, sampling at
    /// `rate` with the errors given.
    pub const fn aligned(rate: f64, accel: TriadErrors, gyro: TriadErrors) -> Self {
        Self {
            rate,
            position: [0.0; 3],
            mounting: IDENTITY,
            accel,
            gyro,
            attitude_sigma: None,
        }
    }

    /// RotorPy 3.0.0's IMU as its `Environment` builds it, sampling at the
    /// simulation rate `rate` (100 Hz by default there): per-sample
    /// σ = √(rate/2)·0.038² m/s² (accelerometer) and √(rate/2)·0.01² rad/s
    /// (gyroscope), RotorPy's squared defaults used as standard
    /// deviations; no bias and no walk. Its noise levels only: RotorPy's
    /// gyroscope ignores the mounting, its lever-arm terms mix frames, and
    /// its bias walk shrinks with the rate; this model does none of that.
    pub fn rotorpy(rate: f64) -> Self {
        // σ = N·√rate = √(rate/2)·c  ⇒  N = c/√2.
        let n = |c: f64| c / core::f64::consts::SQRT_2;
        Self::aligned(
            rate,
            TriadErrors::white(n(0.038 * 0.038)),
            TriadErrors::white(n(0.01 * 0.01)),
        )
    }

    /// The Crazyflie 2.x's Bosch BMI088 at 1 kHz, with the typical noise
    /// densities of Bosch Sensortec's BMI088 datasheet: accelerometer
    /// 175 µg/√Hz, gyroscope 0.014 °/s/√Hz; no bias terms (the datasheet
    /// gives no random walk).
    pub fn crazyflie() -> Self {
        Self::aligned(
            1000.0,
            TriadErrors::white(175e-6 * G0),
            TriadErrors::white(0.014 * DEG),
        )
    }

    /// The InvenSense MPU-9250 at 1 kHz, with the typical noise densities
    /// of its product specification: accelerometer 300 µg/√Hz, gyroscope
    /// 0.01 °/s/√Hz (1.75e-4 rad/s/√Hz).
    pub fn mpu9250() -> Self {
        Self::aligned(
            1000.0,
            TriadErrors::white(300e-6 * G0),
            TriadErrors::white(0.01 * DEG),
        )
    }

    /// The IMU of the FDCL lab's Gazebo simulator (`fdcl-gwu/uav_simulator`):
    /// 100 Hz, Gaussian noise of σ = 1e-4 per sample on every axis of both
    /// triads, and the attitude its IMU message carries, with the same σ
    /// in rad (an assumption: the simulator's orientation noise is not
    /// given).
    pub fn fdcl_gazebo() -> Self {
        // σ = N·√100.
        let n = 1e-4 / 10.0;
        Self {
            attitude_sigma: Some(1e-4),
            ..Self::aligned(100.0, TriadErrors::white(n), TriadErrors::white(n))
        }
    }
}

/// The sensors of a run: any of an IMU, a motion-capture system, a GPS and
/// a barometer, each with its own rate.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SensorSuite {
    /// The IMU.
    pub imu: Option<ImuSpec>,
    /// Motion capture.
    pub mocap: Option<crate::MocapSpec>,
    /// GPS.
    pub gps: Option<crate::GpsSpec>,
    /// Barometer.
    pub baro: Option<crate::BaroSpec>,
}

impl SensorSuite {
    /// The names [`SensorSuite::preset`] knows.
    pub const PRESETS: [&'static str; 4] = ["rotorpy", "crazyflie", "mpu9250", "fdcl-gazebo"];

    /// A named suite: `rotorpy` (RotorPy 3.0.0's IMU and motion capture at
    /// its default 100 Hz), `crazyflie` (the BMI088 at 1 kHz and an
    /// external pose at 100 Hz, 10 ms late), `mpu9250` (the MPU-9250 at
    /// 1 kHz alone), `fdcl-gazebo` (the FDCL simulator's IMU at 100 Hz and
    /// GPS at 10 Hz); `None` for another name.
    pub fn preset(name: &str) -> Option<Self> {
        let none = Self::default();
        Some(match name {
            "rotorpy" => Self {
                imu: Some(ImuSpec::rotorpy(100.0)),
                mocap: Some(crate::MocapSpec::rotorpy(100.0)),
                ..none
            },
            "crazyflie" => Self {
                imu: Some(ImuSpec::crazyflie()),
                mocap: Some(crate::MocapSpec::crazyflie()),
                ..none
            },
            "mpu9250" => Self {
                imu: Some(ImuSpec::mpu9250()),
                ..none
            },
            "fdcl-gazebo" => Self {
                imu: Some(ImuSpec::fdcl_gazebo()),
                gps: Some(crate::GpsSpec::fdcl_gazebo()),
                ..none
            },
            _ => return None,
        })
    }

    /// Which sensors it has.
    pub fn set(&self) -> crate::SensorSet {
        crate::SensorSet {
            imu: self.imu.is_some(),
            mocap: self.mocap.is_some(),
            gps: self.gps.is_some(),
            baro: self.baro.is_some(),
        }
    }

    /// Whether it has no sensor at all.
    pub fn is_empty(&self) -> bool {
        self.set() == crate::SensorSet::default()
    }

    /// Every sensor's spec in range.
    pub fn validate(&self) -> Result<(), crate::SensorError> {
        if let Some(s) = &self.imu {
            s.validate()?;
        }
        if let Some(s) = &self.mocap {
            s.validate()?;
        }
        if let Some(s) = &self.gps {
            s.validate()?;
        }
        if let Some(s) = &self.baro {
            s.validate()?;
        }
        Ok(())
    }

    /// Every sensor with its noise scaled by `k` (white noise, walks,
    /// biases and spikes; rates, latencies and dropouts kept): `0` for a
    /// noiseless suite.
    pub fn noise_scaled(mut self, k: f64) -> Self {
        if let Some(s) = self.imu.as_mut() {
            for e in [&mut s.accel, &mut s.gyro] {
                e.noise_density *= k;
                e.random_walk *= k;
                e.turn_on_bias *= k;
            }
            if let Some(a) = s.attitude_sigma.as_mut() {
                *a *= k;
            }
        }
        if let Some(s) = self.mocap.as_mut() {
            s.position_sigma *= k;
            s.velocity_sigma *= k;
            s.attitude_sigma *= k;
            s.rate_sigma *= k;
            s.velocity_spike.max *= k;
            s.rate_spike.max *= k;
        }
        if let Some(s) = self.gps.as_mut() {
            s.horizontal_sigma *= k;
            s.vertical_sigma *= k;
            s.velocity_sigma *= k;
        }
        if let Some(s) = self.baro.as_mut() {
            s.sigma *= k;
            s.random_walk *= k;
            s.turn_on_bias *= k;
        }
        self
    }
}
