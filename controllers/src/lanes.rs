//! Parameters and gains copied into every lane of a lane backend (`lie`'s
//! `simd` feature), for the laws run on lanes: every lane flies the same
//! vehicle with the same gains, and only the states and references differ
//! (a reference per lane: [`PositionReference::from_lanes`]).

use crate::{AttitudeGains, PositionGains, PositionReference, RigidBodyParams};
use lie::{Backend, SimdBackend, SimdReal, V3, lanes};

impl<L: SimdBackend> RigidBodyParams<L> {
    /// `p` in every lane.
    pub fn splat<S>(p: &RigidBodyParams<S>) -> Self
    where
        S: Backend,
        L::Scalar: SimdReal<Element = S::Scalar>,
    {
        Self {
            mass: SimdReal::simd_splat(p.mass),
            inertia: lanes::mat3_from_fn::<S, L>(|_| p.inertia),
            gravity: SimdReal::simd_splat(p.gravity),
        }
    }
}

impl<L: SimdBackend> AttitudeGains<L> {
    /// `g` in every lane.
    pub fn splat<S>(g: &AttitudeGains<S>) -> Self
    where
        S: Backend,
        L::Scalar: SimdReal<Element = S::Scalar>,
    {
        Self {
            k_r: lanes::vec3_from_fn::<S, L>(|_| g.k_r),
            k_omega: lanes::vec3_from_fn::<S, L>(|_| g.k_omega),
            k_i: lanes::vec3_from_fn::<S, L>(|_| g.k_i),
            c2: SimdReal::simd_splat(g.c2),
        }
    }
}

impl<L: SimdBackend> PositionGains<L> {
    /// `g` in every lane (`clamp_integral` and `sat_branch` as they are:
    /// they are per law, not per lane).
    pub fn splat<S>(g: &PositionGains<S>) -> Self
    where
        S: Backend,
        L::Scalar: SimdReal<Element = S::Scalar>,
    {
        Self {
            k_x: lanes::vec3_from_fn::<S, L>(|_| g.k_x),
            k_v: lanes::vec3_from_fn::<S, L>(|_| g.k_v),
            k_i: lanes::vec3_from_fn::<S, L>(|_| g.k_i),
            c1: SimdReal::simd_splat(g.c1),
            sigma: SimdReal::simd_splat(g.sigma),
            clamp_integral: g.clamp_integral,
            sat_branch: g.sat_branch,
        }
    }
}

impl<L: SimdBackend> PositionReference<L> {
    /// Lane `i` follows `f(i)`: one reference per vehicle of the lanes.
    pub fn from_lanes<S>(f: impl Fn(usize) -> PositionReference<S>) -> Self
    where
        S: Backend,
        L::Scalar: SimdReal<Element = S::Scalar>,
    {
        let field =
            |g: fn(&PositionReference<S>) -> V3<S>| lanes::vec3_from_fn::<S, L>(|i| g(&f(i)));
        Self {
            x: field(|r| r.x),
            v: field(|r| r.v),
            a: field(|r| r.a),
            jerk: field(|r| r.jerk),
            snap: field(|r| r.snap),
            b1d: field(|r| r.b1d),
            b1d_dot: field(|r| r.b1d_dot),
            b1d_ddot: field(|r| r.b1d_ddot),
        }
    }
}
