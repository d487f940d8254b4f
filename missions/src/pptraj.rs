//! The Crazyflie's piecewise-polynomial trajectory files (`pptraj`): a CSV
//! with one piece per row, `duration, x^0 … x^7, y^0 … y^7, z^0 … z^7,
//! yaw^0 … yaw^7` (seconds, metres, radians, each polynomial in the time
//! since its piece began), in the Crazyflie's z-up world frame, as
//! `uav_trajectories` writes them and the firmware's high-level commander
//! flies them. Here, as everywhere in the workspace, e₃ points down: a file
//! is read and written through [`Trajectory::flipped`].
//!
//! Numbers are written in Rust's shortest round-trip form, so a file
//! written here reads back to the same coefficients, bit for bit.

use std::fmt::Write as _;
use std::path::Path;

use crate::error::MissionError;
use crate::poly::{COEFFS, Piece};
use crate::trajectory::Trajectory;

const CELLS: usize = 1 + 4 * COEFFS;

/// The column names, `duration, x^0 … yaw^7`.
pub fn columns() -> Vec<String> {
    let mut c = vec!["duration".to_string()];
    for a in ["x", "y", "z", "yaw"] {
        c.extend((0..COEFFS).map(|j| format!("{a}^{j}")));
    }
    c
}

/// The trajectory a `pptraj` CSV describes (z-up), in this workspace's
/// frame. A first line of column names, blank lines, lines starting with
/// `#` and one empty cell after the last are accepted.
pub fn read(text: &str) -> Result<Trajectory, MissionError> {
    let names = columns();
    let mut pieces = Vec::new();
    for (n, raw) in text.lines().enumerate() {
        let line = raw.trim();
        let header = pieces.is_empty() && line.to_ascii_lowercase().starts_with("duration");
        if line.is_empty() || line.starts_with('#') || header {
            continue;
        }
        let mut cells: Vec<&str> = line.split(',').map(str::trim).collect();
        if cells.len() == CELLS + 1 && cells[CELLS].is_empty() {
            cells.pop();
        }
        if cells.len() != CELLS {
            return Err(MissionError::Row {
                line: n + 1,
                column: format!("count ({})", cells.len()),
                text: raw.to_string(),
                expected: "33 cells: duration and 8 coefficients each of x, y, z and yaw",
            });
        }
        let mut v = [0.0; CELLS];
        for (k, cell) in cells.iter().enumerate() {
            let x: f64 = cell
                .parse()
                .map_err(|_| row(n, &names[k], cell, "a number"))?;
            if !x.is_finite() {
                return Err(row(n, &names[k], cell, "finite"));
            }
            v[k] = x;
        }
        if v[0] <= 0.0 {
            return Err(row(n, "duration", cells[0], "positive (s)"));
        }
        pieces.push(Piece {
            duration: v[0],
            coeffs: std::array::from_fn(|a| std::array::from_fn(|j| v[1 + COEFFS * a + j])),
        });
    }
    if pieces.is_empty() {
        return Err(MissionError::Row {
            line: text.lines().count(),
            column: "duration".into(),
            text: String::new(),
            expected: "at least one piece",
        });
    }
    Ok(Trajectory::new(pieces)?.flipped())
}

fn row(n: usize, column: &str, text: &str, expected: &'static str) -> MissionError {
    MissionError::Row {
        line: n + 1,
        column: column.to_string(),
        text: text.to_string(),
        expected,
    }
}

/// `trajectory` as a `pptraj` CSV (z-up), with a first line of column
/// names.
pub fn write(trajectory: &Trajectory) -> String {
    let mut out = columns().join(",");
    out.push('\n');
    for p in trajectory.flipped().pieces() {
        let _ = write!(out, "{}", p.duration);
        for c in p.coeffs.iter().flatten() {
            let _ = write!(out, ",{c}");
        }
        out.push('\n');
    }
    out
}

/// [`read`] from a file.
pub fn read_file(path: &Path) -> Result<Trajectory, MissionError> {
    let text = std::fs::read_to_string(path).map_err(|source| MissionError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    read(&text)
}

/// [`write()`] to a file, whole or not at all: the text goes to a sibling
/// temporary file first, renamed over `path` once written.
pub fn write_file(path: &Path, trajectory: &Trajectory) -> Result<(), MissionError> {
    let io = |source| MissionError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".partial");
    let tmp = std::path::PathBuf::from(tmp);
    std::fs::write(&tmp, write(trajectory)).map_err(io)?;
    std::fs::rename(&tmp, path).map_err(io)
}
