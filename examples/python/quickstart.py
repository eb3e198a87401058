"""Quickstart: a sweep into a DataFrame, then a figure of rho against n.

ConvergeLocality against ConvergeQuadrant on the paper's setting (FSYNC, b = 1, c = 2,
robots uniform in a square of side 20), n = 10 to 200, 20 seeds each; the figure
(the median of rho and its interquartile range against n) goes to quickstart.png.

    pip install ./python matplotlib
    python examples/python/quickstart.py
"""

import matplotlib

matplotlib.use("Agg")  # no display needed
import matplotlib.pyplot as plt

import monoculus

config = {
    "name": "quickstart",
    "seeds": 20,
    "swarm": {"n": [10, 20, 50, 100, 200], "init": "square", "side": 20.0},
    "algorithm": {"name": ["converge_locality", "converge_quadrant"]},
}

runs = monoculus.run(config)
print(runs.groupby(["algorithm", "n"])[["rho", "tau", "rounds"]].median())

fig, ax = plt.subplots(figsize=(6, 4))
for name, group in runs.groupby("algorithm"):
    stats = group.groupby("n")["rho"].quantile([0.25, 0.5, 0.75]).unstack()
    ax.plot(stats.index, stats[0.5], marker="o", label=name)
    ax.fill_between(stats.index, stats[0.25], stats[0.75], alpha=0.2)
ax.set_xscale("log")
ax.set_xlabel("n (robots)")
ax.set_ylabel("rho (work against the optimum)")
ax.legend()
fig.tight_layout()
fig.savefig("quickstart.png", dpi=100)
print("wrote quickstart.png")
