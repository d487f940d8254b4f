//! Recording does not change the computed trajectory: samples come from
//! each step's continuous extension, not from steps that land on them.

use logs::{CsvWriter, McapWriter, Sink, Tee};
use scenarios::{RunOptions, RunOutput};
use scenes::{Scene, builtin, run};
use studies::metrics;

const STEPPERS: [(&str, f64); 6] = [
    ("lgvi", 1e-3),
    ("rk4", 1e-3),
    ("rk4-projected", 1e-3),
    ("rkmk4", 1e-3),
    ("euler", 1e-4),
    ("dopri", 1e-2),
];

fn flip(kind: &str, dt: f64) -> Scene {
    let mut s = builtin::paper_flip();
    s.duration = 1.5; // the switch at 0.4 s and both sat′ events
    s.integrator.kind = kind.into();
    s.integrator.dt = dt;
    s.integrator.tol = 1e-9;
    // 1.7 ms does not divide dt: no step could land on the samples.
    s.record.sample = 0.0017;
    s
}

/// Everything a run reports about itself, to compare bit for bit.
fn summary(o: &RunOutput) -> String {
    format!(
        "{:?} {:?} {:?} {} {} {} {} {:?} {:?} {:?} {:?}",
        o.last.r,
        o.last.x,
        (
            o.last.omega,
            o.last.v,
            o.last.e_att,
            o.last.e_pos,
            o.last.psi
        ),
        o.steps,
        o.evaluations,
        o.max_thrust,
        o.max_rotor,
        o.max_orthogonality_error,
        o.psi_range,
        o.event_times,
        o.switches,
    )
}

/// The final state, the step and evaluation counts, the events and the
/// summary's extrema are bit-identical with and without recording (kept
/// in memory, streamed to CSV and MCAP), for every stepper; without
/// recording there are only the first and last samples.
#[test]
fn the_run_is_bit_identical_with_and_without_recording() {
    let dir = std::env::temp_dir().join(format!("gpid-dense-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (kind, dt) in STEPPERS {
        let s = flip(kind, dt);
        let quiet = run(
            &s,
            RunOptions {
                record: false,
                ..Default::default()
            },
        )
        .unwrap();
        let kept = run(&s, RunOptions::default()).unwrap();
        let mut csv = CsvWriter::create(&dir.join("a.csv")).unwrap();
        let mut mcap = McapWriter::create(&dir.join("a.mcap")).unwrap();
        let mut tee = Tee(vec![&mut csv as &mut dyn Sink, &mut mcap]);
        let streamed = run(
            &s,
            RunOptions {
                record: false,
                sink: Some(&mut tee),
                ..Default::default()
            },
        )
        .unwrap();
        drop(tee);
        let rows = csv.finish().unwrap();
        mcap.finish(&[], None).unwrap();
        assert!(quiet.samples.is_empty());
        assert_eq!(kept.samples.len() as u64, rows);
        assert!(rows > 800, "{kind}: {rows} samples");
        assert_eq!(summary(&quiet), summary(&kept), "{kind}: kept");
        assert_eq!(summary(&quiet), summary(&streamed), "{kind}: streamed");
        assert_eq!(kept.samples.last().unwrap(), &kept.last);
        assert_eq!(kept.samples.last().unwrap().t, s.duration);
    }
    std::fs::remove_dir_all(dir).ok();
}

/// The per-step figures (extrema) ask the mode for its command at every
/// step's end, and the next step's first load takes that answer instead of
/// asking again: the flight, its step and evaluation counts and its events
/// are bit-identical with the figures off, where every load asks the mode
/// itself, for every stepper (the flip crosses sat′ and switches modes,
/// which move the mode's branches and the active segment between steps).
#[test]
fn the_figures_never_move_the_flight() {
    for (kind, dt) in STEPPERS {
        let s = flip(kind, dt);
        let bare = RunOptions {
            record: false,
            extrema: false,
            ..Default::default()
        };
        let without = run(&s, bare).unwrap();
        let with = run(&s, RunOptions::default()).unwrap();
        let flight = |o: &RunOutput| {
            format!(
                "{:?} {:?} {:?} {:?} {:?} {:?} {} {} {:?} {:?}",
                o.last.r,
                o.last.x,
                o.last.v,
                o.last.omega,
                o.last.e_att,
                o.last.e_pos,
                o.steps,
                o.evaluations,
                o.event_times,
                o.switches,
            )
        };
        assert_eq!(flight(&without), flight(&with), "{kind}");
        // Off, the extrema cover the start, the events and the end only.
        assert!(without.max_thrust <= with.max_thrust, "{kind}");
        assert!(
            !with.event_times.is_empty() && !with.switches.is_empty(),
            "{kind}"
        );
    }
}

/// Largest error over the run's samples in R, x and Ω against a reference
/// run (tight, its steps landing on the samples).
fn sample_error(o: &RunOutput, reference: &RunOutput) -> f64 {
    let metrics::Difference {
        x: dx,
        r: dr,
        compared: n,
        ..
    } = metrics::max_difference(&o.samples, &reference.samples);
    assert!(n + 2 >= o.samples.len(), "{n} common samples");
    let mut dw = 0.0f64;
    for s in &o.samples {
        let r = metrics::at(&reference.samples, s.t).unwrap();
        for k in 0..3 {
            dw = dw.max((s.omega[k] - r.omega[k]).abs());
        }
    }
    dx.max(dr).max(dw / 10.0)
}

/// Interpolated samples agree with a reference within the method's own
/// error, and the error falls with the step at the method's order: the
/// cubic Hermite extension (on the group for R) is off by O(h⁴) given
/// exact end states, so each stepper keeps its order in the samples.
#[test]
fn samples_between_steps_have_the_methods_order() {
    // Reference: RK4 at 1e-5 s, whose steps land on every 1.7 ms sample
    // (1.7e-3 = 170 steps); its own error is ~1e-16 (4th order, and 1e-9 at
    // h = 1e-3).
    let mut reference = flip("rk4", 1e-5);
    reference.record.sample = 0.0017;
    let reference = run(&reference, RunOptions::default()).unwrap();
    for (kind, h, order) in [
        ("rk4", 4e-3, 4.0),
        ("rkmk4", 4e-3, 4.0),
        ("lgvi", 4e-3, 2.0),
        ("euler", 2e-4, 1.0),
    ] {
        let coarse = sample_error(
            &run(&flip(kind, h), RunOptions::default()).unwrap(),
            &reference,
        );
        let fine = sample_error(
            &run(&flip(kind, h / 2.0), RunOptions::default()).unwrap(),
            &reference,
        );
        // The same method landing on the samples (1.7 ms = 17 steps of
        // 0.1 ms): its error at the samples is the method's own.
        let mut landing = flip(kind, 1e-4);
        landing.record.sample = 0.0017;
        let observed = (coarse / fine).log2();
        println!(
            "{kind}: sample error {coarse:.2e} at h = {h}, {fine:.2e} at h/2: order {observed:.2}"
        );
        // Halving the step gives the method's order from both sides:
        // measured rk4 4.00, rkmk4 4.02, lgvi 2.00, euler 0.99 (the kinks
        // of sat′ are located, so they cost nothing); ±0.3 is ten times
        // the largest deviation and far from the next order.
        assert!(
            (observed - order).abs() < 0.3,
            "{kind}: order {observed:.2}"
        );
        let landed = sample_error(&run(&landing, RunOptions::default()).unwrap(), &reference);
        let interpolated = {
            let mut s = flip(kind, 1e-4);
            s.record.sample = 0.00173; // between the steps
            let mut r = flip("rk4", 1e-5);
            r.record.sample = 0.00173;
            r.integrator.dt = 0.00173 / 173.0;
            sample_error(
                &run(&s, RunOptions::default()).unwrap(),
                &run(&r, RunOptions::default()).unwrap(),
            )
        };
        println!("{kind} at 0.1 ms: landing {landed:.2e}, interpolated {interpolated:.2e}");
        // Within the method's error: twice the landing run's (a different
        // set of instants sees a different part of the same error).
        assert!(
            interpolated <= 2.0 * landed + 1e-12,
            "{kind}: {interpolated:e} vs {landed:e}"
        );
    }
}

/// Dormand–Prince takes many substeps in one long call: its samples come
/// from integrating a copy of the stepper from the call's start, so they
/// keep the tolerance's accuracy however long the call (a cubic through the
/// call's two ends left a 2.5e-4 floor in the work-precision sweep's
/// dopri reference, whatever its tolerance).
#[test]
fn adaptive_samples_keep_the_tolerance_over_long_calls() {
    let mut reference = flip("rk4", 1e-5);
    reference.record.sample = 0.0017;
    let reference = run(&reference, RunOptions::default()).unwrap();
    let mut s = flip("dopri", 0.05);
    s.integrator.tol = 1e-10;
    let out = run(&s, RunOptions::default()).unwrap();
    let e = sample_error(&out, &reference);
    println!("dopri 1e-10, 50 ms calls: sample error {e:.2e}");
    // The tolerance times the error's growth over 1.5 s of closed loop:
    // measured 1.6e-10, bound ~30× (the cubic through a call's two ends
    // that this replaced was off by 1e-4).
    assert!(e < 5e-9, "{e:e}");
}
