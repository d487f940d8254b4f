#!/usr/bin/env python3
"""sha256 of the CSV of every built-in scene × stepper × backend pair.

A refactoring that must not change a trajectory runs this with the binary
built before and after and compares the two listings (`diff`): one line per
run, `scene integrator backend scalar sha256`, or the first line of the
error for a pair that refuses the scene (the refusal must not change
either). Runs two at a time.

Usage: scripts/run-hashes.py GEOPID_BINARY > hashes.txt
"""
import concurrent.futures
import hashlib
import os
import subprocess
import sys
import tempfile

STEPPERS = ["lgvi", "rk4", "rk4-projected", "rkmk4", "euler", "dopri"]
PAIRS = [("nalgebra", "f64"), ("nalgebra", "f32"), ("glam", "f64")]


def one(binary, tmp, scene, integrator, backend, scalar):
    csv = os.path.join(tmp, f"{scene}-{integrator}-{backend}-{scalar}.csv")
    p = subprocess.run(
        [binary, "run", scene, "--integrator", integrator, "--backend", backend,
         "--scalar", scalar, "--csv", csv],
        capture_output=True, text=True,
    )
    if p.returncode != 0:
        first = (p.stderr.strip().splitlines() or ["(no message)"])[0]
        return f"{scene} {integrator} {backend} {scalar} exit {p.returncode}: {first}"
    with open(csv, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    os.remove(csv)
    return f"{scene} {integrator} {backend} {scalar} {digest}"


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__.strip().splitlines()[-1])
    binary = sys.argv[1]
    scenes = subprocess.run([binary, "scenes"], check=True, capture_output=True, text=True).stdout.split()
    jobs = [(s, i, b, k) for s in scenes for i in STEPPERS for b, k in PAIRS]
    with tempfile.TemporaryDirectory() as tmp, concurrent.futures.ThreadPoolExecutor(2) as pool:
        for line in pool.map(lambda j: one(binary, tmp, *j), jobs):
            print(line, flush=True)


if __name__ == "__main__":
    main()
