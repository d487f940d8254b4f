//! CSV and MCAP output, read back independently.

use std::collections::BTreeMap;

use logs::{CSV_HEADER, TOPICS, write_csv, write_mcap};
use scenarios::RunOptions;
use scenes::{builtin, run};

fn tmpdir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("gpid-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// A protobuf field as it sits on the wire.
#[derive(Debug)]
enum Wire<'a> {
    Varint(u64),
    F64(f64),
    Bytes(&'a [u8]),
}

/// The fields of a protobuf message, read straight from the wire format
/// (varint keys; wire types 0, 1, 2): independent of the encoder.
fn wire(mut b: &[u8]) -> Vec<(u32, Wire<'_>)> {
    fn varint(b: &mut &[u8]) -> u64 {
        let mut v = 0u64;
        for shift in (0..64).step_by(7) {
            let byte = b[0];
            *b = &b[1..];
            v |= u64::from(byte & 0x7f) << shift;
            if byte < 0x80 {
                break;
            }
        }
        v
    }
    let mut out = Vec::new();
    while !b.is_empty() {
        let key = varint(&mut b);
        let field = (key >> 3) as u32;
        let w = match key & 7 {
            0 => Wire::Varint(varint(&mut b)),
            1 => {
                let (x, rest) = b.split_at(8);
                b = rest;
                Wire::F64(f64::from_le_bytes(x.try_into().unwrap()))
            }
            2 => {
                let n = varint(&mut b) as usize;
                let (x, rest) = b.split_at(n);
                b = rest;
                Wire::Bytes(x)
            }
            t => panic!("wire type {t} not expected here"),
        };
        out.push((field, w));
    }
    out
}

/// Field `k` as a double (0 when absent: proto3 omits zeros).
fn f64_field(fields: &[(u32, Wire<'_>)], k: u32) -> f64 {
    fields
        .iter()
        .find_map(|(f, w)| match (f, w) {
            (f, Wire::F64(x)) if *f == k => Some(*x),
            _ => None,
        })
        .unwrap_or(0.0)
}

/// Field `k` as a nested message's fields.
fn msg_field<'a>(fields: &[(u32, Wire<'a>)], k: u32) -> Vec<(u32, Wire<'a>)> {
    fields
        .iter()
        .find_map(|(f, w)| match (f, w) {
            (f, Wire::Bytes(x)) if *f == k => Some(wire(x)),
            _ => None,
        })
        .unwrap_or_default()
}

fn vec3_field(fields: &[(u32, Wire<'_>)], k: u32) -> [f64; 3] {
    let v = msg_field(fields, k);
    [f64_field(&v, 1), f64_field(&v, 2), f64_field(&v, 3)]
}

/// At t = 1 s: the pose's quaternion is unit and is the sample's R; the
/// errors, command and integrals carry the sample's values bit for bit
/// (field numbers in declaration order); the switch and the mode channel
/// say what the run did.
fn values_match_the_samples(bytes: &[u8], out: &scenarios::RunOutput) {
    use foxglove::Decode;
    use foxglove::messages::PoseInFrame;
    let s = studies::metrics::at(&out.samples, 1.0).unwrap();
    let at = |topic: &str| {
        mcap::MessageStream::new(bytes)
            .unwrap()
            .map(|m| m.unwrap())
            .find(|m| m.channel.topic == topic && m.log_time == 1_000_000_000)
            .unwrap_or_else(|| panic!("{topic} at t = 1 s"))
            .data
            .into_owned()
    };
    let pose = PoseInFrame::decode(&at("/vehicle/pose")[..]).unwrap();
    let q = pose.pose.unwrap().orientation.unwrap();
    let norm = q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w;
    assert!((norm - 1.0).abs() < 1e-12);
    assert_eq!(logs::quaternion_xyzw(&s.r), [q.x, q.y, q.z, q.w]);
    let e = at("/errors");
    let e = wire(&e);
    assert_eq!(f64_field(&e, 1), s.psi);
    assert_eq!(f64_field(&e, 2), s.ex);
    assert_eq!(vec3_field(&e, 4), s.omega);
    assert_eq!(vec3_field(&e, 5), s.omega_d);
    let c = at("/command");
    let c = wire(&c);
    assert_eq!(f64_field(&c, 1), s.thrust);
    assert_eq!(vec3_field(&c, 2), s.moment);
    // Repeated doubles, packed or one field each: both are valid protobuf.
    let rotors: Vec<f64> = c
        .iter()
        .flat_map(|(f, w)| match (f, w) {
            (3, Wire::Bytes(b)) => b
                .chunks(8)
                .map(|x| f64::from_le_bytes(x.try_into().unwrap()))
                .collect(),
            (3, Wire::F64(x)) => vec![*x],
            _ => vec![],
        })
        .collect();
    assert_eq!(rotors, s.rotors);
    let i = at("/integrals");
    let i = wire(&i);
    assert_eq!(vec3_field(&i, 1), s.e_att);
    assert_eq!(vec3_field(&i, 2), s.e_pos);
    // The switch at 0.4 s: from segment 0 (omitted: proto3 drops zeros)
    // to 1, position mode.
    let sw = mcap::MessageStream::new(bytes)
        .unwrap()
        .map(|m| m.unwrap())
        .filter(|m| m.channel.topic == "/mode")
        .nth(1)
        .expect("the switch");
    let sw = wire(&sw.data);
    assert!(
        sw.iter()
            .any(|(f, w)| *f == 3 && matches!(w, Wire::Varint(1))),
        "{sw:?}"
    );
    assert_eq!(f64_field(&sw, 1), 0.4);
    // The mode channel: the first mode at t = 0 with its name.
    let m = mcap::MessageStream::new(bytes)
        .unwrap()
        .map(|m| m.unwrap())
        .find(|m| m.channel.topic == "/mode")
        .unwrap();
    let m = wire(&m.data);
    assert!(
        m.iter()
            .any(|(f, w)| *f == 4 && matches!(w, Wire::Bytes(b) if *b == b"attitude")),
        "{m:?}"
    );
}

#[test]
fn mcap_reads_back_with_the_expected_channels_schemas_and_counts() {
    use foxglove::Decode;
    use foxglove::messages::{FrameTransform, PoseInFrame};
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
        assert_eq!(msg.channel.message_encoding, "protobuf");
        let schema = msg
            .channel
            .schema
            .as_ref()
            .expect("every channel has a schema");
        assert_eq!(schema.encoding, "protobuf");
        assert!(!schema.data.is_empty(), "{topic}: a FileDescriptorSet");
        schemas.insert(topic.clone(), schema.name.clone());
        // Foxglove's own types decode with Foxglove's decoder.
        match topic.as_str() {
            "/vehicle/pose" | "/desired/pose" => {
                let p = PoseInFrame::decode(&msg.data[..]).unwrap();
                assert_eq!(p.frame_id, "ned");
                let ts = p.timestamp.unwrap();
                assert_eq!(
                    u64::from(ts.sec()) * 1_000_000_000 + u64::from(ts.nsec()),
                    msg.log_time
                );
            }
            "/tf" => {
                let tf = FrameTransform::decode(&msg.data[..]).unwrap();
                if tf.child_frame_id == "ned" {
                    assert_eq!(tf.parent_frame_id, "world");
                    world_ned.push(msg.log_time);
                } else {
                    assert_eq!(
                        (tf.parent_frame_id.as_str(), tf.child_frame_id.as_str()),
                        ("ned", "body")
                    );
                }
            }
            _ => assert!(!wire(&msg.data).is_empty() || topic == "/mode"),
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
        ("/errors", n, "errors.Errors"),
        ("/command", n, "command.Command"),
        ("/integrals", n, "integrals.Integrals"),
        ("/mode", 1 + out.switches.len(), "modeswitch.ModeSwitch"),
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
    values_match_the_samples(&bytes, &out);
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
    scene.duration = 0.5; // past the switch at 0.4 s: no warning of its own
    let mut out = run(&scene, RunOptions::default()).unwrap();
    assert!(out.warnings.is_empty(), "{:?}", out.warnings);
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
    use logs::{CsvWriter, McapWriter, Sink, Tee, Watched};
    let scene = builtin::paper_flip();
    let kept = run(&scene, RunOptions::default()).unwrap();
    let dir = tmpdir("stream");
    write_csv(&dir.join("kept.csv"), &kept).unwrap();
    write_mcap(&dir.join("kept.mcap"), &kept).unwrap();

    let mut csv = CsvWriter::create(&dir.join("streamed.csv")).unwrap();
    let mut mcap = McapWriter::create(&dir.join("streamed.mcap")).unwrap();
    let mut tee = Watched::new(Tee(vec![&mut csv as &mut dyn Sink, &mut mcap]));
    let streamed = run(
        &scene,
        RunOptions {
            record: false,
            sink: Some(&mut tee),
            ..Default::default()
        },
    )
    .unwrap();
    assert_eq!(tee.last_t, Some(kept.samples.last().unwrap().t));
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
    let t = out.interrupted_at().expect("interrupted");
    // Progress is reported after each step and the flag is read right
    // after it: the run stops at the step where it was set.
    let set_at = set_at.unwrap();
    assert!(
        (t - set_at).abs() < 1e-12,
        "set at {set_at}, stopped at {t}"
    );
    assert_eq!(out.samples.last().unwrap().t, t);
    assert_eq!(out.last.t, t);
    assert!(out.samples.windows(2).all(|w| w[0].t < w[1].t));
}

/// A work-precision point's CSV row has a field per column and reads back
/// to the point exactly.
#[test]
fn a_work_point_row_reads_back() {
    use studies::metrics::WorkPoint;
    let p = WorkPoint {
        kind: "rkmk4".into(),
        param: 2.5e-3,
        steps: 4001,
        evals: 16004,
        wall: 0.1 + 0.2,
        error: 1.0 / 3.0 * 1e-9,
    };
    let cols: Vec<&str> = WorkPoint::CSV_COLUMNS.split(',').collect();
    let row = p.csv_row();
    let f: Vec<&str> = row.split(',').collect();
    assert_eq!(f.len(), cols.len(), "{row}");
    let back = WorkPoint {
        kind: f[0].into(),
        param: f[1].parse().unwrap(),
        steps: f[2].parse().unwrap(),
        evals: f[3].parse().unwrap(),
        wall: f[4].parse().unwrap(),
        error: f[5].parse().unwrap(),
    };
    assert_eq!(back, p);
}

/// Tables as a log: one channel per table, every row a JSON message whose
/// numbers read back as the CSV's, an empty numeric cell as `null` (and
/// the schema allowing it), a text column as strings; a short row is an
/// error naming the table and line, leaving no file behind.
#[test]
fn tables_read_back_from_the_log() {
    use logs::{Table, write_tables};
    let dir = tmpdir("tables");
    let path = dir.join("t.mcap");
    let summary = "name,median_ns,ratio\nposition \"update\",150.25,1.25\nstep,9e3,\n";
    let points = "integrator,steps,error\nrk4,4004,1.1e-8\neuler,+1,.5\n";
    let tables = [
        Table {
            topic: "/bench/summary",
            schema: "gpid.BenchRow",
            csv: summary,
        },
        Table {
            topic: "/bench/work_precision",
            schema: "gpid.WorkPrecisionPoint",
            csv: points,
        },
    ];
    assert_eq!(write_tables(&path, 1_000, &tables).unwrap(), 4);
    let bytes = std::fs::read(&path).unwrap();
    let mut seen = Vec::new();
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        let schema = m.channel.schema.as_ref().unwrap();
        let text = String::from_utf8(m.data.to_vec()).unwrap();
        seen.push((
            m.channel.topic.clone(),
            m.log_time,
            String::from_utf8(schema.data.to_vec()).unwrap(),
            text,
        ));
    }
    assert_eq!(seen.len(), 4);
    assert_eq!(seen[0].0, "/bench/summary");
    assert_eq!(
        seen[0].3,
        r#"{"name":"position \"update\"","median_ns":150.25,"ratio":1.25}"#
    );
    assert_eq!(seen[1].3, r#"{"name":"step","median_ns":9e3,"ratio":null}"#);
    assert!(
        seen[0].2.contains(r#""ratio":{"type":["number","null"]}"#),
        "{}",
        seen[0].2
    );
    assert!(
        seen[0].2.contains(r#""median_ns":{"type":"number"}"#),
        "{}",
        seen[0].2
    );
    assert!(
        seen[0].2.contains(r#""name":{"type":"string"}"#),
        "{}",
        seen[0].2
    );
    assert_eq!(seen[2].0, "/bench/work_precision");
    assert_eq!(
        seen[2].3,
        r#"{"integrator":"rk4","steps":4004,"error":1.1e-8}"#
    );
    // Numbers f64 reads but JSON does not, reformatted.
    assert_eq!(
        seen[3].3,
        r#"{"integrator":"euler","steps":1.0,"error":0.5}"#
    );
    assert_eq!(
        seen.iter().map(|s| s.1).collect::<Vec<_>>(),
        [1_001, 1_002, 1_003, 1_004]
    );

    let bad = [Table {
        topic: "/t",
        schema: "s",
        csv: "a,b\n1,2\n3\n",
    }];
    let e = write_tables(&dir.join("bad.mcap"), 0, &bad).unwrap_err();
    assert!(e.message.contains("/t: line 3"), "{e}");
    assert!(!dir.join("bad.mcap").exists() && !dir.join("bad.mcap.partial").exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn the_reference_path_is_a_line_strip_per_segment_in_the_log() {
    use foxglove::Decode;
    use foxglove::messages::{SceneUpdate, line_primitive};
    let scene = builtin::mission_takeoff_waypoints_land();
    let out = run(&scene, RunOptions::default()).unwrap();
    let dir = tmpdir("path");
    let path = dir.join("mission.mcap");
    write_mcap(&path, &out).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    let found: Vec<_> = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(Result::unwrap)
        .filter(|m| m.channel.topic == logs::REFERENCE_TOPIC)
        .collect();
    assert_eq!(found.len(), 1);
    let m = &found[0];
    assert_eq!(m.log_time, 0, "shown from the start");
    assert_eq!(
        m.channel.schema.as_ref().unwrap().name,
        "foxglove.SceneUpdate"
    );
    let update = SceneUpdate::decode(&m.data[..]).unwrap();
    // Take-off, the loop and the landing draw a line each; motors-off
    // holds no position and draws none.
    let ids: Vec<_> = update.entities.iter().map(|e| e.id.as_str()).collect();
    assert_eq!(ids, ["segment 0", "segment 1", "segment 2"]);
    for (k, e) in update.entities.iter().enumerate() {
        assert_eq!(e.frame_id, "ned");
        let line = &e.lines[0];
        assert_eq!(line.r#type, line_primitive::Type::LineStrip as i32);
        // Every point is a sample's x_d in that segment, in order, the
        // first one first.
        let xd: Vec<[f64; 3]> = out
            .samples
            .iter()
            .filter(|s| s.segment == k)
            .map(|s| s.xd)
            .collect();
        let mut at = 0;
        for p in &line.points {
            let q = [p.x, p.y, p.z];
            at += xd[at..]
                .iter()
                .position(|x| *x == q)
                .expect("a sample's x_d");
        }
        let p0 = &line.points[0];
        assert_eq!([p0.x, p0.y, p0.z], xd[0]);
    }
    // The take-off climbs 1 m straight up from where the vehicle rested.
    let up = &update.entities[0].lines[0].points;
    let (a, b) = (&up[0], up.last().unwrap());
    assert!((a.z - b.z - 1.0).abs() < 1e-9 && a.x == b.x && a.y == b.y);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn the_mcap_holds_a_filters_sigmas_and_nis() {
    let mut scene = builtin::hover_estimated();
    scene.duration = 1.0;
    let out = scenes::run(&scene, Default::default()).unwrap();
    let path = std::env::temp_dir().join(format!("geopid-est-diag-{}.mcap", std::process::id()));
    logs::write_mcap(&path, &out).unwrap();
    let bytes = std::fs::read(&path).unwrap();
    std::fs::remove_file(&path).ok();
    let diag: Vec<Vec<u8>> = mcap::MessageStream::new(&bytes)
        .unwrap()
        .map(|m| m.unwrap())
        .filter(|m| m.channel.topic == "/estimate/diagnostics")
        .map(|m| m.data.into_owned())
        .collect();
    // One message per record sample; the last one's fields (σ, NIS, its
    // degrees of freedom) are the run's last readout.
    assert_eq!(diag.len(), out.samples.len());
    let fields = wire(diag.last().unwrap());
    // σ: field 1, packed or one double per element.
    let sigma: Vec<f64> = fields
        .iter()
        .flat_map(|(f, w)| match (f, w) {
            (1, Wire::Bytes(b)) => b
                .chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                .collect(),
            (1, Wire::F64(x)) => vec![*x],
            _ => vec![],
        })
        .collect();
    let dof = fields.iter().find_map(|(f, w)| match (f, w) {
        (3, Wire::Varint(v)) => Some(*v),
        _ => None,
    });
    let want = out.last.sensors.as_deref().unwrap().diagnostics.unwrap();
    let (nis, k) = want.nis.unwrap();
    assert_eq!(sigma, want.sigma[..want.states].to_vec());
    assert_eq!((f64_field(&fields, 2), dof), (nis, Some(k as u64)));
    let innovation: Vec<f64> = fields
        .iter()
        .flat_map(|(f, w)| match (f, w) {
            (4, Wire::Bytes(b)) => b
                .chunks_exact(8)
                .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
                .collect(),
            (4, Wire::F64(x)) => vec![*x],
            _ => vec![],
        })
        .collect();
    assert_eq!(innovation, want.innovation[..k].to_vec());
    // After 1 s of 1 cm frames at 100 Hz the position σ is a few mm.
    assert!(
        sigma.len() == 15 && sigma[0] > 1e-4 && sigma[0] < 5e-3,
        "{sigma:?}"
    );
}
