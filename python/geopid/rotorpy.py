"""The paper's position law as a RotorPy controller.

RotorPy (``pip install rotorpy``; not a dependency of this package) calls a
controller as ``update(t, state, flat_output) -> dict``. :class:`GeometricPID`
answers that call with :func:`geopid.position_control`, so a RotorPy
simulation can fly the geometric PID of Goodarzi, Lee & Lee.

Frames: RotorPy's world and body z axes point **up** and thrust acts along
+b3; this package follows the paper, e3 **down** and thrust along -b3. The
two are related by the rotation ``T = diag(1, -1, -1)`` (π about e1)
applied to both frames: ``x = T x_rp``, ``R = T R_rp T``, ``Ω = T Ω_rp``,
``M_rp = T M``; the thrust magnitude is the same. RotorPy's yaw ψ gives the
heading ``b1d = T (cos ψ, sin ψ, 0)``.

The integral terms are integrated here, between calls, by the explicit
Euler rule over the time between two calls (RotorPy calls once per step of
its fixed rate).
"""

from __future__ import annotations

from typing import Any, Dict, Mapping, Optional

import numpy as np

from . import position_control

_T = np.diag([1.0, -1.0, -1.0])


def _quat_xyzw_to_matrix(q: np.ndarray) -> np.ndarray:
    x, y, z, w = q / np.linalg.norm(q)
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def _matrix_to_quat_xyzw(m: np.ndarray) -> np.ndarray:
    # The largest of the four squared components decides the branch, so
    # no division is by a small number.
    tr = np.trace(m)
    squares = [tr, m[0, 0], m[1, 1], m[2, 2]]
    k = int(np.argmax(squares))
    if k == 0:
        w = 0.5 * np.sqrt(1 + tr)
        x, y, z = (m[2, 1] - m[1, 2]) / (4 * w), (m[0, 2] - m[2, 0]) / (4 * w), (m[1, 0] - m[0, 1]) / (4 * w)
    elif k == 1:
        x = 0.5 * np.sqrt(1 + 2 * m[0, 0] - tr)
        w, y, z = (m[2, 1] - m[1, 2]) / (4 * x), (m[0, 1] + m[1, 0]) / (4 * x), (m[0, 2] + m[2, 0]) / (4 * x)
    elif k == 2:
        y = 0.5 * np.sqrt(1 + 2 * m[1, 1] - tr)
        w, x, z = (m[0, 2] - m[2, 0]) / (4 * y), (m[0, 1] + m[1, 0]) / (4 * y), (m[1, 2] + m[2, 1]) / (4 * y)
    else:
        z = 0.5 * np.sqrt(1 + 2 * m[2, 2] - tr)
        w, x, y = (m[1, 0] - m[0, 1]) / (4 * z), (m[0, 2] + m[2, 0]) / (4 * z), (m[1, 2] + m[2, 1]) / (4 * z)
    q = np.array([x, y, z, w])
    return q if w >= 0 else -q


def matched_gains(quad_params: Mapping[str, Any], integral: bool = False) -> Dict[str, float]:
    """Gains of this package's law with the closed-loop rates of RotorPy's
    ``SE3Control`` defaults on the same vehicle: RotorPy's gains are per
    unit mass and inertia (``F = m(-k_p e_x - k_d e_v + ...)``, ``M =
    J(-k_R e_R - k_Ω e_Ω) + ...``), this law's are forces and moments, so
    ``k_x = m·6.5``, ``k_v = m·4``, ``k_R = J_xx·kp_att``, ``k_Ω =
    J_xx·kd_att``. With ``integral``, the integral gains keep the paper's
    ratios to the proportional ones (k_i/k_x = 0.1, k_I/k_R = 0.1); off,
    they are zero, as in ``SE3Control``."""
    m, jxx = float(quad_params["mass"]), float(quad_params["Ixx"])
    kp_att = float(quad_params.get("kp_att", 310.0))
    kd_att = float(quad_params.get("kd_att", 57.0))
    g = {
        "k_x": m * 6.5,
        "k_v": m * 4.0,
        "k_r": jxx * kp_att,
        "k_omega": jxx * kd_att,
        "k_i": 0.0,
        "k_att_i": 0.0,
    }
    if integral:
        g["k_i"] = 0.1 * g["k_x"]
        g["k_att_i"] = 0.1 * g["k_r"]
    return g


class GeometricPID:
    """A RotorPy controller (``update(t, state, flat_output)``) running the
    paper's position law (eqn:f, eqn:M) through :func:`geopid.position_control`.

    ``quad_params`` is RotorPy's vehicle dict (mass, Ixx, Iyy, Izz,
    rotor_pos, rotor_directions, k_eta, k_m); ``gains`` uses the scene
    file's ``[gains]`` keys (default: :func:`matched_gains`).
    """

    def __init__(self, quad_params: Mapping[str, Any], gains: Optional[Mapping[str, Any]] = None,
                 integral: bool = False):
        p = quad_params
        self.params = {
            "mass": float(p["mass"]),
            "inertia": [float(p["Ixx"]), float(p["Iyy"]), float(p["Izz"])],
            "gravity": 9.81,
        }
        self.gains = dict(gains) if gains is not None else matched_gains(p, integral)
        self.k_eta = float(p["k_eta"])
        # Rotor forces -> (thrust, moment) in RotorPy's body frame, as its
        # own controllers build it (rotors along +b3).
        ratio = float(p["k_m"]) / self.k_eta
        pos = [np.asarray(r, dtype=float) for r in p["rotor_pos"].values()]
        arms = np.array([np.cross(r, [0.0, 0.0, 1.0])[:2] for r in pos]).T
        f_to_tm = np.vstack([np.ones(len(pos)), arms, ratio * np.asarray(p["rotor_directions"], dtype=float)])
        self.tm_to_f = np.linalg.pinv(f_to_tm)
        self.e_i_pos = np.zeros(3)
        self.e_i_att = np.zeros(3)
        self.t_last: Optional[float] = None

    def update(self, t: float, state: Mapping[str, Any], flat_output: Mapping[str, Any]) -> Dict[str, Any]:
        """RotorPy's controller call: the command for ``state`` at ``t``."""
        R = _T @ _quat_xyzw_to_matrix(np.asarray(state["q"], dtype=float)) @ _T
        st = {
            "x": (_T @ state["x"])[None, :],
            "v": (_T @ state["v"])[None, :],
            "R": R[None, :, :],
            "omega": (_T @ state["w"])[None, :],
            "e_i_pos": self.e_i_pos[None, :],
            "e_i_att": self.e_i_att[None, :],
        }
        yaw = float(flat_output.get("yaw", 0.0))
        yd = float(flat_output.get("yaw_dot", 0.0))
        ydd = float(flat_output.get("yaw_ddot", 0.0))
        c, s = np.cos(yaw), np.sin(yaw)
        ref = {
            "x": _T @ flat_output["x"],
            "v": _T @ flat_output["x_dot"],
            "a": _T @ flat_output["x_ddot"],
            "jerk": _T @ flat_output.get("x_dddot", np.zeros(3)),
            "snap": _T @ flat_output.get("x_ddddot", np.zeros(3)),
            "b1d": _T @ np.array([c, s, 0.0]),
            "b1d_dot": _T @ np.array([-s * yd, c * yd, 0.0]),
            "b1d_ddot": _T @ np.array([-c * yd * yd - s * ydd, -s * yd * yd + c * ydd, 0.0]),
        }
        out = position_control(st, ref, self.gains, self.params)
        if self.t_last is not None and t > self.t_last:
            h = t - self.t_last
            self.e_i_pos = self.e_i_pos + h * out["e_i_pos_rate"][0]
            self.e_i_att = self.e_i_att + h * out["e_i_att_rate"][0]
        self.t_last = t
        thrust = float(out["thrust"][0])
        moment = _T @ out["moment"][0]
        forces = self.tm_to_f @ np.concatenate([[thrust], moment])
        speeds = np.sign(forces) * np.sqrt(np.abs(forces) / self.k_eta)
        return {
            "cmd_motor_speeds": speeds,
            "cmd_motor_thrusts": forces,
            "cmd_thrust": thrust,
            "cmd_moment": moment,
            "cmd_q": _matrix_to_quat_xyzw(_T @ out["Rc"][0] @ _T),
            "cmd_w": _T @ out["omega_c"][0],
        }
