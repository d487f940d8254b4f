//! A scene's run with nothing kept: the loop alone, for the benches.

use scenarios::RunOptions;
use scenes::{Scene, run};
use std::hint::black_box;

/// The loop alone: no samples, and no per-step extrema (one controller
/// evaluation per step, which the hand-written twins do not do either).
pub fn quiet(s: &Scene) {
    let out = run(
        s,
        RunOptions {
            record: false,
            extrema: false,
            ..Default::default()
        },
    )
    .expect("run");
    black_box(out.last.psi);
}
