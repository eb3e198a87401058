"""Replays from Python: the command line's page from monoculus.replay, a stepped
simulation's replay (its own start included) the same run, the inline frame, the GIF,
lights, and a hunt's counterexample."""

import html
import re
import subprocess

import numpy as np
import pytest

import monoculus

TINY = {
    "name": "tiny",
    "seeds": [5],
    "swarm": {"n": 10, "init": "square", "side": 20.0},
    "algorithm": {"name": "converge_locality"},
}


def test_the_page_is_the_command_line_s(root, cli, tmp_path):
    config = root / "configs" / "replay" / "paper_run.toml"
    small = {"swarm.n": 30, "swarm.side": 12.0}
    got = monoculus.replay(config, set=small)
    page = tmp_path / "cli.html"
    subprocess.run(
        [cli, "replay", str(config), "--set", "swarm.n=30", "--set", "swarm.side=12.0",
         "--out", str(page)],
        check=True,
        capture_output=True,
    )
    assert got.html == page.read_text()
    assert got.verdict == "converged" and got.outcome.startswith("converged after")
    assert got.save(tmp_path / "py.html") == str(tmp_path / "py.html")
    assert (tmp_path / "py.html").read_text() == got.html


def test_inline_it_is_a_frame_of_its_own(tmp_path):
    a, b = monoculus.replay(TINY), monoculus.replay(TINY, seed=6)
    shown = a._repr_html_()
    match = re.fullmatch(r'<iframe class="monoculus-replay" title="[^"<>]*" srcdoc="([^"<>]*)" '
                         r'sandbox="allow-scripts" style="[^"<>]*"></iframe>', shown)
    assert match, shown[:300]
    # The page is the attribute, whole: nothing of it (no script, no style) is outside.
    assert html.unescape(match.group(1)) == a.html
    assert a._repr_html_() != b._repr_html_()
    assert "<script" not in shown and "<style" not in shown


def test_a_gif_is_written(tmp_path):
    r = monoculus.replay(TINY)
    path = r.gif(tmp_path / "run.gif", size=(160, 120))
    data = open(path, "rb").read()
    assert data[:6] == b"GIF89a"
    assert int.from_bytes(data[6:8], "little") == 160
    assert int.from_bytes(data[8:10], "little") == 120
    with pytest.raises(ValueError, match="64 to 4096"):
        r.gif(tmp_path / "bad.gif", size=(10, 10))


def test_a_stepped_simulation_s_replay_is_the_same_run():
    sim = monoculus.Simulation(TINY, seed=5)
    for _ in range(3):
        sim.step()
    r = sim.replay()
    assert r.frames == 4
    assert np.array_equal(r.positions(), sim.positions.astype(np.float32))
    assert r.outcome.startswith("stepped 3 rounds")
    assert r.verdict == ("converged" if sim.converged else "not converged")
    # Run on to the end: the replay is then the whole run's, as monoculus.replay makes it.
    row = sim.run()
    whole, direct = sim.replay(), monoculus.replay(TINY, seed=5)
    assert whole.frames == direct.frames == row["rounds"] + 1
    assert whole.outcome == direct.outcome and whole.verdict == direct.verdict == "converged"
    for k in range(whole.frames):
        assert np.array_equal(whole.positions(k), direct.positions(k))


def test_positions_set_by_hand_are_its_start():
    start = np.array([[0.0, 0.0], [3.0, 0.5], [1.0, 2.5], [-1.5, 1.0]])
    sim = monoculus.Simulation(TINY, positions=start)
    sim.step()
    sim.step()
    r = sim.replay()
    assert np.array_equal(r.positions(0), start.astype(np.float32))
    assert np.array_equal(r.positions(-1), sim.positions.astype(np.float32))
    assert "stepped from Python" in r.title


def test_an_async_simulation_replays_every_tick(root):
    config = dict(TINY, scheduler={"kind": "async"})
    sim = monoculus.Simulation(config)
    sim.step()
    r = sim.replay()
    assert r.frames > 2  # an epoch is many event ticks
    assert np.array_equal(r.positions(), sim.positions.astype(np.float32))
    assert r.outcome.startswith("stepped 1 epochs")


@monoculus.algorithm("py_replay_lit", sensing="directions", lights=["calm", "lively"])
def replay_lit(obs, rng, state):
    state.light = "lively" if len(obs.directions) > 2 else "calm"
    return None


def test_lights_are_on_the_page():
    config = dict(TINY, algorithm={"name": "py_replay_lit"})
    r = monoculus.replay(config)
    assert '"lights":["calm","lively"]' in r.html
    sim = monoculus.Simulation(config)
    sim.step()
    assert '"lights":["calm","lively"]' in sim.replay().html


def test_a_hunt_shows_its_counterexample(root):
    found = monoculus.hunt(root / "configs" / "hunt" / "median.toml", threads=1)
    assert isinstance(found, dict) and found["found"]
    assert isinstance(found.replay, monoculus.Replay)
    assert len(found.replay.positions(0)) == found["n"]
    shown = found._repr_html_()
    assert shown.startswith("<p><b>hunt for ") and '<iframe class="monoculus-replay"' in shown


def test_bad_arguments_are_clear(root):
    with pytest.raises(IndexError, match="cell 3: the config has 1 cells"):
        monoculus.replay(TINY, cell=3)
    with pytest.raises(ValueError, match="at least 1"):
        monoculus.replay(TINY, max_mb=0)
    with pytest.raises(IndexError, match="frame 99"):
        monoculus.replay(TINY).positions(99)
