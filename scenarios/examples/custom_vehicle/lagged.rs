//! A quadrotor whose rotors do not deliver their command at once: each
//! rotor's thrust follows its command with a first-order lag,
//! `Ṫ_k = (sat(u_k) − T_k)/τ`, where `u = A⁻¹ [f; M]` is the allocation
//! inverse of the commanded wrench and `sat` clamps to the rotor's range.
//! The body feels the wrench of the thrusts `T`, not of the command.
//!
//! Written as a crate outside this workspace would write it: only public
//! items of `dynamics` and `lie`. Shared by the `custom_vehicle` example
//! and the tests that check it against the built-in quadrotor.

use dynamics::{Disturbance, DynamicsError, Quadrotor, RigidBodyState, Vehicle, Wrench};
use lie::{Backend, M3, Real, S};

/// The paper's airframe with rotor lag `tau` (s; 0 = rotors follow the
/// command at once, and the vehicle declares no states) and optional
/// per-rotor thrust limits `(min, max)` in N.
pub struct LaggedQuadrotor<B: Backend> {
    quad: Quadrotor<B>,
    tau: S<B>,
    limits: Option<(S<B>, S<B>)>,
}

impl<B: Backend> LaggedQuadrotor<B> {
    /// `quad` (mass, inertia, allocation, disturbance) with rotor lag `tau`.
    pub fn new(quad: Quadrotor<B>, tau: S<B>) -> Result<Self, DynamicsError> {
        if !tau.is_finite() || tau < S::<B>::lit(0.0) {
            return Err(DynamicsError::InvalidParameter {
                field: "tau",
                value: tau.to_f64_lossless(),
                expected: "a finite time constant ≥ 0 s",
            });
        }
        Ok(Self {
            quad,
            tau,
            limits: None,
        })
    }

    /// Clamp every rotor's thrust to `[min, max]` N.
    pub fn with_limits(mut self, min: S<B>, max: S<B>) -> Result<Self, DynamicsError> {
        if !(min.is_finite() && max.is_finite() && min < max) {
            return Err(DynamicsError::InvalidParameter {
                field: "limits",
                value: (max - min).to_f64_lossless(),
                expected: "finite min < max (this is max − min)",
            });
        }
        self.limits = Some((min, max));
        Ok(self)
    }

    /// The rotor thrusts the command asks for, clamped to the limits.
    fn demanded(&self, w: &Wrench<B>) -> [S<B>; 4] {
        let mut u = [S::<B>::lit(0.0); 4];
        // Four rotors, four entries: the allocation cannot fail here.
        let _ = self.quad.actuators_from_wrench(w, &mut u);
        if let Some((lo, hi)) = self.limits {
            u = u.map(|x| x.max(lo).min(hi));
        }
        u
    }

    fn lagged(&self) -> bool {
        self.tau > S::<B>::lit(0.0)
    }
}

impl<B: Backend> Vehicle<B> for LaggedQuadrotor<B> {
    fn name(&self) -> &str {
        "lagged-quadrotor"
    }
    fn mass(&self) -> S<B> {
        self.quad.mass()
    }
    fn inertia(&self) -> M3<B> {
        self.quad.inertia()
    }
    fn gravity(&self) -> S<B> {
        self.quad.gravity()
    }
    fn actuator_count(&self) -> usize {
        4
    }
    fn wrench_from_actuators(&self, u: &[S<B>]) -> Result<Wrench<B>, DynamicsError> {
        self.quad.wrench_from_actuators(u)
    }
    fn actuators_from_wrench(&self, w: &Wrench<B>, out: &mut [S<B>]) -> Result<(), DynamicsError> {
        self.quad.actuators_from_wrench(w, out)
    }
    fn disturbance(&self, t: S<B>, state: &RigidBodyState<B>) -> Option<Disturbance<B>> {
        self.quad.disturbance(t, state)
    }
    fn state_count(&self) -> usize {
        if self.lagged() { 4 } else { 0 }
    }
    fn initial_states(&self, commanded: &Wrench<B>, states: &mut [S<B>]) {
        // Rotors already spinning at what the first command asks.
        states.copy_from_slice(&self.demanded(commanded));
    }
    fn state_rates(
        &self,
        _t: S<B>,
        _body: &RigidBodyState<B>,
        commanded: &Wrench<B>,
        states: &[S<B>],
        rates: &mut [S<B>],
    ) {
        let u = self.demanded(commanded);
        for k in 0..4 {
            rates[k] = (u[k] - states[k]) / self.tau;
        }
    }
    fn applied_wrench(&self, commanded: &Wrench<B>, states: &[S<B>]) -> Wrench<B> {
        let thrusts = if self.lagged() {
            [states[0], states[1], states[2], states[3]]
        } else {
            self.demanded(commanded)
        };
        self.quad
            .wrench_from_actuators(&thrusts)
            .unwrap_or_else(|_| Wrench::zero())
    }
}
