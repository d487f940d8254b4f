//! A trajectory of one's own: position mode tracking a climbing helix given
//! as a plain closure with its derivatives up to snap (and the heading
//! turning along the path), under the paper's disturbances. No scene
//! format involved; the closure is the reference.
//!
//! Run: `cargo run -p geopid --example custom_reference`

use controllers::{
    AccelerationModel, AttitudeGains, PositionGains, PositionMode, PositionReference,
    RigidBodyParams,
};
use dynamics::paper;
use dynamics::{Quadrotor, RigidBodyState};
use lie::NalgebraF64;
use scenarios::{Simulation, Until};
use scenes::reference::derivative_mismatch;

type B = NalgebraF64;

/// A helix of radius `r`, `w` rad/s, climbing at `c` m/s (e3 is down), its
/// heading b1d tangent to the circle.
fn helix(r: f64, w: f64, c: f64) -> impl Fn(f64) -> PositionReference<B> + Clone {
    move |t: f64| {
        let (s, co) = (w * t).sin_cos();
        let v = |x: f64, y: f64, z: f64| B::vec3(x, y, z);
        let (w2, w3, w4) = (w * w, w * w * w, w * w * w * w);
        PositionReference {
            x: v(r * co, r * s, -1.0 - c * t),
            v: v(-r * w * s, r * w * co, -c),
            a: v(-r * w2 * co, -r * w2 * s, 0.0),
            jerk: v(r * w3 * s, -r * w3 * co, 0.0),
            snap: v(r * w4 * co, r * w4 * s, 0.0),
            b1d: v(-s, co, 0.0),
            b1d_dot: v(-w * co, -w * s, 0.0),
            b1d_ddot: v(w2 * s, -w2 * co, 0.0),
        }
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = helix(1.5, 0.8, 0.1);
    // A wrong derivative would make the feedforward fight the feedback;
    // check them against central differences before flying.
    let m = derivative_mismatch(&path, 0.0, 20.0, 200);
    let shown: Vec<String> = m.iter().map(|e| format!("{e:.1e}")).collect();
    println!(
        "derivative check against central differences (v, a, jerk, snap, ḃ1d, b̈1d): {}",
        shown.join(" ")
    );
    if m.iter().any(|e| *e > 1e-5) {
        return Err("the helix's derivatives are inconsistent".into());
    }
    let params = RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
    let mode = PositionMode::new(
        params,
        PositionGains::paper(),
        AttitudeGains::paper(),
        AccelerationModel::Nominal,
        path.clone(),
    );
    let mut start = RigidBodyState::<B>::at_rest();
    start.x = B::vec3(1.5, 0.0, -1.0);
    let quad = Quadrotor::<B>::paper().with_disturbance(Quadrotor::<B>::paper_disturbance())?;
    let out = Simulation::<B>::builder(Box::new(quad))
        .mode(mode, Until::Never)
        .initial(start)
        .dt(1e-3)
        .duration(20.0)
        .record_every(0.01)
        .build()?
        .run(Default::default())?;
    for t in [1.0, 5.0, 10.0, 20.0] {
        let s = studies::metrics::at(&out.samples, t).ok_or("no sample")?;
        println!("t = {t:>4} s: ‖e_x‖ = {:.3e} m, Ψ = {:.3e}", s.ex, s.psi);
    }
    println!(
        "largest ‖e_x‖ over 10–20 s: {:.3e} m; {} steps in {:.1} ms",
        studies::metrics::max_ex_after(&out.samples, 10.0),
        out.steps,
        out.wall * 1e3
    );
    Ok(())
}
