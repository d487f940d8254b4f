//! A run's summary in a few lines of text: what ran, where it ended, the
//! extremes and the cost.

use std::fmt;

use crate::scene::Timing;
use crate::{RunOutput, Scene};

/// [`RunOutput::report`]: the summary `cargo xtask run` prints, for any
/// front end that wants the same lines.
pub struct RunReport<'a> {
    scene: &'a Scene,
    out: &'a RunOutput,
}

impl RunOutput {
    /// The run's summary as text (`Display`): the scene's settings, the
    /// final errors, the extremes over every step, the health figures, the
    /// located events and the cost.
    ///
    /// ```
    /// let mut scene = scenarios::builtin::paper_flip();
    /// scene.duration = 0.5;
    /// let out = scenarios::run(&scene, Default::default())?;
    /// let text = out.report(&scene).to_string();
    /// assert!(text.starts_with("paper-flip — 0.5 s with"));
    /// assert!(text.contains("final: Ψ = "));
    /// # Ok::<(), scenarios::SimError>(())
    /// ```
    pub fn report<'a>(&'a self, scene: &'a Scene) -> RunReport<'a> {
        RunReport { scene, out: self }
    }
}

impl fmt::Display for RunReport<'_> {
    fn fmt(&self, w: &mut fmt::Formatter<'_>) -> fmt::Result {
        let (scene, out) = (self.scene, self.out);
        let (l, ig) = (&out.last, &scene.integrator);
        let tol = if ig.kind == "dopri" {
            format!(", tol {}", ig.tol)
        } else {
            String::new()
        };
        let control = match scene.control.timing {
            Timing::Continuous => "continuous".to_string(),
            Timing::Sampled => format!("sampled {} Hz", scene.control.rate),
        };
        writeln!(
            w,
            "{} — {} s with {} (dt {}{tol}), {:?}/{:?}, {control} control",
            scene.name, scene.duration, ig.kind, ig.dt, scene.scalar, scene.backend,
        )?;
        let round = |v: [f64; 3]| v.map(|c| (c * 1e4).round() / 1e4);
        writeln!(
            w,
            "  final: Ψ = {:.3e}, ‖e_x‖ = {:.3e} m, |Ω| = {:.3e} rad/s, e_I = {:?}, e_i = {:?}",
            l.psi,
            l.ex,
            (l.omega.iter().map(|c| c * c).sum::<f64>()).sqrt(),
            round(l.e_att),
            round(l.e_pos),
        )?;
        writeln!(
            w,
            "  max over every step: thrust {:.3} N, rotor thrust {:.3} N; {} switches, {} located sat′ events",
            out.max_thrust,
            out.max_rotor,
            out.switches.len(),
            out.events
        )?;
        writeln!(
            w,
            "  health over every step: max ‖RᵀR − I‖ = {:.2e}, Ψ in [{:.2e}, {:.3}]",
            out.max_orthogonality_error, out.psi_range.0, out.psi_range.1
        )?;
        if !out.event_times.is_empty() {
            let ev: Vec<String> = out
                .event_times
                .iter()
                .map(|(t, k)| format!("e_i{} at {t:.9} s", k + 1))
                .collect();
            writeln!(w, "  sat′ events: {}", ev.join(", "))?;
        }
        writeln!(
            w,
            "  {} steps, {} evaluations, wall {:.3} s, {:.0} steps/s",
            out.steps,
            out.evaluations,
            out.wall,
            out.steps as f64 / out.wall.max(1e-9)
        )
    }
}
