//! `geopid montecarlo`: the paper's "almost global" attractivity
//! (Propositions 2 and 3) checked over many random initial conditions.
//! The study itself (sampling, classification, statistics) is
//! `studies::montecarlo`; this is its command line: arguments, shards and
//! their merge, the output directory, progress, the figures, and the
//! near-π experiment.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use scenes::Scene;
use studies::montecarlo::{Initial, Outcome, Report, SAMPLES_HEADER, Setup};

use studies::montecarlo::shards::{
    self, Shard, write_atomic, write_run, write_samples, write_shard,
};

fn default_out(experiment: &str) -> PathBuf {
    Path::new("target/montecarlo").join(experiment)
}

/// `geopid montecarlo merge DIR...`: the shards' rows as one run's
/// files.
pub fn merge(dirs: &[PathBuf], out: Option<&Path>) -> Result<(), String> {
    let (setup, rows) = shards::merge(dirs).map_err(|e| e.to_string())?;
    let dir = out.map_or_else(|| default_out(&setup.experiment), Path::to_path_buf);
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    finish(&dir, &setup, &rows, None)
}

/// Which experiment.
#[derive(Copy, Clone, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Experiment {
    /// The pinned vehicle in attitude mode, R_d = I, Ω_d = 0, Δ_R.
    Attitude,
    /// The free quadrotor in position mode to hover at 0, b1d = e1, Δ_x, Δ_R.
    Position,
}

impl Experiment {
    fn name(self) -> &'static str {
        match self {
            Experiment::Attitude => "attitude",
            Experiment::Position => "position",
        }
    }
}

/// Options of `geopid montecarlo`.
#[derive(clap::Args, Debug)]
#[command(args_conflicts_with_subcommands = true)]
pub struct McArgs {
    /// `merge` or `near-pi`; none runs the experiment.
    #[command(subcommand)]
    pub action: Option<McAction>,
    /// attitude or position.
    #[arg(long, value_enum, default_value = "position")]
    pub experiment: Experiment,
    /// Number of samples (indices 0 … N−1).
    #[arg(long, default_value_t = 1000)]
    pub samples: u64,
    /// Seed of every sample's random stream.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (default: one per core).
    #[arg(long)]
    pub threads: Option<usize>,
    /// Run only the samples i with i mod N = K, as `K/N`.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<Shard>,
    /// Output directory (default `target/montecarlo/<experiment>`).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Run only this sample and print it (the slowest samples' replays).
    #[arg(long)]
    pub index: Option<u64>,
    /// Radius of the ball Ω(0) is drawn from, rad/s.
    #[arg(long, default_value_t = 2.0)]
    pub omega_max: f64,
    /// Radius of the ball e_x(0) is drawn from, m (position).
    #[arg(long, default_value_t = 2.0)]
    pub x_max: f64,
    /// Radius of the ball v(0) is drawn from, m/s (position).
    #[arg(long, default_value_t = 1.0)]
    pub v_max: f64,
    /// Ψ below which a sample counts as converged.
    #[arg(long, default_value_t = 1e-3)]
    pub psi_tol: f64,
    /// ‖e_x‖ below which a sample counts as converged (position), m.
    #[arg(long, default_value_t = 1e-2)]
    pub x_tol: f64,
    /// Simulated time a sample has to converge, s.
    #[arg(long, default_value_t = 60.0)]
    pub deadline: f64,
    /// How long the tolerances must hold before a sample counts as
    /// converged, s.
    #[arg(long, default_value_t = 0.5)]
    pub hold: f64,
    /// Integrator (see `geopid run --help`). The default, dopri at
    /// 1e-6, classifies every sample of a 200-sample check as dopri at 1e-9
    /// does, with times to converge within 0.05 s, at a quarter of its
    /// cost; rk4 at 5e-3 misclassified 2 of 200 and at 2e-3 cost more
    /// (the position law's near-singular passages need small steps only
    /// briefly, which an adaptive step pays for only there).
    #[arg(long, default_value = "dopri")]
    pub integrator: String,
    /// Step, s (dopri: longest call).
    #[arg(long, default_value_t = 0.02)]
    pub dt: f64,
    /// dopri tolerance.
    #[arg(long, default_value_t = 1e-6)]
    pub tol: f64,
    /// Fly four samples per instruction stream on f64 SIMD lanes (dopri,
    /// each lane its own step size, sat′ crossings not located: each row
    /// equals the scalar run's with --no-events), several times faster.
    #[arg(long)]
    pub lanes: bool,
    /// Do not locate the sat′ crossings of e_i (what `--lanes` does): a
    /// step integrates across the kink.
    #[arg(long)]
    pub no_events: bool,
    /// With --lanes: one dopri step size shared by the four lanes of an
    /// instruction stream (the worst lane's error decides) instead of one
    /// per lane. Slower, and a row then depends on its lane neighbours (a
    /// replay with --index flies the sample alone); kept to compare.
    #[arg(long, requires = "lanes")]
    pub shared_step: bool,
}

/// `merge` and `near-pi`.
#[derive(clap::Subcommand, Debug)]
pub enum McAction {
    /// Combine shard directories into the files one run writes.
    Merge {
        /// Shard directories (each written with --shard K/N).
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Output directory (default: `target/montecarlo/<experiment>`).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Time to converge from R(0) = exp((π − δ) â), δ = 10⁻ᵏ, against the
    /// unstable eigenvalue at the π equilibrium.
    NearPi {
        /// Output directory (default target/montecarlo).
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

/// The study's setup from the arguments.
fn setup_from_args(a: &McArgs) -> Setup {
    Setup {
        experiment: a.experiment.name().into(),
        samples: a.samples,
        seed: a.seed,
        omega_max: a.omega_max,
        x_max: a.x_max,
        v_max: a.v_max,
        psi_tol: a.psi_tol,
        x_tol: a.x_tol,
        deadline: a.deadline,
        hold: a.hold,
        integrator: a.integrator.clone(),
        dt: a.dt,
        tol: a.tol,
        // The lanes never locate sat′ crossings; recorded so that a
        // sample's replay (`--index`, scalar) reproduces its row.
        locate_events: !(a.no_events || a.lanes),
        shared_step: a.shared_step,
    }
}

/// The flags that reproduce `setup` on the command line.
fn flags(setup: &Setup) -> String {
    let mut f = format!("--experiment {} --seed {}", setup.experiment, setup.seed);
    let d = setup_from_args(&default_args());
    let mut opt = |name: &str, v: f64, dv: f64| {
        if v != dv {
            let _ = write!(f, " --{name} {v}");
        }
    };
    opt("omega-max", setup.omega_max, d.omega_max);
    opt("x-max", setup.x_max, d.x_max);
    opt("v-max", setup.v_max, d.v_max);
    opt("psi-tol", setup.psi_tol, d.psi_tol);
    opt("x-tol", setup.x_tol, d.x_tol);
    opt("deadline", setup.deadline, d.deadline);
    opt("hold", setup.hold, d.hold);
    opt("dt", setup.dt, d.dt);
    if setup.integrator != d.integrator {
        let _ = write!(f, " --integrator {}", setup.integrator);
    }
    if setup.integrator == "dopri" && setup.tol != d.tol {
        let _ = write!(f, " --tol {}", setup.tol);
    }
    if !setup.locate_events {
        f.push_str(" --no-events");
    }
    f
}

/// The experiment's scene with a sample's initial condition, described by
/// the command that reproduces it: what `geopid run` replays.
pub fn scene(setup: &Setup, init: &Initial) -> Scene {
    let mut s = setup.scene(init);
    s.description = format!(
        "A Monte Carlo sample of the {} experiment ({} montecarlo {}).",
        setup.experiment,
        crate::program(),
        flags(setup)
    );
    s
}

fn default_args() -> McArgs {
    use clap::Parser;
    #[derive(clap::Parser)]
    struct P {
        #[command(flatten)]
        a: McArgs,
    }
    P::parse_from(["montecarlo"]).a
}

/// Runs the indices of a shard on `threads` threads; results in index
/// order.
pub fn run_indices(
    setup: &Setup,
    indices: &[u64],
    threads: usize,
    progress: Option<&indicatif::ProgressBar>,
    lanes: bool,
) -> Result<Vec<Outcome>, String> {
    let report = |n: u64| {
        if let Some(p) = progress {
            p.set_position(n);
        }
    };
    if lanes {
        let (rows, usage) = setup
            .run_lanes(indices, Some(threads), Some(&report))
            .map_err(|e| e.to_string())?;
        println!(
            "lanes: f64x4 on the {} path, {} lane-substeps, {:.3} % of them in an empty lane (the queue's tail)",
            lie::cpu::compiled().name(),
            usage.busy + usage.idle,
            100.0 * usage.idle_fraction()
        );
        if setup.shared_step {
            println!(
                "shared step: a row depends on the samples beside it in its lanes; the replays below fly a sample alone, with its own step"
            );
        }
        return Ok(rows);
    }
    setup
        .run(indices, Some(threads), Some(&report))
        .map_err(|e| e.to_string())
}

/// The report of a complete run, each slow sample with its command line.
pub fn summary(setup: &Setup, rows: &[Outcome], wall: Option<f64>) -> Report {
    Report::new(setup, rows, wall, |i| {
        format!(
            "{} montecarlo {} --index {i}",
            crate::program(),
            flags(setup)
        )
    })
}

/// Writes samples.csv, summary.json, the figures and the worst sample's
/// scene into `dir`, and prints the summary.
fn finish(dir: &Path, setup: &Setup, rows: &[Outcome], wall: Option<f64>) -> Result<(), String> {
    write_samples(dir, rows).map_err(|e| e.to_string())?;
    let report = summary(setup, rows, wall);
    let text = serde_json::to_string_pretty(&report).map_err(|e| e.to_string())?;
    write_atomic(&dir.join("summary.json"), text.as_bytes()).map_err(|e| e.to_string())?;
    studies::figures::montecarlo(dir, rows).map_err(|e| e.to_string())?;
    print!("{report}");
    // The replay is the slowest *converged* sample: a diverging one would
    // make `geopid run` (uncapped dopri) grind through its blow-up;
    // those are re-run with their `--index` command instead.
    let worst = rows
        .iter()
        .filter(|r| r.converged)
        .max_by(|a, b| a.t_converge.total_cmp(&b.t_converge));
    if let Some(r) = worst {
        let mut sc = scene(setup, &setup.initial(r.index));
        // Long enough to see the convergence and a little after.
        sc.duration = (r.t_converge + setup.hold + 2.0).min(setup.deadline);
        sc.name = format!("montecarlo-{}-slowest-{}", setup.experiment, r.index);
        let path = dir.join("worst.toml");
        write_atomic(&path, sc.to_toml().as_bytes()).map_err(|e| e.to_string())?;
        println!(
            "slowest converged sample (#{}, {:.3} s) as a scene: {} run {} --mcap worst.mcap",
            r.index,
            r.t_converge,
            crate::program(),
            path.display()
        );
    }
    println!(
        "wrote {}/{{samples.csv, summary.json, angle_vs_time.svg, time_histogram.svg, worst.toml}}",
        dir.display()
    );
    Ok(())
}

/// `geopid montecarlo`.
pub fn montecarlo(a: McArgs) -> Result<(), String> {
    match &a.action {
        Some(McAction::Merge { dirs, out }) => return merge(dirs, out.as_deref()),
        Some(McAction::NearPi { out }) => return near_pi(out.as_deref()),
        None => {}
    }
    let setup = setup_from_args(&a);
    setup.validate().map_err(|e| match e {
        // The library names the setting; the command line spells it as a flag.
        scenes::Error::Run(scenarios::SimError::Setting { field, message }) => {
            format!("--{} {message}", field.replace('_', "-"))
        }
        e => e.to_string(),
    })?;
    if setup.samples == 0 {
        return Err("--samples 0: nothing to run".into());
    }
    if let Some(i) = a.index {
        if i >= setup.samples {
            return Err(format!(
                "--index {i}: the run has {} samples",
                setup.samples
            ));
        }
        let r = setup.run_sample(i).map_err(|e| e.to_string())?;
        println!("{SAMPLES_HEADER}\n{}", r.csv());
        let dir = a
            .out
            .clone()
            .unwrap_or_else(|| default_out(&setup.experiment));
        std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
        let mut sc = scene(&setup, &setup.initial(i));
        sc.name = format!("montecarlo-{}-{i}", setup.experiment);
        let path = dir.join(format!("sample-{i}.toml"));
        write_atomic(&path, sc.to_toml().as_bytes()).map_err(|e| e.to_string())?;
        println!(
            "its scene: {} run {} --mcap sample-{i}.mcap",
            crate::program(),
            path.display()
        );
        return Ok(());
    }
    let shard = a.shard.unwrap_or(Shard::WHOLE);
    let (k, n) = (shard.k, shard.n);
    let indices = shard.indices(setup.samples);
    let threads = a
        .threads
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()));
    if threads == 0 {
        return Err("--threads 0: need at least one".into());
    }
    let dir = a.out.clone().unwrap_or_else(|| {
        let d = default_out(&setup.experiment);
        if n > 1 {
            d.join(format!("shard-{k}-of-{n}"))
        } else {
            d
        }
    });
    std::fs::create_dir_all(&dir).map_err(|e| format!("--out {}: {e}", dir.display()))?;
    let bar = crate::progress(
        indices.len() as u64,
        "{bar:40} {pos}/{len} samples, {per_sec}, {elapsed}<{eta}",
    );
    let started = std::time::Instant::now();
    let rows = run_indices(&setup, &indices, threads, Some(&bar), a.lanes)?;
    bar.finish_and_clear();
    let wall = started.elapsed().as_secs_f64();
    if n > 1 {
        write_shard(&dir, &setup, shard, &rows).map_err(|e| e.to_string())?;
        println!(
            "shard {k}/{n}: {} samples in {wall:.2} s → {}/samples.csv (merge with `{} montecarlo merge DIR...`)",
            rows.len(),
            dir.display(),
            crate::program()
        );
        return Ok(());
    }
    write_run(&dir, &setup, shard).map_err(|e| e.to_string())?;
    finish(&dir, &setup, &rows, Some(wall))
}

/// `geopid montecarlo near-pi`: the escape time from near π against
/// `ln(1/δ)/λ₊` (`studies::montecarlo::near_pi`), `near-pi.csv`, and a
/// failure when the fitted slope and 1/λ₊ differ by more than 1 %.
pub fn near_pi(out: Option<&Path>) -> Result<(), String> {
    let dir = out.map_or_else(|| PathBuf::from("target/montecarlo"), Path::to_path_buf);
    std::fs::create_dir_all(&dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    let report = studies::montecarlo::near_pi().map_err(|e| e.to_string())?;
    if let Some((a, d)) = report.iter().find_map(|a| Some((a.axis, a.unsettled()?))) {
        return Err(format!(
            "near-pi {a} δ = {d:e}: Ψ never dropped below 1e-3 in 60 s"
        ));
    }
    let csv = studies::montecarlo::near_pi_csv(&report);
    write_atomic(&dir.join("near-pi.csv"), csv.as_bytes()).map_err(|e| e.to_string())?;
    println!(
        "time to Ψ < 1e-3 from R(0) = exp((π − δ) â), attitude mode, paper gains, no disturbance:"
    );
    for a in &report {
        println!("{a}");
    }
    let worst = report.iter().map(|a| a.slope_error()).fold(0.0, f64::max);
    println!("wrote {}", dir.join("near-pi.csv").display());
    if worst > 0.01 {
        return Err(format!(
            "the slope and 1/λ₊ differ by {:.2} % (> 1 %)",
            100.0 * worst
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The library's `Setup::default` (what the Python package and a Rust
    /// study start from) is the command line's defaults.
    #[test]
    fn library_defaults_are_the_command_lines() {
        assert_eq!(setup_from_args(&default_args()), Setup::default());
    }

    /// The flags reproduce the setup: only what differs from the defaults.
    #[test]
    fn flags_name_what_differs() {
        let mut s = setup_from_args(&default_args());
        assert_eq!(flags(&s), "--experiment position --seed 1");
        s.hold = 1.0;
        s.integrator = "rk4".into();
        assert_eq!(
            flags(&s),
            "--experiment position --seed 1 --hold 1 --integrator rk4"
        );
    }
}
