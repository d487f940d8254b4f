//! `cargo xtask sensing`: the built-in hover and figure eight flown on the
//! mocap estimator with the `rotorpy` sensor suite at 100 Hz, the RMS
//! position error against the motion capture's latency (0, 5, 10, 20,
//! 50 ms) and a scale of every noise (×0, ×1, ×10, ×100), over 20 seeds
//! (`--quick`: 4 seeds, 5 s runs). `--report PATH` writes the tables as
//! Markdown with the command that made them.

use std::path::PathBuf;

use scenes::scene::{ControlSpec, Timing};
use studies::sensing::{LoopSweep, Sweep, table};

/// Options of `cargo xtask sensing`.
#[derive(clap::Args)]
pub struct SensingArgs {
    /// 4 seeds and 5 s runs instead of 20 and the scenes' durations.
    #[arg(long)]
    quick: bool,
    /// Seeds per cell [default: 20, --quick 4].
    #[arg(long)]
    seeds: Option<u64>,
    /// Worker threads [default: all cores].
    #[arg(long)]
    threads: Option<usize>,
    /// Write the tables as Markdown here.
    #[arg(long, value_name = "PATH")]
    report: Option<PathBuf>,
}

pub fn sensing(a: SensingArgs) -> Result<(), String> {
    let seeds = a.seeds.unwrap_or(if a.quick { 4 } else { 20 });
    let mut hover = scenes::builtin::hover_disturbed();
    hover.duration = 20.0;
    let eight = scenes::builtin::figure_eight();
    let scenes = [
        ("hover (hover-disturbed, 20 s)", hover, false),
        ("figure-eight", eight.clone(), false),
        ("figure-eight, body rates from the gyroscope", eight, true),
    ];
    let mut md = format!(
        "RMS of ‖x − x_d‖ over the run, mm, mean ± standard deviation over {seeds} noise \
         seeds (a run whose RMS passes 1 m is counted lost and left out of both); the modes \
         read the latest motion-capture frame (`estimator = mocap`), sensor suite `rotorpy` (motion capture at 100 Hz), control sampled at 100 Hz{}. Written by \
         `cargo xtask sensing{} --report`.\n",
        if a.quick { ", runs cut to 5 s" } else { "" },
        if a.quick { " --quick" } else { "" },
    );
    for (name, mut scene, gyro_rates) in scenes {
        if a.quick {
            scene.duration = 5.0;
        }
        let sweep = Sweep {
            scene,
            preset: "rotorpy".into(),
            control_rate: 100.0,
            latencies: vec![0.0, 0.005, 0.010, 0.020, 0.050],
            noise_scales: vec![0.0, 1.0, 10.0, 100.0],
            seeds: (1..=seeds).collect(),
            gyro_rates,
        };
        let start = std::time::Instant::now();
        let cells = sweep.run(a.threads).map_err(|e| e.to_string())?;
        let t = table(&cells);
        println!(
            "{name}: {} runs in {:.1} s\n{t}",
            cells.len() as u64 * seeds,
            start.elapsed().as_secs_f64()
        );
        md.push_str(&format!("\n**{name}**\n\n{t}"));
    }
    md.push_str(&loop_rates(&a, seeds)?);
    if let Some(p) = a.report {
        std::fs::write(&p, md).map_err(|e| format!("writing {}: {e}", p.display()))?;
        println!("wrote {}", p.display());
    }
    Ok(())
}

/// The figure eight on the `crazyflie` suite under one control rate and
/// under multi-rate loops: its Markdown section.
fn loop_rates(a: &SensingArgs, seeds: u64) -> Result<String, String> {
    let one = |rate: f64| ControlSpec {
        timing: Timing::Sampled,
        rate,
        ..ControlSpec::default()
    };
    let multi = |position_rate: f64, estimator_rate: f64| ControlSpec {
        position_rate,
        estimator_rate,
        ..one(500.0)
    };
    let loops = vec![
        ("one rate, 100 Hz".to_string(), one(100.0)),
        ("one rate, 500 Hz".into(), one(500.0)),
        ("attitude 500 Hz, position 100 Hz".into(), multi(100.0, 0.0)),
        ("attitude 500 Hz, position 50 Hz".into(), multi(50.0, 0.0)),
        ("attitude 500 Hz, position 25 Hz".into(), multi(25.0, 0.0)),
        (
            "attitude 500 Hz, position 100 Hz, estimate at 50 Hz".into(),
            multi(100.0, 50.0),
        ),
        (
            "`loop_rates = \"crazyflie\"` (1 kHz, 500 Hz, 100 Hz)".into(),
            ControlSpec {
                loop_rates: Some("crazyflie".into()),
                ..ControlSpec::default()
            },
        ),
    ];
    let mut scene = scenes::builtin::figure_eight();
    if a.quick {
        scene.duration = 5.0;
    }
    let sweep = LoopSweep {
        scene,
        preset: "crazyflie".into(),
        loops,
        noise_scales: vec![0.0, 1.0, 10.0],
        seeds: (1..=seeds).collect(),
    };
    let start = std::time::Instant::now();
    let cells = sweep.run(a.threads).map_err(|e| e.to_string())?;
    let t = sweep.table(&cells);
    println!(
        "loop rates: {} runs in {:.1} s\n{t}",
        cells.len() as u64 * seeds,
        start.elapsed().as_secs_f64()
    );
    Ok(format!(
        "\n**figure-eight on the `crazyflie` suite (motion capture at 100 Hz, 10 ms late), by \
         control timing**\n\n{t}"
    ))
}
