"""Algorithms written in Python: exact against the built-ins, each model's queries and
only those, memory, parameters, vectorized decisions, and failures that name the
robot and the round."""

import pathlib
import sys

import numpy as np
import pandas as pd
import pytest

import monoculus

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[2] / "examples" / "python"))
import converge_locality  # noqa: E402  (registers py_converge_locality)

DROP = ["algorithm", "cell", "wall_ms", "config_hash"]


def by_algorithm(runs, name):
    return runs[runs["algorithm"] == name].drop(columns=DROP).reset_index(drop=True)


def config(names, n=50, seeds=10, **extra):
    c = {
        "name": "py",
        "seeds": seeds,
        "swarm": {"n": n, "init": "square", "side": 20.0},
        "algorithm": {"name": names},
    }
    c.update(extra)
    return c


def test_the_python_converge_locality_is_the_built_in_one():
    runs = monoculus.run(config(["py_converge_locality", "converge_locality"]))
    pd.testing.assert_frame_equal(
        by_algorithm(runs, "py_converge_locality"), by_algorithm(runs, "converge_locality")
    )
    assert len(runs) == 20


@pytest.mark.parametrize("scheduler", [{"kind": "ssync", "p": 0.5}, {"kind": "async"}])
def test_and_under_other_schedulers_and_in_space(scheduler):
    c = config(["py_converge_locality", "converge_locality"], n=20, seeds=3, scheduler=scheduler)
    runs = monoculus.run(c)
    pd.testing.assert_frame_equal(
        by_algorithm(runs, "py_converge_locality"), by_algorithm(runs, "converge_locality")
    )
    c["swarm"]["dim"] = 3
    runs = monoculus.run(c)
    pd.testing.assert_frame_equal(
        by_algorithm(runs, "py_converge_locality"), by_algorithm(runs, "converge_locality")
    )


seen = {}


@monoculus.algorithm("py_inspect", sensing="directions")
def inspect_directions(obs, rng):
    seen["directions"] = (obs.directions.shape, obs.dim, hasattr(obs, "far"), hasattr(obs, "relative_positions"))
    return obs.random_visible(rng)


@monoculus.algorithm("py_inspect_ola", sensing="ola", stop="box")
def inspect_ola(obs, rng):
    sides = obs.sides_occupied()
    seen["ola"] = (len(sides), hasattr(obs, "random_far"), hasattr(obs, "relative_positions"))
    empty = [(k, "high" if low else "low") for k, (low, high) in enumerate(sides) if low != high]
    if not empty:
        return None
    return obs.random_in_orthant(empty, rng)


@monoculus.algorithm("py_inspect_positions", sensing="positions", stop="diameter")
def inspect_positions(obs, rng):
    rel = obs.relative_positions
    seen["positions"] = rel.shape
    if len(rel) == 0:
        return None
    g = rel.mean(axis=0)
    return g / np.linalg.norm(g)


def test_each_model_has_its_queries_and_no_other():
    monoculus.run(config(["py_inspect", "py_inspect_ola", "py_inspect_positions"], n=10, seeds=1, stop={"max_rounds": 3}))
    shape, dim, far, positions = seen["directions"]
    assert shape[1] == dim == 2 and not far and not positions
    assert seen["ola"] == (2, False, False)
    assert seen["positions"][1] == 2


@monoculus.algorithm("py_patient", sensing="ld", memory=1, params={"patience": 2}, stop="quiescent")
def patient(obs, rng, state):
    if state[0] >= obs.params["patience"]:
        return None
    far = obs.random_far(rng)
    if far is None:
        state[0] += 1
    else:
        state[0] = 0
    return far


def test_memory_and_params_sweep():
    runs = monoculus.run(config("py_patient", n=15, seeds=3), set={"algorithm.params.patience": [1, 3]})
    assert "algorithm.params.patience" in runs.columns
    assert sorted(runs["algorithm.params.patience"].unique()) == [1, 3]
    assert runs["converged"].all()
    with pytest.raises(monoculus.ConfigError, match="algorithm.params.patience_x: py_patient has no parameter"):
        monoculus.run(config("py_patient", n=15, seeds=1), set={"algorithm.params.patience_x": 2})


@monoculus.algorithm("py_sole", sensing="ld")
def sole(obs, rng):
    return obs.sole_visible()


@monoculus.algorithm("py_sole_vectorized", sensing="ld", vectorized=True)
def sole_vectorized(batch):
    counts = np.diff(batch.offsets)
    stay = counts != 1
    directions = np.zeros((batch.count, batch.dim))
    one = np.nonzero(~stay)[0]
    directions[one] = batch.directions[batch.offsets[one]]
    return directions, stay


def test_a_vectorized_algorithm_gives_the_runs_of_the_same_rule_one_by_one():
    for scheduler in [{"kind": "fsync"}, {"kind": "async"}]:
        c = config(["py_sole", "py_sole_vectorized"], n=12, seeds=4, scheduler=scheduler, stop={"max_rounds": 40})
        c["swarm"]["init"] = "line"
        runs = monoculus.run(c)
        pd.testing.assert_frame_equal(by_algorithm(runs, "py_sole"), by_algorithm(runs, "py_sole_vectorized"))
        assert runs["moves"].sum() > 0


@monoculus.algorithm("py_raises", sensing="ld")
def raises(obs, rng):
    if rng.uniform() < 0.05:
        raise ZeroDivisionError("a bad day")
    return obs.random_far(rng)


@monoculus.algorithm("py_too_long", sensing="ld")
def too_long(obs, rng):
    d = obs.random_visible(rng)
    return None if d is None else 2 * d


def test_an_exception_surfaces_with_its_traceback_robot_and_round(tmp_path):
    with pytest.raises(monoculus.AlgorithmError) as e:
        monoculus.run(config("py_raises", n=20, seeds=6), out=tmp_path)
    message = str(e.value)
    assert "py_raises: panicked: ZeroDivisionError: a bad day (robot " in message and ", round " in message
    assert isinstance(e.value.__cause__, ZeroDivisionError)
    assert e.value.__cause__.__traceback__ is not None
    failures = (tmp_path / "failures.csv").read_text().splitlines()
    assert f"recorded in {tmp_path / 'failures.csv'}" in message
    assert len(e.value.failures) == len(failures) - 1
    runs = pd.read_csv(tmp_path / "runs.csv")
    assert len(failures) - 1 + len(runs) == 6 and len(failures) > 1
    with pytest.raises(monoculus.AlgorithmError, match="py_too_long: decided a step along") as e:
        monoculus.run(config("py_too_long", n=5, seeds=1))
    # Without out=, the failures are on the exception (the temporary folder is gone).
    assert "listed in this exception's failures" in str(e.value)
    failures = e.value.failures
    assert list(failures.columns) == ["cell", "seed", "algorithm", "robot", "round", "message"]
    assert len(failures) == 1 and failures["algorithm"][0] == "py_too_long"
    assert failures["message"][0].startswith("py_too_long: decided a step along")


def test_a_parameter_is_typed_by_its_default():
    with pytest.raises(monoculus.ConfigError) as e:
        monoculus.run(config("py_patient", n=5, seeds=1), set={"algorithm.params.patience": "x"})
    assert e.value.key == "algorithm.params.patience"
    assert "is not an integer, as its default 2 is" in str(e.value)
    # An integer where the default is a float is that float.
    monoculus.run(config("py_typed", n=5, seeds=1, stop={"max_rounds": 2}), set={"algorithm.params.weight": 2})
    assert seen["weight"] == 2.0 and isinstance(seen["weight"], float)
    with pytest.raises(monoculus.ConfigError, match="algorithm.params.weight: `true` is not a number"):
        monoculus.run(config("py_typed", n=5, seeds=1), set={"algorithm.params.weight": True})


@monoculus.algorithm("py_typed", sensing="ld", params={"weight": 0.5})
def typed(obs, rng):
    seen["weight"] = obs.params["weight"]
    return None


def test_an_observation_kept_past_its_activation_refuses_to_answer():
    kept = []

    @monoculus.algorithm("py_keeper", sensing="ld")
    def keeper(obs, rng):
        kept.append((obs, rng))
        return None

    monoculus.run(config("py_keeper", n=3, seeds=1, stop={"max_rounds": 1}))
    obs, rng = kept[0]
    with pytest.raises(RuntimeError, match="use it only inside decide"):
        obs.sole_visible()
    with pytest.raises(RuntimeError, match="use it only inside decide"):
        rng.uniform()


def test_a_built_in_name_is_refused_at_the_decorator_and_every_algorithm_is_listed():
    with pytest.raises(ValueError, match='"median" is the name of a built-in algorithm'):
        monoculus.algorithm("median", sensing="ld")
    with pytest.raises(ValueError, match="lower-case letters, digits and _"):
        monoculus.algorithm("My Rule", sensing="ld")
    table = monoculus.algorithms()
    assert list(table.columns) == ["name", "source", "sensing", "stop", "goal", "lights"]
    builtin = table[table["source"] == "built-in"]
    assert builtin["name"].tolist()[:2] == ["converge_locality", "converge_quadrant"] and len(builtin) == 6
    row = table.set_index("name").loc["converge_locality"]
    assert (row["sensing"], row["stop"], row["goal"]) == ("ld", "quiescent_or_diameter", "disc")
    assert table.set_index("name").loc["py_patient", "source"] == "python"


def test_force_starts_a_folder_over(tmp_path):
    c = config("py_sole", n=6, seeds=2, stop={"max_rounds": 5})
    monoculus.run(c, out=tmp_path)
    c["seeds"] = 3
    with pytest.raises(monoculus.ConfigError, match="force=True"):
        monoculus.run(c, out=tmp_path)
    assert len(monoculus.run(c, out=tmp_path, force=True)) == 3


def test_declarations_are_checked():
    with pytest.raises(ValueError, match="sensing"):
        monoculus.algorithm("x", sensing="sonar")
    with pytest.raises(ValueError, match="memory"):
        monoculus.algorithm("x", memory=0)(lambda obs, rng, s: None)
    with pytest.raises(ValueError, match="stop"):
        monoculus.algorithm("x", stop="never")(lambda obs, rng: None)


@monoculus.algorithm("py_first_seen", sensing="ld", stop="quiescent")
def first_seen(obs, rng):
    d = obs.directions
    return d[0] if len(d) else None


@monoculus.algorithm("py_first_seen_strided", sensing="ld", stop="quiescent")
def first_seen_strided(obs, rng):
    d = np.asfortranarray(obs.directions)  # its rows are not contiguous
    return d[0] if len(d) else None


@monoculus.algorithm("py_first_seen_vectorized", sensing="ld", stop="quiescent", vectorized=True)
def first_seen_vectorized(batch):
    counts = np.diff(batch.offsets)
    stay = counts == 0
    directions = np.zeros((batch.count, batch.dim))
    directions[~stay] = batch.directions[batch.offsets[:-1][~stay]]
    return np.asfortranarray(directions), np.asfortranarray(stay)


def test_arrays_of_any_strides_are_read():
    c = config(["py_first_seen", "py_first_seen_strided", "py_first_seen_vectorized"], n=12, seeds=3, stop={"max_rounds": 20})
    runs = monoculus.run(c)
    for other in ["py_first_seen_strided", "py_first_seen_vectorized"]:
        pd.testing.assert_frame_equal(by_algorithm(runs, "py_first_seen"), by_algorithm(runs, other))
