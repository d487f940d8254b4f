//! `cargo xtask conservation [--steps N]`: the free-body invariant table of
//! final |ΔE/E| and ‖RᵀR − I‖ after 10⁵ and N (default 10⁶) steps
//! at h = 0.01, every stepper, f32 and f64.

use integrators::problems::{InvariantTrace, free_body_invariants};
use integrators::{IntegratorKind, Stepper, StepperConfig};
use lie::{Backend, GlamF32, NalgebraF64};

fn run<B: Backend>(kind: IntegratorKind, steps: usize) -> Result<InvariantTrace, String> {
    let mut st = Stepper::<B, 0>::new(kind, StepperConfig { tol: 1e-12 });
    free_body_invariants::<B, _>(&mut st, 0.01, steps, 10).map_err(|e| format!("{kind}: {e}"))
}

pub fn conservation(steps: usize) -> Result<(), String> {
    if steps < 100_000 {
        return Err(format!("--steps {steps}: must be at least 100000"));
    }
    println!(
        "Free rigid body J = diag(1,2,3), Ω0 = (0.4, −0.8, −1.1), h = 0.01; dopri at tol 1e-12 per 0.01 s call"
    );
    println!(
        "| stepper | scalar | |ΔE/E| 1e5 | ‖RᵀR−I‖ 1e5 | |ΔE/E| {steps:.0e} | ‖RᵀR−I‖ {steps:.0e} | wall s |"
    );
    println!("|---|---|---|---|---|---|---|");
    for kind in IntegratorKind::ALL {
        for scalar in ["f32", "f64"] {
            let start = std::time::Instant::now();
            let tr = match scalar {
                "f32" => run::<GlamF32>(kind, steps),
                _ => run::<NalgebraF64>(kind, steps),
            };
            let wall = start.elapsed().as_secs_f64();
            match tr {
                Ok(tr) => {
                    let i5 = tr.step.iter().position(|&s| s >= 100_000).unwrap_or(0);
                    let last = tr.step.len() - 1;
                    println!(
                        "| {kind} | {scalar} | {:.2e} | {:.2e} | {:.2e} | {:.2e} | {wall:.1} |",
                        tr.energy[i5],
                        tr.orthogonality[i5],
                        tr.energy[last],
                        tr.orthogonality[last]
                    );
                }
                Err(e) => println!("| {kind} | {scalar} | failed: {e} | | | | {wall:.1} |"),
            }
        }
    }
    Ok(())
}
