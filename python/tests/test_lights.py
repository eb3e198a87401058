"""Lights from Python: algorithms declare them, see them, set them through their state;
a Python transcription of examples/wait-for-movers gives the Rust example's runs; a
Simulation shows each robot's light."""

import os
import pathlib
import subprocess
import sys

import numpy as np
import pandas as pd
import pytest

import monoculus

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "examples" / "python"))
import wait_for_movers  # noqa: E402  (registers py_wait_for_movers)

DROP = ["algorithm", "cell", "wall_ms", "config_hash"]


@pytest.fixture(scope="session")
def rust_wait_for_movers():
    """The Rust example's binary (built by `cargo test` before pytest runs in CI;
    MONOCULUS_WAIT_FOR_MOVERS_BIN names another)."""
    default = ROOT / "target" / "debug" / "wait-for-movers"
    path = os.environ.get("MONOCULUS_WAIT_FOR_MOVERS_BIN", str(default))
    if not os.path.exists(path):
        subprocess.run(["cargo", "build", "-p", "wait-for-movers"], cwd=ROOT, check=True)
    return path


def config(name, scheduler, n=10, seeds=4):
    return {
        "name": "lights",
        "seeds": seeds,
        "swarm": {"n": n, "init": "square", "side": 12.0},
        "algorithm": {"name": name},
        "scheduler": scheduler,
        "stop": {"max_rounds": 200},
    }


def toml(c):
    lines = [f'name = "{c["name"]}"', f'seeds = {c["seeds"]}']
    for table in ["swarm", "algorithm", "scheduler", "stop"]:
        lines.append(f"[{table}]")
        for k, v in c[table].items():
            lines.append(f'{k} = "{v}"' if isinstance(v, str) else f"{k} = {v}")
    return "\n".join(lines) + "\n"


@pytest.mark.parametrize("scheduler", [{"kind": "fsync"}, {"kind": "ssync", "p": 0.5}, {"kind": "async"}])
def test_the_python_wait_for_movers_is_the_rust_one_run_for_run(rust_wait_for_movers, tmp_path, scheduler):
    path = tmp_path / "c.toml"
    path.write_text(toml(config("wait_for_movers", scheduler)))
    subprocess.run(
        [rust_wait_for_movers, "run", str(path), "--out", str(tmp_path / "rust")],
        check=True,
        capture_output=True,
    )
    rust = pd.read_csv(tmp_path / "rust" / "runs.csv", true_values=["true"], false_values=["false"])
    python = monoculus.run(config("py_wait_for_movers", scheduler))
    pd.testing.assert_frame_equal(
        python.drop(columns=DROP).reset_index(drop=True),
        rust.drop(columns=DROP).reset_index(drop=True),
    )
    assert python["moves"].sum() > 0
    assert (python["goal"] == "disc").all()


def test_a_simulation_shows_each_robots_light():
    start = np.array([[0.0, 0.0], [10.0, 0.0], [0.0, 10.0]])
    sim = monoculus.Simulation(config("py_wait_for_movers", {"kind": "fsync"}), positions=start)
    assert sim.light_names == ["resting", "moving"]
    assert sim.lights.tolist() == [0, 0, 0]
    for round in range(1, 5):
        sim.step()
        # Each sees the others far: all move in rounds 1, 3, ...; all rest in 2, 4, ...
        want = 1 if round % 2 else 0
        assert sim.lights.tolist() == [want] * 3, round
    assert [sim.light_names[k] for k in sim.lights] == ["resting"] * 3
    plain = monoculus.Simulation(config("converge_locality", {"kind": "fsync"}), positions=start)
    assert plain.light_names == [] and plain.lights.shape == (0,)


seen = {}


@monoculus.algorithm("py_lit_queries", sensing="directions", lights=["off", "on", "blink"], memory=1)
def lit_queries(obs, rng, state):
    pairs = obs.lit()
    seen["lit"] = [name for _, name in pairs]
    seen["colours"] = obs.colours.tolist()
    seen["lights"] = obs.lights
    seen["sees_on"] = (obs.sees_light("on"), obs.sees_light(1))
    seen["repr"] = repr(state)
    state.memory[0] += 1
    state.light = 1 if state.memory[0] >= 1 else 0
    toward = obs.random_lit("on", rng)
    seen["toward_on"] = toward is not None
    return None


def test_the_queries_see_the_colours_of_the_last_round():
    start = np.array([[0.0, 0.0], [4.0, 0.0], [0.0, 4.0]])
    sim = monoculus.Simulation(config("py_lit_queries", {"kind": "fsync"}), positions=start)
    sim.step()
    assert seen["lit"] == ["off", "off"] and seen["colours"] == [0, 0]
    assert seen["sees_on"] == (False, False) and not seen["toward_on"]
    assert seen["lights"] == ["off", "on", "blink"]
    assert seen["repr"].startswith("State(light='off', memory=")
    sim.step()
    # Every robot turned on in round 1: round 2 sees it.
    assert seen["lit"] == ["on", "on"] and seen["colours"] == [1, 1]
    assert seen["sees_on"] == (True, True) and seen["toward_on"]
    assert sim.lights.tolist() == [1, 1, 1]


@monoculus.algorithm("py_wait_vectorized", sensing="ld", lights=["resting", "moving"], goal="disc", vectorized=True)
def wait_vectorized(batch):
    dirs = np.zeros((batch.count, batch.dim))
    stay = np.ones(batch.count, dtype=bool)
    for i in range(batch.count):
        lo, hi = batch.offsets[i], batch.offsets[i + 1]
        if (batch.colours[lo:hi] == 1).any():
            batch.light[i] = 0
            continue
        if hi - lo == 1:
            dirs[i], stay[i] = batch.directions[lo], False
        batch.light[i] = 0 if stay[i] else 1
    return dirs, stay


@monoculus.algorithm("py_wait_sole", sensing="ld", lights=["resting", "moving"], goal="disc")
def wait_sole(obs, rng, state):
    if obs.sees_light("moving"):
        state.light = "resting"
        return None
    toward = obs.sole_visible()
    state.light = "resting" if toward is None else "moving"
    return toward


def test_a_vectorized_algorithm_with_lights_gives_the_runs_of_the_same_rule():
    for scheduler in [{"kind": "fsync"}, {"kind": "async"}]:
        c = config(["py_wait_sole", "py_wait_vectorized"], scheduler, n=8, seeds=3)
        c["swarm"]["init"] = "line"
        runs = monoculus.run(c)
        one = runs[runs["algorithm"] == "py_wait_sole"].drop(columns=DROP).reset_index(drop=True)
        two = runs[runs["algorithm"] == "py_wait_vectorized"].drop(columns=DROP).reset_index(drop=True)
        pd.testing.assert_frame_equal(one, two)
        assert runs["moves"].sum() > 0


def test_bad_lights_are_refused_where_they_are_made():
    with pytest.raises(ValueError, match="each colour needs a name of its own"):
        monoculus.algorithm("x", lights=["a", "a"])
    with pytest.raises(ValueError, match="at most 256"):
        monoculus.algorithm("x", lights=[str(k) for k in range(257)])

    @monoculus.algorithm("py_bad_light", sensing="ld", lights=["off", "on"])
    def bad(obs, rng, state):
        state.light = "purple"

    with pytest.raises(monoculus.AlgorithmError, match="light \"purple\": its lights are off, on"):
        monoculus.run(config("py_bad_light", {"kind": "fsync"}, n=3, seeds=1))
