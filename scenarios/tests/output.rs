//! CSV and MCAP output, read back independently.

use std::collections::BTreeMap;

use scenarios::output::{CSV_HEADER, TOPICS, write_csv, write_mcap};
use scenarios::{RunOptions, builtin, run};

fn tmpdir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("gpid-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn mcap_reads_back_with_the_expected_channels_schemas_and_counts() {
    let scene = builtin::paper_flip();
    let out = run(&scene, RunOptions::default()).unwrap();
    let dir = tmpdir("mcap");
    let path = dir.join("flip.mcap");
    write_mcap(&path, &out).unwrap();
    assert!(
        !dir.join("flip.mcap.partial").exists(),
        "temporary file left behind"
    );
    let bytes = std::fs::read(&path).unwrap();

    let mut counts: BTreeMap<String, usize> = BTreeMap::new();
    let mut schemas: BTreeMap<String, String> = BTreeMap::new();
    let mut last_time: BTreeMap<String, u64> = BTreeMap::new();
    let mut world_ned: Vec<u64> = Vec::new();
    for msg in mcap::MessageStream::new(&bytes).unwrap() {
        let msg = msg.unwrap();
        let topic = msg.channel.topic.clone();
        assert_eq!(msg.channel.message_encoding, "json");
        let schema = msg
            .channel
            .schema
            .as_ref()
            .expect("every channel has a schema");
        assert_eq!(schema.encoding, "jsonschema");
        schemas.insert(topic.clone(), schema.name.clone());
        // Every message is valid JSON; log times never go backwards.
        let v: serde_json::Value = serde_json::from_slice(&msg.data).unwrap();
        assert!(v.is_object());
        if v["child_frame_id"] == "ned" {
            world_ned.push(msg.log_time);
        }
        let prev = last_time.insert(topic.clone(), msg.log_time).unwrap_or(0);
        assert!(msg.log_time >= prev, "{topic}: time went backwards");
        *counts.entry(topic).or_default() += 1;
    }
    let n = out.samples.len();
    assert_eq!(n, 2001, "4 s at 2 ms, both ends");
    let expect = [
        ("/vehicle/pose", n, "foxglove.PoseInFrame"),
        ("/desired/pose", n, "foxglove.PoseInFrame"),
        ("/tf", n + world_ned.len(), "foxglove.FrameTransform"),
        ("/errors", n, "gpid.Errors"),
        ("/command", n, "gpid.Command"),
        ("/integrals", n, "gpid.Integrals"),
        ("/mode", 1 + out.switches.len(), "gpid.ModeSwitch"),
    ];
    assert_eq!(expect.len(), TOPICS.len());
    for (topic, count, schema) in expect {
        assert_eq!(counts.get(topic), Some(&count), "{topic}");
        assert_eq!(
            schemas.get(topic).map(String::as_str),
            Some(schema),
            "{topic}"
        );
    }
    // The constant world → ned transform: with the first sample, then
    // never more than 0.1 s (plus one 2 ms sample interval) apart, and not
    // with every sample.
    assert_eq!(world_ned.first(), Some(&0));
    let gap = world_ned.windows(2).map(|w| w[1] - w[0]).max().unwrap();
    assert!(gap <= 102_000_000, "largest gap {gap} ns");
    assert!(world_ned.len() < n / 10, "{} of {n}", world_ned.len());
    // The summary section is there (the file was finished, not truncated).
    let summary = mcap::Summary::read(&bytes).unwrap().expect("summary");
    assert_eq!(summary.channels.len(), 7);
    assert_eq!(
        summary.stats.unwrap().message_count as usize,
        counts.values().sum::<usize>()
    );
    // A pose message carries a unit quaternion matching the sample's R.
    let first_pose = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| m.unwrap())
        .find(|m| m.channel.topic == "/vehicle/pose" && m.log_time == 1_000_000_000)
        .expect("pose at t = 1 s");
    let v: serde_json::Value = serde_json::from_slice(&first_pose.data).unwrap();
    let q = &v["pose"]["orientation"];
    let norm: f64 = ["x", "y", "z", "w"]
        .iter()
        .map(|k| q[k].as_f64().unwrap().powi(2))
        .sum();
    assert!((norm - 1.0).abs() < 1e-12);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn csv_has_the_fixed_header_and_round_trips_exactly() {
    let mut scene = builtin::paper_flip();
    scene.duration = 0.6; // across the switch
    let out = run(&scene, RunOptions::default()).unwrap();
    let dir = tmpdir("csv");
    let path = dir.join("flip.csv");
    write_csv(&path, &out).unwrap();
    assert!(!dir.join("flip.csv.partial").exists());
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next().unwrap(),
        "t,x1,x2,x3,v1,v2,v3,r11,r12,r13,r21,r22,r23,r31,r32,r33,w1,w2,w3,psi,ex,f,m1,m2,m3,mode"
    );
    assert_eq!(CSV_HEADER.split(',').count(), 26);
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), out.samples.len());
    for (row, s) in rows.iter().zip(&out.samples) {
        let f: Vec<&str> = row.split(',').collect();
        assert_eq!(f.len(), 26);
        let num = |i: usize| f[i].parse::<f64>().unwrap();
        // Exact round trip: Rust's `{}` prints the shortest repr that
        // parses back to the same f64.
        assert_eq!(num(0), s.t);
        assert_eq!([num(1), num(2), num(3)], s.x);
        assert_eq!(num(8), s.r[0][1], "r12 is row 1, column 2");
        assert_eq!(num(12), s.r[1][2], "r23 is row 2, column 3");
        assert_eq!(num(19), s.psi);
        assert_eq!(num(21), s.thrust);
        // At the switch instant the row shows the command about to act:
        // the new mode's.
        let mode = if s.t < 0.4 { "attitude" } else { "position" };
        assert_eq!(f[25], mode, "t = {}", s.t);
    }
    std::fs::remove_dir_all(dir).ok();
}

/// A run's warnings travel in its MCAP log as a `warnings` metadata record.
#[test]
fn warnings_are_a_metadata_record_in_the_mcap() {
    let mut scene = builtin::paper_flip();
    scene.duration = 0.1;
    let mut out = run(&scene, RunOptions::default()).unwrap();
    out.warnings.push("R has left SO(3)".into());
    let dir = tmpdir("mcap-warnings");
    let path = dir.join("w.mcap");
    write_mcap(&path, &out).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let mut found = Vec::new();
    for rec in mcap::read::LinearReader::new(&bytes).unwrap() {
        if let mcap::records::Record::Metadata(m) = rec.unwrap() {
            found.push((m.name.clone(), m.metadata.get("warning 1").cloned()));
        }
    }
    assert_eq!(
        found,
        vec![("warnings".to_string(), Some("R has left SO(3)".to_string()))]
    );
    std::fs::remove_dir_all(&dir).ok();
}

/// Streaming: a run that hands its samples to writers as it goes (keeping
/// none in memory) writes the same CSV, byte for byte, as writing the kept
/// samples afterwards; and the same MCAP messages.
#[test]
fn streamed_outputs_equal_the_written_ones() {
    use scenarios::output::{CsvWriter, McapWriter, Sink, Tee};
    let scene = builtin::paper_flip();
    let kept = run(&scene, RunOptions::default()).unwrap();
    let dir = tmpdir("stream");
    write_csv(&dir.join("kept.csv"), &kept).unwrap();
    write_mcap(&dir.join("kept.mcap"), &kept).unwrap();

    let mut csv = CsvWriter::create(&dir.join("streamed.csv")).unwrap();
    let mut mcap = McapWriter::create(&dir.join("streamed.mcap")).unwrap();
    let mut tee = Tee(vec![&mut csv as &mut dyn Sink, &mut mcap]);
    let streamed = run(
        &scene,
        RunOptions {
            record: false,
            sink: Some(&mut tee),
            ..Default::default()
        },
    )
    .unwrap();
    drop(tee);
    assert!(streamed.samples.is_empty(), "nothing kept in memory");
    assert_eq!(csv.finish().unwrap(), kept.samples.len() as u64);
    mcap.finish(&streamed.warnings, None).unwrap();
    assert_eq!(
        std::fs::read(dir.join("streamed.csv")).unwrap(),
        std::fs::read(dir.join("kept.csv")).unwrap()
    );
    let messages = |name: &str| -> Vec<(String, u64, Vec<u8>)> {
        let bytes = std::fs::read(dir.join(name)).unwrap();
        mcap::MessageStream::new(&bytes)
            .unwrap()
            .map(|m| {
                let m = m.unwrap();
                (m.channel.topic.clone(), m.log_time, m.data.to_vec())
            })
            .collect()
    };
    assert_eq!(messages("streamed.mcap"), messages("kept.mcap"));
    std::fs::remove_dir_all(&dir).ok();
}

/// A cancel flag stops the run at the current step with a last sample
/// there, and says so.
#[test]
fn cancel_stops_at_the_current_step() {
    use std::sync::atomic::{AtomicBool, Ordering};
    let scene = builtin::paper_flip();
    let cancel = AtomicBool::new(false);
    // Set it from the progress callback once a quarter of the run is done.
    let mut set_at = None;
    let mut progress = |f: f64| {
        if f >= 0.25 && set_at.is_none() {
            cancel.store(true, Ordering::Relaxed);
            set_at = Some(f * scene.duration);
        }
    };
    let out = run(
        &scene,
        RunOptions {
            progress: Some(&mut progress),
            cancel: Some(&cancel),
            ..Default::default()
        },
    )
    .unwrap();
    let t = out.interrupted_at.expect("interrupted");
    // The flag is seen after the next step.
    let set_at = set_at.unwrap();
    assert!(
        (t - (set_at + scene.integrator.dt)).abs() < 1e-12,
        "set at {set_at}, stopped at {t}"
    );
    assert_eq!(out.samples.last().unwrap().t, t);
    assert_eq!(out.last.t, t);
    assert!(out.samples.windows(2).all(|w| w[0].t < w[1].t));
}
