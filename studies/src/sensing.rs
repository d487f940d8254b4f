//! Flying on measurements: the RMS position error of a scene flown on the
//! mocap estimator, against the motion capture's latency and a scale of
//! every noise of the sensor suite, over independent noise seeds.

use scenarios::RunOptions;
use scenes::scene::{ControlSpec, EstimatorKind, EstimatorSpec, SensorsSpec, Timing};
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
            ..SensorsSpec::default()
        });
        s.estimator = Some(EstimatorSpec {
            kind: EstimatorKind::Mocap,
            gyro_rates: self.gyro_rates,
            ..EstimatorSpec::default()
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
        let runs: Vec<Scene> = jobs
            .iter()
            .map(|&(l, k, seed)| self.scene_of(l, k, seed))
            .collect();
        let rms = rms_of(&runs, threads)?;
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

/// Each scene's RMS position error (`NaN` for a run that failed), on
/// `threads` threads; a scene refused is an error before any run.
fn rms_of(runs: &[Scene], threads: Option<usize>) -> Result<Vec<f64>, Error> {
    if let Some(s) = runs.first() {
        scenes::builder::<lie::NalgebraF64>(s)?.build()?;
    }
    let index: Vec<u64> = (0..runs.len() as u64).collect();
    crate::montecarlo::parallel_map(&index, threads, |&i| {
        let opts = RunOptions {
            extrema: false,
            ..Default::default()
        };
        Ok(match scenes::run(&runs[i as usize], opts) {
            Ok(out) => crate::metrics::rms_position_error(&out.samples),
            Err(_) => f64::NAN,
        })
    })
}

/// The same scene on the mocap estimator under several control timings
/// (one rate, or a multi-rate loop), over independent noise seeds.
#[derive(Clone, Debug)]
pub struct LoopSweep {
    /// The scene (its sensors and estimator are replaced).
    pub scene: Scene,
    /// The sensor suite, at its own latency and rates.
    pub preset: String,
    /// Each timing with its label.
    pub loops: Vec<(String, ControlSpec)>,
    /// The noise scales.
    pub noise_scales: Vec<f64>,
    /// The seeds of each cell.
    pub seeds: Vec<u64>,
}

impl LoopSweep {
    /// Per timing and noise scale (timings outer), the RMS over every
    /// seed; a cell's `latency` is the timing's index in `loops`.
    pub fn run(&self, threads: Option<usize>) -> Result<Vec<Cell>, Error> {
        let mut runs = Vec::new();
        let mut cells = Vec::new();
        for (i, (_, control)) in self.loops.iter().enumerate() {
            for &k in &self.noise_scales {
                for &seed in &self.seeds {
                    let mut s = self.scene.clone();
                    s.control = control.clone();
                    s.seed = seed;
                    s.sensors = Some(SensorsSpec {
                        preset: self.preset.clone(),
                        noise_scale: k,
                        mocap_latency: None,
                        mocap_rate: None,
                        ..SensorsSpec::default()
                    });
                    s.estimator = Some(EstimatorSpec {
                        kind: EstimatorKind::Mocap,
                        ..EstimatorSpec::default()
                    });
                    runs.push(s);
                }
                cells.push(Cell {
                    latency: i as f64,
                    noise_scale: k,
                    rms: Vec::new(),
                });
            }
        }
        let rms = rms_of(&runs, threads)?;
        for (c, r) in cells.iter_mut().zip(rms.chunks(self.seeds.len())) {
            c.rms = r.to_vec();
        }
        Ok(cells)
    }

    /// The cells as a Markdown table, a row per timing (its label).
    pub fn table(&self, cells: &[Cell]) -> String {
        labelled_table(cells, "loop", |c| {
            let i = c.latency as usize;
            self.loops
                .get(i)
                .map_or_else(|| i.to_string(), |l| l.0.clone())
        })
    }
}

/// The cells as a Markdown table: latencies down, noise scales across,
/// each entry the mean RMS position error ± its standard deviation over the
/// seeds not lost, in mm, with the count lost.
pub fn table(cells: &[Cell]) -> String {
    labelled_table(cells, "latency", |c| format!("{} ms", c.latency * 1e3))
}

/// [`table`] with the first column headed `head` and each row labelled
/// by `label` of its first cell.
fn labelled_table(cells: &[Cell], head: &str, label: impl Fn(&Cell) -> String) -> String {
    let mut scales: Vec<f64> = Vec::new();
    for c in cells {
        if !scales.contains(&c.noise_scale) {
            scales.push(c.noise_scale);
        }
    }
    let mut t = format!("| {head} |");
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
            t.push_str(&format!("| {} |", label(c)));
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

    /// A loop sweep labels its rows by timing; without noise each seed
    /// flies the same, and the timings differ from one another.
    #[test]
    fn a_loop_sweep_has_a_row_per_timing() {
        let mut scene = scenes::builtin::figure_eight();
        scene.duration = 1.0;
        let one = ControlSpec {
            timing: Timing::Sampled,
            rate: 500.0,
            ..ControlSpec::default()
        };
        let multi = ControlSpec {
            position_rate: 50.0,
            ..one.clone()
        };
        let sweep = LoopSweep {
            scene,
            preset: "crazyflie".into(),
            loops: vec![("one rate".into(), one), ("500/50 Hz".into(), multi)],
            noise_scales: vec![0.0],
            seeds: vec![1, 2],
        };
        let cells = sweep.run(Some(2)).expect("sweep");
        assert_eq!(cells.len(), 2);
        for c in &cells {
            assert_eq!(c.rms[0], c.rms[1], "{c:?}");
        }
        assert_ne!(cells[0].rms[0], cells[1].rms[0]);
        let t = sweep.table(&cells);
        assert!(t.contains("| loop |") && t.contains("| 500/50 Hz |"), "{t}");
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
