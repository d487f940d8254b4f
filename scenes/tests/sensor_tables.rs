//! `[sensors.imu]`, `[sensors.mocap]`, `[sensors.gps]`, `[sensors.baro]`:
//! a sensor's settings over the preset's, sensors of the tables alone, and
//! bad values refused at their own key.

use scenarios::MeasurementRecord;
use scenes::scene::Scene;

fn scene(sensors: &str) -> Result<Scene, scenes::SceneError> {
    let text = format!(
        "format = 1\nname = \"sensing\"\nduration = 0.5\n\
         [control]\ntiming = \"sampled\"\nrate = 100.0\n{sensors}\n"
    );
    Scene::from_toml(&text, "sensing.toml")
}

#[test]
fn a_table_overrides_only_the_keys_it_gives() {
    let s = scene(
        "[sensors]\npreset = \"rotorpy\"\nnoise_scale = 2.0\n\
         [sensors.mocap]\nlatency = 0.02\n\
         [sensors.imu.accel]\nnoise_density = 0.003",
    )
    .unwrap();
    let suite = s.sensors.as_ref().unwrap().suite().unwrap();
    let rotorpy = sensors::SensorSuite::preset("rotorpy").unwrap();
    let (m, m0) = (suite.mocap.unwrap(), rotorpy.mocap.unwrap());
    assert_eq!(m.latency, 0.02);
    assert_eq!(
        (m.rate, m.position_sigma),
        (m0.rate, 2.0 * m0.position_sigma)
    );
    let (i, i0) = (suite.imu.unwrap(), rotorpy.imu.unwrap());
    // The table's density is scaled like the preset's.
    assert_eq!(i.accel.noise_density, 2.0 * 0.003);
    assert_eq!(i.gyro.noise_density, 2.0 * i0.gyro.noise_density);
    assert_eq!(i.rate, i0.rate);
}

#[test]
fn tables_alone_give_their_sensors_and_they_fly() {
    // No preset: a noiseless 50 Hz mocap, 20 ms late, and a GPS; the mode
    // reads the mocap.
    let s = scene(
        "[sensors.mocap]\nrate = 50.0\nlatency = 0.02\n\
         [sensors.gps]\nrate = 5.0\n\
         [estimator]\nkind = \"mocap\"",
    )
    .unwrap();
    let suite = s.sensors.as_ref().unwrap().suite().unwrap();
    assert!(suite.imu.is_none() && suite.baro.is_none());
    let m = suite.mocap.unwrap();
    assert_eq!((m.rate, m.latency, m.position_sigma), (50.0, 0.02, 0.0));
    let out = scenes::run(&s, Default::default()).unwrap();
    let frames: Vec<_> = out
        .measurements
        .iter()
        .filter_map(|r| match r {
            MeasurementRecord::Mocap { t, arrival, .. } => Some((*t, *arrival)),
            _ => None,
        })
        .collect();
    // Frames k/50 s for k = 0 … 25, each arriving 20 ms later (those
    // arriving after the end included: they were captured in the run).
    assert!((24..=26).contains(&frames.len()), "{}", frames.len());
    for (k, (t, arrival)) in frames.iter().enumerate() {
        assert_eq!(*t, k as f64 / 50.0);
        assert!((arrival - t - 0.02).abs() < 1e-12);
    }
}

#[test]
fn bad_sensor_values_name_their_key_and_value() {
    let cases = [
        (
            "[sensors.imu.accel]\nnoise_density = -1.0",
            "sensors.imu.accel.noise_density",
            "-1",
        ),
        (
            "[sensors.imu]\nmounting = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, -1.0]]",
            "sensors.imu.mounting",
            "rotation",
        ),
        (
            "[sensors.imu.gyro]\nrange = 0.0",
            "sensors.imu.gyro.range",
            "0",
        ),
        (
            "[sensors.mocap]\ndropout = 1.5",
            "sensors.mocap.dropout",
            "1.5",
        ),
        (
            "[sensors.mocap.velocity_spike]\nprobability = 2.0\nmax = 1.0",
            "sensors.mocap.velocity_spike.probability",
            "2",
        ),
        ("[sensors.gps]\ndelay = nan", "sensors.gps.delay", "NaN"),
        ("[sensors.baro]\nrate = 0.0", "sensors.baro.rate", "0"),
        (
            "[sensors]\nmocap_latency = 0.01\n[sensors.mocap]\nlatency = 0.02",
            "sensors.mocap_latency",
            "give one",
        ),
        (
            "[sensors]\nnoise_scale = 1.0",
            "sensors.preset",
            "names no sensor",
        ),
        // Longer than the 0.5 s run: nothing would arrive.
        (
            "[sensors]\npreset = \"rotorpy\"\nmocap_latency = 5.0",
            "sensors.mocap_latency",
            "5 s is not shorter than the run",
        ),
        (
            "[sensors.gps]\ndelay = 0.5",
            "sensors.gps.delay",
            "0.5 s is not shorter",
        ),
        // A misspelt key: the reader's error, at its line.
        (
            "[sensors.imu]\nrat = 100.0",
            "",
            "sensing.toml:8:1: unknown field `rat`",
        ),
    ];
    for (text, key, says) in cases {
        let e = scene(text).unwrap_err();
        assert!(
            e.key.as_deref().unwrap_or("").starts_with(key) && e.to_string().contains(says),
            "{text}: {e}"
        );
    }
}
