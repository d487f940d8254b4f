//! Where a run's output goes as the run produces it: the [`Sink`] trait the
//! engine writes into, and its error. The CSV and MCAP writers (the
//! `output` module, a layer above) are sinks; so is any type of a user's.

use std::path::PathBuf;

use super::{MeasurementRecord, Sample, SwitchRecord};

/// A failed write, naming the file.
#[derive(Clone, Debug, PartialEq)]
pub struct OutputError {
    /// The file asked for (its `.partial` is what was being written).
    pub path: PathBuf,
    /// What went wrong.
    pub message: String,
    /// The operating system's error kind when the failure was an I/O
    /// error (`BrokenPipe` when a reader such as `head` closed the pipe,
    /// `StorageFull`, …), so that a caller can tell them apart without
    /// reading the message.
    pub io_kind: Option<std::io::ErrorKind>,
}

impl std::fmt::Display for OutputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "writing {}: {}", self.path.display(), self.message)
    }
}

impl std::error::Error for OutputError {}

/// Receives a run's output as the run produces it. Calls come in time
/// order: [`Sink::begin`] once, then samples, with each mode switch
/// reported before the sample taken at its instant.
///
/// ```
/// use scenarios::{OutputError, RunOptions, Sample, Sink, SwitchRecord};
///
/// /// Keeps the largest Ψ after the switch, nothing else.
/// #[derive(Default)]
/// struct PeakAfterSwitch { switched: bool, peak: f64 }
/// impl Sink for PeakAfterSwitch {
///     fn begin(&mut self, _: &[&'static str]) -> Result<(), OutputError> { Ok(()) }
///     fn switch(&mut self, _: &SwitchRecord, _: &str) -> Result<(), OutputError> {
///         self.switched = true;
///         Ok(())
///     }
///     fn sample(&mut self, s: &Sample) -> Result<(), OutputError> {
///         if self.switched { self.peak = self.peak.max(s.psi); }
///         Ok(())
///     }
/// }
/// let mut sink = PeakAfterSwitch::default();
/// let mut scene = scenes::builtin::paper_flip();
/// scene.duration = 1.0;
/// let out = scenes::run(&scene, RunOptions { record: false, sink: Some(&mut sink), ..Default::default() })?;
/// assert!(out.samples.is_empty(), "nothing kept in memory");
/// assert!(sink.peak > 0.5, "the switch to position mode jumps Ψ: {}", sink.peak);
/// # Ok::<(), scenes::Error>(())
/// ```
pub trait Sink {
    /// Before the first sample: the name of each segment's mode, in plan
    /// order (empty without a plan).
    fn begin(&mut self, mode_names: &[&'static str]) -> Result<(), OutputError>;
    /// A mode switch; `mode` is the name of the mode entered.
    fn switch(&mut self, sw: &SwitchRecord, mode: &str) -> Result<(), OutputError>;
    /// One sample.
    fn sample(&mut self, s: &Sample) -> Result<(), OutputError>;
    /// One sensor measurement, in a run with sensors (ignored by default).
    /// They come in batches, after the samples of the same stretch of the
    /// run; each carries its own time.
    fn measurement(&mut self, m: &MeasurementRecord) -> Result<(), OutputError> {
        let _ = m;
        Ok(())
    }
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
    fn measurement(&mut self, m: &MeasurementRecord) -> Result<(), OutputError> {
        self.0.iter_mut().try_for_each(|s| s.measurement(m))
    }
}

/// A sink handing everything on to `inner` and remembering the time of the
/// last sample it handed on: a run that ends in an error can then say up to
/// where its files hold.
pub struct Watched<S> {
    /// The sink fed.
    pub inner: S,
    /// The time of the last sample, s (`None` before the first).
    pub last_t: Option<f64>,
}

impl<S> Watched<S> {
    /// Watches `inner`.
    pub fn new(inner: S) -> Self {
        Watched {
            inner,
            last_t: None,
        }
    }
}

impl<S: Sink> Sink for Watched<S> {
    fn begin(&mut self, mode_names: &[&'static str]) -> Result<(), OutputError> {
        self.inner.begin(mode_names)
    }
    fn switch(&mut self, sw: &SwitchRecord, mode: &str) -> Result<(), OutputError> {
        self.inner.switch(sw, mode)
    }
    fn sample(&mut self, s: &Sample) -> Result<(), OutputError> {
        self.last_t = Some(s.t);
        self.inner.sample(s)
    }
    fn measurement(&mut self, m: &MeasurementRecord) -> Result<(), OutputError> {
        self.inner.measurement(m)
    }
}
