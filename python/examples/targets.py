"""The package's three speed figures, measured in one run against their
baselines (the machine is shared: compare within a run, not across runs).

    pip install ./python
    cargo build --release -p xtask           # the CLI baseline
    python python/examples/targets.py

1. The paper's flip through `geopid.run` against the CLI's own loop time
   (`xtask run` prints steps and steps per second; interpreter start-up
   excluded on both sides).
2. A Python reference callable: the cost per evaluation over the native
   run of the same scene.
3. `position_control` over 10^5 states, ns per state (compare with the
   Rust bench's position update in `cargo xtask bench --quick`).
"""

import os
import re
import statistics
import subprocess
import time

import numpy as np

import geopid

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def median_time(f, n=15):
    ts = []
    for _ in range(n):
        t = time.perf_counter()
        f()
        ts.append(time.perf_counter() - t)
    return statistics.median(ts)


def cli_loop(args):
    exe = os.path.join(ROOT, "target", "release", "xtask")
    if not os.path.exists(exe):
        return None
    walls = []
    for _ in range(5):
        out = subprocess.run([exe, "run", *args], capture_output=True, text=True, cwd=ROOT)
        m = re.search(r"(\d+) steps, .* ([\d.]+) steps/s", out.stdout + out.stderr)
        if m:
            walls.append(int(m.group(1)) / float(m.group(2)))
    return statistics.median(walls) if walls else None


def main():
    cli = cli_loop(["paper-flip"])
    cli_csv = cli_loop(["paper-flip", "--csv", os.devnull])
    few = median_time(lambda: geopid.run("paper-flip", sample=1.0))
    full = median_time(lambda: geopid.run("paper-flip"))
    print("1. paper flip")
    if cli:
        print(f"   xtask run (nothing recorded), loop   {cli * 1e3:6.2f} ms")
        print(f"   geopid.run(sample=1.0)               {few * 1e3:6.2f} ms  ({few / cli:.2f}x)")
    if cli_csv:
        print(f"   xtask run --csv /dev/null, loop      {cli_csv * 1e3:6.2f} ms")
        print(f"   geopid.run (2001 samples as arrays)  {full * 1e3:6.2f} ms  ({full / cli_csv:.2f}x)")
    if not cli:
        print("   (no target/release/xtask: cargo build --release -p xtask for the baseline)")

    calls = [0]

    def counted(t):
        calls[0] += 1
        return ((0.0, 0.0, 0.0),)

    geopid.run("hover-disturbed", duration=10.0, reference=counted)
    native = median_time(lambda: geopid.run("hover-disturbed", duration=10.0), 9)
    python = median_time(lambda: geopid.run("hover-disturbed", duration=10.0,
                                            reference=lambda t: ((0.0, 0.0, 0.0),)), 9)
    print("2. Python reference callable (hover-disturbed, 10 s)")
    print(f"   {calls[0]} evaluations: {(python - native) / calls[0] * 1e9:.0f} ns each over the native run")

    rng = np.random.default_rng(1)
    n = 100_000
    st = {"x": rng.normal(size=(n, 3)), "v": rng.normal(size=(n, 3)),
          "R": np.tile(np.eye(3), (n, 1, 1)), "omega": rng.normal(size=(n, 3))}
    every = median_time(lambda: geopid.position_control(st))
    wrench = median_time(lambda: geopid.position_control(st, outputs=["thrust", "moment"]))
    print("3. position_control over 10^5 states")
    print(f"   every output {every / n * 1e9:.0f} ns/state, thrust and moment only {wrench / n * 1e9:.0f} ns/state")


if __name__ == "__main__":
    main()
