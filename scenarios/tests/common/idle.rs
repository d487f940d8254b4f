//! A flight mode with no control law, for tests of the loop around modes.

use controllers::{ControlError, Mode, ModeOutput, RotorSpeeds, VehicleState};
use lie::{NalgebraF64, S, So3Mat};

type B = NalgebraF64;

/// Commands no thrust and no moment and reports a fixed `Ψ`; with a speed
/// sequence, commands those rotor speeds instead, each held from its time
/// on (open loop: a recorded sequence replayed, or a held step).
pub struct Idle {
    /// The `Ψ` every command reports.
    pub psi: f64,
    /// `(from time, one speed per rotor)`, by time; empty: a wrench mode.
    pub speeds: Vec<(f64, Vec<f64>)>,
}

impl Mode<B> for Idle {
    fn name(&self) -> &'static str {
        "idle"
    }
    fn command(
        &self,
        t: S<B>,
        state: &VehicleState<B, So3Mat<B>>,
        _integrals: &[S<B>],
        _rates: &mut [S<B>],
    ) -> Result<ModeOutput<B>, ControlError> {
        let z = B::vec3(0.0, 0.0, 0.0);
        let k = self
            .speeds
            .partition_point(|(tk, _)| *tk <= t)
            .saturating_sub(1);
        Ok(ModeOutput {
            thrust: 0.0,
            moment: z,
            desired: state.r,
            desired_omega: z,
            psi: self.psi,
            rotor_speeds: self.speeds.get(k).and_then(|(_, w)| RotorSpeeds::new(w)),
        })
    }
}
