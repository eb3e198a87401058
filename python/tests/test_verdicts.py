"""Verdicts from Python: the DataFrame says converged, stuck and stopped_by as runs.csv
does; a Simulation says whether a run ending now would converge or be stuck; an
algorithm's declared stop criterion and goal are the ones its runs use."""

import numpy as np
import pandas as pd

import monoculus


@monoculus.algorithm("py_tired", sensing="ld", memory=1, lights=["fresh", "tired"])
def tired(obs, rng, state):
    """Moves as ConvergeLocality, and stops for good after three moves."""
    if state.memory[0] >= 3:
        return None
    toward = obs.sole_visible()
    if toward is None:
        toward = obs.random_far(rng)
    if toward is not None:
        state.memory[0] += 1
        state.light = "tired" if state.memory[0] >= 3 else "fresh"
    return toward


def square(name, seeds=20, **extra):
    c = {"name": "v", "seeds": seeds, "swarm": {"n": 20, "init": "square", "side": 20.0}, "algorithm": {"name": name}}
    c.update(extra)
    return c


def test_a_rule_that_stops_far_apart_is_stuck_not_converged():
    runs = monoculus.run(square("py_tired"))
    assert not runs["converged"].any()
    assert runs["stuck"].all() and runs["stuck"].dtype == bool
    assert (runs["stopped_by"] == "quiescent").all() and (runs["goal"] == "diameter").all()
    assert (runs["final_diameter"] > 2).all()


def test_the_dataframe_counts_stuck_runs_of_limited_vision(root):
    runs = monoculus.run(root / "configs" / "extensions" / "stuck_clusters.toml")
    assert runs["stuck"].sum() == 9 and runs["converged"].sum() == 1
    assert set(runs["stopped_by"]) == {"quiescent", "diameter"}
    assert (runs.loc[runs["stuck"], "final_radius"] > 2).all()


def test_a_simulation_says_stuck_and_what_would_stop_it(root):
    sim = monoculus.Simulation(root / "configs" / "extensions" / "stuck_clusters.toml", seed=0)
    assert sim.goal == "disc" and sim.stopped_by is None and not sim.stuck
    out = sim.run()
    assert out["stuck"] is True and out["converged"] is False and out["stopped_by"] == "quiescent"
    assert sim.stuck and not sim.converged and sim.stopped_by == "quiescent"
    assert not sim.goal_met and sim.radius > 2
    # Seed 8's clusters merge: converged, stopped by the diameter.
    sim = monoculus.Simulation(root / "configs" / "extensions" / "stuck_clusters.toml", seed=8)
    out = sim.run()
    assert out["converged"] is True and sim.converged and not sim.stuck
    assert sim.stopped_by == "diameter" and sim.goal_met


def test_the_lattice_converges_by_converge_localitys_goal_and_not_by_the_diameter():
    lattice = np.array([[(k % 3) * 0.8, (k // 3) * 0.8] for k in range(9)])
    c = square("converge_locality", seeds=1)
    sim = monoculus.Simulation(c, positions=lattice)
    assert sim.converged and sim.stopped_by == "quiescent" and sim.diameter > 2
    assert abs(sim.radius - 0.8 * 2**0.5) < 1e-12
    by_diameter = monoculus.Simulation(c, positions=lattice, set={"stop.goal": "diameter"})
    assert by_diameter.stuck and not by_diameter.converged


@monoculus.algorithm("py_declares_box", sensing="ola", stop="box", goal="box")
def declares_box(obs, rng):
    sides = obs.sides_occupied()
    empty = [(k, "high" if low else "low") for k, (low, high) in enumerate(sides) if low != high]
    return obs.random_in_orthant(empty, rng) if empty else None


def test_a_python_algorithm_runs_under_the_stop_and_goal_it_declares():
    runs = monoculus.run(square("py_declares_box", seeds=3, stop={"max_rounds": 500}))
    assert (runs["stop_criterion"] == "box").all()
    assert (runs["goal"] == "box").all()
    assert (runs["stopped_by"].isin(["box", "max_rounds"])).all()
    # Without a declaration: quiescent_or_diameter and diameter.
    plain = monoculus.run(square("py_tired", seeds=1))
    assert plain["stop_criterion"].tolist() == ["quiescent_or_diameter"]


def test_summary_counts_stuck_runs(tmp_path):
    monoculus.run(square("py_tired", seeds=5), out=tmp_path)
    summary = pd.read_csv(tmp_path / "summary.csv")
    assert summary["stuck"].tolist() == [5] and summary["converged"].tolist() == [0]
