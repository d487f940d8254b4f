//! The MCAP writer: Foxglove's messages and ours, protobuf-encoded on a
//! thread of its own.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

use super::mcap_chunks::ChunkedMcap;
use super::*;
use scenarios::{MeasurementRecord, RunOutput, Sample, SwitchRecord};

use crate::ReferencePath;

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

/// The topic of the wind at the vehicle (`foxglove.Vector3`, inertial,
/// m/s), written from the first sample with a non-zero wind on.
pub const WIND_TOPIC: &str = "/wind";

/// The topic of the reference path: one `foxglove.SceneUpdate` at the
/// run's start, a line strip per plan segment in frame `ned` (written when
/// the run ends, so it is the path as flown, take-offs and landings
/// anchored where they started).
pub const REFERENCE_TOPIC: &str = "/reference/path";

/// The topics of a run with sensors, each created at its first message:
/// every IMU sample ([`msg::ImuReading`]), motion-capture frame
/// ([`msg::MocapFrame`]), GPS fix ([`msg::GpsFix`]) and barometer sample
/// ([`msg::BaroReading`]) at the time it describes, the estimate the
/// modes read at each record sample (`foxglove.PoseInFrame` in `ned`,
/// beside `/vehicle/pose`), and for a filter that keeps a covariance its
/// standard deviations and last NIS then ([`msg::EstimateDiagnostics`]).
pub const SENSOR_TOPICS: [&str; 6] = [
    "/sensors/imu",
    "/sensors/mocap",
    "/sensors/gps",
    "/sensors/baro",
    "/estimate/pose",
    "/estimate/diagnostics",
];

/// Topics written to the MCAP log (every run; see also [`STATES_TOPIC`]
/// and [`WIND_TOPIC`]).
pub const TOPICS: [&str; 7] = [
    "/vehicle/pose",
    "/desired/pose",
    "/tf",
    "/errors",
    "/command",
    "/integrals",
    "/mode",
];

pub mod msg;

use foxglove::Encode as _;
use msg::{FrameTransform, PoseInFrame};

/// Nanoseconds of a sample time (MCAP log times; negative or non-finite
/// times, which a run never produces, clamp to 0).
fn nanos(t: f64) -> u64 {
    (t * 1e9).round() as u64
}

/// A sample's numbers that go into its messages, copied on the
/// simulation's thread; the writer thread encodes them.
#[derive(Clone, Copy)]
struct Fixed {
    t: f64,
    x: [f64; 3],
    xd: [f64; 3],
    r: [[f64; 3]; 3],
    rd: [[f64; 3]; 3],
    psi: f64,
    ex: f64,
    omega: [f64; 3],
    omega_d: [f64; 3],
    thrust: f64,
    moment: [f64; 3],
    e_att: [f64; 3],
    e_pos: [f64; 3],
    wind: [f64; 3],
}

impl Fixed {
    fn of(s: &Sample) -> Self {
        Self {
            t: s.t,
            x: s.x,
            xd: s.xd,
            r: s.r,
            rd: s.rd,
            psi: s.psi,
            ex: s.ex,
            omega: s.omega,
            omega_d: s.omega_d,
            thrust: s.thrust,
            moment: s.moment,
            e_att: s.e_att,
            e_pos: s.e_pos,
            wind: s.wind,
        }
    }
}

/// What the simulation's thread hands the writer thread in one piece: the
/// samples (copied, encoded there) and the mode switches (encoded here,
/// rare), in order.
#[derive(Default)]
struct Batch {
    samples: Vec<Fixed>,
    /// Each sample's rotor thrusts, then its vehicle states.
    extra: Vec<f64>,
    /// The switches' messages.
    bytes: Vec<u8>,
    items: Vec<Item>,
}

enum Item {
    /// The next sample, with how many rotor thrusts and vehicle states
    /// follow in `extra`.
    Sample { rotors: usize, states: usize },
    /// The next `len` bytes of `bytes`: a message on channel slot `slot`
    /// at `ns`.
    Encoded { slot: u8, ns: u64, len: usize },
}

/// Items per batch handed to the writer thread (a sample is six messages
/// or more).
const BATCH: usize = 1024;

/// The channel slot of `/vehicle/states` (created at its first message).
const STATES_SLOT: u8 = 7;
/// The channel slot of `/wind` (created at its first message).
const WIND_SLOT: u8 = 8;
/// The channel slots of [`SENSOR_TOPICS`] (created at their first
/// messages).
const SENSOR_SLOTS: [u8; 6] = [9, 10, 11, 12, 13, 14];

type Mcap = ChunkedMcap<BufWriter<File>>;

/// The writer named in the file's header.
const LIBRARY: &str = concat!("geopid-logs/", env!("CARGO_PKG_VERSION"));

/// Chunks close once their records pass this size.
const CHUNK_TARGET: usize = 4 << 20;

/// Adds a protobuf schema from the `foxglove` crate's description of a
/// message type.
fn add_schema(w: &mut Mcap, schema: Option<foxglove::Schema>) -> std::io::Result<u16> {
    let s = schema.expect("every message type here has a protobuf schema");
    w.add_schema(&s.name, &s.encoding, &s.data)
}

/// The channels on the writer thread: their ids, sequence numbers, and
/// the states and wind channels created at their first messages.
struct Channels {
    w: Mcap,
    ch: [u16; 7],
    seq: [u32; 15],
    /// Channels created on demand: (slot, topic, schema, id once created).
    lazy: [(u8, &'static str, Option<foxglove::Schema>, Option<u16>); 8],
    messages: u64,
}

impl Channels {
    fn new(w: Mcap, ch: [u16; 7]) -> Self {
        let states = msg::VehicleStates::get_schema();
        Self {
            w,
            ch,
            seq: [0; 15],
            lazy: [
                (STATES_SLOT, STATES_TOPIC, states, None),
                (WIND_SLOT, WIND_TOPIC, msg::Vector3::get_schema(), None),
                (
                    SENSOR_SLOTS[0],
                    SENSOR_TOPICS[0],
                    msg::ImuReading::get_schema(),
                    None,
                ),
                (
                    SENSOR_SLOTS[1],
                    SENSOR_TOPICS[1],
                    msg::MocapFrame::get_schema(),
                    None,
                ),
                (
                    SENSOR_SLOTS[2],
                    SENSOR_TOPICS[2],
                    msg::GpsFix::get_schema(),
                    None,
                ),
                (
                    SENSOR_SLOTS[3],
                    SENSOR_TOPICS[3],
                    msg::BaroReading::get_schema(),
                    None,
                ),
                (
                    SENSOR_SLOTS[4],
                    SENSOR_TOPICS[4],
                    PoseInFrame::get_schema(),
                    None,
                ),
                (
                    SENSOR_SLOTS[5],
                    SENSOR_TOPICS[5],
                    msg::EstimateDiagnostics::get_schema(),
                    None,
                ),
            ],
            messages: 0,
        }
    }

    /// Writes one encoded message on channel slot `slot`.
    fn put(&mut self, slot: u8, ns: u64, data: &[u8]) -> std::io::Result<()> {
        let channel_id = match self.lazy.iter_mut().find(|l| l.0 == slot) {
            Some((_, _, _, Some(id))) => *id,
            Some((_, topic, schema, id)) => {
                let schema = add_schema(&mut self.w, schema.take())?;
                let new = self
                    .w
                    .add_channel(schema, topic, "protobuf", &BTreeMap::new())?;
                *id = Some(new);
                new
            }
            None => self.ch[usize::from(slot)],
        };
        let k = usize::from(slot);
        self.seq[k] = self.seq[k].wrapping_add(1);
        self.messages += 1;
        self.w.message(channel_id, self.seq[k], ns, data)
    }
}

/// A sample's messages, encoded on the writer thread.
#[derive(Default)]
struct SampleMessages {
    buf: Vec<u8>,
    next_static_ns: u64,
    wind_on: bool,
}

impl SampleMessages {
    /// Encodes the message `f` appends and writes it on `slot`.
    fn one(
        &mut self,
        out: &mut Channels,
        slot: u8,
        ns: u64,
        f: impl FnOnce(&mut Vec<u8>),
    ) -> std::io::Result<()> {
        self.buf.clear();
        f(&mut self.buf);
        out.put(slot, ns, &self.buf)
    }

    fn write(
        &mut self,
        out: &mut Channels,
        s: &Fixed,
        rotors: &[f64],
        states: &[f64],
    ) -> std::io::Result<()> {
        let ns = nanos(s.t);
        let at = proto::sec_nsec(ns);
        let q = quaternion_xyzw(&s.r);
        let qd = quaternion_xyzw(&s.rd);
        self.one(out, 0, ns, |b| proto::pose_in_frame(b, at, "ned", s.x, q))?;
        self.one(out, 1, ns, |b| proto::pose_in_frame(b, at, "ned", s.xd, qd))?;
        // world (z up) → ned: a half turn about x, (x, y, z, w). It never
        // changes, so it goes out at most every STATIC_TF_NS of simulated
        // time (Foxglove holds a transform until a newer one comes): at
        // 1 kHz sampling, a tenth of the log's bytes saved.
        if ns >= self.next_static_ns {
            self.next_static_ns = ns.saturating_add(STATIC_TF_NS);
            let half_turn_x = [1.0, 0.0, 0.0, 0.0];
            self.one(out, 2, ns, |b| {
                proto::frame_transform(b, at, "world", "ned", [0.0; 3], half_turn_x)
            })?;
        }
        self.one(out, 2, ns, |b| {
            proto::frame_transform(b, at, "ned", "body", s.x, q)
        })?;
        let e_x = [s.x[0] - s.xd[0], s.x[1] - s.xd[1], s.x[2] - s.xd[2]];
        self.one(out, 3, ns, |b| {
            proto::errors(b, s.psi, s.ex, e_x, s.omega, s.omega_d)
        })?;
        self.one(out, 4, ns, |b| {
            proto::command(b, s.thrust, s.moment, rotors)
        })?;
        self.one(out, 5, ns, |b| proto::integrals(b, s.e_att, s.e_pos))?;
        if !states.is_empty() {
            // Only a vehicle with internal states gets their channel
            // (created at the first message).
            self.one(out, STATES_SLOT, ns, |b| proto::vehicle_states(b, states))?;
        }
        self.wind_on |= s.wind != [0.0; 3];
        if self.wind_on {
            self.one(out, WIND_SLOT, ns, |b| proto::vector3(b, s.wind))?;
        }
        Ok(())
    }
}

/// The writer thread: encodes and writes each batch's samples and writes
/// its switches; returns the writer for `finish`, and the message count.
fn write_batches(
    w: Mcap,
    ch: [u16; 7],
    (rx, back): WorkerEnds<Batch>,
) -> std::io::Result<(Mcap, u64)> {
    let mut out = Channels::new(w, ch);
    let mut enc = SampleMessages::default();
    for mut batch in rx {
        let (mut sample, mut extra, mut byte) = (0, 0, 0);
        for item in &batch.items {
            match *item {
                Item::Sample { rotors, states } => {
                    let xs = &batch.extra[extra..extra + rotors + states];
                    let (r, st) = xs.split_at(rotors);
                    enc.write(&mut out, &batch.samples[sample], r, st)?;
                    sample += 1;
                    extra += rotors + states;
                }
                Item::Encoded { slot, ns, len } => {
                    out.put(slot, ns, &batch.bytes[byte..byte + len])?;
                    byte += len;
                }
            }
        }
        batch.samples.clear();
        batch.extra.clear();
        batch.bytes.clear();
        batch.items.clear();
        // The writer gone (its run failed) needs no buffers back.
        let _ = back.send(batch);
    }
    Ok((out.w, out.messages))
}

/// Streams a run to an MCAP log: poses as `foxglove.PoseInFrame` (frame
/// `ned`, the paper's e3-down inertial frame), `/tf` as
/// `foxglove.FrameTransform` (`world` z-up → `ned` is a half turn about x,
/// constant, sent with the first sample and then at most every
/// [`STATIC_TF_NS`] of simulated time; `ned` → `body` is the vehicle pose,
/// every sample) so Foxglove's 3D panel shows the vehicle upright, and the
/// [`msg`] channels for errors, commands, integral states and mode switches
/// for its plot panel. Every message is protobuf with its schema (a
/// `FileDescriptorSet`) in the file: Foxglove reads it as is, and the
/// official Python `mcap` reader with `mcap-protobuf-support` decodes every
/// message (the guide's first-flight chapter has the snippet). Chunks are not compressed (see
/// [`McapWriter::create`]).
///
/// Protobuf rather than JSON: doubles are copied, not formatted, which
/// takes less time and fewer bytes.
///
/// The caller's thread only copies each sample's numbers; a thread of the
/// writer's own encodes the messages and writes them (record framing into
/// chunks, message indexes, I/O), through a bounded queue: on two cores,
/// the writing overlaps the simulation, and a writer slower than the
/// simulation slows it down instead of piling up samples in memory. The
/// file's layout is the `mcap` crate's, written by this crate (its
/// per-message path was half of an `--mcap` run's instructions, and with
/// it gone the writer thread has room for the encoding the simulation's
/// thread did before).
pub struct McapWriter {
    path: PathBuf,
    target: Target,
    batch: Batch,
    worker: Worker<Batch, (Mcap, u64)>,
    mode_names: Vec<&'static str>,
    path_drawn: ReferencePath,
}

/// The longest simulated time between two `world → ned` transforms, ns.
pub const STATIC_TF_NS: u64 = 100_000_000;

impl McapWriter {
    /// Creates `<path>.partial` with the schemas and channels, and starts
    /// the writer thread.
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        let (target, file) = Target::open(path)?;
        let e = |x: std::io::Error| err_io(path, &x);
        // Append only, so a pipe works like a file: each chunk is
        // assembled in memory and written once. Measured on an hour of
        // `hover-disturbed` at 1 kHz: lz4 on ~100-byte records cost more than
        // writing 2.8x the bytes uncompressed, and the chunk and data
        // CRCs (optional in MCAP, and the file is synced and renamed whole)
        // a tenth of the writer's time. Chunks of 4 MiB, larger than the
        // 64 kB buffer, go to the file without a copy.
        let file = BufWriter::with_capacity(1 << 16, file);
        let mut w = ChunkedMcap::create(file, LIBRARY, CHUNK_TARGET).map_err(e)?;
        let pose = add_schema(&mut w, PoseInFrame::get_schema()).map_err(e)?;
        let tf = add_schema(&mut w, FrameTransform::get_schema()).map_err(e)?;
        let errors = add_schema(&mut w, msg::Errors::get_schema()).map_err(e)?;
        let command = add_schema(&mut w, msg::Command::get_schema()).map_err(e)?;
        let integrals = add_schema(&mut w, msg::Integrals::get_schema()).map_err(e)?;
        let mode = add_schema(&mut w, msg::ModeSwitch::get_schema()).map_err(e)?;
        let meta = BTreeMap::new();
        let mut ch = [0u16; 7];
        for (k, schema) in [pose, pose, tf, errors, command, integrals, mode]
            .into_iter()
            .enumerate()
        {
            ch[k] = w
                .add_channel(schema, TOPICS[k], "protobuf", &meta)
                .map_err(e)?;
        }
        let mcap_path = path.to_path_buf();
        let worker = Worker::spawn(path, "mcap-writer", move |ends| {
            write_batches(w, ch, ends).map_err(|e| err_io(&mcap_path, &e))
        })?;
        Ok(Self {
            path: path.to_path_buf(),
            target,
            batch: Batch::default(),
            worker,
            mode_names: Vec::new(),
            path_drawn: ReferencePath::default(),
        })
    }

    /// Queues an item, handing the batch over when it is full.
    fn push(&mut self, item: Item) -> Result<(), OutputError> {
        self.batch.items.push(item);
        if self.batch.items.len() >= BATCH {
            self.send()?;
        }
        Ok(())
    }

    fn send(&mut self) -> Result<(), OutputError> {
        let next = self.worker.recycled().unwrap_or_else(|| Batch {
            samples: Vec::with_capacity(BATCH),
            extra: Vec::with_capacity(self.batch.extra.capacity()),
            bytes: Vec::new(),
            items: Vec::with_capacity(BATCH),
        });
        let batch = std::mem::replace(&mut self.batch, next);
        self.worker.send(batch)
    }

    /// Queues `m`, encoded here, on channel slot `slot` at `t`.
    fn put_encoded(
        &mut self,
        slot: u8,
        t: f64,
        m: &impl foxglove::Encode,
    ) -> Result<(), OutputError> {
        let before = self.batch.bytes.len();
        m.encode(&mut self.batch.bytes)
            .map_err(|x| err(&self.path, x))?;
        let len = self.batch.bytes.len() - before;
        self.push(Item::Encoded {
            slot,
            ns: nanos(t),
            len,
        })
    }

    fn put_switch(&mut self, t: f64, from: usize, to: usize) -> Result<(), OutputError> {
        let name = self.mode_names.get(to).copied().unwrap_or("none");
        let m = msg::ModeSwitch {
            t,
            from: u32::try_from(from).unwrap_or(u32::MAX),
            to: u32::try_from(to).unwrap_or(u32::MAX),
            mode: name.to_string(),
        };
        let before = self.batch.bytes.len();
        m.encode(&mut self.batch.bytes)
            .map_err(|x| err(&self.path, x))?;
        let len = self.batch.bytes.len() - before;
        self.push(Item::Encoded {
            slot: 6,
            ns: nanos(t),
            len,
        })
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
        if !self.batch.items.is_empty() {
            self.send()?;
        }
        let (mut w, mut messages) = self.worker.join()?;
        let path = self.path.clone();
        let e = |x: std::io::Error| err_io(&path, &x);
        if let Some((t0, update)) = self.path_drawn.scene_update() {
            let ns = nanos(t0);
            let schema = add_schema(&mut w, msg::SceneUpdate::get_schema()).map_err(e)?;
            let meta = BTreeMap::new();
            let ch = w
                .add_channel(schema, REFERENCE_TOPIC, "protobuf", &meta)
                .map_err(e)?;
            let mut data = Vec::new();
            update
                .encode(&mut data)
                .map_err(|x| e(std::io::Error::other(x.to_string())))?;
            w.message(ch, 0, ns, &data).map_err(e)?;
            messages += 1;
        }
        if !warnings.is_empty() {
            let metadata = warnings
                .iter()
                .enumerate()
                .map(|(k, w)| (format!("warning {}", k + 1), w.clone()))
                .collect();
            w.metadata("warnings", &metadata).map_err(e)?;
        }
        if let Some(s) = stopped {
            let metadata = [
                ("t".to_string(), format!("{}", s.t)),
                ("reason".to_string(), s.reason.clone()),
            ]
            .into_iter()
            .collect();
            w.metadata("stopped", &metadata).map_err(e)?;
        }
        let f = w
            .finish()
            .map_err(e)?
            .into_inner()
            .map_err(|x| err_io(&path, x.error()))?;
        self.target.commit(&f, &path)?;
        Ok(messages)
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

    fn measurement(&mut self, m: &MeasurementRecord) -> Result<(), OutputError> {
        let v = |a: [f64; 3]| msg::Vector3 {
            x: a[0],
            y: a[1],
            z: a[2],
        };
        match *m {
            MeasurementRecord::Imu { t, accel, gyro, .. } => {
                let m = msg::ImuReading {
                    t,
                    accel: v(accel),
                    gyro: v(gyro),
                };
                self.put_encoded(SENSOR_SLOTS[0], t, &m)
            }
            MeasurementRecord::Mocap { t, arrival, state } => {
                let [x, y, z, w] = quaternion_xyzw(&state.r);
                let m = msg::MocapFrame {
                    t,
                    arrival,
                    position: v(state.x),
                    velocity: v(state.v),
                    orientation: msg::Quaternion { x, y, z, w },
                    omega: v(state.omega),
                };
                self.put_encoded(SENSOR_SLOTS[1], t, &m)
            }
            MeasurementRecord::Gps {
                t,
                arrival,
                x,
                v: vel,
            } => {
                let m = msg::GpsFix {
                    t,
                    arrival,
                    position: v(x),
                    velocity: v(vel),
                };
                self.put_encoded(SENSOR_SLOTS[2], t, &m)
            }
            MeasurementRecord::Baro { t, height } => {
                self.put_encoded(SENSOR_SLOTS[3], t, &msg::BaroReading { t, height })
            }
            _ => Ok(()),
        }
    }

    fn sample(&mut self, s: &Sample) -> Result<(), OutputError> {
        if let Some(e) = s.sensors.as_deref().and_then(|r| r.estimate) {
            let [x, y, z, w] = quaternion_xyzw(&e.r);
            let (sec, nsec) = proto::sec_nsec(nanos(s.t));
            let pose = PoseInFrame {
                timestamp: Some(msg::Timestamp::new(sec, nsec)),
                frame_id: "ned".into(),
                pose: Some(msg::Pose {
                    position: Some(msg::Vector3 {
                        x: e.x[0],
                        y: e.x[1],
                        z: e.x[2],
                    }),
                    orientation: Some(msg::Quaternion { x, y, z, w }),
                }),
            };
            self.put_encoded(SENSOR_SLOTS[4], s.t, &pose)?;
        }
        if let Some(d) = s.sensors.as_deref().and_then(|r| r.diagnostics) {
            let (nis, dof) = d.nis.unwrap_or((0.0, 0));
            let m = msg::EstimateDiagnostics {
                sigma: d.sigma[..d.states].to_vec(),
                nis,
                nis_dof: dof as u32,
                innovation: d.innovation[..dof.min(6)].to_vec(),
            };
            self.put_encoded(SENSOR_SLOTS[5], s.t, &m)?;
        }
        self.path_drawn.push(s);
        self.batch.samples.push(Fixed::of(s));
        self.batch.extra.extend_from_slice(&s.rotors);
        self.batch.extra.extend_from_slice(&s.vehicle_states);
        self.push(Item::Sample {
            rotors: s.rotors.len(),
            states: s.vehicle_states.len(),
        })
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
    for m in &out.measurements {
        w.measurement(m)?;
    }
    let stopped = out.interrupted_at().map(|t| Stopped {
        t,
        reason: "interrupted".into(),
    });
    w.finish(&out.warnings, stopped.as_ref())
}
