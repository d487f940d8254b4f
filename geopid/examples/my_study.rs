//! A Monte Carlo study of one's own, from public items only: a hexarotor
//! in position mode released at a random attitude (uniform over SO(3)),
//! spinning at up to 3 rad/s, with its own settle criterion (hover within
//! 5 cm, level within Ψ < 10⁻³ and spinning below 0.05 rad/s, for 1 s).
//!
//! Run it with `cargo run --release -p geopid --example my_study`.

use controllers::{
    AccelerationModel, AttitudeGains, HoldPosition, PositionGains, PositionMode, PositionReference,
    RigidBodyParams,
};
use dynamics::paper;
use dynamics::{Hexarotor, RigidBodyState};
use lie::{GlamF64, Real, Rotation, So3Quat};
use scenarios::{DivergenceGuard, Simulation, Until};
use scenes::Error;
use studies::metrics::norm;
use studies::montecarlo::{Study, Summary, in_ball, shoemake};

type B = GlamF64;

/// What each sample draws: an attitude and a body rate.
struct Draw {
    q: [f64; 4],
    omega: [f64; 3],
}

fn main() -> Result<(), Error> {
    let study = Study::new(
        2026,
        1.0,
        |rng| Draw {
            q: shoemake(rng),
            omega: in_ball(rng, 3.0),
        },
        |d: &Draw| {
            let hex = Hexarotor::<B>::paper();
            let params =
                RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY);
            let hover = PositionReference::hold(B::vec3(0.0, 0.0, 0.0), B::vec3(1.0, 0.0, 0.0));
            let mode = PositionMode::new(
                params,
                PositionGains::paper(),
                AttitudeGains::paper(),
                AccelerationModel::Nominal,
                HoldPosition(hover),
            );
            let mut start = RigidBodyState::<B>::at_rest();
            let q = B::quat_from_wxyz(d.q[0], d.q[1], d.q[2], d.q[3]);
            start.r = So3Quat::<B>::from_quaternion_unchecked(q).matrix();
            start.omega = B::vec3(d.omega[0], d.omega[1], d.omega[2]);
            Ok(Simulation::<B>::builder(Box::new(hex))
                .mode(mode, Until::Never)
                .initial(start)
                .duration(40.0)
                .dt(1e-3)
                .record_every(0.05)
                // A sample that spins up past 100 rad/s or flies 50 m away
                // is not coming back: stop it there.
                .guard(DivergenceGuard {
                    omega: Some(100.0),
                    position_error: Some(50.0),
                    ..Default::default()
                }))
        },
        // Below 1 when every figure is inside its tolerance.
        |_t, body, cmd| {
            let x = norm(B::vec3_to_array(body.x));
            let w = norm(B::vec3_to_array(body.omega));
            (x / 0.05)
                .max(cmd.psi.to_f64_lossless() / 1e-3)
                .max(w / 0.05)
        },
    );
    let indices: Vec<u64> = (0..200).collect();
    let trials = study.run(&indices, None, None)?;
    let s = Summary::of(&trials);
    println!(
        "{} samples: {} converged ({:.1} %), {} out of time, {} diverged, {} failed",
        s.samples,
        s.converged,
        100.0 * s.converged_fraction,
        s.deadline,
        s.diverged,
        s.errors
    );
    let t = s.t_converge;
    println!(
        "time to settle: median {:.3} s, 95th {:.3} s, 99th {:.3} s, worst {:.3} s",
        t.median, t.p95, t.p99, t.worst
    );
    if let Some(slow) = trials
        .iter()
        .filter(|t| t.t_settled.is_some())
        .max_by(|a, b| a.t_settled.partial_cmp(&b.t_settled).expect("finite"))
    {
        let [w, x, y, z] = slow.draw.q;
        let angle = 2.0 * (x * x + y * y + z * z).sqrt().atan2(w);
        println!(
            "slowest: sample {} from {:.1}° and |Ω(0)| = {:.2} rad/s",
            slow.index,
            angle.to_degrees(),
            norm(slow.draw.omega)
        );
    }
    Ok(())
}
