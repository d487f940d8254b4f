//! Test problems with known invariants.

use lie::{Backend, M3, Real, RigidState, Rotation, S, So3Mat, V3, ops, orthogonality_error};

use crate::system::inverse_or_nan;
use crate::{Integrator, StepError};

use crate::{Load, State, System};

/// A rigid body turning about a fixed point under gravity, translation
/// suppressed: `J Ω̇ + Ω × JΩ = m g ρ × Rᵀe3`, with `ρ` the centre of mass
/// from the pivot in body coordinates (e3 down). Invariants: the energy
/// `½ΩᵀJΩ − m g e3ᵀRρ` and the vertical momentum `e3ᵀRJΩ`.
///
/// With the centre of mass at the pivot (`ρ = 0`, [`Top::free`]) it is the
/// torque-free body of Euler's equations: then the whole spatial angular
/// momentum `R J Ω` is conserved too, and for a diagonal `J` the solution
/// is known in closed form (Jacobi elliptic functions), so it measures a
/// stepper's order and drift. With `ρ ≠ 0` ([`Top::heavy`]) it is the
/// heavy top (a 3D pendulum), whose moment depends on the attitude.
#[derive(Copy, Clone, Debug)]
pub struct Top<B: Backend> {
    inertia: M3<B>,
    inertia_inv: M3<B>,
    /// `m g ρ`, N m.
    pub mg_rho: V3<B>,
}

impl<B: Backend> Top<B> {
    /// The torque-free body of inertia `inertia` (a singular one has a NaN
    /// inverse, so the first step fails with a non-finite state).
    pub fn free(inertia: M3<B>) -> Self {
        Self::heavy(inertia, ops::zero::<B>())
    }

    /// The torque-free body with `J = diag(1, 2, 3)`, the usual test body.
    pub fn free_diag123() -> Self {
        let l = S::<B>::lit;
        Self::free(ops::diag::<B>(l(1.0), l(2.0), l(3.0)))
    }

    /// The heavy top of inertia `inertia` about the pivot, with `m g ρ`.
    pub fn heavy(inertia: M3<B>, mg_rho: V3<B>) -> Self {
        Self {
            inertia,
            inertia_inv: inverse_or_nan::<B>(inertia),
            mg_rho,
        }
    }

    /// The heavy top of the integrator tests: `J = diag(1, 2, 3)`,
    /// `m g ρ = (0, 0.5, 1)`.
    pub fn heavy_standard() -> Self {
        let l = S::<B>::lit;
        Self::heavy(
            ops::diag::<B>(l(1.0), l(2.0), l(3.0)),
            B::vec3(l(0.0), l(0.5), l(1.0)),
        )
    }

    fn down_body(r: M3<B>) -> V3<B> {
        let z = S::<B>::lit(0.0);
        B::mat3_tr_mul_vec(r, B::vec3(z, z, S::<B>::lit(1.0)))
    }

    /// Total energy `½ΩᵀJΩ − m g e3ᵀRρ`.
    pub fn energy(&self, body: &RigidState<B, M3<B>>) -> S<B> {
        let w = body.omega;
        S::<B>::lit(0.5) * B::dot(w, self.inertia * w)
            - B::dot(Self::down_body(body.r), self.mg_rho)
    }

    /// Spatial angular momentum `π = R J Ω` (conserved when `ρ = 0`).
    pub fn momentum(&self, body: &RigidState<B, M3<B>>) -> V3<B> {
        body.r * (self.inertia * body.omega)
    }

    /// Vertical angular momentum `e3ᵀ R J Ω` (conserved for every `ρ`).
    pub fn vertical_momentum(&self, body: &RigidState<B, M3<B>>) -> S<B> {
        B::dot(Self::down_body(body.r), self.inertia * body.omega)
    }
}

impl<B: Backend> System<B, 0> for Top<B> {
    fn mass(&self) -> S<B> {
        S::<B>::lit(1.0)
    }
    fn inertia(&self) -> M3<B> {
        self.inertia
    }
    fn inertia_inv(&self) -> M3<B> {
        self.inertia_inv
    }
    fn translates(&self) -> bool {
        false
    }
    fn load_depends_on_rates(&self) -> bool {
        false
    }
    fn load(&mut self, _t: S<B>, y: &State<B, 0>) -> Load<B, 0> {
        Load {
            force: ops::zero::<B>(),
            moment: B::cross(self.mg_rho, Self::down_body(y.body.r)),
            extra_rate: [],
        }
    }
}

/// Invariant errors of a long free-body run, sampled at checkpoints.
#[derive(Clone, Debug, Default)]
pub struct InvariantTrace {
    /// Step index (1-based) of each checkpoint.
    pub step: Vec<usize>,
    /// `|E − E₀|/E₀`.
    pub energy: Vec<f64>,
    /// `|π − π₀|/|π₀|`, spatial angular momentum.
    pub momentum: Vec<f64>,
    /// `‖RᵀR − I‖_F`.
    pub orthogonality: Vec<f64>,
}

/// The free-body start used by the conservation tests and `cargo xtask
/// conservation`: `J = diag(1, 2, 3)`, `R₀ = exp((0.3, −0.5, 0.2)^)`,
/// `Ω₀ = (0.4, −0.8, −1.1)` (major-axis tumbling, all components non-zero).
pub fn free_body_start<B: Backend>() -> RigidState<B, M3<B>> {
    let l = S::<B>::lit;
    let mut body = RigidState::<B, M3<B>>::at_rest();
    body.r = So3Mat::<B>::exp(B::vec3(l(0.3), l(-0.5), l(0.2))).matrix();
    body.omega = B::vec3(l(0.4), l(-0.8), l(-1.1));
    body
}

/// Runs `steps` steps of `h` on the free body from [`free_body_start`] and
/// samples the invariants at `checkpoints` evenly spaced steps. Time of step
/// `k` is `k h` (multiplied, not accumulated).
pub fn free_body_invariants<B: Backend, I: Integrator<B, 0>>(
    integ: &mut I,
    h: f64,
    steps: usize,
    checkpoints: usize,
) -> Result<InvariantTrace, StepError> {
    let mut sys = Top::<B>::free_diag123();
    let mut y = crate::State::<B, 0>::new(free_body_start::<B>());
    let f = |x: V3<B>| B::vec3_to_array(x).map(|c| c.to_f64_lossless());
    let e0 = sys.energy(&y.body).to_f64_lossless();
    let p0 = f(sys.momentum(&y.body));
    let dist = |a: [f64; 3], b: [f64; 3]| {
        ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
    };
    let pn = dist(p0, [0.0; 3]);
    let hs = S::<B>::lit(h);
    let every = (steps / checkpoints.max(1)).max(1);
    let mut tr = InvariantTrace::default();
    for k in 0..steps {
        let t = hs * S::<B>::lit(k as f64);
        integ.step(&mut sys, t, hs, &mut y)?;
        if (k + 1) % every == 0 || k + 1 == steps {
            let e = sys.energy(&y.body).to_f64_lossless();
            let p = f(sys.momentum(&y.body));
            tr.step.push(k + 1);
            tr.energy.push(((e - e0) / e0).abs());
            tr.momentum.push(dist(p, p0) / pn);
            tr.orthogonality
                .push(orthogonality_error::<B>(y.body.r).to_f64_lossless());
        }
    }
    Ok(tr)
}
