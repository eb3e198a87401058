"""monoculus.hunt: the command line's hunt from Python, a Python algorithm hunted, the
counterexample replayed by monoculus.run, bad hunts as ConfigError."""

import json
import subprocess

import numpy as np
import pytest

import monoculus


def test_the_same_as_the_command_line(root, cli, tmp_path):
    config = root / "configs" / "hunt" / "median.toml"
    found = monoculus.hunt(config, out=tmp_path / "py", threads=1)
    subprocess.run(
        [cli, "hunt", str(config), "--out", str(tmp_path / "cli"), "--quiet"],
        check=True,
        capture_output=True,
    )
    want = json.loads((tmp_path / "cli" / "summary.json").read_text())
    got = {k: v for k, v in found.items() if k not in ("positions", "out")}
    assert {k: v for k, v in got.items() if k != "seconds"} == {
        k: v for k, v in want.items() if k != "seconds"
    }
    assert found["found"] and found["shrunk"] and found["n"] <= 6
    assert found["positions"].shape == (found["n"], 2)
    assert (tmp_path / "py" / "replay.html").exists()
    runs = monoculus.run(tmp_path / "py" / "reproduce.toml")
    assert bool(runs["hull_grew"][0])


def test_an_async_counterexample_keeps_its_durations(root, tmp_path):
    config = root / "configs" / "hunt" / "stale_view.toml"
    found = monoculus.hunt(config, out=tmp_path / "h")
    assert found["found"] and found["durations_searched"]
    assert found["durations_given"] == 1
    assert (tmp_path / "h" / "durations.csv").read_text().startswith(
        "robot,cycle,phase,ticks\n"
    )
    runs = monoculus.run(tmp_path / "h" / "reproduce.toml")
    assert float(runs["final_diameter"][0]) == 0.0


def test_a_python_algorithm_is_hunted():
    # Move toward the first direction seen: a directions-only rule, which the
    # impossibility result says grows the hull from some start.
    @monoculus.algorithm("toward_first_py", sensing="directions")
    def toward_first(obs, rng):
        d = obs.directions
        return d[0] if len(d) else None

    found = monoculus.hunt(
        {
            "name": "py-hunt",
            "swarm": {"n": 4, "init": "square", "side": 3.0},
            "algorithm": {"name": "toward_first_py"},
            "stop": {"max_rounds": 10},
            "hunt": {"property": "hull_grows", "n_min": 3, "n_max": 6, "evaluations": 5000},
        }
    )
    assert found["found"], found
    assert found["algorithm"] == "toward_first_py"
    assert found["out"] is None
    assert isinstance(found["positions"], np.ndarray)


def test_bad_hunts_raise_config_error():
    config = {
        "name": "bad",
        "swarm": {"n": 4, "init": "square"},
        "algorithm": {"name": "median"},
        "hunt": {"property": "hull_grows", "evaluations": 0},
    }
    with pytest.raises(monoculus.ConfigError, match="hunt.evaluations"):
        monoculus.hunt(config)
    del config["hunt"]["evaluations"]
    with pytest.raises(monoculus.ConfigError, match="no budget"):
        monoculus.hunt(config)
    del config["hunt"]
    with pytest.raises(monoculus.ConfigError, match=r"no \[hunt\] section"):
        monoculus.hunt(config)
