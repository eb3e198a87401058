"""``monoculus.plot``: the figures of ``monoculus plot``, drawn with matplotlib."""

from __future__ import annotations

import os
from typing import Any, Optional, Sequence, Union

import numpy as np
import pandas as pd

# The command line's palette (monoculus-plot), in the order algorithms first appear.
PALETTE = ["#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#8c564b"]

_Runs = Union[pd.DataFrame, str, "os.PathLike[str]"]


def _matplotlib() -> Any:
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:  # pragma: no cover - exercised without matplotlib
        raise ImportError(
            "monoculus.plot draws with matplotlib, which is not installed: "
            "pip install 'monoculus[plot]' (or pip install matplotlib)"
        ) from e
    return plt


def _runs(runs: _Runs) -> pd.DataFrame:
    if isinstance(runs, pd.DataFrame):
        return runs
    path = os.fspath(runs)
    if os.path.isdir(path):
        path = os.path.join(path, "runs.csv")
    if not os.path.exists(path):
        raise FileNotFoundError(f"{path}: no runs.csv; run an experiment into it first")
    return pd.read_csv(path, true_values=["true"], false_values=["false"])


def swept(runs: pd.DataFrame) -> list[str]:
    """The swept parameters of ``runs``: the columns between ``cell`` and ``seed``
    (``algorithm`` aside) whose values differ, as ``monoculus plot`` finds them."""
    cols = list(runs.columns)
    for needed in ("cell", "seed", "algorithm"):
        if needed not in cols:
            raise ValueError(f"runs: no `{needed}` column (is this runs.csv?)")
    inner = cols[cols.index("cell") + 1 : cols.index("seed")]
    return [c for c in inner if c != "algorithm" and runs[c].nunique(dropna=False) > 1]


def _ordered(values: Sequence[Any]) -> list[Any]:
    """Distinct values: numerically if all are numbers, else in order of appearance."""
    seen: list[Any] = []
    for v in values:
        if v not in seen:
            seen.append(v)
    try:
        return sorted(seen, key=float)
    except (TypeError, ValueError):
        return seen


def box_stats(values: Sequence[float]) -> Optional[dict[str, Any]]:
    """The box ``monoculus plot`` draws of ``values`` (finite ones): quartiles as
    numpy's default (linear) interpolation, as ``summary.csv``; whiskers to the most
    extreme values within 1.5 interquartile ranges of the box; the rest as fliers.
    ``None`` without a finite value."""
    v = np.asarray([x for x in values if np.isfinite(x)], dtype=float)
    if v.size == 0:
        return None
    q1, med, q3 = (float(np.percentile(v, q)) for q in (25, 50, 75))
    lo_fence, hi_fence = q1 - 1.5 * (q3 - q1), q3 + 1.5 * (q3 - q1)
    inside = v[(v >= lo_fence) & (v <= hi_fence)]
    return {
        "q1": q1,
        "med": med,
        "q3": q3,
        "whislo": min(q1, float(inside.min())),
        "whishi": max(q3, float(inside.max())),
        "fliers": v[(v < lo_fence) | (v > hi_fence)],
    }


def plot(
    runs: _Runs,
    x: Optional[str] = None,
    y: str = "rho",
    *,
    figure: Optional[str] = None,
    algorithm: Optional[str] = None,
    ax: Any = None,
) -> Any:
    """Draws a figure of ``monoculus plot`` from ``runs`` (a DataFrame of ``runs.csv``'s
    rows, as :func:`monoculus.run` returns, or a results folder) as a matplotlib
    :class:`~matplotlib.figure.Figure` a user can restyle.

    ``y`` (``"rho"``, ``"tau"``, or any numeric column) over the categories of the
    swept parameter ``x`` (default: the first swept one), a Tukey box per algorithm and
    category over the converged runs, in the command line's colours. ``figure`` names a
    figure as ``monoculus plot`` names its files: ``"rho_vs_n"`` (the paper's Figures 3
    to 10 are ``rho_vs_n``, ``tau_vs_n``, ``rho_vs_side`` and ``tau_vs_side``), with
    ``"__converge_locality"`` for one algorithm's. ``algorithm`` keeps one algorithm.
    When other parameters are swept too, each of their combinations gets a panel
    (titled as the command line's file of that group). With ``ax``, draws into it (one
    panel only). Needs matplotlib: ``pip install 'monoculus[plot]'``.
    """
    plt = _matplotlib()
    frame = _runs(runs)
    if figure is not None:
        stem, _, only = figure.partition("__")
        if "_vs_" not in stem:
            raise ValueError(
                f"figure {figure!r}: a name as `monoculus plot` writes, METRIC_vs_PARAMETER"
                " (e.g. rho_vs_n), optionally __ALGORITHM"
            )
        y, x = stem.split("_vs_", 1)
        algorithm = only or algorithm
    params = swept(frame)
    if y not in frame.columns:
        raise ValueError(f"y = {y!r}: runs have no such column")
    if x is not None and x != "all runs" and x not in frame.columns:
        raise ValueError(f"x = {x!r}: runs have no such column; swept here: {params}")
    if x is None:
        x = params[0] if params else None
    if x == "all runs":
        x = None
    algorithms = _ordered(list(frame["algorithm"]))
    if algorithm is not None:
        if algorithm not in algorithms:
            raise ValueError(f"algorithm {algorithm!r}: not in these runs ({algorithms})")
        series = [algorithm]
    else:
        series = algorithms
    others = [c for c in params if c != x]
    groups = (
        [((), frame)]
        if not others
        else [(k if isinstance(k, tuple) else (k,), g) for k, g in frame.groupby(others, sort=False)]
    )
    if ax is not None and len(groups) > 1:
        raise ValueError(
            f"ax: one panel, but {others} are swept too; choose with runs[runs[...] == ...]"
        )
    name = str(frame["name"].iloc[0]) if "name" in frame.columns and len(frame) else ""
    if ax is not None:
        fig, axes = ax.figure, [ax]
    else:
        cols = min(len(groups), 2)
        rows = -(-len(groups) // cols)
        fig, grid = plt.subplots(rows, cols, figsize=(9 * cols, 5.6 * rows), squeeze=False)
        axes = list(grid.flat)
        for extra in axes[len(groups) :]:
            extra.remove()
    for panel, (key, rows_) in zip(axes, groups):
        _panel(panel, rows_, x, y, series, name, dict(zip(others, key)), algorithm)
    fig.tight_layout()
    return fig


def _panel(
    ax: Any,
    rows: pd.DataFrame,
    x: Optional[str],
    y: str,
    series: list[str],
    name: str,
    group: dict[str, Any],
    algorithm: Optional[str],
) -> None:
    categories = _ordered(list(rows[x])) if x is not None else [""]
    converged = rows[rows["converged"].astype(bool)] if "converged" in rows else rows
    m = len(series)
    width = 0.8 / m
    for s, algo in enumerate(series):
        stats, where = [], []
        for c, cat in enumerate(categories):
            mine = converged[converged["algorithm"] == algo]
            if x is not None:
                mine = mine[mine[x] == cat]
            b = box_stats(mine[y].astype(float).tolist())
            if b is not None:
                stats.append(b)
                where.append(c + (s - (m - 1) / 2) * width)
        colour = PALETTE[s % len(PALETTE)]
        if stats:
            ax.bxp(
                stats,
                positions=where,
                widths=width * 0.85,
                boxprops={"color": colour, "linewidth": 2},
                whiskerprops={"color": colour, "linewidth": 2},
                capprops={"color": colour, "linewidth": 2},
                medianprops={"color": colour, "linewidth": 2},
                flierprops={"markeredgecolor": colour, "marker": "o", "markersize": 4},
            )
        ax.plot([], [], "s", color=colour, label=algo)
    ax.set_xticks(range(len(categories)))
    ax.set_xticklabels([str(c) for c in categories])
    ax.set_xlim(-0.6, len(categories) - 0.4)
    ax.set_xlabel(x if x is not None else "all runs")
    ax.set_ylabel(y)
    where_ = ", ".join(f"{k}={v}" for k, v in group.items())
    title = f"{name}: {y}" + (f" ({where_})" if where_ else "")
    ax.set_title(title + (f", {algorithm}" if algorithm else ""))
    ax.legend(loc="upper left")
    ax.grid(axis="y", color="#eeeeee")
