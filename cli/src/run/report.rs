//! The health warnings of a run, with what to change on the command line.

use scenarios::RunOutput;

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

#[cfg(test)]
mod tests {
    use super::*;

    /// The CLI adds what to change to the library's health finding.
    #[test]
    fn health_warnings_say_what_to_change() {
        let mut s = scenes::builtin::paper_flip();
        s.integrator.kind = "euler".into();
        s.integrator.dt = 0.002;
        let out = scenes::run(&s, Default::default()).unwrap();
        assert!(matches!(
            out.health()[..],
            [scenarios::Health::OffGroup { .. }]
        ));
        let w = health_warnings(&out);
        assert!(w[0].ends_with("(rk4-projected, rkmk4, lgvi)"), "{w:?}");
    }
}
