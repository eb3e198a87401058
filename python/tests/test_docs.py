"""The Python code of docs/python.md runs as written (in order, in one namespace, from
the repository root, as a reader would paste it)."""

import pathlib
import re

import monoculus

ROOT = pathlib.Path(__file__).resolve().parents[2]


def test_the_guide_s_code_runs(monkeypatch):
    text = (ROOT / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) >= 4
    monkeypatch.chdir(ROOT)
    namespace = {}
    for block in blocks:
        exec(compile(block, "docs/python.md", "exec"), namespace)
    names = monoculus.algorithms()["name"].tolist()
    assert "my_locality" in names and "toward_one" in names
    runs = monoculus.run(
        {"name": "doc", "seeds": 2, "swarm": {"n": 20, "init": "square"}, "algorithm": {"name": "toward_one"}, "stop": {"max_rounds": 5}}
    )
    assert len(runs) == 2


def test_the_guide_s_first_line_runs():
    text = (ROOT / "docs" / "python.md").read_text()
    line = re.search(r'python -c "(.*)"', text).group(1)
    exec(compile(line, "docs/python.md", "exec"), {})


def test_the_notebook_page_s_code_runs(monkeypatch, tmp_path):
    """docs/notebooks.md's code, in a folder of its own (it writes run.html and run.gif)
    that sees the repository's configs/ as a reader at the root does."""
    text = (ROOT / "docs" / "notebooks.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) >= 4
    (tmp_path / "configs").symlink_to(ROOT / "configs")
    monkeypatch.chdir(tmp_path)
    namespace = {}
    for block in blocks:
        exec(compile(block, "docs/notebooks.md", "exec"), namespace)
    assert (tmp_path / "run.html").read_text() == namespace["replay"].html
    assert (tmp_path / "run.gif").read_bytes()[:6] == b"GIF89a"
    assert namespace["stepped"].outcome.startswith("stepped 3 rounds")
    assert namespace["found"]["found"] and namespace["found"].replay is not None
