//! Scenes as one front end of the [`Simulation`]: a [`Scene`] becomes a
//! vehicle, a plan of [`Mode`](controllers::Mode)s with their references, an integrator and
//! the run settings. A [`Registry`] adds a program's own vehicle kinds, so a
//! scene file can name them.

use std::any::{Any, TypeId};
use std::collections::BTreeMap;
use std::sync::Arc;

use controllers::{
    AccelerationModel, AttitudeGains, AttitudeMode, AttitudeThrust, FlightPhase, Mode, MotorsOff,
    PositionGains, PositionMode, PositionReference, RigidBodyParams, VehicleState,
};
use dynamics::{
    AttitudeStand, Disturbance, FreeRigidBody, Hexarotor, Multirotor, Quadrotor, Vehicle,
};
use integrators::{Stepper, StepperConfig};
use lie::{
    Backend, GlamF32, GlamF64, NalgebraF32, NalgebraF64, Real, Rotation, S, So3Mat, V3, ops,
};

use crate::reference::{self, m, v};
use crate::scene::{
    AccelModel, BackendKind, GainsSpec, ModeKind, Scalar, Scene, ThrustSpec, VehicleKind,
};
use crate::sources::{SceneAttitude, ScenePosition};
use crate::{Error, SceneError, builtin};
use scenarios::{RunOptions, RunOutput, Segment, SimError, Simulation, SimulationBuilder, Until};

/// Builds a program's own vehicle kind from a scene, on any backend.
///
/// Register it with [`Registry::vehicle`]; a scene file then names it in
/// `vehicle.kind`, with its own numbers in `[vehicle.params]` (the
/// [`Registry`] page runs a whole scene through one).
///
/// ```
/// use dynamics::{FreeRigidBody, Vehicle};
/// use lie::{Backend, ops};
/// use scenes::{FactoryError, Scene, VehicleFactory};
///
/// /// A free body whose inertia is `params.scale` times the scene's.
/// struct Scaled;
/// impl VehicleFactory for Scaled {
///     fn build<B: Backend>(&self, scene: &Scene) -> Result<Box<dyn Vehicle<B>>, FactoryError> {
///         let k = scene.vehicle.params.get("scale").copied().unwrap_or(1.0);
///         if !(k > 0.0) {
///             return Err(format!("vehicle.params.scale = {k}: must be positive").into());
///         }
///         let [a, b, c] = scene.vehicle.inertia.map(|j| lie::Real::lit(k * j));
///         Ok(Box::new(FreeRigidBody::<B>::new(ops::diag::<B>(a, b, c))?))
///     }
/// }
/// let mut scene = scenes::builtin::free_rigid_body();
/// scene.vehicle.params.insert("scale".into(), 2.0);
/// let v = Scaled.build::<lie::NalgebraF64>(&scene)?;
/// assert_eq!(ops::elems::<lie::NalgebraF64>(v.inertia())[0][0], 2.0 * scene.vehicle.inertia[0]);
/// // A bad value comes back as the factory's message, through a run too.
/// scene.vehicle.params.insert("scale".into(), -1.0);
/// let e = Scaled.build::<lie::NalgebraF64>(&scene).err().unwrap();
/// assert_eq!(e.to_string(), "vehicle.params.scale = -1: must be positive");
/// # Ok::<(), FactoryError>(())
/// ```
pub trait VehicleFactory: Send + Sync + 'static {
    /// The vehicle of `scene` (read `scene.vehicle`, its `params`, and
    /// `scene.disturbance`). An `Err` of any error type (a
    /// [`dynamics::DynamicsError`] with `?`, or a message naming the
    /// parameter and value at fault) becomes [`Error::CustomVehicle`]
    /// naming the kind, with the error kept as its source.
    fn build<B: Backend>(&self, scene: &Scene) -> Result<Box<dyn Vehicle<B>>, FactoryError>;
}

/// What a [`VehicleFactory`] returns when it cannot build: any error,
/// boxed (`String`, `&str` and every `Error` type convert with `?` or
/// `.into()`).
pub type FactoryError = Box<dyn std::error::Error + Send + Sync>;

type Build<B> = Box<dyn Fn(&Scene) -> Result<Box<dyn Vehicle<B>>, FactoryError> + Send + Sync>;

/// The vehicle kinds a program adds to scene files, and the entry points
/// that know them: [`Registry::load`], [`Registry::from_toml`],
/// [`Registry::run`]. The free functions [`crate::load`] and [`crate::run`]
/// use an empty registry.
///
/// ```
/// use dynamics::{Quadrotor, Vehicle};
/// use lie::{Backend, Real};
/// use scenes::{FactoryError, Registry, Scene, VehicleFactory};
///
/// /// The paper's quadrotor, heavier by `params.payload` kg.
/// struct Loaded;
/// impl VehicleFactory for Loaded {
///     fn build<B: Backend>(&self, scene: &Scene) -> Result<Box<dyn Vehicle<B>>, FactoryError> {
///         let payload = scene.vehicle.params.get("payload").copied().unwrap_or(0.0);
///         let mut q = Quadrotor::<B>::paper();
///         q = Quadrotor::new(q.mass() + B::Scalar::lit(payload), q.inertia(), q.gravity(),
///             B::Scalar::lit(scene.vehicle.arm), B::Scalar::lit(scene.vehicle.c_tau_f))?;
///         Ok(Box::new(q))
///     }
/// }
///
/// let registry = Registry::new().vehicle("loaded-quadrotor", Loaded);
/// let text = std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/paper-flip.toml"))
///     .unwrap()
///     .replace("kind = \"quadrotor\"", "kind = \"loaded-quadrotor\"\nparams = { payload = 0.1 }");
/// let scene = registry.from_toml(&text, "loaded.toml").unwrap();
/// // Without the registration the same file is an error naming the key.
/// assert!(Scene::from_toml(&text, "loaded.toml").is_err());
/// let out = registry.run(&scene, Default::default()).unwrap();
/// assert!(out.last.psi < 1e-2);
/// ```
#[derive(Default)]
pub struct Registry {
    vehicles: BTreeMap<(String, TypeId), Box<dyn Any + Send + Sync>>,
    names: Vec<String>,
}

impl Registry {
    /// No registered kinds.
    pub fn new() -> Self {
        Self::default()
    }

    /// Registers `factory` as vehicle kind `name` (kebab-case by
    /// convention); a later registration of the same name replaces it.
    pub fn vehicle<F: VehicleFactory>(mut self, name: &str, factory: F) -> Self {
        let f = Arc::new(factory);
        self.insert::<NalgebraF64, F>(name, f.clone());
        self.insert::<GlamF64, F>(name, f.clone());
        self.insert::<NalgebraF32, F>(name, f.clone());
        self.insert::<GlamF32, F>(name, f);
        if !self.names.iter().any(|n| n == name) {
            self.names.push(name.to_string());
        }
        self
    }

    fn insert<B: Backend, F: VehicleFactory>(&mut self, name: &str, f: Arc<F>) {
        let build: Build<B> = Box::new(move |scene| f.build::<B>(scene));
        self.vehicles
            .insert((name.to_string(), TypeId::of::<B>()), Box::new(build));
    }

    /// The registered kind names.
    pub fn kinds(&self) -> Vec<&str> {
        self.names.iter().map(String::as_str).collect()
    }

    /// Parses a TOML scene that may name a registered kind.
    pub fn from_toml(&self, text: &str, origin: &str) -> Result<Scene, SceneError> {
        Scene::from_toml_with_kinds(text, origin, &self.kinds())
    }

    /// A built-in scene by name, or a TOML file by path.
    pub fn load(&self, name_or_path: &str) -> Result<Scene, SceneError> {
        if let Some(s) = builtin::by_name(name_or_path) {
            return Ok(s);
        }
        let path = std::path::Path::new(name_or_path);
        if path.exists() || name_or_path.ends_with(".toml") {
            let text = std::fs::read_to_string(path).map_err(|e| SceneError {
                message: format!("cannot read scene file `{name_or_path}`: {e}"),
                location: None,
                key: None,
            })?;
            return self.from_toml(&text, name_or_path);
        }
        let names: Vec<String> = builtin::all().into_iter().map(|s| s.name).collect();
        Err(SceneError {
            message: format!(
                "no scene `{name_or_path}`: not a built-in ({}) and not a file",
                names.join(", ")
            ),
            location: None,
            key: None,
        })
    }

    /// The vehicle of `scene` on backend `B`.
    pub fn build_vehicle<B: Backend>(&self, scene: &Scene) -> Result<Box<dyn Vehicle<B>>, Error> {
        self.build_vehicle_seeded(scene, Seeds::NONE)
    }

    /// [`Registry::build_vehicle`] with `seeds` (a registered kind reads
    /// the scene on its own and takes none).
    pub(crate) fn build_vehicle_seeded<B: Backend>(
        &self,
        scene: &Scene,
        seeds: Seeds<'_>,
    ) -> Result<Box<dyn Vehicle<B>>, Error> {
        if let VehicleKind::Custom(name) = &scene.vehicle.kind {
            let build = self
                .vehicles
                .get(&(name.clone(), TypeId::of::<B>()))
                .and_then(|b| b.downcast_ref::<Build<B>>())
                .ok_or_else(|| {
                    Error::Scene(scene.check_kind(&self.kinds()).err().map_or_else(
                        || SceneError::at_key("vehicle.kind", format!("vehicle kind `{name}`")),
                        |(k, m)| SceneError::at_key(k, m),
                    ))
                })?;
            let vehicle = build(scene).map_err(|e| Error::CustomVehicle {
                kind: name.clone(),
                source: crate::BuildError::new(e),
            })?;
            return on_ground(scene, vehicle);
        }
        let vehicle = build_vehicle_seeded::<B>(scene, seeds)?;
        on_ground(scene, vehicle)
    }

    /// Runs `scene` with its scalar and backend.
    pub fn run(&self, scene: &Scene, opts: RunOptions<'_>) -> Result<RunOutput, Error> {
        match (scene.scalar, scene.backend) {
            (Scalar::F64, BackendKind::Nalgebra) => self.run_generic::<NalgebraF64>(scene, opts),
            (Scalar::F64, BackendKind::Glam) => self.run_generic::<GlamF64>(scene, opts),
            (Scalar::F32, BackendKind::Nalgebra) => self.run_generic::<NalgebraF32>(scene, opts),
            (Scalar::F32, BackendKind::Glam) => self.run_generic::<GlamF32>(scene, opts),
        }
    }

    /// The simulation of `scene` on backend `B`, ready to change (a
    /// guard, a stop condition, another integrator) and build: what
    /// [`Registry::run`] runs, for a caller that steps it
    /// ([`Simulation::advance_to`]).
    pub fn builder<B: Backend>(
        &self,
        scene: &Scene,
    ) -> Result<SimulationBuilder<'static, B>, Error> {
        self.check(scene)?;
        let vehicle = self.build_vehicle::<B>(scene)?;
        let plan = plan::<B>(scene, vehicle.as_ref());
        builder_from::<B>(scene, vehicle, plan, Seeds::NONE)
    }

    /// Runs `scene` on backend `B`.
    pub fn run_generic<B: Backend>(
        &self,
        scene: &Scene,
        opts: RunOptions<'_>,
    ) -> Result<RunOutput, Error> {
        self.check(scene)?;
        let (vehicle, plan) = self.parts::<B>(scene, None, Seeds::NONE)?;
        builder_from::<B>(scene, vehicle, plan, Seeds::NONE)?
            .build()?
            .run(opts)
            .map_err(Error::Run)
    }

    /// `scene` validated, its vehicle kind built in or registered here.
    #[doc(hidden)]
    pub fn check(&self, scene: &Scene) -> Result<(), Error> {
        scene
            .validate()
            .and_then(|()| scene.check_kind(&self.kinds()))
            .map_err(|(k, msg)| Error::at_key(k, msg))
    }

    /// The vehicle and plan of a validated `scene`.
    #[doc(hidden)]
    pub fn parts<B: Backend>(
        &self,
        scene: &Scene,
        position: Option<&PositionFn>,
        seeds: Seeds<'_>,
    ) -> Result<Parts<B>, Error> {
        let vehicle = self.build_vehicle_seeded::<B>(scene, seeds)?;
        let plan = plan_with::<B>(scene, vehicle.as_ref(), position, seeds);
        Ok((vehicle, plan))
    }
}

/// A scene's vehicle and plan.
pub type Parts<B> = (Box<dyn Vehicle<B>>, Vec<Segment<'static, B>>);

/// The [`SimulationBuilder`] of `scene` with `vehicle` flying `plan`.
#[doc(hidden)]
pub fn builder_from<B: Backend>(
    scene: &Scene,
    vehicle: Box<dyn Vehicle<B>>,
    plan: Vec<Segment<'static, B>>,
    seeds: Seeds<'_>,
) -> Result<SimulationBuilder<'static, B>, Error> {
    let kind: integrators::IntegratorKind =
        scene.integrator.kind.parse().map_err(Error::Integrator)?;
    let stepper = Stepper::<B>::new(
        kind,
        StepperConfig {
            tol: scene.integrator.tol,
        },
    );
    let i = &scene.initial;
    let mut body = dynamics::RigidBodyState::<B>::at_rest();
    body.r = m::<B>(reference::rotation_f64(i.rotation)).matrix();
    if seeds.any("initial.attitude") {
        // R₀ ⊕ δ = R₀ Exp(δ), δ = 0 seeded: derivatives in the tangent space.
        let delta = seeds.vec::<B>("initial.attitude", [0.0; 3]);
        body.r = body.r * So3Mat::<B>::exp(delta).matrix();
    }
    body.omega = seeds.vec::<B>("initial.omega", i.omega);
    body.x = seeds.vec::<B>("initial.x", i.x);
    body.v = seeds.vec::<B>("initial.v", i.v);
    let floor = integrators::Dopri::<B>::floor().to_f64_lossless();
    let tol_warning = (kind == integrators::IntegratorKind::Dopri && scene.integrator.tol < floor)
        .then(|| {
            format!(
                "dopri tolerance {:e} is below what {} can deliver; using its ε = {floor:.2e}",
                scene.integrator.tol,
                if floor > 1e-10 { "f32" } else { "f64" }
            )
        });
    let format_note = scene
        .format
        .is_none()
        .then(crate::scene::missing_format_note);
    let warning = format_note.into_iter().chain(tol_warning);
    let mut b = Simulation::<B>::builder(vehicle)
        .integrator(stepper)
        .initial(body)
        .dt(scene.integrator.dt)
        .duration(scene.duration)
        .record_every(scene.record.sample)
        .locate_events(scene.integrator.locate_events)
        .compensate_configuration_moment(scene.control.compensate_configuration_moment)
        .control(
            scene
                .control
                .control()
                .map_err(|(k, msg)| Error::at_key(k, msg))?,
        );
    b = with_sensing(scene, b, seeds)?;
    for seg in plan {
        b = b.segment(seg);
    }
    if let Some(w) = &scene.wind {
        b = b.wind(w.build().map_err(|(k, msg)| Error::at_key(k, msg))?);
    }
    Ok(b.warnings(warning))
}

/// The controller's view of the vehicle and the scene's gains.
#[doc(hidden)]
pub fn gains<B: Backend>(
    scene: &Scene,
    vehicle: &dyn Vehicle<B>,
    seeds: Seeds<'_>,
) -> (
    RigidBodyParams<B>,
    PositionGains<B>,
    AttitudeGains<B>,
    AccelerationModel<B>,
) {
    let (pg, ag, model) = controller_gains::<B>(&scene.gains, seeds);
    (controller_params(scene, vehicle, seeds), pg, ag, model)
}

/// Mass, inertia and gravity as the scene's controller knows them: the
/// scene's numbers (the mass `model_mass` when given), the vehicle's
/// inertia (a kind may derive it).
#[doc(hidden)]
pub fn controller_params<B: Backend>(
    scene: &Scene,
    vehicle: &dyn Vehicle<B>,
    seeds: Seeds<'_>,
) -> RigidBodyParams<B> {
    RigidBodyParams {
        mass: match scene.vehicle.model_mass {
            Some(m) => seeds.lift::<B>("vehicle.model_mass", m),
            None => seeds.lift::<B>("vehicle.mass", scene.vehicle.mass),
        },
        inertia: vehicle.inertia(),
        gravity: seeds.lift::<B>("vehicle.gravity", scene.vehicle.gravity),
    }
}

/// The laws' gains and acceleration model from a scene's `[gains]`.
#[doc(hidden)]
pub fn controller_gains<B: Backend>(
    g: &GainsSpec,
    seeds: Seeds<'_>,
) -> (PositionGains<B>, AttitudeGains<B>, AccelerationModel<B>) {
    let l = |name: &str, x: f64| seeds.lift::<B>(name, x);
    let mut pg = PositionGains::<B>::uniform(
        l("gains.k_x", g.k_x),
        l("gains.k_v", g.k_v),
        l("gains.k_i", g.k_i),
        l("gains.c1", g.c1),
        l("gains.sigma", g.sigma),
    );
    pg.clamp_integral = g.clamp_integral;
    let ag = AttitudeGains::<B>::uniform(
        l("gains.k_r", g.k_r),
        l("gains.k_omega", g.k_omega),
        l("gains.k_att_i", g.k_att_i),
        l("gains.c2", g.c2),
    );
    let model = match g.acceleration_model {
        AccelModel::Nominal => AccelerationModel::Nominal,
        AccelModel::NominalWithoutEstimate => AccelerationModel::NominalWithoutEstimate,
    };
    (pg, ag, model)
}

/// The scene's plan as [`Mode`](controllers::Mode)s. The paper's modes share the integral
/// register `[e_I, e_i]`; the first position segment zeroes `e_i` when
/// entered, later ones keep it (the paper's "when position mode first
/// starts"), unless a take-off, hover or landing came first (position
/// flight has started: the disturbance `e_i` has learnt still acts). A
/// take-off zeroes `e_i` wherever it is; a take-off, hover or landing that
/// starts the plan is anchored at the initial state.
pub fn plan<B: Backend>(scene: &Scene, vehicle: &dyn Vehicle<B>) -> Vec<Segment<'static, B>> {
    plan_with(scene, vehicle, None, Seeds::NONE)
}

/// A position reference given in f64, whatever the simulation's scalar:
/// `t ↦ [x_d, ẋ_d, ẍ_d, x_d⁽³⁾, x_d⁽⁴⁾, b1d, ḃ1d, b̈1d]` (a front end's
/// callable, say; see [`crate::SceneSimulation::with_position`]).
pub type PositionFn = Arc<dyn Fn(f64) -> [[f64; 3]; 8] + Send + Sync>;

/// `f` as a [`PositionSource`](controllers::PositionSource) on `B`.
fn position_source<B: Backend>(f: PositionFn) -> impl Fn(S<B>) -> PositionReference<B> {
    move |t: S<B>| {
        let [x, v_, a, jerk, snap, b1d, b1d_dot, b1d_ddot] = f(t.to_f64_lossless()).map(v::<B>);
        PositionReference {
            x,
            v: v_,
            a,
            jerk,
            snap,
            b1d,
            b1d_dot,
            b1d_ddot,
        }
    }
}

/// [`plan`] with every position-mode segment tracking `position` instead
/// of its scene reference, when given.
fn plan_with<B: Backend>(
    scene: &Scene,
    vehicle: &dyn Vehicle<B>,
    position: Option<&PositionFn>,
    seeds: Seeds<'_>,
) -> Vec<Segment<'static, B>> {
    let (params, pg, ag, model) = gains::<B>(scene, vehicle, seeds);
    let hover = params.mass * params.gravity;
    let mut position_seen = false;
    // Where a take-off, hover or landing that starts the plan is anchored.
    let i = &scene.initial;
    let start = VehicleState {
        x: v::<B>(i.x),
        v: v::<B>(i.v),
        r: So3Mat::<B>::exp(v::<B>(i.rotation)),
        omega: v::<B>(i.omega),
    };
    scene
        .plan
        .iter()
        .map(|s| {
            let mode: Box<dyn Mode<B>> = match s.mode {
                ModeKind::Attitude => {
                    let a = SceneAttitude::<B>::new(s.attitude.as_ref().expect("validated"));
                    let thrust = match s.thrust {
                        ThrustSpec::Hover => AttitudeThrust::Constant(hover),
                        ThrustSpec::PdProjection => AttitudeThrust::PdProjection {
                            gains: pg,
                            reference: ScenePosition::<B>::new(
                                s.position.as_ref().expect("validated"),
                            ),
                        },
                    };
                    Box::new(AttitudeMode::new(params, ag, a, thrust))
                }
                ModeKind::TakeOff | ModeKind::Hover | ModeKind::Land => {
                    position_seen = true;
                    let vertical = s.vertical::<B>().expect("a vertical phase");
                    let start = (&start, S::<B>::lit(0.0));
                    Box::new(FlightPhase::new(params, (pg, ag), model, vertical, start))
                }
                ModeKind::MotorsOff => Box::new(MotorsOff),
                ModeKind::Position => {
                    let keep = std::mem::replace(&mut position_seen, true);
                    match position {
                        Some(f) => {
                            let p = position_source::<B>(f.clone());
                            position_mode(PositionMode::new(params, pg, ag, model, p), keep)
                        }
                        None => {
                            let p =
                                ScenePosition::<B>::new(s.position.as_ref().expect("validated"));
                            position_mode(PositionMode::new(params, pg, ag, model, p), keep)
                        }
                    }
                }
            };
            let until = match (s.until, s.until_psi, s.until_clearance) {
                (Some(u), ..) => Until::Time(u),
                (None, Some(p), _) => Until::PsiBelow(p),
                (None, None, Some(c)) => Until::Condition(clearance_below(scene, c)),
                (None, None, None) => Until::Never,
            };
            Segment { mode, until }
        })
        .collect()
}

/// Whether every foot is at most `clearance` above the scene's ground
/// (validation makes sure the ground is there): the highest foot decides,
/// so a vehicle that lands tilted is down when its last foot is.
fn clearance_below<B: Backend>(scene: &Scene, clearance: f64) -> scenarios::Condition<'static, B> {
    let g = scene.ground.clone().unwrap_or_default();
    let feet: Vec<V3<B>> = g.feet(scene.vehicle.arm).into_iter().map(v::<B>).collect();
    Box::new(move |_t, s, _out| {
        let highest = feet
            .iter()
            .map(|p| B::vec3_to_array(s.x + s.r * *p)[2].to_f64_lossless())
            .fold(f64::INFINITY, f64::min);
        g.height - highest <= clearance
    })
}

/// The paper's position mode, keeping `e_i` on entry after the first
/// position segment (the paper's "when position mode first starts").
fn position_mode<B: Backend, P: controllers::PositionSource<B> + 'static>(
    mode: PositionMode<B, P>,
    keep: bool,
) -> Box<dyn Mode<B>> {
    if keep {
        Box::new(mode.keep_integral_on_entry())
    } else {
        Box::new(mode)
    }
}

/// Builds the built-in vehicle of a scene (a [`VehicleKind::Custom`] kind
/// needs a [`Registry`]), on the scene's ground if it has one.
pub fn build_vehicle<B: Backend>(scene: &Scene) -> Result<Box<dyn Vehicle<B>>, Error> {
    on_ground(scene, build_vehicle_seeded(scene, Seeds::NONE)?)
}

/// `vehicle` over the scene's `[ground]`, if any.
fn on_ground<B: Backend>(
    scene: &Scene,
    vehicle: Box<dyn Vehicle<B>>,
) -> Result<Box<dyn Vehicle<B>>, Error> {
    let Some(g) = &scene.ground else {
        return Ok(vehicle);
    };
    let feet = g.feet(scene.vehicle.arm);
    let v = dynamics::OnGround::new(vehicle, g.ground(), &feet)
        .map_err(|e| Error::Run(SimError::Vehicle(e)))?;
    Ok(Box::new(v))
}

/// [`build_vehicle`] with `seeds` (the mass, inertia, gravity, arm and
/// torque coefficient of the quadrotor-family kinds).
fn build_vehicle_seeded<B: Backend>(
    scene: &Scene,
    seeds: Seeds<'_>,
) -> Result<Box<dyn Vehicle<B>>, Error> {
    let l = S::<B>::lit;
    let ve = &scene.vehicle;
    let [j0, j1, j2] = B::vec3_to_array(seeds.vec::<B>("vehicle.inertia", ve.inertia));
    let j = ops::diag::<B>(j0, j1, j2);
    let err = |e| Error::Run(SimError::Vehicle(e));
    let (mass, gravity) = (
        seeds.lift::<B>("vehicle.mass", ve.mass),
        seeds.lift::<B>("vehicle.gravity", ve.gravity),
    );
    let (arm, c_tau_f) = (
        seeds.lift::<B>("vehicle.arm", ve.arm),
        seeds.lift::<B>("vehicle.c_tau_f", ve.c_tau_f),
    );
    let mut quad = Quadrotor::<B>::new(mass, j, gravity, arm, c_tau_f).map_err(err)?;
    if let Some(d) = &scene.disturbance {
        quad = quad
            .with_disturbance(Disturbance {
                force: v::<B>(d.force),
                moment: v::<B>(d.moment),
            })
            .map_err(err)?;
    }
    Ok(match &ve.kind {
        VehicleKind::Quadrotor => Box::new(quad),
        VehicleKind::PinnedQuadrotor => Box::new(AttitudeStand::new(quad, l(0.0)).map_err(err)?),
        VehicleKind::AttitudeStand => {
            Box::new(AttitudeStand::new(quad, l(ve.stand_height)).map_err(err)?)
        }
        VehicleKind::FreeRigidBody => Box::new(FreeRigidBody::new(j).map_err(err)?),
        VehicleKind::Hexarotor => {
            let mut hex = Hexarotor::<B>::new(mass, j, gravity, arm, c_tau_f).map_err(err)?;
            if let Some(d) = quad.fixed_disturbance() {
                hex = hex.with_disturbance(d).map_err(err)?;
            }
            Box::new(hex)
        }
        VehicleKind::Multirotor => {
            let mut multi =
                Multirotor::new(crate::scene::multirotor_params::<B>(scene)).map_err(err)?;
            if let Some(d) = quad.fixed_disturbance() {
                multi = multi.with_disturbance(d);
            }
            Box::new(multi)
        }
        VehicleKind::Custom(name) => {
            return Err(Error::Scene(SceneError::at_key(
                "vehicle.kind",
                format!("vehicle kind `{name}` is not built in; register it with scenes::Registry"),
            )));
        }
    })
}

/// The scene parameters a run takes derivatives with respect to, by name
/// (see [`PARAMETERS`]); a name's position is its direction. Empty for
/// every run but a gradient's (the `sensitivity` module of `geopid-studies`), and then each
/// number reads exactly as without it.
#[derive(Clone, Copy, Debug)]
#[doc(hidden)]
pub struct Seeds<'a> {
    names: &'a [&'a str],
}

/// The scene parameters a gradient can be taken with respect to: the
/// gains, the quadrotor-family vehicle's numbers (`inertia` per axis), the
/// initial state per component, the attitude as a perturbation
/// `R₀ Exp(δ)` in the body frame, and the invariant EKF's noise scales.
pub const PARAMETERS: &[&str] = &[
    "gains.k_x",
    "gains.k_v",
    "gains.k_i",
    "gains.c1",
    "gains.sigma",
    "gains.k_r",
    "gains.k_omega",
    "gains.k_att_i",
    "gains.c2",
    "vehicle.mass",
    "vehicle.gravity",
    "vehicle.arm",
    "vehicle.c_tau_f",
    "vehicle.inertia[0]",
    "vehicle.inertia[1]",
    "vehicle.inertia[2]",
    "initial.x[0]",
    "initial.x[1]",
    "initial.x[2]",
    "initial.v[0]",
    "initial.v[1]",
    "initial.v[2]",
    "initial.omega[0]",
    "initial.omega[1]",
    "initial.omega[2]",
    "initial.attitude[0]",
    "initial.attitude[1]",
    "initial.attitude[2]",
    "estimator.q_scale",
    "estimator.r_scale",
];

/// The scene's number behind a name of [`PARAMETERS`] (the attitude
/// perturbation `initial.attitude[k]` has none: it is a direction at
/// `R₀`, always 0; the noise scales exist only for an `iekf` estimator):
/// what a gradient's parameter reads, and what a tuning step or a finite
/// difference changes.
pub fn parameter_mut<'s>(scene: &'s mut Scene, name: &str) -> Option<&'s mut f64> {
    if let Some(scale) = name.strip_prefix("estimator.") {
        // Only the invariant EKF reads them; 1 when the scene leaves them.
        let e = scene
            .estimator
            .as_mut()
            .filter(|e| e.kind == crate::scene::EstimatorKind::Iekf)?;
        return match scale {
            "q_scale" => Some(e.q_scale.get_or_insert(1.0)),
            "r_scale" => Some(e.r_scale.get_or_insert(1.0)),
            _ => None,
        };
    }
    let (g, ve, i) = (&mut scene.gains, &mut scene.vehicle, &mut scene.initial);
    Some(match name {
        "gains.k_x" => &mut g.k_x,
        "gains.k_v" => &mut g.k_v,
        "gains.k_i" => &mut g.k_i,
        "gains.c1" => &mut g.c1,
        "gains.sigma" => &mut g.sigma,
        "gains.k_r" => &mut g.k_r,
        "gains.k_omega" => &mut g.k_omega,
        "gains.k_att_i" => &mut g.k_att_i,
        "gains.c2" => &mut g.c2,
        "vehicle.mass" => &mut ve.mass,
        "vehicle.gravity" => &mut ve.gravity,
        "vehicle.arm" => &mut ve.arm,
        "vehicle.c_tau_f" => &mut ve.c_tau_f,
        _ => {
            let (base, k) = name.strip_suffix(']')?.split_once('[')?;
            let k: usize = k.parse().ok().filter(|k| *k < 3)?;
            match base {
                "vehicle.inertia" => &mut ve.inertia[k],
                "initial.x" => &mut i.x[k],
                "initial.v" => &mut i.v[k],
                "initial.omega" => &mut i.omega[k],
                _ => return None,
            }
        }
    })
}

impl<'a> Seeds<'a> {
    /// No seeds: every number as the scene gives it.
    pub const NONE: Seeds<'static> = Seeds { names: &[] };

    /// `names` as directions 0, 1, …
    pub fn new(names: &'a [&'a str]) -> Self {
        Self { names }
    }

    /// `x`, seeded if `name` is one of the names.
    pub fn lift<B: Backend>(&self, name: &str, x: f64) -> S<B> {
        match self.names.iter().position(|n| *n == name) {
            Some(i) => S::<B>::seeded(x, i),
            None => S::<B>::lit(x),
        }
    }

    /// The vector `a`, component `k` named `prefix[k]`.
    pub fn vec<B: Backend>(&self, prefix: &str, a: [f64; 3]) -> lie::V3<B> {
        if !self.any(prefix) {
            return v::<B>(a);
        }
        let c = |k: usize| self.lift::<B>(&format!("{prefix}[{k}]"), a[k]);
        B::vec3(c(0), c(1), c(2))
    }

    /// Some name starts with `prefix`.
    pub fn any(&self, prefix: &str) -> bool {
        self.names.iter().any(|n| n.starts_with(prefix))
    }
}

/// `b` with the scene's sensors and estimator.
fn with_sensing<B: Backend>(
    scene: &Scene,
    mut b: SimulationBuilder<'static, B>,
    seeds: Seeds<'_>,
) -> Result<SimulationBuilder<'static, B>, Error> {
    let Some(spec) = &scene.sensors else {
        return Ok(b);
    };
    let suite = spec.suite().map_err(|(k, msg)| Error::at_key(k, msg))?;
    b = b.sensors(suite, scene.seed);
    if let Some(e) = &scene.estimator
        && let Some(est) = crate::estimators::build::<B>(e, &suite, scene.vehicle.gravity, seeds)
            .map_err(|(k, msg)| Error::at_key(k, msg))?
    {
        b = b.estimator(est);
    }
    Ok(b)
}
