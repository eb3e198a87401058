"""monoculus.plot: the command line's box figures with matplotlib, checked against
summary.csv's quartiles; figures by name, one algorithm's, panels, and the message
without matplotlib."""

import sys

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pandas as pd
import pytest

import monoculus
from monoculus._plot import box_stats


@pytest.fixture(scope="module")
def vs_n(root, tmp_path_factory):
    out = tmp_path_factory.mktemp("vs_n")
    runs = monoculus.run(
        root / "configs" / "paper" / "vs_n.toml",
        set={"seeds": 6, "swarm.n": [10, 20, 50]},
        out=out,
    )
    return runs, pd.read_csv(out / "summary.csv"), out


def horizontal(ax):
    """Every y of the lines drawn: boxes (their quartiles), medians, whiskers, caps."""
    return np.concatenate([np.asarray(line.get_ydata(), dtype=float) for line in ax.lines])


def test_the_boxes_are_summary_csv_s_quartiles(vs_n):
    runs, summary, _ = vs_n
    for metric in ("rho", "tau"):
        fig = monoculus.plot(runs, x="n", y=metric)
        (ax,) = fig.axes
        drawn = horizontal(ax)
        for _, row in summary.iterrows():
            for q in ("median", "q1", "q3"):
                want = row[f"{metric}_{q}"]
                assert np.isclose(drawn, want, rtol=0, atol=1e-12).any(), (metric, q, want)
        assert ax.get_title() == f"paper-vs-n: {metric}"
        assert [t.get_text() for t in ax.get_xticklabels()] == ["10", "20", "50"]
        assert ax.get_xlabel() == "n" and ax.get_ylabel() == metric
        labels = [t.get_text() for t in ax.get_legend().get_texts()]
        assert labels == ["converge_locality", "converge_quadrant"]


def test_figures_by_name_and_one_algorithm(vs_n):
    runs, summary, out = vs_n
    fig = monoculus.plot(out, figure="tau_vs_n__converge_quadrant")
    (ax,) = fig.axes
    assert ax.get_title() == "paper-vs-n: tau, converge_quadrant"
    cq = summary[summary["algorithm"] == "converge_quadrant"]
    drawn = horizontal(ax)
    for m in cq["tau_median"]:
        assert np.isclose(drawn, m, rtol=0, atol=1e-12).any()
    cl = summary[summary["algorithm"] == "converge_locality"]["tau_median"]
    assert not any(np.isclose(drawn, m, rtol=0, atol=1e-12).any() for m in cl)
    with pytest.raises(ValueError, match="METRIC_vs_PARAMETER"):
        monoculus.plot(runs, figure="rho")
    with pytest.raises(ValueError, match="no such column"):
        monoculus.plot(runs, x="nope")


def test_a_second_swept_key_gives_panels():
    runs = monoculus.run({
        "name": "two-keys",
        "seeds": 3,
        "swarm": {"n": [8, 16], "init": "square", "side": [6.0, 10.0]},
        "algorithm": {"name": "converge_locality"},
    })
    fig = monoculus.plot(runs, x="n")
    titles = sorted(ax.get_title() for ax in fig.axes)
    # As the command line's files: the values as runs.csv writes them.
    assert titles == ["two-keys: rho (side=10)", "two-keys: rho (side=6)"]
    import matplotlib.pyplot as plt

    _, ax = plt.subplots()
    with pytest.raises(ValueError, match="one panel"):
        monoculus.plot(runs, x="n", ax=ax)
    one = runs[runs["side"] == 6]
    assert monoculus.plot(one, x="n", ax=ax).axes[0] is ax


def test_tukey_whiskers_stop_at_the_data():
    s = box_stats([1.0, 2.0, 2.5, 3.0, 3.5, 4.0, 20.0, float("nan")])
    assert s["q1"] == np.percentile([1, 2, 2.5, 3, 3.5, 4, 20], 25)
    assert s["whislo"] == 1.0 and s["whishi"] == 4.0
    assert list(s["fliers"]) == [20.0]
    assert box_stats([float("nan")]) is None


def test_without_matplotlib_the_message_says_how(monkeypatch, vs_n):
    monkeypatch.setitem(sys.modules, "matplotlib.pyplot", None)
    with pytest.raises(ImportError, match=r"pip install 'monoculus\[plot\]'"):
        monoculus.plot(vs_n[0])
