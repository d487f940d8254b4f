"""Type stubs of the native extension (the Rust crate python/src). Users
import the wrappers in geopid/__init__.py; these describe what they call."""

from typing import Any, Callable, Dict, List, Optional, Sequence, Tuple

import numpy as np

__version__: str

class SceneError(ValueError):
    """A scene that does not parse or validate."""

    key: Optional[str]
    """The dotted key the error is about (``integrator.dt``), if any."""
    location: Optional[str]
    """``file:line:col`` when known."""

class SimulationError(RuntimeError):
    """A run that failed (a step, a control law)."""

    t: float
    """When, s."""

class DivergedError(SimulationError):
    """A run stopped by its divergence guard."""

    termination: Dict[str, Any]
    result: Any

class Scene:
    """A validated scene."""

    @staticmethod
    def load(name_or_path: str) -> Scene:
        """A built-in scene by name, or a scene file by path."""
    @staticmethod
    def from_toml(text: str, origin: str = "<string>") -> Scene:
        """Parses TOML text; ``origin`` names it in error locations."""
    @staticmethod
    def from_dict(d: Dict[str, Any], origin: str = "<dict>") -> Scene:
        """A scene from a dict in the scene schema."""
    def with_overrides(self, **kwargs: Any) -> Scene:
        """The scene with settings replaced, validated."""
    def to_toml(self) -> str:
        """The scene as TOML (every value a run uses)."""
    @property
    def name(self) -> str: ...
    @property
    def duration(self) -> float: ...
    @staticmethod
    def builtin_names() -> List[str]:
        """The built-in scenes' names."""

class Simulation:
    """A scene's run, advanced in pieces."""

    def __init__(self, scene: Scene, reference: Optional[Callable[[float], Any]] = None) -> None: ...
    def advance_to(self, t: float) -> None:
        """Advances to ``t`` (at most the duration)."""
    def state(self) -> Dict[str, Any]:
        """t, x, v, R, omega, integrals, vehicle_states, segment, mode."""
    def set_state(self, **fields: np.ndarray) -> None:
        """Replaces x, v, R, omega, integrals or vehicle_states."""
    @property
    def time(self) -> float: ...
    @property
    def duration(self) -> float: ...
    def termination(self) -> Optional[Dict[str, Any]]:
        """How the run ended, or None while it can go on."""
    def output(self) -> Dict[str, Any]:
        """The run so far, as ``run`` returns it."""
    def finish(self) -> Dict[str, Any]:
        """Ends the run where it is and returns its output."""

def run(
    scene: Scene,
    *,
    csv: Optional[str] = None,
    mcap: Optional[str] = None,
    guard: Optional[Dict[str, float]] = None,
    reference: Optional[Callable[[float], Any]] = None,
    raise_on_divergence: bool = True,
) -> Dict[str, Any]:
    """Runs ``scene`` to the end; the samples' columns and the figures."""

def position_control(
    states: Dict[str, np.ndarray],
    references: Optional[Dict[str, np.ndarray]] = None,
    gains_json: Optional[str] = None,
    params: Optional[Dict[str, Any]] = None,
    outputs: Optional[List[str]] = None,
) -> Dict[str, np.ndarray]:
    """The position law over N states."""

def attitude_control(
    states: Dict[str, np.ndarray],
    references: Optional[Dict[str, np.ndarray]] = None,
    gains_json: Optional[str] = None,
    params: Optional[Dict[str, Any]] = None,
) -> Dict[str, np.ndarray]:
    """The attitude law over N states."""

def montecarlo(
    setup_json: Optional[str] = None,
    indices: Optional[Sequence[int]] = None,
    threads: Optional[int] = None,
) -> Dict[str, Any]:
    """The Monte Carlo experiment's columns and its samples.csv text."""

def montecarlo_header() -> str:
    """The header of samples.csv."""

def gradient(
    scene: Scene, params: Sequence[str], every: Optional[float] = None
) -> Tuple[float, np.ndarray]:
    """The tracking cost and its gradient with respect to 1 to 4 parameters."""

def tune(
    scene: Scene,
    factor: float,
    thrust_to_weight: Optional[float],
    gradients: int,
    every: Optional[float] = None,
) -> Dict[str, Any]:
    """k_x, k_v, k_R, k_Omega tuned on the exact gradient of the tracking cost."""

def minsnap(
    points: Sequence[Sequence[float]],
    yaw: Optional[Sequence[float]] = None,
    times: Optional[Sequence[float]] = None,
    mean_speed: Optional[float] = None,
    time_budget: Optional[float] = None,
    start_velocity: Optional[Sequence[float]] = None,
    end_velocity: Optional[Sequence[float]] = None,
    sample: Optional[Sequence[float]] = None,
) -> Dict[str, Any]:
    """A minimum-snap trajectory through waypoints, as its pieces."""

def instruction_set() -> str: ...
def cpu_has_x86_64_v3() -> bool: ...
