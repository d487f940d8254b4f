"""The command line of the Python package, for a machine without the
repository or a Rust toolchain::

    python -m geopid run paper-flip --csv paper-flip.csv --mcap paper-flip.mcap
    python -m geopid scenes

``run`` takes the options of ``cargo xtask run`` that change what is
simulated or written (options left out keep the scene's values) and writes
the same CSV and MCAP bytes; it prints one summary line. Exit status: 0
when the run completed, 1 when it stopped on a failed step or a
divergence, 2 for a bad scene or option, 130 on Ctrl-C, 141 when a reader
closed the output pipe.
"""

import argparse
import math
import os
import sys
from typing import List, Optional

import geopid


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="python -m geopid", description=__doc__.split("\n\n")[0])
    sub = p.add_subparsers(dest="command", required=True)
    sub.add_parser("scenes", help="list the built-in scenes")
    r = sub.add_parser("run", help="run a scene (a built-in name or a TOML file)")
    r.add_argument("scene", help="a built-in scene's name or a scene file")
    r.add_argument("--integrator", help="lgvi, rk4, rk4-projected, rkmk4, euler or dopri")
    r.add_argument("--dt", type=float, help="step (s); dopri's first step")
    r.add_argument("--tol", type=float, help="dopri's tolerance")
    r.add_argument("--scalar", help="f32 or f64")
    r.add_argument("--backend", help="glam or nalgebra")
    r.add_argument("--duration", type=float, help="s")
    r.add_argument("--sample", type=float, help="recording period, s")
    r.add_argument("--control-rate", type=float, help="sampled control at this rate, Hz")
    r.add_argument("--loop-rates", metavar="PRESET", help="crazyflie: estimator 1 kHz, attitude 500 Hz, position 100 Hz")
    r.add_argument("--no-integral", action="store_true", help="the integral terms off")
    r.add_argument("--sensors", metavar="PRESET", help="rotorpy, crazyflie, mpu9250 or fdcl-gazebo")
    r.add_argument("--estimator", choices=["none", "mocap"], help="what the modes read")
    r.add_argument("--seed", type=int, help="seed of the sensor noise")
    r.add_argument("--csv", help="write the samples as CSV")
    r.add_argument("--mcap", help="write an MCAP log (Foxglove schemas)")
    return p


def _summary(res: "geopid.Result") -> str:
    omega = math.sqrt(sum(float(c) ** 2 for c in res.omega[-1]))
    return (
        f"{res.termination['kind']} at t = {float(res.t[-1]):.6g} s: "
        f"Ψ = {float(res.psi[-1]):.3e}, ‖e_x‖ = {float(res.ex[-1]):.3e} m, "
        f"|Ω| = {omega:.3e} rad/s; {res.steps} steps, largest thrust {res.max_thrust:.4g} N"
    )


def _main(argv: Optional[List[str]]) -> int:
    args = _parser().parse_args(argv)
    if args.command == "scenes":
        print("\n".join(geopid.scene_names()))
        return 0
    try:
        res = geopid.run(
            args.scene,
            integrator=args.integrator,
            dt=args.dt,
            tol=args.tol,
            scalar=args.scalar,
            backend=args.backend,
            duration=args.duration,
            sample=args.sample,
            control_rate=args.control_rate,
            loop_rates=args.loop_rates,
            no_integral=args.no_integral,
            sensors=args.sensors,
            estimator=args.estimator,
            seed=args.seed,
            csv=args.csv,
            mcap=args.mcap,
        )
    except KeyboardInterrupt:
        print("interrupted", file=sys.stderr)
        return 130
    except (geopid.SceneError, OSError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 2
    except (geopid.SimulationError, geopid.DivergedError) as e:
        print(f"error: {e}", file=sys.stderr)
        return 1
    for w in list(res.warnings) + list(res.health):
        print(f"warning: {w}", file=sys.stderr)
    print(_summary(res))
    return 0


def main(argv: Optional[List[str]] = None) -> int:
    """The command line; returns the exit status."""
    try:
        return _main(argv)
    except BrokenPipeError:
        # A reader such as `head` closed the pipe: stop quietly with the
        # status of a process ended by SIGPIPE, as `cargo xtask` does.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 141


if __name__ == "__main__":
    sys.exit(main())
