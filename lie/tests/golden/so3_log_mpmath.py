"""Golden values for `lie/tests/so3_log_golden.rs`: the SO(3) logarithm of
rotation matrices rounded to f64, evaluated in 50-digit arithmetic.

Each line: the nine elements of R (row-major, as f64 `repr`), then the
rotation vector of R (rounded to f64). R is exp(θ a) computed with mpmath
and rounded; its logarithm is taken from the rounded matrix itself
(Shepperd's quaternion in 50 digits, normalised, θ = 2 atan2(|q_v|, w)),
so the reference carries no error of its own beyond the final rounding.
The angles cover the series region, both sides of the asin/acos switch
(π/4), both sides of the quaternion fallback (2π/3) and the approach to π.

Run: python3 so3_log_mpmath.py > so3_log_mpmath.txt
"""
import math

import mpmath as mp

mp.mp.dps = 50

AXES = [(1, 2, 3), (0.3, -0.7, 0.8), (1, 0, 0), (0.2, 0.1, -1)]
ANGLES = [1e-9, 1e-6, 1e-3, 0.3, math.pi / 4 - 1e-3, math.pi / 4 + 1e-3, 1.0, 1.5,
          2 * math.pi / 3 - 1e-3, 2 * math.pi / 3 + 1e-3, 2.5, 3.0,
          math.pi - 1e-6, math.pi - 1e-9]


def exp_so3(phi):
    th = mp.sqrt(sum(p * p for p in phi))
    a = [p / th for p in phi]
    c, s = mp.cos(th), mp.sin(th)
    k = [[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]]
    return [[(1 if i == j else 0) * c + (1 - c) * a[i] * a[j] + s * k[i][j]
             for j in range(3)] for i in range(3)]


def log_so3(r):
    tr = r[0][0] + r[1][1] + r[2][2]
    pivots = [tr, r[0][0], r[1][1], r[2][2]]
    k = max(range(4), key=lambda i: pivots[i])
    if k == 0:
        w = mp.sqrt(1 + tr) / 2
        x, y, z = ((r[2][1] - r[1][2]) / (4 * w), (r[0][2] - r[2][0]) / (4 * w),
                   (r[1][0] - r[0][1]) / (4 * w))
    elif k == 1:
        x = mp.sqrt(1 + r[0][0] - r[1][1] - r[2][2]) / 2
        w, y, z = ((r[2][1] - r[1][2]) / (4 * x), (r[0][1] + r[1][0]) / (4 * x),
                   (r[0][2] + r[2][0]) / (4 * x))
    elif k == 2:
        y = mp.sqrt(1 - r[0][0] + r[1][1] - r[2][2]) / 2
        w, x, z = ((r[0][2] - r[2][0]) / (4 * y), (r[0][1] + r[1][0]) / (4 * y),
                   (r[1][2] + r[2][1]) / (4 * y))
    else:
        z = mp.sqrt(1 - r[0][0] - r[1][1] + r[2][2]) / 2
        w, x, y = ((r[1][0] - r[0][1]) / (4 * z), (r[0][2] + r[2][0]) / (4 * z),
                   (r[1][2] + r[2][1]) / (4 * z))
    n = mp.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    if w < 0:
        w, x, y, z = -w, -x, -y, -z
    vn = mp.sqrt(x * x + y * y + z * z)
    th = 2 * mp.atan2(vn, w)
    return [th * x / vn, th * y / vn, th * z / vn]


for ax in AXES:
    norm = math.sqrt(sum(a * a for a in ax))
    for th in ANGLES:
        phi = [mp.mpf(a / norm) * mp.mpf(th) for a in ax]
        r = [[float(v) for v in row] for row in exp_so3(phi)]
        ref = log_so3([[mp.mpf(v) for v in row] for row in r])
        print(" ".join(repr(v) for row in r for v in row),
              " ".join(repr(float(v)) for v in ref))
