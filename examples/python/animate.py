"""Steps a Simulation round by round and animates it: 60 robots running ConvergeLocality
from a square of side 15, each frame one round, written to animate.gif.

    python examples/python/animate.py
"""

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.animation import FuncAnimation, PillowWriter

import monoculus

sim = monoculus.Simulation(
    {
        "name": "animate",
        "swarm": {"n": 60, "init": "square", "side": 15.0},
        "algorithm": {"name": "converge_locality"},
    },
    seed=3,
)

frames = [sim.positions]
while not sim.converged and sim.round < 200:
    sim.step()
    frames.append(sim.positions)
print(f"{sim.round} rounds, final diameter {sim.diameter:.3f}")

fig, ax = plt.subplots(figsize=(4, 4))
lo, hi = frames[0].min() - 1, frames[0].max() + 1
ax.set_xlim(lo, hi)
ax.set_ylim(lo, hi)
ax.set_aspect("equal")
dots = ax.scatter(frames[0][:, 0], frames[0][:, 1], s=12)
title = ax.set_title("round 0")


def draw(k):
    dots.set_offsets(frames[k])
    title.set_text(f"round {k}")
    return dots, title


FuncAnimation(fig, draw, frames=len(frames)).save("animate.gif", writer=PillowWriter(fps=5))
print("wrote animate.gif")
