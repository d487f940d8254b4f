"""The paper's numerical example from Python: a flip in attitude mode, then
position recovery under the disturbances Δ_x, Δ_R, with and without the
integral terms (the paper's figure of Ψ and x).

    pip install ./python            # the package, from the repository root
    pip install matplotlib          # only for the figure
    python python/examples/paper_flip.py            # writes paper_flip.png
    python python/examples/paper_flip.py --no-plot  # prints the figures only
"""

import argparse
import time

import numpy as np

import geopid


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--no-plot", action="store_true", help="print, do not draw")
    ap.add_argument("--out", default="paper_flip.png", help="figure file")
    args = ap.parse_args()

    t0 = time.perf_counter()
    with_i = geopid.run("paper-flip", duration=10.0)
    without = geopid.run("paper-flip", duration=10.0, no_integral=True)
    wall = time.perf_counter() - t0

    # With the integral terms the vehicle returns to x_d = 0 although
    # Δ_x ≠ 0; without them it settles where k_x e_x balances Δ_x.
    for name, r in (("with integral terms", with_i), ("without", without)):
        print(f"{name:>20}: final Psi {r.psi[-1]:.2e}, final |e_x| {r.ex[-1]:.4f} m, "
              f"max thrust {r.max_thrust:.2f} N, {r.steps} steps")
    print(f"two 10 s runs in {wall * 1e3:.0f} ms of wall time")
    assert with_i.ex[-1] < without.ex[-1] / 10

    if args.no_plot:
        return
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        raise SystemExit("matplotlib is not installed: pip install matplotlib (or use --no-plot)")
    fig, ax = plt.subplots(4, 1, figsize=(7, 9), sharex=True)
    for r, style, label in ((with_i, "-", "with integral terms"), (without, "--", "without")):
        ax[0].semilogy(r.t, np.maximum(r.psi, 1e-16), style, label=label)
        for k in range(3):
            ax[k + 1].plot(r.t, r.x[:, k], style, label=label)
    ax[0].set_ylabel("Ψ")
    for k in range(3):
        ax[k + 1].set_ylabel(f"x{k + 1} (m)")
    ax[0].legend()
    ax[-1].set_xlabel("t (s)")
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
