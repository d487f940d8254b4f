//! A run's summary in a few lines of text: what ran, where it ended, the
//! extremes and the cost.

use std::fmt;

use crate::Scene;
use scenarios::RunOutput;

/// A run's summary as text (`Display`): the scene's settings, the final
/// errors, the extremes over every step, the health figures, the located
/// events and the cost; what `geopid run` prints, for any front end that
/// wants the same lines.
///
/// ```
/// let mut scene = scenes::builtin::paper_flip();
/// scene.duration = 0.5;
/// let out = scenes::run(&scene, Default::default())?;
/// let text = scenes::RunReport::new(&scene, &out).to_string();
/// assert!(text.starts_with("paper-flip — 0.5 s with"));
/// assert!(text.contains("final: Ψ = "));
/// # Ok::<(), scenes::Error>(())
/// ```
pub struct RunReport<'a> {
    scene: &'a Scene,
    out: &'a RunOutput,
}

impl<'a> RunReport<'a> {
    /// The summary of `out`, a run of `scene`.
    pub fn new(scene: &'a Scene, out: &'a RunOutput) -> Self {
        Self { scene, out }
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
        let control = scene.control.describe();
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
            out.max_orthogonality_error, out.psi_range.min, out.psi_range.max
        )?;
        if !out.event_times.is_empty() {
            let ev: Vec<String> = out
                .event_times
                .iter()
                .map(|e| format!("e_i{} at {:.9} s", e.component + 1, e.t))
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
