#!/usr/bin/env python3
"""Runs the shell and Python blocks of the README and the guide; counts the rest.

Every fenced block of `README.md` and `geopid/guide/*.md` is one of:
- Rust (no info string, or `rust`): a doctest of the `geopid` crate, run by
  `cargo test --workspace`; counted here, and with `--doctest-log LOG` the
  log must show at least as many of geopid's doctests passed;
- shell (`sh`, `bash`, `console`) or Python (`python`): tagged `ci` (run
  here, in order, in one scratch directory per file) or `no-ci` (not run;
  its first line must be `# not run by CI: <reason>`); an untagged block is
  an error;
- anything else (`toml`, `text`, `c`): data shown to the reader.

Every `cargo … -p PKG`, `--example NAME` and `--test NAME` in a shell block,
run or not, must name a package, example or test of the workspace, so a
renamed package breaks CI, not a reader.

Blocks run with CI's debug binaries instead of rebuilding: `cargo xtask …`
runs `$XTASK`, `cargo run -p PKG --example NAME [-- ARGS]` runs
`$EXAMPLES/NAME ARGS`; `geopid` runs `$GEOPID` (the Rust command) and
`python` comes from `$VENV/bin` when given (the wheel's own console script
is run as `python -m geopid`, so the two never stand in for each other).

Usage: scripts/doc-blocks.py [--list] [--doctest-log LOG]
Environment: XTASK, GEOPID, EXAMPLES (CI's target/debug binaries and examples), VENV.
"""
import json
import os
import pathlib
import re
import shlex
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parent.parent
SHELL = {"sh", "bash", "console", "shell"}
RUST_ATTRS = {"ignore", "no_run", "should_panic", "compile_fail", "test_harness"}
REASON = re.compile(r"^# not run by CI: \S")
TIMEOUT = 600

PRELUDE = r'''
set -euo pipefail
geopid() { "$GEOPID" "$@"; }
cargo() {
    case "${1:-}" in
        xtask) shift; "$XTASK" "$@" ;;
        run)
            shift
            local example="" args=()
            while [ $# -gt 0 ]; do
                case "$1" in
                    --example) example="$2"; shift 2 ;;
                    -p|--package) shift 2 ;;
                    --release) shift ;;
                    --) shift; args=("$@"); break ;;
                    *) echo "doc-blocks: unsupported cargo run option $1" >&2; return 97 ;;
                esac
            done
            [ -n "$example" ] || { echo "doc-blocks: cargo run without --example" >&2; return 97; }
            "$EXAMPLES/$example" "${args[@]+"${args[@]}"}"
            ;;
        *) echo "doc-blocks: 'cargo $1' is not run from a block (tag it no-ci with a reason)" >&2; return 97 ;;
    esac
}
'''


def blocks(path):
    """(line, info tokens, body lines) of each fenced block of a file."""
    out, lines = [], path.read_text().splitlines()
    i = 0
    while i < len(lines):
        m = re.match(r"^(\s*)(```+|~~~+)(.*)$", lines[i])
        if not m:
            i += 1
            continue
        fence, info, start = m.group(2), m.group(3).strip(), i + 1
        body = []
        i += 1
        while i < len(lines) and not lines[i].strip().startswith(fence):
            body.append(lines[i])
            i += 1
        if i == len(lines):
            sys.exit(f"{path.relative_to(ROOT)}:{start}: unclosed code block")
        out.append((start, [t for t in re.split(r"[\s,]+", info) if t], body))
        i += 1
    return out


def workspace():
    meta = json.loads(
        subprocess.run(
            ["cargo", "metadata", "--no-deps", "--format-version", "1"],
            cwd=ROOT, check=True, capture_output=True, text=True,
        ).stdout
    )
    pkgs = {}
    for p in meta["packages"]:
        targets = {}
        for t in p["targets"]:
            for k in t["kind"]:
                targets.setdefault(k, set()).add(t["name"])
        pkgs[p["name"]] = targets
    return pkgs


def check_names(where, body, pkgs):
    """Errors for `cargo` words naming what the workspace does not have."""
    errors = []
    text = "\n".join(l for l in body if not l.lstrip().startswith("#")).replace("\\\n", " ")
    for line in text.splitlines():
        try:
            words = shlex.split(line, comments=True)
        except ValueError:
            continue
        for k, w in enumerate(words):
            if w != "cargo":
                continue
            rest = words[k + 1:]
            pkg = None
            for j, x in enumerate(rest):
                if x in ("-p", "--package") and j + 1 < len(rest):
                    pkg = rest[j + 1]
                    if pkg not in pkgs:
                        errors.append(f"{where}: no package `{pkg}` in the workspace")
                        pkg = None
            for j, x in enumerate(rest):
                for flag, kind in (("--example", "example"), ("--test", "test"), ("--bench", "bench")):
                    if x == flag and j + 1 < len(rest):
                        name = rest[j + 1]
                        owners = [pkg] if pkg else list(pkgs)
                        if not any(name in pkgs[o].get(kind, ()) for o in owners):
                            errors.append(f"{where}: no {kind} `{name}` in {pkg or 'the workspace'}")
    return errors


def scratch_dir():
    d = pathlib.Path(tempfile.mkdtemp(prefix="doc-blocks-"))
    for entry in ROOT.iterdir():
        if entry.name != ".git":
            (d / entry.name).symlink_to(entry)
    return d


def run(where, lang, body, cwd, env):
    started = time.monotonic()
    if lang == "python":
        py = os.path.join(env["VENV"], "bin", "python") if env.get("VENV") else "python3"
        cmd = [py, "-c", "\n".join(body)]
    else:
        cmd = ["bash", "-c", PRELUDE + "\n".join(body)]
    try:
        p = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True, timeout=TIMEOUT)
        ok, out = p.returncode == 0, p.stdout + p.stderr
    except subprocess.TimeoutExpired:
        ok, out = False, f"timed out after {TIMEOUT} s"
    secs = time.monotonic() - started
    print(f"  {'ran' if ok else 'FAILED'} {where} ({lang}, {secs:.1f} s)")
    if not ok:
        print("    " + "\n    ".join(out.strip().splitlines()[-25:]))
    return ok


def main():
    args = sys.argv[1:]
    list_only = "--list" in args
    log = args[args.index("--doctest-log") + 1] if "--doctest-log" in args else None
    files = [ROOT / "README.md"] + sorted((ROOT / "geopid" / "guide").glob("*.md"))
    pkgs = workspace()
    env = dict(os.environ)
    if env.get("VENV"):
        env["PATH"] = os.path.join(env["VENV"], "bin") + os.pathsep + env["PATH"]
    if not list_only:
        for var in ("XTASK", "GEOPID", "EXAMPLES"):
            if not env.get(var):
                sys.exit(f"doc-blocks: set {var} (CI's debug binaries)")
    n_rust = n_data = n_ran = 0
    skipped, untagged, failed, errors = [], [], [], []
    for f in files:
        rel = f.relative_to(ROOT).as_posix()
        cwd = None
        for line, info, body in blocks(f):
            where = f"{rel}:{line}"
            lang = info[0] if info else "rust"
            if lang == "rust" or lang in RUST_ATTRS:
                n_rust += 1
                if any(t in ("ignore", "no_run") for t in info):
                    errors.append(f"{where}: a Rust block marked {info}: every Rust block runs")
                continue
            if lang in SHELL or lang == "python":
                if lang in SHELL:
                    errors += check_names(where, body, pkgs)
                tags = set(info[1:])
                if "ci" in tags:
                    if list_only:
                        print(f"  would run {where}")
                        n_ran += 1
                        continue
                    cwd = cwd or scratch_dir()
                    if run(where, lang, body, cwd, env):
                        n_ran += 1
                    else:
                        failed.append(where)
                elif "no-ci" in tags:
                    if not body or not REASON.match(body[0]):
                        errors.append(f"{where}: a no-ci block's first line must be `# not run by CI: <reason>`")
                    else:
                        skipped.append((where, body[0][len("# not run by CI: "):]))
                else:
                    untagged.append(where)
                continue
            n_data += 1
    for where, why in skipped:
        print(f"  skipped {where}: {why}")
    for where in untagged:
        print(f"  UNTAGGED {where}: tag it `ci` or `no-ci` (with `# not run by CI: <reason>`)")
    for e in errors:
        print(f"  ERROR {e}")
    doctests = None
    if log:
        text = pathlib.Path(log).read_text(errors="replace")
        m = re.search(r"Doc-tests geopid\n(?:.*\n)*?test result: ok\. (\d+) passed", text)
        doctests = int(m.group(1)) if m else 0
        if doctests < n_rust:
            errors.append(f"{log}: {doctests} doctests of geopid passed, fewer than the {n_rust} Rust blocks")
    print(
        f"doc blocks: {len(files)} files; {n_rust} Rust blocks"
        + (f" ({doctests} geopid doctests passed)" if doctests is not None else " (run as doctests)")
        + f"; {n_ran + len(failed) + len(skipped) + len(untagged)} shell/Python blocks: {n_ran} run, "
        f"{len(skipped)} skipped with reasons, {len(untagged)} untagged, {len(failed)} failed; "
        f"{n_data} data blocks; {len(errors)} errors"
    )
    sys.exit(1 if failed or untagged or errors else 0)


if __name__ == "__main__":
    main()
