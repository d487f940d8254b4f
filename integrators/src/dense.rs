//! Continuous extension of a step: the state at any instant inside a step
//! from the two end states and their rates, so that recording samples does
//! not have to move the step grid.
//!
//! Cubic Hermite interpolation of `x`, `v`, `Ω` and the extra states from
//! their values and derivatives at both ends. `R` is interpolated on the
//! group, not entry-wise: `R(θ) = R₀ Exp(ξ(θ))` with `ξ` the cubic Hermite
//! curve in the Lie algebra through `ξ(0) = 0`, `ξ(1) = Log(R₀ᵀR₁)` with
//! slopes `h Ω₀` and `h J_r⁻¹(ξ(1)) Ω₁` (for `R = R₀ Exp(ξ)`,
//! `Ω = J_r(ξ) ξ̇`). So the interpolant is a rotation for every `θ`, equals
//! both end states exactly, and has their angular velocities there.
//!
//! With exact end data a cubic Hermite interpolant is off by `O(h⁴)`; with
//! a method of order `p` the end data are off by `O(hᵖ)`, so a sample is
//! off by `O(h^min(p, 4))`: the method's own order for every stepper here
//! (Euler 1, LGVI 2, RK4/RKMK4 4; Dormand–Prince's 5th-order steps give
//! 4th-order samples).

use lie::{Backend, Real, Rotation, S, So3Mat, ops, right_jacobian_inv};

use crate::system::{Load, State, System};

/// A state's rates, as the continuous extension needs them.
#[derive(Copy, Clone, Debug)]
pub struct Rates<B: Backend, const N: usize> {
    /// `v̇ = force / m`.
    pub v_dot: lie::V3<B>,
    /// `Ω̇ = J⁻¹(M − Ω × JΩ)`.
    pub omega_dot: lie::V3<B>,
    /// The extra states' rates.
    pub extra: [S<B>; N],
}

impl<B: Backend, const N: usize> Rates<B, N> {
    /// The rates at `y` under load `l` for `sys`'s mass and inertia.
    pub fn of<Sys: System<B, N> + ?Sized>(sys: &Sys, y: &State<B, N>, l: &Load<B, N>) -> Self {
        let w = y.body.omega;
        Self {
            v_dot: l.force * (S::<B>::lit(1.0) / sys.mass()),
            omega_dot: sys.inertia_inv() * (l.moment - B::cross(w, sys.inertia() * w)),
            extra: l.extra_rate,
        }
    }
}

/// The state at `θ ∈ [0, 1]` of a step of length `h` from `y0` (rates
/// `r0`) to `y1` (rates `r1`); `θ = 0` and `θ = 1` give the end states
/// (to rounding).
pub fn interpolate<B: Backend, const N: usize>(
    y0: &State<B, N>,
    r0: &Rates<B, N>,
    y1: &State<B, N>,
    r1: &Rates<B, N>,
    h: S<B>,
    theta: S<B>,
) -> State<B, N> {
    let l = S::<B>::lit;
    let (t2, t3) = (theta * theta, theta * theta * theta);
    // The Hermite basis, with the slopes' weights scaled by h.
    let h00 = l(2.0) * t3 - l(3.0) * t2 + l(1.0);
    let h10 = (t3 - l(2.0) * t2 + theta) * h;
    let h01 = l(3.0) * t2 - l(2.0) * t3;
    let h11 = (t3 - t2) * h;
    let cubic = |p0: lie::V3<B>, m0: lie::V3<B>, p1: lie::V3<B>, m1: lie::V3<B>| {
        p0 * h00 + m0 * h10 + p1 * h01 + m1 * h11
    };
    let (b0, b1) = (&y0.body, &y1.body);
    let ra = So3Mat::<B>::from_matrix_unchecked(b0.r);
    let rb = So3Mat::<B>::from_matrix_unchecked(b1.r);
    let xi1 = ra.inverse().compose(rb).log();
    let m1 = right_jacobian_inv::<B>(xi1) * b1.omega;
    let xi = cubic(ops::zero::<B>(), b0.omega, xi1, m1);
    let mut y = *y0;
    y.body.r = ra.compose(So3Mat::<B>::exp(xi)).matrix();
    y.body.x = cubic(b0.x, b0.v, b1.x, b1.v);
    y.body.v = cubic(b0.v, r0.v_dot, b1.v, r1.v_dot);
    y.body.omega = cubic(b0.omega, r0.omega_dot, b1.omega, r1.omega_dot);
    for k in 0..N {
        y.extra[k] = y0.extra[k] * h00 + r0.extra[k] * h10 + y1.extra[k] * h01 + r1.extra[k] * h11;
    }
    y
}
