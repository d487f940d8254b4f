//! A non-finite reference injected mid-run, and the files read back.

use super::*;
use scenes::Error;

/// Position mode hovering at 1 m, its reference turning NaN at t = 1.5 s;
/// the run streams to CSV and MCAP.
pub(super) fn non_finite(r: &mut Report<'_>, _quick: bool, dir: &Path) -> Result<(), SuiteError> {
    type B = GlamF64;
    const T_BAD: f64 = 1.5;
    let reference = |t: f64| {
        let z = B::vec3(0.0, 0.0, 0.0);
        let x = if t < T_BAD {
            B::vec3(0.0, 0.0, -1.0)
        } else {
            B::vec3(0.0, f64::NAN, -1.0)
        };
        PositionReference::<B> {
            x,
            v: z,
            a: z,
            jerk: z,
            snap: z,
            b1d: B::vec3(1.0, 0.0, 0.0),
            b1d_dot: z,
            b1d_ddot: z,
        }
    };
    let mode = PositionMode::new(
        RigidBodyParams::<B>::diagonal(
            dynamics::paper::MASS,
            dynamics::paper::INERTIA,
            dynamics::paper::GRAVITY,
        ),
        PositionGains::paper(),
        AttitudeGains::paper(),
        AccelerationModel::Nominal,
        reference,
    );
    let quad = Quadrotor::<B>::paper()
        .with_disturbance(Quadrotor::<B>::paper_disturbance())
        .map_err(|e| failed("non-finite vehicle")(Error::Run(SimError::Vehicle(e))))?;
    let csv_path = dir.join("non-finite.csv");
    let mcap_path = dir.join("non-finite.mcap");
    let mut csv = logs::CsvWriter::create(&csv_path).map_err(SuiteError::Output)?;
    let mut mcap = logs::McapWriter::create(&mcap_path).map_err(SuiteError::Output)?;
    let sim = Simulation::<B>::builder(Box::new(quad))
        .mode(mode, Until::Never)
        .initial(RigidBodyState::<B>::at_rest())
        .dt(1e-3)
        .duration(4.0)
        .record_every(0.01)
        .build()
        .map_err(|e| failed("non-finite")(e.into()))?;
    let mut last_t = None;
    let result = {
        let mut tee = logs::Tee(vec![&mut csv as &mut dyn Sink, &mut mcap]);
        let mut sink = LastTime {
            inner: &mut tee,
            t: &mut last_t,
        };
        sim.run(RunOptions {
            record: false,
            sink: Some(&mut sink),
            ..Default::default()
        })
    };
    let message = match &result {
        Ok(_) => String::new(),
        Err(e) => e.to_string(),
    };
    r.note(format!("    the run says: {message}"));
    let held = last_t.unwrap_or(0.0);
    let rows = csv.finish().map_err(SuiteError::Output)?;
    let stopped = logs::Stopped {
        t: held,
        reason: format!("error: {message}"),
    };
    let messages = mcap
        .finish(&[], Some(&stopped))
        .map_err(SuiteError::Output)?;
    r.holds(
        "non-finite",
        "the run stops with an error".into(),
        result.is_err(),
        "a NaN reference must not fly on",
    );
    // What went wrong, from the error's variant and fields; then that the
    // message the user reads shows the same.
    let (field, t_err) = match &result {
        Err(SimError::Step {
            t,
            control: Some(controllers::ControlError::NonFiniteReference { field }),
            ..
        }) => (Some(*field), Some(*t)),
        _ => (None, None),
    };
    r.holds(
        "non-finite",
        format!("the error is the reference's and names the field (`reference.x`): {field:?}"),
        field == Some("reference.x"),
        "the user must learn which input went bad",
    );
    r.holds(
        "non-finite",
        format!("the error names the time, within one step of {T_BAD} s: {t_err:?}"),
        t_err.is_some_and(|t| (t - T_BAD).abs() <= 1e-3 + 1e-12),
        "the user must learn when it went bad",
    );
    let shown = t_err
        .is_some_and(|t| shows(&message, "reference.x") && shows(&message, &format!("t = {t}")));
    r.holds(
        "non-finite",
        format!("the message shows the field and the time: {message:?}"),
        shown,
        "the typed error reaches the user as a sentence",
    );
    // Read both files back.
    let (n, t_last) = csv_read_back(r, &csv_path, rows, T_BAD)?;
    mcap_read_back(r, &mcap_path, messages, n, t_last)?;
    Ok(())
}

/// Whether a message shown to the user contains `what` (a check of the
/// message itself; nothing is decided from it).
fn shows(text: &str, what: &str) -> bool {
    text.contains(what)
}

/// The non-finite case's CSV, read back: whole rows, increasing times, as
/// many as the writer said, the last one just before the NaN at `t_bad`.
/// Returns the row count and the last time.
fn csv_read_back(
    r: &mut Report<'_>,
    csv_path: &Path,
    rows: u64,
    t_bad: f64,
) -> Result<(u64, f64), SuiteError> {
    let text = std::fs::read_to_string(csv_path).map_err(unreadable(csv_path))?;
    let mut lines = text.lines();
    let header = lines.next().unwrap_or_default();
    let width = header.split(',').count();
    let (mut n, mut whole, mut t_last) = (0u64, true, f64::NAN);
    let mut increasing = true;
    for l in lines {
        let cells: Vec<&str> = l.split(',').collect();
        whole &= cells.len() == width;
        let t: f64 = cells[0].parse().unwrap_or(f64::NAN);
        // The first row compares against NaN: true.
        increasing &= t_last.is_nan() || t > t_last;
        t_last = t;
        n += 1;
    }
    r.holds(
        "non-finite",
        format!(
            "CSV: {n} rows (writer said {rows}), all whole, times increasing, last t = {t_last}"
        ),
        whole && increasing && n == rows && n > 0 && (t_bad - 0.011..t_bad).contains(&t_last),
        "everything sampled before the NaN is on disk, up to the last sample before it",
    );
    Ok((n, t_last))
}

/// The non-finite case's MCAP, read back: finished and indexed, every pose
/// decodes, one pose per CSV row (`n`) up to `t_last`, and a `stopped`
/// record there.
fn mcap_read_back(
    r: &mut Report<'_>,
    mcap_path: &Path,
    messages: u64,
    n: u64,
    t_last: f64,
) -> Result<(), SuiteError> {
    let bytes = std::fs::read(mcap_path).map_err(unreadable(mcap_path))?;
    let summary = mcap::Summary::read(&bytes)
        .map_err(unreadable(mcap_path))?
        .and_then(|s| s.stats)
        .map(|s| s.message_count);
    let (mut count, mut last_pose, mut poses) = (0u64, 0u64, 0u64);
    let mut all_decode = true;
    for m in mcap::MessageStream::new(&bytes).map_err(unreadable(mcap_path))? {
        let m = m.map_err(unreadable(mcap_path))?;
        if m.channel.topic == "/vehicle/pose" {
            use foxglove::Decode;
            all_decode &= foxglove::messages::PoseInFrame::decode(&m.data[..]).is_ok();
            poses += 1;
            last_pose = m.log_time;
        }
        count += 1;
    }
    let mut stopped_t = None;
    for rec in mcap::read::LinearReader::new(&bytes).map_err(unreadable(mcap_path))? {
        if let Ok(mcap::records::Record::Metadata(m)) = rec
            && m.name == "stopped"
        {
            stopped_t = m.metadata.get("t").and_then(|v| v.parse::<f64>().ok());
        }
    }
    r.holds(
        "non-finite",
        format!(
            "MCAP: {count} messages (writer said {messages}, summary {summary:?}), {poses} poses, last at {} s, `stopped` at {stopped_t:?}",
            last_pose as f64 * 1e-9
        ),
        summary == Some(count)
            && count == messages
            && all_decode
            && poses == n
            && last_pose == (t_last * 1e9).round() as u64
            && stopped_t == Some(t_last),
        "the MCAP is finished and indexed, readable to the last sample, and says where and why it stopped",
    );
    Ok(())
}

/// Remembers the time of the last sample passed on.
struct LastTime<'a, 'b> {
    inner: &'a mut dyn Sink,
    t: &'b mut Option<f64>,
}

impl Sink for LastTime<'_, '_> {
    fn begin(&mut self, mode_names: &[&'static str]) -> Result<(), logs::OutputError> {
        self.inner.begin(mode_names)
    }
    fn switch(&mut self, s: &scenarios::SwitchRecord, mode: &str) -> Result<(), logs::OutputError> {
        self.inner.switch(s, mode)
    }
    fn sample(&mut self, s: &Sample) -> Result<(), logs::OutputError> {
        *self.t = Some(s.t);
        self.inner.sample(s)
    }
}
