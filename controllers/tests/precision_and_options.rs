//! The same control laws in f32 (glam) and f64 (nalgebra), and the
//! clamped anti-windup option.

use controllers::*;
use dynamics::paper;
use lie::{GlamF32, NalgebraF64, So3Mat};

/// One position-mode evaluation at a generic state in glam-f32 against
/// nalgebra-f64: the laws are written once, so the only difference is
/// rounding. f32's ε = 1.2e-7 through a few dozen operations on O(10)
/// quantities gives a few 1e-6 relative.
#[test]
fn f32_glam_matches_f64_nalgebra() {
    let x = [0.3, -0.2, 0.1];
    let v = [0.5, 0.1, -0.3];
    let w = [0.4, -0.7, 0.2];
    let phi = [0.2, 0.1, -0.3];
    let ei = [0.1, -0.2, 0.3];
    let e_att = [0.05, 0.02, -0.01];

    let v32 = |a: [f64; 3]| glam::Vec3::new(a[0] as f32, a[1] as f32, a[2] as f32);
    let v64 = |a: [f64; 3]| nalgebra::Vector3::new(a[0], a[1], a[2]);
    let st32 = VehicleState {
        x: v32(x),
        v: v32(v),
        r: So3Mat::<GlamF32>::exp(v32(phi)),
        omega: v32(w),
    };
    let st64 = VehicleState {
        x: v64(x),
        v: v64(v),
        r: So3Mat::<NalgebraF64>::exp(v64(phi)),
        omega: v64(w),
    };
    let r32 = PositionReference::<GlamF32>::hold(v32([0.0; 3]), v32([0.0, 1.0, 0.0]));
    let r64 = PositionReference::<NalgebraF64>::hold(v64([0.0; 3]), v64([0.0, 1.0, 0.0]));
    let o32 = position_control(
        &RigidBodyParams::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        &PositionGains::paper(),
        &AttitudeGains::paper(),
        &PositionInput {
            state: &st32,
            e_i_pos: v32(ei),
            e_i_att: v32(e_att),
            reference: &r32,
            model: AccelerationModel::Nominal,
        },
    )
    .unwrap();
    let o64 = position_control(
        &RigidBodyParams::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        &PositionGains::paper(),
        &AttitudeGains::paper(),
        &PositionInput {
            state: &st64,
            e_i_pos: v64(ei),
            e_i_att: v64(e_att),
            reference: &r64,
            model: AccelerationModel::Nominal,
        },
    )
    .unwrap();
    let d = |a: glam::Vec3, b: nalgebra::Vector3<f64>| {
        ((a.x as f64 - b.x).powi(2) + (a.y as f64 - b.y).powi(2) + (a.z as f64 - b.z).powi(2))
            .sqrt()
    };
    let (df, dm, dw, dwd) = (
        (o32.thrust as f64 - o64.thrust).abs() / o64.thrust.abs(),
        d(o32.moment, o64.moment) / o64.moment.norm(),
        d(o32.omega_c, o64.omega_c) / o64.omega_c.norm(),
        d(o32.omega_c_dot, o64.omega_c_dot) / o64.omega_c_dot.norm(),
    );
    println!(
        "glam-f32 vs nalgebra-f64, relative: f {df:.1e}, M {dm:.1e}, Ω_c {dw:.1e}, Ω̇_c {dwd:.1e}"
    );
    assert!(df < 1e-5 && dm < 1e-5 && dw < 1e-5 && dwd < 1e-5);
}

#[test]
fn clamped_integral_stops_at_sigma() {
    type B = NalgebraF64;
    let mut gains = PositionGains::<B>::paper();
    gains.clamp_integral = true;
    let v = nalgebra::Vector3::new;
    // e_x pushes e_i further past +σ in x and back inside in y.
    let st = VehicleState {
        x: v(1.0, -1.0, 0.0),
        v: v(0.0, 0.0, 0.0),
        r: So3Mat::<B>::identity(),
        omega: v(0.0, 0.0, 0.0),
    };
    let reference = PositionReference::<B>::hold(v(0.0, 0.0, 0.0), v(1.0, 0.0, 0.0));
    let e_i = v(1.0, 1.0, 0.2);
    let out = position_control(
        &RigidBodyParams::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        &gains,
        &AttitudeGains::paper(),
        &PositionInput {
            state: &st,
            e_i_pos: e_i,
            e_i_att: v(0.0, 0.0, 0.0),
            reference: &reference,
            model: AccelerationModel::Nominal,
        },
    )
    .unwrap();
    assert_eq!(out.e_i_pos_rate.x, 0.0, "at +σ and pushing outward: held");
    assert!(
        (out.e_i_pos_rate.y - (-3.6)).abs() < 1e-12,
        "pushing inward: free (c1 e_x = −3.6)"
    );
    gains.clamp_integral = false;
    let free = position_control(
        &RigidBodyParams::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        &gains,
        &AttitudeGains::paper(),
        &PositionInput {
            state: &st,
            e_i_pos: e_i,
            e_i_att: v(0.0, 0.0, 0.0),
            reference: &reference,
            model: AccelerationModel::Nominal,
        },
    )
    .unwrap();
    assert!(
        (free.e_i_pos_rate.x - 3.6).abs() < 1e-12,
        "the paper's form integrates freely"
    );
}
