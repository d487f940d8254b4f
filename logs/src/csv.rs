//! The CSV writer: one row per sample, numbers in their shortest
//! round-trip form, formatted and written on a thread of its own.

use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};

use super::*;
use scenarios::{RunOutput, Sample, SwitchRecord};

/// The shortest round-trip decimal form of `x` (`NaN`, `inf`, `-inf` when
/// not finite).
fn push_num(buf: &mut Vec<u8>, x: f64) {
    let mut b = zmij::Buffer::new();
    buf.extend_from_slice(b.format(x).as_bytes());
}

/// Numbers of a row before the mode column: t, x, v, R (rows), Ω, Ψ,
/// ‖e_x‖, f, M.
const CSV_FIXED: usize = 25;

/// Numbers a run with sensors adds after the vehicle's states: the
/// estimate (x, v, R by rows, Ω), the latest accelerometer and gyroscope
/// readings, motion-capture and GPS positions and barometric height, the
/// estimator's 15 standard deviations (its own error states, in its order),
/// last NIS and last innovation (6), each `NaN` where the run has not got
/// it.
const SENSOR_COLUMNS: usize = 53;

/// The names of the [`SENSOR_COLUMNS`], comma first.
fn sensor_header() -> String {
    let mut h = String::new();
    let mut add = |prefix: &str, n: usize| {
        for k in 1..=n {
            h.push_str(&format!(",{prefix}{k}"));
        }
    };
    add("est_x", 3);
    add("est_v", 3);
    for i in 1..=3 {
        add(&format!("est_r{i}"), 3);
    }
    add("est_w", 3);
    add("acc", 3);
    add("gyr", 3);
    add("mocap_x", 3);
    add("gps_x", 3);
    add("baro_h", 1);
    add("est_sigma", 15);
    add("est_nis", 1);
    add("est_innov", 6);
    h.replace(",baro_h1", ",baro_h")
        .replace(",est_nis1", ",est_nis")
}

/// The sensor columns of `s` (nothing without sensors).
fn sensor_numbers(s: &Sample, out: &mut Vec<f64>) {
    let Some(r) = s.sensors.as_deref() else {
        return;
    };
    let nan3 = [f64::NAN; 3];
    match &r.estimate {
        Some(e) => {
            out.extend_from_slice(&e.x);
            out.extend_from_slice(&e.v);
            e.r.iter().for_each(|row| out.extend_from_slice(row));
            out.extend_from_slice(&e.omega);
        }
        None => out.extend_from_slice(&[f64::NAN; 18]),
    }
    for v in [r.accel, r.gyro, r.mocap_x, r.gps_x] {
        out.extend_from_slice(&v.unwrap_or(nan3));
    }
    out.push(r.baro.unwrap_or(f64::NAN));
    match &r.diagnostics {
        Some(d) => {
            out.extend_from_slice(&d.sigma);
            out.push(d.nis.map_or(f64::NAN, |n| n.0));
            out.extend_from_slice(&d.innovation);
        }
        None => out.extend_from_slice(&[f64::NAN; 22]),
    }
}

/// The width of `s`'s row.
fn row_width(s: &Sample) -> usize {
    CSV_FIXED
        + s.vehicle_states.len()
        + if s.sensors.is_some() {
            SENSOR_COLUMNS
        } else {
            0
        }
}

/// A row's numbers in column order: the fixed ones, the vehicle's states,
/// then the sensor columns of a run with sensors.
fn csv_numbers(s: &Sample, out: &mut Vec<f64>) {
    out.push(s.t);
    out.extend_from_slice(&s.x);
    out.extend_from_slice(&s.v);
    s.r.iter().for_each(|r| out.extend_from_slice(r));
    out.extend_from_slice(&s.omega);
    out.extend_from_slice(&[s.psi, s.ex, s.thrust]);
    out.extend_from_slice(&s.moment);
    out.extend_from_slice(&s.vehicle_states);
    sensor_numbers(s, out);
}

/// Formats one row (no line end) from its numbers and mode.
fn push_csv_row_from(row: &mut Vec<u8>, nums: &[f64], mode: &str) {
    for &x in &nums[..CSV_FIXED] {
        push_num(row, x);
        row.push(b',');
    }
    row.extend_from_slice(mode.as_bytes());
    for &x in &nums[CSV_FIXED..] {
        row.push(b',');
        push_num(row, x);
    }
}

fn push_csv_row(row: &mut Vec<u8>, s: &Sample) {
    let mut nums = Vec::with_capacity(row_width(s));
    csv_numbers(s, &mut nums);
    push_csv_row_from(row, &nums, s.mode);
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

/// Rows handed to the CSV thread: their numbers (`width` per row) and
/// modes.
struct CsvBatch {
    width: usize,
    /// The rows end with the sensor columns.
    sensors: bool,
    nums: Vec<f64>,
    modes: Vec<&'static str>,
}

/// Rows per batch handed to the CSV thread.
const CSV_BATCH: usize = 4096;

/// Bytes gathered before each write to the file.
const CSV_CHUNK: usize = 1 << 20;

/// The CSV thread: the header at the first batch (whose width tells the
/// vehicle's state count), then whole rows. Rows are formatted straight
/// into the buffer that goes to the file, written in pieces of about
/// [`CSV_CHUNK`] bytes that each end with a whole row (through a
/// `BufWriter`, each row was copied once more: 0.6 % of the instructions
/// of a CSV-only run at 1 kHz, 2 % of this thread's).
fn write_csv_batches(mut file: File, (rx, back): WorkerEnds<CsvBatch>) -> std::io::Result<File> {
    let mut header = false;
    let mut out = Vec::with_capacity(CSV_CHUNK + 4096);
    for mut b in rx {
        if !header {
            header = true;
            let extra = if b.sensors { SENSOR_COLUMNS } else { 0 };
            out.extend_from_slice(csv_header(b.width - CSV_FIXED - extra).as_bytes());
            if b.sensors {
                out.extend_from_slice(sensor_header().as_bytes());
            }
            out.push(b'\n');
        }
        for (nums, mode) in b.nums.chunks_exact(b.width).zip(&b.modes) {
            push_csv_row_from(&mut out, nums, mode);
            out.push(b'\n');
            if out.len() >= CSV_CHUNK {
                file.write_all(&out)?;
                out.clear();
            }
        }
        b.nums.clear();
        b.modes.clear();
        // The writer gone (its run failed) needs no buffers back.
        let _ = back.send(b);
    }
    file.write_all(&out)?;
    Ok(file)
}

/// Streams samples to a CSV file (the header comes with the first sample,
/// which tells the vehicle's internal-state count). Rows are whole lines:
/// what [`CsvWriter::finish`] flushes ends with the last complete row.
///
/// The caller's thread only copies each sample's numbers; a thread of the
/// writer's own formats and writes them (shortest round-trip decimals cost
/// more than the simulation step at 1 kHz sampling), through a bounded
/// queue, as [`McapWriter`] does.
pub struct CsvWriter {
    path: PathBuf,
    target: Target,
    batch: CsvBatch,
    rows: u64,
    worker: Worker<CsvBatch, File>,
}

impl CsvWriter {
    /// Creates `<path>.partial` (a stream such as `/dev/null` or a pipe is
    /// written in place) and starts the writer thread.
    pub fn create(path: &Path) -> Result<Self, OutputError> {
        let (target, f) = Target::open(path)?;
        let csv_path = path.to_path_buf();
        let worker = Worker::spawn(path, "csv-writer", move |ends| {
            write_csv_batches(f, ends).map_err(|e| err_io(&csv_path, &e))
        })?;
        Ok(Self {
            path: path.to_path_buf(),
            target,
            batch: CsvBatch {
                width: 0,
                sensors: false,
                nums: Vec::new(),
                modes: Vec::new(),
            },
            rows: 0,
            worker,
        })
    }

    /// Rows written so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    fn send(&mut self) -> Result<(), OutputError> {
        let (width, sensors) = (self.batch.width, self.batch.sensors);
        let next = match self.worker.recycled() {
            Some(b) => CsvBatch {
                width,
                sensors,
                ..b
            },
            None => CsvBatch {
                width,
                sensors,
                nums: Vec::with_capacity(width * CSV_BATCH),
                modes: Vec::with_capacity(CSV_BATCH),
            },
        };
        let batch = std::mem::replace(&mut self.batch, next);
        self.worker.send(batch)
    }

    /// Writes what is queued, flushes, syncs and renames `<path>.partial`
    /// to `<path>`; returns the row count.
    pub fn finish(mut self) -> Result<u64, OutputError> {
        if self.batch.width == 0 {
            // No sample: the header alone.
            self.batch.width = CSV_FIXED;
        }
        self.send()?;
        let f = self.worker.join()?;
        self.target.commit(&f, &self.path)?;
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
        let width = row_width(s);
        if self.batch.width == 0 {
            self.batch.width = width;
            self.batch.sensors = s.sensors.is_some();
        } else if width != self.batch.width || s.sensors.is_some() != self.batch.sensors {
            return Err(err(
                &self.path,
                format!(
                    "a sample {} columns after rows of {}: the columns are fixed by the first",
                    width, self.batch.width
                ),
            ));
        }
        csv_numbers(s, &mut self.batch.nums);
        self.batch.modes.push(s.mode);
        self.rows += 1;
        if self.batch.modes.len() >= CSV_BATCH {
            self.send()?;
        }
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
