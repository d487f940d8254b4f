//! The paper's conventions pinned by value, against closed forms written
//! here (not against the inverse or twin the code also computes):
//! `Ψ = ½ tr(I − R_dᵀR)`, `e_R = ½(R_dᵀR − RᵀR_d)^∨`, `e_Ω = Ω − RᵀR_dΩ_d`
//! and the attitude law (eqn:M),
//! `M = −k_R e_R − k_Ω e_Ω − k_I e_I + (RᵀR_dΩ_d)^ J RᵀR_dΩ_d + J RᵀR_dΩ̇_d`.
//!
//! For `R = Exp(θ a)` (unit `a`) against `R_d = I`: `Ψ = 1 − cos θ`, and
//! `e_R = sin θ a`: a positive rotation about `a` is an error along `+a`,
//! and the law's restoring moment is along `−a`.

use controllers::*;
use lie::{NalgebraF64 as B, So3Mat};
use nalgebra::{Matrix3, Vector3};

type V = Vector3<f64>;
type R = So3Mat<B>;

fn gains() -> AttitudeGains<B> {
    AttitudeGains {
        k_r: V::new(0.65, 0.7, 0.8),
        k_omega: V::new(0.11, 0.12, 0.13),
        k_i: V::new(0.06, 0.05, 0.04),
        c2: 0.8,
    }
}

fn params() -> RigidBodyParams<B> {
    RigidBodyParams {
        mass: 0.755,
        inertia: Matrix3::from_diagonal(&V::new(0.43e-2, 0.43e-2, 1.02e-2)),
        gravity: 9.81,
    }
}

#[test]
fn attitude_errors_and_the_restoring_moment_have_the_papers_signs() {
    let (p, g) = (params(), gains());
    for (axis, theta) in [
        (V::new(1.0, 0.0, 0.0), 0.3),
        (V::new(0.0, 1.0, 0.0), -1.1),
        (V::new(2.0, -1.0, 2.0) / 3.0, 2.5),
    ] {
        let r = R::exp(axis * theta);
        let omega = V::new(0.4, -0.3, 0.2);
        let e_i = V::new(0.1, 0.2, -0.3);
        let reference = AttitudeReference {
            rd: R::identity(),
            omega_d: V::zeros(),
            omega_d_dot: V::zeros(),
        };
        let out = attitude_control(&p, &g, r, omega, e_i, &reference).unwrap();
        let e_r = axis * theta.sin();
        assert!(
            (out.psi - (1.0 - theta.cos())).abs() < 1e-15,
            "Ψ at θ = {theta}"
        );
        assert!(
            (out.e_r - e_r).norm() < 1e-15,
            "e_R at θ = {theta}: {}",
            out.e_r
        );
        assert!((out.e_omega - omega).norm() < 1e-15);
        let m = -g.k_r.component_mul(&e_r)
            - g.k_omega.component_mul(&omega)
            - g.k_i.component_mul(&e_i);
        assert!(
            (out.moment - m).norm() < 1e-15,
            "M at θ = {theta}: {} vs {m}",
            out.moment
        );
        // ė_I = e_Ω + c2 e_R (the attitude integral's rate).
        assert!((out.e_i_rate - (omega + e_r * 0.8)).norm() < 1e-15);
    }
}

/// A moving reference: `R = I`, `R_d = Exp(φ e3)`, `Ω_d = e1`,
/// `Ω̇_d = (0, 0.5, 0)`. Then `RᵀR_dΩ_d = (cos φ, sin φ, 0)`, `e_Ω = Ω − that`,
/// `e_R = ½(R_dᵀ − R_d)^∨ = −sin φ e3`, and (eqn:M)'s feed-forward terms
/// are `w × Jw + J R_d Ω̇_d` with `w = R_dΩ_d`.
#[test]
fn the_feed_forward_terms_follow_the_reference() {
    let (p, g) = (params(), gains());
    let phi: f64 = 0.7;
    let rd = R::exp(V::new(0.0, 0.0, phi));
    let omega = V::new(0.2, 0.1, -0.4);
    let reference = AttitudeReference {
        rd,
        omega_d: V::new(1.0, 0.0, 0.0),
        omega_d_dot: V::new(0.0, 0.5, 0.0),
    };
    let out = attitude_control(&p, &g, R::identity(), omega, V::zeros(), &reference).unwrap();
    let w = V::new(phi.cos(), phi.sin(), 0.0);
    let wd = V::new(-0.5 * phi.sin(), 0.5 * phi.cos(), 0.0);
    let e_r = V::new(0.0, 0.0, -phi.sin());
    let e_w = omega - w;
    let j = p.inertia;
    let m = -g.k_r.component_mul(&e_r) - g.k_omega.component_mul(&e_w) + w.cross(&(j * w)) + j * wd;
    assert!((out.e_r - e_r).norm() < 1e-15, "{}", out.e_r);
    assert!((out.e_omega - e_w).norm() < 1e-15, "{}", out.e_omega);
    assert!((out.psi - (1.0 - phi.cos())).abs() < 1e-15);
    assert!((out.moment - m).norm() < 1e-15, "{} vs {m}", out.moment);
}

/// The attitude mode's thrust (the position-PD projection of (eqn:f)
/// without the integral): `f = (k_x e_x + k_v e_v + m g e3 − m ẍ_d)·R e3`,
/// with every term non-zero and `R = Exp(θ e1)`, `R e3 = (0, −sin θ, cos θ)`.
#[test]
fn the_pd_thrust_projection_is_eqn_f_without_the_integral() {
    let p = params();
    let mut gains = PositionGains::<B>::paper();
    gains.k_x = V::new(12.8, 11.0, 10.0);
    gains.k_v = V::new(4.22, 4.0, 3.5);
    let theta: f64 = 0.3;
    let state = VehicleState::<B, _> {
        x: V::new(0.5, -0.4, 0.3),
        v: V::new(-0.2, 0.6, 0.1),
        r: R::exp(V::new(theta, 0.0, 0.0)),
        omega: V::zeros(),
    };
    let mut reference = PositionReference::<B>::hold(V::new(0.1, 0.2, -0.3), V::y());
    reference.v = V::new(0.05, -0.1, 0.2);
    reference.a = V::new(0.7, -0.3, 1.1);
    let ex = state.x - reference.x;
    let ev = state.v - reference.v;
    let a = gains.k_x.component_mul(&ex)
        + gains.k_v.component_mul(&ev)
        + V::new(0.0, 0.0, p.mass * p.gravity)
        - reference.a * p.mass;
    let want = a.dot(&V::new(0.0, -theta.sin(), theta.cos()));
    let got = thrust_pd_projection(&p, &gains, &state, &reference);
    assert!((got - want).abs() < 1e-14, "{got} vs {want}");
}

/// A measured acceleration or jerk that is not finite is refused by name,
/// each on its own (the other finite).
#[test]
fn a_non_finite_measured_acceleration_or_jerk_is_named() {
    let (p, ag) = (params(), gains());
    let pg = PositionGains::<B>::paper();
    let state = VehicleState {
        x: V::zeros(),
        v: V::zeros(),
        r: R::identity(),
        omega: V::zeros(),
    };
    let reference = PositionReference::<B>::hold(V::zeros(), V::y());
    let ok = V::new(0.0, 0.0, 0.1);
    let nan = V::new(f64::NAN, 0.0, 0.0);
    for (accel, jerk) in [(nan, ok), (ok, nan)] {
        let input = PositionInput {
            state: &state,
            e_i_pos: V::zeros(),
            e_i_att: V::zeros(),
            reference: &reference,
            model: AccelerationModel::Measured { accel, jerk },
        };
        let err = position_control(&p, &pg, &ag, &input).unwrap_err();
        assert_eq!(
            err,
            ControlError::NonFinite {
                field: "measured acceleration/jerk"
            }
        );
    }
}
