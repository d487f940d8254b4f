"""RotorPy's own simulation of its SE3Control on its crazyflie, the
reference for `studies/tests/rotorpy_closed_loop.rs`.

Two cases, 10 s each, RotorPy 3.0.0's `Environment.run` (its simulation
loop: controller at 100 Hz on the true state, `Multirotor.step` between)
with aerodynamics on, no wind, and the vehicle integrated by
`solve_ivp` (RK45) at rtol = atol = 1e-12:

- `hover`: `HoverTraj` at the origin, released from (0.3, -0.2, 0.1) m;
- `circle`: `ThreeDCircularTraj` of radius 1 m in the horizontal plane
  at 0.2 Hz (centre 0), released at rest at its start point (1, 0, 0).

The rotors start at the controller's first command. Output, in this
project's frames (inertial e3 down, thrust along -b3; RotorPy is z-up,
related by P = diag(1, -1, -1) on world and body): `x`, `v`, `R`
(row-major), `omega` and rotor speeds every 0.1 s, and RotorPy's wall time
per simulated second. Usage:

    python3 rotorpy_closed_loop.py OUT.txt
"""

import sys
import time

import numpy as np
from rotorpy.controllers.quadrotor_control import SE3Control
from rotorpy.environments import Environment
from rotorpy.trajectories.circular_traj import ThreeDCircularTraj
from rotorpy.trajectories.hover_traj import HoverTraj
from rotorpy.vehicles.crazyflie_params import quad_params
from rotorpy.vehicles.multirotor import Multirotor
from scipy.spatial.transform import Rotation

P = np.diag([1.0, -1.0, -1.0])
DURATION = 10.0


def run(name, traj, x0):
    params = dict(quad_params)
    state = {"x": np.array(x0, dtype=float), "v": np.zeros(3), "q": np.array([0.0, 0.0, 0.0, 1.0]),
             "w": np.zeros(3), "wind": np.zeros(3), "rotor_speeds": np.zeros(4)}
    first = SE3Control(params).update(0.0, state, traj.update(0.0))["cmd_motor_speeds"]
    state["rotor_speeds"] = np.clip(first, params["rotor_speed_min"], params["rotor_speed_max"])
    vehicle = Multirotor(params, initial_state=state, aero=True,
                         integrator_kwargs={"method": "RK45", "rtol": 1e-12, "atol": 1e-12})
    env = Environment(vehicle=vehicle, controller=SE3Control(params), trajectory=traj,
                      sim_rate=100, safety_margin=0.25)
    t0 = time.perf_counter()
    res = env.run(t_final=DURATION, use_mocap=False, terminate=False, plot=False,
                  animate_bool=False, verbose=False)
    wall = time.perf_counter() - t0
    lines = [f"case {name}", f"wall_per_sim_s {wall / DURATION!r}"]
    s = res["state"]
    for k, t in enumerate(res["time"]):
        if k % 10:
            continue
        r = P @ Rotation.from_quat(s["q"][k]).as_matrix() @ P
        row = [t, *(P @ s["x"][k]), *(P @ s["v"][k]), *r.reshape(-1), *(P @ s["w"][k]),
               *s["rotor_speeds"][k]]
        lines.append("state " + " ".join(repr(float(c)) for c in row))
    return lines


def main():
    out = sys.argv[1]
    text = ["# rotorpy 3.0.0 Environment.run, SE3Control, crazyflie, aero on, "
            "solve_ivp RK45 rtol = atol = 1e-12, frames of this project"]
    text += run("hover", HoverTraj(), [0.3, -0.2, 0.1])
    text += run("circle", ThreeDCircularTraj(radius=np.array([1.0, 1.0, 0.0]),
                                             freq=np.array([0.2, 0.2, 0.2])), [1.0, 0.0, 0.0])
    with open(out, "w") as f:
        f.write("\n".join(text) + "\n")


if __name__ == "__main__":
    main()
