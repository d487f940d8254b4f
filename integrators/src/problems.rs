//! Test problems with known invariants.

use lie::{Backend, M3, Real, S, V3, ops};

use crate::{Load, State, System};

/// The heavy top (a 3D pendulum on a fixed pivot, translation suppressed):
/// `J Ω̇ + Ω × JΩ = m g ρ × Rᵀe3`, with `ρ` the centre of mass from the pivot
/// in body coordinates (e3 down). Invariants: the energy
/// `½ΩᵀJΩ − m g e3ᵀRρ` and the vertical momentum `e3ᵀRJΩ`.
#[derive(Copy, Clone, Debug)]
pub struct HeavyTop<B: Backend> {
    inertia: M3<B>,
    inertia_inv: M3<B>,
    /// `m g ρ`, N m.
    pub mg_rho: V3<B>,
}

impl<B: Backend> HeavyTop<B> {
    /// `J = diag(1, 2, 3)`, `m g ρ = (0, 0.5, 1)`: the problem of the
    /// integrator note.
    pub fn standard() -> Self {
        let l = S::<B>::lit;
        let inertia = ops::diag::<B>(l(1.0), l(2.0), l(3.0));
        Self {
            inertia,
            inertia_inv: ops::inverse::<B>(inertia).expect("diagonal, positive"),
            mg_rho: B::vec3(l(0.0), l(0.5), l(1.0)),
        }
    }

    fn down_body(r: M3<B>) -> V3<B> {
        let z = S::<B>::lit(0.0);
        B::mat3_tr_mul_vec(r, B::vec3(z, z, S::<B>::lit(1.0)))
    }

    /// Total energy.
    pub fn energy<const N: usize>(&self, y: &State<B, N>) -> S<B> {
        let w = y.body.omega;
        S::<B>::lit(0.5) * B::dot(w, self.inertia * w)
            - B::dot(Self::down_body(y.body.r), self.mg_rho)
    }

    /// Vertical angular momentum `e3ᵀ R J Ω`.
    pub fn vertical_momentum<const N: usize>(&self, y: &State<B, N>) -> S<B> {
        B::dot(Self::down_body(y.body.r), self.inertia * y.body.omega)
    }
}

impl<B: Backend> System<B, 0> for HeavyTop<B> {
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
