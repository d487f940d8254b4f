//! Writes the firmware test's inputs: paper-flip simulated in `f32` on glam
//! (the scene as shipped, scalar and backend changed), its state and
//! integrals every 20 ms for 4 s, with the scene's attitude reference (the
//! flip) and position reference (the recovery's hold) at each instant. Both
//! laws run on every record, whichever mode the flight was in, so the
//! attitude law sees the flip's large errors and the position law the
//! recovery's.
//!
//! Run: `cargo run -p geopid --example flight_vectors -- firmware/vectors/paper-flip-f32.bin`

use geopid_control::vectors::Record;
use geopid_control::{GpcAttitudeReference, GpcIntegrals, GpcPositionReference, GpcState};
use lie::{GlamF32, S};
use scenes::scene::{BackendKind, Scalar};
use scenes::{Registry, builtin, reference};

/// Record spacing, s: 201 records over the flight keep the image small
/// (50 KB of inputs) and the run under QEMU within seconds.
const SPACING: f64 = 0.02;

fn rows(m: glam::Mat3) -> [[f32; 3]; 3] {
    m.transpose().to_cols_array_2d()
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .ok_or("usage: flight_vectors <output.bin>")?;
    let mut scene = builtin::paper_flip();
    scene.scalar = Scalar::F32;
    scene.backend = BackendKind::Glam;
    let attitude_ref = scene.plan[0]
        .attitude
        .clone()
        .ok_or("plan[0] has no attitude")?;
    let position_ref = scene.plan[1]
        .position
        .clone()
        .ok_or("plan[1] has no position")?;
    let mut sim = Registry::new().builder::<GlamF32>(&scene)?.build()?;
    let steps = (scene.duration / SPACING).round() as usize;
    let mut bytes = Vec::new();
    for k in 0..=steps {
        let t = k as f64 * SPACING;
        if k > 0 {
            sim.advance_to(t)?;
        }
        let s = sim.state();
        let (body, e) = (s.body, s.integrals);
        let a = reference::attitude::<GlamF32>(&attitude_ref, t as S<GlamF32>);
        let p = reference::position::<GlamF32>(&position_ref, t as S<GlamF32>);
        let record = Record {
            state: GpcState {
                x: body.x.to_array(),
                v: body.v.to_array(),
                r: rows(body.r),
                omega: body.omega.to_array(),
            },
            integrals: GpcIntegrals {
                e_i_att: [e[0], e[1], e[2]],
                e_i_pos: [e[3], e[4], e[5]],
            },
            attitude: GpcAttitudeReference {
                rd: rows(a.rd.as_matrix()),
                omega_d: a.omega_d.to_array(),
                omega_d_dot: a.omega_d_dot.to_array(),
            },
            position: GpcPositionReference {
                x: p.x.to_array(),
                v: p.v.to_array(),
                a: p.a.to_array(),
                jerk: p.jerk.to_array(),
                snap: p.snap.to_array(),
                b1d: p.b1d.to_array(),
                b1d_dot: p.b1d_dot.to_array(),
                b1d_ddot: p.b1d_ddot.to_array(),
            },
        };
        bytes.extend_from_slice(&record.encode());
    }
    std::fs::write(&path, &bytes)?;
    println!("wrote {path}: {} records, {} bytes", steps + 1, bytes.len());
    Ok(())
}
