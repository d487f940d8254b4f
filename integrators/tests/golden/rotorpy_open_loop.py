"""RotorPy's multirotor flown open loop, the reference for
`integrators/tests/rotorpy.rs`.

Two cases, each 5 s of rotor-speed commands held piecewise constant at
100 Hz, in a constant wind, with aerodynamics on:

- `crazyflie`: RotorPy 3.0.0's crazyflie parameters as shipped (rotor
  drag and inflow, 72 ms motor lag; its parasitic drag, translational lift
  and flapping coefficients are zero);
- `hummingbird-flap`: its hummingbird parameters (parasitic drag,
  translational lift, 5 ms motor lag) with a flapping coefficient of 2e-7
  added, so that every term of the model is exercised.

The commands climb, tilt about both axes, yaw and descend, as differential
rotor speeds around hover. RotorPy integrates each 10 ms hold with
`scipy.integrate.solve_ivp` (RK45) at rtol = atol = 1e-12.

Output, in this project's frames (inertial e3 down, thrust along -b3;
RotorPy is z-up, related by P = diag(1, -1, -1) on world and body):
`x`, `v`, `R` (row-major), `omega` and rotor speeds every 0.1 s, the
commands (every 10 ms), the wind and the parameter changes. Usage:

    python3 rotorpy_open_loop.py OUT.txt
"""

import math
import sys

import numpy as np
import rotorpy
from rotorpy.vehicles.crazyflie_params import quad_params as crazyflie
from rotorpy.vehicles.hummingbird_params import quad_params as hummingbird
from rotorpy.vehicles.multirotor import Multirotor
from scipy.spatial.transform import Rotation

P = np.diag([1.0, -1.0, -1.0])
DT = 0.01
STEPS = 500


def commands(hover, t):
    """Four rotor speeds at time t: a climb, a roll pulse, a pitch pulse, a
    yaw pulse and a descent, each a few percent of hover and reversed
    half-way so that the vehicle does not tumble."""
    d = np.zeros(4)
    def pulse(t0, length):
        if t0 <= t < t0 + length / 2:
            return 1.0
        if t0 + length / 2 <= t < t0 + length:
            return -1.0
        return 0.0
    climb = 0.04 if 0.2 <= t < 1.2 else (-0.03 if 3.8 <= t < 4.8 else 0.0)
    d += climb
    # Rotors (RotorPy order): 1 front-left, 2 front-right... as laid out by
    # its rotor_pos: r1 (+,+), r2 (+,-), r3 (-,-), r4 (-,+) in its z-up frame.
    roll = 0.002 * pulse(1.3, 0.6)
    d += roll * np.array([1.0, -1.0, -1.0, 1.0])
    pitch = 0.002 * pulse(2.0, 0.6)
    d += pitch * np.array([-1.0, -1.0, 1.0, 1.0])
    yaw = 0.01 * pulse(2.7, 1.0)
    d += yaw * np.array([1.0, -1.0, 1.0, -1.0])
    wobble = 0.0005 * math.sin(2 * math.pi * 1.7 * t)
    d += wobble * np.array([1.0, 1.0, -1.0, -1.0])
    return hover * (1.0 + d)


def run(name, params, wind_zup):
    params = dict(params)
    vehicle = Multirotor(
        params,
        control_abstraction="cmd_motor_speeds",
        aero=True,
        integrator_kwargs={"method": "RK45", "rtol": 1e-12, "atol": 1e-12},
    )
    hover = math.sqrt(params["mass"] * 9.81 / (4 * params["k_eta"]))
    state = {
        "x": np.zeros(3),
        "v": np.zeros(3),
        "q": np.array([0.0, 0.0, 0.0, 1.0]),
        "w": np.zeros(3),
        "wind": np.array(wind_zup, dtype=float),
        "rotor_speeds": np.full(4, hover),
    }
    lines = [f"case {name}"]
    lines.append("wind " + " ".join(repr(float(c)) for c in P @ state["wind"]))
    lines.append(f"k_flap {params.get('k_flap', 0.0)!r}")
    states, cmds = [], []
    for k in range(STEPS + 1):
        t = k * DT
        r = P @ Rotation.from_quat(state["q"]).as_matrix() @ P
        row = [t, *(P @ state["x"]), *(P @ state["v"]), *r.reshape(-1),
               *(P @ state["w"]), *state["rotor_speeds"]]
        if k % 10 == 0:
            states.append("state " + " ".join(repr(float(c)) for c in row))
        if k == STEPS:
            break
        cmd = commands(hover, t)
        cmds.append("cmd " + " ".join(repr(float(c)) for c in [t, *cmd]))
        state = vehicle.step(state, {"cmd_motor_speeds": cmd}, DT)
        state["wind"] = np.array(wind_zup, dtype=float)
    return lines + cmds + states


def main():
    out = sys.argv[1]
    flap = dict(hummingbird)
    flap["k_flap"] = 2e-7
    text = [f"# rotorpy {getattr(rotorpy, '__version__', '3.0.0')}, "
            "solve_ivp RK45 rtol = atol = 1e-12, frames of this project"]
    text += run("crazyflie", crazyflie, [1.5, -0.8, 0.3])
    text += run("hummingbird-flap", flap, [-1.0, 0.5, -0.2])
    with open(out, "w") as f:
        f.write("\n".join(text) + "\n")


if __name__ == "__main__":
    main()
