//! A firmware run against the host: reads the stored inputs and what the
//! Cortex-M4F image printed under QEMU (`scripts/flight.sh` writes
//! `target/firmware/qemu.txt`), runs the same C-ABI calls on the host for
//! every record (both laws) and every stream event (both filters), and
//! requires the two sides' output bits to be equal; then prints what the
//! calls cost on the target and fails when one needs more than its
//! instruction budget or the laws' stack more than 4 KB.
//!
//! Without the QEMU output there is nothing to compare: the test says so
//! and passes, unless `GEOPID_REQUIRE_FIRMWARE=1` (CI sets it, after
//! running `scripts/flight.sh`), when a missing file is a failure.

use geopid_control::vectors::{
    ESTIMATE_WORDS, EVENT_BYTES, Event, OUTPUT_WORDS, RECORD_BYTES, Record, apply, output_words,
    outputs_at,
};
use geopid_control::*;
use std::path::Path;

/// A full position-mode update (position law with its attitude law) in at
/// most 1 % of a 500 Hz tick on a 168 MHz core: 168e6 / 500 / 100.
const POSITION_BUDGET: f64 = 3360.0;
/// Stack budget of one update, bytes.
const STACK_BUDGET: usize = 4096;
/// The invariant EKF's predict: 15 % of a 1 kHz tick at 168 MHz.
const IEKF_PREDICT_BUDGET: f64 = 25_000.0;
/// Either complementary-filter update: what a Crazyflie-class loop spends
/// on its attitude estimate.
const COMPLEMENTARY_BUDGET: f64 = 2_000.0;

/// The host's words for one record, with the two statuses.
fn host_words(r: &Record) -> (i32, i32, [u32; OUTPUT_WORDS]) {
    let (v, pg, ag) = (
        gpc_paper_vehicle(),
        gpc_paper_position_gains(),
        gpc_paper_attitude_gains(),
    );
    let (mut p, mut a) = (GpcPositionOutput::default(), GpcAttitudeOutput::default());
    let ps = gpc_position_update(
        Some(&v),
        Some(&pg),
        Some(&ag),
        Some(&r.state),
        Some(&r.integrals),
        Some(&r.position),
        Some(&mut p),
    );
    let as_ = gpc_attitude_update(
        Some(&v),
        Some(&ag),
        Some(&r.state),
        Some(&r.integrals),
        Some(&r.attitude),
        Some(&mut a),
    );
    (ps as i32, as_ as i32, output_words(&p, &a))
}

/// `(min, max, sum, count)` of a `C` line.
fn cost(fields: &[&str]) -> Result<[f64; 4], String> {
    let mut out = [0.0; 4];
    for (o, f) in out.iter_mut().zip(fields) {
        *o = f.parse().map_err(|e| format!("cost field `{f}`: {e}"))?;
    }
    Ok(out)
}

/// The host's filters, replaying the stream as the image does.
struct HostFilters {
    events: Vec<Event>,
    iekf: GpcIekf,
    complementary: GpcComplementary,
    next: usize,
}

impl HostFilters {
    fn new(stream: &[u8]) -> Self {
        Self {
            events: stream
                .chunks_exact(EVENT_BYTES)
                .map(|c| Event::decode(c).expect("whole event"))
                .collect(),
            iekf: GpcIekf::default(),
            complementary: GpcComplementary::default(),
            next: 0,
        }
    }

    /// Checks the image's line for event `i` (statuses and words) against
    /// the host's run of the same event.
    fn check(&mut self, i: &str, statuses: [&str; 2], words: &[&str]) -> Result<(), String> {
        let i: usize = i.parse().map_err(|e| format!("event index `{i}`: {e}"))?;
        if i != self.next {
            return Err(format!("event {i} printed, {} expected", self.next));
        }
        let e = self
            .events
            .get(i)
            .ok_or(format!("event {i} is not in the stream"))?;
        let (si, sc) = apply(&mut self.iekf, &mut self.complementary, e);
        let host = outputs_at(&self.iekf, &self.complementary, e.time());
        let want = [(si as i32).to_string(), (sc as i32).to_string()];
        if statuses != [want[0].as_str(), want[1].as_str()] {
            return Err(format!(
                "event {i}: statuses {statuses:?} on the target, {want:?} on the host"
            ));
        }
        let target: Vec<u32> = words
            .iter()
            .map(|w| u32::from_str_radix(w, 16).map_err(|e| format!("word `{w}`: {e}")))
            .collect::<Result<_, _>>()?;
        if let Some(k) = (0..ESTIMATE_WORDS).find(|&k| target.get(k) != Some(&host[k])) {
            return Err(format!(
                "event {i}, word {k}: target {:?}, host {:08x} ({})",
                target.get(k).map(|w| format!("{w:08x}")),
                host[k],
                f32::from_bits(host[k])
            ));
        }
        self.next += 1;
        Ok(())
    }
}

fn compare(vectors: &[u8], stream: &[u8], printed: &str) -> Result<(), String> {
    let mut filters = HostFilters::new(stream);
    let (mut filter_stack, mut filter_done) = (None, None);
    let records: Vec<Record> = vectors
        .chunks_exact(RECORD_BYTES)
        .map(|c| Record::decode(c).expect("whole record"))
        .collect();
    let (mut matched, mut costs, mut stack, mut done) = (0usize, Vec::new(), None, None);
    for line in printed.lines() {
        let f: Vec<&str> = line.split_whitespace().collect();
        match f.as_slice() {
            ["R", i, ps, as_, words @ ..] => {
                let i: usize = i.parse().map_err(|e| format!("record index `{i}`: {e}"))?;
                let r = records
                    .get(i)
                    .ok_or(format!("record {i} is not in the vectors"))?;
                let target: Vec<u32> = words
                    .iter()
                    .map(|w| u32::from_str_radix(w, 16).map_err(|e| format!("word `{w}`: {e}")))
                    .collect::<Result<_, _>>()?;
                let (hps, has, host) = host_words(r);
                if (ps.parse::<i32>().ok(), as_.parse::<i32>().ok()) != (Some(hps), Some(has)) {
                    return Err(format!(
                        "record {i}: statuses {ps} {as_} on the target, {hps} {has} on the host"
                    ));
                }
                if let Some(k) = (0..OUTPUT_WORDS).find(|&k| target.get(k) != Some(&host[k])) {
                    return Err(format!(
                        "record {i}, word {k}: target {:?}, host {:08x} ({})",
                        target.get(k).map(|w| format!("{w:08x}")),
                        host[k],
                        f32::from_bits(host[k])
                    ));
                }
                matched += 1;
            }
            ["C", name, rest @ ..] => costs.push((name.to_string(), cost(rest)?)),
            ["E", i, si, sc, words @ ..] => filters.check(i, [*si, *sc], words)?,
            ["S", "stack", b] => stack = b.parse::<usize>().ok(),
            ["S", "filters", b] => filter_stack = b.parse::<usize>().ok(),
            ["D", n] => done = n.parse::<usize>().ok(),
            ["F", n] => filter_done = n.parse::<usize>().ok(),
            _ => {}
        }
    }
    if done != Some(records.len()) || matched != records.len() {
        return Err(format!(
            "the image compared {matched} of {} records (done line: {done:?})",
            records.len()
        ));
    }
    println!(
        "{matched} records: every output word of both laws equal on the Cortex-M4F and the host"
    );
    let events = filters.events.len();
    if filter_done != Some(events) || filters.next != events {
        return Err(format!(
            "the image compared {} of {events} stream events (done line: {filter_done:?})",
            filters.next
        ));
    }
    println!(
        "{events} stream events: both filters' estimates and the invariant EKF's covariance \
         diagonal equal on the Cortex-M4F and the host"
    );
    println!(
        "stack high-water of a filter call: {} B",
        filter_stack.ok_or("no filters' stack line")?
    );
    report(&costs, stack)
}

fn report(costs: &[(String, [f64; 4])], stack: Option<usize>) -> Result<(), String> {
    let cal = costs
        .iter()
        .find(|(n, _)| n == "calibration")
        .map(|(_, c)| c[2] / c[3] / 1000.0)
        .ok_or("no calibration line")?;
    println!("SysTick ticks per instruction (1 000 nops): {cal:.5}");
    println!(
        "{:<20} {:>12} {:>12} {:>12}",
        "call", "min instr", "mean instr", "max instr"
    );
    let mut position = None;
    for (name, [min, max, sum, n]) in costs.iter().filter(|(n, _)| n != "calibration") {
        let mean = sum / n / cal;
        println!(
            "{name:<20} {:>12.0} {mean:>12.0} {:>12.0}",
            min / cal,
            max / cal
        );
        let budget = match name.as_str() {
            "position" => {
                position = Some(max / cal);
                None
            }
            "iekf-imu" => Some(IEKF_PREDICT_BUDGET),
            "complementary-imu" | "complementary-mocap" => Some(COMPLEMENTARY_BUDGET),
            _ => None,
        };
        if let Some(b) = budget.filter(|b| max / cal > *b) {
            return Err(format!(
                "{name}: {:.0} instructions > budget {b}",
                max / cal
            ));
        }
    }
    let stack = stack.ok_or("no stack line")?;
    println!("stack high-water of an update: {stack} B");
    let position = position.ok_or("no position line")?;
    if position > POSITION_BUDGET {
        return Err(format!(
            "position update {position:.0} instructions > budget {POSITION_BUDGET}"
        ));
    }
    if stack > STACK_BUDGET {
        return Err(format!("stack {stack} B > budget {STACK_BUDGET} B"));
    }
    println!(
        "within budget: position update ≤ {POSITION_BUDGET} instructions, stack ≤ {STACK_BUDGET} B"
    );
    Ok(())
}

#[test]
fn firmware_outputs_equal_the_host_bit_for_bit() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let vectors = root.join("firmware/vectors/paper-flip-f32.bin");
    let printed = root.join("target/firmware/qemu.txt");
    let required = std::env::var("GEOPID_REQUIRE_FIRMWARE").is_ok_and(|v| v == "1");
    let Ok(text) = std::fs::read_to_string(&printed) else {
        assert!(
            !required,
            "{} is missing: scripts/flight.sh did not run",
            printed.display()
        );
        println!(
            "no {}: run scripts/flight.sh to compare a firmware run",
            printed.display()
        );
        return;
    };
    let v = std::fs::read(&vectors).expect("the stored inputs");
    let stream =
        std::fs::read(root.join("firmware/vectors/estimators-f32.bin")).expect("the stored stream");
    if let Err(e) = compare(&v, &stream, &text) {
        panic!("{e}");
    }
}
