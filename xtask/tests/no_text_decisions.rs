//! No code decides anything from an error's text: errors are typed, and
//! code matches on variants and fields. This scans the source of every
//! crate (unit-test modules and test files aside, which check messages on
//! purpose) for reading an error's message: `.to_string().contains(…)` and
//! the like, or `contains`/`starts_with`/`ends_with`/`find` on a variable
//! named as an error or a message.

use std::path::{Path, PathBuf};

const NAMES: [&str; 7] = ["e", "err", "error", "msg", "message", "reason", "why"];
const METHODS: [&str; 4] = ["contains(", "starts_with(", "ends_with(", "find("];

/// Whether `line` reads text out of an error.
fn reads_error_text(line: &str) -> bool {
    let code = line.split("//").next().unwrap_or("");
    for m in METHODS {
        if code.contains(&format!(".to_string().{m}")) {
            return true;
        }
        for n in NAMES {
            let pat = format!("{n}.{m}");
            let mut rest = code;
            while let Some(k) = rest.find(&pat) {
                let before = rest[..k].chars().last();
                if !before.is_some_and(|c| c.is_alphanumeric() || c == '_' || c == '.') {
                    return true;
                }
                rest = &rest[k + pat.len()..];
            }
        }
    }
    false
}

/// The file up to its unit-test module (`#[cfg(test)]`, maybe more
/// attributes, then `mod`: the crate's convention puts it last).
fn shipped(text: &str) -> &str {
    let mut from = 0;
    while let Some(k) = text[from..].find("#[cfg(test)]") {
        let at = from + k;
        let next_item = text[at..]
            .lines()
            .skip(1)
            .find(|l| !l.trim_start().starts_with("#["))
            .unwrap_or("");
        if next_item.trim_start().starts_with("mod ") {
            return &text[..at];
        }
        from = at + 1;
    }
    text
}

fn sources(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in std::fs::read_dir(dir).unwrap().flatten() {
        let p = entry.path();
        if p.is_dir() {
            sources(&p, out);
        } else if p.extension().is_some_and(|e| e == "rs") {
            out.push(p);
        }
    }
}

#[test]
fn no_code_reads_an_errors_text() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).parent().unwrap();
    let mut files = Vec::new();
    for krate in [
        "lie",
        "controllers",
        "dynamics",
        "integrators",
        "scenarios",
        "xtask",
    ] {
        sources(&root.join(krate).join("src"), &mut files);
        let examples = root.join(krate).join("examples");
        if examples.is_dir() {
            sources(&examples, &mut files);
        }
    }
    assert!(
        files.len() > 40,
        "{} files: the scan found the crates",
        files.len()
    );
    let mut found = Vec::new();
    for f in &files {
        let text = std::fs::read_to_string(f).unwrap();
        let code = shipped(&text);
        for (k, line) in code.lines().enumerate() {
            if reads_error_text(line) {
                found.push(format!("{}:{}: {}", f.display(), k + 1, line.trim()));
            }
        }
    }
    assert!(
        found.is_empty(),
        "code reading an error's text:\n{}",
        found.join("\n")
    );
}

/// The scan finds what it is for, and not method calls on other names.
#[test]
fn the_scan_sees_text_decisions() {
    assert!(reads_error_text(
        r#"if msg.contains("substeps in one call") {"#
    ));
    assert!(reads_error_text(
        r#"Some(c) if c.to_string().contains("`reference") => x,"#
    ));
    assert!(reads_error_text(r#"    e.starts_with("--csv")"#));
    assert!(!reads_error_text(r#"if name.contains('.') {"#));
    assert!(!reads_error_text(
        r#"let t = the.message.len(); // e.contains("x")"#
    ));
    assert!(!reads_error_text(r#"if s.e.contains(x) {"#));
}
