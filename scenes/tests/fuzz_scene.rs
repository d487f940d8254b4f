//! Fuzzing the scene parser and validator: random and mutated TOML must
//! never panic, every rejection is a `SceneError` with a message and a
//! `file:line:col` location, and every accepted scene runs a few steps
//! without panicking (an error is fine; a panic or a hang is not).
//!
//! `cargo test -p geopid-scenarios --test fuzz_scene` runs a short pass (the
//! proptest default of 256 cases per property, or `PROPTEST_CASES`) from
//! a fixed seed (`PROPTEST_RNG_SEED` picks another); a failure prints the
//! seed that reproduces it and is kept in `fuzz_scene.proptest-regressions`.
//! The long campaign is an ignored test bounded by wall time:
//!
//! ```text
//! SCENE_FUZZ_SECS=600 cargo test --release -p geopid-scenarios --test fuzz_scene \
//!     -- --ignored --nocapture fuzz_for_a_while
//! ```
//!
//! What a campaign found is kept below as plain regression tests
//! (`found_*`), so it never depends on a seed file.

use std::sync::atomic::{AtomicU64, Ordering};

use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestCaseError, TestRng, TestRunner};
use scenarios::RunOptions;
use scenes::{Scene, builtin};

/// Valid starting points: every built-in scene as TOML and the shipped file.
fn corpus() -> Vec<String> {
    let mut v: Vec<String> = builtin::all().iter().map(Scene::to_toml).collect();
    v.push(include_str!("../scenes/paper-flip.toml").to_string());
    v
}

/// Values a user (or a corrupted file) might put after `=`.
const TOKENS: &[&str] = &[
    "nan",
    "inf",
    "-inf",
    "+inf",
    "-1.0",
    "0",
    "0.0",
    "-0.0",
    "1e308",
    "1e-320",
    "5e-324",
    "9999999999999999999",
    "-9223372036854775808",
    "1",
    "3",
    "\"\"",
    "\"x\"",
    "\"rk4\"",
    "\"dopri\"",
    "\"lgvi\"",
    "\"euler\"",
    "\"rkmk4\"",
    "\"rk4-projected\"",
    "\"sampled\"",
    "\"continuous\"",
    "\"f32\"",
    "\"glam\"",
    "\"attitude\"",
    "\"position\"",
    "\"hold\"",
    "\"figure-eight\"",
    "\"paper-flip\"",
    "\"quadrotor\"",
    "\"attitude-stand\"",
    "\"free-rigid-body\"",
    "\"pd-projection\"",
    "\"multirotor\"",
    "\"crazyflie\"",
    "\"hummingbird\"",
    "\"dryden\"",
    "\"ladder\"",
    "\"sinusoid\"",
    "\"constant\"",
    "[]",
    "[1, 2]",
    "[1.0, 2.0, 3.0]",
    "[nan, 0.0, 0.0]",
    "[0.0, 0.0, 0.0]",
    "[1e300, 1e300, 1e300]",
    "[[1,2,3]]",
    "true",
    "false",
    "{}",
    "{ kind = \"hold\" }",
    "1979-05-27T07:32:00Z",
    "'''multi'''",
    "\"\\u0000\"",
];

/// Keys of the schema (some nested), used to insert lines.
const KEYS: &[&str] = &[
    "name",
    "duration",
    "scalar",
    "backend",
    "kind",
    "dt",
    "tol",
    "rate",
    "timing",
    "sample",
    "mass",
    "inertia",
    "gravity",
    "arm",
    "c_tau_f",
    "stand_height",
    "rotation",
    "omega",
    "x",
    "v",
    "b1d",
    "k_r",
    "k_omega",
    "k_i",
    "sigma",
    "until",
    "mode",
    "thrust",
    "attitude",
    "position",
    "force",
    "moment",
    "params",
    "locate_events",
    "psi_below",
    "amplitude",
    "frequency",
    "center",
    "a",
    "b",
    "unknown_key",
];

const HEADERS: &[&str] = &[
    "[vehicle]",
    "[initial]",
    "[gains]",
    "[integrator]",
    "[control]",
    "[record]",
    "[disturbance]",
    "[[plan]]",
    "[plan.attitude]",
    "[plan.position]",
    "[vehicle.params]",
    "[[plan.attitude]]",
    "[",
    "[[",
    "[]",
];

#[derive(Clone, Debug)]
enum Mutation {
    DeleteLine(usize),
    DuplicateLine(usize),
    SwapLines(usize, usize),
    /// Replace what follows the first `=` of a line.
    ReplaceValue(usize, usize),
    InsertKey(usize, usize, usize),
    InsertHeader(usize, usize),
    /// Overwrite one byte (then repair to UTF-8 lossily).
    Byte(usize, u8),
    Truncate(usize),
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let i = any::<usize>();
    prop_oneof![
        i.prop_map(Mutation::DeleteLine),
        i.prop_map(Mutation::DuplicateLine),
        (i, i).prop_map(|(a, b)| Mutation::SwapLines(a, b)),
        (i, 0..TOKENS.len()).prop_map(|(a, t)| Mutation::ReplaceValue(a, t)),
        (i, 0..KEYS.len(), 0..TOKENS.len()).prop_map(|(a, k, t)| Mutation::InsertKey(a, k, t)),
        (i, 0..HEADERS.len()).prop_map(|(a, h)| Mutation::InsertHeader(a, h)),
        (i, any::<u8>()).prop_map(|(a, b)| Mutation::Byte(a, b)),
        i.prop_map(Mutation::Truncate),
    ]
}

fn apply(text: &str, m: &Mutation) -> String {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    if lines.is_empty() {
        lines.push(String::new());
    }
    let n = lines.len();
    match *m {
        Mutation::DeleteLine(i) => {
            lines.remove(i % n);
        }
        Mutation::DuplicateLine(i) => {
            let l = lines[i % n].clone();
            lines.insert(i % n, l);
        }
        Mutation::SwapLines(a, b) => lines.swap(a % n, b % n),
        Mutation::ReplaceValue(i, t) => {
            // The first line with a `=` at or after i, wrapping round.
            if let Some(j) = (0..n)
                .map(|k| (i + k) % n)
                .find(|&j| lines[j].contains('='))
            {
                let key = lines[j].split('=').next().unwrap_or_default().to_string();
                lines[j] = format!("{key}= {}", TOKENS[t]);
            }
        }
        Mutation::InsertKey(i, k, t) => {
            lines.insert(i % (n + 1), format!("{} = {}", KEYS[k], TOKENS[t]));
        }
        Mutation::InsertHeader(i, h) => lines.insert(i % (n + 1), HEADERS[h].to_string()),
        Mutation::Byte(i, b) => {
            let mut bytes = lines.join("\n").into_bytes();
            if !bytes.is_empty() {
                let k = i % bytes.len();
                bytes[k] = b;
            }
            return String::from_utf8_lossy(&bytes).into_owned();
        }
        Mutation::Truncate(i) => {
            let joined = lines.join("\n");
            let mut k = i % (joined.len() + 1);
            while !joined.is_char_boundary(k) {
                k -= 1;
            }
            return joined[..k].to_string();
        }
    }
    lines.join("\n")
}

/// A few mutations of one corpus entry.
fn mutated() -> impl Strategy<Value = String> {
    let n = corpus().len();
    (0..n, prop::collection::vec(mutation(), 1..6)).prop_map(|(k, ms)| {
        let mut text = corpus()[k].clone();
        for m in &ms {
            text = apply(&text, m);
        }
        text
    })
}

/// TOML-looking text from the schema's own words.
fn tomlish() -> impl Strategy<Value = String> {
    let line = prop_oneof![
        (0..KEYS.len(), 0..TOKENS.len()).prop_map(|(k, t)| format!("{} = {}", KEYS[k], TOKENS[t])),
        (0..HEADERS.len()).prop_map(|h| HEADERS[h].to_string()),
    ];
    prop::collection::vec(line, 0..25).prop_map(|v| v.join("\n"))
}

/// Outcome counts: rejected, accepted and ran, accepted and the run
/// returned an error. The campaign prints them so a generator that only
/// ever produces rejections shows up.
static COUNTS: [AtomicU64; 3] = [AtomicU64::new(0), AtomicU64::new(0), AtomicU64::new(0)];

/// The property: parse, and on success run a short stretch.
fn check(text: &str) -> Result<(), TestCaseError> {
    match Scene::from_toml(text, "fuzz.toml") {
        Err(e) => {
            COUNTS[0].fetch_add(1, Ordering::Relaxed);
            prop_assert!(!e.message.is_empty(), "empty message for {text:?}");
            prop_assert!(
                e.location
                    .as_deref()
                    .is_some_and(|l| l.starts_with("fuzz.toml:")),
                "rejection without a location: {e} for {text:?}"
            );
            // A validation error points at its key: the reported line names
            // it, or is a table header (the key's table, or the segment,
            // when the key is absent), or the key is nowhere in the text.
            if let (Some(key), Some(loc)) = (&e.key, &e.location) {
                let name = key.rsplit('.').next().unwrap_or(key);
                let line: usize = loc
                    .split(':')
                    .nth(1)
                    .and_then(|l| l.parse().ok())
                    .unwrap_or(0);
                let at = text.lines().nth(line.saturating_sub(1)).unwrap_or_default();
                prop_assert!(
                    at.contains(name) || at.trim_start().starts_with('[') || !text.contains(name),
                    "{e}: line {line} is {at:?}, not about `{key}`, in {text:?}"
                );
            }
        }
        Ok(mut scene) => {
            // Round trip: what we write we read back, equal.
            let again = Scene::from_toml(&scene.to_toml(), "again.toml");
            prop_assert!(
                again.as_ref() == Ok(&scene),
                "round trip changed the scene: {again:?} for {text:?}"
            );
            // A few steps only: the fuzzer checks for panics, not physics.
            let dt = scene.integrator.dt;
            scene.duration = scene.duration.min(5.0 * dt).min(0.02);
            scene.record.sample = scene.record.sample.max(scene.duration / 4.0);
            let out = scenes::run(
                &scene,
                RunOptions {
                    record: true,
                    ..Default::default()
                },
            );
            match out {
                Ok(out) => {
                    COUNTS[1].fetch_add(1, Ordering::Relaxed);
                    prop_assert!(out.last.t.is_finite());
                }
                Err(e) => {
                    COUNTS[2].fetch_add(1, Ordering::Relaxed);
                    prop_assert!(!e.to_string().is_empty());
                }
            }
        }
    }
    Ok(())
}

/// The seed of the short pass: fixed, so a run is repeatable and CI's
/// result does not depend on the day; `PROPTEST_RNG_SEED=N` runs another.
const SEED: u64 = 0x0005_CE7E_F022;

/// Where failing cases are kept: proptest re-runs them first on every
/// later run (commit the file if it ever appears).
const REGRESSIONS: &str = "tests/fuzz_scene.proptest-regressions";

/// Runs one property with the fixed seed (or `PROPTEST_RNG_SEED`) and the
/// regression file; a failure panics with the seed that reproduces it.
fn property<S: Strategy<Value = String>>(name: &str, strategy: S) {
    use proptest::test_runner::{FileFailurePersistence, RngSeed};
    let env = Config::default();
    let seed = match env.rng_seed {
        RngSeed::Fixed(s) => s,
        RngSeed::Random => SEED,
    };
    let config = Config {
        rng_seed: RngSeed::Fixed(seed),
        failure_persistence: Some(Box::new(FileFailurePersistence::Direct(REGRESSIONS))),
        ..env
    };
    let mut runner = TestRunner::new(config);
    if let Err(e) = runner.run(&strategy, |t| check(&t)) {
        panic!("{name}: {e}\nreproduce with PROPTEST_RNG_SEED={seed}");
    }
}

#[test]
fn mutated_scenes_never_panic() {
    property("mutated scenes", mutated());
}

#[test]
fn schema_words_never_panic() {
    property("schema words", tomlish());
}

#[test]
fn arbitrary_text_never_panics() {
    property("arbitrary text", ".{0,300}".prop_map(|s: String| s));
}

/// The long campaign: all three generators in turn, fresh seeds each round,
/// until `SCENE_FUZZ_SECS` (default 600) have passed. Prints the count.
#[test]
#[ignore = "a campaign of minutes; run by hand (see the file's docs)"]
fn fuzz_for_a_while() {
    let secs: u64 = std::env::var("SCENE_FUZZ_SECS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(600);
    let start = std::time::Instant::now();
    let mut cases = 0u64;
    let mut round = 0u64;
    while start.elapsed().as_secs() < secs {
        let mut seed = [0u8; 32];
        seed[..8].copy_from_slice(&round.to_le_bytes());
        seed[8..16].copy_from_slice(&0x0005_CE7E_F022_u64.to_le_bytes());
        let config = Config {
            cases: 500,
            failure_persistence: None,
            ..Config::default()
        };
        let rng = TestRng::from_seed(RngAlgorithm::ChaCha, &seed);
        let mut runner = TestRunner::new_with_rng(config, rng);
        let result = match round % 3 {
            0 => runner.run(&mutated(), |t| check(&t)),
            1 => runner.run(&tomlish(), |t| check(&t)),
            _ => runner.run(&".{0,300}", |t: String| check(&t)),
        };
        if let Err(e) = result {
            let seed: String = seed.iter().map(|b| format!("{b:02x}")).collect();
            panic!("round {round} (ChaCha seed {seed}): {e}");
        }
        cases += 500;
        round += 1;
    }
    let [rejected, ran, run_err] = COUNTS.each_ref().map(|c| c.load(Ordering::Relaxed));
    println!(
        "scene fuzzing: {cases} cases in {:.0} s ({round} rounds), no failure: \
         {rejected} rejected with a location, {ran} accepted and ran, \
         {run_err} accepted and the run returned an error",
        start.elapsed().as_secs_f64()
    );
}

/// The shipped paper-flip file with one line replaced.
fn flip_with(line_start: &str, replacement: &str) -> String {
    let text = include_str!("../scenes/paper-flip.toml");
    let mut found = false;
    let out: Vec<String> = text
        .lines()
        .map(|l| {
            if !found && l.trim_start().starts_with(line_start) {
                found = true;
                replacement.to_string()
            } else {
                l.to_string()
            }
        })
        .collect();
    assert!(found, "no line starting with {line_start:?}");
    out.join("\n")
}

fn rejected_at(text: &str) -> (String, usize) {
    let e = Scene::from_toml(text, "f.toml").expect_err("must be rejected");
    let loc = e
        .location
        .clone()
        .unwrap_or_else(|| panic!("no location: {e}"));
    let line: usize = loc.split(':').nth(1).unwrap().parse().unwrap();
    (e.message, line)
}

fn line_of(text: &str, needle: &str) -> usize {
    text.lines().position(|l| l.contains(needle)).unwrap() + 1
}

/// Found by the campaign: a figure-eight with `a = nan` was accepted (the
/// reference parameters were not checked) and failed only mid-run.
#[test]
fn found_nan_in_a_reference_parameter() {
    let mut scene = builtin::figure_eight();
    let text = scene.to_toml().replace("\na = 1.0", "\na = nan");
    assert_ne!(text, scene.to_toml());
    let (msg, line) = rejected_at(&text);
    assert!(msg.contains("`a` = NaN"), "{msg}");
    assert_eq!(line, line_of(&text, "a = nan"));
    // Every reference parameter, through the struct as well.
    if let Some(scenes::scene::PositionRef::FigureEight { omega, .. }) = &mut scene.plan[0].position
    {
        *omega = f64::INFINITY;
    }
    let (key, msg) = scene.validate().unwrap_err();
    assert_eq!(key, "omega", "{msg}");
    scene.plan[0].position = Some(scenes::scene::PositionRef::Sinusoids {
        center: [0.0; 3],
        amplitude: [1.0; 3],
        omega: [1.0; 3],
        phase: [0.0, f64::NAN, 0.0],
    });
    let (key, msg) = scene.validate().unwrap_err();
    assert_eq!(key, "phase", "{msg}");
    assert!(msg.contains("NaN"), "{msg}");
}

/// Found by the campaign: `[vehicle.params]` on a built-in kind was
/// rejected without a location (the key is a table header, not `key =`).
#[test]
fn found_table_header_errors_have_a_location() {
    let text = flip_with("gravity", "[vehicle.params]\ngravity = 9.81");
    let (msg, line) = rejected_at(&text);
    assert!(msg.contains("vehicle.params"), "{msg}");
    assert_eq!(line, line_of(&text, "[vehicle.params]"));
}

/// Found by the campaign: a segment missing its `until` was rejected
/// without a location; it now points at that segment's `[[plan]]`.
#[test]
fn found_missing_until_points_at_the_segment() {
    let text = flip_with("until", "");
    let (msg, line) = rejected_at(&text);
    assert!(msg.contains("plan[0] has no `until`"), "{msg}");
    assert_eq!(line, line_of(&text, "[[plan]]"));
}

/// Found while fixing the above: a segment switched by `until_psi` skipped
/// the checks of its mode and references.
#[test]
fn until_psi_segments_are_checked_like_any_other() {
    let mut scene = builtin::tumble_recovery();
    assert!(scene.plan[0].until_psi.is_some());
    scene.plan[0].attitude = None;
    let (key, msg) = scene.validate().unwrap_err();
    assert_eq!(key, "mode", "{msg}");
    assert!(msg.contains("plan[0]"), "{msg}");
}

/// Found by the campaign: `rate = nan` was accepted under continuous
/// control (where the rate is unused).
#[test]
fn found_nan_rate_under_continuous_control() {
    let text = flip_with("rate", "rate = nan");
    assert!(text.contains("timing = \"continuous\""));
    let (msg, line) = rejected_at(&text);
    assert!(msg.contains("rate` = NaN"), "{msg}");
    assert_eq!(line, line_of(&text, "rate = nan"));
}

/// Found by the campaign: `timing = "sampled"` without a `rate` line was
/// rejected without a location (the key is absent); it now points at
/// `[control]` and says what is missing.
#[test]
fn found_sampled_without_rate_points_at_control() {
    let text = flip_with("timing", "timing = \"sampled\"").replace("rate = 0.0", "");
    let (msg, line) = rejected_at(&text);
    assert!(msg.contains("needs a controller rate"), "{msg}");
    assert_eq!(line, line_of(&text, "[control]"));
}
