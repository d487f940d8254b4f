//! Scenes as data: Rust structs that are also the TOML schema.

use std::collections::BTreeMap;

use controllers::paper as paper_gains;
use dynamics::{MultirotorParams, paper};
use serde::{Deserialize, Serialize};

/// A complete scene. Every field has the same name in TOML; unknown keys are
/// errors.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
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

/// The air's velocity, inertial frame (e3 down), m/s.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum WindSpec {
    /// A steady, uniform wind.
    Constant {
        /// m/s.
        velocity: [f64; 3],
    },
    /// `mean + amplitude · sin(2π frequency t + phase)`.
    Sinusoid {
        /// m/s.
        #[serde(default)]
        mean: [f64; 3],
        /// m/s.
        amplitude: [f64; 3],
        /// Hz.
        frequency: f64,
        /// rad.
        #[serde(default)]
        phase: f64,
    },
    /// `velocities[k]` from `times[k]` on; the steps land on the times.
    Ladder {
        /// s, increasing.
        times: Vec<f64>,
        /// m/s, one per time.
        velocities: Vec<[f64; 3]>,
    },
    /// Dryden turbulence over a mean wind (MIL-F-8785C forming filters
    /// driven by noise on a fixed grid, reproducible from `seed`).
    Dryden {
        /// Mean wind, m/s.
        #[serde(default)]
        mean: [f64; 3],
        /// σ of the longitudinal, lateral and vertical components, m/s
        /// (default 1).
        #[serde(default = "dryden_sigma")]
        sigma: [f64; 3],
        /// Scale lengths L_u, L_v, L_w, m (default 94, 94, 15: the
        /// low-altitude values at 15 m).
        #[serde(default = "dryden_length")]
        length: [f64; 3],
        /// Speed the turbulence is carried past the vehicle at, m/s
        /// (default 5).
        #[serde(default = "dryden_speed")]
        speed: f64,
        /// Noise seed (default 1).
        #[serde(default = "dryden_seed")]
        seed: u64,
        /// Noise grid, s (default 0.005).
        #[serde(default = "dryden_grid")]
        grid: f64,
    },
}

fn dryden_sigma() -> [f64; 3] {
    dynamics::DrydenSpec::gusty().sigma
}
fn dryden_length() -> [f64; 3] {
    dynamics::DrydenSpec::gusty().length
}
fn dryden_speed() -> f64 {
    dynamics::DrydenSpec::gusty().speed
}
fn dryden_seed() -> u64 {
    dynamics::DrydenSpec::gusty().seed
}
fn dryden_grid() -> f64 {
    dynamics::DrydenSpec::gusty().grid
}

impl WindSpec {
    /// Dryden turbulence with the parameters of `spec` (e.g.
    /// [`dynamics::DrydenSpec::gusty`], with its mean or speed changed).
    pub fn dryden(spec: dynamics::DrydenSpec) -> Self {
        let dynamics::DrydenSpec {
            mean,
            sigma,
            length,
            speed,
            seed,
            grid,
        } = spec;
        WindSpec::Dryden {
            mean,
            sigma,
            length,
            speed,
            seed,
            grid,
        }
    }

    /// The wind field; an error names the `wind.<field>` key.
    pub fn build(&self) -> Result<Box<dyn dynamics::Wind>, (&'static str, String)> {
        use dynamics::{ConstantWind, DrydenSpec, DrydenWind, LadderWind, SinusoidWind};
        let key = |e: dynamics::WindError| {
            let k = match e.field {
                "times" => "wind.times",
                "velocities" => "wind.velocities",
                "mean" => "wind.mean",
                "sigma" => "wind.sigma",
                "length" => "wind.length",
                "speed" => "wind.speed",
                _ => "wind.grid",
            };
            (k, format!("`{k}`: {}", e.message))
        };
        let finite = |k: &'static str, v: &[f64]| match v.iter().find(|c| !c.is_finite()) {
            Some(c) => Err((k, format!("`{k}` = {c}: must be finite"))),
            None => Ok(()),
        };
        Ok(match self {
            WindSpec::Constant { velocity } => {
                finite("wind.velocity", velocity)?;
                Box::new(ConstantWind(*velocity))
            }
            WindSpec::Sinusoid {
                mean,
                amplitude,
                frequency,
                phase,
            } => {
                finite("wind.mean", mean)?;
                finite("wind.amplitude", amplitude)?;
                finite("wind.frequency", &[*frequency])?;
                finite("wind.phase", &[*phase])?;
                Box::new(SinusoidWind {
                    mean: *mean,
                    amplitude: *amplitude,
                    frequency: *frequency,
                    phase: *phase,
                })
            }
            WindSpec::Ladder { times, velocities } => {
                Box::new(LadderWind::new(times.clone(), velocities.clone()).map_err(key)?)
            }
            WindSpec::Dryden {
                mean,
                sigma,
                length,
                speed,
                seed,
                grid,
            } => Box::new(
                DrydenWind::new(DrydenSpec {
                    mean: *mean,
                    sigma: *sigma,
                    length: *length,
                    speed: *speed,
                    seed: *seed,
                    grid: *grid,
                })
                .map_err(key)?,
            ),
        })
    }
}

impl Default for VehicleSpec {
    fn default() -> Self {
        Self {
            kind: VehicleKind::Quadrotor,
            mass: paper::MASS,
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

/// One flight-mode segment.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// `attitude` or `position`.
    pub mode: ModeKind,
    /// End time, s (absolute); absent for the last segment.
    #[serde(default)]
    pub until: Option<f64>,
    /// Or: leave the segment when Ψ against its desired attitude drops
    /// below this (0 < value < 2); the crossing is located to rounding.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub until_psi: Option<f64>,
    /// Attitude reference (attitude mode).
    #[serde(default)]
    pub attitude: Option<AttitudeRef>,
    /// Position reference (position mode; in attitude mode, the target of
    /// the `pd-projection` thrust).
    #[serde(default)]
    pub position: Option<PositionRef>,
    /// Thrust in attitude mode.
    #[serde(default)]
    pub thrust: ThrustSpec,
}

impl SegmentSpec {
    /// Position mode towards `reference`, with no end.
    pub fn position(reference: PositionRef) -> Self {
        Self {
            mode: ModeKind::Position,
            until: None,
            until_psi: None,
            attitude: None,
            position: Some(reference),
            thrust: ThrustSpec::Hover,
        }
    }

    /// Attitude mode tracking `reference` with `thrust`, with no end.
    pub fn attitude(reference: AttitudeRef, thrust: ThrustSpec) -> Self {
        Self {
            mode: ModeKind::Attitude,
            until: None,
            until_psi: None,
            attitude: Some(reference),
            position: None,
            thrust,
        }
    }

    /// The same segment, ending at time `t`, s (absolute).
    pub fn until(self, t: f64) -> Self {
        Self {
            until: Some(t),
            ..self
        }
    }

    /// The same segment, ending when Ψ drops below `psi`.
    pub fn until_psi(self, psi: f64) -> Self {
        Self {
            until_psi: Some(psi),
            ..self
        }
    }

    /// The same attitude segment with `position` as the target of its
    /// `pd-projection` thrust.
    pub fn toward(self, position: PositionRef) -> Self {
        Self {
            position: Some(position),
            ..self
        }
    }
}

/// Flight mode.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ModeKind {
    /// Attitude tracking (eqn:aM).
    Attitude,
    /// Position tracking (eqn:f, eqn:M).
    Position,
}

/// Attitude-mode thrust.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ThrustSpec {
    /// m g.
    #[default]
    Hover,
    /// f = (k_x e_x + k_v e_v + m g e3 − m ẍ_d)·R e3 towards the segment's
    /// position reference (the paper's flip).
    PdProjection,
}

/// Attitude references.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum AttitudeRef {
    /// The paper's flip: R_d(t) = exp(π t e3^) exp(4π t e2^). A struct
    /// variant with no fields, not a unit variant, so that an unknown key
    /// beside `kind` is rejected (serde lets a unit variant of a tagged
    /// enum ignore extra keys).
    PaperFlip {},
    /// The paper's experiment: 3-2-1 Euler angles φ = a sin(ωt),
    /// θ = a cos(ωt), ψ = 0, R_d = R_y(θ) R_x(φ).
    EulerExperiment {
        /// Amplitude a, rad (paper: π/9).
        amplitude: f64,
        /// ω, rad/s (paper: π).
        frequency: f64,
    },
    /// A fixed attitude, as a rotation vector.
    Hold {
        /// Rotation vector, rad.
        rotation: [f64; 3],
    },
}

/// Position references.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum PositionRef {
    /// Hold x_d with heading b1d.
    Hold {
        /// x_d, m.
        x: [f64; 3],
        /// b1d (normalised internally).
        b1d: [f64; 3],
    },
    /// Lissajous figure eight x_d = c + (a sin ωt, b sin 2ωt, 0), b1d = e1.
    FigureEight {
        /// Centre, m.
        center: [f64; 3],
        /// Half-width along e1, m.
        a: f64,
        /// Half-height along e2, m.
        b: f64,
        /// ω, rad/s.
        omega: f64,
    },
    /// Circle x_d = c + r (cos ωt, sin ωt, 0), b1d = e1; ω < 0 turns the
    /// other way (RotorPy's z-up circle seen with e3 down).
    Circle {
        /// Centre, m.
        center: [f64; 3],
        /// Radius, m.
        radius: f64,
        /// ω, rad/s.
        omega: f64,
    },
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
    /// Sampled: controller rate, Hz.
    pub rate: f64,
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

/// A scene that failed to load or validate.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// What is wrong, naming the key and the value.
    pub message: String,
    /// `file:line:column` when known.
    pub location: Option<String>,
    /// The key a validation error is about, dotted by table
    /// (`integrator.kind`; in a segment, the key inside `[[plan]]`);
    /// `None` for a TOML syntax or type error, which the location alone
    /// places.
    pub key: Option<String>,
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.location {
            Some(l) => write!(f, "{l}: {}", self.message),
            None => f.write_str(&self.message),
        }
    }
}

impl std::error::Error for SceneError {}

impl SceneError {
    /// A validation error about `key`, without a place in a file.
    pub fn at_key(key: &str, message: String) -> Self {
        Self {
            message,
            location: None,
            key: Some(key.to_string()),
        }
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
        let scene: Scene = toml::from_str(text).map_err(|e| {
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

    /// Serialises to TOML (the inverse of [`Scene::from_toml`]).
    ///
    /// Infallible: every field is a number, string, bool, array or a map
    /// with string keys, which TOML always represents (NaN and ±∞ as
    /// `nan`/`inf`); the tests serialise every built-in scene, non-finite
    /// values and registered-kind parameters.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a Scene has only types TOML represents")
    }

    /// Checks that the vehicle kind is a built-in or one of `custom_kinds`.
    pub fn check_kind(&self, custom_kinds: &[&str]) -> Result<(), (&'static str, String)> {
        if let VehicleKind::Custom(name) = &self.vehicle.kind
            && !custom_kinds.contains(&name.as_str())
        {
            let mut names: Vec<&str> = VehicleKind::BUILT_IN.iter().map(|k| k.name()).collect();
            names.extend_from_slice(custom_kinds);
            return Err((
                "vehicle.kind",
                format!(
                    "vehicle `kind` = \"{name}\": expected one of {} (a program can register \
                     its own kinds with scenarios::Registry)",
                    names.join(", ")
                ),
            ));
        }
        if !matches!(self.vehicle.kind, VehicleKind::Custom(_)) && !self.vehicle.params.is_empty() {
            return Err((
                "vehicle.params",
                format!(
                    "`vehicle.params` is for registered kinds; the built-in `{}` takes none",
                    self.vehicle.kind.name()
                ),
            ));
        }
        Ok(())
    }

    /// Checks values; on failure returns the dotted key and a message naming
    /// it and the value.
    pub fn validate(&self) -> Result<(), (&'static str, String)> {
        pos("duration", self.duration)?;
        self.validate_vehicle()?;
        self.validate_settings()?;
        let mut last = 0.0;
        for (k, seg) in self.plan.iter().enumerate() {
            self.validate_segment(k, seg, &mut last)?;
            validate_references(k, seg)?;
        }
        if !self.plan.is_empty() && self.vehicle.kind == VehicleKind::FreeRigidBody {
            return Err((
                "plan",
                "a free rigid body has no actuators; remove the `[[plan]]` segments".into(),
            ));
        }
        Ok(())
    }

    /// The vehicle table: positive mass, arm and principal moments that a
    /// rigid body can have (unless the file allows otherwise), finite rest.
    fn validate_vehicle(&self) -> Result<(), (&'static str, String)> {
        let ve = &self.vehicle;
        pos("vehicle.mass", ve.mass)?;
        for j in ve.inertia {
            pos("vehicle.inertia", j)?;
        }
        // Principal moments of a rigid body: each is at most the sum of
        // the other two (J3 = ∫(x² + y²) ≤ ∫(y² + z²) + ∫(x² + z²)).
        let [j1, j2, j3] = ve.inertia;
        for (k, (a, b, c)) in [(j1, j2, j3), (j2, j1, j3), (j3, j1, j2)]
            .into_iter()
            .enumerate()
        {
            if a > (b + c) * (1.0 + 1e-12) && !ve.allow_nonphysical_inertia {
                return Err((
                    "vehicle.inertia",
                    format!(
                        "`vehicle.inertia` = {:?}: J{} = {a} exceeds the sum of the other two ({}); \
                         no rigid body has these principal moments (set \
                         `allow_nonphysical_inertia = true` to use them anyway, as the paper's \
                         example does)",
                        ve.inertia,
                        k + 1,
                        b + c
                    ),
                ));
            }
        }
        nonneg("vehicle.gravity", ve.gravity)?;
        pos("vehicle.arm", ve.arm)?;
        self.validate_multirotor()?;
        nonneg("vehicle.stand_height", ve.stand_height)?;
        if !(ve.c_tau_f.is_finite() && ve.c_tau_f != 0.0) {
            return Err((
                "vehicle.c_tau_f",
                format!(
                    "`vehicle.c_tau_f` = {}: must be finite and non-zero",
                    ve.c_tau_f
                ),
            ));
        }
        Ok(())
    }

    /// The `[vehicle.multirotor]` table: present exactly for the
    /// `multirotor` kind, parameters the vehicle accepts, and rotors that
    /// can lift the airframe (a scene that names a preset but keeps the
    /// default airframe, the paper's 4.34 kg, would otherwise fall).
    fn validate_multirotor(&self) -> Result<(), (&'static str, String)> {
        let ve = &self.vehicle;
        let key = "vehicle.multirotor";
        match (&ve.kind, &ve.multirotor) {
            (VehicleKind::Multirotor, None) => {
                return Err((
                    key,
                    "the `multirotor` kind needs a `[vehicle.multirotor]` table with \
                     `preset = \"crazyflie\"` or `\"hummingbird\"`"
                        .into(),
                ));
            }
            (VehicleKind::Multirotor, Some(_)) => {}
            (k, Some(_)) => {
                return Err((
                    key,
                    format!(
                        "`[vehicle.multirotor]` is for the `multirotor` kind, not `{}`",
                        k.name()
                    ),
                ));
            }
            (_, None) => return Ok(()),
        }
        if let Some(spec) = &ve.multirotor {
            match (&spec.rotor_positions, &spec.rotor_directions) {
                (Some(p), Some(d)) if p.len() != d.len() => {
                    return Err((
                        "vehicle.multirotor.rotor_directions",
                        format!(
                            "`rotor_directions` has {} entries for {} `rotor_positions`; give one per rotor",
                            d.len(),
                            p.len()
                        ),
                    ));
                }
                (Some(_), None) | (None, Some(_)) => {
                    return Err((
                        "vehicle.multirotor.rotor_positions",
                        "`rotor_positions` and `rotor_directions` go together (the X layout is the default for neither)".into(),
                    ));
                }
                _ => {}
            }
        }
        let p = multirotor_params::<lie::NalgebraF64>(self);
        let lift = p.rotors.len() as f64 * p.k_eta * p.rotor_speed_max * p.rotor_speed_max;
        if let Err(e) = dynamics::Multirotor::new(p) {
            return Err((key, format!("`[vehicle.multirotor]`: {e}")));
        }
        if lift <= ve.mass * ve.gravity {
            return Err((
                "vehicle.mass",
                format!(
                    "`vehicle.mass` = {} kg: the rotors lift at most {lift:.4} N (n k_eta \
                     rotor_speed_max²), not the weight {:.4} N; give the airframe's own mass, \
                     inertia and arm (the crazyflie's: mass = 0.03, inertia = [1.43e-5, \
                     1.43e-5, 2.89e-5], arm = 0.043)",
                    ve.mass,
                    ve.mass * ve.gravity
                ),
            ));
        }
        Ok(())
    }

    /// Disturbances, initial state, gains, integrator, control, recording.
    fn validate_settings(&self) -> Result<(), (&'static str, String)> {
        if let Some(w) = &self.wind {
            w.build()?;
        }
        if let Some(d) = &self.disturbance {
            finite3("disturbance.force", &d.force)?;
            finite3("disturbance.moment", &d.moment)?;
        }
        let i = &self.initial;
        finite3("initial.x", &i.x)?;
        finite3("initial.v", &i.v)?;
        finite3("initial.rotation", &i.rotation)?;
        finite3("initial.omega", &i.omega)?;
        let g = &self.gains;
        for (k, v) in [
            ("gains.k_x", g.k_x),
            ("gains.k_v", g.k_v),
            ("gains.k_r", g.k_r),
            ("gains.k_omega", g.k_omega),
            ("gains.sigma", g.sigma),
        ] {
            pos(k, v)?;
        }
        for (k, v) in [
            ("gains.k_i", g.k_i),
            ("gains.k_att_i", g.k_att_i),
            ("gains.c1", g.c1),
            ("gains.c2", g.c2),
        ] {
            nonneg(k, v)?;
        }
        pos("integrator.dt", self.integrator.dt)?;
        if self
            .integrator
            .kind
            .parse::<integrators::IntegratorKind>()
            .is_err()
        {
            return Err((
                "integrator.kind",
                format!(
                    "integrator `kind` = \"{}\": expected one of lgvi, rk4, rk4-projected, rkmk4, euler, dopri",
                    self.integrator.kind
                ),
            ));
        }
        pos("integrator.tol", self.integrator.tol)?;
        // Checked even when unused (continuous control): a NaN in a file
        // is a mistake whatever the timing.
        if self.control.timing == Timing::Sampled {
            if !(self.control.rate.is_finite() && self.control.rate > 0.0) {
                return Err((
                    "control.rate",
                    format!(
                        "`rate` = {}: `timing = \"sampled\"` needs a controller rate > 0 (Hz) in [control]",
                        self.control.rate
                    ),
                ));
            }
        } else {
            nonneg("control.rate", self.control.rate)?;
        }
        pos("record.sample", self.record.sample)?;
        Ok(())
    }

    /// Segment `k`: its switch (`until` after the previous one's, or
    /// `until_psi` in (0, 2) with a segment after it) and its mode's
    /// references; `last` is the previous `until`.
    fn validate_segment(
        &self,
        k: usize,
        seg: &SegmentSpec,
        last: &mut f64,
    ) -> Result<(), (&'static str, String)> {
        let is_last = k + 1 == self.plan.len();
        if let Some(p) = seg.until_psi {
            if seg.until.is_some() {
                return Err((
                    "until_psi",
                    format!("plan[{k}] has both `until` and `until_psi`; give one"),
                ));
            }
            if !(p.is_finite() && p > 0.0 && p < 2.0) {
                return Err((
                    "until_psi",
                    format!("plan[{k}] `until_psi` = {p}: must be in (0, 2)"),
                ));
            }
            if is_last {
                return Err((
                    "until_psi",
                    format!("plan[{k}] is the last segment: `until_psi` has nothing to switch to"),
                ));
            }
        }
        match seg.until {
            // A Ψ-switched segment's own checks are above; its mode and
            // references are checked below like any other's.
            _ if seg.until_psi.is_some() => {}
            Some(u) if !(u.is_finite() && u > *last) => {
                return Err((
                    "until",
                    format!("plan[{k}] `until` = {u}: must be finite and after {last}"),
                ));
            }
            Some(u) => *last = u,
            None if !is_last => {
                return Err((
                    "until",
                    format!("plan[{k}] has no `until`; only the last segment may omit it"),
                ));
            }
            None => {}
        }
        match seg.mode {
            ModeKind::Attitude if seg.attitude.is_none() => {
                return Err((
                    "mode",
                    format!("plan[{k}] is `attitude` mode but has no `[plan.attitude]` reference"),
                ));
            }
            ModeKind::Attitude
                if seg.thrust == ThrustSpec::PdProjection && seg.position.is_none() =>
            {
                return Err((
                    "thrust",
                    format!(
                        "plan[{k}] `thrust` = \"pd-projection\" needs a `[plan.position]` target"
                    ),
                ));
            }
            ModeKind::Position if seg.position.is_none() => {
                return Err((
                    "mode",
                    format!("plan[{k}] is `position` mode but has no `[plan.position]` reference"),
                ));
            }
            ModeKind::Position
                if !matches!(
                    self.vehicle.kind,
                    VehicleKind::Quadrotor
                        | VehicleKind::Hexarotor
                        | VehicleKind::Multirotor
                        | VehicleKind::Custom(_)
                ) =>
            {
                return Err((
                    "mode",
                    format!(
                        "plan[{k}] is `position` mode but the vehicle `{}` cannot translate",
                        self.vehicle.kind.name()
                    ),
                ));
            }
            _ => {}
        }
        Ok(())
    }
}

/// Segment `k`'s reference parameters: a NaN here would surface only as a
/// non-finite command mid-run.
fn validate_references(k: usize, seg: &SegmentSpec) -> Result<(), (&'static str, String)> {
    let num = |key: &'static str, v: f64| -> Result<(), (&'static str, String)> {
        if v.is_finite() {
            Ok(())
        } else {
            Err((key, format!("plan[{k}] `{key}` = {v}: must be finite")))
        }
    };
    let num3 = |key: &'static str, v: &[f64; 3]| -> Result<(), (&'static str, String)> {
        if v.iter().all(|c| c.is_finite()) {
            Ok(())
        } else {
            Err((key, format!("plan[{k}] `{key}` = {v:?}: must be finite")))
        }
    };
    match &seg.attitude {
        Some(AttitudeRef::EulerExperiment {
            amplitude,
            frequency,
        }) => {
            num("amplitude", *amplitude)?;
            num("frequency", *frequency)?;
        }
        Some(AttitudeRef::Hold { rotation }) => num3("rotation", rotation)?,
        Some(AttitudeRef::PaperFlip {}) | None => {}
    }
    match &seg.position {
        Some(PositionRef::Hold { x, b1d }) => {
            num3("x", x)?;
            num3("b1d", b1d)?;
            if b1d.iter().map(|c| c * c).sum::<f64>() < 1e-12 {
                return Err((
                    "b1d",
                    format!("plan[{k}] `b1d` = {b1d:?}: must be non-zero"),
                ));
            }
        }
        Some(PositionRef::FigureEight {
            center,
            a,
            b,
            omega,
        }) => {
            num3("center", center)?;
            num("a", *a)?;
            num("b", *b)?;
            num("omega", *omega)?;
        }
        Some(PositionRef::Circle {
            center,
            radius,
            omega,
        }) => {
            num3("center", center)?;
            num("radius", *radius)?;
            num("omega", *omega)?;
        }
        None => {}
    }
    Ok(())
}

fn pos(key: &'static str, v: f64) -> Result<(), (&'static str, String)> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err((key, format!("`{key}` = {v}: must be finite and > 0")))
    }
}
fn nonneg(key: &'static str, v: f64) -> Result<(), (&'static str, String)> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err((key, format!("`{key}` = {v}: must be finite and ≥ 0")))
    }
}
fn finite3(key: &'static str, v: &[f64; 3]) -> Result<(), (&'static str, String)> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err((key, format!("`{key}` = {v:?}: must be finite")))
    }
}

fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let col = before.rfind('\n').map_or(offset, |p| offset - p - 1) + 1;
    (line, col)
}

/// Where a validation error about `key` points: for a message about
/// `plan[k]`, the key inside the k-th `[[plan]]` segment (or that segment's
/// header when the key is missing there); otherwise the first `key`.
fn locate_error(text: &str, key: &str, message: &str) -> Option<(usize, usize)> {
    let segment = message
        .strip_prefix("plan[")
        .and_then(|r| r.split(']').next())
        .and_then(|k| k.parse::<usize>().ok());
    if let Some(k) = segment {
        let lines: Vec<&str> = text.lines().collect();
        let starts: Vec<usize> = (0..lines.len())
            .filter(|&i| lines[i].trim().starts_with("[[plan]]"))
            .collect();
        if let Some(&start) = starts.get(k) {
            // The segment runs to the next header that is not a sub-table
            // of this segment.
            let end = (start + 1..lines.len())
                .find(|&i| {
                    let t = lines[i].trim();
                    t.starts_with('[') && !t.starts_with("[plan.")
                })
                .unwrap_or(lines.len());
            let body = lines[start..end].join("\n");
            return Some(locate_key(&body, key).map_or((start + 1, 1), |(l, c)| (start + l, c)));
        }
    }
    Some(locate_dotted(text, key))
}

/// The name of a table header line (`[vehicle]`, `[ plan.position ]  # c`
/// → `vehicle`, `plan.position`), `None` for other lines; arrays of tables
/// (`[[plan]]`) keep one pair of brackets off.
fn header_name(line: &str) -> Option<String> {
    let t = line.split('#').next().unwrap_or_default().trim();
    let inner = t.strip_prefix('[')?.strip_suffix(']')?;
    let inner = inner
        .strip_prefix('[')
        .and_then(|i| i.strip_suffix(']'))
        .unwrap_or(inner);
    Some(
        inner
            .split('.')
            .map(str::trim)
            .collect::<Vec<_>>()
            .join("."),
    )
}

/// Where `key` (`table.name`, or a top-level `name`) is set: `name =` in
/// the `[table]` section (top-level keys: before the first header), else a
/// table header naming the key itself (`[vehicle.params]`), else a dotted
/// `table.name =` or an inline `table = { name = … }`, else the `[table]`
/// header (the key is absent and its default failed a check), else the
/// first `name =` anywhere, else the file's start.
fn locate_dotted(text: &str, key: &str) -> (usize, usize) {
    let (table, name) = key.rsplit_once('.').unwrap_or(("", key));
    let lines: Vec<&str> = text.lines().collect();
    let headers: Vec<(usize, String)> = lines
        .iter()
        .enumerate()
        .filter_map(|(i, l)| header_name(l).map(|n| (i, n)))
        .collect();
    let section = if table.is_empty() {
        Some(0)
    } else {
        headers.iter().find(|(_, n)| n == table).map(|(i, _)| i + 1)
    };
    if let Some(start) = section {
        let end = headers
            .iter()
            .map(|(i, _)| *i)
            .find(|&i| i >= start)
            .unwrap_or(lines.len());
        let body = lines[start..end].join("\n");
        if let Some((l, c)) = locate_key(&body, name).filter(|(l, _)| *l <= end - start) {
            return (start + l, c);
        }
    }
    if let Some((i, _)) = headers.iter().find(|(_, n)| n == key) {
        return (i + 1, 1);
    }
    if !table.is_empty() {
        if let Some(p) = locate_key(text, key) {
            return p;
        }
        let last = table.rsplit('.').next().unwrap_or(table);
        for (i, l) in lines.iter().enumerate() {
            if let Some((lhs, rhs)) = l.split_once('=')
                && lhs.trim() == last
                && rhs.contains(name)
            {
                return (i + 1, l.len() - l.trim_start().len() + 1);
            }
        }
        if let Some(start) = section {
            return (start, 1);
        }
    }
    locate_key(text, name).unwrap_or((1, 1))
}

/// First `key =` in the text (the dotted context is in the message).
fn locate_key(text: &str, key: &str) -> Option<(usize, usize)> {
    let is_ident = |c: char| c.is_ascii_alphanumeric() || c == '_' || c == '-';
    // `key = …` at the start of a line, then anywhere in one (an inline
    // table), then a table header ending in the key (`[vehicle.params]`).
    let assignment = |line: &str, from_start: bool| -> Option<usize> {
        let mut search = 0;
        while let Some(off) = line[search..].find(key) {
            let at = search + off;
            let before_ok = line[..at].chars().next_back().is_none_or(|c| !is_ident(c));
            let rest = &line[at + key.len()..];
            if before_ok
                && rest.trim_start().starts_with('=')
                && (!from_start || line[..at].trim().is_empty())
            {
                return Some(at);
            }
            search = at + key.len();
        }
        None
    };
    for from_start in [true, false] {
        for (i, line) in text.lines().enumerate() {
            if let Some(at) = assignment(line, from_start) {
                return Some((i + 1, line[..at].chars().count() + 1));
            }
        }
    }
    for (i, line) in text.lines().enumerate() {
        let t = line.trim();
        if t.starts_with('[') {
            let name = t.trim_matches(|c| c == '[' || c == ']').trim();
            if name
                .rsplit('.')
                .next()
                .is_some_and(|last| last.trim() == key)
            {
                return Some((i + 1, line.len() - line.trim_start().len() + 1));
            }
        }
    }
    None
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
