//! `cargo xtask run` interrupted by real signals, in a real child process:
//! SIGINT and SIGTERM stop the run at the current step and leave complete,
//! readable CSV and MCAP files (every row whole, the MCAP finished with its
//! summary and a `stopped` record); SIGKILL leaves only `.partial` files.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

/// How long any wait on the child may take before the test fails: start-up
/// and a megabyte of output take well under a second on this machine, an
/// interrupted run closes its files in milliseconds.
const PATIENCE: Duration = Duration::from_secs(60);

/// The child run: killed and reaped when the guard goes, on every path,
/// a failed assertion included (a panic unwinds through `drop`), so no
/// hour-long run outlives its test.
struct Run(Child);

impl Drop for Run {
    fn drop(&mut self) {
        if let Ok(None) = self.0.try_wait() {
            let _ = self.0.kill();
        }
        let _ = self.0.wait();
    }
}

impl Run {
    /// Waits for the exit (at most `PATIENCE`) and returns the status and
    /// what the child wrote to stderr. stderr is read on a thread of its
    /// own, so a chatty child cannot block on a full pipe meanwhile.
    fn finish(mut self) -> (ExitStatus, String) {
        let mut pipe = self.0.stderr.take();
        let reader = std::thread::spawn(move || {
            let mut s = String::new();
            if let Some(p) = pipe.as_mut() {
                let _ = p.read_to_string(&mut s);
            }
            s
        });
        let t0 = Instant::now();
        let status = loop {
            if let Some(st) = self.0.try_wait().expect("the child can be waited for") {
                break st;
            }
            assert!(
                t0.elapsed() < PATIENCE,
                "the child did not exit within {PATIENCE:?}"
            );
            std::thread::sleep(Duration::from_millis(10));
        };
        (status, reader.join().unwrap_or_default())
    }
}

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gpid-signals-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// An hour of hover at 1 kHz sampling: far longer than the test waits.
fn start(d: &Path) -> Run {
    let child = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args([
            "run",
            "hover-disturbed",
            "--duration",
            "3600",
            "--sample",
            "0.001",
        ])
        .arg("--csv")
        .arg(d.join("a.csv"))
        .arg("--mcap")
        .arg(d.join("a.mcap"))
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("the xtask binary runs");
    Run(child)
}

/// Waits until the run has written something (so the signal lands mid-run,
/// not during start-up).
fn wait_for_output(d: &Path) {
    let t0 = Instant::now();
    let partial = d.join("a.csv.partial");
    while std::fs::metadata(&partial).map_or(0, |m| m.len()) < 1 << 20 {
        assert!(t0.elapsed() < PATIENCE, "no output after {PATIENCE:?}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

fn signal(child: &Run, sig: &str) {
    let ok = Command::new("kill")
        .args([sig, &child.0.id().to_string()])
        .status()
        .unwrap()
        .success();
    assert!(ok, "kill {sig} failed");
}

/// Reads the CSV back: every row whole (26 fields, numbers parse), times
/// strictly increasing; returns (rows, last t).
fn check_csv(path: &Path) -> (usize, f64) {
    let text = std::fs::read_to_string(path).unwrap();
    assert!(text.ends_with('\n'), "the CSV ends with a whole row");
    let mut lines = text.lines();
    assert!(lines.next().unwrap().starts_with("t,x1,"));
    let mut last = f64::NEG_INFINITY;
    let mut rows = 0;
    for line in lines {
        let f: Vec<&str> = line.split(',').collect();
        assert_eq!(f.len(), 26, "row {rows}: {line}");
        for x in &f[..25] {
            x.parse::<f64>()
                .unwrap_or_else(|_| panic!("row {rows}: {x}"));
        }
        let t: f64 = f[0].parse().unwrap();
        assert!(t > last, "row {rows}: time {t} after {last}");
        last = t;
        rows += 1;
    }
    (rows, last)
}

/// Reads the MCAP back: the summary is there and counts every message;
/// the poses run to `t_last`; a `stopped` record gives that time and the
/// reason.
fn check_mcap(path: &Path, rows: usize, t_last: f64, reason: &str) {
    let bytes = std::fs::read(path).unwrap();
    let summary = mcap::Summary::read(&bytes)
        .unwrap()
        .expect("a finished MCAP has a summary");
    let mut count = 0u64;
    let mut poses = 0usize;
    let mut last_pose = 0u64;
    for m in mcap::MessageStream::new(&bytes).unwrap() {
        let m = m.unwrap();
        if m.channel.topic == "/vehicle/pose" {
            use foxglove::Decode;
            let p = foxglove::messages::PoseInFrame::decode(&m.data[..]).unwrap();
            assert_eq!(p.frame_id, "ned");
            poses += 1;
            last_pose = m.log_time;
        }
        count += 1;
    }
    assert_eq!(summary.stats.unwrap().message_count, count);
    assert_eq!(poses, rows, "one pose per CSV row");
    assert_eq!(last_pose, (t_last * 1e9).round() as u64);
    let mut stopped = None;
    for rec in mcap::read::LinearReader::new(&bytes).unwrap() {
        if let mcap::records::Record::Metadata(m) = rec.unwrap()
            && m.name == "stopped"
        {
            stopped = Some(m.metadata.clone());
        }
    }
    let stopped = stopped.expect("a `stopped` metadata record");
    assert_eq!(stopped["reason"], reason);
    assert_eq!(stopped["t"].parse::<f64>().unwrap(), t_last);
}

fn interrupted_run_leaves_complete_files(sig: &str, name: &str, code: i32) {
    let d = dir(name);
    let child = start(&d);
    wait_for_output(&d);
    signal(&child, sig);
    let (status, stderr) = child.finish();
    assert_eq!(status.code(), Some(code), "stderr: {stderr}");
    assert!(stderr.contains(&format!("stopped by {name}")), "{stderr}");
    for f in ["a.csv.partial", "a.mcap.partial"] {
        assert!(!d.join(f).exists(), "{f} left behind");
    }
    let (rows, t_last) = check_csv(&d.join("a.csv"));
    assert!(
        rows > 1000 && t_last < 3600.0,
        "{rows} rows to t = {t_last}"
    );
    check_mcap(&d.join("a.mcap"), rows, t_last, name);
    std::fs::remove_dir_all(&d).ok();
}

#[test]
fn sigint_closes_the_files_and_exits_130() {
    interrupted_run_leaves_complete_files("-INT", "SIGINT", 130);
}

#[test]
fn sigterm_closes_the_files_and_exits_143() {
    interrupted_run_leaves_complete_files("-TERM", "SIGTERM", 143);
}

#[test]
fn sigkill_leaves_only_partial_files() {
    let d = dir("SIGKILL");
    let child = start(&d);
    wait_for_output(&d);
    signal(&child, "-KILL");
    let (status, _) = child.finish();
    assert_eq!(status.code(), None, "killed by a signal");
    assert!(d.join("a.csv.partial").exists());
    assert!(d.join("a.mcap.partial").exists());
    assert!(!d.join("a.csv").exists() && !d.join("a.mcap").exists());
    std::fs::remove_dir_all(&d).ok();
}

/// `--csv /dev/stdout | head -3`: the rows stream to the pipe, the
/// summary goes to stderr, and when the reader closes the pipe the run
/// ends quietly with SIGPIPE's status (141), as `yes | head` does, and no
/// error message.
#[test]
fn a_closed_pipe_ends_the_run_quietly() {
    use std::io::{BufRead, BufReader};
    let mut child = Run(Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args([
            "run",
            "hover-disturbed",
            "--duration",
            "100",
            "--csv",
            "/dev/stdout",
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap());
    let mut lines = BufReader::new(child.0.stdout.take().unwrap()).lines();
    let header = lines.next().unwrap().unwrap();
    assert!(header.starts_with("t,x1,x2,x3"), "{header}");
    for _ in 0..2 {
        let row = lines.next().unwrap().unwrap();
        assert!(row.split(',').count() == 26, "{row}");
    }
    drop(lines); // the reader goes away, as `head` does
    let (status, err) = child.finish();
    assert_eq!(status.code(), Some(141), "stderr: {err}");
    assert!(!err.contains("error"), "{err}");
}
