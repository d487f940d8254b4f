#!/usr/bin/env python3
"""Each workspace member's share of the Rust source lines under the members' `src/`.

A crate that holds most of the workspace holds several jobs; the aim is no
library crate above 25 %. Prints one row a crate, largest first. With
`--max PCT` it exits 1 when a library crate (not xtask, testkit or a
binding) is above PCT.

Usage: scripts/crate-size.py [--max PCT]
"""
import json
import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
NOT_LIBRARIES = {"xtask", "testkit", "geopid-python"}


def members():
    meta = json.loads(
        subprocess.run(
            ["cargo", "metadata", "--no-deps", "--format-version", "1"],
            cwd=ROOT, check=True, capture_output=True, text=True,
        ).stdout
    )
    return [(p["name"], pathlib.Path(p["manifest_path"]).parent) for p in meta["packages"]]


def main():
    args = sys.argv[1:]
    limit = float(args[args.index("--max") + 1]) if "--max" in args else None
    rows = []
    for name, d in members():
        n = sum(len(f.read_text().splitlines()) for f in (d / "src").rglob("*.rs"))
        rows.append((n, name))
    total = sum(n for n, _ in rows)
    rows.sort(reverse=True)
    print(f"Rust lines under src/ of {len(rows)} members: {total}")
    over = []
    for n, name in rows:
        share = 100.0 * n / total
        print(f"  {name:24} {n:6} {share:5.1f} %")
        if limit is not None and share > limit and name not in NOT_LIBRARIES:
            over.append(f"{name} ({share:.1f} %)")
    if over:
        sys.exit(f"above {limit} % of the workspace: {', '.join(over)}")


if __name__ == "__main__":
    main()
