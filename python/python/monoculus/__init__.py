"""monoculus: swarms of robots that cannot measure distances, from Python.

The Rust engine of the `monoculus` command line, with a Python face:

- :func:`run` runs a sweep (a config file, or a dict in its shape) into a
  :class:`pandas.DataFrame` of ``runs.csv``'s rows, and into a results folder if asked;
- :class:`Simulation` steps one run, with its positions as numpy arrays;
- :func:`algorithm` turns a Python function into an algorithm that every scheduler,
  error model and fault model runs, in the plane and in space;
- :func:`replay` records a run as a :class:`Replay`, shown inline in Jupyter, saved as
  the replay page or a GIF; :meth:`Simulation.replay` does so for a stepped run;
- :func:`plot` draws ``monoculus plot``'s figures from a DataFrame with matplotlib.

See ``docs/python.md`` in the repository.
"""

from __future__ import annotations

import io
import os
import tempfile
from typing import Any, Callable, Mapping, Optional, Sequence, Union

import numpy as np
import pandas as pd

from . import _native
from ._native import AlgorithmError, ConfigError, Rng, State
from ._plot import plot
from ._replay import HuntResult, Replay

__all__ = [
    "AlgorithmError",
    "ConfigError",
    "HuntResult",
    "Replay",
    "Rng",
    "State",
    "Simulation",
    "algorithm",
    "algorithms",
    "hunt",
    "plot",
    "replay",
    "run",
]

__version__: str = _native.__version__

_REGISTERED: dict[str, dict[str, Any]] = {}


def algorithm(
    name: str,
    sensing: str = "ld",
    memory: Optional[int] = None,
    params: Optional[Mapping[str, Any]] = None,
    vectorized: bool = False,
    stop: Optional[str] = None,
    goal: Optional[str] = None,
    lights: Optional[Sequence[str]] = None,
) -> Callable[[Callable[..., Any]], Callable[..., Any]]:
    """Registers ``decide`` as the algorithm ``name`` (what ``algorithm.name`` selects).

    ``decide(obs, rng)`` (``decide(obs, rng, state)`` with ``memory``) is called for
    each activation of a robot, from what it senses in the model ``sensing``
    (``"directions"``, ``"ld"``, ``"ola"`` or ``"positions"``), in its local frame; it
    returns a direction in that frame (a numpy array or a tuple, a unit vector) or
    ``None`` to stay. ``rng`` is the robot's own random stream: draw only from it, and
    runs are reproducible whatever the thread count. ``state`` is a numpy array of
    ``memory`` floats the robot keeps between its activations (zeros at the start;
    change it in place). ``params`` are the defaults of the algorithm's parameters,
    which a config's ``[algorithm.params]`` may set (and sweep); ``obs.params`` holds
    them. ``stop`` is the default stop criterion (``"quiescent_or_diameter"`` unless
    given: ``"quiescent"``, ``"diameter"``, ``"quiescent_or_diameter"`` or ``"box"``);
    ``goal`` is what its convergence means (``"diameter"`` unless given: every pair
    within c; ``"disc"``: every robot within a disc of radius c; ``"box"``: a bounding
    box of extent at most 2b): a run converges when its stop criterion ends it and its
    goal holds, and a run that falls quiescent short of its goal is *stuck*.

    With ``lights`` (the names of the colours a robot may show, the luminous-robot
    model), every robot shows a colour, the first at the start, and sees the colour of
    each robot it sees: ``obs.lit()`` (pairs of a direction and a colour's name),
    ``obs.colours`` (indices, in the order of ``obs.directions``),
    ``obs.random_lit(colour, rng)`` and ``obs.sees_light(colour)`` (a colour by name or
    index). ``decide(obs, rng, state)`` then gets the robot's :class:`State`: set
    ``state.light`` (a name or an index) to change the colour it shows, which the others
    see from the next round (ASYNC: once its Compute ends); ``state.memory`` holds its
    ``memory`` floats. A robot that would only change its light is not quiescent.

    With ``vectorized=True``, ``decide(batch)`` is called once per round (ASYNC: per
    tick) with every activation at once: ``batch.count`` activations,
    ``batch.offsets`` (``count + 1``; activation ``i``'s points are rows
    ``offsets[i]:offsets[i + 1]``), ``batch.directions`` (one row per visible point),
    ``batch.far`` (ld) or ``batch.sides`` (ola: ``count`` rows of low/high per axis),
    ``batch.random`` (``count`` rows of 8 uniform draws from each robot's stream),
    ``batch.state`` (with ``memory``, ``count`` rows, changed in place),
    with ``lights`` ``batch.colours`` (the colour of each visible point, one per row of
    ``batch.directions``), ``batch.light`` (each robot's colour, changed in place) and
    ``batch.lights`` (the names), and ``batch.params``; it returns ``(directions, stay)``: an ``(count, dim)`` array and
    ``count`` booleans.
    """
    declaration = {
        "name": name,
        "sensing": sensing,
        "memory": memory,
        "params": dict(params) if params is not None else None,
        "vectorized": bool(vectorized),
        "stop": stop,
        "goal": goal,
        "lights": list(lights) if lights is not None else None,
        "func": None,
    }
    _native.check_algorithm(declaration)  # a bad declaration fails here, at its line

    def register(decide: Callable[..., Any]) -> Callable[..., Any]:
        _REGISTERED[name] = dict(declaration, func=decide)
        return decide

    return register


def algorithms() -> pd.DataFrame:
    """Every algorithm a config may name: the built-ins (``source`` ``"built-in"``) and
    the Python algorithms registered so far (``"python"``), one row each, with their
    ``sensing``, default ``stop`` criterion, ``goal`` and ``lights``."""
    rows = _native.algorithm_table(_declared())
    return pd.DataFrame(rows, columns=["name", "source", "sensing", "stop", "goal", "lights"])


def _declared() -> list[dict[str, Any]]:
    return list(_REGISTERED.values())


_Config = Union[str, "os.PathLike[str]", Mapping[str, Any]]
_Set = Optional[Union[Mapping[str, Any], Sequence[str], str]]


def _config(config: _Config) -> Any:
    return dict(config) if isinstance(config, Mapping) else config


def _frame(path: str) -> pd.DataFrame:
    return pd.read_csv(path, keep_default_na=True, true_values=["true"], false_values=["false"])


def run(
    config: _Config,
    set: _Set = None,
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    threads: Optional[int] = None,
    force: bool = False,
) -> pd.DataFrame:
    """Runs every cell x seed of ``config``, as ``monoculus run`` does.

    ``config`` is a path to a TOML file or a dict in its shape; ``set`` overrides dotted
    keys as ``--set`` does (a dict ``{"swarm.n": [10, 20]}``, a list value sweeping, or
    ``"KEY=VALUE"`` strings). Returns ``runs.csv`` as a DataFrame, row for row what the
    command line writes. With ``out``, the results folder is written there (and resumed
    the same way; ``force=True`` starts it over, as ``--force`` does, also when it holds
    another config's results); ``threads`` defaults to all cores. A bad config raises
    :class:`ConfigError`; runs whose algorithm failed raise :class:`AlgorithmError`
    (the other runs are written); Ctrl-C stops the sweep at the end of the running
    rounds, leaving a folder that resumes.
    """
    if out is not None:
        folder = os.fspath(out)
        _sweep(config, set, folder, threads, kept=True, force=force)
        return _frame(os.path.join(folder, "runs.csv"))
    with tempfile.TemporaryDirectory(prefix="monoculus-") as folder:
        _sweep(config, set, folder, threads, kept=False, force=False)
        return _frame(os.path.join(folder, "runs.csv"))


def _sweep(
    config: _Config, set: _Set, folder: str, threads: Optional[int], kept: bool, force: bool
) -> None:
    """Runs the sweep into ``folder``; an :class:`AlgorithmError` carries the failed runs
    as ``failures`` (read before a temporary folder is removed)."""
    try:
        _native.run(_config(config), set, folder, threads, _declared(), force)
    except AlgorithmError as e:
        path = os.path.join(folder, "failures.csv")
        e.failures = (
            pd.read_csv(path, dtype={"cell": str}, keep_default_na=False)
            if os.path.exists(path)
            else pd.DataFrame(columns=["cell", "seed", "algorithm", "robot", "round", "message"])
        )
        where = (
            f"recorded in {path}; the other runs are in {folder}"
            if kept
            else "listed in this exception's failures; give out= to keep the other runs"
        )
        e.args = (f"{e.args[0]} ({where})",) + e.args[1:]
        raise


def hunt(
    config: _Config,
    set: _Set = None,
    out: Optional[Union[str, "os.PathLike[str]"]] = None,
    threads: Optional[int] = None,
    cell: Optional[int] = None,
) -> HuntResult:
    """Searches for a counterexample to the config's ``[hunt]`` property, shrinks it and
    writes it, as ``monoculus hunt`` does.

    Returns ``summary.json`` as a dict (``property``, ``found``, ``shrunk``, ``score``,
    ``n``, ``round``, ``evaluations``, ``seconds``, ``seed``, ...) with two more keys:
    ``positions``, the counterexample's start as an ``(n, dim)`` array (``None`` if no
    run completed), and ``out``, the folder written (``None`` without ``out``: then a
    temporary folder is used and removed). The folder holds ``positions.csv``,
    ``schedule.csv`` (when the schedule matters), ``durations.csv`` (when ASYNC
    phase durations are given), ``reproduce.toml`` (replay it with
    :func:`run`), ``replay.html`` and ``summary.json``. Algorithms declared with
    :func:`algorithm` can be hunted. Ctrl-C stops the hunt, keeping its best candidate
    in ``out`` marked as not shrunk, and raises ``KeyboardInterrupt``.

    The result is a :class:`HuntResult`, a dict with the counterexample's replay as
    ``result.replay`` (a :class:`Replay` of ``reproduce.toml``, ``None`` if no run
    completed); in Jupyter it shows the summary and that replay.
    """
    import json

    def hunt_into(folder: str) -> HuntResult:
        text = _native.hunt(_config(config), set, folder, threads, _declared(), cell)
        summary: dict[str, Any] = json.loads(text)
        if summary["failures"]:
            import warnings

            warnings.warn(
                f"{summary['failures']} of the hunt's runs failed; the first: "
                f"{summary['first_failure']}",
                RuntimeWarning,
                stacklevel=3,
            )
        path = os.path.join(folder, "positions.csv")
        summary["positions"] = (
            np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
            if os.path.exists(path)
            else None
        )
        reproduce = os.path.join(folder, "reproduce.toml")
        shown = (
            Replay(_native.replay(reproduce, None, 0, None, _declared(), 20_000, 30))
            if os.path.exists(reproduce)
            else None
        )
        return HuntResult(summary, shown)

    if out is not None:
        folder = os.fspath(out)
        summary = hunt_into(folder)
        summary["out"] = folder
        return summary
    with tempfile.TemporaryDirectory(prefix="monoculus-hunt-") as folder:
        summary = hunt_into(folder)
        summary["out"] = None
        return summary


def replay(
    config: _Config,
    seed: int = 0,
    cell: int = 0,
    set: _Set = None,
    max_drawn: int = 20_000,
    max_mb: int = 30,
) -> Replay:
    """Records one run of ``config``'s cell ``cell`` with ``seed`` (as for
    :class:`Simulation`), as ``monoculus replay --cell CELL --seed SEED`` does: the same
    run as :func:`run` makes of that cell and seed.

    Returns a :class:`Replay`: in Jupyter it shows the replay page inline (play, step,
    zoom, click a robot for its Look; lights in their colours); ``.save("run.html")``
    writes the page, ``.gif("run.gif")`` the animation. ``config`` and ``set`` as for
    :func:`run`; ``max_drawn`` and ``max_mb`` as ``--max-drawn`` and ``--max-mb``.
    """
    return Replay(
        _native.replay(_config(config), seed, cell, set, _declared(), max_drawn, max_mb)
    )


def _value(text: str) -> Any:
    if text == "":
        return None
    if text in ("true", "false"):
        return text == "true"
    for kind in (int, float):
        try:
            return kind(text)
        except ValueError:
            pass
    return text


class Simulation:
    """One run of a config's cell and seed, stepped from Python.

    ``Simulation(config, seed=0, cell=0, set=None, positions=None)``: ``config`` and
    ``set`` as for :func:`run`; ``positions`` an ``(n, dim)`` array of start positions
    in place of the config's initial shape.
    """

    def __init__(
        self,
        config: _Config,
        seed: int = 0,
        cell: int = 0,
        set: _Set = None,
        positions: Optional[np.ndarray] = None,
    ) -> None:
        if positions is not None:
            positions = np.ascontiguousarray(positions, dtype=np.float64)
        self._sim = _native.Simulation(
            _config(config), seed, cell, set, positions, _declared()
        )

    def step(self) -> None:
        """Advances one round (ASYNC: one epoch)."""
        self._sim.step()

    def run(self, max_rounds: Optional[int] = None) -> dict[str, Any]:
        """Runs to the stop criterion (or ``max_rounds`` rounds in all); the outcome as a
        dict of ``runs.csv``'s fields."""
        row = self._sim.run(max_rounds)
        return {k: _value(v) for k, v in row.items()}

    @property
    def positions(self) -> np.ndarray:
        """Every robot's position, an ``(n, dim)`` array (a copy)."""
        return self._sim.positions

    @property
    def lights(self) -> np.ndarray:
        """The colour each robot shows now, by robot: indices into :attr:`light_names`
        (an empty array when the algorithm has no lights; ASYNC: the colour the others
        see, set by a Compute that has ended). ``np.array(sim.light_names)[sim.lights]``
        names them."""
        return self._sim.lights

    @property
    def light_names(self) -> list[str]:
        """The names of the algorithm's lights (empty: it has none)."""
        return self._sim.light_names

    @property
    def round(self) -> int:
        """Rounds completed (ASYNC: epochs)."""
        return self._sim.round

    @property
    def converged(self) -> bool:
        """Whether a run ending now would have converged: its stop criterion holds, and
        its goal (:attr:`goal`) holds."""
        return self._sim.converged

    @property
    def stuck(self) -> bool:
        """Whether the swarm is stuck now: no robot would move, and the goal does not
        hold (a run would end here, not converged)."""
        return self._sim.stuck

    @property
    def stopped_by(self) -> Optional[str]:
        """What would end a run now: ``"quiescent"``, ``"diameter"`` or ``"box"``, or
        ``None`` while the run would go on."""
        return self._sim.stopped_by

    @property
    def goal(self) -> str:
        """The goal the run is judged by: ``"diameter"``, ``"disc"`` or ``"box"``."""
        return self._sim.goal

    @property
    def goal_met(self) -> bool:
        """Whether the goal holds now."""
        return self._sim.goal_met

    @property
    def radius(self) -> float:
        """The radius of the smallest disc (ball in 3D) holding the robots now."""
        return self._sim.radius

    @property
    def diameter(self) -> float:
        """The swarm's diameter now."""
        return self._sim.diameter

    @property
    def hull_area(self) -> float:
        """The area (3D: volume) of the swarm's convex hull now."""
        return self._sim.hull_area

    def replay(self, max_drawn: int = 20_000, max_mb: int = 30) -> Replay:
        """The replay of this simulation so far, as :func:`replay` gives for a run: a
        frame at its start (its own ``positions`` if it was given them) and after
        every round (ASYNC: every event tick) it was stepped or run. The run is recorded
        again from its start through the same calls (the same run, bit for bit), so it
        costs about what stepping it did."""
        return Replay(self._sim.replay(max_drawn, max_mb))

    def look(self, robot: int) -> pd.DataFrame:
        """What ``robot`` sees now, as ``monoculus look`` prints it: one row per visible
        point (``index``, ``far`` or ``side_*``, the direction ``dx, dy[, dz]``)."""
        return pd.read_csv(io.StringIO(self._sim.look(robot)), true_values=["true"], false_values=["false"])
