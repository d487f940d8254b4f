"""RotorPy's minimum-snap trajectories, the reference for `missions/tests/rotorpy_minsnap.rs`.

RotorPy 3.0.0's `MinSnap` (its QP solved by cvxopt) through five waypoint
sets, with and without yaw. The sets keep every waypoint more than 0.1 m
from the one before (RotorPy drops closer ones) and every segment's
midpoint speed under RotorPy's bounds (v_max 3 m/s, yaw rate 2 pi rad/s),
so only its equality constraints are active; each set's largest midpoint
speed is written so that the test can say so.

Output, per set: a line `set NAME v_avg N` and the N waypoints as lines
`w x y z yaw`; a line `times` with RotorPy's segment durations; then 400
lines, at times evenly spread over the trajectory, of `t`, x, x', x'', x''',
x'''' (3 each), yaw, yaw', yaw''; a line `midspeed S`. Usage:

    python3 rotorpy_minsnap.py OUT.txt
"""

import sys

import numpy as np
from rotorpy.trajectories.minsnap import MinSnap

PI = np.pi
SETS = [
    ("square-climb", 1.0,
     [[0, 0, 0], [1, 0, 0.5], [1, 1, 1], [0, 1, 1.5], [0, 0, 2]], None),
    ("square-climb-yaw", 1.0,
     [[0, 0, 0], [1, 0, 0.5], [1, 1, 1], [0, 1, 1.5], [0, 0, 2]],
     [0, PI / 2, PI, 3 * PI / 2, 2 * PI]),
    ("zigzag-yaw", 2.0,
     [[0, 0, 1], [1.5, 0.4, 1.2], [2.0, -1.0, 0.8], [3.7, -0.6, 1.5],
      [4.1, 0.9, 1.1], [5.5, 1.2, 1.0], [6.0, 0.0, 1.3]],
     [0.0, 0.3, -0.4, 0.8, 0.2, -0.6, 0.1]),
    ("one-segment-yaw", 0.5, [[0, 0, 1], [1, 2, 2]], [0.0, 1.0]),
    ("uneven", 0.5,
     [[0, 0, 0], [0.3, 0, 0], [3.3, 0, 0.2], [3.5, 1, 0.2], [3.7, 1.2, 0.4]], None),
]


def main(path):
    lines = []
    for name, v_avg, points, yaw in SETS:
        pts = np.array(points, dtype=float)
        yaws = None if yaw is None else np.array(yaw, dtype=float)
        traj = MinSnap(pts, yaw_angles=yaws, v_avg=v_avg, verbose=False)
        lines.append(f"set {name} {v_avg!r} {len(pts)}")
        y = np.zeros(len(pts)) if yaws is None else yaws
        for p, a in zip(pts, y):
            lines.append("w " + " ".join(repr(float(c)) for c in [*p, a]))
        lines.append("times " + " ".join(repr(float(t)) for t in traj.delta_t))
        end = float(traj.t_keyframes[-1])
        for t in np.linspace(0.0, end, 400):
            f = traj.update(t)
            row = [t]
            for k in ["x", "x_dot", "x_ddot", "x_dddot", "x_ddddot"]:
                row.extend(float(c) for c in f[k])
            row.extend(float(f[k]) for k in ["yaw", "yaw_dot", "yaw_ddot"])
            lines.append(" ".join(repr(float(c)) for c in row))
        mid = 0.0
        for i, dt in enumerate(traj.delta_t):
            v = traj.update(traj.t_keyframes[i] + dt / 2)["x_dot"]
            mid = max(mid, float(np.max(v)))
        lines.append(f"midspeed {mid!r}")
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(sys.argv[1])
