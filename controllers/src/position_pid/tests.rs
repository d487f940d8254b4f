use super::reference::position_control_reference;
use super::*;
use dynamics::paper;
use lie::{GlamF32, NalgebraF64, So3Mat};

type B = NalgebraF64;

/// A small deterministic generator (xorshift), uniform in [−1, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
    fn v(&mut self, scale: f64) -> lie::V3<B> {
        B::vec3(
            scale * self.next(),
            scale * self.next(),
            scale * self.next(),
        )
    }
}

type Inputs = (
    VehicleState<B, So3Mat<B>>,
    V3<B>,
    V3<B>,
    PositionReference<B>,
);

fn inputs(rng: &mut Rng) -> Inputs {
    let st = VehicleState {
        x: rng.v(2.0),
        v: rng.v(2.0),
        r: So3Mat::<B>::exp(rng.v(3.0)),
        omega: rng.v(5.0),
    };
    let r = PositionReference {
        x: rng.v(1.0),
        v: rng.v(1.0),
        a: rng.v(3.0),
        jerk: rng.v(5.0),
        snap: rng.v(10.0),
        b1d: rng.v(1.0) + B::vec3(1.5, 0.0, 0.0),
        b1d_dot: rng.v(1.0),
        b1d_ddot: rng.v(1.0),
    };
    (st, rng.v(1.5), rng.v(0.5), r)
}

/// The projected formulas against the first implementation (full
/// derivative vectors through `R_cᵀṘ_c`, `R_cᵀR̈_c`), on random states
/// covering both sides of sat′, forced branches, the clamp and every
/// acceleration model. They differ by rounding only: relative 1e-12
/// on quantities of size ≤ ~10³ (Ω̇_c).
#[test]
fn projected_formulas_equal_the_full_products() {
    let mut rng = Rng(0x9e3779b97f4a7c15);
    let p = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let ag = AttitudeGains::<B>::paper();
    let mut worst = 0.0f64;
    for k in 0..2000 {
        let (st, ei, e_att, r) = inputs(&mut rng);
        let mut pg = PositionGains::<B>::paper();
        pg.clamp_integral = k % 3 == 0;
        if k % 5 == 0 {
            pg.sat_branch = [SatBranch::Inside, SatBranch::Outside, SatBranch::Auto];
        }
        let model = match k % 3 {
            0 => AccelerationModel::Nominal,
            1 => AccelerationModel::NominalWithoutEstimate,
            _ => AccelerationModel::Measured {
                accel: rng.v(3.0),
                jerk: rng.v(5.0),
            },
        };
        let a = position_control(
            &p,
            &pg,
            &ag,
            &PositionInput {
                state: &st,
                e_i_pos: ei,
                e_i_att: e_att,
                reference: &r,
                model,
            },
        )
        .unwrap();
        let b = position_control_reference(
            &p,
            &pg,
            &ag,
            &PositionInput {
                state: &st,
                e_i_pos: ei,
                e_i_att: e_att,
                reference: &r,
                model,
            },
        )
        .unwrap();
        assert_eq!(a.degeneracy, b.degeneracy);
        let d = |x: V3<B>, y: V3<B>| (x - y).norm() / (1.0 + y.norm());
        let rel = [
            (a.thrust - b.thrust).abs() / (1.0 + b.thrust.abs()),
            d(a.moment, b.moment),
            d(a.omega_c, b.omega_c),
            d(a.omega_c_dot, b.omega_c_dot),
            (a.rc.matrix() - b.rc.matrix()).norm(),
            (a.psi - b.psi).abs(),
            d(a.e_r, b.e_r),
            d(a.e_i_att_rate, b.e_i_att_rate),
            d(a.e_i_pos_rate, b.e_i_pos_rate),
        ];
        for (i, e) in rel.iter().enumerate() {
            assert!(*e < 1e-12, "case {k}, quantity {i}: {e}");
            worst = worst.max(*e);
        }
    }
    println!("projected vs full formulas, 2000 random states: worst relative {worst:.1e}");
}

/// Both fallbacks (‖A‖ → 0, b1d ∥ b3c) give the same command as the
/// first implementation.
/// The thrust-direction guard of (eqn:A1) switches where its docs put
/// it, at `‖A‖ = √ε m g`: half of that is degenerate, twice is not
/// (in the law and in its first implementation alike). `A` is set
/// through the reference acceleration, `A = m(ẍ_d − g e3)` at rest on
/// the reference with zero integrals.
#[test]
fn the_thrust_direction_guard_switches_at_root_epsilon_m_g() {
    let p = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let (pg, ag) = (PositionGains::<B>::paper(), AttitudeGains::<B>::paper());
    let z = B::vec3(0.0, 0.0, 0.0);
    let st = VehicleState {
        x: z,
        v: z,
        r: So3Mat::<B>::identity(),
        omega: z,
    };
    let floor = f64::EPSILON.sqrt() * 0.755 * 9.81;
    for (factor, degenerate) in [(0.5, true), (2.0, false)] {
        let mut r = PositionReference::<B>::hold(z, B::vec3(0.0, 1.0, 0.0));
        r.a = B::vec3(factor * floor / 0.755, 0.0, 9.81);
        let input = PositionInput {
            state: &st,
            e_i_pos: z,
            e_i_att: z,
            reference: &r,
            model: AccelerationModel::Nominal,
        };
        let a = position_control(&p, &pg, &ag, &input).unwrap();
        let b = position_control_reference(&p, &pg, &ag, &input).unwrap();
        for (name, d) in [("law", a.degeneracy), ("reference", b.degeneracy)] {
            assert_eq!(
                d.thrust_direction_undefined, degenerate,
                "{name} at ‖A‖ = {factor} √ε m g"
            );
        }
    }
}

/// The heading guard (b1d ∥ b3c) switches at `‖b3c × b1d‖ =
/// √ε (1 + ‖b1d‖)`: half of that is degenerate, twice is not, in the
/// law and its first implementation. At rest on the reference `b3c`
/// is `e3`, so `b1d = (δ, 0, 1)` puts `‖b3c × b1d‖` at `δ`.
#[test]
fn the_heading_guard_switches_at_root_epsilon_times_one_plus_b1d() {
    let p = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let (pg, ag) = (PositionGains::<B>::paper(), AttitudeGains::<B>::paper());
    let z = B::vec3(0.0, 0.0, 0.0);
    let st = VehicleState {
        x: z,
        v: z,
        r: So3Mat::<B>::identity(),
        omega: z,
    };
    for (factor, degenerate) in [(0.5, true), (2.0, false)] {
        // ‖b1d‖ = √(1 + δ²) = 1 to far below the factor's resolution.
        let delta = factor * f64::EPSILON.sqrt() * 2.0;
        let r = PositionReference::<B>::hold(z, B::vec3(delta, 0.0, 1.0));
        let input = PositionInput {
            state: &st,
            e_i_pos: z,
            e_i_att: z,
            reference: &r,
            model: AccelerationModel::Nominal,
        };
        let a = position_control(&p, &pg, &ag, &input).unwrap();
        let b = position_control_reference(&p, &pg, &ag, &input).unwrap();
        for (name, d) in [("law", a.degeneracy), ("reference", b.degeneracy)] {
            assert!(!d.thrust_direction_undefined, "{name}");
            assert_eq!(
                d.heading_undefined, degenerate,
                "{name} at δ = {factor} √ε (1 + ‖b1d‖)"
            );
        }
    }
}

#[test]
fn degenerate_cases_equal_the_first_implementation() {
    let p = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let (pg, ag) = (PositionGains::<B>::paper(), AttitudeGains::<B>::paper());
    let st = VehicleState {
        x: B::vec3(0.0, 0.0, 0.0),
        v: B::vec3(0.0, 0.0, 0.0),
        r: So3Mat::<B>::exp(B::vec3(0.1, -0.2, 0.3)),
        omega: B::vec3(0.3, 0.2, -0.1),
    };
    let z = B::vec3(0.0, 0.0, 0.0);
    // Free fall commanded: ẍ_d = g e3 makes A = 0.
    let mut fall = PositionReference::<B>::hold(z, B::vec3(1.0, 0.0, 0.0));
    fall.a = B::vec3(0.0, 0.0, 9.81);
    // b1d along the thrust axis at hover.
    let vertical = PositionReference::<B>::hold(z, B::vec3(0.0, 0.0, 1.0));
    for r in [fall, vertical] {
        let m = AccelerationModel::Nominal;
        let a = position_control(
            &p,
            &pg,
            &ag,
            &PositionInput {
                state: &st,
                e_i_pos: z,
                e_i_att: z,
                reference: &r,
                model: m,
            },
        )
        .unwrap();
        let b = position_control_reference(
            &p,
            &pg,
            &ag,
            &PositionInput {
                state: &st,
                e_i_pos: z,
                e_i_att: z,
                reference: &r,
                model: m,
            },
        )
        .unwrap();
        assert_eq!(a.degeneracy, b.degeneracy);
        assert!(a.degeneracy.thrust_direction_undefined || a.degeneracy.heading_undefined);
        assert!((a.moment - b.moment).norm() < 1e-12 * (1.0 + b.moment.norm()));
        assert!((a.omega_c_dot - b.omega_c_dot).norm() < 1e-12 * (1.0 + b.omega_c_dot.norm()));
    }
}

/// A NaN or ±∞ in any component of any input is reported naming that
/// input: the outputs-only check is safe, in the regular case and in
/// both fallbacks (where derivatives are replaced and could drop it).
#[test]
fn every_non_finite_input_is_named() {
    let p = RigidBodyParams::<GlamF32>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let (pg, ag) = (
        PositionGains::<GlamF32>::paper(),
        AttitudeGains::<GlamF32>::paper(),
    );
    let v = |x: f32, y: f32, z: f32| glam::Vec3::new(x, y, z);
    let base_state = VehicleState {
        x: v(0.2, -0.1, 0.3),
        v: v(0.1, 0.2, -0.1),
        r: So3Mat::<GlamF32>::exp(v(0.1, -0.2, 0.3)),
        omega: v(0.3, 0.2, -0.1),
    };
    let regular = PositionReference::<GlamF32>::hold(v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0));
    let mut fall = regular;
    fall.a = v(0.0, 0.0, 9.81);
    let fall_state = VehicleState {
        x: v(0.0, 0.0, 0.0),
        v: v(0.0, 0.0, 0.0),
        ..base_state
    };
    let vertical = PositionReference::<GlamF32>::hold(v(0.0, 0.0, 0.0), v(0.0, 0.0, 1.0));
    let cases = [
        ("regular", base_state, regular),
        ("free fall", fall_state, fall),
        ("b1d vertical", fall_state, vertical),
    ];
    let mut checked = 0;
    for (name, st0, r0) in cases {
        for bad in [f32::NAN, f32::INFINITY, f32::NEG_INFINITY] {
            for field in 0..13 {
                for comp in 0..3 {
                    let (mut st, mut r) = (st0, r0);
                    let (mut ei, mut e_att) = (v(0.0, 0.0, 0.0), v(0.0, 0.0, 0.0));
                    let slot: &mut glam::Vec3 = match field {
                        0 => &mut st.x,
                        1 => &mut st.v,
                        2 => &mut st.omega,
                        3 => &mut ei,
                        4 => &mut e_att,
                        5 => &mut r.x,
                        6 => &mut r.v,
                        7 => &mut r.a,
                        8 => &mut r.jerk,
                        9 => &mut r.snap,
                        10 => &mut r.b1d,
                        11 => &mut r.b1d_dot,
                        _ => &mut r.b1d_ddot,
                    };
                    slot[comp] = bad;
                    let expected = [
                        "state.x",
                        "state.v",
                        "state.omega",
                        "e_i (position integral)",
                        "e_I (attitude integral)",
                        "reference.x",
                        "reference.v",
                        "reference.a",
                        "reference.jerk",
                        "reference.snap",
                        "reference.b1d",
                        "reference.b1d_dot",
                        "reference.b1d_ddot",
                    ][field];
                    let got = position_control(
                        &p,
                        &pg,
                        &ag,
                        &PositionInput {
                            state: &st,
                            e_i_pos: ei,
                            e_i_att: e_att,
                            reference: &r,
                            model: AccelerationModel::Nominal,
                        },
                    );
                    let want = if field >= 5 {
                        ControlError::NonFiniteReference { field: expected }
                    } else {
                        ControlError::NonFinite { field: expected }
                    };
                    assert_eq!(got.err(), Some(want), "{name}: {bad} in {expected}[{comp}]");
                    checked += 1;
                }
            }
        }
    }
    assert_eq!(checked, 3 * 3 * 13 * 3);
}
