#!/usr/bin/env python3
"""Compare two Monte Carlo runs (`samples.csv` of the same setup and seed):
the share of samples in the same class, the converged fractions, the times
to converge of the samples both converge, and the samples that change class.
Exits 1 when fewer than --min-same percent share a class or the converged
fractions differ by more than --max-converged-pp percentage points."""
import argparse
import csv
import math
import sys


def rows(path):
    with open(path, newline="") as f:
        return {int(r["index"]): r for r in csv.DictReader(f)}


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("a", help="first samples.csv (the reference)")
    p.add_argument("b", help="second samples.csv")
    p.add_argument("--min-same", type=float, default=99.5)
    p.add_argument("--max-converged-pp", type=float, default=0.2)
    args = p.parse_args()
    a, b = rows(args.a), rows(args.b)
    if a.keys() != b.keys():
        sys.exit(f"different sample indices: {len(a)} vs {len(b)} rows")
    n = len(a)
    changed = [i for i in sorted(a) if a[i]["status"] != b[i]["status"]]
    same = 100.0 * (n - len(changed)) / n
    conv = [100.0 * sum(r[i]["converged"] == "1" for i in r) / n for r in (a, b)]
    dt = sorted(
        abs(float(a[i]["t_converge"]) - float(b[i]["t_converge"]))
        for i in a
        if a[i]["converged"] == "1" and b[i]["converged"] == "1"
    )
    print(f"{n} samples: {n - len(changed)} in the same class ({same:.2f} %)")
    print(f"converged: {conv[0]:.2f} % vs {conv[1]:.2f} % ({conv[1] - conv[0]:+.2f} pp)")
    if dt:
        q = lambda p: dt[min(len(dt) - 1, math.ceil(p * len(dt)) - 1)]
        print(f"time to converge, |difference|: median {q(0.5):.3g} s, 99th {q(0.99):.3g} s, worst {dt[-1]:.3g} s")
    for i in changed:
        r = a[i]
        print(
            f"  #{i}: {r['status']} -> {b[i]['status']} "
            f"(from {math.degrees(float(r['angle'])):.1f} deg, |Omega0| {float(r['omega0']):.2f}, ex0 {float(r['ex0']):.2f})"
        )
    ok = same >= args.min_same and abs(conv[1] - conv[0]) <= args.max_converged_pp
    print("agreement: " + ("within" if ok else "OUTSIDE") + f" {args.min_same} % same class and {args.max_converged_pp} pp converged")
    sys.exit(0 if ok else 1)


if __name__ == "__main__":
    main()
