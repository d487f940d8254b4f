"""Golden values for lie/tests/se3_golden.rs, computed with mpmath at 60
significant digits from the closed forms (no series, no cut-offs: at this
precision the cancellations near θ = 0 cost nothing that shows in f64).

    pip install mpmath
    python3 lie/tests/golden/se3_mpmath.py > lie/tests/golden/se3_mpmath.txt

Each line: a kind, its inputs, and the expected outputs, all rounded to 17
significant digits (enough to round-trip an f64):
- `q  rho(3) phi(3)  Q(9, row-major)` — the Q block of the SE(3) left
  Jacobian, Q(ρ, φ) = ½ρ^ + a(φ^ρ^ + ρ^φ^ + φ^ρ^φ^) + b(φ^²ρ^ + ρ^φ^² − 3φ^ρ^φ^)
  + c(φ^ρ^φ^² + φ^²ρ^φ^), a = (θ − sin θ)/θ³, b = (θ² + 2 cos θ − 2)/(2θ⁴),
  c = (2θ − 3 sin θ + θ cos θ)/(2θ⁵) (Barfoot & Furgale 2014; that this is
  the Jacobian of this crate's Exp is checked apart, against finite
  differences, in tests/group.rs); what is tested here is the f64
  evaluation: series below the cut-off, closed forms above it;
- `exp  rho(3) phi(3)  R(9) t(3)` — Exp of a twist: R = exp(φ^),
  t = J_l(φ) ρ, J_l = I + (1 − cos θ)/θ² φ^ + (θ − sin θ)/θ³ φ^².
"""

import mpmath as mp

mp.mp.dps = 60


def hat(v):
    return mp.matrix([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def norm(v):
    return mp.sqrt(sum(x * x for x in v))


def q_block(rho, phi):
    th = norm(phi)
    p, r = hat(phi), hat(rho)
    a = (th - mp.sin(th)) / th**3
    b = (th**2 + 2 * mp.cos(th) - 2) / (2 * th**4)
    c = (2 * th - 3 * mp.sin(th) + th * mp.cos(th)) / (2 * th**5)
    return r / 2 + a * (p * r + r * p + p * r * p) + b * (p * p * r + r * p * p - 3 * p * r * p) \
        + c * (p * r * p * p + p * p * r * p)


def exp_twist(rho, phi):
    th = norm(phi)
    p = hat(phi)
    eye = mp.eye(3)
    R = eye + mp.sin(th) / th * p + (1 - mp.cos(th)) / th**2 * p * p
    J = eye + (1 - mp.cos(th)) / th**2 * p + (th - mp.sin(th)) / th**3 * p * p
    t = J * mp.matrix(rho)
    return R, t


def axis(th, u):
    """th·u/|u|, rounded to f64 first: the test reads the inputs as f64,
    so the outputs are those of exactly these inputs."""
    n = norm(u)
    return [mp.mpf(float(th * x / n)) for x in u]


def fmt(xs):
    return " ".join(mp.nstr(x, 17, min_fixed=1, max_fixed=0) for x in xs)


def main():
    u = [mp.mpf(3), mp.mpf(-2), mp.mpf(6)]
    big = [mp.mpf(1000), mp.mpf(-2000), mp.mpf(500)]
    # The Q block where its series take over (θ small) and with a large ρ,
    # whose ½ρ^ term dwarfs the θ-dependent ones.
    for th in ["1e-9", "1e-6", "1e-4", "1e-2", "0.5", "3.14159"]:
        phi = axis(mp.mpf(th), u)
        Q = q_block(big, phi)
        print("q", fmt(big + phi), fmt([Q[i, j] for i in range(3) for j in range(3)]))
    # Exp of twists near θ = π (and at a generic angle), large translation.
    for th in [mp.pi - mp.mpf("1e-6"), mp.pi - mp.mpf("1e-9"), mp.mpf("1.3")]:
        phi = axis(th, u)
        R, t = exp_twist(big, phi)
        print("exp", fmt(big + phi), fmt([R[i, j] for i in range(3) for j in range(3)] + [t[i] for i in range(3)]))


if __name__ == "__main__":
    main()
