//! What `cargo xtask run` prints about a run: the summary and the health
//! warnings with what to change.

use scenarios::scene::Timing;
use scenarios::{RunOutput, Scene};

/// The run's health warnings ([`scenarios::RunOutput::health`]), with what to change
/// on the command line.
pub fn health_warnings(out: &RunOutput) -> Vec<String> {
    out.health()
        .iter()
        .map(|h| match h {
            scenarios::Health::OffGroup { .. } => format!(
                "{h}; use a smaller --dt or a stepper that stays on the group (rk4-projected, rkmk4, lgvi)"
            ),
            _ => h.to_string(),
        })
        .collect()
}

/// Prints the end-of-run summary.
pub fn summary(w: &mut dyn std::io::Write, scene: &Scene, out: &RunOutput) -> std::io::Result<()> {
    let l = &out.last;
    writeln!(
        w,
        "{} — {} s with {} (dt {}{}), {:?}/{:?}, {} control",
        scene.name,
        scene.duration,
        scene.integrator.kind,
        scene.integrator.dt,
        if scene.integrator.kind == "dopri" {
            format!(", tol {}", scene.integrator.tol)
        } else {
            String::new()
        },
        scene.scalar,
        scene.backend,
        match scene.control.timing {
            Timing::Continuous => "continuous".to_string(),
            Timing::Sampled => format!("sampled {} Hz", scene.control.rate),
        }
    )?;
    writeln!(
        w,
        "  final: Ψ = {:.3e}, ‖e_x‖ = {:.3e} m, |Ω| = {:.3e} rad/s, e_I = {:?}, e_i = {:?}",
        l.psi,
        l.ex,
        (l.omega.iter().map(|c| c * c).sum::<f64>()).sqrt(),
        l.e_att.map(|c| (c * 1e4).round() / 1e4),
        l.e_pos.map(|c| (c * 1e4).round() / 1e4),
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
    let sps = out.steps as f64 / out.wall.max(1e-9);
    writeln!(
        w,
        "  {} steps, {} evaluations, wall {:.3} s, {:.0} steps/s",
        out.steps, out.evaluations, out.wall, sps
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The CLI adds what to change to the library's health finding.
    #[test]
    fn health_warnings_say_what_to_change() {
        let mut s = scenarios::builtin::paper_flip();
        s.integrator.kind = "euler".into();
        s.integrator.dt = 0.002;
        let out = scenarios::run(&s, Default::default()).unwrap();
        assert!(matches!(
            out.health()[..],
            [scenarios::Health::OffGroup { .. }]
        ));
        let w = health_warnings(&out);
        assert!(w[0].ends_with("(rk4-projected, rkmk4, lgvi)"), "{w:?}");
    }
}
