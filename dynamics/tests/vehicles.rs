//! Vehicles: allocation and its inverse, limits, loads, the stand's gravity
//! moment, parameter validation.
//!
//! Most tests run on nalgebra-f64: they check formulas (determinants,
//! clamping, the stand's moment, error naming) whose code is the same
//! generic source on every pair. What a pair could change, rounding, is
//! checked by `allocation_and_hover_on_every_pair` (all four) and
//! `f32_glam_matches_f64` (the far corner, glam-f32 against nalgebra-f64).
#![allow(clippy::needless_range_loop)] // index notation mirrors the formulas

use dynamics::{
    AttitudeStand, DynamicsError, FreeRigidBody, Quadrotor, RigidBodyState, RotorLimits, Vehicle,
    Wrench, loads,
};
use lie::{Backend, GlamF32, NalgebraF64, Real, Rotation, S, So3Mat, ops};

type B = NalgebraF64;

fn det4(m: [[f64; 4]; 4]) -> f64 {
    // Laplace along the first row.
    let minor = |c: usize| {
        let mut s = [[0.0; 3]; 3];
        for i in 0..3 {
            let mut k = 0;
            for j in 0..4 {
                if j != c {
                    s[i][k] = m[i + 1][j];
                    k += 1;
                }
            }
        }
        s[0][0] * (s[1][1] * s[2][2] - s[1][2] * s[2][1])
            - s[0][1] * (s[1][0] * s[2][2] - s[1][2] * s[2][0])
            + s[0][2] * (s[1][0] * s[2][1] - s[1][1] * s[2][0])
    };
    (0..4)
        .map(|c| if c % 2 == 0 { 1.0 } else { -1.0 } * m[0][c] * minor(c))
        .sum()
}

#[test]
fn allocation_determinant_and_inverse() {
    let q = Quadrotor::<B>::paper();
    let (d, c) = (q.arm(), q.c_tau_f());
    let det = det4(q.allocation());
    // det = 8 c d² (the allocation's determinant); the sign depends on row order, the size not.
    assert!((det.abs() - 8.0 * c * d * d).abs() < 1e-15, "det {det}");
    let mut rng = 0x1234_5678_u64;
    let mut next = || {
        rng ^= rng << 13;
        rng ^= rng >> 7;
        rng ^= rng << 17;
        (rng % 10_000) as f64 / 5_000.0 - 1.0
    };
    for _ in 0..1000 {
        let w = Wrench::<B> {
            thrust: 8.0 * next(),
            moment: B::vec3(next(), next(), 0.1 * next()),
        };
        let mut f = [0.0; 4];
        q.actuators_from_wrench(&w, &mut f).unwrap();
        let back = q.wrench_from_actuators(&f).unwrap();
        // Condition number of the allocation is ~ 1/c ≈ 76; 1e-13 is a few
        // hundred ulp of the largest entry.
        assert!((back.thrust - w.thrust).abs() < 1e-13);
        assert!(ops::norm::<B>(back.moment - w.moment) < 1e-13);
    }
}

/// The paper's rotor convention by value, not through the inverse the
/// code also computes. Rotor i sits at `d (cos((i−1)π/2), sin((i−1)π/2), 0)`
/// in the body frame (rotor 1 on b1, rotor 2 on b2), pushes along −b3 (e3
/// points down), and its drag torque about b3 is `τ_i = (−1)^i c_τf f_i`
/// (the paper's quadrotor model). The wrench the body feels from a unit
/// thrust on rotor i alone is then `r_i × (−e3) + τ_i e3`, written here
/// from those positions and a cross product; `wrench_from_actuators` must
/// give it, the allocation matrix must hold it as column i, and
/// `actuators_from_wrench` must map it back to the unit vector. Flipping
/// the spin directions (the yaw row and its inverse together) or the arm
/// layout fails here even though allocation and inverse stay consistent.
#[test]
fn rotor_positions_and_spin_directions_are_the_papers() {
    // The paper's numbers, written out (not read from `Quadrotor::paper`).
    let (d, c) = (0.169, 0.0132);
    let q = Quadrotor::<B>::paper();
    assert_eq!((q.arm(), q.c_tau_f()), (d, c));
    let a = q.allocation();
    for i in 0..4 {
        let ang = i as f64 * std::f64::consts::FRAC_PI_2;
        let r = [d * ang.cos(), d * ang.sin(), 0.0];
        let push = [0.0, 0.0, -1.0];
        let arm = [
            r[1] * push[2] - r[2] * push[1],
            r[2] * push[0] - r[0] * push[2],
            r[0] * push[1] - r[1] * push[0],
        ];
        let spin = if (i + 1) % 2 == 0 { 1.0 } else { -1.0 };
        let expected = [1.0, arm[0], arm[1], arm[2] + spin * c];
        let mut unit = [0.0; 4];
        unit[i] = 1.0;
        let w = q.wrench_from_actuators(&unit).unwrap();
        let got = [w.thrust, w.moment[0], w.moment[1], w.moment[2]];
        for k in 0..4 {
            // cos(π/2) is 6e-17, not 0: the positions carry one rounding.
            assert!(
                (got[k] - expected[k]).abs() <= 1e-16,
                "rotor {}: wrench row {k} is {}, the paper's {}",
                i + 1,
                got[k],
                expected[k]
            );
            assert!(
                (a[k][i] - expected[k]).abs() <= 1e-16,
                "allocation[{k}][{i}]"
            );
        }
        let mut back = [0.0; 4];
        q.actuators_from_wrench(&w, &mut back).unwrap();
        for k in 0..4 {
            // Condition ~1/c: a few ulp of 1 times 76.
            assert!(
                (back[k] - unit[k]).abs() < 1e-13,
                "rotor {}: {back:?}",
                i + 1
            );
        }
    }
    // The sign of yaw by itself: a positive M3 (nose right about e3 down)
    // needs the even rotors, whose drag torque is +c_τf f, to work harder.
    let mut f = [0.0; 4];
    let yaw = Wrench::<B> {
        thrust: 4.0,
        moment: B::vec3(0.0, 0.0, 0.01),
    };
    q.actuators_from_wrench(&yaw, &mut f).unwrap();
    assert!(
        f[1] > f[0] && f[3] > f[2] && f[1] == f[3] && f[0] == f[2],
        "{f:?}"
    );
}

#[test]
fn rotor_limits_clamp_each_rotor() {
    let q = Quadrotor::<B>::paper()
        .with_rotor_limits(RotorLimits { min: 0.0, max: 3.0 })
        .unwrap();
    let w = Wrench::<B> {
        thrust: 7.0,
        moment: B::vec3(0.6, -0.2, 0.05),
    };
    let mut raw = [0.0; 4];
    q.actuators_from_wrench(&w, &mut raw).unwrap();
    assert!(
        raw.iter().any(|&f| !(0.0..=3.0).contains(&f)),
        "test needs saturation: {raw:?}"
    );
    let sat = q.saturate(w);
    let mut f = [0.0; 4];
    q.actuators_from_wrench(&sat, &mut f).unwrap();
    for (fi, ri) in f.iter().zip(raw) {
        assert!(
            (*fi - ri.clamp(0.0, 3.0)).abs() < 1e-12,
            "{f:?} vs clamp of {raw:?}"
        );
    }
    // The paper's vehicle has none: saturate is the identity.
    assert_eq!(Quadrotor::<B>::paper().saturate(w), w);
    let bad = Quadrotor::<B>::paper().with_rotor_limits(RotorLimits { min: 2.0, max: 1.0 });
    assert!(bad.unwrap_err().to_string().contains("rotor_limits"));
}

#[test]
fn hover_loads_balance_and_disturbance_adds() {
    let q = Quadrotor::<B>::paper();
    let hover = Wrench::<B> {
        thrust: q.mass() * q.gravity(),
        moment: ops::zero::<B>(),
    };
    let s = RigidBodyState::<B>::at_rest();
    let l = loads(&q, 0.0, &s, &hover);
    assert!(ops::norm::<B>(l.force) < 1e-15 && ops::norm::<B>(l.moment) == 0.0);
    let d = Quadrotor::<B>::paper_disturbance();
    let qd = q.with_disturbance(d).unwrap();
    let l = loads(&qd, 0.0, &s, &hover);
    assert!(ops::norm::<B>(l.force - d.force) < 1e-15);
    assert_eq!(l.moment, d.moment);
    // Thrust acts along −R e3: rolled 90° about b1, it pushes along +e2·(…)
    let mut rolled = s;
    rolled.r = So3Mat::<B>::exp(B::vec3(std::f64::consts::FRAC_PI_2, 0.0, 0.0)).matrix();
    let l = loads(&q, 0.0, &rolled, &hover);
    let expect = B::vec3(0.0, hover.thrust, q.mass() * q.gravity());
    assert!(ops::norm::<B>(l.force - expect) < 1e-12, "{:?}", l.force);
}

#[test]
fn stand_gravity_tips_the_body_over_and_it_cannot_translate() {
    let stand = AttitudeStand::new(Quadrotor::<B>::paper(), 0.05).unwrap();
    assert!(!stand.capabilities().translates);
    let (m, g, l) = (stand.mass(), stand.gravity(), 0.05);
    for axis in [
        B::vec3(1.0, 0.0, 0.0),
        B::vec3(0.0, 1.0, 0.0),
        B::vec3(0.6, 0.8, 0.0),
    ] {
        let tilt = 0.2;
        let r = So3Mat::<B>::from_axis_angle(axis, tilt).matrix();
        let mg = stand.gravity_moment(r);
        // Inverted pendulum: the moment is along the tilt axis (it increases
        // the tilt), of size m g l sin(tilt).
        assert!(
            (mg.dot(&axis) - m * g * l * tilt.sin()).abs() < 1e-14,
            "{mg:?}"
        );
        let mut s = RigidBodyState::<B>::at_rest();
        s.r = r;
        let ld = loads(&stand, 0.0, &s, &Wrench::zero());
        assert_eq!(ld.force, ops::zero::<B>());
        assert!(ops::norm::<B>(ld.moment - mg) < 1e-15);
    }
    // Parallel-axis inertia: J + m l² diag(1, 1, 0).
    let j = stand.inertia();
    assert!((j[(0, 0)] - (0.43e-2 + m * l * l)).abs() < 1e-15);
    assert!((j[(2, 2)] - 1.02e-2).abs() < 1e-15);
    assert!(
        AttitudeStand::new(Quadrotor::<B>::paper(), -1.0)
            .unwrap_err()
            .to_string()
            .contains("height")
    );
}

#[test]
fn vehicles_are_usable_as_trait_objects() {
    let fleet: Vec<Box<dyn Vehicle<B>>> = vec![
        Box::new(Quadrotor::paper()),
        Box::new(AttitudeStand::new(Quadrotor::paper(), 0.05).unwrap()),
        Box::new(FreeRigidBody::diag123()),
    ];
    let names: Vec<&str> = fleet.iter().map(|v| v.name()).collect();
    assert_eq!(names, ["quadrotor", "attitude-stand", "free-rigid-body"]);
    let counts: Vec<usize> = fleet.iter().map(|v| v.actuator_count()).collect();
    assert_eq!(counts, [4, 4, 0]);
    let e = fleet[0].wrench_from_actuators(&[1.0, 2.0]).unwrap_err();
    assert_eq!(
        e,
        DynamicsError::ActuatorCount {
            expected: 4,
            got: 2
        }
    );
    assert!(e.to_string().contains("2 entries"));
}

#[test]
fn bad_parameters_are_named_errors() {
    let j = ops::diag::<B>(0.1, 0.1, 0.2);
    let e = Quadrotor::<B>::new(-1.0, j, 9.81, 0.2, 0.01).unwrap_err();
    assert!(e.to_string().contains("`mass` = -1"), "{e}");
    let e = Quadrotor::<B>::new(1.0, ops::diag::<B>(0.1, -0.1, 0.2), 9.81, 0.2, 0.01).unwrap_err();
    assert!(e.to_string().contains("inertia"), "{e}");
    let e = Quadrotor::<B>::new(1.0, j, 9.81, 0.2, 0.0).unwrap_err();
    assert!(e.to_string().contains("c_tau_f"), "{e}");
    let e = Quadrotor::<B>::new(1.0, j, f64::NAN, 0.2, 0.01).unwrap_err();
    assert!(e.to_string().contains("gravity"), "{e}");
    let nan = dynamics::Disturbance::<B> {
        force: B::vec3(f64::NAN, 0.0, 0.0),
        moment: ops::zero::<B>(),
    };
    let e = Quadrotor::<B>::paper().with_disturbance(nan).unwrap_err();
    assert!(e.to_string().contains("disturbance.force"), "{e}");
}

/// The same vehicle code in f32 on glam agrees with f64 on nalgebra.
#[test]
fn f32_glam_matches_f64() {
    let q32 = Quadrotor::<GlamF32>::paper();
    let q64 = Quadrotor::<B>::paper();
    let w32 = Wrench::<GlamF32> {
        thrust: 7.2,
        moment: GlamF32::vec3(0.1, -0.05, 0.01),
    };
    let w64 = Wrench::<B> {
        thrust: 7.2,
        moment: B::vec3(0.1, -0.05, 0.01),
    };
    let (mut a, mut b) = ([0.0f32; 4], [0.0f64; 4]);
    q32.actuators_from_wrench(&w32, &mut a).unwrap();
    q64.actuators_from_wrench(&w64, &mut b).unwrap();
    for (x, y) in a.iter().zip(b) {
        assert!((x.to_f64_lossless() - y).abs() < 1e-5 * (1.0 + y.abs()));
    }
    let _: S<GlamF32> = 0.0;
}

/// The hexarotor: the allocation rows reduce to the quadrotor's formula,
/// the minimum-norm inverse reproduces any wrench, is orthogonal to the
/// allocation's null space (that is what minimum norm means), and hovers
/// with six equal thrusts.
#[test]
fn hexarotor_minimum_norm_allocation() {
    use dynamics::Hexarotor;
    let h = Hexarotor::<B>::paper();
    let a = h.allocation();
    let w = Wrench::<B> {
        thrust: 7.0,
        moment: B::vec3(0.3, -0.2, 0.04),
    };
    let mut f = [0.0; 6];
    h.actuators_from_wrench(&w, &mut f).unwrap();
    let back = h.wrench_from_actuators(&f).unwrap();
    assert!((back.thrust - w.thrust).abs() < 1e-12);
    assert!(
        ops::norm::<B>(back.moment - w.moment) < 1e-12,
        "{:?}",
        back.moment
    );
    // Null-space directions of A (independent construction): alternate
    // opposite pairs; check A n = 0 first, then f ⟂ n.
    let nulls = [
        [1.0, 0.0, 0.0, 1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0, 1.0, 0.0],
    ];
    for n0 in nulls {
        // Project out the row space numerically: n = n0 − Aᵀ(AAᵀ)⁻¹A n0.
        let an: Vec<f64> = a
            .iter()
            .map(|r| (0..6).map(|k| r[k] * n0[k]).sum())
            .collect();
        let mut aat = [[0.0; 4]; 4];
        for i in 0..4 {
            for j in 0..4 {
                aat[i][j] = (0..6).map(|k| a[i][k] * a[j][k]).sum();
            }
        }
        for i in 0..4 {
            for j in 0..4 {
                if i != j {
                    assert!(
                        aat[i][j].abs() < 1e-15,
                        "AAᵀ is diagonal for the symmetric layout"
                    );
                }
            }
        }
        let n: Vec<f64> = (0..6)
            .map(|k| n0[k] - (0..4).map(|i| a[i][k] * an[i] / aat[i][i]).sum::<f64>())
            .collect();
        for r in &a {
            assert!((0..6).map(|k| r[k] * n[k]).sum::<f64>().abs() < 1e-14);
        }
        let dot: f64 = (0..6).map(|k| f[k] * n[k]).sum();
        assert!(dot.abs() < 1e-12, "not minimum norm: f·n = {dot}");
    }
    let hover = Wrench::<B> {
        thrust: h.mass() * h.gravity(),
        moment: ops::zero::<B>(),
    };
    h.actuators_from_wrench(&hover, &mut f).unwrap();
    for fk in f {
        assert!((fk - h.mass() * h.gravity() / 6.0).abs() < 1e-14);
    }
    let fleet: Vec<Box<dyn Vehicle<B>>> = vec![Box::new(h)];
    assert_eq!(fleet[0].actuator_count(), 6);
}

/// Allocation round trip and hover balance on every (backend, scalar) pair:
/// the vehicles are generic code, and this is where a backend's own
/// arithmetic (glam's SIMD-friendly layout, nalgebra's column storage)
/// could differ. Tolerance: a few ε of the pair times the O(10 N) values.
fn allocation_on<P: Backend>() {
    let q = Quadrotor::<P>::paper();
    let l = S::<P>::lit;
    let eps = <S<P> as lie::Real>::epsilon().to_f64_lossless();
    let w = Wrench::<P> {
        thrust: l(8.0),
        moment: P::vec3(l(0.1), l(-0.05), l(0.01)),
    };
    let mut f = [l(0.0); 4];
    q.actuators_from_wrench(&w, &mut f).unwrap();
    let back = q.wrench_from_actuators(&f).unwrap();
    let d = (back.thrust - w.thrust).to_f64_lossless().abs()
        + ops::norm::<P>(back.moment - w.moment).to_f64_lossless();
    assert!(d < 64.0 * eps * 10.0, "{}: round trip {d:e}", P::NAME);
    let each = q.mass() * q.gravity() / l(4.0);
    let hover = q.wrench_from_actuators(&[each; 4]).unwrap();
    let lo = loads(&q, l(0.0), &RigidBodyState::at_rest(), &hover);
    let residual = ops::norm::<P>(lo.force).to_f64_lossless();
    assert!(
        residual < 64.0 * eps * 10.0,
        "{}: hover {residual:e}",
        P::NAME
    );
}

#[test]
fn allocation_and_hover_on_every_pair() {
    allocation_on::<lie::NalgebraF64>();
    allocation_on::<lie::NalgebraF32>();
    allocation_on::<lie::GlamF64>();
    allocation_on::<GlamF32>();
}

/// The paper's frames and disturbances by value: e3 points down, so
/// gravity is `+m g e3` and thrust acts along `−R e3`; `Δ_x` adds to the
/// inertial force and `Δ_R` to the body moment with their signs, the
/// paper's numbers `Δ_x = (−0.5, 0.2, 1) N`, `Δ_R = (0.2, −0.1, −0.02) N m`.
/// With `R = Exp(θ e2)`, `R e3 = (sin θ, 0, cos θ)`.
#[test]
fn gravity_thrust_and_disturbances_have_the_papers_signs() {
    let q = Quadrotor::<B>::paper()
        .with_disturbance(Quadrotor::<B>::paper_disturbance())
        .unwrap();
    let theta: f64 = 0.4;
    let state = RigidBodyState::<B> {
        r: So3Mat::<B>::exp(B::vec3(0.0, theta, 0.0)).as_matrix(),
        x: B::vec3(0.0, 0.0, 0.0),
        v: B::vec3(0.0, 0.0, 0.0),
        omega: B::vec3(0.0, 0.0, 0.0),
    };
    let (f, m) = (7.0, [0.01, -0.02, 0.003]);
    let w = Wrench::<B> {
        thrust: f,
        moment: B::vec3(m[0], m[1], m[2]),
    };
    let l = loads(&q, 0.0, &state, &w);
    let (mass, g) = (0.755, 9.81);
    let force = [
        -f * theta.sin() - 0.5,
        0.2,
        mass * g - f * theta.cos() + 1.0,
    ];
    let moment = [m[0] + 0.2, m[1] - 0.1, m[2] - 0.02];
    for k in 0..3 {
        assert!(
            (l.force[k] - force[k]).abs() < 1e-15,
            "force {k}: {} vs {}",
            l.force[k],
            force[k]
        );
        assert!((l.moment[k] - moment[k]).abs() < 1e-15, "moment {k}");
    }
    // Hover: thrust m g at R = I balances gravity and nothing else.
    let hover = q.with_disturbance(dynamics::Disturbance {
        force: B::vec3(0.0, 0.0, 0.0),
        moment: B::vec3(0.0, 0.0, 0.0),
    });
    let l = loads(
        &hover.unwrap(),
        0.0,
        &RigidBodyState::<B>::at_rest(),
        &Wrench::<B> {
            thrust: mass * g,
            moment: B::vec3(0.0, 0.0, 0.0),
        },
    );
    assert!(ops::norm::<B>(l.force) < 1e-15);
}
