//! Closed loops on SIMD lanes (feature `simd`): the systems
//! `integrators::lanes` advances, one vehicle per lane. The same code runs
//! on a scalar backend (one lane), which is how its lanes are checked and
//! timed against the scalar path.
//!
//! They are the simulation's closed loop specialised to one vehicle and one
//! law (no plan, no `dyn` mode or vehicle, no recording or events), not a
//! replacement for it: the scalar [`Simulation`](crate::Simulation) runs any
//! scene. On one lane these loops take about half the time of the scalar
//! Monte Carlo path through the `Simulation` for the same steps, classes
//! and times to converge (the lanes chapter of the guide has the bench);
//! the lane tests tie the two paths' rows together.

use controllers::{
    AccelerationModel, AttitudeGains, AttitudeReference, PositionGains, PositionInput,
    PositionReference, RigidBodyParams, attitude_law, position_law,
};
use dynamics::Disturbance;
use integrators::lanes::LaneSystem;
use integrators::{Load, State};
use lie::num_traits::Zero;
use lie::{Backend, M3, Real, S, SimdBackend, SimdReal, So3Mat, V3};

/// The free quadrotor under the position law with constant disturbances
/// `Δ_x`, `Δ_R`, no rotor limits: force `m g e3 − f R e3 + Δ_x`, moment
/// `M + Δ_R`, the integral register `[e_I, e_i]` in the six extra states
/// (what the scalar simulation computes for a position segment on a
/// `Quadrotor` with a fixed disturbance). Every lane flies the same vehicle,
/// gains and reference; the lanes differ in their states.
///
/// The command of the last load evaluation is kept ([`PositionLoop::last`]):
/// after an accepted Dormand–Prince substep that is the command at its end
/// state (first same as last), so a driver reads Ψ and the thrust without
/// evaluating the law again.
pub struct PositionLoop<L: SimdBackend> {
    params: RigidBodyParams<L>,
    pos: PositionGains<L>,
    att: AttitudeGains<L>,
    model: AccelerationModel<L>,
    reference: PositionReference<L>,
    weight: S<L>,
    delta_x: V3<L>,
    delta_r: V3<L>,
    inertia_inv: M3<L>,
    last: Command<L>,
}

/// What a driver reads of the law's output between steps.
#[derive(Copy, Clone, Debug)]
pub struct Command<L: SimdBackend> {
    /// Thrust `f`, N.
    pub thrust: S<L>,
    /// Moment `M` (without `Δ_R`), N m.
    pub moment: V3<L>,
    /// `Ψ(R, R_c)`.
    pub psi: S<L>,
}

impl<L: SimdBackend> PositionLoop<L> {
    /// The loop of one vehicle (scalar backend `E`, the lanes' element
    /// type) copied into every lane; `None` for a singular inertia.
    #[allow(clippy::too_many_arguments)]
    pub fn splat<E>(
        params: &RigidBodyParams<E>,
        pos: &PositionGains<E>,
        att: &AttitudeGains<E>,
        model: AccelerationModel<E>,
        reference: &PositionReference<E>,
        disturbance: Option<Disturbance<E>>,
    ) -> Option<Self>
    where
        E: Backend,
        L: SimdBackend<Scalar: SimdReal<Element = E::Scalar>>,
    {
        let inv = lie::ops::inverse::<E>(params.inertia)?;
        let zero = E::vec3(E::Scalar::zero(), E::Scalar::zero(), E::Scalar::zero());
        let (dx, dr) = disturbance.map_or((zero, zero), |d| (d.force, d.moment));
        let splat = |v: V3<E>| lie::lanes::vec3_from_fn::<E, L>(|_| v);
        let model = match model {
            AccelerationModel::Nominal => AccelerationModel::Nominal,
            AccelerationModel::NominalWithoutEstimate => AccelerationModel::NominalWithoutEstimate,
            AccelerationModel::Measured { accel, jerk } => AccelerationModel::Measured {
                accel: splat(accel),
                jerk: splat(jerk),
            },
        };
        Some(Self {
            params: RigidBodyParams::splat(params),
            pos: PositionGains::splat(pos),
            att: AttitudeGains::splat(att),
            model,
            reference: PositionReference::from_lanes(|_| *reference),
            weight: S::<L>::simd_splat(params.mass * params.gravity),
            delta_x: splat(dx),
            delta_r: splat(dr),
            inertia_inv: lie::lanes::mat3_from_fn::<E, L>(|_| inv),
            last: Command {
                thrust: S::<L>::zero(),
                moment: splat(zero),
                psi: S::<L>::zero(),
            },
        })
    }

    /// The paper's vehicle and gains holding hover at the origin with
    /// `b1d = e1`, under the paper's Δ_x, Δ_R (the position experiment's
    /// loop), in every lane; `E` is the lanes' element backend.
    pub fn paper<E>() -> Self
    where
        E: Backend,
        L: SimdBackend<Scalar: SimdReal<Element = E::Scalar>>,
    {
        let d = |a: [f64; 3]| {
            E::vec3(
                E::Scalar::lit(a[0]),
                E::Scalar::lit(a[1]),
                E::Scalar::lit(a[2]),
            )
        };
        let hold = PositionReference::<E>::hold(d([0.0; 3]), d([1.0, 0.0, 0.0]));
        let disturbance = Disturbance {
            force: d(dynamics::paper::DELTA_X),
            moment: d(dynamics::paper::DELTA_R),
        };
        Self::splat(
            &RigidBodyParams::<E>::diagonal(
                dynamics::paper::MASS,
                dynamics::paper::INERTIA,
                dynamics::paper::GRAVITY,
            ),
            &PositionGains::<E>::paper(),
            &AttitudeGains::<E>::paper(),
            AccelerationModel::Nominal,
            &hold,
            Some(disturbance),
        )
        .expect("the paper's inertia is invertible")
    }
}

/// A closed loop that keeps the command of its last load evaluation.
pub trait Commanded<L: SimdBackend> {
    /// The command of the last load evaluation (zeros before the first):
    /// after an accepted Dormand–Prince substep, the command at its end
    /// state.
    fn last(&self) -> Command<L>;
}

impl<L: SimdBackend> Commanded<L> for PositionLoop<L> {
    fn last(&self) -> Command<L> {
        self.last
    }
}

/// The quadrotor pinned at its centre of gravity (the attitude stand at
/// height 0: no translation, no gravity moment) under the attitude law
/// holding `R_d` with `Ω_d = 0`, a constant disturbance moment `Δ_R` and
/// a constant thrust (the hover thrust `m g`, which moves nothing here):
/// moment `M + Δ_R`, `e_I` in extra states 0–2 (3–5 stay zero: the
/// register the scalar simulation shares with the position mode).
pub struct AttitudeLoop<L: SimdBackend> {
    params: RigidBodyParams<L>,
    gains: AttitudeGains<L>,
    reference: AttitudeReference<L, So3Mat<L>>,
    thrust: S<L>,
    delta_r: V3<L>,
    inertia_inv: M3<L>,
    last: Command<L>,
}

impl<L: SimdBackend> AttitudeLoop<L> {
    /// The loop of one vehicle (scalar backend `E`) copied into every
    /// lane, holding `rd` with thrust `thrust`; `None` for a singular
    /// inertia.
    pub fn splat<E>(
        params: &RigidBodyParams<E>,
        gains: &AttitudeGains<E>,
        rd: M3<E>,
        thrust: E::Scalar,
        delta_r: Option<V3<E>>,
    ) -> Option<Self>
    where
        E: Backend,
        L: SimdBackend<Scalar: SimdReal<Element = E::Scalar>>,
    {
        let inv = lie::ops::inverse::<E>(params.inertia)?;
        let zero = E::vec3(E::Scalar::zero(), E::Scalar::zero(), E::Scalar::zero());
        let splat = |v: V3<E>| lie::lanes::vec3_from_fn::<E, L>(|_| v);
        Some(Self {
            params: RigidBodyParams::splat(params),
            gains: AttitudeGains::splat(gains),
            reference: AttitudeReference {
                rd: So3Mat::from_matrix_unchecked(lie::lanes::mat3_from_fn::<E, L>(|_| rd)),
                omega_d: splat(zero),
                omega_d_dot: splat(zero),
            },
            thrust: S::<L>::simd_splat(thrust),
            delta_r: splat(delta_r.unwrap_or(zero)),
            inertia_inv: lie::lanes::mat3_from_fn::<E, L>(|_| inv),
            last: Command {
                thrust: S::<L>::zero(),
                moment: splat(zero),
                psi: S::<L>::zero(),
            },
        })
    }
}

impl<L: SimdBackend> Commanded<L> for AttitudeLoop<L> {
    fn last(&self) -> Command<L> {
        self.last
    }
}

impl<L: SimdBackend> LaneSystem<L, 6> for AttitudeLoop<L> {
    fn mass(&self) -> S<L> {
        self.params.mass
    }
    fn inertia(&self) -> M3<L> {
        self.params.inertia
    }
    fn inertia_inv(&self) -> M3<L> {
        self.inertia_inv
    }
    fn translates(&self) -> bool {
        false
    }
    /// `e_I` alone, as the scalar attitude mode's register.
    fn extra_in_use(&self) -> usize {
        3
    }
    #[inline(always)]
    fn load(&mut self, _t: S<L>, y: &State<L, 6>) -> Load<L, 6> {
        let [a0, a1, a2, ..] = y.extra;
        let out = attitude_law(
            &self.params,
            &self.gains,
            So3Mat::<L>::from_matrix_unchecked(y.body.r),
            y.body.omega,
            L::vec3(a0, a1, a2),
            &self.reference,
        );
        let z = S::<L>::zero();
        let a = L::vec3_to_array(out.e_i_rate);
        self.last = Command {
            thrust: self.thrust,
            moment: out.moment,
            psi: out.psi,
        };
        Load {
            force: L::vec3(z, z, z),
            moment: out.moment + self.delta_r,
            extra_rate: [a[0], a[1], a[2], z, z, z],
        }
    }
}

impl<L: SimdBackend> LaneSystem<L, 6> for PositionLoop<L> {
    fn mass(&self) -> S<L> {
        self.params.mass
    }
    fn inertia(&self) -> M3<L> {
        self.params.inertia
    }
    fn inertia_inv(&self) -> M3<L> {
        self.inertia_inv
    }
    #[inline(always)]
    fn load(&mut self, _t: S<L>, y: &State<L, 6>) -> Load<L, 6> {
        let [a0, a1, a2, p0, p1, p2] = y.extra;
        let state = y.body.group();
        let out = position_law(
            &self.params,
            &self.pos,
            &self.att,
            &PositionInput {
                state: &state,
                e_i_pos: L::vec3(p0, p1, p2),
                e_i_att: L::vec3(a0, a1, a2),
                reference: &self.reference,
                model: self.model,
            },
        );
        // `dynamics::body_loads` for a quadrotor without rotor limits.
        let z = S::<L>::zero();
        let [_, _, b3] = L::mat3_cols(y.body.r);
        let force = L::vec3(z, z, self.weight) - b3 * out.thrust + self.delta_x;
        let (a, p) = (
            L::vec3_to_array(out.e_i_att_rate),
            L::vec3_to_array(out.e_i_pos_rate),
        );
        let moment = out.moment + self.delta_r;
        self.last = Command {
            thrust: out.thrust,
            moment: out.moment,
            psi: out.psi,
        };
        Load {
            force,
            moment,
            extra_rate: [a[0], a[1], a[2], p[0], p[1], p[2]],
        }
    }
}
