"""Writes stream.csv: 2 s of a turning, accelerating vehicle as the FDCL
lab's estimator reads it. IMU rows at 100 Hz (acceleration without gravity
and rate in the IMU frame R_bi = diag(1, -1, -1), and the IMU's attitude,
IMU to world, each with noise), GPS rows at 10 Hz (position and velocity
with noise), NED world (e3 down). A constant accelerometer bias of
0.1 m/s^2 along e3 is in the readings, as their model has it.

    python3 make_stream.py stream.csv
"""

import csv
import sys

import numpy as np


def hat(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def exp_so3(r):
    th = np.linalg.norm(r)
    k = hat(r)
    if th < 1e-12:
        return np.eye(3) + k
    return np.eye(3) + np.sin(th) / th * k + (1 - np.cos(th)) / th**2 * k @ k


def main(path):
    rng = np.random.default_rng(20261207)
    r_bi = np.diag([1.0, -1.0, -1.0])
    w = np.array([0.3, -0.2, 0.5])
    bias = 0.1
    rows = []
    for k in range(1, 201):
        t = k / 100.0
        R = exp_so3(w * t)
        a = np.array([-0.3 * np.sin(t), 0.2 * np.cos(t), 0.4 * np.cos(2 * t)])
        a_imu = r_bi.T @ R.T @ (a - bias * np.array([0, 0, 1.0])) + 1e-3 * rng.standard_normal(3)
        w_imu = r_bi.T @ w + 1e-3 * rng.standard_normal(3)
        R_imu = R @ exp_so3(0.01 * rng.standard_normal(3)) @ r_bi
        rows.append(["imu", repr(t)] + [repr(float(z)) for z in list(a_imu) + list(w_imu) + list(R_imu.reshape(9))])
        if k % 10 == 0:
            x = np.array([0.3 * np.sin(t), -0.2 * np.cos(t) + 0.2, -0.1 * np.cos(2 * t) + 0.1])
            v = np.array([0.3 * np.cos(t), 0.2 * np.sin(t), 0.2 * np.sin(2 * t)])
            xg = x + 0.01 * rng.standard_normal(3)
            vg = v + 0.01 * rng.standard_normal(3)
            rows.append(["gps", repr(t)] + [repr(float(z)) for z in list(xg) + list(vg)])
    with open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["kind", "t", "values..."])
        w.writerows(rows)


if __name__ == "__main__":
    main(sys.argv[1])
