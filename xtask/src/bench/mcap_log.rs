//! `target/bench/bench.mcap`: the benchmark points as a log (JSON with
//! JSON schemas), readable with the same tools as the flight logs.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use serde_json::json;

use super::Row;
use crate::sweep::Point;

/// Writes `rows` and the work-precision points `wp` to `path` (through a
/// `.partial` file renamed when complete).
pub fn write_mcap(
    path: &Path,
    rows: &[Row],
    wp: &[(String, &str, Point)],
) -> Result<(), mcap::McapError> {
    let tmp = path.with_extension("mcap.partial");
    let file = BufWriter::new(File::create(&tmp)?);
    let mut w = mcap::WriteOptions::new()
        .compression(Some(mcap::Compression::Lz4))
        .profile("")
        .create(file)?;
    let num = r#"{"type":"number"}"#;
    let nnum = r#"{"type":["number","null"]}"#;
    let string = r#"{"type":"string"}"#;
    let schema = |title: &str, fields: &[(&str, &str)]| {
        let props: Vec<String> = fields
            .iter()
            .map(|(k, t)| format!(r#""{k}":{t}"#))
            .collect();
        let req: Vec<String> = fields.iter().map(|(k, _)| format!(r#""{k}""#)).collect();
        format!(
            r#"{{"title":"{title}","type":"object","properties":{{{}}},"required":[{}]}}"#,
            props.join(","),
            req.join(",")
        )
    };
    let s1 = w.add_schema(
        "gpid.BenchRow",
        "jsonschema",
        schema(
            "gpid.BenchRow",
            &[
                ("name", string),
                ("backend", string),
                ("scalar", string),
                ("median_ns", num),
                ("baseline_ns", nnum),
                ("ratio", nnum),
            ],
        )
        .as_bytes(),
    )?;
    let s2 = w.add_schema(
        "gpid.WorkPrecisionPoint",
        "jsonschema",
        schema(
            "gpid.WorkPrecisionPoint",
            &[
                ("scene", string),
                ("backend", string),
                ("scalar", string),
                ("integrator", string),
                ("param", num),
                ("steps", num),
                ("evaluations", num),
                ("wall_s", num),
                ("error", num),
            ],
        )
        .as_bytes(),
    )?;
    let meta = BTreeMap::new();
    let c1 = w.add_channel(s1, "/bench/summary", "json", &meta)?;
    let c2 = w.add_channel(s2, "/bench/work_precision", "json", &meta)?;
    // Stamped with the time of the run: files from several runs line up on
    // one timeline.
    let now = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos() as u64);
    let mut seq = 0u32;
    let mut put = |w: &mut mcap::Writer<BufWriter<File>>, ch: u16, v: serde_json::Value| {
        seq += 1;
        w.write_to_known_channel(
            &mcap::records::MessageHeader {
                channel_id: ch,
                sequence: seq,
                log_time: now + u64::from(seq),
                publish_time: now + u64::from(seq),
            },
            v.to_string().as_bytes(),
        )
    };
    for r in rows {
        let ratio = r.baseline_ns.map(|b| r.median_ns / b);
        put(
            &mut w,
            c1,
            json!({"name": r.name, "backend": r.backend, "scalar": r.scalar,
                   "median_ns": r.median_ns, "baseline_ns": r.baseline_ns, "ratio": ratio}),
        )?;
    }
    for (scene, pair, p) in wp {
        let (backend, scalar) = pair.split_once('-').unwrap_or((pair, ""));
        put(
            &mut w,
            c2,
            json!({"scene": scene, "backend": backend, "scalar": scalar, "integrator": p.kind,
                   "param": p.param, "steps": p.steps, "evaluations": p.evals,
                   "wall_s": p.wall, "error": p.error}),
        )?;
    }
    w.finish()?;
    drop(w);
    std::fs::rename(&tmp, path)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::{Row, Variant, parse};

    /// The log reads back: both channels, every message valid JSON with the
    /// fields its schema requires.
    #[test]
    fn bench_log_reads_back() {
        let dir = std::env::temp_dir().join(format!("gpid-bench-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("bench.mcap");
        let rows = vec![Row {
            name: "position update".into(),
            backend: "glam".into(),
            scalar: "f64".into(),
            median_ns: 150.0,
            baseline_ns: Some(120.0),
        }];
        let wp = vec![(
            "paper-flip".to_string(),
            "glam-f64",
            Point {
                kind: "rk4".into(),
                param: 1e-3,
                steps: 4004,
                evals: 16020,
                wall: 3e-3,
                error: 1e-8,
            },
        )];
        write_mcap(&path, &rows, &wp).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        let mut seen = Vec::new();
        for m in mcap::MessageStream::new(&bytes).unwrap() {
            let m = m.unwrap();
            let v: serde_json::Value = serde_json::from_slice(&m.data).unwrap();
            seen.push((m.channel.topic.clone(), v));
        }
        assert_eq!(seen.len(), 2);
        assert_eq!(seen[0].0, "/bench/summary");
        assert_eq!(seen[0].1["ratio"].as_f64(), Some(1.25));
        assert_eq!(seen[1].0, "/bench/work_precision");
        assert_eq!(seen[1].1["steps"].as_u64(), Some(4004));
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn criterion_ids_split_into_group_pair_and_twin() {
        assert_eq!(
            parse("position/glam-f64-hand"),
            Some(("position".into(), "glam-f64".into(), Variant::Hand))
        );
        assert_eq!(
            parse("step-rk4/nalgebra-f32"),
            Some(("step-rk4".into(), "nalgebra-f32".into(), Variant::Generic))
        );
        assert_eq!(
            parse("step-rk4/glam-f32-direct"),
            Some(("step-rk4".into(), "glam-f32".into(), Variant::Direct))
        );
        assert_eq!(parse("nogroup"), None);
    }
}
