//! Flying on measurements: the RMS position error of a scene flown on the
//! mocap estimator, against the motion capture's latency and a scale of
//! every noise of the sensor suite, over independent noise seeds.

use scenarios::RunOptions;
use scenes::scene::{EstimatorKind, EstimatorSpec, SensorsSpec, Timing};
use scenes::{Error, Scene};

/// One cell of a sweep: a latency and a noise scale, over every seed.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub struct Cell {
    /// The motion capture's latency, s.
    pub latency: f64,
    /// The suite's noise times this.
    pub noise_scale: f64,
    /// Each seed's RMS of ‖x − x_d‖ over the recorded samples, m (`NaN`
    /// for a run that failed: it diverged).
    pub rms: Vec<f64>,
}

/// An RMS position error above this, m, is a vehicle lost (the scenes
/// here fly within a metre or two of their reference).
pub const LOST_ABOVE: f64 = 1.0;

impl Cell {
    /// Mean and sample standard deviation of the RMS values of the runs
    /// not lost, and how many were lost (failed, or RMS above
    /// [`LOST_ABOVE`]).
    pub fn stats(&self) -> (f64, f64, usize) {
        let ok: Vec<f64> = self
            .rms
            .iter()
            .copied()
            .filter(|r| r.is_finite() && *r <= LOST_ABOVE)
            .collect();
        let n = ok.len() as f64;
        let mean = ok.iter().sum::<f64>() / n;
        let var = ok.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
        (mean, var.sqrt(), self.rms.len() - ok.len())
    }
}

/// What a sweep flies: `scene` under sampled control at `control_rate`
/// with the sensor suite `preset`, the modes on the mocap estimator.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The scene.
    pub scene: Scene,
    /// The sensor suite (`sensors::SensorSuite::PRESETS`).
    pub preset: String,
    /// The control rate, Hz.
    pub control_rate: f64,
    /// The latencies, s.
    pub latencies: Vec<f64>,
    /// The noise scales.
    pub noise_scales: Vec<f64>,
    /// The seeds of each cell.
    pub seeds: Vec<u64>,
    /// The body rates from the IMU's gyroscope instead of the motion
    /// capture (as flight computers close their rate loop).
    pub gyro_rates: bool,
}

impl Sweep {
    /// The scene of one run.
    pub fn scene_of(&self, latency: f64, noise_scale: f64, seed: u64) -> Scene {
        let mut s = self.scene.clone();
        s.control.timing = Timing::Sampled;
        s.control.rate = self.control_rate;
        s.seed = seed;
        s.sensors = Some(SensorsSpec {
            preset: self.preset.clone(),
            noise_scale,
            mocap_latency: Some(latency),
            mocap_rate: None,
        });
        s.estimator = Some(EstimatorSpec {
            kind: EstimatorKind::Mocap,
            gyro_rates: self.gyro_rates,
        });
        s
    }

    /// Every cell, latencies outer, noise scales inner; the runs on
    /// `threads` threads (all cores for `None`). A scene the sensors or the
    /// estimator refuse is an error; a run that diverges is a `NaN`.
    pub fn run(&self, threads: Option<usize>) -> Result<Vec<Cell>, Error> {
        let mut jobs = Vec::new();
        for &l in &self.latencies {
            for &k in &self.noise_scales {
                for &seed in &self.seeds {
                    jobs.push((l, k, seed));
                }
            }
        }
        // Refused settings surface before any run.
        if let Some(&(l, k, seed)) = jobs.first() {
            let s = self.scene_of(l, k, seed);
            scenes::builder::<lie::NalgebraF64>(&s)?.build()?;
        }
        let index: Vec<u64> = (0..jobs.len() as u64).collect();
        let rms = crate::montecarlo::parallel_map(&index, threads, |&i| {
            let (l, k, seed) = jobs[i as usize];
            let opts = RunOptions {
                extrema: false,
                ..Default::default()
            };
            Ok(match scenes::run(&self.scene_of(l, k, seed), opts) {
                Ok(out) => crate::metrics::rms_position_error(&out.samples),
                Err(_) => f64::NAN,
            })
        })?;
        let per = self.seeds.len();
        Ok(jobs
            .chunks(per)
            .zip(rms.chunks(per))
            .map(|(j, r)| Cell {
                latency: j[0].0,
                noise_scale: j[0].1,
                rms: r.to_vec(),
            })
            .collect())
    }
}

/// The cells as a Markdown table: latencies down, noise scales across,
/// each entry the mean RMS position error ± its standard deviation over the
/// seeds not lost, in mm, with the count lost.
pub fn table(cells: &[Cell]) -> String {
    let mut scales: Vec<f64> = Vec::new();
    for c in cells {
        if !scales.contains(&c.noise_scale) {
            scales.push(c.noise_scale);
        }
    }
    let mut t = String::from("| latency |");
    for k in &scales {
        t.push_str(&format!(" noise ×{k} |"));
    }
    t.push_str("\n|---|");
    t.push_str(&"---|".repeat(scales.len()));
    t.push('\n');
    let mut latency = f64::NAN;
    for c in cells {
        if c.latency != latency {
            if !latency.is_nan() {
                t.push('\n');
            }
            latency = c.latency;
            t.push_str(&format!("| {} ms |", c.latency * 1e3));
        }
        let (mean, sd, lost) = c.stats();
        let n = c.rms.len();
        if lost == n {
            t.push_str(&format!(" lost ({n} of {n}) |"));
        } else if lost > 0 {
            t.push_str(&format!(
                " {:.2} ± {:.2} ({lost} of {n} lost) |",
                mean * 1e3,
                sd * 1e3
            ));
        } else {
            t.push_str(&format!(" {:.2} ± {:.2} |", mean * 1e3, sd * 1e3));
        }
    }
    t.push('\n');
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> Sweep {
        let mut scene = scenes::builtin::figure_eight();
        scene.duration = 1.0;
        Sweep {
            scene,
            preset: "rotorpy".into(),
            control_rate: 100.0,
            latencies: vec![0.0, 0.02],
            noise_scales: vec![0.0, 1.0],
            seeds: vec![1, 2, 3],
            gyro_rates: false,
        }
    }

    /// The noise is keyed on (seed, sensor, sample, axis), so a sweep's
    /// cells are the same bit for bit on one thread and on two; without
    /// noise every seed flies the same, with it each seed its own.
    #[test]
    fn a_sweep_is_the_same_on_one_thread_and_on_two() {
        let sweep = small();
        let one = sweep.run(Some(1)).expect("sweep");
        let two = sweep.run(Some(2)).expect("sweep");
        assert_eq!(one, two);
        assert_eq!(one.len(), 4);
        for c in &one {
            let distinct = c.rms[0] != c.rms[1] && c.rms[1] != c.rms[2];
            assert_eq!(distinct, c.noise_scale > 0.0, "{c:?}");
        }
        assert!(table(&one).contains("| 20 ms |"));
    }

    /// A sensor suite the scene cannot fly is an error before any run.
    #[test]
    fn an_unknown_preset_is_refused() {
        let mut sweep = small();
        sweep.preset = "vicon".into();
        let e = sweep.run(Some(1)).expect_err("refused").to_string();
        assert!(e.contains("vicon"), "{e}");
    }
}
