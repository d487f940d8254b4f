"""RotorPy flying on its own motion capture, the reference for
`studies/tests/rotorpy_closed_loop.rs`'s head-on comparison with noise.

RotorPy 3.0.0's `Environment.run(..., use_mocap=True)` at `sim_rate=100`:
its SE3Control reads the default `MotionCapture` (per-frame σ =
√(100/2)·{0.0005 m, 0.0010 m/s, 0.0005 rad, 0.0005 rad/s}, no spikes) at
every 10 ms step, on its crazyflie with aerodynamics on, for 10 s. Two
cases as in `rotorpy_closed_loop.py` (hover released from (0.3, -0.2,
0.1) m; the circle of radius 1 m at 0.2 Hz from (1, 0, 0)), 20 seeds each
(`np.random.seed(k)`, k = 0..19); the vehicle integrated by `solve_ivp`
(RK45) at rtol = atol = 1e-8.

The rotors start at the controller's first command on the true state, as
in `rotorpy_closed_loop.py` (the Rust side starts them there too).

Output: per case and seed, the RMS over the 1001 steps at k·10 ms of
‖x − x_d‖ (m; the same in either frame). Usage:

    python3 rotorpy_mocap.py OUT.txt
"""

import sys

import numpy as np
from rotorpy.controllers.quadrotor_control import SE3Control
from rotorpy.environments import Environment
from rotorpy.trajectories.circular_traj import ThreeDCircularTraj
from rotorpy.trajectories.hover_traj import HoverTraj
from rotorpy.vehicles.crazyflie_params import quad_params
from rotorpy.vehicles.multirotor import Multirotor

SEEDS = 20
DURATION = 10.0


def rms(name, traj, x0, seed):
    np.random.seed(seed)
    params = dict(quad_params)
    state = {"x": np.array(x0, dtype=float), "v": np.zeros(3), "q": np.array([0.0, 0.0, 0.0, 1.0]),
             "w": np.zeros(3), "wind": np.zeros(3), "rotor_speeds": np.zeros(4)}
    first = SE3Control(params).update(0.0, state, traj.update(0.0))["cmd_motor_speeds"]
    state["rotor_speeds"] = np.clip(first, params["rotor_speed_min"], params["rotor_speed_max"])
    vehicle = Multirotor(params, initial_state=state, aero=True,
                         integrator_kwargs={"method": "RK45", "rtol": 1e-8, "atol": 1e-8})
    env = Environment(vehicle=vehicle, controller=SE3Control(params), trajectory=traj,
                      sim_rate=100, safety_margin=0.25)
    res = env.run(t_final=DURATION, use_mocap=True, terminate=False, plot=False,
                  animate_bool=False, verbose=False)
    # RotorPy's clock is a running sum of steps: it may take a step past
    # 10 s. The RMS is over the 1001 steps at k·10 ms, k = 0..1000.
    keep = res["time"] <= DURATION + 1e-9
    e = res["state"]["x"][keep] - res["flat"]["x"][keep]
    assert len(e) == 1001, len(e)
    return float(np.sqrt(np.mean(np.sum(e * e, axis=1))))


def main():
    out = sys.argv[1]
    cases = [
        ("hover", HoverTraj(), [0.3, -0.2, 0.1]),
        ("circle", ThreeDCircularTraj(radius=np.array([1.0, 1.0, 0.0]),
                                      freq=np.array([0.2, 0.2, 0.2])), [1.0, 0.0, 0.0]),
    ]
    text = ["# rotorpy 3.0.0 Environment.run(use_mocap=True), sim_rate 100, SE3Control, "
            "crazyflie, aero on, RK45 1e-8; RMS of |x - x_d| (m) per seed 0..19"]
    for name, traj, x0 in cases:
        values = [rms(name, traj, x0, k) for k in range(SEEDS)]
        text.append(f"rms {name} " + " ".join(repr(v) for v in values))
    with open(out, "w") as f:
        f.write("\n".join(text) + "\n")


if __name__ == "__main__":
    main()
