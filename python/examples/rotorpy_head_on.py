"""Head-on with RotorPy: the same crazyflie, hover and circle, flown by
RotorPy (its SE3Control, and this package's law through the
geopid.rotorpy adapter) and by this package (from Python and from
`cargo xtask run`); wall time per simulated second and the difference of
the trajectories where the models agree.

    pip install ./python rotorpy      # RotorPy is not a dependency of geopid
    python python/examples/rotorpy_head_on.py [--duration 10] [--json out.json]

Model differences, and how they are handled:
- Frames: RotorPy is z-up with thrust along +b3; this package e3-down with
  thrust along -b3. Everything is compared in RotorPy's frame (T = diag(1,-1,-1)).
- Motors: RotorPy integrates rotor speeds with a first-order lag (the
  crazyflie's tau_m = 72 ms) and clips them; the paper's `quadrotor` kind
  flown here applies the commanded wrench at once. The comparison of
  trajectories sets tau_m = 1 ms in RotorPy, where the two models agree
  to the lag. (The `multirotor` kind has RotorPy's lag and aerodynamics
  and matches it to 1e-10 m; see the README's "Wind, drag and motors".)
- Control timing: RotorPy holds each command for one step of its 100 Hz
  loop; the scene here samples its control at 100 Hz too (zero-order hold).
- Aerodynamics off in RotorPy (aero=False): the `quadrotor` kind has no
  drag model.
- Controllers: SE3Control is Lee's geometric law without the feedforward
  of Ω_c, Ω̇_c (it takes Ω_d = (0, 0, yaw_dot)) and without integral
  terms; the paper's law computes Ω_c, Ω̇_c from jerk and snap exactly.
  Its gains here have the same closed-loop rates as SE3Control's.
"""

import argparse
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

import geopid

try:
    from rotorpy.controllers.quadrotor_control import SE3Control
    from rotorpy.environments import Environment
    from rotorpy.trajectories.circular_traj import ThreeDCircularTraj
    from rotorpy.trajectories.hover_traj import HoverTraj
    from rotorpy.vehicles.crazyflie_params import quad_params
    from rotorpy.vehicles.multirotor import Multirotor
except ImportError:
    sys.exit("RotorPy is not installed: pip install rotorpy")

from geopid.rotorpy import GeometricPID, matched_gains

T = np.diag([1.0, -1.0, -1.0])
RATE = 100.0  # RotorPy's loop, Hz
FREQ = 0.2  # the circle's revolutions per second


def scene(kind, duration):
    """The crazyflie in this package's scene schema (e3 down)."""
    p = quad_params
    position = ({"kind": "hold", "x": [0.0, 0.0, 0.0], "b1d": [1.0, 0.0, 0.0]} if kind == "hover" else
                # RotorPy's counter-clockwise circle seen with e3 down turns the other way.
                {"kind": "circle", "center": [0.0, 0.0, 0.0], "radius": 1.0, "omega": -2 * math.pi * FREQ})
    return {
        "name": f"crazyflie-{kind}",
        "duration": duration,
        "vehicle": {"kind": "quadrotor", "mass": p["mass"], "inertia": [p["Ixx"], p["Iyy"], p["Izz"]],
                    "arm": float(np.linalg.norm(p["rotor_pos"]["r1"])), "c_tau_f": p["k_m"] / p["k_eta"],
                    # RotorPy's crazyflie has J3 > J1 + J2, like the paper's quadrotor.
                    "allow_nonphysical_inertia": True},
        "gains": matched_gains(p),
        "plan": [{"mode": "position", "position": position}],
        "integrator": {"kind": "rk4", "dt": 1e-3},
        "control": {"timing": "sampled", "rate": RATE},
        "record": {"sample": 1.0 / RATE},
    }


def rotorpy_run(kind, controller, duration, tau_m=None, first_step=None):
    params = dict(quad_params)
    if tau_m is not None:
        params["tau_m"] = tau_m
    x0 = {"x": np.zeros(3), "v": np.zeros(3), "q": np.array([0, 0, 0, 1.0]), "w": np.zeros(3),
          "wind": np.zeros(3), "rotor_speeds": np.full(4, math.sqrt(params["mass"] * 9.81 / 4 / params["k_eta"]))}
    kwargs = {"method": "RK45"} if first_step is None else {"method": "RK45", "first_step": first_step}
    traj = HoverTraj() if kind == "hover" else ThreeDCircularTraj(radius=np.array([1.0, 1.0, 0.0]),
                                                                    freq=np.array([FREQ, FREQ, FREQ]))
    env = Environment(vehicle=Multirotor(params, initial_state=x0, aero=False, integrator_kwargs=kwargs),
                      controller=controller(params), trajectory=traj, sim_rate=RATE, safety_margin=0.25)
    t = time.perf_counter()
    res = env.run(t_final=duration, use_mocap=False, terminate=False, plot=False, animate_bool=False,
                  verbose=False)
    return time.perf_counter() - t, res


def cli_loop_wall(sc):
    """`cargo xtask run` of the scene: its loop's wall time (steps over the
    steps per second it prints), or None without cargo."""
    if shutil.which("cargo") is None:
        return None
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    with tempfile.NamedTemporaryFile("w", suffix=".toml", delete=False) as f:
        f.write(geopid.load_scene(sc).to_toml())
    try:
        done = subprocess.run(["cargo", "xtask", "run", f.name], cwd=root, capture_output=True, text=True)
    finally:
        os.unlink(f.name)
    m = re.search(r"(\d+) steps, .* ([\d.]+) steps/s", done.stdout + done.stderr)
    return int(m.group(1)) / float(m.group(2)) if m else None


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--duration", type=float, default=10.0)
    ap.add_argument("--json", help="write the figures here")
    args = ap.parse_args()
    dur = args.duration
    rows, figures = [], {}
    for kind in ("hover", "circle"):
        w_se3, se3 = rotorpy_run(kind, SE3Control, dur)
        w_se3_fs, _ = rotorpy_run(kind, SE3Control, dur, first_step=1.0 / RATE)
        w_ad, ad = rotorpy_run(kind, GeometricPID, dur)
        w_fast, fast = rotorpy_run(kind, GeometricPID, dur, tau_m=1e-3)
        sc = scene(kind, dur)
        t = time.perf_counter()
        ours = geopid.run(sc)
        w_py = time.perf_counter() - t
        w_cli = cli_loop_wall(sc)
        # Where the models agree (lag 1 ms, same law, same hold): positions
        # in RotorPy's frame at RotorPy's sample times.
        n = min(len(fast["time"]), len(ours.t))
        assert np.allclose(fast["time"][:n], ours.t[:n], atol=1e-9)
        diff = np.linalg.norm(fast["state"]["x"][:n] - ours.x[:n] @ T, axis=1).max()
        lag = np.linalg.norm(ad["state"]["x"][:n] - ours.x[:n] @ T, axis=1).max()
        err = {name: np.linalg.norm(r["state"]["x"] - r["flat"]["x"], axis=1)[r["time"] > dur / 2].max()
               for name, r in (("se3", se3), ("adapter", ad))}
        figures[kind] = {
            "rotorpy_se3_s_per_s": w_se3 / dur, "rotorpy_se3_first_step_s_per_s": w_se3_fs / dur,
            "rotorpy_adapter_s_per_s": w_ad / dur, "geopid_run_s_per_s": w_py / dur,
            "cli_loop_s_per_s": None if w_cli is None else w_cli / dur,
            "max_diff_tau1ms_m": diff, "max_diff_tau72ms_m": lag,
            "late_max_ex_se3_m": err["se3"], "late_max_ex_adapter_m": err["adapter"],
            "late_max_ex_geopid_m": float(ours.ex[ours.t > dur / 2].max()),
        }
        rows.append((kind, figures[kind]))
    print(f"wall time per simulated second ({dur:g} s runs, crazyflie, aero off):")
    print(f"{'':>7} {'RotorPy SE3':>12} {'first_step':>11} {'RotorPy+ours':>13} {'geopid.run':>11} {'xtask run':>10}")
    for kind, f in rows:
        cli = "n/a" if f["cli_loop_s_per_s"] is None else f"{f['cli_loop_s_per_s'] * 1e3:.2f} ms"
        print(f"{kind:>7} {f['rotorpy_se3_s_per_s'] * 1e3:>9.1f} ms {f['rotorpy_se3_first_step_s_per_s'] * 1e3:>8.1f} ms "
              f"{f['rotorpy_adapter_s_per_s'] * 1e3:>10.1f} ms {f['geopid_run_s_per_s'] * 1e3:>8.2f} ms {cli:>10}")
    print("tracking (max ‖x − x_d‖ over the second half) and trajectory difference, same law:")
    for kind, f in rows:
        print(f"{kind:>7}: SE3Control {f['late_max_ex_se3_m']:.2e} m, geometric PID in RotorPy "
              f"{f['late_max_ex_adapter_m']:.2e} m, in geopid {f['late_max_ex_geopid_m']:.2e} m; "
              f"RotorPy (tau_m 1 ms) vs geopid {f['max_diff_tau1ms_m']:.2e} m, (tau_m 72 ms) {f['max_diff_tau72ms_m']:.2e} m")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as fh:
            json.dump(figures, fh, indent=1)


if __name__ == "__main__":
    main()
