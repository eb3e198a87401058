"""Shared fixtures: the repository, the command-line binary the Python results are
compared with, and small configs."""

import os
import pathlib
import subprocess

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]


@pytest.fixture(scope="session")
def root():
    return ROOT


@pytest.fixture(scope="session")
def cli():
    """The `monoculus` binary (built by `cargo test` before pytest runs in CI;
    MONOCULUS_BIN names another)."""
    path = os.environ.get("MONOCULUS_BIN", str(ROOT / "target" / "debug" / "monoculus"))
    if not os.path.exists(path):
        subprocess.run(["cargo", "build", "-p", "monoculus-cli"], cwd=ROOT, check=True)
    return path


SMALL = {
    "name": "small",
    "seeds": 4,
    "swarm": {"n": [12, 25], "init": "square", "side": 8.0},
    "algorithm": {"name": ["converge_locality", "converge_quadrant"]},
}


@pytest.fixture
def small():
    import copy

    return copy.deepcopy(SMALL)
