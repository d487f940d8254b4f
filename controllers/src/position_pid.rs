//! Position controlled flight mode (Section IV): thrust (eqn:f), computed
//! attitude (eqn:Rd3, eqn:RdWc) with its angular velocity and acceleration
//! obtained by differentiating `b3c` and `b1c` analytically, and the moment
//! (eqn:M).

use crate::attitude_pid::{AttitudeGains, AttitudeReference, attitude_law};
use crate::{ControlError, RigidBodyParams};
use lie::ops::{cmul, is_finite_vec as is_finite, norm, zero};
use lie::{AttitudeErrors, Backend, Real, Rotation, S, SimdMask, SimdReal, V3};

/// The comparison mask of a backend's scalar: `bool` for `f32`/`f64`.
pub type Mask<B> = <S<B> as SimdReal>::Mask;
/// The number type in each lane of a backend's scalar.
type Element<B> = <S<B> as SimdReal>::Element;

/// Position gains, per inertial axis (diagonal); the paper's are scalars.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PositionGains<B: lie::SimdBackend> {
    /// `k_x` per axis.
    pub k_x: V3<B>,
    /// `k_v` per axis.
    pub k_v: V3<B>,
    /// `k_i` per axis (0 disables the integral term).
    pub k_i: V3<B>,
    /// `c1`: weight of `e_x` in the integrand of `e_i`.
    pub c1: S<B>,
    /// `σ`: the saturation level of `sat_σ(e_i)`.
    pub sigma: S<B>,
    /// Off (the paper's form): `e_i` integrates freely and only the value
    /// fed to `A` is saturated. On: `e_i`'s rate is zeroed in any component
    /// already at `±σ` and pushing outward, so `e_i` itself stays in
    /// `[−σ, σ]` (clamped anti-windup).
    pub clamp_integral: bool,
    /// Which branch `sat′` takes per component. [`SatBranch::Auto`] (the
    /// default) decides from `e_i`; a simulation that has located a
    /// crossing of `±σ` forces the branch of the side it is integrating, so
    /// that stages landing a rounding error past the boundary do not pick
    /// up the other side's `Ω_c` (a first-order error otherwise).
    pub sat_branch: [SatBranch; 3],
}

/// Branch of `sat′_σ` for one component of `e_i`.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub enum SatBranch {
    /// `1` for `|e| ≤ σ`, `0` outside.
    #[default]
    Auto,
    /// `1`, whatever `e`.
    Inside,
    /// `0`, whatever `e`.
    Outside,
}

impl<B: Backend> PositionGains<B> {
    /// Scalar gains, as in the paper, with the clamp off.
    pub fn uniform(k_x: S<B>, k_v: S<B>, k_i: S<B>, c1: S<B>, sigma: S<B>) -> Self {
        let v = |k| B::vec3(k, k, k);
        Self {
            k_x: v(k_x),
            k_v: v(k_v),
            k_i: v(k_i),
            c1,
            sigma,
            clamp_integral: false,
            sat_branch: [SatBranch::Auto; 3],
        }
    }
    /// The paper's gains: `k_x = 12.8, k_v = 4.22, k_i = 1.28, c1 = 3.6, σ = 1`.
    pub fn paper() -> Self {
        let s = S::<B>::lit;
        let g = crate::paper::POSITION_GAINS;
        Self::uniform(s(g.k_x), s(g.k_v), s(g.k_i), s(g.c1), s(g.sigma))
    }
}

/// The position command `x_d(t)` with four derivatives and the heading
/// command `b1d(t)` with two.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PositionReference<B: lie::SimdBackend> {
    /// `x_d`.
    pub x: V3<B>,
    /// `ẋ_d`.
    pub v: V3<B>,
    /// `ẍ_d`.
    pub a: V3<B>,
    /// `x_d⁽³⁾`.
    pub jerk: V3<B>,
    /// `x_d⁽⁴⁾`.
    pub snap: V3<B>,
    /// `b1d`, the desired heading direction (need not be unit or normal to
    /// `b3c`; it is projected).
    pub b1d: V3<B>,
    /// `ḃ1d`.
    pub b1d_dot: V3<B>,
    /// `b̈1d`.
    pub b1d_ddot: V3<B>,
}

impl<B: Backend> PositionReference<B> {
    /// Hold position `x_d` with heading `b1d`, all derivatives zero.
    pub fn hold(x: V3<B>, b1d: V3<B>) -> Self {
        let z = zero::<B>();
        Self {
            x,
            v: z,
            a: z,
            jerk: z,
            snap: z,
            b1d,
            b1d_dot: z,
            b1d_ddot: z,
        }
    }
}

/// The vehicle state the position law reads: attitude `R`, position `x`
/// and velocity `v = ẋ` in the inertial frame, body angular velocity `Ω`.
/// It is [`lie::RigidState`], the one rigid-body state of the workspace,
/// with the attitude in the representation `R` the law runs on (a matrix,
/// as the simulations integrate it, or a quaternion).
pub type VehicleState<B, R> = lie::RigidState<B, R>;

/// Which translational acceleration (and its derivative) the computed
/// attitude's derivatives use.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum AccelerationModel<B: lie::SimdBackend> {
    /// The nominal model with the integral term as the disturbance
    /// estimate: `a = g e3 − (f/m) R e3 + k_i sat_σ(e_i)/m` (the default).
    /// The controller does not know `Δ_x`, but at the equilibrium the
    /// integral term equals it (`k_i sat_σ(e_i) = Δ_x`), so this model is
    /// exact there and the equilibrium is the paper's.
    Nominal,
    /// The bare nominal model `a = g e3 − (f/m) R e3`. With `Δ_x ≠ 0` it
    /// predicts an acceleration `−Δ_x/m` at hover, so `Ω_c ≠ 0` while the
    /// vehicle is still and the loop settles with a persistent attitude
    /// and position offset (the `closed_loop` tests measure it). It is exact
    /// when `Δ_x = 0`.
    NominalWithoutEstimate,
    /// A measured or estimated acceleration and jerk.
    Measured {
        /// `ẍ`.
        accel: V3<B>,
        /// `x⁽³⁾`.
        jerk: V3<B>,
    },
}

/// Fallbacks taken when the construction of `R_c` degenerates.
///
/// `M` is the mask type of the backend's scalar: `bool` for `f32`/`f64`,
/// one flag per lane on a lane backend.
#[derive(Copy, Clone, Debug, Default, PartialEq, Eq)]
pub struct Degeneracy<M = bool> {
    /// `‖A‖` was (numerically) zero, (eqn:A1) violated: the thrust direction
    /// is undefined. `b3c` is then the current body axis `R e3` with zero
    /// derivatives, and the thrust `−A·Re3` is ≈ 0.
    pub thrust_direction_undefined: M,
    /// `b1d` was (nearly) parallel to `b3c`, so the heading is undefined.
    /// The current body axis `R e1` is used as `b1d` with zero derivatives
    /// (hold the present heading); if that is parallel too, `R e2`.
    pub heading_undefined: M,
}

/// What the position law computed.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct PositionOutput<B: lie::SimdBackend, R: AttitudeErrors<B>> {
    /// Total thrust `f` (eqn:f), acting along `−R e3`.
    pub thrust: S<B>,
    /// Moment `M` (eqn:M), body frame.
    pub moment: V3<B>,
    /// Computed attitude `R_c` (eqn:RdWc).
    pub rc: R,
    /// `Ω_c`, from `Ω_c^ = R_cᵀ Ṙ_c`.
    pub omega_c: V3<B>,
    /// `Ω̇_c`.
    pub omega_c_dot: V3<B>,
    /// `e_x = x − x_d`.
    pub e_x: V3<B>,
    /// `e_v = v − ẋ_d`.
    pub e_v: V3<B>,
    /// `e_R` against `R_c`.
    pub e_r: V3<B>,
    /// `e_Ω` against `Ω_c`.
    pub e_omega: V3<B>,
    /// `Ψ(R, R_c)`.
    pub psi: S<B>,
    /// `ė_i = e_v + c1 e_x` (zeroed where clamped, if the clamp is on).
    pub e_i_pos_rate: V3<B>,
    /// `ė_I = e_Ω + c2 e_R`.
    pub e_i_att_rate: V3<B>,
    /// Fallbacks taken, if any (per lane on a lane backend).
    pub degeneracy: Degeneracy<Mask<B>>,
}

// Always inlined: on the dual scalar it was left out of line and its two
// vectors returned through memory (1.8 % of a gradient's instructions);
// on `f32`/`f64` it was inlined already.
#[inline(always)]
fn sat_and_slope<B: lie::SimdBackend>(
    e: V3<B>,
    sigma: S<B>,
    branch: [SatBranch; 3],
) -> (V3<B>, V3<B>) {
    let a = B::vec3_to_array(e);
    let (one, zero_) = (S::<B>::simd_lit(1.0), S::<B>::simd_lit(0.0));
    // Component by component rather than `[_; 3]::map`: the array map was
    // left out of line in release builds.
    let s = |i: usize| {
        let v = a[i].simd_max(-sigma).simd_min(sigma);
        if !S::<B>::CARRIES_DERIVATIVES {
            return v;
        }
        // A located crossing lands e_i on ±σ, where the clamp's tie hands
        // over either operand's derivatives: a forced branch decides (the
        // value is the clamp's either way).
        match branch[i] {
            SatBranch::Auto => v,
            SatBranch::Inside => v.with_derivatives_of(a[i]),
            SatBranch::Outside => {
                let outer = S::<B>::simd_select(a[i].simd_lt(zero_), -sigma, sigma);
                v.with_derivatives_of(outer)
            }
        }
    };
    // sat′ is 1 inside [−σ, σ] (the closed interval: the paper's cases) and
    // 0 outside, unless a branch is forced.
    let d = |i: usize| match branch[i] {
        SatBranch::Auto => S::<B>::simd_select(a[i].simd_abs().simd_le(sigma), one, zero_),
        SatBranch::Inside => one,
        SatBranch::Outside => zero_,
    };
    (B::vec3(s(0), s(1), s(2)), B::vec3(d(0), d(1), d(2)))
}

/// Zeroes the rate of components that sit at `±σ` and push outward.
#[inline]
fn clamp_rate<B: lie::SimdBackend>(e: V3<B>, rate: V3<B>, sigma: S<B>) -> V3<B> {
    let (e, r) = (B::vec3_to_array(e), B::vec3_to_array(rate));
    let z = S::<B>::simd_lit(0.0);
    let c = |i: usize| {
        let outward =
            (e[i].simd_ge(sigma) & r[i].simd_gt(z)) | (e[i].simd_le(-sigma) & r[i].simd_lt(z));
        S::<B>::simd_select(outward, z, r[i])
    };
    B::vec3(c(0), c(1), c(2))
}

/// The thrust of the paper's attitude-mode flip,
/// `f = (k_x e_x + k_v e_v + m g e3 − m ẍ_d)·R e3`: the position-PD
/// projection of (eqn:f) without the integral term.
pub fn thrust_pd_projection<B: Backend, R: Rotation<B>>(
    params: &RigidBodyParams<B>,
    gains: &PositionGains<B>,
    state: &VehicleState<B, R>,
    reference: &PositionReference<B>,
) -> S<B> {
    let e3 = B::vec3(S::<B>::lit(0.0), S::<B>::lit(0.0), S::<B>::lit(1.0));
    let a = cmul::<B>(gains.k_x, state.x - reference.x)
        + cmul::<B>(gains.k_v, state.v - reference.v)
        + e3 * (params.mass * params.gravity)
        - reference.a * params.mass;
    B::dot(a, state.r.act(e3))
}

/// What the position law reads at one instant, by name: the two integrals
/// sit next to each other in the register in the order `[e_I, e_i]`, and
/// named fields keep them from being swapped.
#[derive(Copy, Clone, Debug)]
pub struct PositionInput<'a, B: lie::SimdBackend, R: AttitudeErrors<B>> {
    /// The vehicle's state.
    pub state: &'a VehicleState<B, R>,
    /// The position integral `e_i` (register slots 3–5 in the paper's
    /// modes).
    pub e_i_pos: V3<B>,
    /// The attitude integral `e_I` (register slots 0–2).
    pub e_i_att: V3<B>,
    /// The position and heading command.
    pub reference: &'a PositionReference<B>,
    /// Which acceleration the derivatives of `R_c` use.
    pub model: AccelerationModel<B>,
}

/// The position law: (eqn:Rd3), (eqn:f), (eqn:RdWc), (eqn:M).
///
/// `input.e_i_pos` and `input.e_i_att` are the caller-held integrals
/// `e_i` and `e_I`.
/// With `A = −k_x e_x − k_v e_v − k_i sat_σ(e_i) − m g e3 + m ẍ_d`:
/// `b3c = −A/‖A‖`, `f = −A·R e3`, `b2c = b3c × b1d/‖·‖`, `b1c = b2c × b3c`,
/// `R_c = [b1c, b2c, b3c]`. `Ȧ` and `Ä` use `ė_x = e_v`, `ė_v = a − ẍ_d`,
/// `ė_i = e_v + c1 e_x`, sat′ (piecewise constant, so sat″ = 0 between
/// crossings), and the acceleration from `model`; then
/// `Ω_c = (R_cᵀṘ_c)^∨`, `Ω̇_c = (R_cᵀR̈_c)^∨` (the symmetric part
/// `Ṙ_cᵀṘ_c` of the derivative of `R_cᵀṘ_c` has no vee).
///
/// Only the projections the result needs are formed: with `ḃ_k` the
/// derivatives of the columns of `R_c`, `Ω_c = (b3·ḃ2, b1·ḃ3, −b1·ḃ2)` and
/// `Ω̇_c = (b3·b̈2 − Ω2Ω3, b1·b̈3 − Ω3Ω1, −b1·b̈2 + Ω1Ω2)` (the products
/// `ḃ_j·ḃ_k` expressed through `Ω_c`), so `b1`'s derivatives are never
/// formed. A non-finite input is found from the outputs (every input but
/// `e_i`, whose saturation would drop a NaN, reaches `f` or `M`; a test
/// injects NaN and ±∞ into each), and then named by checking the inputs.
#[inline(always)]
pub fn position_control<B: Backend, R: Rotation<B>>(
    params: &RigidBodyParams<B>,
    pos_gains: &PositionGains<B>,
    att_gains: &AttitudeGains<B>,
    input: &PositionInput<'_, B, R>,
) -> Result<PositionOutput<B, R>, ControlError> {
    let PositionInput {
        state,
        e_i_pos,
        e_i_att,
        reference,
        model,
    } = *input;
    // `sat` clamps with min/max, which return the other operand for a NaN:
    // e_i must be checked itself.
    if !is_finite::<B>(e_i_pos) {
        return Err(ControlError::NonFinite {
            field: "e_i (position integral)",
        });
    }
    if let AccelerationModel::Measured { accel, jerk } = model
        && !(is_finite::<B>(accel) && is_finite::<B>(jerk))
    {
        return Err(ControlError::NonFinite {
            field: "measured acceleration/jerk",
        });
    }
    let out = position_law(params, pos_gains, att_gains, input);
    let degenerate = out.degeneracy.thrust_direction_undefined || out.degeneracy.heading_undefined;
    // A fallback replaces derivatives by zeros and could drop a NaN in
    // them: then every input is checked, as it is whenever an output is
    // not finite.
    let finite = out.thrust.is_finite() && is_finite::<B>(out.moment);
    if degenerate || !finite {
        if let Some(e) = non_finite_input(state, e_i_att, reference) {
            return Err(e);
        }
        if !finite {
            return Err(ControlError::NonFinite { field: "state.r" });
        }
    }
    Ok(out)
}

/// The name of the first non-finite input of [`position_control`]. Out of
/// line and cold: it runs only once an output is known to be bad, and
/// keeping it out of the law's body leaves the law's registers alone.
#[cold]
#[inline(never)]
fn non_finite_input<B: Backend, R: Rotation<B>>(
    state: &VehicleState<B, R>,
    e_i_att: V3<B>,
    reference: &PositionReference<B>,
) -> Option<ControlError> {
    let own = [
        (state.x, "state.x"),
        (state.v, "state.v"),
        (state.omega, "state.omega"),
        (e_i_att, "e_I (attitude integral)"),
    ];
    if let Some((_, field)) = own.into_iter().find(|(v, _)| !is_finite::<B>(*v)) {
        return Some(ControlError::NonFinite { field });
    }
    reference_field(reference).map(|field| ControlError::NonFiniteReference { field })
}

/// The first field of `reference` that is not finite.
fn reference_field<B: Backend>(reference: &PositionReference<B>) -> Option<&'static str> {
    [
        (reference.x, "reference.x"),
        (reference.v, "reference.v"),
        (reference.a, "reference.a"),
        (reference.jerk, "reference.jerk"),
        (reference.snap, "reference.snap"),
        (reference.b1d, "reference.b1d"),
        (reference.b1d_dot, "reference.b1d_dot"),
        (reference.b1d_ddot, "reference.b1d_ddot"),
    ]
    .into_iter()
    .find(|(v, _)| !is_finite::<B>(*v))
    .map(|(_, f)| f)
}

/// `(b, ḃ, b̈, q, 1/‖u‖)` of [`unit_with_derivatives`].
type UnitDerivatives<B> = (V3<B>, V3<B>, V3<B>, S<B>, S<B>);

/// `b = u/‖u‖` and its first two derivatives from those of `u` (`n` =
/// ‖u‖ > 0): with `q = b·u̇`, `ḃ = (u̇ − q b)/‖u‖`,
/// `b̈ = (ü − 2q ḃ − (ḃ·u̇ + b·ü) b)/‖u‖`. Returns `(b, ḃ, b̈, q, 1/‖u‖)`.
#[inline(always)]
fn unit_with_derivatives<B: lie::SimdBackend>(
    u: V3<B>,
    ud: V3<B>,
    udd: V3<B>,
    n: S<B>,
) -> UnitDerivatives<B> {
    let (one, two) = (S::<B>::simd_lit(1.0), S::<B>::simd_lit(2.0));
    let inv = one / n;
    let b = u * inv;
    let q = B::dot(b, ud);
    let bd = (ud - b * q) * inv;
    let bdd = (udd - bd * (two * q) - b * (B::dot(bd, ud) + B::dot(b, udd))) * inv;
    (b, bd, bdd, q, inv)
}

/// `b2c` and `1/‖c‖` when `b3c` is `R e3` (no thrust direction) or nearly
/// parallel to `b1d`: `c = b3c × b1d` from `b3c` itself, and when even
/// that vanishes a body axis (`b1`, else `b2`) replaces `b1d` (its
/// derivatives zero), noted in the returned mask (per lane); the `b1d`
/// used is returned. It reads `b1d` from the reference itself: a copy of
/// it made for this cold call would stay in the caller's stack frame, and
/// the regular path's loads from that copy (wider than its stores) miss
/// store forwarding.
#[cold]
#[inline(never)]
fn degenerate_heading<B: lie::SimdBackend>(
    b3: V3<B>,
    reference: &PositionReference<B>,
    (rb1, rb2): (V3<B>, V3<B>),
    c_floor: S<B>,
) -> Heading<B> {
    let mut b1d = (reference.b1d, reference.b1d_dot, reference.b1d_ddot);
    let z = zero::<B>();
    let c = B::cross(b3, b1d.0);
    let nc = norm::<B>(c);
    let undefined = nc.simd_le(c_floor);
    let (c, nc) = if undefined.any() {
        let alt =
            lie::ops::select_vec::<B>(norm::<B>(B::cross(b3, rb1)).simd_gt(c_floor), rb1, rb2);
        b1d = (
            lie::ops::select_vec::<B>(undefined, alt, b1d.0),
            lie::ops::select_vec::<B>(undefined, z, b1d.1),
            lie::ops::select_vec::<B>(undefined, z, b1d.2),
        );
        let c = B::cross(b3, b1d.0);
        (c, norm::<B>(c))
    } else {
        (c, nc)
    };
    let invc = S::<B>::simd_lit(1.0) / nc;
    (c * invc, invc, b1d, undefined)
}

/// `b3c = u/‖u‖` with its derivatives ([`unit_with_derivatives`]) where
/// `‖u‖ > floor`, else `R e3` with zero derivatives; and the mask of the
/// lanes where `‖u‖ > floor`. One lane: an `if`. Lanes: the regular
/// construction, with the fallback blended into the lanes that need it.
#[inline(always)]
fn thrust_axis<B: lie::SimdBackend>(
    (u, ud, udd): WithDerivatives<B>,
    n: S<B>,
    floor: S<B>,
    re3: V3<B>,
) -> (UnitDerivatives<B>, Mask<B>) {
    let (z, zs) = (zero::<B>(), S::<B>::simd_lit(0.0));
    let ok = n.simd_gt(floor);
    let fallback = || (re3, z, z, zs, zs);
    let axis = if ok.all() {
        unit_with_derivatives::<B>(u, ud, udd, n)
    } else if !ok.any() {
        fallback()
    } else {
        let (r, f) = (unit_with_derivatives::<B>(u, ud, udd, n), fallback());
        let (v, sc) = (lie::ops::select_vec::<B>, S::<B>::simd_select);
        (
            v(ok, r.0, f.0),
            v(ok, r.1, f.1),
            v(ok, r.2, f.2),
            sc(ok, r.3, f.3),
            sc(ok, r.4, f.4),
        )
    };
    (axis, ok)
}

/// A vector and its first two derivatives (`b1d`, `ḃ1d`, `b̈1d`).
type WithDerivatives<B> = (V3<B>, V3<B>, V3<B>);
/// What [`heading_axis`] returns: `(b2c, 1/‖c‖, b1d used, heading undefined)`.
type Heading<B> = (V3<B>, S<B>, WithDerivatives<B>, Mask<B>);

/// `b2c = c/‖c‖` with `c = b3c × b1d`, `1/‖c‖`, the `b1d` (and its
/// derivatives) actually used, and the lanes whose heading was undefined.
/// In the regular case `c = (u × b1d)/‖u‖`, so `b2c = (u × b1d)/‖u × b1d‖`
/// and `1/‖c‖ = ‖u‖/‖u × b1d‖`: the two square roots and reciprocals do
/// not wait on each other (they are the longest chain of the law). Where
/// the thrust direction is undefined or `b1d ∥ b3c`,
/// [`degenerate_heading`].
#[inline(always)]
fn heading_axis<B: lie::SimdBackend>(
    (u, n): (V3<B>, S<B>),
    b3: V3<B>,
    reference: &PositionReference<B>,
    (thrust_ok, c_floor): (Mask<B>, S<B>),
    body: (V3<B>, V3<B>),
) -> Heading<B> {
    let b1d = (reference.b1d, reference.b1d_dot, reference.b1d_ddot);
    let cu = B::cross(u, b1d.0);
    let ncu = norm::<B>(cu);
    let regular = thrust_ok & ncu.simd_gt(c_floor * n);
    let heading = || {
        let inv_cu = S::<B>::simd_lit(1.0) / ncu;
        (cu * inv_cu, n * inv_cu)
    };
    if regular.all() {
        let (b2, invc) = heading();
        (b2, invc, b1d, Mask::<B>::splat(false))
    } else if !regular.any() {
        degenerate_heading::<B>(b3, reference, body, c_floor)
    } else {
        let (b2, invc) = heading();
        let (b2_f, invc_f, b1d_f, undefined) =
            degenerate_heading::<B>(b3, reference, body, c_floor);
        let v = |a, b| lie::ops::select_vec::<B>(regular, a, b);
        (
            v(b2, b2_f),
            S::<B>::simd_select(regular, invc, invc_f),
            (v(b1d.0, b1d_f.0), v(b1d.1, b1d_f.1), v(b1d.2, b1d_f.2)),
            undefined & !regular,
        )
    }
}

/// The position law (eqn:Rd3), (eqn:f), (eqn:RdWc), (eqn:M) without input
/// checks: what [`position_control`] computes, on any backend, SIMD lanes
/// included (`lie`'s `simd` feature: one call computes four or eight
/// vehicles' thrusts and moments). Each branch of the law (the
/// saturation, the two degeneracy fallbacks) is taken lane by lane, and
/// the returned [`Degeneracy`] says which lanes took a fallback. A NaN or
/// ±∞ in an input gives NaN outputs (in that lane) instead of an error,
/// with one exception on `f32`/`f64`: `sat_σ` clamps with `max`/`min`,
/// which drop a NaN in `e_i` (on lanes the clamp is a select and keeps
/// it). Call [`position_control`] for the checked law, which checks `e_i`.
#[inline(always)]
pub fn position_law<B: lie::SimdBackend, R: AttitudeErrors<B>>(
    params: &RigidBodyParams<B>,
    pos_gains: &PositionGains<B>,
    att_gains: &AttitudeGains<B>,
    input: &PositionInput<'_, B, R>,
) -> PositionOutput<B, R> {
    let (state, e_i_pos, e_i_att, reference) =
        (input.state, input.e_i_pos, input.e_i_att, input.reference);
    let model = &input.model;
    let s = S::<B>::simd_lit;
    let (one, two) = (s(1.0), s(2.0));
    let (m, g) = (params.mass, params.gravity);
    let inv_m = one / m;
    let g_ = &pos_gains;
    let z = s(0.0);
    let r = state.r;
    let e_x = state.x - reference.x;
    let e_v = state.v - reference.v;
    let (sat, slope) = sat_and_slope::<B>(e_i_pos, g_.sigma, g_.sat_branch);
    let mut ei_rate = e_v + e_x * g_.c1;
    if g_.clamp_integral {
        ei_rate = clamp_rate::<B>(e_i_pos, ei_rate, g_.sigma);
    }
    let ki_sat = cmul::<B>(g_.k_i, sat);
    // u = −A (eqn:A1) and its derivatives are formed directly rather than
    // A and then negated: IEEE negation is exact, so `−(a + b) = −a − b`
    // and `−(−p) − (−q) = p + q` bit for bit, and the law saves a
    // negation per component of every term. `g e3`, `m g e3` are written
    // with their zero components: `x − 0 = x` folds, `0·g` would not.
    let u = cmul::<B>(g_.k_x, e_x) + cmul::<B>(g_.k_v, e_v) + ki_sat + B::vec3(z, z, m * g)
        - reference.a * m;
    let [rb1, rb2, re3] = r.body_axes();
    let thrust = B::dot(u, re3);

    // First derivatives.
    let ki_slope_rate = cmul::<B>(g_.k_i, cmul::<B>(slope, ei_rate));
    let accel = match model {
        AccelerationModel::Nominal => B::vec3(z, z, g) - re3 * (thrust * inv_m) + ki_sat * inv_m,
        AccelerationModel::NominalWithoutEstimate => B::vec3(z, z, g) - re3 * (thrust * inv_m),
        AccelerationModel::Measured { accel, .. } => *accel,
    };
    let ev_dot = accel - reference.a;
    let ud =
        cmul::<B>(g_.k_x, e_v) + cmul::<B>(g_.k_v, ev_dot) + ki_slope_rate - reference.jerk * m;
    // Second derivatives. R e3 moves as R (Ω × e3) = Ω2 b1 − Ω1 b2.
    let w = B::vec3_to_array(state.omega);
    let re3_dot = rb1 * w[1] - rb2 * w[0];
    let thrust_dot = B::dot(ud, re3) + B::dot(u, re3_dot);
    let bare_jerk = -(re3 * thrust_dot + re3_dot * thrust) * inv_m;
    let jerk = match model {
        AccelerationModel::Nominal => bare_jerk + ki_slope_rate * inv_m,
        AccelerationModel::NominalWithoutEstimate => bare_jerk,
        AccelerationModel::Measured { jerk, .. } => *jerk,
    };
    let ev_ddot = jerk - reference.jerk;
    let mut ei_rate_dot = ev_dot + e_v * g_.c1;
    if g_.clamp_integral {
        ei_rate_dot = clamp_rate::<B>(e_i_pos, ei_rate_dot, g_.sigma);
    }
    let udd = cmul::<B>(g_.k_x, ev_dot)
        + cmul::<B>(g_.k_v, ev_ddot)
        + cmul::<B>(g_.k_i, cmul::<B>(slope, ei_rate_dot))
        - reference.snap * m;

    // b3c = u/‖u‖ and its derivatives; (eqn:A1) guarded.
    let n = norm::<B>(u);
    let root_eps = S::<B>::simd_splat(<Element<B> as Real>::epsilon()).simd_sqrt();
    let a_floor = root_eps * m * g;
    let ((b3, b3d, b3dd, q3, inv3), thrust_ok) = thrust_axis::<B>((u, ud, udd), n, a_floor, re3);
    let thrust_undefined = !thrust_ok;

    // b2c = c/‖c‖, c = b3c × b1d; b1d ∥ b3c guarded. In the regular case
    // c = (u × b1d)/‖u‖, so b2c = (u × b1d)/‖u × b1d‖ and 1/‖c‖ =
    // ‖u‖/‖u × b1d‖: the two square roots and reciprocals do not wait on
    // each other (they are the longest chain of the law).
    let c_floor = root_eps * (one + norm::<B>(reference.b1d));
    let (b2, invc, b1d, heading_undefined) =
        heading_axis::<B>((u, n), b3, reference, (thrust_ok, c_floor), (rb1, rb2));
    let cd = B::cross(b3d, b1d.0) + B::cross(b3, b1d.1);
    let cdd = B::cross(b3dd, b1d.0) + B::cross(b3d, b1d.1) * two + B::cross(b3, b1d.2);
    let qc = B::dot(b2, cd);
    let b1 = B::cross(b2, b3);

    // Ω_c from the projections: b3·ḃ2 = b3·ċ/‖c‖, b1·ḃ2 = b1·ċ/‖c‖ (b2 ⟂
    // b1, b3), b1·ḃ3.
    let w1 = B::dot(b3, cd) * invc;
    let w3 = -B::dot(b1, cd) * invc;
    let w2 = B::dot(b1, b3d);
    // b3·b̈2, b1·b̈2 and b1·b̈3 from b̈ = (ü − 2q ḃ − (…) b)/‖u‖, whose last
    // term is normal to the projection axis.
    let b3_b2dd = (B::dot(b3, cdd) - two * qc * w1) * invc;
    let b1_b2dd = (B::dot(b1, cdd) + two * qc * w3) * invc;
    let b1_b3dd = if thrust_undefined.all() {
        s(0.0)
    } else {
        let b1_b3dd = (B::dot(b1, udd) - two * q3 * w2) * inv3;
        if thrust_undefined.any() {
            S::<B>::simd_select(thrust_undefined, s(0.0), b1_b3dd)
        } else {
            b1_b3dd
        }
    };
    let omega_c = B::vec3(w1, w2, w3);
    let omega_c_dot = B::vec3(b3_b2dd - w2 * w3, b1_b3dd - w3 * w1, -b1_b2dd + w1 * w2);
    let rc = R::from_frame(b1, b2, b3);

    let att = attitude_law(
        params,
        att_gains,
        r,
        state.omega,
        e_i_att,
        &AttitudeReference {
            rd: rc,
            omega_d: omega_c,
            omega_d_dot: omega_c_dot,
        },
    );
    PositionOutput {
        thrust,
        moment: att.moment,
        rc,
        omega_c,
        omega_c_dot,
        e_x,
        e_v,
        e_r: att.e_r,
        e_omega: att.e_omega,
        psi: att.psi,
        e_i_pos_rate: ei_rate,
        e_i_att_rate: att.e_i_rate,
        degeneracy: Degeneracy {
            thrust_direction_undefined: thrust_undefined,
            heading_undefined,
        },
    }
}

#[cfg(test)]
mod reference;
#[cfg(test)]
mod tests;
