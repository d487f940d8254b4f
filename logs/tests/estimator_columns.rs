//! The CSV's estimator columns: the filter's standard deviations and its
//! last NIS beside the estimate, `NaN` for an estimator that keeps none.

use scenes::scene::EstimatorKind;

fn last_row(kind: EstimatorKind) -> (Vec<String>, Vec<String>) {
    let mut scene = scenes::builtin::hover_estimated();
    scene.duration = 1.0;
    scene.estimator.as_mut().unwrap().kind = kind;
    let out = scenes::run(&scene, Default::default()).unwrap();
    let path = std::env::temp_dir().join(format!("geopid-est-cols-{}.csv", kind.name()));
    logs::write_csv(&path, &out).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    std::fs::remove_file(&path).ok();
    let mut lines = text.lines();
    let header = lines.next().unwrap().split(',').map(String::from).collect();
    let last = lines.last().unwrap().split(',').map(String::from).collect();
    (header, last)
}

#[test]
fn the_csv_holds_the_filters_sigmas_and_nis() {
    let (header, row) = last_row(EstimatorKind::Iekf);
    assert_eq!(header.len(), row.len());
    let num = |name: &str| {
        let i = header
            .iter()
            .position(|c| c == name)
            .unwrap_or_else(|| panic!("no {name}"));
        row[i].parse::<f64>().unwrap()
    };
    // The IEKF's order: position, velocity, attitude, gyro bias, accel
    // bias. After 1 s of 1 cm mocap frames at 100 Hz fused with the IMU
    // the position σ is a few mm; the attitude σ is below one frame's
    // 4.5 mrad.
    assert!(
        num("est_sigma1") > 1e-4 && num("est_sigma1") < 5e-3,
        "{row:?}"
    );
    assert!(num("est_sigma7") < 4.5e-3, "{row:?}");
    assert!(num("est_sigma15").is_finite() && num("est_nis").is_finite());
    // The last frame's innovation: 1 cm frames against an estimate of a
    // few mm; the attitude's against 4.5 mrad frames.
    assert!(
        num("est_innov1").abs() < 0.05 && num("est_innov6").abs() < 0.03,
        "{row:?}"
    );
    let (header, row) = last_row(EstimatorKind::Mocap);
    let i = header.iter().position(|c| c == "est_sigma1").unwrap();
    assert_eq!(row[i], "NaN", "the mocap estimator keeps no covariance");
}
