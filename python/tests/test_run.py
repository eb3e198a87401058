"""monoculus.run: row for row the command line's runs.csv, numeric dtypes, sweeps
through `set`, results folders that resume, errors that say where."""

import subprocess

import numpy as np
import pandas as pd
import pytest

import monoculus


def without_wall(df):
    return df.drop(columns=["wall_ms"]).reset_index(drop=True)


def test_rows_are_the_command_lines(root, cli, tmp_path):
    config = root / "configs" / "paper" / "vs_n.toml"
    runs = monoculus.run(config, set={"seeds": 3, "swarm.n": [10, 50]})
    subprocess.run(
        [cli, "run", str(config), "--set", "seeds=3", "--set", "swarm.n=[10, 50]", "--out", str(tmp_path / "cli")],
        check=True,
        capture_output=True,
    )
    want = pd.read_csv(tmp_path / "cli" / "runs.csv", true_values=["true"], false_values=["false"])
    pd.testing.assert_frame_equal(without_wall(runs), without_wall(want))
    assert len(runs) == 2 * 2 * 3
    for column in ["n", "rounds", "moves", "seed"]:
        assert runs[column].dtype == np.int64, column
    for column in ["rho", "tau", "d_opt", "final_diameter"]:
        assert runs[column].dtype == np.float64, column
    assert runs["converged"].dtype == bool


def test_dicts_and_set_sweep(small):
    runs = monoculus.run(small, set=["swarm.side=[6.0, 9.0]"])
    assert sorted(runs["side"].unique()) == [6, 9]
    assert len(runs) == 2 * 2 * 2 * 4
    assert runs["converged"].all()


def test_a_results_folder_is_written_and_resumed(small, tmp_path):
    out = tmp_path / "out"
    first = monoculus.run(small, out=out)
    assert (out / "runs.csv").exists() and (out / "summary.csv").exists()
    again = monoculus.run(small, out=out)
    pd.testing.assert_frame_equal(without_wall(first), without_wall(again))


def test_results_do_not_depend_on_the_thread_count(small):
    one = monoculus.run(small, threads=1)
    two = monoculus.run(small, threads=2)
    pd.testing.assert_frame_equal(without_wall(one), without_wall(two))


def test_a_bad_config_raises_config_error_naming_file_line_and_key(tmp_path, small):
    bad = tmp_path / "bad.toml"
    bad.write_text('name = "b"\n[swarm]\nn = "ten"\ninit = "square"\n[algorithm]\nname = "converge_locality"\n')
    with pytest.raises(monoculus.ConfigError) as e:
        monoculus.run(bad)
    assert isinstance(e.value, ValueError)
    assert (type(e.value).__module__, type(e.value).__name__) == ("monoculus", "ConfigError")
    assert str(e.value).startswith(f"{bad}:3: swarm.n: invalid type")
    assert (e.value.file, e.value.line, e.value.key) == (str(bad), 3, "swarm.n")
    small["algorithm"]["name"] = "nowhere"
    with pytest.raises(monoculus.ConfigError, match="is not a registered algorithm"):
        monoculus.run(small)
    small["algorithm"]["name"] = "converge_locality"
    with pytest.raises(monoculus.ConfigError, match="set: swarm.n: must be at least 1"):
        monoculus.run(small, set={"swarm.n": 0})


def test_a_dict_configs_errors_name_the_key_and_no_line(small):
    small["algorithm"]["params"] = {"p_mov": 0.5}
    with pytest.raises(monoculus.ConfigError) as e:
        monoculus.run(small)
    assert str(e.value).startswith("algorithm.params.p_mov: "), str(e.value)
    assert "<dict>" not in str(e.value)
    assert (e.value.file, e.value.line, e.value.key) == (None, None, "algorithm.params.p_mov")
    del small["algorithm"]["params"]
    with pytest.raises(monoculus.ConfigError) as e:
        monoculus.run(small, set={"swarm.n": 0})
    assert str(e.value).startswith("set: swarm.n: must be at least 1"), str(e.value)


def test_the_version_is_the_workspaces(root):
    import importlib.metadata
    import re

    cargo = (root / "Cargo.toml").read_text()
    version = re.search(r'^version = "(.*)"$', cargo, flags=re.M).group(1)
    assert monoculus.__version__ == version
    assert importlib.metadata.version("monoculus") == version
