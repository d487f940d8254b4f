//! Tables as MCAP channels: each CSV table (header first) becomes a channel
//! of JSON messages, one per row, with a JSON schema naming its fields, so
//! a benchmark's or a study's rows read with the same tools as the flight
//! logs.

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::fs::File;
use std::io::BufWriter;
use std::path::Path;

use super::{OutputError, err, err_chain};

/// One table for [`write_tables`].
#[derive(Clone, Copy, Debug)]
pub struct Table<'a> {
    /// The channel's topic, e.g. `/bench/summary`.
    pub topic: &'a str,
    /// The schema's name and title, e.g. `gpid.BenchRow`.
    pub schema: &'a str,
    /// CSV text: a header of field names, then one line per row (no
    /// quoting: a cell holds no comma).
    pub csv: &'a str,
}

/// A column's JSON type: a number when every non-empty cell is a finite
/// number (an empty cell is then `null`), a string otherwise.
fn numeric(rows: &[Vec<&str>], k: usize) -> (bool, bool) {
    let cells = || rows.iter().map(|r| r[k]);
    let number = cells().all(|c| c.is_empty() || c.parse::<f64>().is_ok_and(f64::is_finite));
    (number, number && cells().any(str::is_empty))
}

/// Whether `s` is a number in JSON's grammar,
/// `-?(0|[1-9][0-9]*)(.[0-9]+)?([eE][+-]?[0-9]+)?`: what Rust's float
/// formatting writes, but not every text `f64` parses (`.5`, `+1`, `1.`,
/// `007`).
fn is_json_number(s: &str) -> bool {
    let b = s.as_bytes();
    let mut i = usize::from(b.first() == Some(&b'-'));
    let digits = |i: &mut usize| {
        let start = *i;
        while b.get(*i).is_some_and(u8::is_ascii_digit) {
            *i += 1;
        }
        *i - start
    };
    let int_start = i;
    let n = digits(&mut i);
    if n == 0 || (n > 1 && b[int_start] == b'0') {
        return false;
    }
    if b.get(i) == Some(&b'.') {
        i += 1;
        if digits(&mut i) == 0 {
            return false;
        }
    }
    if matches!(b.get(i), Some(b'e' | b'E')) {
        i += 1;
        if matches!(b.get(i), Some(b'+' | b'-')) {
            i += 1;
        }
        if digits(&mut i) == 0 {
            return false;
        }
    }
    i == b.len()
}

fn json_string(out: &mut String, s: &str) {
    out.push('"');
    for c in s.chars() {
        match c {
            '"' => out.push_str("\\\""),
            '\\' => out.push_str("\\\\"),
            c if u32::from(c) < 0x20 => {
                let _ = write!(out, "\\u{:04x}", u32::from(c));
            }
            c => out.push(c),
        }
    }
    out.push('"');
}

/// Writes the tables to `path` (as `<path>.partial`, renamed when
/// complete), lz4-compressed: one channel per table, one message per row,
/// stamped `stamp_ns + 1, + 2, …` in order (a run's wall-clock time lines
/// up files of several runs). Number cells are written as they stand in
/// the CSV when that is JSON (Rust's float formatting always is), else
/// reformatted. Returns the number of messages.
///
/// Errors: a row whose cell count differs from the header's, naming the
/// table and the line; and the file's.
pub fn write_tables(path: &Path, stamp_ns: u64, tables: &[Table<'_>]) -> Result<u64, OutputError> {
    let tmp = super::temp_path(path);
    let written = write_to(path, &tmp, stamp_ns, tables);
    match written {
        Ok(n) => std::fs::rename(&tmp, path)
            .map(|()| n)
            .map_err(|e| super::err_io(path, &e)),
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            Err(e)
        }
    }
}

fn write_to(
    path: &Path,
    tmp: &Path,
    stamp_ns: u64,
    tables: &[Table<'_>],
) -> Result<u64, OutputError> {
    let mcap_err = |e: mcap::McapError| err_chain(path, &e);
    let file = BufWriter::new(File::create(tmp).map_err(|e| super::err_io(path, &e))?);
    let mut w = mcap::WriteOptions::new()
        // Uncompressed, as the flight logs: no compression codec to build.
        .compression(None)
        .profile("")
        .create(file)
        .map_err(mcap_err)?;
    let mut seq = 0u32;
    for t in tables {
        let mut lines = t.csv.lines();
        let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
        let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
        if let Some(k) = rows.iter().position(|r| r.len() != header.len()) {
            let msg = format!(
                "{}: line {} has {} cells, the header {}",
                t.topic,
                k + 2,
                rows[k].len(),
                header.len()
            );
            return Err(err(path, msg));
        }
        let kinds: Vec<(bool, bool)> = (0..header.len()).map(|k| numeric(&rows, k)).collect();
        let mut schema = format!(
            r#"{{"title":"{}","type":"object","properties":{{"#,
            t.schema
        );
        for (k, (name, (number, nullable))) in header.iter().zip(&kinds).enumerate() {
            let ty = match (number, nullable) {
                (true, true) => r#"["number","null"]"#,
                (true, false) => r#""number""#,
                _ => r#""string""#,
            };
            let sep = if k == 0 { "" } else { "," };
            let _ = write!(schema, r#"{sep}"{name}":{{"type":{ty}}}"#);
        }
        let required: Vec<String> = header.iter().map(|h| format!(r#""{h}""#)).collect();
        let _ = write!(schema, r#"}},"required":[{}]}}"#, required.join(","));
        let sid = w
            .add_schema(t.schema, "jsonschema", schema.as_bytes())
            .map_err(mcap_err)?;
        let ch = w
            .add_channel(sid, t.topic, "json", &BTreeMap::new())
            .map_err(mcap_err)?;
        for row in &rows {
            let mut m = String::from("{");
            for (k, (cell, (number, _))) in row.iter().zip(&kinds).enumerate() {
                m.push_str(if k == 0 { "" } else { "," });
                json_string(&mut m, header[k]);
                m.push(':');
                match (number, cell.is_empty()) {
                    (true, true) => m.push_str("null"),
                    (true, false) if is_json_number(cell) => m.push_str(cell),
                    // Parsed when the column was typed: finite.
                    (true, false) => {
                        let _ = write!(m, "{:?}", cell.parse::<f64>().unwrap_or_default());
                    }
                    _ => json_string(&mut m, cell),
                }
            }
            m.push('}');
            seq += 1;
            let header = mcap::records::MessageHeader {
                channel_id: ch,
                sequence: seq,
                log_time: stamp_ns + u64::from(seq),
                publish_time: stamp_ns + u64::from(seq),
            };
            w.write_to_known_channel(&header, m.as_bytes())
                .map_err(mcap_err)?;
        }
    }
    w.finish().map_err(mcap_err)?;
    Ok(u64::from(seq))
}
