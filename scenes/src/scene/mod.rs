//! Scenes as data: Rust structs that are also the TOML schema.

use std::collections::BTreeMap;

use controllers::paper as paper_gains;
use dynamics::{MultirotorParams, paper};
use serde::{Deserialize, Serialize};

mod control;
mod format;
mod ground;
mod locate;
mod plan;
mod references;
mod sensing;
mod sensor_tables;
mod validate;
mod wind;

pub use crate::error::SceneError;
pub use format::{SCENE_FORMAT, missing_format_note};
pub use ground::GroundSpec;
use locate::{line_col, locate_error};
pub use plan::{ModeKind, SegmentSpec, ThrustSpec};
pub use references::{AttitudeRef, PositionRef};
pub use sensing::{EstimatorKind, EstimatorSpec, SensorsSpec};
pub use sensor_tables::{BaroTable, GpsTable, ImuTable, MocapTable, SpikeTable, TriadTable};
pub use wind::WindSpec;

/// A complete scene. Every field has the same name in TOML; unknown keys are
/// errors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// The scene format the file was written for: `Some(SCENE_FORMAT)`,
    /// or `None` for a file without a `format` key, which is read as
    /// format 1 with a note in the run's warnings. A file of a newer
    /// format, or a `format` that is not a positive integer, is refused
    /// naming the key and the value. Always written as `format = 1`.
    #[serde(
        default,
        deserialize_with = "format::read",
        serialize_with = "format::write"
    )]
    pub format: Option<u32>,
    /// Short name (`paper-flip`).
    pub name: String,
    /// What the scene shows.
    #[serde(default)]
    pub description: String,
    /// Simulated time, s.
    pub duration: f64,
    /// `f32` or `f64`.
    #[serde(default)]
    pub scalar: Scalar,
    /// `nalgebra` or `glam`.
    #[serde(default)]
    pub backend: BackendKind,
    /// The vehicle and its parameters.
    #[serde(default)]
    pub vehicle: VehicleSpec,
    /// Constant disturbances Δ_x (inertial force) and Δ_R (body moment); none
    /// when absent.
    #[serde(default)]
    pub disturbance: Option<DisturbanceSpec>,
    /// The wind; none when absent. Only vehicles with aerodynamics (the
    /// `multirotor` kind) feel it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wind: Option<WindSpec>,
    /// A flat ground under the vehicle; none when absent (the vehicle
    /// may fly through any height).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ground: Option<GroundSpec>,
    /// Initial state.
    #[serde(default)]
    pub initial: InitialSpec,
    /// Controller gains.
    #[serde(default)]
    pub gains: GainsSpec,
    /// Flight-mode plan; empty means no controller (a free body).
    #[serde(default)]
    pub plan: Vec<SegmentSpec>,
    /// Integrator and step.
    #[serde(default)]
    pub integrator: IntegratorSpec,
    /// Control timing.
    #[serde(default)]
    pub control: ControlSpec,
    /// What to record.
    #[serde(default)]
    pub record: RecordSpec,
    /// The seed of every random number the run draws (sensor noise); a
    /// Monte Carlo sample adds its index.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub seed: u64,
    /// The sensors the vehicle carries (none by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensors: Option<SensorsSpec>,
    /// What the flight modes read (the true state by default).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub estimator: Option<EstimatorSpec>,
}

fn is_zero(x: &u64) -> bool {
    *x == 0
}

/// Scalar type of the simulation.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Scalar {
    /// Single precision.
    F32,
    /// Double precision.
    #[default]
    F64,
}

/// Linear-algebra backend.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum BackendKind {
    /// nalgebra.
    #[default]
    Nalgebra,
    /// glam.
    Glam,
}

/// Which vehicle. In a scene file a kebab-case name: one of the built-ins
/// below, or a kind a program registered with [`crate::Registry::vehicle`]
/// ([`VehicleKind::Custom`]).
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub enum VehicleKind {
    /// The paper's quadrotor, free to translate.
    #[default]
    Quadrotor,
    /// The quadrotor on a spherical joint at its centre of gravity: attitude
    /// only, no translation integrated (the paper's hardware test without
    /// the stand's gravity moment).
    PinnedQuadrotor,
    /// A torque-free rigid body (no actuators, no gravity).
    FreeRigidBody,
    /// The same airframe with six rotors (minimum-norm allocation).
    Hexarotor,
    /// The paper's test stand (Section VI): the quadrotor on a spherical
    /// joint `stand_height` below its centre of gravity, so gravity tips it
    /// over (an inverted 3D pendulum); attitude only.
    AttitudeStand,
    /// A multirotor with motor lag and aerodynamics (RotorPy's model):
    /// the airframe from `mass`, `inertia`, `gravity` and `arm` (four
    /// rotors in the X layout), rotors and aerodynamics from the
    /// `[vehicle.multirotor]` table (a preset and overrides).
    Multirotor,
    /// A kind registered by a program ([`crate::Registry::vehicle`]), by
    /// name; its own parameters go in `[vehicle.params]`.
    Custom(String),
}

impl VehicleKind {
    /// The built-in kinds.
    pub const BUILT_IN: [VehicleKind; 6] = [
        VehicleKind::Quadrotor,
        VehicleKind::PinnedQuadrotor,
        VehicleKind::FreeRigidBody,
        VehicleKind::Hexarotor,
        VehicleKind::AttitudeStand,
        VehicleKind::Multirotor,
    ];

    /// The name used in scene files.
    pub fn name(&self) -> &str {
        match self {
            VehicleKind::Quadrotor => "quadrotor",
            VehicleKind::PinnedQuadrotor => "pinned-quadrotor",
            VehicleKind::FreeRigidBody => "free-rigid-body",
            VehicleKind::Hexarotor => "hexarotor",
            VehicleKind::AttitudeStand => "attitude-stand",
            VehicleKind::Multirotor => "multirotor",
            VehicleKind::Custom(name) => name,
        }
    }

    /// The kind called `name`: a built-in, else [`VehicleKind::Custom`].
    pub fn from_name(name: &str) -> Self {
        Self::BUILT_IN
            .into_iter()
            .find(|k| k.name() == name)
            .unwrap_or_else(|| VehicleKind::Custom(name.to_string()))
    }
}

impl Serialize for VehicleKind {
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

impl<'de> Deserialize<'de> for VehicleKind {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        Ok(VehicleKind::from_name(&String::deserialize(d)?))
    }
}

/// Vehicle parameters (defaults: the paper's numerical example).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct VehicleSpec {
    /// Kind of vehicle.
    pub kind: VehicleKind,
    /// Mass, kg.
    pub mass: f64,
    /// The mass the controller assumes, kg (absent: `mass`): a model
    /// error the position law's integral term has to absorb.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub model_mass: Option<f64>,
    /// Principal inertia diag(J), kg m².
    pub inertia: [f64; 3],
    /// Accept principal moments that no rigid body has (one exceeding the
    /// sum of the other two). The paper's J = diag(0.43, 0.43, 1.02)·10⁻²
    /// is such a set (1.02 > 0.86), so the paper's scenes set this; in a
    /// file it defaults to `false`, so that a typo such as `[1, 1, 3]` is
    /// an error rather than a run that needs 155 N rotors.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub allow_nonphysical_inertia: bool,
    /// Gravity, m/s².
    pub gravity: f64,
    /// Arm length d, m.
    pub arm: f64,
    /// Reaction-torque coefficient c_τf, m.
    pub c_tau_f: f64,
    /// `attitude-stand` only: height of the centre of gravity above the
    /// pivot, m.
    pub stand_height: f64,
    /// Parameters of a registered kind (`[vehicle.params]`, name = number);
    /// empty for the built-ins.
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    pub params: BTreeMap<String, f64>,
    /// `multirotor` only: the rotor and aerodynamic parameters.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub multirotor: Option<MultirotorSpec>,
}

/// The rotors and aerodynamics of a `multirotor` vehicle: a RotorPy
/// preset and, under RotorPy's names, any parameter to change in it (the
/// airframe's mass, inertia and arm come from the vehicle table).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MultirotorSpec {
    /// `crazyflie` or `hummingbird` (RotorPy 3.0.0's parameter sets).
    pub preset: Preset,
    /// Thrust coefficient, N/(rad/s)².
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k_eta: Option<f64>,
    /// Yaw-moment coefficient, N m/(rad/s)².
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k_m: Option<f64>,
    /// Rotor drag coefficient, kg/rad.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k_d: Option<f64>,
    /// Induced-inflow coefficient, kg/rad.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k_z: Option<f64>,
    /// Translational-lift coefficient, kg/m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k_h: Option<f64>,
    /// Flapping-moment coefficient, kg m/rad.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub k_flap: Option<f64>,
    /// Parasitic drag along b1, N/(m/s)².
    #[serde(rename = "c_Dx", skip_serializing_if = "Option::is_none")]
    pub c_dx: Option<f64>,
    /// Parasitic drag along b2, N/(m/s)².
    #[serde(rename = "c_Dy", skip_serializing_if = "Option::is_none")]
    pub c_dy: Option<f64>,
    /// Parasitic drag along b3, N/(m/s)².
    #[serde(rename = "c_Dz", skip_serializing_if = "Option::is_none")]
    pub c_dz: Option<f64>,
    /// Motor time constant, s (0: rotors follow their commands at once).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tau_m: Option<f64>,
    /// Lowest rotor speed, rad/s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotor_speed_min: Option<f64>,
    /// Highest rotor speed, rad/s.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotor_speed_max: Option<f64>,
    /// Aerodynamic terms on (RotorPy's `aero`; default true).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub aero: Option<bool>,
    /// Hub positions, body frame of this project (e3 down; RotorPy's
    /// `(x, y, z)` is `(x, −y, −z)` here), m; default: four rotors in the X
    /// layout at the vehicle's `arm`. Needs `rotor_directions`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotor_positions: Option<Vec<[f64; 3]>>,
    /// Spin directions, ±1 each, as RotorPy's `rotor_directions` (its `+1`
    /// rotor's reaction moment is along its +z, −e3 here).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rotor_directions: Option<Vec<f64>>,
}

/// A RotorPy parameter set.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Preset {
    /// Bitcraze Crazyflie 2.0 (30 g; 72 ms motors).
    #[default]
    Crazyflie,
    /// AscTec Hummingbird (0.5 kg; 5 ms motors, parasitic drag, lift).
    Hummingbird,
}

impl Default for VehicleSpec {
    fn default() -> Self {
        Self {
            kind: VehicleKind::Quadrotor,
            mass: paper::MASS,
            model_mass: None,
            inertia: paper::INERTIA,
            allow_nonphysical_inertia: true,
            gravity: paper::GRAVITY,
            arm: paper::ARM,
            c_tau_f: paper::C_TAU_F,
            stand_height: 0.0,
            params: BTreeMap::new(),
            multirotor: None,
        }
    }
}

/// Constant disturbances.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DisturbanceSpec {
    /// Δ_x, inertial force, N.
    pub force: [f64; 3],
    /// Δ_R, body moment, N m.
    pub moment: [f64; 3],
}

impl DisturbanceSpec {
    /// The paper's Δ_x = [−0.5, 0.2, 1] N, Δ_R = [0.2, −0.1, −0.02] N m.
    pub fn paper() -> Self {
        Self {
            force: paper::DELTA_X,
            moment: paper::DELTA_R,
        }
    }
}

/// Initial state; the attitude is a rotation vector (axis × angle, rad).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct InitialSpec {
    /// Position, m.
    pub x: [f64; 3],
    /// Velocity, m/s.
    pub v: [f64; 3],
    /// Attitude as a rotation vector, rad.
    pub rotation: [f64; 3],
    /// Body angular velocity, rad/s.
    pub omega: [f64; 3],
}

/// Gains (defaults: the paper's).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct GainsSpec {
    /// k_x.
    pub k_x: f64,
    /// k_v.
    pub k_v: f64,
    /// k_i (position integral).
    pub k_i: f64,
    /// k_R.
    pub k_r: f64,
    /// k_Ω.
    pub k_omega: f64,
    /// k_I (attitude integral).
    pub k_att_i: f64,
    /// c1.
    pub c1: f64,
    /// c2.
    pub c2: f64,
    /// σ of sat_σ(e_i).
    pub sigma: f64,
    /// Acceleration model for Ω_c, Ω̇_c.
    pub acceleration_model: AccelModel,
    /// Clamped anti-windup for e_i (off: the paper's law, e_i integrates
    /// freely and only sat_σ(e_i) enters the thrust).
    pub clamp_integral: bool,
}

impl Default for GainsSpec {
    fn default() -> Self {
        let (p, a) = (paper_gains::POSITION_GAINS, paper_gains::ATTITUDE_GAINS);
        Self {
            k_x: p.k_x,
            k_v: p.k_v,
            k_i: p.k_i,
            k_r: a.k_r,
            k_omega: a.k_omega,
            k_att_i: a.k_i,
            c1: p.c1,
            c2: a.c2,
            sigma: p.sigma,
            acceleration_model: AccelModel::Nominal,
            clamp_integral: false,
        }
    }
}

/// Which acceleration the computed attitude's derivatives use.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum AccelModel {
    /// g e3 − (f/m) R e3 + k_i sat(e_i)/m (the controller's disturbance
    /// estimate included; the controller never sees Δ_x itself).
    #[default]
    Nominal,
    /// g e3 − (f/m) R e3 only.
    NominalWithoutEstimate,
}

/// Integrator choice.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct IntegratorSpec {
    /// `lgvi | rk4 | rk4-projected | rkmk4 | euler | dopri`.
    pub kind: String,
    /// Step, s (for dopri: the longest call; it adapts inside).
    pub dt: f64,
    /// dopri tolerance.
    pub tol: f64,
    /// Locate the sat′ discontinuities (e_i crossing ±σ) and split steps
    /// there. Off only to measure what it buys.
    pub locate_events: bool,
}

impl Default for IntegratorSpec {
    fn default() -> Self {
        Self {
            kind: "rk4".into(),
            dt: 1e-3,
            tol: 1e-10,
            locate_events: true,
        }
    }
}

/// Control timing.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct ControlSpec {
    /// `continuous` (controller inside the vector field) or `sampled`.
    pub timing: Timing,
    /// Sampled: controller rate, Hz (the attitude law's in a multi-rate
    /// loop).
    pub rate: f64,
    /// Sampled: the position law's rate, Hz, held in between (0: `rate`).
    pub position_rate: f64,
    /// Sampled with an estimator: the rate the estimate is taken at, Hz
    /// (0: at every control instant).
    pub estimator_rate: f64,
    /// A flight computer's loop rates by name, in place of the three
    /// rates: `crazyflie` (estimator 1 kHz, attitude 500 Hz, position
    /// 100 Hz).
    pub loop_rates: Option<String>,
    /// Add `−M_cfg(R)`, the vehicle's known configuration moment (gravity
    /// about the stand's pivot), to the commanded moment: the compensation
    /// term the paper adds for its experiment.
    pub compensate_configuration_moment: bool,
}

/// Control timing.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Timing {
    /// Controller inside the vector field.
    #[default]
    Continuous,
    /// Zero-order hold at `rate`.
    Sampled,
}

/// Recording.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct RecordSpec {
    /// Sample interval, s; 0 records nothing but the final state.
    pub sample: f64,
}

impl Default for RecordSpec {
    fn default() -> Self {
        Self { sample: 0.01 }
    }
}

impl Scene {
    /// Parses a TOML scene; `origin` names the file in errors.
    pub fn from_toml(text: &str, origin: &str) -> Result<Self, SceneError> {
        Self::from_toml_with_kinds(text, origin, &[])
    }

    /// [`Scene::from_toml`] accepting the registered vehicle kinds
    /// `custom_kinds` besides the built-ins.
    pub fn from_toml_with_kinds(
        text: &str,
        origin: &str,
        custom_kinds: &[&str],
    ) -> Result<Self, SceneError> {
        let mut scene: Scene = toml::from_str(text).map_err(|e| {
            let location = e.span().map(|sp| {
                let (line, col) = line_col(text, sp.start);
                format!("{origin}:{line}:{col}")
            });
            SceneError {
                message: e.message().trim().to_string(),
                location,
                key: None,
            }
        })?;
        if origin.ends_with(".toml")
            && let Some(dir) = std::path::Path::new(origin).parent()
        {
            for seg in &mut scene.plan {
                if let Some(p) = &mut seg.position {
                    p.resolve_path(dir);
                }
            }
        }
        scene
            .validate()
            .and_then(|()| scene.check_kind(custom_kinds))
            .map_err(|(key, msg)| SceneError {
                location: locate_error(text, key, &msg).map(|(l, c)| format!("{origin}:{l}:{c}")),
                message: msg,
                key: Some(key.to_string()),
            })?;
        Ok(scene)
    }

    /// Steps a run of this scene takes: its fixed steps, or Dormand–Prince's
    /// calls (its longest step is `dt`).
    pub fn estimated_steps(&self) -> f64 {
        self.duration / self.integrator.dt
    }

    /// Refuses a scene of more than `max_steps` steps, saying how long it
    /// would take at about 1 µs a closed-loop step (a round figure for
    /// the message, not a measurement): a mistyped `duration` or `dt` otherwise starts a run
    /// that never ends. The error's key is `duration`.
    pub fn check_size(&self, max_steps: f64) -> Result<(), SceneError> {
        let steps = self.estimated_steps();
        if steps <= max_steps {
            return Ok(());
        }
        let secs = steps * 1e-6;
        let took = if secs < 86_400.0 {
            format!("{:.1} hours", secs / 3600.0)
        } else if secs < 3.2e7 {
            format!("{:.0} days", secs / 86_400.0)
        } else {
            format!("{:.1e} years", secs / 3.156e7)
        };
        Err(SceneError {
            message: format!(
                "{}: {steps:.2e} steps (duration = {} s at dt = {} s), more than {max_steps:.0e}: about {took} at 1 µs a step",
                self.name, self.duration, self.integrator.dt
            ),
            location: None,
            key: Some("duration".into()),
        })
    }

    /// Serialises to TOML (the inverse of [`Scene::from_toml`]).
    ///
    /// Infallible: every field is a number, string, bool, array or a map
    /// with string keys, which TOML always represents (NaN and ±∞ as
    /// `nan`/`inf`); the tests serialise every built-in scene, non-finite
    /// values and registered-kind parameters.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a Scene has only types TOML represents")
    }
}

/// The parameters of a `multirotor` scene's vehicle: the preset, the
/// airframe (mass, inertia, gravity, four rotors in the X layout at `arm`)
/// from the vehicle table, then the table's overrides. Not validated here
/// ([`dynamics::Multirotor::new`] does that).
pub(crate) fn multirotor_params<B: lie::Backend>(scene: &Scene) -> MultirotorParams<B> {
    use lie::Real;
    let l = lie::S::<B>::lit;
    let ve = &scene.vehicle;
    let spec = ve.multirotor.clone().unwrap_or_default();
    let mut p = match spec.preset {
        Preset::Crazyflie => MultirotorParams::<B>::crazyflie(),
        Preset::Hummingbird => MultirotorParams::<B>::hummingbird(),
    };
    p.mass = l(ve.mass);
    p.inertia = lie::ops::diag::<B>(l(ve.inertia[0]), l(ve.inertia[1]), l(ve.inertia[2]));
    p.gravity = l(ve.gravity);
    p.rotors = match (&spec.rotor_positions, &spec.rotor_directions) {
        (Some(pos), Some(dir)) => pos
            .iter()
            .zip(dir)
            .map(|(r, d)| dynamics::Rotor {
                position: B::vec3(l(r[0]), l(r[1]), l(r[2])),
                direction: l(*d),
            })
            .collect(),
        _ => MultirotorParams::<B>::x_layout(l(ve.arm)),
    };
    let set = |field: &mut lie::S<B>, v: Option<f64>| {
        if let Some(v) = v {
            *field = l(v);
        }
    };
    set(&mut p.k_eta, spec.k_eta);
    set(&mut p.k_m, spec.k_m);
    set(&mut p.k_d, spec.k_d);
    set(&mut p.k_z, spec.k_z);
    set(&mut p.k_h, spec.k_h);
    set(&mut p.k_flap, spec.k_flap);
    set(&mut p.tau_m, spec.tau_m);
    set(&mut p.rotor_speed_min, spec.rotor_speed_min);
    set(&mut p.rotor_speed_max, spec.rotor_speed_max);
    let [mut cx, mut cy, mut cz] = B::vec3_to_array(p.c_d);
    set(&mut cx, spec.c_dx);
    set(&mut cy, spec.c_dy);
    set(&mut cz, spec.c_dz);
    p.c_d = B::vec3(cx, cy, cz);
    p.aero = spec.aero.unwrap_or(p.aero);
    p
}
