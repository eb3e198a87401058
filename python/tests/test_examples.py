"""The examples run headless and write their figures."""

import pathlib
import re
import subprocess
import sys

EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples" / "python"


def run(script, cwd):
    env = {"MPLBACKEND": "Agg", "PATH": "/usr/bin:/bin"}
    import os

    env.update({k: v for k, v in os.environ.items() if k.startswith(("PYTHON", "VIRTUAL_ENV", "HOME"))})
    return subprocess.run([sys.executable, str(EXAMPLES / script)], cwd=cwd, env=env, capture_output=True, text=True, timeout=600)


def test_quickstart_writes_its_figure(tmp_path):
    r = run("quickstart.py", tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "quickstart.png").stat().st_size > 10_000
    assert "converge_quadrant" in r.stdout


def test_animate_writes_its_gif(tmp_path):
    r = run("animate.py", tmp_path)
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "animate.gif").read_bytes()[:3] == b"GIF"


def test_the_python_converge_locality_example_runs(tmp_path):
    r = run("converge_locality.py", tmp_path)
    assert r.returncode == 0, r.stderr
    assert "py_converge_locality" in r.stdout


def test_every_example_is_run_by_a_test():
    tests = "".join(p.read_text() for p in pathlib.Path(__file__).parent.glob("test_*.py"))
    for example in sorted(EXAMPLES.iterdir()):
        if example.suffix in (".py", ".ipynb"):
            imported = re.search(rf"^import {example.stem}\b", tests, flags=re.M)
            named = f'"{example.name}"' in tests or imported
            assert named, f"examples/python/{example.name} is run by no test"
