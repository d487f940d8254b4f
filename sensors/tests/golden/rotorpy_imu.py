"""RotorPy's IMU along a flight, the reference for `sensors/tests/rotorpy_imu.rs`.

RotorPy 3.0.0's crazyflie (aerodynamics on) flies its `ThreeDCircularTraj`
(radius 1 m in x and y, 0.5 m in z, 0.2 Hz) under its `SE3Control` for
10 s, stepped by `Multirotor.step` at 100 Hz. At each step the state, its
derivative from `Multirotor.statedot` (the accelerations an IMU reads) and
`Imu.measurement(..., with_noise=False)` are written, for an IMU at the
centre of mass (p = 0: RotorPy's lever-arm terms mix frames) turned by a
mounting rotation R_BS.

Output, in RotorPy's own frames (z up): per line `t`, `x`, `v`, `q`
(x, y, z, w), `w` (body), `vdot`, `wdot`, the accelerometer and the
gyroscope. Usage:

    python3 rotorpy_imu.py OUT.txt
"""

import sys

import numpy as np
from rotorpy.controllers.quadrotor_control import SE3Control
from rotorpy.sensors.imu import Imu
from rotorpy.trajectories.circular_traj import ThreeDCircularTraj
from rotorpy.vehicles.crazyflie_params import quad_params
from rotorpy.vehicles.multirotor import Multirotor
from scipy.spatial.transform import Rotation

# A mounting with no symmetry: 0.4 rad about (1, 2, 3)/|(1, 2, 3)|.
AXIS = np.array([1.0, 2.0, 3.0]) / np.sqrt(14.0)
R_BS = Rotation.from_rotvec(0.4 * AXIS).as_matrix()


def main(path):
    traj = ThreeDCircularTraj(
        center=np.array([0.0, 0.0, 0.0]),
        radius=np.array([1.0, 1.0, 0.5]),
        freq=np.array([0.2, 0.2, 0.2]),
    )
    flat = traj.update(0.0)
    hover = np.sqrt(quad_params["mass"] * 9.81 / (4 * quad_params["k_eta"]))
    state = {
        "x": np.array(flat["x"], dtype=float),
        "v": np.zeros(3),
        "q": np.array([0.0, 0.0, 0.0, 1.0]),
        "w": np.zeros(3),
        "wind": np.zeros(3),
        "rotor_speeds": np.full(4, hover),
    }
    vehicle = Multirotor(quad_params, initial_state=state, aero=True)
    controller = SE3Control(quad_params)
    imu = Imu(R_BS=R_BS, p_BS=np.zeros(3), sampling_rate=100)
    dt = 0.01
    lines = [
        "# rotorpy 3.0.0 crazyflie, ThreeDCircularTraj, SE3Control, 100 Hz; "
        "t x v q(xyzw) w vdot wdot accel gyro, RotorPy frames (z up)",
        "r_bs " + " ".join(repr(float(c)) for c in R_BS.flatten()),
    ]
    for k in range(1001):
        t = k * dt
        control = controller.update(t, state, traj.update(t))
        sd = vehicle.statedot(state, control, dt)
        m = imu.measurement(state, {"vdot": sd["vdot"], "wdot": sd["wdot"]}, with_noise=False)
        row = [t, *state["x"], *state["v"], *state["q"], *state["w"], *sd["vdot"], *sd["wdot"], *m["accel"], *m["gyro"]]
        lines.append("s " + " ".join(repr(float(c)) for c in row))
        state = vehicle.step(state, control, dt)
    with open(path, "w") as f:
        f.write("\n".join(lines) + "\n")


if __name__ == "__main__":
    main(sys.argv[1])
