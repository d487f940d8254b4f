#!/usr/bin/env python3
"""Counts the methods of the extension traits a user implements.

For each trait below: its required methods (no body), its provided ones
and the load methods (named `loads` or `*_loads*`); exits 1 when a limit is
broken. Sealed methods (taking a token type no other crate can name) are
not counted: no user implements them. A trait a user must read whole to implement should stay small.

Usage: scripts/trait-methods.py
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
# (file, trait, at most this many required, at most this many in all, at
# most this many load methods).
TRAITS = [
    ("dynamics/src/vehicle.rs", "Vehicle", 8, 9, 1),
    ("dynamics/src/vehicle.rs", "Actuators", 1, 3, 0),
    ("controllers/src/mode.rs", "Mode", 2, 6, None),
]


def methods(path, trait):
    text = (ROOT / path).read_text()
    m = re.search(r"^pub trait " + trait + r"\b[^{]*\{", text, re.M)
    if not m:
        sys.exit(f"{path}: no `pub trait {trait}`")
    depth, i, body = 1, m.end(), []
    while depth:
        c = text[i]
        depth += c == "{"
        depth -= c == "}"
        body.append(c if depth == 1 or (depth == 2 and c == "{") else " ")
        i += 1
    body = "".join(body)
    out = []
    for f in re.finditer(r"\bfn\s+(\w+)", body):
        # The signature ends at the first `;` or `{` outside brackets
        # (`[f64; 3]` holds a `;`).
        depth, j = 0, f.end()
        while depth or body[j] not in ";{":
            depth += body[j] in "([<"
            depth -= body[j] in ")]>" and not body[j - 1] == "-"
            j += 1
        # A method whose signature takes a sealed token cannot be
        # overridden outside its crate: not part of what a user implements.
        if "sealed::Token" in body[f.end():j]:
            continue
        out.append((f.group(1), body[j] == ";"))
    return out


def main():
    bad = []
    for path, trait, max_req, max_all, max_loads in TRAITS:
        ms = methods(path, trait)
        req = [n for n, r in ms if r]
        loads = [n for n, _ in ms if n == "loads" or "_loads" in n or n.endswith("loads")]
        print(f"{trait}: {len(ms)} methods, {len(req)} required ({', '.join(req)}), "
              f"{len(loads)} load methods {loads}")
        if len(req) > max_req or len(ms) > max_all or (max_loads is not None and len(loads) > max_loads):
            bad.append(f"{trait}: {len(req)} required / {len(ms)} in all / {len(loads)} load "
                       f"(at most {max_req} / {max_all} / {max_loads})")
    if bad:
        sys.exit("\n".join(bad))


if __name__ == "__main__":
    main()
