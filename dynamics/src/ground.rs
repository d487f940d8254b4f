//! A flat ground under a vehicle: a stiff spring–damper at contact points
//! of the vehicle's own (landing-gear tips), with Coulomb friction
//! regularised near zero slip so that the loads stay continuous.
//!
//! The ground is the plane `z = height` (e3 points down: a point is in the
//! ground when its `z` is larger). At a foot `p` (body frame) the
//! penetration is `δ = e3·(x + R p) − height` and its rate
//! `δ̇ = e3·(v + R (Ω × p))`. A foot in the ground is pushed out along
//! `−e3` by `N = max(0, k δ + c δ̇)` (never pulled in: the damper lets go
//! as the foot lifts), and its slip `u` (the foot's velocity in the plane)
//! is opposed by `μ N u / √(|u|² + s²)`. Below the slip speed `s` the
//! friction is viscous, so a steady sideways force `F < μ N` on a foot
//! makes it creep at about `F s / (μ N)` instead of holding it still.
//!
//! The contact is stiff: its heave frequency `√(n k / m)` is hundreds of
//! rad/s for the paper's quadrotor, and rocking on the feet, damped by the
//! dampers and the friction, is stiffer still. The explicit Runge–Kutta
//! steppers (RK4, its projected and Munthe-Kaas forms, Dormand–Prince)
//! resolve it at a step short enough for its stiffest mode (a simulation
//! refuses a longer fixed step, naming the bound); explicit Euler is
//! unstable on it at any step a flight uses, and the variational
//! integrator's fixed-point iteration on rate-dependent loads does not
//! converge on it, so a simulation refuses both for a vehicle on the
//! ground.

use core::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use lie::{Backend, M3, Real, S, V3, ops};

use crate::{
    Capabilities, Contact, DynamicsError, LoadInput, Loads, RigidBodyState, Vehicle, Wrench,
};

/// The ground's numbers (per contact point), in f64.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Ground {
    /// The plane's position along e3, m (`z = height`; e3 points down, so
    /// a ground 0 m below the origin is `height = 0`).
    pub height: f64,
    /// Spring constant per contact point, N/m.
    pub stiffness: f64,
    /// Damping per contact point, N s/m.
    pub damping: f64,
    /// Coulomb friction coefficient μ.
    pub friction: f64,
    /// Slip speed below which friction grows linearly, m/s: the
    /// regularisation `s` that keeps the friction force continuous.
    pub slip_speed: f64,
    /// The speed into the ground, m/s, above which a foot's touchdown is a
    /// crash (a simulation ends the run there; `f64::INFINITY`: never).
    pub crash_speed: f64,
}

impl Ground {
    /// A stiff floor at `height`: k = 10⁵ N/m and c = 200 N s/m per
    /// contact, μ = 0.5, s = 5 cm/s, a crash above 1 m/s (a drop from 5 cm).
    /// On four feet under the paper's 0.755 kg quadrotor's arms the vehicle
    /// rests 19 µm deep with 0.73 of critical damping in heave (730 rad/s),
    /// a 0.5 m/s touchdown stays under 0.7 mm deep, and the stiffest mode,
    /// rocking on the feet, runs at about 2 200/s, which RK4 steps at 1 ms
    /// (see [`OnGround::stiffest_rate`]). A heavier vehicle needs a stiffer
    /// ground for the same depth (the depth scales with `v √(m / k)`); feet
    /// further out, or a smaller `s`, make the rocking stiffer.
    pub fn at(height: f64) -> Self {
        Self {
            height,
            stiffness: 1e5,
            damping: 200.0,
            friction: 0.5,
            slip_speed: 0.05,
            crash_speed: 1.0,
        }
    }

    /// Checks every number: finite; stiffness and slip speed positive;
    /// damping and friction not negative; the crash speed positive
    /// (infinite: no crash).
    pub fn check(&self) -> Result<(), DynamicsError> {
        let bad = |field, value: f64, expected| {
            Err(DynamicsError::InvalidParameter {
                field,
                value,
                expected,
            })
        };
        if !self.height.is_finite() {
            return bad("ground.height", self.height, "finite (m)");
        }
        if !(self.stiffness.is_finite() && self.stiffness > 0.0) {
            return bad("ground.stiffness", self.stiffness, "finite and > 0 (N/m)");
        }
        if !(self.damping.is_finite() && self.damping >= 0.0) {
            return bad("ground.damping", self.damping, "finite and ≥ 0 (N s/m)");
        }
        if !(self.friction.is_finite() && self.friction >= 0.0) {
            return bad("ground.friction", self.friction, "finite and ≥ 0");
        }
        if !(self.slip_speed.is_finite() && self.slip_speed > 0.0) {
            return bad("ground.slip_speed", self.slip_speed, "finite and > 0 (m/s)");
        }
        if self.crash_speed.is_nan() || self.crash_speed <= 0.0 {
            return bad(
                "ground.crash_speed",
                self.crash_speed,
                "> 0 (m/s; inf: never)",
            );
        }
        Ok(())
    }
}

/// `V` standing on, or flying over, a [`Ground`], touching it at `feet`
/// (body-frame points, m).
pub struct OnGround<B: Backend, V> {
    vehicle: V,
    ground: Ground,
    feet: Vec<V3<B>>,
    /// Whether [`Contact::hold`] holds the pushing feet, and which.
    holding: AtomicBool,
    held: AtomicU64,
}

impl<B: Backend, V: Vehicle<B>> OnGround<B, V> {
    /// `vehicle` over `ground` with contact points `feet` (at least one,
    /// each finite).
    pub fn new(vehicle: V, ground: Ground, feet: &[[f64; 3]]) -> Result<Self, DynamicsError> {
        ground.check()?;
        if feet.is_empty() {
            return Err(DynamicsError::InvalidParameter {
                field: "ground.feet",
                value: 0.0,
                expected: "at least one contact point",
            });
        }
        if let Some(c) = feet.iter().flatten().find(|c| !c.is_finite()) {
            return Err(DynamicsError::InvalidParameter {
                field: "ground.feet",
                value: *c,
                expected: "finite (m)",
            });
        }
        let l = S::<B>::lit;
        let feet = feet
            .iter()
            .map(|p| B::vec3(l(p[0]), l(p[1]), l(p[2])))
            .collect();
        Ok(Self {
            vehicle,
            ground,
            feet,
            holding: AtomicBool::new(false),
            held: AtomicU64::new(0),
        })
    }

    /// The ground.
    pub fn ground(&self) -> &Ground {
        &self.ground
    }

    /// The vehicle it carries.
    pub fn vehicle(&self) -> &V {
        &self.vehicle
    }

    /// The largest rate of the contact's linearised modes while every foot
    /// carries its share `mg/n` of the weight, 1/s: heave
    /// (`m δ̈ + n c δ̇ + n k δ = 0`), rocking about `b1` and `b2` (the
    /// springs and dampers on the feet's lever arms, `J_ii θ̈ + c Σr² θ̇ +
    /// k Σr² θ = 0`, with the friction's viscous part below the slip speed,
    /// `μ (mg/n)/s` per foot, acting on the feet's depth `Σp₃²`), yaw
    /// (that friction on the feet's horizontal reach) and sliding
    /// (`μ g / s`). For each mode the larger root magnitude of
    /// `λ² + aλ + b`.
    pub fn stiffest_rate(&self) -> f64 {
        let g = &self.ground;
        let m = self.vehicle.mass().to_f64_lossless();
        let grav = self.vehicle.gravity().to_f64_lossless();
        let j = ops::elems::<B>(self.vehicle.inertia()).map(|r| r.map(|c| c.to_f64_lossless()));
        let feet: Vec<[f64; 3]> = self
            .feet
            .iter()
            .map(|p| B::vec3_to_array(*p).map(|c| c.to_f64_lossless()))
            .collect();
        let n = feet.len() as f64;
        // The friction's viscous coefficient per foot below the slip speed.
        let viscous = g.friction * m * grav / (n * g.slip_speed);
        let root = |a: f64, b: f64| {
            if a * a > 4.0 * b {
                0.5 * (a + (a * a - 4.0 * b).sqrt())
            } else {
                b.sqrt()
            }
        };
        let sum = |f: &dyn Fn(&[f64; 3]) -> f64| feet.iter().map(f).sum::<f64>();
        let depth = sum(&|p| p[2] * p[2]);
        let heave = root(n * g.damping / m, n * g.stiffness / m);
        let rock = |lever: f64, jii: f64| {
            root(
                (g.damping * lever + viscous * depth) / jii,
                g.stiffness * lever / jii,
            )
        };
        let roll = rock(sum(&|p| p[1] * p[1]), j[0][0]);
        let pitch = rock(sum(&|p| p[0] * p[0]), j[1][1]);
        let yaw = viscous * sum(&|p| p[0] * p[0] + p[1] * p[1]) / j[2][2];
        let slide = n * viscous / m;
        [heave, roll, pitch, yaw, slide]
            .into_iter()
            .fold(0.0, f64::max)
    }

    /// The deepest penetration of a foot in `state`, m (negative: every
    /// foot above the ground by that much).
    pub fn penetration(&self, state: &RigidBodyState<B>) -> f64 {
        self.feet
            .iter()
            .map(|p| self.depth(state, *p).to_f64_lossless())
            .fold(f64::NEG_INFINITY, f64::max)
    }

    fn depth(&self, state: &RigidBodyState<B>, p: V3<B>) -> S<B> {
        let z = B::vec3_to_array(state.x + state.r * p)[2];
        z - S::<B>::lit(self.ground.height)
    }

    /// The push `k δ + c δ̇` of the foot at `p` and its velocity, when it
    /// is in the ground and pushing.
    fn push(&self, state: &RigidBodyState<B>, p: V3<B>) -> Option<(S<B>, [S<B>; 3])> {
        if self.depth(state, p).to_f64_lossless() <= 0.0 {
            return None;
        }
        let (push, vel) = self.push_any(state, p);
        (push.to_f64_lossless() > 0.0).then_some((push, vel))
    }

    /// `k δ + c δ̇` of the foot at `p` and its velocity, whatever their
    /// signs (a held foot near its change).
    fn push_any(&self, state: &RigidBodyState<B>, p: V3<B>) -> (S<B>, [S<B>; 3]) {
        let g = &self.ground;
        let depth = self.depth(state, p);
        let vel = B::vec3_to_array(state.v + state.r * B::cross(state.omega, p));
        let push = S::<B>::lit(g.stiffness) * depth + S::<B>::lit(g.damping) * vel[2];
        (push, vel)
    }

    /// The contact force (inertial) and moment (body) in `state`.
    pub fn contact(&self, state: &RigidBodyState<B>) -> Loads<B> {
        let g = &self.ground;
        let l = S::<B>::lit;
        let mut force = ops::zero::<B>();
        let mut moment = ops::zero::<B>();
        let held = self
            .holding
            .load(Ordering::Relaxed)
            .then(|| self.held.load(Ordering::Relaxed));
        for (i, &p) in self.feet.iter().enumerate() {
            let found = match held {
                None => self.push(state, p),
                Some(m) if i < 64 && m & (1 << i) != 0 => Some(self.push_any(state, p)),
                Some(_) => None,
            };
            let Some((push, [vx, vy, _])) = found else {
                continue;
            };
            let slip = (vx * vx + vy * vy + l(g.slip_speed * g.slip_speed)).sqrt();
            let k = l(g.friction) * push / slip;
            let f = B::vec3(-k * vx, -k * vy, -push);
            force = force + f;
            moment = moment + B::cross(p, B::mat3_transpose(state.r) * f);
        }
        Loads { force, moment }
    }
}

impl<B: Backend, V: Vehicle<B>> Vehicle<B> for OnGround<B, V> {
    fn name(&self) -> &str {
        self.vehicle.name()
    }
    fn mass(&self) -> S<B> {
        self.vehicle.mass()
    }
    fn inertia(&self) -> M3<B> {
        self.vehicle.inertia()
    }
    fn gravity(&self) -> S<B> {
        self.vehicle.gravity()
    }
    fn actuator_count(&self) -> usize {
        self.vehicle.actuator_count()
    }
    fn wrench_from_actuators(&self, u: &[S<B>]) -> Result<Wrench<B>, DynamicsError> {
        self.vehicle.wrench_from_actuators(u)
    }
    fn actuators_from_wrench(&self, w: &Wrench<B>, out: &mut [S<B>]) -> Result<(), DynamicsError> {
        self.vehicle.actuators_from_wrench(w, out)
    }
    fn loads(
        &self,
        t: S<B>,
        state: &RigidBodyState<B>,
        input: LoadInput<'_, B>,
        rates: &mut [S<B>],
    ) -> Option<Loads<B>> {
        let mut out = self.vehicle.loads(t, state, input, rates)?;
        let c = self.contact(state);
        out.force = out.force + c.force;
        out.moment = out.moment + c.moment;
        Some(out)
    }
    fn capabilities(&self) -> Capabilities<'_, B> {
        let mut c = self.vehicle.capabilities().rate_dependent(true);
        c.contact = Some(self);
        c
    }
}

impl<B: Backend, V: Vehicle<B>> Contact<B> for OnGround<B, V> {
    fn pushing(&self, state: &RigidBodyState<B>) -> u64 {
        let mut mask = 0u64;
        for (i, &p) in self.feet.iter().enumerate().take(64) {
            if self.push(state, p).is_some() {
                mask |= 1 << i;
            }
        }
        mask
    }
    fn hold(&self, mask: Option<u64>) {
        self.held.store(mask.unwrap_or(0), Ordering::Relaxed);
        self.holding.store(mask.is_some(), Ordering::Relaxed);
    }
    fn crash_speed(&self) -> f64 {
        self.ground.crash_speed
    }
    fn stiffest_rate(&self) -> f64 {
        self.stiffest_rate()
    }
    fn normal_speed(&self, state: &RigidBodyState<B>, i: usize) -> f64 {
        self.feet.get(i).map_or(0.0, |&p| {
            let vel = state.v + state.r * B::cross(state.omega, p);
            B::vec3_to_array(vel)[2].to_f64_lossless()
        })
    }
}
