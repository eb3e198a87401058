"""Ctrl-C stops a long run promptly and leaves a results folder that resumes."""

import os
import signal
import subprocess
import sys
import time

import pandas as pd

SCRIPT = """
import sys, monoculus
config = {"name": "long", "seeds": 400, "swarm": {"n": 300, "init": "square", "side": 60.0},
          "algorithm": {"name": "converge_locality"}}
try:
    monoculus.run(config, out=sys.argv[1], threads=1)
    print("finished")
except KeyboardInterrupt:
    print("interrupted")
"""


def test_ctrl_c_stops_the_sweep_and_the_folder_resumes(tmp_path):
    out = tmp_path / "out"
    p = subprocess.Popen([sys.executable, "-c", SCRIPT, str(out)], stdout=subprocess.PIPE, text=True)
    runs = out / "runs.csv"
    deadline = time.time() + 60
    while not (runs.exists() and runs.read_text().count("\n") > 3):
        assert time.time() < deadline and p.poll() is None, "no runs written"
        time.sleep(0.05)
    sent = time.time()
    p.send_signal(signal.SIGINT)
    stdout, _ = p.communicate(timeout=30)
    assert time.time() - sent < 10, "took too long to stop"
    assert stdout.strip() == "interrupted"
    before = pd.read_csv(runs)
    assert 0 < len(before) < 400
    # Resumed (with another thread count): the runs written stay as they were, the
    # missing ones are added, and the whole sweep is there.
    finish = SCRIPT.replace("threads=1", "threads=2")
    q = subprocess.run([sys.executable, "-c", finish, str(out)], capture_output=True, text=True, timeout=600)
    assert q.stdout.strip() == "finished", q.stderr
    after = pd.read_csv(runs)
    assert len(after) == 400
    pd.testing.assert_frame_equal(after.iloc[: len(before)], before)


REPLAY = """
import sys, monoculus
config = {"name": "long", "swarm": {"n": 1500, "init": "square", "side": 400.0},
          "algorithm": {"name": "converge_locality"}}
if sys.argv[1] == "simulation":
    sim = monoculus.Simulation(config)
    sim.run(max_rounds=300)
print("started", flush=True)
try:
    if sys.argv[1] == "replay":
        monoculus.replay(config)
    else:
        sim.replay()
    print("finished")
except KeyboardInterrupt:
    print("interrupted")
"""


def test_ctrl_c_stops_a_replay_being_recorded():
    for how in ("replay", "simulation"):
        p = subprocess.Popen([sys.executable, "-c", REPLAY, how], stdout=subprocess.PIPE, text=True)
        assert p.stdout.readline().strip() == "started"
        time.sleep(1.5)
        sent = time.time()
        p.send_signal(signal.SIGINT)
        stdout, _ = p.communicate(timeout=60)
        assert time.time() - sent < 10, f"{how}: took too long to stop"
        assert stdout.strip() == "interrupted", how
