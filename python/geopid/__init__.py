"""Geometric PID control of multirotors on SE(3), from Python.

The simulation, the controllers and the Monte Carlo study of the Rust
workspace (Goodarzi, Lee & Lee, "Geometric Nonlinear PID Control of a
Quadrotor UAV on SE(3)"), with results as numpy arrays. Frames follow the
paper: the inertial e3 axis points **down**, thrust acts along -b3.

>>> import geopid
>>> r = geopid.run("paper-flip", duration=2.0, sample=0.01)
>>> r.t.shape, r.R.shape
((201,), (201, 3, 3))
>>> bool(r.psi[-1] < 0.05)
True

A scene is a built-in name (``geopid.scene_names()``), a path to a TOML
scene file, TOML text, or a dict in the same schema; ``load_scene`` turns
any of them into a validated :class:`Scene`.
"""

from __future__ import annotations

import json
import os
from typing import Any, Callable, Dict, Mapping, Optional, Sequence, Union

import numpy as np

from ._native import ext as _geopid

DivergedError = _geopid.DivergedError
Scene = _geopid.Scene
SceneError = _geopid.SceneError
SimulationError = _geopid.SimulationError

__all__ = [
    "DivergedError",
    "Result",
    "Scene",
    "SceneError",
    "Simulation",
    "SimulationError",
    "attitude_control",
    "gradient",
    "instruction_set",
    "load_scene",
    "minsnap",
    "montecarlo",
    "position_control",
    "run",
    "scene_names",
    "tune",
]

__version__ = _geopid.__version__

SceneLike = Union[str, "os.PathLike[str]", Mapping[str, Any], Scene]


def instruction_set() -> str:
    """The instructions the loaded build of the extension uses:
    ``"x86-64-v3"`` (AVX2, FMA: the SIMD lanes' fast path) or
    ``"baseline"`` (any x86-64). A wheel imports its x86-64-v3 build on a
    CPU that has those features; ``GEOPID_INSTRUCTION_SET=baseline`` forces
    the other. Results are identical to the bit either way."""
    return _geopid.instruction_set()


def scene_names() -> list:
    """The built-in scenes' names."""
    return Scene.builtin_names()


def load_scene(scene: SceneLike, **overrides: Any) -> Scene:
    """A validated :class:`Scene` from a built-in name, a file path, TOML
    text or a dict, with settings overridden by keyword (``integrator``,
    ``dt``, ``tol``, ``duration``, ``sample``, ``control_rate``,
    ``loop_rates`` ("crazyflie": estimator, attitude and position at
    1 kHz, 500 Hz and 100 Hz),
    ``scalar`` ("f32"/"f64"), ``backend`` ("nalgebra"/"glam"),
    ``no_integral``, ``sensors`` (a suite: "rotorpy", "crazyflie",
    "mpu9250", "fdcl-gazebo"), ``estimator`` ("none", "mocap", "iekf", "complementary", "fdcl-ekf"), ``seed``;
    ``None`` keeps the scene's value).

    Raises :class:`SceneError` (a ``ValueError``) with ``key`` and
    ``location`` ("file:line:col") when the scene does not parse or
    validate.
    """
    if isinstance(scene, Scene):
        s = scene
    elif isinstance(scene, Mapping):
        s = Scene.from_dict(dict(scene))
    elif isinstance(scene, os.PathLike):
        s = Scene.load(os.fspath(scene))
    elif isinstance(scene, str):
        # TOML text always has a key = value line; a name or a path never
        # contains a newline or an equals sign.
        if "\n" in scene or "=" in scene:
            s = Scene.from_toml(scene)
        else:
            s = Scene.load(scene)
    else:
        raise TypeError(
            f"scene: expected a name, path, TOML text, dict or Scene, got {type(scene).__name__}"
        )
    return s.with_overrides(**overrides)


class Result:
    """What a run produced: the samples as numpy arrays (one row per
    recorded sample) and the run's figures.

    Arrays: ``t`` (n,), ``x``, ``v``, ``omega``, ``moment``, ``xd``,
    ``omega_d``, ``e_att``, ``e_pos``, ``wind`` (n, 3; the air's velocity
    at the vehicle, zero without a ``[wind]``), ``R``, ``Rd`` (n, 3, 3),
    ``psi``, ``ex``, ``thrust`` (n,), ``rotors`` (n, rotors),
    ``vehicle_states`` (n, k), ``segment`` (n,) int. Lists: ``mode`` (the
    active mode's name per sample), ``mode_names`` (per plan segment),
    ``switches`` ((t, from, to) tuples), ``event_times`` ((t, component)),
    ``contacts`` ((t, foot, touchdown, speed into the ground) for each foot
    touching or leaving the ground, located inside the step),
    ``warnings``, ``health`` (numerical-health warnings, empty when the
    run is sound). Figures: ``steps``, ``evaluations``, ``max_thrust``,
    ``max_rotor``, ``wall`` (s), ``max_orthogonality_error``,
    ``psi_range``, ``epsilon``. ``termination`` is a dict: ``kind``
    ("completed", "stopped", "interrupted", "diverged" or "crashed";
    "unknown" for a reason newer than this package), ``t`` and, for a
    divergence, ``what`` and ``value``; for a crash (a touchdown faster
    than ``ground.crash_speed``), the foot ``point`` and its ``speed``.

    With sensors, ``measurements`` holds a dict of arrays per sensor, a
    row per sample it took: ``imu`` (``t``, ``accel``, ``gyro``),
    ``mocap`` (``t``, ``arrival``, ``x``, ``v``, ``R``, ``omega``),
    ``gps`` (``t``, ``arrival``, ``x``, ``v``), ``baro`` (``t``,
    ``height``); and with an estimator, ``estimate`` holds the state the
    modes read at each recorded sample (``x``, ``v``, ``R``, ``omega``;
    ``None`` without one).
    """

    _ARRAYS = (
        "t", "x", "v", "R", "omega", "psi", "ex", "thrust", "moment", "Rd",
        "omega_d", "xd", "e_att", "e_pos", "wind", "rotors", "vehicle_states",
    )

    def __init__(self, fields: Dict[str, Any]):
        self.__dict__.update(fields)
        self.segment = np.asarray(self.segment, dtype=np.int64)

    def __repr__(self) -> str:
        kind = self.termination["kind"]
        return f"<Result {len(self.t)} samples to t={self.t[-1]:.6g} s, {self.steps} steps, {kind}>"

    def to_pandas(self):
        """The samples as a pandas DataFrame indexed by t, one column per
        scalar (``x0``..``x2``, ``R00``..``R22``, ``rotor0``...). pandas
        is not a dependency: this raises ImportError without it."""
        import pandas as pd  # noqa: PLC0415 - optional dependency

        cols: Dict[str, np.ndarray] = {}
        for name in self._ARRAYS[1:]:
            a = getattr(self, name)
            if a.ndim == 1:
                cols[name] = a
            elif a.ndim == 2:
                prefix = "rotor" if name == "rotors" else name
                for k in range(a.shape[1]):
                    cols[f"{prefix}{k}"] = a[:, k]
            else:
                for i in range(3):
                    for j in range(3):
                        cols[f"{name}{i}{j}"] = a[:, i, j]
        cols["mode"] = self.mode
        cols["segment"] = self.segment
        return pd.DataFrame(cols, index=pd.Index(self.t, name="t"))


def _wrap_diverged(e: DivergedError) -> DivergedError:
    if isinstance(getattr(e, "result", None), dict):
        e.result = Result(e.result)
    return e


def run(
    scene: SceneLike,
    *,
    integrator: Optional[str] = None,
    dt: Optional[float] = None,
    tol: Optional[float] = None,
    scalar: Optional[str] = None,
    backend: Optional[str] = None,
    duration: Optional[float] = None,
    sample: Optional[float] = None,
    control_rate: Optional[float] = None,
    loop_rates: Optional[str] = None,
    no_integral: bool = False,
    sensors: Optional[str] = None,
    estimator: Optional[str] = None,
    seed: Optional[int] = None,
    csv: Optional[Union[str, "os.PathLike[str]"]] = None,
    mcap: Optional[Union[str, "os.PathLike[str]"]] = None,
    guard: Optional[Mapping[str, float]] = None,
    reference: Optional[Callable[[float], Any]] = None,
    raise_on_divergence: bool = True,
) -> Result:
    """Runs a scene to its end (keywords as :func:`load_scene`'s; ``None``
    keeps the scene's value; ``sensors``, ``estimator`` and ``seed`` fly
    it on measurements, see :class:`Result` for what they add) and returns its :class:`Result`; ``csv`` and
    ``mcap`` write the samples as ``cargo xtask run`` does. ``guard`` sets
    divergence limits: ``omega`` (|Ω|, rad/s), ``position_error``
    (‖x − x_d‖, m), ``moment`` (‖M‖, N m), ``substeps`` (per dopri call).
    ``reference``, a callable ``t -> (x, v, a, jerk, snap, b1d, b1d_dot,
    b1d_ddot)`` (a tuple of up to eight 3-vectors, the rest zero and
    ``b1d`` = e1, or a dict with those keys), replaces the position
    reference of every position-mode segment; it is the slow path (a few
    µs an evaluation, several evaluations a step), and an exception it
    raises stops the run and is re-raised.

    Raises ``OSError`` (with ``field``, "csv" or "mcap", and ``path``)
    before anything runs when an output cannot be written there (a
    missing directory, a directory, both outputs naming one file),
    :class:`SceneError` for a bad scene or setting,
    :class:`SimulationError` (with ``t``) when a step fails, and
    :class:`DivergedError` (with ``t``, ``termination`` and the partial
    ``result``) when the guard stops the run, unless
    ``raise_on_divergence`` is false (then ``result.termination`` says
    "diverged"); Ctrl-C stops the run and raises ``KeyboardInterrupt``.
    """
    s = load_scene(
        scene,
        integrator=integrator,
        dt=dt,
        tol=tol,
        scalar=scalar,
        backend=backend,
        duration=duration,
        sample=sample,
        control_rate=control_rate,
        loop_rates=loop_rates,
        no_integral=no_integral,
        sensors=sensors,
        estimator=estimator,
        seed=seed,
    )
    try:
        out = _geopid.run(
            s,
            csv=None if csv is None else os.fspath(csv),
            mcap=None if mcap is None else os.fspath(mcap),
            guard=None if guard is None else dict(guard),
            reference=reference,
            raise_on_divergence=raise_on_divergence,
        )
    except DivergedError as e:
        raise _wrap_diverged(e) from None
    return Result(out)


class Simulation:
    """A scene's run to advance in pieces, look at and change: a notebook,
    a gym-style loop, a co-simulation.

    >>> sim = geopid.Simulation("hover-disturbed", duration=4.0)
    >>> sim.advance_to(1.0)
    >>> s = sim.state
    >>> sim.set_state(omega=s["omega"] + [2.0, 0.0, 0.0])  # a kick about b1
    >>> sim.advance_to(4.0)
    >>> bool(sim.finish().psi[-1] < 1e-3)
    True

    ``advance_to(t)`` takes every step that ends at or before ``t``: the
    step grid never moves, so advancing in pieces gives the same samples
    as one :func:`run`, bit for bit. ``reference`` is a callable as in
    :func:`run`.
    """

    def __init__(
        self,
        scene: SceneLike,
        reference: Optional[Callable[[float], Any]] = None,
        **overrides: Any,
    ):
        # An unknown setting is a TypeError from `load_scene`.
        self._sim = _geopid.Simulation(load_scene(scene, **overrides), reference)

    def advance_to(self, t: float) -> None:
        """Advances to ``t`` (at most the duration)."""
        self._sim.advance_to(float(t))

    @property
    def state(self) -> Dict[str, Any]:
        """The state now: ``t``, ``x``, ``v``, ``R`` (3, 3), ``omega``,
        ``integrals``, ``vehicle_states`` (numpy arrays), ``segment``,
        ``mode``."""
        return self._sim.state()

    def set_state(self, **fields: Any) -> None:
        """Replaces ``x``, ``v``, ``R``, ``omega``, ``integrals`` or
        ``vehicle_states`` (the others stay). Raises ``ValueError`` naming
        the field for a wrong shape or a non-finite value."""
        self._sim.set_state(**{k: np.asarray(v, dtype=np.float64) for k, v in fields.items()})

    @property
    def time(self) -> float:
        """Time reached, s."""
        return self._sim.time

    @property
    def duration(self) -> float:
        """The run's duration, s."""
        return self._sim.duration

    @property
    def termination(self) -> Optional[Dict[str, Any]]:
        """How the run ended, or None while it can go on."""
        return self._sim.termination()

    def output(self) -> Result:
        """The run so far."""
        return Result(self._sim.output())

    def finish(self) -> Result:
        """Ends the run where it is (``termination`` says "interrupted"
        before the duration) and returns its :class:`Result`."""
        return Result(self._sim.finish())


def _arrays(d: Optional[Mapping[str, Any]]) -> Optional[Dict[str, np.ndarray]]:
    if d is None:
        return None
    return {k: np.ascontiguousarray(v, dtype=np.float64) for k, v in d.items()}


def position_control(
    states: Mapping[str, Any],
    references: Optional[Mapping[str, Any]] = None,
    gains: Optional[Mapping[str, Any]] = None,
    params: Optional[Mapping[str, Any]] = None,
    outputs: Optional[Sequence[str]] = None,
) -> Dict[str, np.ndarray]:
    """The paper's position law for N states at once.

    ``states``: ``x``, ``v``, ``omega`` (N, 3), ``R`` (N, 3, 3), and the
    integrals ``e_i_pos``, ``e_i_att`` (N, 3; zero if left out).
    ``references``: ``x``, ``v``, ``a``, ``jerk``, ``snap``, ``b1d``,
    ``b1d_dot``, ``b1d_ddot``, each (N, 3) or (3,) for all (zero if left
    out, ``b1d`` = e1). ``gains``: the scene file's ``[gains]`` keys
    (``k_x``, ``k_v``, ``k_i``, ``k_r``, ``k_omega``, ``k_att_i``, ``c1``,
    ``c2``, ``sigma``, ``clamp_integral``, ``acceleration_model``; the
    paper's for those left out). ``params``: ``mass``, ``inertia``
    (diagonal), ``gravity`` (the paper's quadrotor by default).

    Returns ``thrust``, ``psi`` (N,), ``moment``, ``omega_c``,
    ``omega_c_dot``, ``e_x``, ``e_v``, ``e_R``, ``e_omega``,
    ``e_i_pos_rate``, ``e_i_att_rate`` (N, 3) and ``Rc`` (N, 3, 3), or
    only those named in ``outputs`` (``["thrust", "moment"]`` for a
    simulator that needs the wrench: over many states the fresh arrays
    cost as much as the law). A wrong shape, unknown key or non-finite
    input raises ``ValueError`` naming the field (and the row).
    """
    g = None if gains is None else json.dumps(dict(gains))
    sel = None if outputs is None else [str(o) for o in outputs]
    return _geopid.position_control(_arrays(states), _arrays(references), g, params, sel)


def attitude_control(
    states: Mapping[str, Any],
    references: Optional[Mapping[str, Any]] = None,
    gains: Optional[Mapping[str, Any]] = None,
    params: Optional[Mapping[str, Any]] = None,
) -> Dict[str, np.ndarray]:
    """The paper's attitude law for N states at once.

    ``states``: ``R`` (N, 3, 3), ``omega`` (N, 3), ``e_i`` (N, 3; zero if
    left out). ``references``: ``Rd`` (N, 3, 3) or (3, 3), ``omega_d``,
    ``omega_d_dot`` (N, 3) or (3,) (identity and zero if left out).
    ``gains`` and ``params`` as for :func:`position_control`. Returns
    ``moment``, ``e_R``, ``e_omega``, ``e_i_rate`` (N, 3) and ``psi`` (N,).
    """
    g = None if gains is None else json.dumps(dict(gains))
    return _geopid.attitude_control(_arrays(states), _arrays(references), g, params)


_SAMPLE_DTYPE = np.dtype(
    [
        ("index", np.uint64),
        ("angle", np.float64),
        ("axis1", np.float64),
        ("axis2", np.float64),
        ("axis3", np.float64),
        ("omega0", np.float64),
        ("ex0", np.float64),
        ("converged", np.bool_),
        ("t_converge", np.float64),
        ("final_psi", np.float64),
        ("final_ex", np.float64),
        ("max_thrust", np.float64),
        ("max_rotor", np.float64),
        ("steps", np.uint64),
        ("status", "U9"),
    ]
)


def montecarlo(
    experiment: str = "position",
    samples: int = 1000,
    seed: int = 1,
    *,
    threads: Optional[int] = None,
    indices: Optional[Sequence[int]] = None,
    csv: Optional[Union[str, "os.PathLike[str]"]] = None,
    lanes: bool = False,
    **setup: Any,
) -> np.ndarray:
    """The paper's Monte Carlo experiment ("attitude" or "position"):
    samples ``0..samples`` (or ``indices``) of ``seed`` on ``threads``
    threads (default: one per core), with the interpreter's lock released.

    Further keywords set the study as ``cargo xtask montecarlo``'s flags
    do: ``omega_max``, ``x_max``, ``v_max``, ``psi_tol``, ``x_tol``,
    ``deadline``, ``hold``, ``integrator``, ``dt``, ``tol``,
    ``locate_events``.

    ``lanes=True`` flies four samples per instruction stream on SIMD lanes
    (``dopri`` only; several times faster). The lanes do
    not locate the sat′ crossings of e_i, so ``locate_events`` is off: each
    row then equals the scalar run's with ``locate_events=False``.

    Returns a numpy structured array with the columns of ``samples.csv``;
    ``csv`` writes that file, byte for byte what the command line writes
    for the same setup. Ctrl-C stops the study and raises
    ``KeyboardInterrupt``.
    """
    cfg = dict(setup, experiment=experiment, samples=int(samples), seed=int(seed))
    if lanes:
        cfg["locate_events"] = False
    idx = None if indices is None else [int(i) for i in indices]
    cols = _geopid.montecarlo(json.dumps(cfg), idx, threads, bool(lanes))
    rows = np.zeros(len(cols["index"]), dtype=_SAMPLE_DTYPE)
    for name in _SAMPLE_DTYPE.names:
        rows[name] = cols[name]
    if csv is not None:
        path = os.fspath(csv)
        tmp = path + ".partial"
        with open(tmp, "w", encoding="utf-8", newline="") as f:
            f.write(cols["csv"])
        os.replace(tmp, path)
    return rows


def gradient(
    scene: SceneLike,
    params: Sequence[str],
    *,
    every: Optional[float] = None,
) -> "tuple[float, np.ndarray]":
    """The tracking cost ``sum ||x(t_k) - x_d(t_k)||^2 dt`` of a scene's
    first position segment, sampled every ``every`` seconds (default: the
    scene's record interval), and its exact gradient with respect to
    ``params``: 1 to 4 parameter names such as ``"gains.k_x"``,
    ``"vehicle.mass"`` or ``"initial.x[2]"``.

    The derivatives are those of the flight as flown (every step, event
    and mode switch of the same run), computed by forward-mode dual
    numbers through the whole simulation, not by finite differences.
    Returns ``(cost, gradient)``. A name that is not a parameter raises
    ``SceneError`` naming it; a derivative that turns non-finite raises
    ``SimulationError`` with ``t``.
    """
    value, g = _geopid.gradient(load_scene(scene), [str(p) for p in params], every)
    return value, g


def minsnap(
    points: Sequence[Sequence[float]],
    *,
    yaw: Optional[Sequence[float]] = None,
    times: Optional[Sequence[float]] = None,
    mean_speed: Optional[float] = None,
    time_budget: Optional[float] = None,
    start_velocity: Optional[Sequence[float]] = None,
    end_velocity: Optional[Sequence[float]] = None,
    sample: Optional[Sequence[float]] = None,
) -> Dict[str, Any]:
    """The minimum-snap trajectory through ``points`` (m, e3 down; at
    least two): degree-7 pieces, the position at each point, velocity to
    snap continuous between pieces, at rest at both ends unless
    ``start_velocity`` / ``end_velocity`` (m/s) say otherwise, and a yaw
    trajectory of its own through ``yaw`` (rad, one per point).

    The timing is at most one of ``times`` (s at each point, 0 first),
    ``mean_speed`` (each segment's length over it, m/s; RotorPy's rule,
    1 m/s when none is given) and ``time_budget`` (a total, s, shared out
    to minimise the snap cost).

    Returns a dict: ``durations`` (n,), ``coefficients`` (n, 4, 8: x, y,
    z, yaw in ascending powers of each piece's local time), ``pptraj``
    (the pieces as a Crazyflie trajectory file, z up) and, with
    ``sample`` (times, s), ``x`` (m, 5, 3: the position and its first four
    derivatives) and ``yaw`` (m, 3: yaw and its two derivatives). Bad
    input raises ``ValueError`` whose ``field`` names it (``"times[2]"``,
    ``"waypoints[1].y"``).
    """
    as_list = lambda v: None if v is None else [float(c) for c in v]
    return _geopid.minsnap(
        [[float(c) for c in p] for p in points],
        as_list(yaw),
        as_list(times),
        None if mean_speed is None else float(mean_speed),
        None if time_budget is None else float(time_budget),
        as_list(start_velocity),
        as_list(end_velocity),
        as_list(sample),
    )


def tune(
    scene: SceneLike = "difftune-circle",
    *,
    factor: float = 10.0,
    thrust_to_weight: Optional[float] = 2.0,
    gradients: int = 20,
    every: Optional[float] = None,
    noise_seeds: int = 0,
) -> Dict[str, Any]:
    """The gains ``k_x, k_v, k_R, k_Omega`` tuned on the exact gradient of
    the tracking cost (as ``cargo xtask tune``): projected gradient descent
    on their logarithms with a line search, each gain within
    ``[g0 / factor, g0 * factor]`` of its start, no flight commanding more
    than ``thrust_to_weight`` times the weight (``None``: no limit), at most
    ``gradients`` gradient evaluations. With ``noise_seeds`` above 1 the
    cost and its gradient are means over the scene flown with seeds
    ``seed, ..., seed + noise_seeds - 1`` (tuning for the sensor noise's
    distribution rather than one draw of it).

    Returns a dict: ``scene`` (the tuned :class:`Scene`), ``names``, and per
    iteration ``gains`` (n, 4), ``cost``, ``gradient`` (n, 4),
    ``max_thrust`` (N) and ``plain_runs``; ``final_cost`` is the tuned
    scene's. ``sqrt(cost / duration)`` is the RMS position error.
    """
    return _geopid.tune(
        load_scene(scene),
        float(factor),
        thrust_to_weight,
        int(gradients),
        every,
        int(noise_seeds),
    )
