#!/usr/bin/env python3
"""Per-file table of a cargo-mutants run, for docs/mutants.md.

Usage: scripts/mutants-table.py RUN.json [RUN.json ...] [--rerun RERUN.json ...] [--list]

Reads cargo-mutants' `outcomes.json` files (runs of disjoint parts of one
sample are joined; a mutant in several keeps its last outcome) and
prints, per source file, the mutants tested, caught, missed, unviable and
timed out, with the caught fraction of the viable ones (caught + missed +
timeout). A later run of some of the same mutants (`--rerun`, e.g. the
viable ones re-tested after new tests) overrides only their outcome, so
the table shows "after". Timeouts count as not caught. `--list` prints
the mutants not caught instead of the table.
"""
import json
import sys
from collections import defaultdict

KINDS = {
    "CaughtMutant": "caught",
    "MissedMutant": "missed",
    "Unviable": "unviable",
    "Timeout": "timeout",
}


def outcomes(path):
    data = json.load(open(path))
    out = {}
    for o in data["outcomes"]:
        sc = o["scenario"]
        if not isinstance(sc, dict) or "Mutant" not in sc:
            continue  # the baseline
        out[sc["Mutant"]["name"]] = (sc["Mutant"]["file"], KINDS[o["summary"]])
    return out


def main(argv):
    if not argv:
        sys.exit(__doc__)
    show_list = "--list" in argv
    argv = [a for a in argv if a != "--list"]
    result = {}
    while argv and argv[0] != "--rerun":
        result.update(outcomes(argv[0]))
        argv = argv[1:]
    while argv:
        if argv[0] != "--rerun" or len(argv) < 2:
            sys.exit(__doc__)
        for name, (f, kind) in outcomes(argv[1]).items():
            if name in result:
                result[name] = (f, kind)
        argv = argv[2:]
    if show_list:
        for name, (_, kind) in sorted(result.items()):
            if kind in ("missed", "timeout"):
                print(f"{kind:8} {name}")
        return
    table = defaultdict(lambda: defaultdict(int))
    for f, kind in result.values():
        table[f][kind] += 1
    print("| file | tested | caught | missed | unviable | timeout | caught ÷ viable |")
    print("|---|---:|---:|---:|---:|---:|---:|")
    total = defaultdict(int)
    for f in sorted(table):
        row = table[f]
        for k, n in row.items():
            total[k] += n
        print(line(f, row))
    print(line("**all**", total))


def line(name, row):
    viable = row["caught"] + row["missed"] + row["timeout"]
    n = viable + row["unviable"]
    frac = f"{100.0 * row['caught'] / viable:.1f} %" if viable else "–"
    return (f"| {name} | {n} | {row['caught']} | {row['missed']} | "
            f"{row['unviable']} | {row['timeout']} | {frac} |")


if __name__ == "__main__":
    main(sys.argv[1:])
