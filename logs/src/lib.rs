//! CSV and MCAP output, streamed.
//!
//! A run hands each [`Sample`](scenarios::Sample) and mode switch to a [`Sink`] as it produces
//! them ([`scenarios::RunOptions::sink`]), so memory stays bounded whatever the
//! duration. [`CsvWriter`] and [`McapWriter`] are the two sinks shipped;
//! [`Tee`] feeds several at once. Both write a file to `<name>.partial` and
//! rename it to `<name>` in `finish`: a run killed outright (SIGKILL, power
//! loss) leaves a `.partial` file, never a truncated file under the
//! requested name, and any other failure removes the `.partial`. A stream
//! (a character device such as `/dev/null`, a FIFO, a pipe behind
//! `/dev/stdout`) is written in place: renaming over it would replace the
//! device node with a regular file. A directory or a dangling link is an
//! error at `create`, before anything is written ([`classify_output`]). [`write_csv`] and [`write_mcap`] write a finished [`RunOutput`](scenarios::RunOutput)
//! through the same writers.
//!
//! CSV numbers are written in the shortest form that parses back to the
//! same f64 (the `zmij` formatter, which `serde_json` uses too), so a value
//! read back is the sample's bit for bit; a non-finite value is `NaN`/`inf`.
//! MCAP messages are protobuf (Foxglove's `PoseInFrame` and
//! `FrameTransform`, and the [`msg`] types), whose doubles are the
//! sample's bits.

use std::fs::File;
use std::path::{Path, PathBuf};

pub use scenarios::{OutputError, Sink, Tee, Watched};

mod csv;
mod mcap_chunks;
mod mcap_file;
mod paths;
mod proto;
mod reference_path;
mod table_log;
pub use csv::{CsvWriter, csv_header, csv_row, write_csv};
pub use mcap_file::{
    McapWriter, REFERENCE_TOPIC, SENSOR_TOPICS, STATES_TOPIC, STATIC_TF_NS, TOPICS, WIND_TOPIC,
    msg, quaternion_xyzw, write_mcap,
};
pub use paths::{PathError, check_paths, is_stdout};
pub use reference_path::{MAX_POINTS, ReferencePath};
pub use table_log::{Table, write_tables};

/// The CSV header, fixed.
pub const CSV_HEADER: &str =
    "t,x1,x2,x3,v1,v2,v3,r11,r12,r13,r21,r22,r23,r31,r32,r33,w1,w2,w3,psi,ex,f,m1,m2,m3,mode";

fn err(path: &Path, e: impl std::fmt::Display) -> OutputError {
    OutputError {
        path: path.to_path_buf(),
        message: e.to_string(),
        io_kind: None,
    }
}

/// An I/O error, keeping its kind.
fn err_io(path: &Path, e: &std::io::Error) -> OutputError {
    OutputError {
        io_kind: Some(e.kind()),
        ..err(path, e)
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

/// An error with its causes: the MCAP crate's I/O error says only "I/O
/// error from writing", and the cause (`No space left on device`) is
/// what the reader needs.
fn err_chain(path: &Path, e: &dyn std::error::Error) -> OutputError {
    let mut message = e.to_string();
    let mut io_kind = None;
    let mut cause = e.source();
    while let Some(c) = cause {
        message.push_str(": ");
        message.push_str(&c.to_string());
        if let Some(io) = c.downcast_ref::<std::io::Error>() {
            io_kind = Some(io.kind());
        }
        cause = c.source();
    }
    OutputError {
        io_kind,
        ..err(path, message)
    }
}

fn temp_path(path: &Path) -> PathBuf {
    let mut name = path.file_name().unwrap_or_default().to_os_string();
    name.push(".partial");
    path.with_file_name(name)
}

/// What an output path names, as far as writing it is concerned.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PathKind {
    /// Nothing there yet: written as `<name>.partial`, renamed when closed.
    New,
    /// A regular file (or a symlink to one): replaced the same way, so a
    /// run that dies leaves the old file intact.
    Regular,
    /// A character device, FIFO or socket (`/dev/null`, `/dev/stdout` on a
    /// pipe): written in place. Renaming over it would replace the device
    /// node with a regular file, for the whole machine when run as root.
    Stream,
}

/// Classifies an output path before anything is written, so that a bad
/// one fails before a run starts: a directory, a symlink loop or dangling
/// link, or a parent directory that does not exist is an error naming the
/// path.
pub fn classify_output(path: &Path) -> Result<PathKind, OutputError> {
    use std::os::unix::fs::FileTypeExt;
    match std::fs::metadata(path) {
        Ok(m) if m.is_file() => Ok(PathKind::Regular),
        Ok(m) if m.is_dir() => Err(err(path, "is a directory, not a file")),
        Ok(m) => {
            let t = m.file_type();
            if t.is_char_device() || t.is_fifo() || t.is_socket() {
                Ok(PathKind::Stream)
            } else {
                Err(err(
                    path,
                    "is neither a file nor a stream (a block device?)",
                ))
            }
        }
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            if std::fs::symlink_metadata(path).is_ok() {
                return Err(err(path, "is a symlink to nothing"));
            }
            let dir = match path.parent() {
                Some(d) if !d.as_os_str().is_empty() => d,
                _ => Path::new("."),
            };
            match std::fs::metadata(dir) {
                Ok(m) if m.is_dir() => Ok(PathKind::New),
                Ok(_) => Err(err(path, format!("{} is not a directory", dir.display()))),
                Err(e) => Err(err(path, format!("directory {}: {e}", dir.display()))),
            }
        }
        Err(e) => Err(err(path, e)),
    }
}

/// An output being written: either `<name>.partial` (renamed to `<name>`
/// by [`Target::commit`], removed if dropped before that) or a stream
/// written in place.
struct Target {
    path: PathBuf,
    /// The `.partial` file while it exists.
    tmp: Option<PathBuf>,
}

impl Target {
    /// Opens `path` for writing as [`classify_output`] says.
    fn open(path: &Path) -> Result<(Self, File), OutputError> {
        match classify_output(path)? {
            PathKind::Stream => {
                let f = std::fs::OpenOptions::new()
                    .write(true)
                    .open(path)
                    .map_err(|e| err_io(path, &e))?;
                let t = Self {
                    path: path.to_path_buf(),
                    tmp: None,
                };
                Ok((t, f))
            }
            PathKind::New | PathKind::Regular => {
                // A symlink to a regular file: replace the file it names,
                // not the link.
                let real = path.canonicalize().unwrap_or_else(|_| path.to_path_buf());
                let tmp = temp_path(&real);
                let f = File::create(&tmp).map_err(|e| err_io(path, &e))?;
                let t = Self {
                    path: real,
                    tmp: Some(tmp),
                };
                Ok((t, f))
            }
        }
    }

    /// Syncs a file (a stream has nothing to sync: `fsync` on a pipe or
    /// `/dev/null` fails) and renames the `.partial` over the target.
    fn commit(&mut self, f: &File, shown: &Path) -> Result<(), OutputError> {
        if let Some(tmp) = &self.tmp {
            f.sync_all().map_err(|e| err_io(shown, &e))?;
            std::fs::rename(tmp, &self.path).map_err(|e| err_io(shown, &e))?;
            self.tmp = None;
        }
        Ok(())
    }
}

impl Drop for Target {
    fn drop(&mut self) {
        // Not committed: a write failed or the writer was abandoned. What
        // was written is incomplete; leave nothing behind.
        if let Some(tmp) = self.tmp.take() {
            let _ = std::fs::remove_file(tmp);
        }
    }
}

/// A writer thread fed batches through a bounded queue (two in flight:
/// enough to ride out a slow write, and memory stays a few MB); a writer
/// slower than the simulation slows it down instead of piling up samples.
/// The thread hands each batch back once written, so that a run allocates
/// its few batch buffers once, not one per batch.
struct Worker<T, R> {
    path: PathBuf,
    what: &'static str,
    tx: Option<std::sync::mpsc::SyncSender<T>>,
    back: std::sync::mpsc::Receiver<T>,
    thread: Option<std::thread::JoinHandle<Result<R, OutputError>>>,
}

/// The two ends a writer thread gets: batches to write, and the way back
/// for their emptied buffers.
type WorkerEnds<T> = (std::sync::mpsc::Receiver<T>, std::sync::mpsc::Sender<T>);

impl<T: Send + 'static, R: Send + 'static> Worker<T, R> {
    fn spawn(
        path: &Path,
        what: &'static str,
        work: impl FnOnce(WorkerEnds<T>) -> Result<R, OutputError> + Send + 'static,
    ) -> Result<Self, OutputError> {
        let (tx, rx) = std::sync::mpsc::sync_channel::<T>(2);
        let (back_tx, back) = std::sync::mpsc::channel::<T>();
        let thread = std::thread::Builder::new()
            .name(what.into())
            .spawn(move || work((rx, back_tx)))
            .map_err(|e| err(path, e))?;
        Ok(Self {
            path: path.to_path_buf(),
            what,
            tx: Some(tx),
            back,
            thread: Some(thread),
        })
    }

    /// A batch the thread has written and handed back, if one is waiting.
    fn recycled(&self) -> Option<T> {
        self.back.try_recv().ok()
    }

    fn send(&mut self, batch: T) -> Result<(), OutputError> {
        let tx = self
            .tx
            .as_ref()
            .ok_or_else(|| err(&self.path, "finished"))?;
        if tx.send(batch).is_err() {
            // The thread stopped on an error: report it.
            return Err(match self.join() {
                Err(e) => e,
                Ok(_) => err(&self.path, format!("the {} thread stopped", self.what)),
            });
        }
        Ok(())
    }

    /// Closes the queue and waits for the thread's result.
    fn join(&mut self) -> Result<R, OutputError> {
        self.tx = None;
        let h = self.thread.take().ok_or_else(|| {
            err(
                &self.path,
                format!("the {} thread already failed", self.what),
            )
        })?;
        match h.join() {
            Ok(r) => r,
            Err(_) => Err(err(
                &self.path,
                format!("the {} thread panicked", self.what),
            )),
        }
    }
}
