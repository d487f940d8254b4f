//! CSV and MCAP output. Both are written to a temporary file next to the
//! target and renamed into place when complete, so an interrupted run never
//! leaves a truncated file under the requested name.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use serde_json::json;

use crate::{RunOutput, Sample};

/// The CSV header, fixed.
pub const CSV_HEADER: &str =
    "t,x1,x2,x3,v1,v2,v3,r11,r12,r13,r21,r22,r23,r31,r32,r33,w1,w2,w3,psi,ex,f,m1,m2,m3,mode";

fn temp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".partial");
    path.with_file_name(name)
}

fn commit(tmp: &Path, path: &Path) -> std::io::Result<()> {
    std::fs::rename(tmp, path)
}

/// One CSV row (at a switch time the row carries the command that acts
/// from then on, i.e. the new mode). Numbers use Rust's shortest round-trip formatting (`{}` of
/// f64), so parsing them gives back the same f64.
pub fn csv_row(s: &Sample) -> String {
    let mut row = String::with_capacity(400);
    let mut push = |x: f64| {
        row.push_str(&format!("{x},"));
    };
    push(s.t);
    s.x.iter().for_each(|&c| push(c));
    s.v.iter().for_each(|&c| push(c));
    s.r.iter().flatten().for_each(|&c| push(c));
    s.omega.iter().for_each(|&c| push(c));
    push(s.psi);
    push(s.ex);
    push(s.thrust);
    s.moment.iter().for_each(|&c| push(c));
    row.push_str(s.mode);
    for &c in &s.vehicle_states {
        row.push_str(&format!(",{c}"));
    }
    row
}

/// The CSV header for a vehicle with `n` internal states: [`CSV_HEADER`]
/// followed by `s1 … sn`.
pub fn csv_header(n: usize) -> String {
    let mut h = CSV_HEADER.to_string();
    for k in 1..=n {
        h.push_str(&format!(",s{k}"));
    }
    h
}

/// Writes the samples as CSV.
pub fn write_csv(path: &Path, out: &RunOutput) -> std::io::Result<()> {
    let tmp = temp_path(path);
    {
        let mut w = BufWriter::new(File::create(&tmp)?);
        let n = out.samples.first().map_or(0, |s| s.vehicle_states.len());
        writeln!(w, "{}", csv_header(n))?;
        for s in &out.samples {
            writeln!(w, "{}", csv_row(s))?;
        }
        w.flush()?;
    }
    commit(&tmp, path)
}

/// Unit quaternion `(x, y, z, w)` (Foxglove's order, `w ≥ 0`) of a rotation
/// matrix given by rows, through `lie::shepperd` (largest pivot, no
/// cancellation near angle π).
pub fn quaternion_xyzw(r: &[[f64; 3]; 3]) -> [f64; 4] {
    use lie::{NalgebraF64, ops};
    let [w, x, y, z] = lie::shepperd::<NalgebraF64>(ops::from_elems::<NalgebraF64>(*r));
    let n = (w * w + x * x + y * y + z * z).sqrt();
    let sg = if w < 0.0 { -1.0 } else { 1.0 };
    [sg * x / n, sg * y / n, sg * z / n, sg * w / n]
}

/// The topic of a vehicle's internal states (rotor thrusts with lag, …),
/// written only for a vehicle that has them.
pub const STATES_TOPIC: &str = "/vehicle/states";

/// Topics written to the MCAP log (every run; see also [`STATES_TOPIC`]).
pub const TOPICS: [&str; 7] = [
    "/vehicle/pose",
    "/desired/pose",
    "/tf",
    "/errors",
    "/command",
    "/integrals",
    "/mode",
];

const VEC3: &str = r#"{"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"}},"required":["x","y","z"]}"#;
const QUAT: &str = r#"{"type":"object","properties":{"x":{"type":"number"},"y":{"type":"number"},"z":{"type":"number"},"w":{"type":"number"}},"required":["x","y","z","w"]}"#;
const TIME: &str = r#"{"type":"object","properties":{"sec":{"type":"integer","minimum":0},"nsec":{"type":"integer","minimum":0,"maximum":999999999}},"required":["sec","nsec"]}"#;

fn pose_in_frame_schema() -> String {
    format!(
        r#"{{"title":"foxglove.PoseInFrame","type":"object","properties":{{"timestamp":{TIME},"frame_id":{{"type":"string"}},"pose":{{"type":"object","properties":{{"position":{VEC3},"orientation":{QUAT}}},"required":["position","orientation"]}}}},"required":["timestamp","frame_id","pose"]}}"#
    )
}

fn frame_transform_schema() -> String {
    format!(
        r#"{{"title":"foxglove.FrameTransform","type":"object","properties":{{"timestamp":{TIME},"parent_frame_id":{{"type":"string"}},"child_frame_id":{{"type":"string"}},"translation":{VEC3},"rotation":{QUAT}}},"required":["timestamp","parent_frame_id","child_frame_id","translation","rotation"]}}"#
    )
}

fn object_schema(title: &str, fields: &[(&str, &str)]) -> String {
    let props: Vec<String> = fields
        .iter()
        .map(|(k, ty)| {
            let t = match *ty {
                "vec3" => VEC3.to_string(),
                "number" => r#"{"type":"number"}"#.to_string(),
                "integer" => r#"{"type":"integer"}"#.to_string(),
                "string" => r#"{"type":"string"}"#.to_string(),
                "array" => r#"{"type":"array","items":{"type":"number"}}"#.to_string(),
                other => other.to_string(),
            };
            format!(r#""{k}":{t}"#)
        })
        .collect();
    let req: Vec<String> = fields.iter().map(|(k, _)| format!(r#""{k}""#)).collect();
    format!(
        r#"{{"title":"{title}","type":"object","properties":{{{}}},"required":[{}]}}"#,
        props.join(","),
        req.join(",")
    )
}

fn stamp(t: f64) -> serde_json::Value {
    let ns = (t * 1e9).round() as u64;
    json!({"sec": ns / 1_000_000_000, "nsec": ns % 1_000_000_000})
}

fn v3(a: [f64; 3]) -> serde_json::Value {
    json!({"x": a[0], "y": a[1], "z": a[2]})
}

fn q4(q: [f64; 4]) -> serde_json::Value {
    json!({"x": q[0], "y": q[1], "z": q[2], "w": q[3]})
}

/// Writes the run as MCAP: poses as `foxglove.PoseInFrame` (frame `ned`,
/// the paper's e3-down inertial frame), `/tf` as `foxglove.FrameTransform`
/// (`world` z-up → `ned` is a half turn about x; `ned` → `body` is the
/// vehicle pose) so Foxglove's 3D panel shows the vehicle upright, and
/// JSON channels (with JSON schemas) for errors, commands, integral states
/// and mode switches for its plot panel.
pub fn write_mcap(path: &Path, out: &RunOutput) -> Result<(), String> {
    let tmp = temp_path(path);
    let result = (|| -> Result<(), mcap::McapError> {
        let file = BufWriter::new(File::create(&tmp)?);
        let mut w = mcap::WriteOptions::new()
            .compression(Some(mcap::Compression::Lz4))
            .profile("")
            .create(file)?;
        let pose = w.add_schema(
            "foxglove.PoseInFrame",
            "jsonschema",
            pose_in_frame_schema().as_bytes(),
        )?;
        let tf = w.add_schema(
            "foxglove.FrameTransform",
            "jsonschema",
            frame_transform_schema().as_bytes(),
        )?;
        let errors = w.add_schema(
            "gpid.Errors",
            "jsonschema",
            object_schema(
                "gpid.Errors",
                &[
                    ("psi", "number"),
                    ("ex", "number"),
                    ("e_x", "vec3"),
                    ("omega", "vec3"),
                    ("omega_d", "vec3"),
                ],
            )
            .as_bytes(),
        )?;
        let command = w.add_schema(
            "gpid.Command",
            "jsonschema",
            object_schema(
                "gpid.Command",
                &[
                    ("thrust", "number"),
                    ("moment", "vec3"),
                    ("rotor_thrusts", "array"),
                ],
            )
            .as_bytes(),
        )?;
        let integrals = w.add_schema(
            "gpid.Integrals",
            "jsonschema",
            object_schema("gpid.Integrals", &[("e_I", "vec3"), ("e_i", "vec3")]).as_bytes(),
        )?;
        let mode = w.add_schema(
            "gpid.ModeSwitch",
            "jsonschema",
            object_schema(
                "gpid.ModeSwitch",
                &[
                    ("t", "number"),
                    ("from", "integer"),
                    ("to", "integer"),
                    ("mode", "string"),
                ],
            )
            .as_bytes(),
        )?;
        let n_states = out.samples.first().map_or(0, |s| s.vehicle_states.len());
        let states = if n_states > 0 {
            Some(w.add_schema(
                "gpid.VehicleStates",
                "jsonschema",
                object_schema("gpid.VehicleStates", &[("states", "array")]).as_bytes(),
            )?)
        } else {
            None
        };
        let meta = BTreeMap::new();
        let ch = [
            w.add_channel(pose, TOPICS[0], "json", &meta)?,
            w.add_channel(pose, TOPICS[1], "json", &meta)?,
            w.add_channel(tf, TOPICS[2], "json", &meta)?,
            w.add_channel(errors, TOPICS[3], "json", &meta)?,
            w.add_channel(command, TOPICS[4], "json", &meta)?,
            w.add_channel(integrals, TOPICS[5], "json", &meta)?,
            w.add_channel(mode, TOPICS[6], "json", &meta)?,
        ];
        // Only a vehicle with internal states gets their channel.
        let states_channel = match states {
            Some(id) => Some(w.add_channel(id, STATES_TOPIC, "json", &meta)?),
            None => None,
        };
        let mut states_seq = 0u32;
        let mut seq = [0u32; 7];
        let mut put =
            |w: &mut mcap::Writer<BufWriter<File>>, k: usize, t: f64, v: serde_json::Value| {
                let ns = (t * 1e9).round() as u64;
                seq[k] += 1;
                w.write_to_known_channel(
                    &mcap::records::MessageHeader {
                        channel_id: ch[k],
                        sequence: seq[k],
                        log_time: ns,
                        publish_time: ns,
                    },
                    v.to_string().as_bytes(),
                )
            };
        let world_to_ned = [1.0, 0.0, 0.0, 0.0]; // half turn about x, (x, y, z, w)
        let mode_name = |k: usize| out.mode_names.get(k).copied().unwrap_or("none");
        if !out.mode_names.is_empty() {
            put(
                &mut w,
                6,
                0.0,
                json!({"t": 0.0, "from": 0, "to": 0, "mode": mode_name(0)}),
            )?;
        }
        let mut switches = out.switches.iter().peekable();
        for s in &out.samples {
            while let Some(sw) = switches.next_if(|sw| sw.t <= s.t) {
                put(
                    &mut w,
                    6,
                    sw.t,
                    json!({"t": sw.t, "from": sw.from, "to": sw.to, "mode": mode_name(sw.to)}),
                )?;
            }
            let q = quaternion_xyzw(&s.r);
            let qd = quaternion_xyzw(&s.rd);
            put(
                &mut w,
                0,
                s.t,
                json!({"timestamp": stamp(s.t), "frame_id": "ned",
                "pose": {"position": v3(s.x), "orientation": q4(q)}}),
            )?;
            put(
                &mut w,
                1,
                s.t,
                json!({"timestamp": stamp(s.t), "frame_id": "ned",
                "pose": {"position": v3(s.xd), "orientation": q4(qd)}}),
            )?;
            put(
                &mut w,
                2,
                s.t,
                json!({"timestamp": stamp(s.t), "parent_frame_id": "world",
                "child_frame_id": "ned", "translation": v3([0.0; 3]), "rotation": q4(world_to_ned)}),
            )?;
            put(
                &mut w,
                2,
                s.t,
                json!({"timestamp": stamp(s.t), "parent_frame_id": "ned",
                "child_frame_id": "body", "translation": v3(s.x), "rotation": q4(q)}),
            )?;
            let e_x = [s.x[0] - s.xd[0], s.x[1] - s.xd[1], s.x[2] - s.xd[2]];
            put(
                &mut w,
                3,
                s.t,
                json!({"psi": s.psi, "ex": s.ex, "e_x": v3(e_x),
                "omega": v3(s.omega), "omega_d": v3(s.omega_d)}),
            )?;
            put(
                &mut w,
                4,
                s.t,
                json!({"thrust": s.thrust, "moment": v3(s.moment),
                "rotor_thrusts": s.rotors}),
            )?;
            put(
                &mut w,
                5,
                s.t,
                json!({"e_I": v3(s.e_att), "e_i": v3(s.e_pos)}),
            )?;
            if let Some(id) = states_channel {
                let ns = (s.t * 1e9).round() as u64;
                states_seq += 1;
                w.write_to_known_channel(
                    &mcap::records::MessageHeader {
                        channel_id: id,
                        sequence: states_seq,
                        log_time: ns,
                        publish_time: ns,
                    },
                    json!({"states": s.vehicle_states}).to_string().as_bytes(),
                )?;
            }
        }
        // Warnings of the run (a clamped tolerance, R leaving SO(3), …) as
        // a metadata record, so a log carries its own caveats.
        if !out.warnings.is_empty() {
            let metadata = out
                .warnings
                .iter()
                .enumerate()
                .map(|(k, w)| (format!("warning {}", k + 1), w.clone()))
                .collect();
            w.write_metadata(&mcap::records::Metadata {
                name: "warnings".into(),
                metadata,
            })?;
        }
        w.finish()?;
        Ok(())
    })();
    match result {
        Ok(()) => commit(&tmp, path).map_err(|e| format!("renaming {}: {e}", tmp.display())),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(format!("writing {}: {e}", path.display()))
        }
    }
}
