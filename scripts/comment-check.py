#!/usr/bin/env python3
"""Fails when a comment under a crate's `src/` carries a measurement.

Timings, instruction counts and speed-ups rot as the code around them
changes; they belong in commit messages and in the performance chapter of
the guide, which `cargo xtask bench --report` regenerates. A comment keeps
one sentence of why. The few lines that must keep a matching phrase are
listed in `scripts/comment-allow.txt` as `path: text  # reason`.

Usage: scripts/comment-check.py   (from anywhere; prints what it found)
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
PATTERN = re.compile(
    r"(ns|µs) per|per 1 ?000 steps|callgrind|instructions (per|a step)"
    r"|% (faster|slower|fewer|more)|\(measured\)"
)
MAX_ALLOWED = 10


def comment_of(line: str):
    """The comment part of a Rust source line, or None (a `//` inside a
    string literal, e.g. a URL, is not a comment)."""
    in_str = False
    i = 0
    while i < len(line) - 1:
        c = line[i]
        if c == "\\" and in_str:
            i += 2
            continue
        if c == '"':
            in_str = not in_str
        elif not in_str and line.startswith("//", i):
            return line[i:]
        i += 1
    return None


def allow_list():
    path = ROOT / "scripts" / "comment-allow.txt"
    entries = []
    for n, raw in enumerate(path.read_text().splitlines(), 1):
        if not raw.strip() or raw.startswith("#"):
            continue
        body, sep, reason = raw.partition("  # ")
        file, sep2, text = body.partition(": ")
        if not sep or not sep2 or not reason.strip():
            sys.exit(f"{path}:{n}: expected `path: text  # reason`, got {raw!r}")
        entries.append((file.strip(), text.strip(), n))
    if len(entries) > MAX_ALLOWED:
        sys.exit(f"{path}: {len(entries)} allowed lines, at most {MAX_ALLOWED}")
    return entries


def main():
    allowed = allow_list()
    used = set()
    hits = []
    files = sorted(ROOT.glob("*/src/**/*.rs"))
    for f in files:
        rel = f.relative_to(ROOT).as_posix()
        for n, line in enumerate(f.read_text().splitlines(), 1):
            c = comment_of(line)
            if c is None or not PATTERN.search(c):
                continue
            match = [e for e in allowed if e[0] == rel and e[1] in line]
            if match:
                used.update(e[2] for e in match)
            else:
                hits.append(f"{rel}:{n}: {line.strip()}")
    stale = [e for e in allowed if e[2] not in used]
    for h in hits:
        print(f"measurement in a comment: {h}")
    for file, text, n in stale:
        print(f"scripts/comment-allow.txt:{n}: no longer matches ({file}: {text})")
    print(
        f"comment check: {len(files)} files, {len(hits)} measurement(s) in comments, "
        f"{len(allowed)} allow-listed line(s) (at most {MAX_ALLOWED})"
    )
    sys.exit(1 if hits or stale else 0)


if __name__ == "__main__":
    main()
