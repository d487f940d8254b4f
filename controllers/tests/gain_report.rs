//! The gain checker on the paper's gains, as a test without the libtest
//! harness so that its report is part of every `cargo test` output (a
//! failed assertion still fails the run).

use controllers::*;
use dynamics::paper;
use lie::NalgebraF64 as B;

/// The gain checker on the paper's gains. Expected values computed
/// independently (numpy, eigvalsh/roots) for the bounds below:
/// B1 = 8 N (hover needs m g = 7.41 N), B2 = 0.1 (‖2J − tr J I‖ = 0.0102
/// times ‖Ω_d‖ ≈ 10 rad/s), δ_x = ‖Δ_x‖∞ = 1 N, ψ1 = 0.05, e_xmax = 1 m.
fn main() {
    testkit::run(&[("paper_gains_report", paper_gains_report)]);
}

/// The paper's gains against its conditions: which hold, by how much.
fn paper_gains_report() {
    let report = check_gains(
        &RigidBodyParams::<B>::diagonal(paper::MASS, paper::INERTIA, paper::GRAVITY),
        &PositionGains::<B>::paper(),
        &AttitudeGains::<B>::paper(),
        &GainBounds {
            b1: 8.0,
            b2: 0.1,
            delta_x: 1.0,
            psi1: 0.05,
            e_x_max: 1.0,
        },
    );
    println!("gain checker, paper's gains (controllers/tests/gain_report.rs):\n{report}");
    let [c2, kis, c1, w] = report.conditions;
    assert!(c2.holds && (c2.bound - 4.529544986617253).abs() < 1e-9);
    assert!(kis.holds && (kis.margin - 0.28).abs() < 1e-12);
    // The paper's c1 = 3.6 exceeds the bound of (eqn:c1b), 1.785: its
    // numerical example does not satisfy this sufficient condition.
    assert!(!c1.holds && (c1.bound - 1.7850694965293705).abs() < 1e-9);
    // …and with it W1 is indefinite (λm(W1) = −2.70), so (eqn:kRkWb)
    // cannot be met either.
    assert!(!w.holds && (w.value - 0.07772608597468376).abs() < 1e-9 && w.bound.is_infinite());
    assert!((report.attitude_time_constant - 14.636082150918588).abs() < 1e-6);
    assert!((report.position_time_constant - 2.7435192162213027).abs() < 1e-6);
}
