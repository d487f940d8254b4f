//! A run's summary in a few lines of text: what ran, where it ended, the
//! extremes and the cost.

use std::fmt;

use crate::Scene;
use scenarios::{RunOutput, Termination};

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
        if !out.switches.is_empty() {
            let sw: Vec<String> = out
                .switches
                .iter()
                .map(|s| {
                    let name = out.mode_names.get(s.to).copied().unwrap_or("?");
                    format!("{name} at {:.3} s", s.t)
                })
                .collect();
            writeln!(w, "  switches: {}", sw.join(", "))?;
        }
        contacts(w, out)?;
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

/// The ground contacts' line (touchdowns, lift-offs, the fastest
/// touchdown) and how the run ended when it did not run to its duration.
fn contacts(w: &mut fmt::Formatter<'_>, out: &RunOutput) -> fmt::Result {
    if !out.contacts.is_empty() {
        let downs = out.contacts.iter().filter(|c| c.pushing).count();
        write!(
            w,
            "  ground: {downs} touchdowns, {} lift-offs",
            out.contacts.len() - downs
        )?;
        let fastest = out
            .contacts
            .iter()
            .filter(|c| c.pushing)
            .max_by(|a, b| a.normal_speed.total_cmp(&b.normal_speed));
        match fastest {
            Some(c) => writeln!(
                w,
                "; fastest touchdown {:.3} m/s (foot {} at {:.6} s)",
                c.normal_speed, c.point, c.t
            )?,
            None => writeln!(w)?,
        }
    }
    match out.termination {
        Termination::Crashed { t, point, speed } => writeln!(
            w,
            "  crashed: foot {point} touched down at {speed:.3} m/s at {t:.6} s"
        ),
        Termination::StoppedBy { t } => writeln!(w, "  stopped by its condition at {t:.6} s"),
        Termination::Diverged { what, t } => writeln!(w, "  diverged at {t:.6} s: {what:?}"),
        _ => Ok(()),
    }
}
