//! A quadrotor whose rotors do not deliver their command at once: each
//! rotor's thrust follows its command with a first-order lag,
//! `Ṫ_k = (sat(u_k) − T_k)/τ`, where `u = A⁻¹ [f; M]` is the allocation
//! inverse of the commanded wrench and `sat` clamps to the rotor's range.
//! The body feels the wrench of the thrusts `T`, not of the command.
//!
//! Written as an outside crate would: public items of `dynamics` and `lie`
//! only. Shared by the example and the tests comparing it with the quadrotor.

use dynamics::{Actuators, Capabilities, Command, LoadInput, Loads, RigidBodyState, body_loads};
use dynamics::{DynamicsError, Quadrotor, Vehicle, Wrench};
use lie::{Backend, M3, Real, S};

/// The paper's airframe with rotor lag `tau` (s; 0: none, and no states)
/// and optional per-rotor thrust limits `(min, max)` in N.
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
    fn loads(
        &self,
        _t: S<B>,
        state: &RigidBodyState<B>,
        input: LoadInput<'_, B>,
        rates: &mut [S<B>],
    ) -> Option<Loads<B>> {
        let w = input.wrench_command()?;
        let (u, states) = (self.demanded(&w), input.states);
        for k in 0..rates.len().min(states.len()) {
            rates[k] = (u[k] - states[k]) / self.tau;
        }
        let d = self.delivered(&w, states);
        Some(body_loads(self, state, d, self.quad.fixed_disturbance()))
    }
    fn capabilities(&self) -> Capabilities<'_, B> {
        Capabilities::RIGID.with_actuators(self)
    }
}

impl<B: Backend> Actuators<B> for LaggedQuadrotor<B> {
    fn delivered(&self, commanded: &Wrench<B>, states: &[S<B>]) -> Wrench<B> {
        let t = <[S<B>; 4]>::try_from(states).unwrap_or_else(|_| self.demanded(commanded));
        self.quad
            .wrench_from_actuators(&t)
            .unwrap_or_else(|_| Wrench::zero())
    }
    fn state_count(&self) -> usize {
        if self.tau > S::<B>::lit(0.0) { 4 } else { 0 }
    }
    fn initial_states(&self, first: Command<'_, B>, states: &mut [S<B>]) {
        // Rotors already spinning at what the first command asks.
        if let Command::Wrench(w) = first {
            states.copy_from_slice(&self.demanded(&w));
        }
    }
}
