"""Golden values for `lie/tests/series_golden.rs`: the coefficient
functions of the SO(3)/SE(3) exponential and its Jacobians, evaluated from
their closed forms in 100-digit arithmetic (the closed forms cancel up to
θ⁻⁴ at small angles, which costs at most 30 of those digits here, so every
value below is exact to far beyond f64).

Every angle is an f32 number (so the same line serves the f32 and the f64
test). The angles are a logarithmic grid over [1e-6, π] and, for every
series/closed-form cut-off of either precision (exp: 1e-3 and 1e-2;
C and D: 0.5 and 1.5; E and F: 1.0 and 2.0), the cut-off times
1 ∓ 1e-6, 1/1.5 and 1.5: both branches are checked next to the switch and
a little away from it, so a cut-off moved either way meets a golden on
the branch that then no longer holds its precision.

Each line: θ, then A = sin θ/θ, B = (1 − cos θ)/θ², cos θ,
C = (θ − sin θ)/θ³, D = 1/θ² − (1 + cos θ)/(2θ sin θ),
E = (θ² + 2cos θ − 2)/(2θ⁴), F = (2θ − 3 sin θ + θ cos θ)/(2θ⁵),
cos(θ/2) and sin(θ/2)/θ, each rounded to f64 (`repr`).

Run: python3 series_mpmath.py > series_mpmath.txt
"""
import math
import struct

import mpmath as mp

mp.mp.dps = 100

CUTS = [1e-3, 1e-2, 0.5, 1.5, 1.0, 2.0]


def f32(x):
    return struct.unpack("f", struct.pack("f", x))[0]


def angles():
    out = set()
    n = 64
    for k in range(n + 1):
        out.add(f32(math.exp(math.log(1e-6) + (math.log(math.pi) - math.log(1e-6)) * k / n)))
    for c in CUTS:
        for s in (1 - 1e-6, 1 + 1e-6, 1 / 1.5, 1.5):
            out.add(f32(c * s))
    # π itself rounds up in f32; the largest f32 below π stays in range.
    return sorted(t for t in out if t < math.pi)


def coefficients(theta):
    t = mp.mpf(theta)
    s, c = mp.sin(t), mp.cos(t)
    return [
        s / t,
        (1 - c) / t**2,
        c,
        (t - s) / t**3,
        1 / t**2 - (1 + c) / (2 * t * s),
        (t**2 + 2 * c - 2) / (2 * t**4),
        (2 * t - 3 * s + t * c) / (2 * t**5),
        mp.cos(t / 2),
        mp.sin(t / 2) / t,
    ]


for th in angles():
    vals = coefficients(th)
    print(repr(th), " ".join(repr(float(v)) for v in vals))
