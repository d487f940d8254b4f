//! Attitude controlled flight mode (Section III): the moment (eqn:aM) and
//! the integral term (eqn:eI).

use crate::{ControlError, RigidBodyParams};
use lie::ops::{cmul, is_finite_vec as is_finite};
use lie::{AttitudeErrors, Backend, Real, Rotation, S, V3};

/// Attitude gains. The paper uses scalars; here `k_R`, `k_Ω`, `k_I` are
/// diagonal (one value per body axis), as flight code often tunes yaw apart
/// from roll and pitch. [`AttitudeGains::uniform`] gives the paper's form.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct AttitudeGains<B: lie::SimdBackend> {
    /// `k_R` per body axis.
    pub k_r: V3<B>,
    /// `k_Ω` per body axis.
    pub k_omega: V3<B>,
    /// `k_I` per body axis (0 disables the integral term).
    pub k_i: V3<B>,
    /// `c2` of (eqn:eI): weight of `e_R` in the integrand.
    pub c2: S<B>,
}

impl<B: Backend> AttitudeGains<B> {
    /// Scalar gains, as in the paper.
    pub fn uniform(k_r: S<B>, k_omega: S<B>, k_i: S<B>, c2: S<B>) -> Self {
        Self {
            k_r: B::vec3(k_r, k_r, k_r),
            k_omega: B::vec3(k_omega, k_omega, k_omega),
            k_i: B::vec3(k_i, k_i, k_i),
            c2,
        }
    }
    /// The paper's gains: `k_R = 0.65, k_Ω = 0.11, k_I = 0.06, c2 = 0.8`.
    pub fn paper() -> Self {
        let s = S::<B>::lit;
        let g = crate::paper::ATTITUDE_GAINS;
        Self::uniform(s(g.k_r), s(g.k_omega), s(g.k_i), s(g.c2))
    }
}

/// The desired attitude `R_d`, angular velocity `Ω_d` and its derivative
/// `Ω̇_d` (both in the desired body frame, `Ṙ_d = R_d Ω_d^`).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct AttitudeReference<B: lie::SimdBackend, R: AttitudeErrors<B>> {
    /// `R_d`.
    pub rd: R,
    /// `Ω_d`.
    pub omega_d: V3<B>,
    /// `Ω̇_d`.
    pub omega_d_dot: V3<B>,
}

/// What the attitude law computed.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct AttitudeOutput<B: lie::SimdBackend> {
    /// The moment `M` (body frame).
    pub moment: V3<B>,
    /// `e_R`.
    pub e_r: V3<B>,
    /// `e_Ω`.
    pub e_omega: V3<B>,
    /// `Ψ(R, R_d)`.
    pub psi: S<B>,
    /// `ė_I = e_Ω + c2 e_R`, the integrand of (eqn:eI): integrate it
    /// (continuous control) or multiply by the sample period (sampled).
    pub e_i_rate: V3<B>,
}

/// The attitude law (eqn:aM):
/// `M = −k_R e_R − k_Ω e_Ω − k_I e_I + (RᵀR_dΩ_d)^ J RᵀR_dΩ_d + J RᵀR_dΩ̇_d`,
/// with `e_I` the caller-held integral of (eqn:eI). The gyroscopic term
/// `Ω × JΩ` is not cancelled, as in the paper.
///
/// A NaN or ±∞ in any input reaches `M` (no saturation or branch in this
/// law; a test injects each), so only the output is checked, and on a
/// non-finite one the inputs are checked to name the field.
#[inline]
pub fn attitude_control<B: Backend, R: Rotation<B>>(
    params: &RigidBodyParams<B>,
    gains: &AttitudeGains<B>,
    r: R,
    omega: V3<B>,
    e_i: V3<B>,
    reference: &AttitudeReference<B, R>,
) -> Result<AttitudeOutput<B>, ControlError> {
    let out = attitude_law(params, gains, r, omega, e_i, reference);
    if is_finite::<B>(out.moment) {
        return Ok(out);
    }
    if !is_finite::<B>(omega) {
        return Err(ControlError::NonFinite { field: "omega" });
    }
    if !is_finite::<B>(e_i) {
        return Err(ControlError::NonFinite {
            field: "e_i (attitude integral)",
        });
    }
    if !is_finite::<B>(reference.omega_d) || !is_finite::<B>(reference.omega_d_dot) {
        return Err(ControlError::NonFiniteReference {
            field: "reference.omega_d / omega_d_dot",
        });
    }
    Err(ControlError::NonFinite {
        field: "attitude (R or R_d)",
    })
}

/// The attitude law (eqn:aM) without input checks: what
/// [`attitude_control`] and the position law (eqn:M) compute, on any
/// backend, SIMD lanes included (`lie`'s `simd` feature: one call computes
/// the moments of four or eight vehicles). A NaN or ±∞ in an input gives a
/// NaN moment (in that lane only) instead of an error; call
/// [`attitude_control`] for the checked law.
///
/// `E = R_dᵀR` is formed once: `e_R` and `Ψ` are its skew part and trace,
/// and the desired rates seen in the body frame are `Eᵀ Ω_d`, `Eᵀ Ω̇_d`.
#[inline(always)]
pub fn attitude_law<B: lie::SimdBackend, R: AttitudeErrors<B>>(
    params: &RigidBodyParams<B>,
    gains: &AttitudeGains<B>,
    r: R,
    omega: V3<B>,
    e_i: V3<B>,
    reference: &AttitudeReference<B, R>,
) -> AttitudeOutput<B> {
    let e = r.error_rotation(reference.rd);
    let (e_r, psi) = e.errors_to_identity();
    // R^T R_d Ω_d and R^T R_d Ω̇_d: the desired rates seen in the body frame.
    let w = e.inverse_act(reference.omega_d);
    let wd = e.inverse_act(reference.omega_d_dot);
    let e_w = omega - w;
    // A principal-axes inertia (every shipped vehicle) takes 3 products
    // per J·v instead of 9, with the same values: the skipped terms are
    // exact zeros.
    let (jw, jwd) = match lie::ops::diagonal::<B>(params.inertia) {
        Some(d) => (cmul::<B>(d, w), cmul::<B>(d, wd)),
        None => inertia_products::<B>(&params.inertia, &w, &wd),
    };
    let moment =
        -cmul::<B>(gains.k_r, e_r) - cmul::<B>(gains.k_omega, e_w) - cmul::<B>(gains.k_i, e_i)
            + B::cross(w, jw)
            + jwd;
    AttitudeOutput {
        moment,
        e_r,
        e_omega: e_w,
        psi,
        e_i_rate: e_w + e_r * gains.c2,
    }
}

/// `(J w, J wd)` for an inertia with products of inertia. Cold and out of
/// line: every shipped vehicle takes the diagonal path, and with these
/// 18 products inline the compiler laid that path out as the jump target.
/// By reference: a 3×3 matrix passed by value is copied to the stack on
/// the way in, on every call.
#[cold]
#[inline(never)]
fn inertia_products<B: lie::SimdBackend>(j: &lie::M3<B>, w: &V3<B>, wd: &V3<B>) -> (V3<B>, V3<B>) {
    (B::mat3_mul_vec(*j, *w), B::mat3_mul_vec(*j, *wd))
}

/// The first implementation of [`attitude_core`] (`R_dᵀR` formed three
/// times through the generic `e_r`, `e_omega`, `psi`), kept as the
/// reference the faster one is tested against.
#[cfg(test)]
pub(crate) fn attitude_core_reference<B: Backend, R: Rotation<B>>(
    params: &RigidBodyParams<B>,
    gains: &AttitudeGains<B>,
    r: R,
    omega: V3<B>,
    e_i: V3<B>,
    reference: &AttitudeReference<B, R>,
) -> AttitudeOutput<B> {
    let (rd, omega_d, omega_d_dot) = (reference.rd, reference.omega_d, reference.omega_d_dot);
    let e_r = r.e_r(rd);
    let e_w = lie::e_omega::<B, R>(r, omega, rd, omega_d);
    let rel = r.inverse() * rd;
    let w = rel.act(omega_d);
    let wd = rel.act(omega_d_dot);
    let j = params.inertia;
    let moment =
        -cmul::<B>(gains.k_r, e_r) - cmul::<B>(gains.k_omega, e_w) - cmul::<B>(gains.k_i, e_i)
            + B::cross(w, B::mat3_mul_vec(j, w))
            + B::mat3_mul_vec(j, wd);
    AttitudeOutput {
        moment,
        e_r,
        e_omega: e_w,
        psi: r.psi(rd),
        e_i_rate: e_w + e_r * gains.c2,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use dynamics::paper;
    use lie::{GlamF32, NalgebraF64, So3Mat};

    /// A NaN or ±∞ in any component of any input is reported naming it,
    /// and the law equals the first implementation on random states.
    #[test]
    fn non_finite_inputs_are_named_and_the_law_is_unchanged() {
        type B = GlamF32;
        let p = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
        let g = AttitudeGains::<B>::paper();
        let v = |x: f32, y: f32, z: f32| glam::Vec3::new(x, y, z);
        let r0 = So3Mat::<B>::exp(v(0.1, -0.2, 0.3));
        let ref0 = AttitudeReference {
            rd: So3Mat::<B>::exp(v(-0.3, 0.1, 0.2)),
            omega_d: v(0.2, 0.1, -0.4),
            omega_d_dot: v(0.3, -0.1, 0.2),
        };
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            for field in 0..4 {
                for comp in 0..3 {
                    let (mut w, mut ei, mut rf) = (v(0.4, -0.7, 0.2), v(0.05, 0.02, -0.01), ref0);
                    let slot = match field {
                        0 => &mut w,
                        1 => &mut ei,
                        2 => &mut rf.omega_d,
                        _ => &mut rf.omega_d_dot,
                    };
                    slot[comp] = bad;
                    let expected = [
                        "omega",
                        "e_i (attitude integral)",
                        "reference.omega_d / omega_d_dot",
                        "reference.omega_d / omega_d_dot",
                    ][field];
                    let want = if field >= 2 {
                        ControlError::NonFiniteReference { field: expected }
                    } else {
                        ControlError::NonFinite { field: expected }
                    };
                    assert_eq!(
                        attitude_control(&p, &g, r0, w, ei, &rf).err(),
                        Some(want),
                        "{bad} in {expected}[{comp}]"
                    );
                }
            }
        }
        // E = R_dᵀR once against the three generic products, f64; the
        // paper's principal-axes inertia (element-wise products) and one
        // with products of inertia (the full matrix).
        type D = NalgebraF64;
        let g = AttitudeGains::<D>::paper();
        let diagonal = RigidBodyParams::<D>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
        let mut full = diagonal;
        full.inertia = lie::ops::from_elems::<D>([
            [0.43e-2, 1e-4, -2e-4],
            [1e-4, 0.43e-2, 3e-4],
            [-2e-4, 3e-4, 1.02e-2],
        ]);
        let mut worst = 0.0f64;
        for k in 0..400 {
            let p = if k % 2 == 0 { diagonal } else { full };
            let t = k as f64 * 0.37;
            let vv = |a: f64| {
                D::vec3(
                    (a * 1.3).sin() * 3.0,
                    (a * 0.7).cos() * 2.0,
                    (a * 2.1).sin(),
                )
            };
            let (r, rd) = (So3Mat::<D>::exp(vv(t)), So3Mat::<D>::exp(vv(t + 1.0)));
            let args = (vv(t + 2.0), vv(t + 3.0) * 0.1, vv(t + 4.0), vv(t + 5.0));
            let a = attitude_law(
                &p,
                &g,
                r,
                args.0,
                args.1,
                &AttitudeReference {
                    rd,
                    omega_d: args.2,
                    omega_d_dot: args.3,
                },
            );
            let b = attitude_core_reference(
                &p,
                &g,
                r,
                args.0,
                args.1,
                &AttitudeReference {
                    rd,
                    omega_d: args.2,
                    omega_d_dot: args.3,
                },
            );
            worst = worst
                .max((a.moment - b.moment).norm())
                .max((a.psi - b.psi).abs())
                .max((a.e_i_rate - b.e_i_rate).norm());
        }
        assert!(worst < 1e-13, "{worst}");
    }
}
