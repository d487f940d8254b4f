//! The first implementation of the position law, kept as the reference the
//! faster one is tested against: full derivative vectors, every input
//! checked up front, and its own written-out saturation (no helper shared
//! with the law under test).

use super::*;
use lie::vee;

/// The first implementation of [`position_control`] (full derivative
/// vectors, `Ω_c` and `Ω̇_c` through `R_cᵀṘ_c`, `R_cᵀR̈_c` products, every
/// input checked up front), kept as the reference the faster one is tested
/// against.
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
pub(crate) fn position_control_reference<B: Backend, R: Rotation<B>>(
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
    check_inputs(state, e_i_pos, e_i_att, reference, &model)?;
    let s = S::<B>::lit;
    let (m, g) = (params.mass, params.gravity);
    let g_ = &pos_gains;
    let (z, e1, e2, e3) = (
        zero::<B>(),
        B::vec3(s(1.0), s(0.0), s(0.0)),
        B::vec3(s(0.0), s(1.0), s(0.0)),
        B::vec3(s(0.0), s(0.0), s(1.0)),
    );
    let r = state.r;
    let mut degeneracy = Degeneracy::default();

    let e_x = state.x - reference.x;
    let e_v = state.v - reference.v;
    let (sat, slope) = written_out_sat::<B>(e_i_pos, g_);
    let clamp = |rate: V3<B>| written_out_clamp::<B>(e_i_pos, rate, g_.sigma);
    let mut ei_rate = e_v + e_x * g_.c1;
    if g_.clamp_integral {
        ei_rate = clamp(ei_rate);
    }
    let a_cmd =
        -cmul::<B>(g_.k_x, e_x) - cmul::<B>(g_.k_v, e_v) - cmul::<B>(g_.k_i, sat) - e3 * (m * g)
            + reference.a * m;
    let re3 = r.act(e3);
    let thrust = -B::dot(a_cmd, re3);

    // First derivatives.
    let estimate = cmul::<B>(g_.k_i, sat) * (s(1.0) / m);
    let accel = match model {
        AccelerationModel::Nominal => e3 * g - re3 * (thrust / m) + estimate,
        AccelerationModel::NominalWithoutEstimate => e3 * g - re3 * (thrust / m),
        AccelerationModel::Measured { accel, .. } => accel,
    };
    let ev_dot = accel - reference.a;
    let a_dot = -cmul::<B>(g_.k_x, e_v)
        - cmul::<B>(g_.k_v, ev_dot)
        - cmul::<B>(g_.k_i, cmul::<B>(slope, ei_rate))
        + reference.jerk * m;
    // Second derivatives.
    let re3_dot = r.act(B::cross(state.omega, e3));
    let thrust_dot = -B::dot(a_dot, re3) - B::dot(a_cmd, re3_dot);
    let bare_jerk = -(re3 * thrust_dot + re3_dot * thrust) * (s(1.0) / m);
    let jerk = match model {
        AccelerationModel::Nominal => {
            bare_jerk + cmul::<B>(g_.k_i, cmul::<B>(slope, ei_rate)) * (s(1.0) / m)
        }
        AccelerationModel::NominalWithoutEstimate => bare_jerk,
        AccelerationModel::Measured { jerk, .. } => jerk,
    };
    let ev_ddot = jerk - reference.jerk;
    let mut ei_rate_dot = ev_dot + e_v * g_.c1;
    if g_.clamp_integral {
        ei_rate_dot = clamp(ei_rate_dot);
    }
    let a_ddot = -cmul::<B>(g_.k_x, ev_dot)
        - cmul::<B>(g_.k_v, ev_ddot)
        - cmul::<B>(g_.k_i, cmul::<B>(slope, ei_rate_dot))
        + reference.snap * m;

    // b3c and its derivatives; (eqn:A1) guarded.
    let a_norm = norm::<B>(a_cmd);
    let a_floor = S::<B>::epsilon().sqrt() * m * g;
    let (b3, b3d, b3dd) = if a_norm > a_floor {
        unit_derivs::<B>(-a_cmd, -a_dot, -a_ddot)
    } else {
        degeneracy.thrust_direction_undefined = true;
        (re3, z, z)
    };

    // b2c = b3c × b1d / ‖·‖ and derivatives; b1d ∥ b3c guarded.
    let mut b1d = (reference.b1d, reference.b1d_dot, reference.b1d_ddot);
    let c_floor = S::<B>::epsilon().sqrt() * (s(1.0) + norm::<B>(reference.b1d));
    if norm::<B>(B::cross(b3, b1d.0)) <= c_floor {
        degeneracy.heading_undefined = true;
        let alt = if norm::<B>(B::cross(b3, r.act(e1))) > c_floor {
            r.act(e1)
        } else {
            r.act(e2)
        };
        b1d = (alt, z, z);
    }
    let c = B::cross(b3, b1d.0);
    let cd = B::cross(b3d, b1d.0) + B::cross(b3, b1d.1);
    let cdd = B::cross(b3dd, b1d.0) + B::cross(b3d, b1d.1) * s(2.0) + B::cross(b3, b1d.2);
    let (b2, b2d, b2dd) = unit_derivs::<B>(c, cd, cdd);
    let b1 = B::cross(b2, b3);
    let b1dot = B::cross(b2d, b3) + B::cross(b2, b3d);
    let b1ddot = B::cross(b2dd, b3) + B::cross(b2d, b3d) * s(2.0) + B::cross(b2, b3dd);

    let rc_m = B::mat3_from_cols(b1, b2, b3);
    let rct = B::mat3_transpose(rc_m);
    let omega_c = vee::<B>(rct * B::mat3_from_cols(b1dot, b2d, b3d));
    let omega_c_dot = vee::<B>(rct * B::mat3_from_cols(b1ddot, b2dd, b3dd));
    let rc = R::from_matrix(rc_m);

    let att = crate::attitude_pid::attitude_core_reference(
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
    if !is_finite::<B>(att.moment) || !thrust.is_finite() {
        return Err(ControlError::NonFinite { field: "state.r" });
    }
    Ok(PositionOutput {
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
        degeneracy,
    })
}

/// sat_σ(e_i) and sat′ for the reference law, written out from their
/// definitions rather than through the law's helpers: a broken helper must
/// not break the law and its reference alike.
fn written_out_sat<B: Backend>(e_i_pos: V3<B>, g: &PositionGains<B>) -> (V3<B>, V3<B>) {
    let s = S::<B>::lit;
    let sigma = g.sigma;
    let ei = B::vec3_to_array(e_i_pos);
    let sat_c = |y: S<B>| {
        if y > sigma {
            sigma
        } else if y < -sigma {
            -sigma
        } else {
            y
        }
    };
    let slope_c = |k: usize| match g.sat_branch[k] {
        SatBranch::Inside => s(1.0),
        SatBranch::Outside => s(0.0),
        SatBranch::Auto if ei[k].abs() <= sigma => s(1.0),
        SatBranch::Auto => s(0.0),
    };
    (
        B::vec3(sat_c(ei[0]), sat_c(ei[1]), sat_c(ei[2])),
        B::vec3(slope_c(0), slope_c(1), slope_c(2)),
    )
}

/// The anti-windup clamp for the reference law, written out likewise: a
/// component held at ±σ stops growing outward.
fn written_out_clamp<B: Backend>(e_i_pos: V3<B>, rate: V3<B>, sigma: S<B>) -> V3<B> {
    let zero = S::<B>::lit(0.0);
    let (ei, r) = (B::vec3_to_array(e_i_pos), B::vec3_to_array(rate));
    let c = |k: usize| {
        let outward = (ei[k] >= sigma && r[k] > zero) || (ei[k] <= -sigma && r[k] < zero);
        if outward { zero } else { r[k] }
    };
    B::vec3(c(0), c(1), c(2))
}

/// The reference law's inputs, all checked up front: the first that is not
/// finite, named.
fn check_inputs<B: Backend, R: Rotation<B>>(
    state: &VehicleState<B, R>,
    e_i_pos: V3<B>,
    e_i_att: V3<B>,
    reference: &PositionReference<B>,
    model: &AccelerationModel<B>,
) -> Result<(), ControlError> {
    for (v, field) in [
        (state.x, "state.x"),
        (state.v, "state.v"),
        (state.omega, "state.omega"),
        (e_i_pos, "e_i (position integral)"),
        (e_i_att, "e_I (attitude integral)"),
    ] {
        if !is_finite::<B>(v) {
            return Err(ControlError::NonFinite { field });
        }
    }
    if let Some(field) = reference_field(reference) {
        return Err(ControlError::NonFiniteReference { field });
    }
    if let AccelerationModel::Measured { accel, jerk } = *model
        && !(is_finite::<B>(accel) && is_finite::<B>(jerk))
    {
        return Err(ControlError::NonFinite {
            field: "measured acceleration/jerk",
        });
    }
    Ok(())
}

/// `u/|u|` and its first two time derivatives given `u, u̇, ü`:
/// `ḃ = u̇/n − u (u·u̇)/n³`,
/// `b̈ = ü/n − (2u̇ (u·u̇) + u (u̇·u̇ + u·ü))/n³ + 3u (u·u̇)²/n⁵`:
/// the textbook form the law's projected derivatives are checked against.
fn unit_derivs<B: Backend>(u: V3<B>, ud: V3<B>, udd: V3<B>) -> (V3<B>, V3<B>, V3<B>) {
    let n = norm::<B>(u);
    let inv = S::<B>::lit(1.0) / n;
    let inv3 = inv * inv * inv;
    let uud = B::dot(u, ud);
    let b = u * inv;
    let bd = ud * inv - u * (uud * inv3);
    let bdd = udd * inv
        - (ud * (S::<B>::lit(2.0) * uud) + u * (B::dot(ud, ud) + B::dot(u, udd))) * inv3
        + u * (S::<B>::lit(3.0) * uud * uud * inv3 * inv * inv);
    (b, bd, bdd)
}
