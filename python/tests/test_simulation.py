"""monoculus.Simulation: stepping, running, positions, and looks."""

import numpy as np
import pytest

import monoculus


def cfg(**extra):
    c = {"name": "sim", "swarm": {"n": 30, "init": "square", "side": 10.0}, "algorithm": {"name": "converge_locality"}}
    c.update(extra)
    return c


def test_steps_then_runs_to_the_outcome_of_a_plain_run():
    plain = monoculus.Simulation(cfg(), seed=2).run()
    sim = monoculus.Simulation(cfg(), seed=2)
    start = sim.positions
    assert start.shape == (30, 2) and start.dtype == np.float64
    sim.step()
    sim.step()
    assert sim.round == 2 and not np.array_equal(sim.positions, start)
    stepped = sim.run()
    for key in ["rounds", "moves", "activations", "rho", "tau", "final_diameter", "converged"]:
        assert stepped[key] == plain[key], key
    assert sim.converged and sim.diameter <= 2.0 and sim.hull_area >= 0
    assert plain["n"] == 30 and plain["final_extent_z"] is None


def test_a_copy_of_the_positions_and_a_start_of_ones_own():
    start = np.array([[0.0, 0.0], [0.5, 0.0], [3.0, 0.0]])
    sim = monoculus.Simulation(cfg(), positions=start)
    p = sim.positions
    p[0, 0] = 99.0
    assert sim.positions[0, 0] == 0.0
    look = sim.look(0)
    assert list(look.columns) == ["index", "far", "dx", "dy"]
    assert look["index"].tolist() == [1] and not look["far"][0]
    with pytest.raises(IndexError):
        sim.look(3)


def test_async_steps_are_epochs_and_space_works():
    sim = monoculus.Simulation(cfg(scheduler={"kind": "async"}), seed=1)
    sim.step()
    assert sim.round == 1
    space = monoculus.Simulation({"name": "s", "swarm": {"n": 20, "dim": 3, "init": "square", "side": 6.0}, "algorithm": {"name": "converge_quadrant"}})
    assert space.positions.shape == (20, 3)
    out = space.run()
    assert out["converged"] and out["dim"] == 3
    assert list(space.look(0).columns)[:4] == ["index", "side_x", "side_y", "side_z"]


def test_max_rounds_caps_a_run():
    out = monoculus.Simulation(cfg(), seed=0).run(max_rounds=2)
    assert out["rounds"] == 2 and not out["converged"]
