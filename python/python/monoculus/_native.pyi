"""Type stubs of ``monoculus._native``, the Rust engine under the ``monoculus`` package.

Users meet these classes as the ``obs`` and ``rng`` arguments of an algorithm's
``decide``; the functions are called through :mod:`monoculus`.
"""

from typing import Any, Literal, Optional, Sequence

import numpy as np
import numpy.typing as npt

Side = Literal["low", "high"]
Vector = npt.NDArray[np.float64]

__version__: str

class ConfigError(ValueError):
    """A bad config, ``set`` or results folder; the message names the file, line and key."""

    file: Optional[str]
    line: Optional[int]
    key: Optional[str]

class AlgorithmError(RuntimeError):
    """Runs whose algorithm failed; a Python exception raised by ``decide`` is its
    ``__cause__``, and the message names the robot and the round."""

class Rng:
    """The robot's own random stream (valid only during its ``decide`` call)."""

    def uniform(self) -> float:
        """A uniform draw in [0, 1)."""
    def below(self, n: int) -> int:
        """A uniform integer in 0..n (n >= 1)."""
    def normal(self) -> float:
        """A standard normal draw."""

class State:
    """A robot's state, as an algorithm with ``lights`` gets it (valid during ``decide``)."""

    @property
    def light(self) -> str:
        """The name of the colour the robot shows."""
    @light.setter
    def light(self, colour: str | int) -> None:
        """Shows another colour: a name of the algorithm's lights, or its index."""
    @property
    def memory(self) -> npt.NDArray[np.float64]:
        """The robot's ``memory`` floats (empty without), changed in place."""

class _Observation:
    """What every model senses (valid only during the ``decide`` call it is given to)."""

    @property
    def dim(self) -> int:
        """The dimension (2 or 3)."""
    @property
    def params(self) -> dict[str, Any]:
        """The algorithm's parameters."""
    @property
    def directions(self) -> npt.NDArray[np.float64]:
        """Every visible point's unit direction in the robot's frame, a (k, dim) array."""
    def sole_visible(self) -> Optional[Vector]:
        """If exactly one point is visible, its direction; else None."""
    def count_visible_up_to(self, limit: int) -> int:
        """The number of visible points, counted up to ``limit``."""
    def random_visible(self, rng: Rng) -> Optional[Vector]:
        """The direction of a uniformly random visible point (None if none is)."""
    @property
    def colours(self) -> npt.NDArray[np.int64]:
        """The colour each visible point's robot shows (indices into ``lights``), in the
        order of ``directions``."""
    @property
    def lights(self) -> list[str]:
        """The names of the algorithm's lights (empty without)."""
    def lit(self) -> list[tuple[Vector, Optional[str]]]:
        """Every visible point as (direction, the name of the colour its robot shows)."""
    def random_lit(self, colour: str | int, rng: Rng) -> Optional[Vector]:
        """A uniformly random visible point whose robot shows ``colour`` (or None)."""
    def sees_light(self, colour: str | int) -> bool:
        """Whether a visible point's robot shows ``colour``."""

class DirectionsObservation(_Observation):
    """The ``directions`` model: unit directions only."""

class LdObservation(_Observation):
    """The ``ld`` model (locality detection): directions and far bits."""

    @property
    def far(self) -> npt.NDArray[np.bool_]:
        """Each visible point's far bit (farther than c), in the order of ``directions``."""
    def random_far(self, rng: Rng) -> Optional[Vector]:
        """The direction of a uniformly random visible point farther than c (or None)."""

class OlaObservation(_Observation):
    """The ``ola`` model (orthogonal line agreement): directions in the agreed axes."""

    def side_occupied(self, axis: int, side: Side) -> bool:
        """Whether a visible robot lies beyond the robot on ``side`` of local ``axis``."""
    def sides_occupied(self) -> list[list[bool]]:
        """For each local axis, ``[low occupied, high occupied]``."""
    def random_in_orthant(
        self, constraints: Sequence[tuple[int, Side]], rng: Rng
    ) -> Optional[Vector]:
        """A uniformly random visible point in the closed orthant of ``constraints``."""

class PositionsObservation(_Observation):
    """The ``positions`` model (the baselines): positions of the visible robots."""

    @property
    def relative_positions(self) -> npt.NDArray[np.float64]:
        """The visible points relative to the robot, a (k, dim) array."""

class Simulation:
    def __init__(
        self,
        config: Any,
        seed: int = 0,
        cell: int = 0,
        set: Any = None,
        positions: Optional[npt.NDArray[np.float64]] = None,
        algorithms: list[dict[str, Any]] = ...,
    ) -> None: ...
    def step(self) -> None: ...
    def run(self, max_rounds: Optional[int] = None) -> dict[str, str]: ...
    @property
    def positions(self) -> npt.NDArray[np.float64]: ...
    @property
    def round(self) -> int: ...
    @property
    def converged(self) -> bool: ...
    @property
    def stuck(self) -> bool: ...
    @property
    def stopped_by(self) -> Optional[str]: ...
    @property
    def goal(self) -> str: ...
    @property
    def goal_met(self) -> bool: ...
    @property
    def radius(self) -> float: ...
    @property
    def lights(self) -> npt.NDArray[np.int64]: ...
    @property
    def light_names(self) -> list[str]: ...
    @property
    def diameter(self) -> float: ...
    @property
    def hull_area(self) -> float: ...
    def look(self, robot: int) -> str: ...
    def replay(self, max_drawn: int, max_mb: int) -> ReplayData: ...

class ReplayData:
    def html(self) -> str: ...
    def gif(self, path: str, width: int, height: int) -> None: ...
    @property
    def title(self) -> str: ...
    @property
    def subtitle(self) -> str: ...
    @property
    def outcome(self) -> str: ...
    @property
    def verdict(self) -> str: ...
    @property
    def frames(self) -> int: ...
    def frame_positions(self, k: int) -> npt.NDArray[np.float32]: ...

def replay(
    config: Any,
    seed: Optional[int],
    cell: int,
    set: Any,
    algorithms: list[dict[str, Any]],
    max_drawn: int,
    max_mb: int,
) -> ReplayData: ...

def run(
    config: Any,
    set: Any,
    out: str,
    threads: Optional[int],
    algorithms: list[dict[str, Any]],
    force: bool = False,
) -> None: ...
def algorithm_table(
    algorithms: list[dict[str, Any]],
) -> list[tuple[str, str, str, str, str, list[str]]]: ...
def hunt(
    config: Any,
    set: Any,
    out: str,
    threads: Optional[int],
    algorithms: list[dict[str, Any]],
    cell: Optional[int] = None,
) -> str: ...
def check_algorithm(declaration: dict[str, Any]) -> None: ...
