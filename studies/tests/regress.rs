//! The regression table as a test: every check of `cargo xtask regress
//! --quick` (the paper's flip against a tight reference and without event
//! location, closed forms, the sampled-control ratio, the attitude stand,
//! the free body, wind) must hold, so `cargo test` fails where the table
//! would. Each check carries its tolerance and the reason for its size.

#[test]
fn every_quick_regression_check_holds() {
    let checks = studies::regress::checks(true, &mut |_, _| {}).expect("every scene runs");
    assert!(checks.len() >= 30, "{} checks", checks.len());
    let failed: Vec<String> = checks
        .iter()
        .filter(|c| !c.ok())
        .map(|c| {
            format!(
                "{} | {}: {:e} (expected {:e}, tolerance {:e})",
                c.scene, c.metric, c.value, c.expected, c.tol
            )
        })
        .collect();
    println!(
        "{} regression checks, {} failed",
        checks.len(),
        failed.len()
    );
    assert!(failed.is_empty(), "failed checks:\n{}", failed.join("\n"));
}
