//! CSV and MCAP output, streamed.
//!
//! A run hands each [`Sample`] and mode switch to a [`Sink`] as it produces
//! them ([`crate::RunOptions::sink`]), so memory stays bounded whatever the
//! duration. [`CsvWriter`] and [`McapWriter`] are the two sinks shipped;
//! [`Tee`] feeds several at once. Both write to `<name>.partial` and rename
//! it to `<name>` in `finish`: a run killed outright (SIGKILL, power loss)
//! leaves a `.partial` file, never a truncated file under the requested
//! name. [`write_csv`] and [`write_mcap`] write a finished [`RunOutput`]
//! through the same writers.
//!
//! Numbers are written in the shortest form that parses back to the same
//! f64 (the `zmij` formatter, which `serde_json` uses too): a CSV or JSON
//! value read back is the sample's value bit for bit. A non-finite value is
//! `NaN`/`inf` in the CSV and `null` in JSON (which has no NaN).

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

use crate::{RunOutput, Sample, SwitchRecord};

/// The CSV header, fixed.
pub const CSV_HEADER: &str =
    "t,x1,x2,x3,v1,v2,v3,r11,r12,r13,r21,r22,r23,r31,r32,r33,w1,w2,w3,psi,ex,f,m1,m2,m3,mode";

/// A failed write, naming the file.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputError {
    /// The file asked for (its `.partial` is what was being written).
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
}

impl std::fmt::Display for OutputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "writing {}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for OutputError {}

fn err(path: &Path, e: impl std::fmt::Display) -> OutputError {
    OutputError {
        path: path.to_path_buf(),
        message: e.to_string(),
    }
}

/// Receives a run's output as the run produces it. Calls come in time
/// order: [`Sink::begin`] once, then samples, with each mode switch
/// reported before the sample taken at its instant.
pub trait Sink {
    /// Before the first sample: the name of each segment's mode, in plan
    /// order (empty without a plan).
    fn begin(&mut self, mode_names: &[&'static str]) -> Result<(), OutputError>;
    /// A mode switch; `mode` is the name of the mode entered.
    fn switch(&mut self, sw: &SwitchRecord, mode: &str) -> Result<(), OutputError>;
    /// One sample.
    fn sample(&mut self, s: &Sample) -> Result<(), OutputError>;
}

/// Several sinks fed the same calls, in order.
pub struct Tee<'a>(pub Vec<&'a mut dyn Sink>);

impl Sink for Tee<'_> {
    fn begin(&mut self, mode_names: &[&'static str]) -> Result<(), OutputError> {
        self.0.iter_mut().try_for_each(|s| s.begin(mode_names))
    }
    fn switch(&mut self, sw: &SwitchRecord, mode: &str) -> Result<(), OutputError> {
        self.0.iter_mut().try_for_each(|s| s.switch(sw, mode))
    }
    fn sample(&mut self, smp: &Sample) -> Result<(), OutputError> {
        self.0.iter_mut().try_for_each(|s| s.sample(smp))
    }
}

/// Where and why a run stopped before its end, for the MCAP's `stopped`
/// metadata record.
#[derive(Clone, Debug, PartialEq)]
pub struct Stopped {
    /// The time of the last sample, s.
    pub t: f64,
    /// Why (`"SIGINT"`, `"SIGTERM"`, an error message, …).
    pub reason: String,
}

fn temp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".partial");
    path.with_file_name(name)
}

/// The shortest round-trip decimal form of `x` (`NaN`, `inf`, `-inf` when
/// not finite).
fn push_num(buf: &mut Vec<u8>, x: f64) {
    let mut b = zmij::Buffer::new();
    buf.extend_from_slice(b.format(x).as_bytes());
}

/// As [`push_num`], `null` when not finite (JSON has no NaN).
fn push_json_num(buf: &mut Vec<u8>, x: f64) {
    if x.is_finite() {
        let mut b = zmij::Buffer::new();
        buf.extend_from_slice(b.format_finite(x).as_bytes());
    } else {
        buf.extend_from_slice(b"null");
    }
}

fn push_int(buf: &mut Vec<u8>, n: u64) {
    let mut b = itoa::Buffer::new();
    buf.extend_from_slice(b.format(n).as_bytes());
}

fn push_csv_row(row: &mut Vec<u8>, s: &Sample) {
    let mut push = |x: f64| {
        push_num(row, x);
        row.push(b',');
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
    row.extend_from_slice(s.mode.as_bytes());
    for &c in &s.vehicle_states {
        row.push(b',');
        push_num(row, c);
    }
}

/// One CSV row (at a switch time the row carries the command that acts
/// from then on, i.e. the new mode), without the line end.
pub fn csv_row(s: &Sample) -> String {
    let mut row = Vec::with_capacity(512);
    push_csv_row(&mut row, s);
    String::from_utf8(row).expect("numbers and mode names are UTF-8")
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

/// Streams samples to a CSV file (the header comes with the first sample,
/// which tells the vehicle's internal-state count). Rows are whole lines:
/// what [`CsvWriter::finish`] flushes ends with the last complete row.
pub struct CsvWriter {
    path: PathBuf,
    tmp: PathBuf,
    w: BufWriter<File>,
    row: Vec<u8>,
    rows: u64,
    header: bool,
}

impl CsvWriter {
    /// Creates `<path>.partial`.
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        let tmp = temp_path(path);
        let f = File::create(&tmp).map_err(|e| err(path, e))?;
        Ok(Self {
            path: path.to_path_buf(),
            tmp,
            w: BufWriter::with_capacity(1 << 16, f),
            row: Vec::with_capacity(512),
            rows: 0,
            header: false,
        })
    }

    /// Rows written so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// Flushes, syncs and renames `<path>.partial` to `<path>`; returns the
    /// row count.
    pub fn finish(mut self) -> Result<u64, OutputError> {
        if !self.header {
            let h = csv_header(0);
            writeln!(self.w, "{h}").map_err(|e| err(&self.path, e))?;
        }
        let f = self
            .w
            .into_inner()
            .map_err(|e| err(&self.path, e.error()))?;
        f.sync_all().map_err(|e| err(&self.path, e))?;
        std::fs::rename(&self.tmp, &self.path).map_err(|e| err(&self.path, e))?;
        Ok(self.rows)
    }
}

impl Sink for CsvWriter {
    fn begin(&mut self, _: &[&'static str]) -> Result<(), OutputError> {
        Ok(())
    }
    fn switch(&mut self, _: &SwitchRecord, _: &str) -> Result<(), OutputError> {
        Ok(())
    }
    fn sample(&mut self, s: &Sample) -> Result<(), OutputError> {
        if !self.header {
            self.header = true;
            let h = csv_header(s.vehicle_states.len());
            writeln!(self.w, "{h}").map_err(|e| err(&self.path, e))?;
        }
        self.row.clear();
        push_csv_row(&mut self.row, s);
        self.row.push(b'\n');
        self.w
            .write_all(&self.row)
            .map_err(|e| err(&self.path, e))?;
        self.rows += 1;
        Ok(())
    }
}

/// Writes the samples of a finished run as CSV.
pub fn write_csv(path: &Path, out: &RunOutput) -> Result<u64, OutputError> {
    let mut w = CsvWriter::create(path)?;
    for s in &out.samples {
        w.sample(s)?;
    }
    w.finish()
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

/// A message under construction: JSON written straight into a reused
/// buffer (no intermediate tree, no allocation per message).
struct Json<'b>(&'b mut Vec<u8>);

impl Json<'_> {
    fn raw(&mut self, s: &str) -> &mut Self {
        self.0.extend_from_slice(s.as_bytes());
        self
    }
    fn num(&mut self, x: f64) -> &mut Self {
        push_json_num(self.0, x);
        self
    }
    fn v3(&mut self, a: [f64; 3]) -> &mut Self {
        self.raw(r#"{"x":"#)
            .num(a[0])
            .raw(r#","y":"#)
            .num(a[1])
            .raw(r#","z":"#)
            .num(a[2])
            .raw("}")
    }
    fn q4(&mut self, q: [f64; 4]) -> &mut Self {
        self.raw(r#"{"x":"#)
            .num(q[0])
            .raw(r#","y":"#)
            .num(q[1])
            .raw(r#","z":"#)
            .num(q[2])
            .raw(r#","w":"#)
            .num(q[3])
            .raw("}")
    }
    fn stamp(&mut self, ns: u64) -> &mut Self {
        self.raw(r#"{"sec":"#);
        push_int(self.0, ns / 1_000_000_000);
        self.raw(r#","nsec":"#);
        push_int(self.0, ns % 1_000_000_000);
        self.raw("}")
    }
    fn array(&mut self, a: &[f64]) -> &mut Self {
        self.raw("[");
        for (k, &x) in a.iter().enumerate() {
            if k > 0 {
                self.raw(",");
            }
            self.num(x);
        }
        self.raw("]")
    }
}

/// Nanoseconds of a sample time (MCAP log times; negative or non-finite
/// times, which a run never produces, clamp to 0).
fn nanos(t: f64) -> u64 {
    (t * 1e9).round() as u64
}

/// Messages formatted on the simulation's thread, handed to the writer
/// thread in one piece.
#[derive(Default)]
struct Batch {
    bytes: Vec<u8>,
    /// (channel slot, log time in ns, end offset in `bytes`).
    msgs: Vec<(u8, u64, usize)>,
}

/// Messages per batch handed to the writer thread.
const BATCH: usize = 4096;

/// The channel slot of `/vehicle/states` (created at its first message).
const STATES_SLOT: u8 = 7;

type Mcap = mcap::Writer<BufWriter<File>>;

/// The writer thread: writes each batch's messages, creating the states
/// channel at its first message; returns the writer for `finish`.
fn write_batches(
    mut w: Mcap,
    ch: [u16; 7],
    rx: std::sync::mpsc::Receiver<Batch>,
) -> Result<Mcap, mcap::McapError> {
    let mut seq = [0u32; 8];
    let mut states: Option<u16> = None;
    for batch in rx {
        let mut start = 0;
        for &(slot, ns, end) in &batch.msgs {
            let channel_id = if slot == STATES_SLOT {
                match states {
                    Some(id) => id,
                    None => {
                        let schema = w.add_schema(
                            "gpid.VehicleStates",
                            "jsonschema",
                            object_schema("gpid.VehicleStates", &[("states", "array")]).as_bytes(),
                        )?;
                        let id = w.add_channel(schema, STATES_TOPIC, "json", &BTreeMap::new())?;
                        states = Some(id);
                        id
                    }
                }
            } else {
                ch[usize::from(slot)]
            };
            let k = usize::from(slot);
            seq[k] = seq[k].wrapping_add(1);
            w.write_to_known_channel(
                &mcap::records::MessageHeader {
                    channel_id,
                    sequence: seq[k],
                    log_time: ns,
                    publish_time: ns,
                },
                &batch.bytes[start..end],
            )?;
            start = end;
        }
    }
    Ok(w)
}

/// Streams a run to an MCAP log: poses as `foxglove.PoseInFrame` (frame
/// `ned`, the paper's e3-down inertial frame), `/tf` as
/// `foxglove.FrameTransform` (`world` z-up → `ned` is a half turn about x,
/// constant, sent with the first sample and then at most every
/// [`STATIC_TF_NS`] of simulated time; `ned` → `body` is the vehicle pose,
/// every sample) so Foxglove's 3D panel shows the vehicle upright, and
/// JSON channels (with JSON schemas) for errors, commands, integral states
/// and mode switches for its plot panel. Every
/// message is JSON: the official `mcap` Python reader and `json.loads`
/// decode it without Foxglove or protobuf tooling. Chunks are
/// lz4-compressed.
///
/// The messages are formatted on the caller's thread and written (record
/// framing, lz4, CRCs, I/O) by a thread of the writer's own, through a
/// bounded queue: on two cores, compression overlaps the simulation, and a
/// writer slower than the simulation slows it down instead of piling up
/// samples in memory.
pub struct McapWriter {
    path: PathBuf,
    tmp: PathBuf,
    batch: Batch,
    tx: Option<std::sync::mpsc::SyncSender<Batch>>,
    thread: Option<std::thread::JoinHandle<Result<Mcap, mcap::McapError>>>,
    mode_names: Vec<&'static str>,
    messages: u64,
    next_static_ns: u64,
}

/// The longest simulated time between two `world → ned` transforms, ns.
pub const STATIC_TF_NS: u64 = 100_000_000;

impl McapWriter {
    /// Creates `<path>.partial` with the schemas and channels, and starts
    /// the writer thread.
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        let tmp = temp_path(path);
        let e = |x: mcap::McapError| err(path, x);
        let file = BufWriter::with_capacity(1 << 16, File::create(&tmp).map_err(|x| err(path, x))?);
        let mut w = mcap::WriteOptions::new()
            .compression(Some(mcap::Compression::Lz4))
            .profile("")
            .create(file)
            .map_err(e)?;
        let pose = w
            .add_schema(
                "foxglove.PoseInFrame",
                "jsonschema",
                pose_in_frame_schema().as_bytes(),
            )
            .map_err(e)?;
        let tf = w
            .add_schema(
                "foxglove.FrameTransform",
                "jsonschema",
                frame_transform_schema().as_bytes(),
            )
            .map_err(e)?;
        let mut object = |title: &str, fields: &[(&str, &str)]| {
            w.add_schema(title, "jsonschema", object_schema(title, fields).as_bytes())
        };
        let errors = object(
            "gpid.Errors",
            &[
                ("psi", "number"),
                ("ex", "number"),
                ("e_x", "vec3"),
                ("omega", "vec3"),
                ("omega_d", "vec3"),
            ],
        )
        .map_err(e)?;
        let command = object(
            "gpid.Command",
            &[
                ("thrust", "number"),
                ("moment", "vec3"),
                ("rotor_thrusts", "array"),
            ],
        )
        .map_err(e)?;
        let integrals = object("gpid.Integrals", &[("e_I", "vec3"), ("e_i", "vec3")]).map_err(e)?;
        let mode = object(
            "gpid.ModeSwitch",
            &[
                ("t", "number"),
                ("from", "integer"),
                ("to", "integer"),
                ("mode", "string"),
            ],
        )
        .map_err(e)?;
        let meta = BTreeMap::new();
        let mut ch = [0u16; 7];
        for (k, schema) in [pose, pose, tf, errors, command, integrals, mode]
            .into_iter()
            .enumerate()
        {
            ch[k] = w.add_channel(schema, TOPICS[k], "json", &meta).map_err(e)?;
        }
        // Two batches in flight: enough to ride out a slow write, and
        // memory stays a few MB.
        let (tx, rx) = std::sync::mpsc::sync_channel::<Batch>(2);
        let thread = std::thread::Builder::new()
            .name("mcap-writer".into())
            .spawn(move || write_batches(w, ch, rx))
            .map_err(|x| err(path, x))?;
        Ok(Self {
            path: path.to_path_buf(),
            tmp,
            batch: Batch::default(),
            tx: Some(tx),
            thread: Some(thread),
            mode_names: Vec::new(),
            messages: 0,
            next_static_ns: 0,
        })
    }

    /// Messages written so far.
    pub fn messages(&self) -> u64 {
        self.messages
    }

    /// Ends the message being formatted at the end of the batch buffer.
    fn put(&mut self, slot: u8, ns: u64) -> Result<(), OutputError> {
        self.batch.msgs.push((slot, ns, self.batch.bytes.len()));
        self.messages += 1;
        if self.batch.msgs.len() >= BATCH {
            self.send()?;
        }
        Ok(())
    }

    fn send(&mut self) -> Result<(), OutputError> {
        let next = Batch {
            bytes: Vec::with_capacity(self.batch.bytes.capacity()),
            msgs: Vec::with_capacity(BATCH),
        };
        let batch = std::mem::replace(&mut self.batch, next);
        let tx = self
            .tx
            .as_ref()
            .ok_or_else(|| err(&self.path, "finished"))?;
        if tx.send(batch).is_err() {
            // The writer thread stopped on an error: report it.
            return Err(match self.join() {
                Err(e) => e,
                Ok(_) => err(&self.path, "the writer thread stopped"),
            });
        }
        Ok(())
    }

    fn join(&mut self) -> Result<Mcap, OutputError> {
        self.tx = None;
        let h = self
            .thread
            .take()
            .ok_or_else(|| err(&self.path, "the writer thread already failed"))?;
        match h.join() {
            Ok(r) => r.map_err(|x| err(&self.path, x)),
            Err(_) => Err(err(&self.path, "the writer thread panicked")),
        }
    }

    fn put_switch(&mut self, t: f64, from: usize, to: usize) -> Result<(), OutputError> {
        let name = self.mode_names.get(to).copied().unwrap_or("none");
        let b = &mut self.batch.bytes;
        Json(b).raw(r#"{"t":"#).num(t).raw(r#","from":"#);
        push_int(b, from as u64);
        b.extend_from_slice(br#","to":"#);
        push_int(b, to as u64);
        b.extend_from_slice(br#","mode":"#);
        // A user's mode name may hold any character: let serde escape it.
        b.extend_from_slice(serde_json::Value::from(name).to_string().as_bytes());
        b.push(b'}');
        self.put(6, nanos(t))
    }

    /// Writes what is queued, then the run's warnings (a `warnings`
    /// metadata record, one entry each) and, for a run that ended early, a
    /// `stopped` record (`t`, `reason`); writes the summary and indexes,
    /// syncs, and renames `<path>.partial` to `<path>`. Returns the message
    /// count.
    pub fn finish(
        mut self,
        warnings: &[String],
        stopped: Option<&Stopped>,
    ) -> Result<u64, OutputError> {
        if !self.batch.msgs.is_empty() {
            self.send()?;
        }
        let mut w = self.join()?;
        let path = self.path.clone();
        let e = |x: mcap::McapError| err(&path, x);
        if !warnings.is_empty() {
            let metadata = warnings
                .iter()
                .enumerate()
                .map(|(k, w)| (format!("warning {}", k + 1), w.clone()))
                .collect();
            w.write_metadata(&mcap::records::Metadata {
                name: "warnings".into(),
                metadata,
            })
            .map_err(e)?;
        }
        if let Some(s) = stopped {
            let metadata = [
                ("t".to_string(), format!("{}", s.t)),
                ("reason".to_string(), s.reason.clone()),
            ]
            .into_iter()
            .collect();
            w.write_metadata(&mcap::records::Metadata {
                name: "stopped".into(),
                metadata,
            })
            .map_err(e)?;
        }
        w.finish().map_err(e)?;
        let f = w
            .into_inner()
            .into_inner()
            .map_err(|x| err(&path, x.error()))?;
        f.sync_all().map_err(|x| err(&path, x))?;
        std::fs::rename(&self.tmp, &path).map_err(|x| err(&path, x))?;
        Ok(self.messages)
    }
}

impl Sink for McapWriter {
    fn begin(&mut self, mode_names: &[&'static str]) -> Result<(), OutputError> {
        self.mode_names = mode_names.to_vec();
        if !self.mode_names.is_empty() {
            self.put_switch(0.0, 0, 0)?;
        }
        Ok(())
    }

    fn switch(&mut self, sw: &SwitchRecord, _: &str) -> Result<(), OutputError> {
        self.put_switch(sw.t, sw.from, sw.to)
    }

    fn sample(&mut self, s: &Sample) -> Result<(), OutputError> {
        let ns = nanos(s.t);
        let q = quaternion_xyzw(&s.r);
        let qd = quaternion_xyzw(&s.rd);
        for (k, x, q) in [(0, s.x, q), (1, s.xd, qd)] {
            Json(&mut self.batch.bytes)
                .raw(r#"{"timestamp":"#)
                .stamp(ns)
                .raw(r#","frame_id":"ned","pose":{"position":"#)
                .v3(x)
                .raw(r#","orientation":"#)
                .q4(q)
                .raw("}}");
            self.put(k, ns)?;
        }
        // world (z up) → ned: a half turn about x, (x, y, z, w). It never
        // changes, so it goes out at most every STATIC_TF_NS of simulated
        // time (Foxglove holds a transform until a newer one comes): at
        // 1 kHz sampling, a tenth of the log's bytes saved.
        let world = ("world", "ned", [0.0; 3], [1.0, 0.0, 0.0, 0.0]);
        let body = ("ned", "body", s.x, q);
        let tfs: &[_] = if ns >= self.next_static_ns {
            self.next_static_ns = ns.saturating_add(STATIC_TF_NS);
            &[world, body]
        } else {
            &[body]
        };
        for &(parent, child, tr, rot) in tfs {
            Json(&mut self.batch.bytes)
                .raw(r#"{"timestamp":"#)
                .stamp(ns)
                .raw(r#","parent_frame_id":""#)
                .raw(parent)
                .raw(r#"","child_frame_id":""#)
                .raw(child)
                .raw(r#"","translation":"#)
                .v3(tr)
                .raw(r#","rotation":"#)
                .q4(rot)
                .raw("}");
            self.put(2, ns)?;
        }
        let e_x = [s.x[0] - s.xd[0], s.x[1] - s.xd[1], s.x[2] - s.xd[2]];
        Json(&mut self.batch.bytes)
            .raw(r#"{"psi":"#)
            .num(s.psi)
            .raw(r#","ex":"#)
            .num(s.ex)
            .raw(r#","e_x":"#)
            .v3(e_x)
            .raw(r#","omega":"#)
            .v3(s.omega)
            .raw(r#","omega_d":"#)
            .v3(s.omega_d)
            .raw("}");
        self.put(3, ns)?;
        Json(&mut self.batch.bytes)
            .raw(r#"{"thrust":"#)
            .num(s.thrust)
            .raw(r#","moment":"#)
            .v3(s.moment)
            .raw(r#","rotor_thrusts":"#)
            .array(&s.rotors)
            .raw("}");
        self.put(4, ns)?;
        Json(&mut self.batch.bytes)
            .raw(r#"{"e_I":"#)
            .v3(s.e_att)
            .raw(r#","e_i":"#)
            .v3(s.e_pos)
            .raw("}");
        self.put(5, ns)?;
        if !s.vehicle_states.is_empty() {
            // Only a vehicle with internal states gets their channel (the
            // writer thread creates it at the first message).
            Json(&mut self.batch.bytes)
                .raw(r#"{"states":"#)
                .array(&s.vehicle_states)
                .raw("}");
            self.put(STATES_SLOT, ns)?;
        }
        Ok(())
    }
}

/// Writes a finished run as MCAP (see [`McapWriter`]), its warnings as a
/// `warnings` metadata record.
pub fn write_mcap(path: &Path, out: &RunOutput) -> Result<u64, OutputError> {
    let mut w = McapWriter::create(path)?;
    w.begin(&out.mode_names)?;
    let mut switches = out.switches.iter().peekable();
    for s in &out.samples {
        while let Some(sw) = switches.next_if(|sw| sw.t <= s.t) {
            w.switch(sw, "")?;
        }
        w.sample(s)?;
    }
    let stopped = out.interrupted_at.map(|t| Stopped {
        t,
        reason: "interrupted".into(),
    });
    w.finish(&out.warnings, stopped.as_ref())
}
