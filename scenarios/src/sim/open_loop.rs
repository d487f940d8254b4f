//! A vehicle under a held wrench as an integrator's [`System`]: where the
//! vehicle models of `dynamics` meet the steppers of `integrators` (neither
//! of which knows the other).

use dynamics::{Capabilities, Vehicle, Wrench, loads};
use integrators::{Load, State, System};
use lie::{Backend, M3, S};

/// A vehicle under a fixed commanded wrench (zero for an unactuated body):
/// the open-loop [`System`] with no extra states, for running a vehicle
/// model on a stepper without a controller or a [`Simulation`](crate::Simulation).
///
/// # Example
/// A torque-free body (J = diag(1, 2, 3)) for 100 s by the LGVI and by
/// RK4: the variational method keeps the kinetic energy to rounding, RK4
/// to its truncation error.
///
/// ```
/// use dynamics::{FreeRigidBody, Vehicle, Wrench};
/// use integrators::{Lgvi, Rk4, State, integrate_fixed};
/// use lie::{Backend, NalgebraF64, RigidState, ops};
/// use scenarios::OpenLoop;
/// type B = NalgebraF64;
///
/// let body = FreeRigidBody::<B>::new(ops::diag::<B>(1.0, 2.0, 3.0))?;
/// let energy = |y: &State<B, 0>| 0.5 * B::dot(y.body.omega, body.inertia() * y.body.omega);
/// let mut start = State::<B, 0>::new(RigidState::at_rest());
/// start.body.omega = B::vec3(1.0, 0.5, -0.3);
/// let (mut lgvi, mut rk4) = (start, start);
/// let mut sys = OpenLoop::new(&body, Wrench::zero());
/// integrate_fixed(&mut Lgvi::default(), &mut sys, 0.0, 0.01, 10_000, &mut lgvi)?;
/// integrate_fixed(&mut Rk4::default(), &mut sys, 0.0, 0.01, 10_000, &mut rk4)?;
/// let drift = |y: &State<B, 0>| (energy(y) / energy(&start) - 1.0).abs();
/// assert!(drift(&lgvi) < 1e-12 && drift(&rk4) > 1e-12 && drift(&rk4) < 1e-6);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct OpenLoop<'a, B: Backend> {
    vehicle: &'a dyn Vehicle<B>,
    caps: Capabilities<'a, B>,
    /// The commanded wrench, held.
    pub wrench: Wrench<B>,
    inertia: M3<B>,
    inertia_inv: M3<B>,
}

impl<'a, B: Backend> OpenLoop<'a, B> {
    /// `vehicle` with wrench `wrench`. The built-in vehicles validate
    /// their inertia when built ([`dynamics::check_inertia`]); a singular
    /// one of a user's vehicle gives a NaN inverse, so the first step fails
    /// with a non-finite state rather than integrating a wrong body.
    pub fn new(vehicle: &'a dyn Vehicle<B>, wrench: Wrench<B>) -> Self {
        let inertia = vehicle.inertia();
        Self {
            vehicle,
            caps: vehicle.capabilities(),
            wrench,
            inertia,
            inertia_inv: integrators::inverse_or_nan::<B>(inertia),
        }
    }
}

impl<B: Backend> System<B, 0> for OpenLoop<'_, B> {
    fn mass(&self) -> S<B> {
        self.vehicle.mass()
    }
    fn inertia(&self) -> M3<B> {
        self.inertia
    }
    fn inertia_inv(&self) -> M3<B> {
        self.inertia_inv
    }
    fn translates(&self) -> bool {
        self.caps.translates
    }
    fn load_depends_on_rates(&self) -> bool {
        self.caps.rate_dependent_loads
    }
    fn load(&mut self, t: S<B>, y: &State<B, 0>) -> Load<B, 0> {
        let l = loads(self.vehicle, t, &y.body, &self.wrench);
        Load {
            force: l.force,
            moment: l.moment,
            extra_rate: [],
        }
    }
}
