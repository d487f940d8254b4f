//! One update of each control law on the dual scalar: its real part is the
//! `f64` update bit for bit, and its derivatives with respect to every gain
//! equal central differences of the `f64` update.
//!
//! The difference step is swept over 1e-3 … 1e-8 (relative to the gain)
//! and the best step is reported per law: truncation (`h²`) shrinks and
//! rounding (`ε/h`) grows along the sweep. Measured: the attitude law is
//! linear in its gains, so its largest step is exact to 1e-12; the
//! position law's best is 4e-8 at 1e-5. The bound, 1e-6, is what a
//! gradient must meet to drive a tuning loop as well as exact derivatives
//! would, and a wrong term in any derivative fails it by orders.

use controllers::{
    AccelerationModel, AttitudeGains, AttitudeReference, PositionGains, PositionInput,
    PositionReference, RigidBodyParams, VehicleState, attitude_control, position_control,
};
use dynamics::paper::{GRAVITY, INERTIA, MASS};
use lie::{Backend, Dual, NalgebraDual, NalgebraF64, Real, S, So3Mat, V3};

/// The position gains (k_x, k_v, k_i per axis, c1, σ) then the attitude
/// gains the position law's moment uses (k_R, k_Ω, k_I per axis, c2).
const NP: usize = 21;
/// The attitude gains alone.
const NA: usize = 10;

fn v<B: Backend>(a: [f64; 3]) -> V3<B> {
    B::vec3(S::<B>::lit(a[0]), S::<B>::lit(a[1]), S::<B>::lit(a[2]))
}

fn gains_vector() -> [f64; NP] {
    let (p, a) = (
        controllers::paper::POSITION_GAINS,
        controllers::paper::ATTITUDE_GAINS,
    );
    // Per-axis gains made unequal so that each axis's derivative is its own.
    let axes = |k: f64| [k, 1.1 * k, 0.9 * k];
    let mut g = Vec::new();
    for k in [p.k_x, p.k_v, p.k_i, a.k_r, a.k_omega, a.k_i].map(axes) {
        g.extend(k);
    }
    let mut out = [0.0; NP];
    out[..9].copy_from_slice(&g[..9]);
    out[9] = p.c1;
    out[10] = p.sigma;
    out[11..20].copy_from_slice(&g[9..18]);
    out[20] = a.c2;
    out
}

fn attitude_gains<B: Backend>(g: &[S<B>]) -> AttitudeGains<B> {
    AttitudeGains {
        k_r: B::vec3(g[0], g[1], g[2]),
        k_omega: B::vec3(g[3], g[4], g[5]),
        k_i: B::vec3(g[6], g[7], g[8]),
        c2: g[9],
    }
}

/// Every output of one position update, flattened.
fn position_update<B: Backend>(g: [S<B>; NP]) -> Vec<S<B>> {
    let mut pos = PositionGains::<B>::paper();
    pos.k_x = B::vec3(g[0], g[1], g[2]);
    pos.k_v = B::vec3(g[3], g[4], g[5]);
    pos.k_i = B::vec3(g[6], g[7], g[8]);
    pos.c1 = g[9];
    pos.sigma = g[10];
    let att = attitude_gains::<B>(&g[11..]);
    let state = VehicleState {
        x: v::<B>([0.3, -0.2, 0.1]),
        v: v::<B>([0.5, 0.1, -0.3]),
        r: So3Mat::<B>::exp(v::<B>([0.2, 0.1, -0.3])),
        omega: v::<B>([0.4, -0.7, 0.2]),
    };
    let reference = PositionReference::<B>::hold(v::<B>([0.0; 3]), v::<B>([0.0, 1.0, 0.0]));
    let params = RigidBodyParams::diagonal(MASS, INERTIA, GRAVITY);
    let out = position_control(
        &params,
        &pos,
        &att,
        &PositionInput {
            state: &state,
            // x saturated (|1.4| > σ = 1): the output depends on σ there.
            e_i_pos: v::<B>([1.4, -0.3, 0.2]),
            e_i_att: v::<B>([0.05, 0.02, -0.01]),
            reference: &reference,
            model: AccelerationModel::Nominal,
        },
    )
    .expect("a regular state");
    let mut y = vec![out.thrust, out.psi];
    for w in [
        out.moment,
        out.omega_c,
        out.omega_c_dot,
        out.e_i_pos_rate,
        out.e_i_att_rate,
    ] {
        y.extend(B::vec3_to_array(w));
    }
    y
}

/// Every output of one attitude update, flattened.
fn attitude_update<B: Backend>(g: [S<B>; NA]) -> Vec<S<B>> {
    let params = RigidBodyParams::diagonal(MASS, INERTIA, GRAVITY);
    let reference = AttitudeReference {
        rd: So3Mat::<B>::exp(v::<B>([0.9, -0.4, 1.7])),
        omega_d: v::<B>([0.1, 0.2, -0.3]),
        omega_d_dot: v::<B>([0.0, -0.5, 0.4]),
    };
    let out = attitude_control(
        &params,
        &attitude_gains::<B>(&g),
        So3Mat::<B>::exp(v::<B>([0.2, 0.1, -0.3])),
        v::<B>([0.4, -0.7, 0.2]),
        v::<B>([0.05, 0.02, -0.01]),
        &reference,
    )
    .expect("a regular state");
    let mut y = vec![out.psi];
    for w in [out.moment, out.e_r, out.e_omega, out.e_i_rate] {
        y.extend(B::vec3_to_array(w));
    }
    y
}

/// Checks `f` on duals against `f` on f64 (bits) and central differences
/// (best step of the sweep); returns the worst relative error and its step.
fn check<const N: usize>(
    name: &str,
    g: [f64; N],
    fd: impl Fn([Dual<N>; N]) -> Vec<Dual<N>>,
    ff: impl Fn([f64; N]) -> Vec<f64>,
) {
    let dual = fd(core::array::from_fn(|i| Dual::variable(g[i], i)));
    let plain = ff(g);
    for (k, (d, p)) in dual.iter().zip(&plain).enumerate() {
        assert_eq!(
            d.re.to_bits(),
            p.to_bits(),
            "{name}: output {k}'s real part"
        );
    }
    let steps = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8];
    let mut best = (f64::INFINITY, 0.0);
    for h in steps {
        let mut worst = 0.0f64;
        for i in 0..N {
            let dh = h * g[i].abs().max(1.0);
            let at = |s: f64| {
                let mut x = g;
                x[i] += s * dh;
                ff(x)
            };
            let (up, down) = (at(1.0), at(-1.0));
            for k in 0..plain.len() {
                let diff = (up[k] - down[k]) / (2.0 * dh);
                let exact = dual[k].eps[i];
                // An output that does not depend on a gain has an exact
                // zero derivative, and its difference is exactly zero too.
                let rel = (exact - diff).abs() / exact.abs().max(1e-8);
                worst = worst.max(rel);
            }
        }
        if worst < best.0 {
            best = (worst, h);
        }
    }
    println!(
        "{name}: worst relative error {:.1e} at step {:.0e}",
        best.0, best.1
    );
    assert!(
        best.0 < 1e-6,
        "{name}: dual vs central differences {:e}",
        best.0
    );
}

#[test]
fn position_update_gradient_wrt_every_gain() {
    check(
        "position update",
        gains_vector(),
        position_update::<NalgebraDual<NP>>,
        position_update::<NalgebraF64>,
    );
}

#[test]
fn attitude_update_gradient_wrt_every_gain() {
    let g: [f64; NA] = core::array::from_fn(|i| gains_vector()[11 + i]);
    check(
        "attitude update",
        g,
        attitude_update::<NalgebraDual<NA>>,
        attitude_update::<NalgebraF64>,
    );
}

/// An output that does not depend on a seeded gain gets an exact zero,
/// not rounding noise: the thrust `f = −A·R e3` reads the position gains
/// only, so its derivatives along the eleven attitude gains must be 0.
#[test]
fn unused_gain_has_exact_zero_derivative() {
    let g = gains_vector();
    let dual =
        position_update::<NalgebraDual<NP>>(core::array::from_fn(|i| Dual::variable(g[i], i)));
    // thrust: no attitude gain enters f.
    for i in 11..NP {
        assert_eq!(dual[0].eps[i], 0.0, "thrust depends on attitude gain {i}?");
    }
}

/// The attitude loop linearised at the rotation by π about `e1` from one
/// dual evaluation of its vector field (state: the attitude as
/// `R_π Exp(δ)`, `Ω`, `e_I`; `R_d = I`, `Ω_d = 0`): its one unstable
/// eigenvalue is the positive root of `J₁ s³ + k_Ω s² + (k_I − k_R) s −
/// k_I c2`, which the near-π study uses (`gain_check::lambda_plus`,
/// bisection to rounding). Agreement to 1e-9 relative is what a 9×9
/// nonsymmetric eigenproblem with a simple, well-separated root keeps of
/// an exact Jacobian; a Jacobian wrong in any entry of the moment's
/// derivative moves the root at first order.
#[test]
fn linearisation_at_pi_has_the_closed_form_unstable_root() {
    type B = NalgebraDual<9>;
    let seed = |i: usize| Dual::<9>::variable(0.0, i);
    let delta = B::vec3(seed(0), seed(1), seed(2));
    let omega = B::vec3(seed(3), seed(4), seed(5));
    let e_i = B::vec3(seed(6), seed(7), seed(8));
    let l = S::<B>::lit;
    let r_pi = So3Mat::<B>::exp(B::vec3(l(std::f64::consts::PI), l(0.0), l(0.0)));
    let r =
        So3Mat::<B>::from_matrix_unchecked(r_pi.as_matrix() * So3Mat::<B>::exp(delta).as_matrix());
    let params = RigidBodyParams::<B>::diagonal(MASS, INERTIA, GRAVITY);
    let gains = AttitudeGains::<B>::paper();
    let reference = AttitudeReference {
        rd: So3Mat::<B>::identity(),
        omega_d: B::vec3(l(0.0), l(0.0), l(0.0)),
        omega_d_dot: B::vec3(l(0.0), l(0.0), l(0.0)),
    };
    let out = attitude_control(&params, &gains, r, omega, e_i, &reference).unwrap();
    // δ̇ = J_r(δ)⁻¹ Ω, J Ω̇ = M − Ω × JΩ, ė_I = e_Ω + c2 e_R.
    let j = params.inertia;
    let delta_dot = lie::so3::right_jacobian_inv::<B>(delta) * omega;
    let omega_dot = lie::ops::inverse::<B>(j).unwrap() * (out.moment - omega.cross(&(j * omega)));
    let rows: Vec<Dual<9>> = [delta_dot, omega_dot, out.e_i_rate]
        .iter()
        .flat_map(|v| v.iter().copied())
        .collect();
    let a = nalgebra::SMatrix::<f64, 9, 9>::from_fn(|i, k| rows[i].eps[k]);
    let unstable = a
        .complex_eigenvalues()
        .iter()
        .map(|z| z.re)
        .fold(f64::NEG_INFINITY, f64::max);
    let g = controllers::paper::ATTITUDE_GAINS;
    let closed = controllers::gain_check::lambda_plus(INERTIA[0], g.k_r, g.k_omega, g.k_i, g.c2);
    println!("unstable eigenvalue at π: dual Jacobian {unstable:.15}, closed form {closed:.15}");
    assert!(
        (unstable - closed).abs() < 1e-9 * closed,
        "{unstable} vs {closed}"
    );
}
