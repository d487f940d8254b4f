//! Where outputs may go: a new or regular file is written as `.partial`
//! and renamed; a stream (character device, FIFO) is written in place and
//! never replaced; a directory or dangling link is refused before anything
//! is written; no error leaves a `.partial` behind.
//!
//! The device tests use `mknod` copies of `/dev/null` and `/dev/full` in a
//! temporary directory, never the real nodes. `mknod` needs root (CI runs
//! as root); elsewhere those two tests say so and return.

use std::os::unix::fs::FileTypeExt;
use std::path::{Path, PathBuf};
use std::process::Command;

use logs::{CsvWriter, McapWriter, PathKind, classify_output, write_csv, write_mcap};
use scenarios::{RunOptions, RunOutput};
use scenes::{builtin, run};

fn tmpdir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("gpid-targets-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn short_run() -> RunOutput {
    let mut s = builtin::paper_flip();
    s.duration = 0.2;
    run(&s, RunOptions::default()).unwrap()
}

/// A device node like the real one (major, minor), in `dir`; `None` when
/// this process may not create device nodes.
fn device(dir: &Path, name: &str, major: u32, minor: u32) -> Option<PathBuf> {
    let p = dir.join(name);
    let ok = Command::new("mknod")
        .arg(&p)
        .arg("c")
        .arg(major.to_string())
        .arg(minor.to_string())
        .status()
        .is_ok_and(|s| s.success());
    if !ok {
        eprintln!("mknod is not permitted here (not root): device-node case not run");
        return None;
    }
    Some(p)
}

fn is_char_device(p: &Path) -> bool {
    std::fs::metadata(p).is_ok_and(|m| m.file_type().is_char_device())
}

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_null_device_is_written_in_place_and_stays_a_device() {
    let dir = tmpdir("null");
    let Some(null) = device(&dir, "null", 1, 3) else {
        return;
    };
    assert_eq!(classify_output(&null).unwrap(), PathKind::Stream);
    let out = short_run();
    assert_eq!(write_csv(&null, &out).unwrap(), out.samples.len() as u64);
    assert!(write_mcap(&null, &out).unwrap() > 0);
    assert!(is_char_device(&null), "the node was replaced by a file");
    assert_eq!(entries(&dir), ["null"], "nothing else written");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_full_device_is_a_clear_error_and_stays_a_device() {
    let dir = tmpdir("full");
    let Some(full) = device(&dir, "full", 1, 7) else {
        return;
    };
    let out = short_run();
    let e = write_csv(&full, &out).unwrap_err();
    assert_eq!(e.path, full);
    assert!(e.to_string().contains("No space left"), "{e}");
    let e = write_mcap(&full, &out).unwrap_err();
    assert!(e.to_string().contains("No space left"), "{e}");
    assert!(is_char_device(&full));
    assert_eq!(entries(&dir), ["full"]);
    std::fs::remove_dir_all(dir).ok();
}

/// A FIFO is streamed to a reader on another thread; the reader gets the
/// same bytes a file gets.
#[test]
fn a_fifo_is_streamed_and_stays_a_fifo() {
    let dir = tmpdir("fifo");
    let fifo = dir.join("pipe");
    assert!(
        Command::new("mkfifo")
            .arg(&fifo)
            .status()
            .unwrap()
            .success()
    );
    assert_eq!(classify_output(&fifo).unwrap(), PathKind::Stream);
    let out = short_run();
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).unwrap())
    };
    write_csv(&fifo, &out).unwrap();
    let got = reader.join().unwrap();
    write_csv(&dir.join("file.csv"), &out).unwrap();
    assert_eq!(got, std::fs::read(dir.join("file.csv")).unwrap());
    assert!(std::fs::metadata(&fifo).unwrap().file_type().is_fifo());
    // The MCAP writer never seeks, so it can stream too.
    let reader = {
        let fifo = fifo.clone();
        std::thread::spawn(move || std::fs::read(fifo).unwrap())
    };
    let n = write_mcap(&fifo, &out).unwrap();
    let bytes = reader.join().unwrap();
    let read = mcap::MessageStream::new(&bytes).unwrap().count() as u64;
    assert_eq!(read, n, "every message of the streamed MCAP reads back");
    assert_eq!(entries(&dir), ["file.csv", "pipe"]);
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn a_directory_or_dangling_link_fails_before_anything_is_written() {
    let dir = tmpdir("dir");
    let sub = dir.join("d");
    std::fs::create_dir(&sub).unwrap();
    let e = CsvWriter::create(&sub)
        .err()
        .expect("a directory is refused");
    assert!(e.to_string().contains("is a directory"), "{e}");
    let e = McapWriter::create(&sub)
        .err()
        .expect("a directory is refused");
    assert!(e.to_string().contains("is a directory"), "{e}");
    std::os::unix::fs::symlink(dir.join("nowhere"), dir.join("dangling")).unwrap();
    let e = classify_output(&dir.join("dangling")).unwrap_err();
    assert!(e.to_string().contains("symlink to nothing"), "{e}");
    let e = classify_output(&dir.join("nodir").join("a.csv")).unwrap_err();
    assert!(e.to_string().contains("nodir"), "{e}");
    assert_eq!(entries(&dir), ["d", "dangling"], "no .partial left");
    assert!(entries(&sub).is_empty());
    std::fs::remove_dir_all(dir).ok();
}

/// A read-only directory: a chmod 555 directory, or, where permission bits
/// do not bind (root), `/proc`, which no one can create files in.
#[test]
fn a_read_only_directory_is_an_error_at_create() {
    use std::os::unix::fs::PermissionsExt;
    let dir = tmpdir("ro");
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o555)).unwrap();
    let bites = std::fs::write(dir.join("probe"), b"").is_err();
    let target = if bites {
        dir.join("a.csv")
    } else {
        PathBuf::from("/proc/gpid-read-only-test.csv")
    };
    assert!(CsvWriter::create(&target).is_err());
    assert!(McapWriter::create(&target).is_err());
    std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o755)).unwrap();
    let left: Vec<String> = entries(&dir).into_iter().filter(|n| n != "probe").collect();
    assert!(left.is_empty(), "{left:?}");
    std::fs::remove_dir_all(dir).ok();
}

/// A regular file is replaced whole; through a symlink, the file it names
/// is replaced and the link stays a link.
#[test]
fn a_regular_file_is_replaced_and_a_symlink_kept() {
    let dir = tmpdir("regular");
    let file = dir.join("a.csv");
    std::fs::write(&file, "old").unwrap();
    std::os::unix::fs::symlink(&file, dir.join("link.csv")).unwrap();
    let out = short_run();
    write_csv(&dir.join("link.csv"), &out).unwrap();
    let meta = std::fs::symlink_metadata(dir.join("link.csv")).unwrap();
    assert!(meta.file_type().is_symlink(), "the link was replaced");
    let text = std::fs::read_to_string(&file).unwrap();
    assert!(text.starts_with("t,x1"), "the linked file holds the CSV");
    assert_eq!(entries(&dir), ["a.csv", "link.csv"]);
    std::fs::remove_dir_all(dir).ok();
}

/// A writer dropped without `finish` (an error path that never closes it)
/// removes its `.partial`; a failed write does too.
#[test]
fn no_partial_file_survives_an_abandoned_or_failed_writer() {
    use logs::Sink;
    let dir = tmpdir("abandon");
    let out = short_run();
    {
        let mut w = CsvWriter::create(&dir.join("a.csv")).unwrap();
        let mut m = McapWriter::create(&dir.join("a.mcap")).unwrap();
        m.begin(&["attitude"]).unwrap();
        for s in &out.samples {
            w.sample(s).unwrap();
            m.sample(s).unwrap();
        }
        assert!(dir.join("a.csv.partial").exists());
    }
    assert!(entries(&dir).is_empty(), "{:?}", entries(&dir));
    // Columns that change mid-file are an error, and leave nothing.
    let mut w = CsvWriter::create(&dir.join("b.csv")).unwrap();
    w.sample(&out.samples[0]).unwrap();
    let mut odd = out.samples[1].clone();
    odd.vehicle_states.push(1.0);
    assert!(w.sample(&odd).is_err());
    drop(w);
    assert!(entries(&dir).is_empty(), "{:?}", entries(&dir));
    std::fs::remove_dir_all(dir).ok();
}
