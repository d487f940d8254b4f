//! The C ABI computes what the library's laws compute (bit for bit, from
//! inputs built here column by column, so a row/column mix-up in the
//! conversions shows), converts z-up frames as the physics says, and turns
//! every bad input into its status.

use controllers::{
    AccelerationModel, AttitudeGains, AttitudeReference, PositionGains, PositionInput,
    PositionReference, RigidBodyParams, VehicleState, attitude_control, position_control,
};
use geopid_control::*;
use glam::{Mat3, Vec3};
use lie::{GlamF32, So3Mat};

type B = GlamF32;

/// A deterministic generator of inputs in [−1, 1).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f32 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
    }
    fn v(&mut self, scale: f32) -> [f32; 3] {
        [
            self.next() * scale,
            self.next() * scale,
            self.next() * scale,
        ]
    }
    fn rotation(&mut self) -> Mat3 {
        let axis = Vec3::from_array(self.v(1.0)).normalize();
        Mat3::from_axis_angle(axis, self.next() * 3.0)
    }
}

/// Row-major rows of a glam matrix, read entry by entry (`R_ij` = row i,
/// column j), not through the crate's own conversion.
fn rows(m: Mat3) -> [[f32; 3]; 3] {
    let mut r = [[0.0; 3]; 3];
    for (i, row) in r.iter_mut().enumerate() {
        for (j, e) in row.iter_mut().enumerate() {
            *e = m.col(j)[i];
        }
    }
    r
}

#[test]
fn both_updates_equal_the_library_laws_to_the_bit() {
    let mut g = Lcg(7);
    let (vehicle, pg, ag) = (
        gpc_paper_vehicle(),
        gpc_paper_position_gains(),
        gpc_paper_attitude_gains(),
    );
    let params = RigidBodyParams::<B>::diagonal(0.755, [0.43e-2, 0.43e-2, 1.02e-2], 9.81);
    let (lib_pg, lib_ag) = (PositionGains::<B>::paper(), AttitudeGains::<B>::paper());
    for _ in 0..500 {
        let (r, rd) = (g.rotation(), g.rotation());
        let state = GpcState {
            x: g.v(2.0),
            v: g.v(3.0),
            r: rows(r),
            omega: g.v(5.0),
        };
        let integrals = GpcIntegrals {
            e_i_att: g.v(0.5),
            e_i_pos: g.v(1.5),
        };
        let mut pref = GpcPositionReference::default();
        for f in [
            &mut pref.x,
            &mut pref.v,
            &mut pref.a,
            &mut pref.jerk,
            &mut pref.snap,
            &mut pref.b1d_dot,
            &mut pref.b1d_ddot,
        ] {
            *f = g.v(1.0);
        }
        pref.b1d = [1.0, g.next() * 0.3, 0.0];
        let aref = GpcAttitudeReference {
            rd: rows(rd),
            omega_d: g.v(2.0),
            omega_d_dot: g.v(4.0),
        };

        let mut out = GpcPositionOutput::default();
        let st = gpc_position_update(
            Some(&vehicle),
            Some(&pg),
            Some(&ag),
            Some(&state),
            Some(&integrals),
            Some(&pref),
            Some(&mut out),
        );
        assert_eq!(st, GpcStatus::Ok);
        let v = |a: [f32; 3]| Vec3::from_array(a);
        let lib_state = VehicleState::<B, So3Mat<B>> {
            x: v(state.x),
            v: v(state.v),
            r: So3Mat::from_matrix_unchecked(r),
            omega: v(state.omega),
        };
        let lib_ref = PositionReference::<B> {
            x: v(pref.x),
            v: v(pref.v),
            a: v(pref.a),
            jerk: v(pref.jerk),
            snap: v(pref.snap),
            b1d: v(pref.b1d),
            b1d_dot: v(pref.b1d_dot),
            b1d_ddot: v(pref.b1d_ddot),
        };
        let input = PositionInput {
            state: &lib_state,
            e_i_pos: v(integrals.e_i_pos),
            e_i_att: v(integrals.e_i_att),
            reference: &lib_ref,
            model: AccelerationModel::Nominal,
        };
        let lib = position_control(&params, &lib_pg, &lib_ag, &input).expect("finite inputs");
        assert_eq!(out.thrust.to_bits(), lib.thrust.to_bits());
        assert_eq!(out.moment, lib.moment.to_array());
        assert_eq!(out.rc, rows(lib.rc.as_matrix()));
        assert_eq!(
            (out.omega_c, out.omega_c_dot),
            (lib.omega_c.to_array(), lib.omega_c_dot.to_array())
        );
        assert_eq!(
            (out.e_i_pos_rate, out.e_i_att_rate),
            (lib.e_i_pos_rate.to_array(), lib.e_i_att_rate.to_array())
        );
        assert_eq!(out.psi.to_bits(), lib.psi.to_bits());

        let mut aout = GpcAttitudeOutput::default();
        let st = gpc_attitude_update(
            Some(&vehicle),
            Some(&ag),
            Some(&state),
            Some(&integrals),
            Some(&aref),
            Some(&mut aout),
        );
        assert_eq!(st, GpcStatus::Ok);
        let lib_aref = AttitudeReference::<B, So3Mat<B>> {
            rd: So3Mat::from_matrix_unchecked(rd),
            omega_d: v(aref.omega_d),
            omega_d_dot: v(aref.omega_d_dot),
        };
        let lib = attitude_control(
            &params,
            &lib_ag,
            lib_state.r,
            lib_state.omega,
            v(integrals.e_i_att),
            &lib_aref,
        )
        .expect("finite inputs");
        assert_eq!(aout.moment, lib.moment.to_array());
        assert_eq!(aout.e_i_rate, lib.e_i_rate.to_array());
        assert_eq!(aout.psi.to_bits(), lib.psi.to_bits());
    }
}

#[test]
fn z_up_frames_convert_as_the_physics_says() {
    // A yaw ψ about z-up turns the nose toward +y (left); in the z-down
    // frame left is −y, so the same attitude is a yaw −ψ about z-down.
    let psi = 0.5f32;
    let z_up = GpcState {
        x: [1.0, 2.0, 3.0],
        v: [0.1, 0.2, 0.3],
        r: rows(Mat3::from_rotation_z(psi)),
        omega: [0.0, 0.0, 0.7],
    };
    let mut ned = GpcState::default();
    assert_eq!(
        gpc_state_from_z_up(Some(&z_up), Some(&mut ned)),
        GpcStatus::Ok
    );
    assert_eq!(ned.x, [1.0, -2.0, -3.0], "3 m up is z = −3 with e3 down");
    assert_eq!(
        ned.omega,
        [0.0, 0.0, -0.7],
        "a left yaw rate about b3-up is negative about b3-down"
    );
    let want = rows(Mat3::from_rotation_z(-psi));
    for (got, want) in ned.r.as_flattened().iter().zip(want.as_flattened()) {
        assert!((got - want).abs() < 1e-7, "R: {:?} vs {want:?}", ned.r);
    }
    // The conversion is an involution: twice gives the input back exactly.
    let mut back = GpcState::default();
    assert_eq!(
        gpc_state_from_z_up(Some(&ned), Some(&mut back)),
        GpcStatus::Ok
    );
    assert_eq!(back, z_up);

    // Hovering 1 m up at the z-up target, level: the thrust carries the
    // weight and no moment is asked.
    let level = GpcState {
        x: [0.0, 0.0, 1.0],
        v: [0.0; 3],
        r: GPC_IDENTITY,
        omega: [0.0; 3],
    };
    let target = GpcPositionReference {
        x: [0.0, 0.0, 1.0],
        b1d: [1.0, 0.0, 0.0],
        ..Default::default()
    };
    let (mut s, mut r) = (GpcState::default(), GpcPositionReference::default());
    gpc_state_from_z_up(Some(&level), Some(&mut s));
    gpc_position_reference_from_z_up(Some(&target), Some(&mut r));
    let mut out = GpcPositionOutput::default();
    let st = gpc_position_update(
        Some(&gpc_paper_vehicle()),
        Some(&gpc_paper_position_gains()),
        Some(&gpc_paper_attitude_gains()),
        Some(&s),
        Some(&GpcIntegrals::default()),
        Some(&r),
        Some(&mut out),
    );
    assert_eq!(st, GpcStatus::Ok);
    assert!(
        (out.thrust - 0.755 * 9.81).abs() < 1e-5,
        "thrust {}",
        out.thrust
    );
    assert!(
        out.moment.iter().all(|m| m.abs() < 1e-6),
        "moment {:?}",
        out.moment
    );
    // A moment about b1 (roll) keeps its sign; about b2 and b3 it flips.
    let mut m = [1.0f32, 2.0, 3.0];
    // SAFETY: three floats, converted in place (the function allows it).
    let st = unsafe { gpc_vector_from_z_up(m.as_ptr(), m.as_mut_ptr()) };
    assert_eq!(st, GpcStatus::Ok);
    assert_eq!(m, [1.0, -2.0, -3.0]);
}

#[test]
fn bad_inputs_are_statuses_and_leave_the_output_alone() {
    let (v, pg, ag) = (
        gpc_paper_vehicle(),
        gpc_paper_position_gains(),
        gpc_paper_attitude_gains(),
    );
    let s = GpcState {
        r: GPC_IDENTITY,
        ..Default::default()
    };
    let (i, r) = (
        GpcIntegrals::default(),
        GpcPositionReference {
            b1d: [1.0, 0.0, 0.0],
            ..Default::default()
        },
    );
    let run = |v: &GpcVehicle, pg: &GpcPositionGains, s: &GpcState| {
        let mut out = GpcPositionOutput {
            thrust: 42.0,
            ..Default::default()
        };
        let st = gpc_position_update(
            Some(v),
            Some(pg),
            Some(&ag),
            Some(s),
            Some(&i),
            Some(&r),
            Some(&mut out),
        );
        if st != GpcStatus::Ok {
            assert_eq!(out.thrust, 42.0, "output written on {st:?}");
        }
        st
    };
    assert_eq!(run(&v, &pg, &s), GpcStatus::Ok);
    assert_eq!(
        run(&GpcVehicle { mass: 0.0, ..v }, &pg, &s),
        GpcStatus::InvalidVehicle
    );
    assert_eq!(
        run(&GpcVehicle { mass: -1.0, ..v }, &pg, &s),
        GpcStatus::InvalidVehicle
    );
    assert_eq!(
        run(
            &GpcVehicle {
                gravity: f32::NAN,
                ..v
            },
            &pg,
            &s
        ),
        GpcStatus::InvalidVehicle
    );
    assert_eq!(
        run(&v, &GpcPositionGains { sigma: -1.0, ..pg }, &s),
        GpcStatus::InvalidGains
    );
    assert_eq!(
        run(
            &v,
            &GpcPositionGains {
                k_x: [1.0, f32::INFINITY, 1.0],
                ..pg
            },
            &s
        ),
        GpcStatus::InvalidGains
    );
    let mut reflected = s;
    reflected.r[2][2] = -1.0;
    assert_eq!(
        run(&v, &pg, &reflected),
        GpcStatus::NotARotation,
        "a reflection is orthogonal but not a rotation"
    );
    let mut scaled = s;
    scaled.r[0][0] = 1.01;
    assert_eq!(run(&v, &pg, &scaled), GpcStatus::NotARotation);
    let mut drifted = s;
    drifted.r[0][0] = 1.0 + 1e-4;
    assert_eq!(
        run(&v, &pg, &drifted),
        GpcStatus::Ok,
        "estimator drift well inside the tolerance is accepted"
    );
    let mut nan = s;
    nan.omega[1] = f32::NAN;
    assert_eq!(run(&v, &pg, &nan), GpcStatus::NonFiniteState);
    let mut out = GpcPositionOutput::default();
    assert_eq!(
        gpc_position_update(
            None,
            Some(&pg),
            Some(&ag),
            Some(&s),
            Some(&i),
            Some(&r),
            Some(&mut out)
        ),
        GpcStatus::NullPointer
    );

    let mut integrals = GpcIntegrals {
        e_i_att: [1.0, 2.0, 3.0],
        e_i_pos: [0.5; 3],
    };
    let null = std::ptr::null();
    // SAFETY (this and the calls below): a valid `GpcIntegrals`, rates of
    // three floats or NULL.
    let st =
        unsafe { gpc_integrals_step(&mut integrals, [1.0f32, -1.0, 0.5].as_ptr(), null, 0.25) };
    assert_eq!(st, GpcStatus::Ok);
    assert_eq!(
        integrals,
        GpcIntegrals {
            e_i_att: [1.25, 1.75, 3.125],
            e_i_pos: [0.5; 3]
        }
    );
    let st = unsafe { gpc_integrals_step(&mut integrals, null, null, -0.1) };
    assert_eq!(st, GpcStatus::InvalidPeriod);
    let st = unsafe { gpc_integrals_step(&mut integrals, [f32::NAN; 3].as_ptr(), null, 0.1) };
    assert_eq!(st, GpcStatus::NonFiniteIntegral);
    let st = unsafe { gpc_integrals_step(std::ptr::null_mut(), null, null, 0.1) };
    assert_eq!(st, GpcStatus::NullPointer);
    assert_eq!(
        integrals.e_i_att,
        [1.25, 1.75, 3.125],
        "nothing written on an error"
    );
    for code in 0..=15 {
        // SAFETY: gpc_status_name returns a static NUL-terminated string.
        let name = unsafe { std::ffi::CStr::from_ptr(gpc_status_name(code)) }
            .to_str()
            .unwrap();
        assert!(!name.is_empty());
        assert_eq!(name == "unknown status", code == 15, "code {code}: {name}");
    }
}
