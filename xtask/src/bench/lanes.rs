//! The lane rows of `cargo xtask bench`: the criterion medians of the
//! control laws and of one closed-loop RK4 step per scene (`controllers`
//! and `scenarios` benches `lanes`), one lane against four or eight, and
//! the position updates per second of every core at once.

use std::collections::BTreeMap;
use std::hint::black_box;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::time::{Duration, Instant};

use integrators::State;
use integrators::lanes::LaneSystem;
use lie::{Backend, NalgebraF32, NalgebraF32x8, NalgebraF64, NalgebraF64x4, SimdBackend, SimdReal};
use scenarios::lanes::PositionLoop;

/// The groups of the lane benches and their names here.
const GROUPS: [(&str, &str); 3] = [
    ("lanes/attitude", "attitude_law"),
    ("lanes/position", "position_law"),
    ("lanes/step-rk4", "closed-loop RK4 step"),
];

/// (one lane, lanes) of each precision.
const PAIRS: [(&str, &str); 2] = [
    ("nalgebra-f64", "nalgebra-f64x4"),
    ("nalgebra-f32", "nalgebra-f32x8"),
];

/// The lane benches' medians (nanoseconds a vehicle or scene) with the
/// speed-up of the lanes over one lane, as a Markdown table (also printed).
pub fn lanes_table(raw: &[(String, f64)]) -> String {
    let medians: BTreeMap<&str, f64> = raw.iter().map(|(id, m)| (id.as_str(), *m)).collect();
    let mut md = String::from(
        "| per vehicle or scene | one lane | ns | lanes | ns | speed-up |\n|---|---|---|---|---|---|\n",
    );
    for (group, what) in GROUPS {
        for (one, many) in PAIRS {
            let get = |pair: &str| medians.get(format!("{group}/{pair}").as_str()).copied();
            let (Some(a), Some(b)) = (get(one), get(many)) else {
                continue;
            };
            md += &format!(
                "| {what} | {one} | {a:.1} | {many} | {b:.1} | {:.2} |\n",
                a / b
            );
        }
    }
    println!("\n{md}");
    md
}

/// Scene `i`: the position Monte Carlo's sample `i` (random attitude,
/// rates, position and velocity; integrals zero).
fn scene<S: Backend>(i: usize) -> State<S, 6> {
    State::new(
        studies::montecarlo::Setup::default()
            .initial(i as u64)
            .body::<S>(),
    )
}

/// Position-law evaluations (with the loads: `PositionLoop::paper`'s
/// `load`) per
/// second on `threads` threads at once for `run`, 64 scenes per thread.
fn updates_per_second<S, L>(threads: usize, run: Duration) -> f64
where
    S: Backend,
    L: SimdBackend<Scalar: SimdReal<Element = S::Scalar>>,
{
    let n = <L::Scalar as SimdReal>::LANES;
    let stop = AtomicBool::new(false);
    let count = AtomicU64::new(0);
    let started = Instant::now();
    std::thread::scope(|s| {
        for _ in 0..threads {
            s.spawn(|| {
                let mut sys = PositionLoop::<L>::paper::<S>();
                let ys: Vec<State<L, 6>> = (0..64 / n)
                    .map(|g| {
                        integrators::lanes::state_from_fn::<S, L, 6>(|i| scene::<S>(g * n + i))
                    })
                    .collect();
                let t = L::Scalar::simd_lit(0.0);
                let mut done = 0u64;
                while !stop.load(Ordering::Relaxed) {
                    for y in &ys {
                        black_box(sys.load(t, black_box(y)));
                    }
                    done += 64;
                }
                count.fetch_add(done, Ordering::Relaxed);
            });
        }
        std::thread::sleep(run);
        stop.store(true, Ordering::Relaxed);
    });
    count.load(Ordering::Relaxed) as f64 / started.elapsed().as_secs_f64()
}

/// The position updates per second on one core and on every core, one
/// lane and lanes, each precision, as a Markdown table (also printed).
pub fn throughput(quick: bool) -> String {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    let run = Duration::from_millis(if quick { 300 } else { 1500 });
    let mut md =
        format!("| position updates per second | one core | {cores} cores |\n|---|---|---|\n");
    let mut row = |name: &str, f: &dyn Fn(usize) -> f64| {
        let (one, all) = (f(1), f(cores));
        md += &format!("| {name} | {one:.3e} | {all:.3e} |\n");
    };
    row("nalgebra-f64", &|k| {
        updates_per_second::<NalgebraF64, NalgebraF64>(k, run)
    });
    row("nalgebra-f64x4", &|k| {
        updates_per_second::<NalgebraF64, NalgebraF64x4>(k, run)
    });
    row("nalgebra-f32", &|k| {
        updates_per_second::<NalgebraF32, NalgebraF32>(k, run)
    });
    row("nalgebra-f32x8", &|k| {
        updates_per_second::<NalgebraF32, NalgebraF32x8>(k, run)
    });
    println!("\n{md}");
    md
}
