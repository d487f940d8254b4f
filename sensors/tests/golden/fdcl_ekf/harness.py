"""Runs the FDCL lab's estimator (fdcl-gwu/uav_simulator, estimator.py) on
a recorded measurement stream, outside ROS, and writes its estimates.

    python3 harness.py PATH/TO/uav_simulator/src/fdcl_uav stream.csv out.csv

Their node needs ROS 2 (rclpy and three message packages) only to exist
and to read the wall clock: this harness puts empty stand-ins for those
modules in `sys.modules`, builds the node, and replaces its `get_dt` (which
reads the wall clock) with the stream's own time steps. It then calls the
node's `prediction` and `imu_correction` for each `imu` row, as their
`imu_callback` does, and `gps_correction` for each `gps` row, as their
`gps_callback` does, with the covariances their callbacks pass. After each
row it writes the node's `get_states()`, its bias and its covariance's
diagonal. Nothing of their code is copied: it is imported from the path
given.
"""

import csv
import sys
import types

import numpy as np


def stub_ros():
    class Node:
        def __init__(self, name):
            self.name = name

        def get_clock(self):
            return types.SimpleNamespace(now=lambda: 0)

        def create_subscription(self, *args):
            return None

        def create_publisher(self, *args):
            return None

    for name in ["rclpy", "rclpy.node", "nav_msgs", "nav_msgs.msg", "sensor_msgs",
                 "sensor_msgs.msg", "uav_gazebo", "uav_gazebo.msg"]:
        sys.modules[name] = types.ModuleType(name)
    sys.modules["rclpy.node"].Node = Node
    sys.modules["nav_msgs.msg"].Odometry = object
    sys.modules["sensor_msgs.msg"].Imu = object
    sys.modules["uav_gazebo.msg"].StateData = object


def main(package_dir, stream_path, out_path):
    stub_ros()
    sys.path.insert(0, package_dir)
    from fdcl_uav.estimator import EstimatorNode

    node = EstimatorNode()
    clock = {"t": 0.0, "h": 0.0}
    node.get_dt = lambda: clock["h"]
    with open(stream_path) as f, open(out_path, "w", newline="") as g:
        w = csv.writer(g)
        w.writerow(["kind", "t"] + [f"x{i}" for i in range(3)] + [f"v{i}" for i in range(3)]
                   + [f"a{i}" for i in range(3)] + [f"R{i}{j}" for i in range(3) for j in range(3)]
                   + [f"W{i}" for i in range(3)] + ["b_a"] + [f"P{i}" for i in range(10)])
        for row in csv.reader(f):
            if row[0] == "kind":
                continue
            kind, t, vals = row[0], float(row[1]), np.array([float(x) for x in row[2:]])
            if kind == "imu":
                clock["h"], clock["t"] = t - clock["t"], t
                node.prediction(vals[0:3], vals[3:6])
                node.imu_correction(vals[6:15].reshape(3, 3), node.V_R_imu)
            elif kind == "gps":
                node.gps_correction(vals[0:3], vals[3:6], node.V_x_gps, node.V_v_gps)
            x, v, a, R, W = node.get_states()
            w.writerow([kind, repr(t)] + [repr(float(z)) for z in
                        list(x) + list(v) + list(a) + list(R.reshape(9)) + list(W)
                        + [node.b_a] + list(np.diag(node.P))])


if __name__ == "__main__":
    main(*sys.argv[1:4])
