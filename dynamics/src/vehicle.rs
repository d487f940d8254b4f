//! The [`Vehicle`] trait, what its one load path is given, and its optional
//! parts.

use lie::num_traits::Zero;
use lie::{Backend, M3, Real, S, V3, ops};

use crate::{Disturbance, DynamicsError, Loads, RigidBodyState, Wrench};

/// What the actuators are asked for at one evaluation.
#[derive(Copy, Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum Command<'a, B: Backend> {
    /// A total thrust along `−b3` and a body moment (what the paper's laws
    /// give).
    Wrench(Wrench<B>),
    /// Rotor speeds, rad/s, one per rotor (a flight mode that commands
    /// them, as RotorPy's controller does).
    RotorSpeeds(&'a [S<B>]),
}

/// What [`Vehicle::loads`] reads besides the time and the body's state:
/// the command, the vehicle's internal states and the air.
#[derive(Copy, Clone, Debug)]
#[non_exhaustive]
pub struct LoadInput<'a, B: Backend> {
    /// What the actuators are asked for.
    pub command: Command<'a, B>,
    /// The vehicle's internal states ([`Actuators::state_count`] entries),
    /// or empty when the caller integrates none (an open loop): the
    /// actuators then respond at once.
    pub states: &'a [S<B>],
    /// The inertial velocity of the air at the vehicle, m/s (zero in still
    /// air).
    pub wind: V3<B>,
}

impl<'a, B: Backend> LoadInput<'a, B> {
    /// `command` in internal states `states` and wind `wind`.
    pub fn new(command: Command<'a, B>, states: &'a [S<B>], wind: V3<B>) -> Self {
        Self {
            command,
            states,
            wind,
        }
    }
    /// The commanded wrench, `None` for rotor speeds: what a vehicle that
    /// takes wrenches only reads (`let w = input.wrench_command()?;`).
    #[inline]
    pub fn wrench_command(&self) -> Option<Wrench<B>> {
        match self.command {
            Command::Wrench(w) => Some(w),
            _ => None,
        }
    }
    /// A commanded wrench in still air with no internal states.
    pub fn wrench(w: Wrench<B>) -> Self {
        Self::new(Command::Wrench(w), &[], ops::zero::<B>())
    }
}

/// A vehicle's optional parts, which a simulation reads once when a run
/// is built. [`Capabilities::RIGID`] (the default) is a free body whose
/// actuators deliver what they are asked, with nothing else.
#[derive(Copy, Clone)]
#[non_exhaustive]
pub struct Capabilities<'a, B: Backend> {
    /// Whether the body translates. `false` for a body on a spherical joint
    /// (or an attitude-only study): integrators then leave `x` and `v`
    /// untouched and skip their arithmetic.
    pub translates: bool,
    /// Whether the loads read the velocities `v` or `Ω` (drag, say).
    /// Implicit integrators (LGVI) then iterate their end-point loads;
    /// `false` lets them evaluate once.
    pub rate_dependent_loads: bool,
    /// Actuators with limits or dynamics of their own.
    pub actuators: Option<&'a dyn Actuators<B>>,
    /// An attitude-dependent moment (gravity about a pivot) that a flight
    /// loop may compensate in its command.
    pub configuration_moment: Option<&'a dyn ConfigurationMoment<B>>,
    /// A stiff contact in the loads (the ground): a simulation refuses
    /// the steppers that cannot step it and locates where it changes.
    pub contact: Option<&'a dyn Contact<B>>,
}

impl<B: Backend> Capabilities<'_, B> {
    /// A translating body with ideal actuators and no configuration moment.
    pub const RIGID: Self = Self {
        translates: true,
        rate_dependent_loads: false,
        actuators: None,
        configuration_moment: None,
        contact: None,
    };
}

impl<'a, B: Backend> Capabilities<'a, B> {
    /// `self` with `translates` set.
    pub fn translating(mut self, translates: bool) -> Self {
        self.translates = translates;
        self
    }
    /// `self` with `rate_dependent_loads` set.
    pub fn rate_dependent(mut self, yes: bool) -> Self {
        self.rate_dependent_loads = yes;
        self
    }
    /// `self` with the actuator model `a`.
    pub fn with_actuators(mut self, a: &'a dyn Actuators<B>) -> Self {
        self.actuators = Some(a);
        self
    }
    /// `self` with the configuration moment `c`.
    pub fn with_configuration_moment(mut self, c: &'a dyn ConfigurationMoment<B>) -> Self {
        self.configuration_moment = Some(c);
        self
    }
}

impl<B: Backend> Default for Capabilities<'_, B> {
    fn default() -> Self {
        Self::RIGID
    }
}

/// Actuators that do not deliver a command as it is given: limits, a lag,
/// internal states (rotor speeds, motor currents) that a simulation
/// integrates with the body. Their rates are written by [`Vehicle::loads`].
pub trait Actuators<B: Backend>: Send + Sync {
    /// The wrench delivered when `command` is asked in internal states
    /// `states` (empty when the caller integrates none: the actuators then
    /// respond at once, within their limits), without aerodynamics.
    fn delivered(&self, command: &Wrench<B>, states: &[S<B>]) -> Wrench<B>;
    /// How many internal states to integrate with the body (0 for limits
    /// alone).
    fn state_count(&self) -> usize {
        0
    }
    /// The internal states at the start of a run, given its first command
    /// (e.g. rotors already spinning at it); `states` has
    /// [`Actuators::state_count`] entries, zero on entry.
    fn initial_states(&self, _first: Command<'_, B>, _states: &mut [S<B>]) {}
}

/// Contact points whose loads switch on and off (feet on the ground): a
/// simulation splits a step where the set of points pushing changes, so
/// that no step integrates across the switch.
pub trait Contact<B: Backend>: Send + Sync {
    /// The points pushing in `state`, bit `i` for point `i` (at most 64).
    fn pushing(&self, state: &RigidBodyState<B>) -> u64;
    /// Point `i`'s velocity into the contact in `state`, m/s (positive
    /// towards it).
    fn normal_speed(&self, state: &RigidBodyState<B>, i: usize) -> f64;
    /// Holds the points of `mask` pushing and the others not, whatever the
    /// state, until called with `None`: a simulation integrates up to a
    /// located change on the side it came from. [`Contact::pushing`]
    /// still reads the state.
    fn hold(&self, mask: Option<u64>);
    /// The speed into the contact above which a touchdown is a crash,
    /// m/s (a simulation ends the run there); never, by default.
    fn crash_speed(&self) -> f64 {
        f64::INFINITY
    }
    /// The largest rate, 1/s, at which the contact's fastest mode decays
    /// or oscillates while it carries the vehicle: a fixed-step explicit
    /// stepper is stable on it only below a limit of `rate · dt` (2.78 for
    /// RK4), so a simulation refuses a longer step. Zero by default.
    fn stiffest_rate(&self) -> f64 {
        0.0
    }
}

/// An attitude-dependent moment, body frame, such as gravity about a pivot.
pub trait ConfigurationMoment<B: Backend>: Send + Sync {
    /// The moment in `state`, N m.
    fn moment(&self, state: &RigidBodyState<B>) -> V3<B>;
}

/// A vehicle: a rigid body with actuators. Object safe; simulations hold a
/// `Box<dyn Vehicle<B>>` so that a new vehicle needs no change anywhere else.
///
/// Seven methods are required (what the body is and the actuator map both
/// ways). The loop calls one more, [`Vehicle::loads`], whose default is the
/// rigid body under the delivered command; [`Vehicle::capabilities`] names
/// the optional parts.
///
/// # Example
/// A body with one thruster along `−b3` and no moment (a "sled"): only the
/// seven required methods.
///
/// ```
/// use dynamics::{DynamicsError, RigidBodyState, Vehicle, Wrench, loads};
/// use lie::{Backend, GlamF64, M3, S, ops};
/// type B = GlamF64;
///
/// struct Sled;
/// impl Vehicle<B> for Sled {
///     fn name(&self) -> &str { "sled" }
///     fn mass(&self) -> S<B> { 1.0 }
///     fn inertia(&self) -> M3<B> { ops::identity::<B>() }
///     fn gravity(&self) -> S<B> { 9.81 }
///     fn actuator_count(&self) -> usize { 1 }
///     fn wrench_from_actuators(&self, u: &[S<B>]) -> Result<Wrench<B>, DynamicsError> {
///         match u {
///             [f] => Ok(Wrench { thrust: *f, moment: B::vec3(0.0, 0.0, 0.0) }),
///             _ => Err(DynamicsError::ActuatorCount { expected: 1, got: u.len() }),
///         }
///     }
///     fn actuators_from_wrench(&self, w: &Wrench<B>, out: &mut [S<B>]) -> Result<(), DynamicsError> {
///         match out {
///             [f] => { *f = w.thrust; Ok(()) }
///             _ => Err(DynamicsError::ActuatorCount { expected: 1, got: out.len() }),
///         }
///     }
/// }
/// // Twice the weight: 1 g upwards (−e3) net.
/// let w = Sled.wrench_from_actuators(&[2.0 * 9.81])?;
/// let l = loads(&Sled, 0.0, &RigidBodyState::at_rest(), &w);
/// assert_eq!(B::vec3_to_array(l.force), [0.0, 0.0, -9.81]);
/// assert!(Sled.wrench_from_actuators(&[1.0, 2.0]).is_err());
/// # Ok::<(), DynamicsError>(())
/// ```
pub trait Vehicle<B: Backend>: Send + Sync {
    /// Short name for reports, e.g. `"quadrotor"`.
    fn name(&self) -> &str;
    /// Mass, kg.
    fn mass(&self) -> S<B>;
    /// Inertia about the point the body rotates about (the centre of mass
    /// for a free body, the pivot for a pinned one), body frame, kg m².
    fn inertia(&self) -> M3<B>;
    /// Gravitational acceleration along `+e3`, m/s².
    fn gravity(&self) -> S<B>;
    /// Number of actuators (rotors, …).
    fn actuator_count(&self) -> usize;
    /// Wrench produced by the actuator values `u` (e.g. rotor thrusts).
    fn wrench_from_actuators(&self, u: &[S<B>]) -> Result<Wrench<B>, DynamicsError>;
    /// Actuator values that produce `w` (the allocation inverse), written
    /// into `out` (no allocation).
    fn actuators_from_wrench(&self, w: &Wrench<B>, out: &mut [S<B>]) -> Result<(), DynamicsError>;

    /// The force and moment on the body at time `t` in `state` (the
    /// right-hand sides of (eqn:EL2) and (eqn:EL4) without the gyroscopic
    /// term), with the internal states' rates written into `rates`
    /// ([`Actuators::state_count`] entries, or none when `input.states` is
    /// empty). `None` when the vehicle takes no such command (rotor speeds
    /// to a vehicle without rotors).
    ///
    /// The default is [`body_loads`] of the wrench the
    /// [`Capabilities::actuators`] deliver, and refuses rotor speeds.
    /// Override it for a disturbance, aerodynamics or actuator dynamics.
    #[inline]
    fn loads(
        &self,
        _t: S<B>,
        state: &RigidBodyState<B>,
        input: LoadInput<'_, B>,
        _rates: &mut [S<B>],
    ) -> Option<Loads<B>> {
        let w = input.wrench_command()?;
        let delivered = match self.capabilities().actuators {
            Some(a) => a.delivered(&w, input.states),
            None => w,
        };
        Some(body_loads(self, state, delivered, None))
    }

    /// The optional parts: whether the body translates, whether its loads
    /// read the rates, its actuator model, its configuration moment.
    fn capabilities(&self) -> Capabilities<'_, B> {
        Capabilities::RIGID
    }
}

/// The loads of gravity, the `delivered` thrust along `−b3` and moment, a
/// `disturbance` (Δ_x, Δ_R) and the vehicle's configuration moment: the
/// right-hand sides of (eqn:EL2) and (eqn:EL4) without the gyroscopic term.
/// A body that does not translate gets no force.
#[inline]
pub fn body_loads<B: Backend, V: Vehicle<B> + ?Sized>(
    vehicle: &V,
    state: &RigidBodyState<B>,
    delivered: Wrench<B>,
    disturbance: Option<Disturbance<B>>,
) -> Loads<B> {
    let caps = vehicle.capabilities();
    let w = delivered;
    let [_, _, b3] = B::mat3_cols(state.r);
    let zero = S::<B>::zero();
    let mut force = if caps.translates {
        B::vec3(zero, zero, vehicle.mass() * vehicle.gravity()) - b3 * w.thrust
    } else {
        ops::zero::<B>()
    };
    let mut moment = w.moment;
    if let Some(d) = disturbance {
        if caps.translates {
            force = force + d.force;
        }
        moment = moment + d.moment;
    }
    if let Some(c) = caps.configuration_moment {
        moment = moment + c.moment(state);
    }
    Loads { force, moment }
}

/// The loads on `vehicle` in `state` at time `t` under the commanded
/// `wrench`, in still air with no internal states (the actuators respond
/// at once): [`Vehicle::loads`] of [`LoadInput::wrench`]. NaN loads, which
/// stop an integrator with a non-finite state, if the vehicle refuses it.
#[inline]
pub fn loads<B: Backend, V: Vehicle<B> + ?Sized>(
    vehicle: &V,
    t: S<B>,
    state: &RigidBodyState<B>,
    wrench: &Wrench<B>,
) -> Loads<B> {
    vehicle
        .loads(t, state, LoadInput::wrench(*wrench), &mut [])
        .unwrap_or_else(|| {
            let nan = S::<B>::nan();
            Loads {
                force: B::vec3(nan, nan, nan),
                moment: B::vec3(nan, nan, nan),
            }
        })
}

/// A boxed vehicle is a vehicle (so that a wrapper such as
/// [`OnGround`](crate::OnGround) takes one chosen at run time).
impl<B: Backend> Vehicle<B> for Box<dyn Vehicle<B> + '_> {
    fn name(&self) -> &str {
        (**self).name()
    }
    fn mass(&self) -> S<B> {
        (**self).mass()
    }
    fn inertia(&self) -> M3<B> {
        (**self).inertia()
    }
    fn gravity(&self) -> S<B> {
        (**self).gravity()
    }
    fn actuator_count(&self) -> usize {
        (**self).actuator_count()
    }
    fn wrench_from_actuators(&self, u: &[S<B>]) -> Result<Wrench<B>, DynamicsError> {
        (**self).wrench_from_actuators(u)
    }
    fn actuators_from_wrench(&self, w: &Wrench<B>, out: &mut [S<B>]) -> Result<(), DynamicsError> {
        (**self).actuators_from_wrench(w, out)
    }
    #[inline]
    fn loads(
        &self,
        t: S<B>,
        state: &RigidBodyState<B>,
        input: LoadInput<'_, B>,
        rates: &mut [S<B>],
    ) -> Option<Loads<B>> {
        (**self).loads(t, state, input, rates)
    }
    fn capabilities(&self) -> Capabilities<'_, B> {
        (**self).capabilities()
    }
}
