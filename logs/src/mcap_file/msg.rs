//! The messages of the `gpid` channels, described through the `foxglove`
//! crate's derive (each type's schema is a protobuf `FileDescriptorSet`
//! stored in the MCAP, so any protobuf reader decodes them; the poses and
//! transforms are Foxglove's own `PoseInFrame` and `FrameTransform`). A
//! sample's messages are written by an encoder of this crate's own, tested
//! to produce the derive's and `prost`'s bytes exactly; these types decode
//! them.

pub use foxglove::messages::{
    Color, FrameTransform, LinePrimitive, Point3, Pose, PoseInFrame, Quaternion, SceneEntity,
    SceneUpdate, Timestamp, Vector3, line_primitive,
};

/// `/errors`: Ψ, ‖e_x‖, e_x = x − x_d, Ω and Ω_d (or Ω_c).
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub struct Errors {
    /// Ψ against the active desired attitude.
    pub psi: f64,
    /// ‖x − x_d‖, m.
    pub ex: f64,
    /// x − x_d, m.
    pub e_x: Vector3,
    /// Body angular velocity, rad/s.
    pub omega: Vector3,
    /// Desired angular velocity, rad/s.
    pub omega_d: Vector3,
}

/// `/command`: the commanded thrust and moment, the rotor thrusts
/// delivered.
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub struct Command {
    /// N.
    pub thrust: f64,
    /// N m, body frame.
    pub moment: Vector3,
    /// N, one per rotor (empty without rotors).
    pub rotor_thrusts: Vec<f64>,
}

/// `/integrals`: the integral states (named so because protobuf's
/// JSON names of `e_I` and `e_i` would collide).
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub struct Integrals {
    /// e_I, the attitude integral (register slots 0–2).
    pub attitude: Vector3,
    /// e_i, the position integral (slots 3–5).
    pub position: Vector3,
}

/// `/mode`: a switch, and the first mode at t = 0.
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub struct ModeSwitch {
    /// s.
    pub t: f64,
    /// Segment left.
    pub from: u32,
    /// Segment entered.
    pub to: u32,
    /// Its mode's name.
    pub mode: String,
}

/// `/vehicle/states`: a vehicle's internal states.
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub struct VehicleStates {
    /// In the vehicle's own order.
    pub states: Vec<f64>,
}

/// `/sensors/imu`: one IMU sample, in the sensor's axes.
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub struct ImuReading {
    /// Its time, s.
    pub t: f64,
    /// Specific force, m/s² (a level IMU at rest reads −g along b3).
    pub accel: Vector3,
    /// Angular rate, rad/s.
    pub gyro: Vector3,
}

/// `/sensors/mocap`: one motion-capture frame (world frame `ned`, rates
/// in the body frame).
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub struct MocapFrame {
    /// Capture time, s.
    pub t: f64,
    /// Arrival time (capture plus latency), s.
    pub arrival: f64,
    /// m.
    pub position: Vector3,
    /// m/s.
    pub velocity: Vector3,
    /// Attitude, body to world.
    pub orientation: Quaternion,
    /// Body rates, rad/s.
    pub omega: Vector3,
}

/// `/sensors/gps`: one GPS fix (world frame `ned`).
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub struct GpsFix {
    /// The instant it describes, s.
    pub t: f64,
    /// Arrival time (plus the delay), s.
    pub arrival: f64,
    /// m.
    pub position: Vector3,
    /// m/s.
    pub velocity: Vector3,
}

/// `/estimate/diagnostics`: what a filter knows of its own accuracy, at
/// a record sample.
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub struct EstimateDiagnostics {
    /// The standard deviations of its error states, in its own order
    /// (the invariant EKF: position, velocity, attitude, gyroscope bias,
    /// accelerometer bias; 15 values).
    pub sigma: Vec<f64>,
    /// Its last correction's normalised innovation squared (0 before the
    /// first).
    pub nis: f64,
    /// That correction's degrees of freedom (0 before the first).
    pub nis_dof: u32,
    /// That correction's innovation: the observation less its prediction,
    /// in the filter's measurement coordinates (`nis_dof` values).
    pub innovation: Vec<f64>,
}

/// `/sensors/baro`: one barometer sample.
#[derive(Clone, Debug, Default, PartialEq, foxglove::Encode)]
pub struct BaroReading {
    /// Its time, s.
    pub t: f64,
    /// Height above the origin, m (up).
    pub height: f64,
}
