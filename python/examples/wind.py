"""RotorPy's crazyflie in wind from Python: the built-in `figure-eight-wind`
(a 3 m/s mean wind with Dryden gusts, rotor drag, 72 ms motors), with and
without the integral terms, and the same gusts seed by seed.

    pip install ./python            # the package, from the repository root
    pip install matplotlib          # only for the figure
    python python/examples/wind.py            # writes wind.png
    python python/examples/wind.py --no-plot  # prints the figures only
"""

import argparse

import numpy as np

import geopid


def rms_after(r, t0=2.0):
    """RMS of ‖e_x‖ after the start-up transient."""
    e = r.ex[r.t >= t0]
    return float(np.sqrt(np.mean(e * e)))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--no-plot", action="store_true", help="print, do not draw")
    ap.add_argument("--out", default="wind.png", help="figure file")
    args = ap.parse_args()

    on = geopid.run("figure-eight-wind")
    off = geopid.run("figure-eight-wind", no_integral=True)
    print(f"RMS |e_x| after 2 s: {rms_after(on):.4f} m with integral terms, "
          f"{rms_after(off):.4f} m without")
    print(f"peak rotor speed {on.vehicle_states.max():.0f} rad/s; "
          f"wind speed up to {np.linalg.norm(on.wind, axis=1).max():.2f} m/s")
    # The mean drag is what the integral terms learn.
    assert rms_after(on) < 0.7 * rms_after(off)

    # The gusts are a function of the seed alone: another seed, another
    # flight; the same seed, the same one to the last bit.
    scene = geopid.load_scene("figure-eight-wind").to_toml()
    other = geopid.run(scene.replace("seed = 1", "seed = 2"))
    again = geopid.run(scene)
    assert np.array_equal(again.x, on.x) and not np.array_equal(other.x, on.x)
    print(f"seed 2: RMS |e_x| {rms_after(other):.4f} m (the same seed repeats bit for bit)")

    if args.no_plot:
        return
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise SystemExit("matplotlib is not installed: pip install matplotlib (or use --no-plot)")
    fig, ax = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    for r, style, label in ((on, "-", "with integral terms"), (off, "--", "without")):
        ax[0].plot(r.t, r.ex, style, label=label)
    for k, name in enumerate(("north", "east", "down")):
        ax[1].plot(on.t, on.wind[:, k], label=name)
    for k in range(on.vehicle_states.shape[1]):
        ax[2].plot(on.t, on.vehicle_states[:, k], label=f"rotor {k + 1}")
    ax[0].set_ylabel("|x - x_d| (m)")
    ax[1].set_ylabel("wind (m/s)")
    ax[2].set_ylabel("rotor speed (rad/s)")
    for a in ax:
        a.legend(fontsize=8)
    ax[-1].set_xlabel("t (s)")
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
