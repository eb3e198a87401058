"""What a Python algorithm costs per activation, and what running from Python costs.

    python python/benches/overhead.py [--n 1000] [--seeds 3] [--repeats 5]

1. Per activation: the same sweep with the built-in converge_locality and with its
   Python transcription (examples/python/converge_locality.py, the same runs bit for
   bit), on one thread; the difference of the wall times over the activations.
   Target (docs/performance.md): 5 microseconds per activation at n = 10^3.
2. Vectorized: one rule (toward a uniformly random visible robot) written one
   activation at a time and vectorized with numpy, on one thread (n = 100, 10 seeds x
   50 rounds, where the full look the rule needs stays cheap); the
   wall time per activation of each (whole calls, the engine's work included).
3. Built-ins from Python: `monoculus.run` against the `monoculus run` command line on
   the same config, all threads, run in turn; the ratio of wall times (target: within
   5%). Needs the command-line binary (MONOCULUS_BIN, else target/release/monoculus).

Timings are whole calls, taken in turn (A B A B ...) so that drifts of the machine
fall on both; the report gives the median and the range over the repeats.
"""

import argparse
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

import monoculus

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "examples" / "python"))
import converge_locality  # noqa: E402,F401  (registers py_converge_locality)


def config(name, n, seeds):
    return {
        "name": "overhead",
        "seeds": seeds,
        "swarm": {"n": n, "init": "square", "side": 2.0 * n**0.5},
        "algorithm": {"name": name},
    }


def timed(f):
    t = time.perf_counter()
    out = f()
    return time.perf_counter() - t, out


def spread(xs):
    return f"median {statistics.median(xs):.3f} (range {min(xs):.3f}-{max(xs):.3f})"


def per_activation(n, seeds, repeats):
    builtin, python, activations = [], [], None
    for _ in range(repeats):
        tb, rb = timed(lambda: monoculus.run(config("converge_locality", n, seeds), threads=1))
        tp, rp = timed(lambda: monoculus.run(config("py_converge_locality", n, seeds), threads=1))
        assert (rb["rounds"].to_numpy() == rp["rounds"].to_numpy()).all(), "not the same runs"
        activations = int(rb["activations"].sum())
        builtin.append(tb)
        python.append(tp)
    extra = [(p - b) / activations * 1e6 for b, p in zip(builtin, python)]
    print(f"n = {n}, {seeds} seeds, {activations} activations, one thread")
    print(f"  built-in converge_locality  s: {spread(builtin)}")
    print(f"  Python transcription        s: {spread(python)}")
    print(f"  extra per activation       us: {spread(extra)}")


@monoculus.algorithm("bench_toward_one", sensing="ld")
def toward_one(obs, rng):
    d = obs.directions
    if len(d) == 0:
        return None
    return d[int(rng.uniform() * len(d))]


@monoculus.algorithm("bench_toward_one_vectorized", sensing="ld", vectorized=True)
def toward_one_vectorized(batch):
    counts = np.diff(batch.offsets)
    stay = counts == 0
    pick = batch.offsets[:-1] + (batch.random[:, 0] * counts).astype(np.int64)
    directions = np.zeros((batch.count, batch.dim))
    directions[~stay] = batch.directions[pick[~stay]]
    return directions, stay


def vectorized(repeats, n=100, seeds=10, rounds=50):
    by_one, together, activations = [], [], None
    for _ in range(repeats):
        c = lambda name: dict(config(name, n, seeds), stop={"max_rounds": rounds})  # noqa: E731
        t1, r1 = timed(lambda: monoculus.run(c("bench_toward_one"), threads=1))
        tv, rv = timed(lambda: monoculus.run(c("bench_toward_one_vectorized"), threads=1))
        activations = int(r1["activations"].sum())
        assert activations == int(rv["activations"].sum()) == n * seeds * rounds
        by_one.append(t1 / activations * 1e6)
        together.append(tv / activations * 1e6)
    print(f"toward a random visible robot, n = {n}, {seeds} seeds x {rounds} rounds, one thread")
    print(f"  one activation per call    us: {spread(by_one)}")
    print(f"  vectorized (numpy)         us: {spread(together)}")


def from_python(path, repeats, binary):
    cli, py = [], []
    for _ in range(repeats):
        with tempfile.TemporaryDirectory() as out:
            t, r = timed(lambda: subprocess.run([binary, "run", str(path), "--out", out], capture_output=True))
            assert r.returncode == 0, r.stderr.decode()
            cli.append(t)
        t, _ = timed(lambda: monoculus.run(path))
        py.append(t)
    ratio = [p / c for c, p in zip(cli, py)]
    print(f"{path.relative_to(ROOT)}, all threads")
    print(f"  monoculus run (CLI)          s: {spread(cli)}")
    print(f"  monoculus.run (Python)       s: {spread(py)}")
    print(f"  Python / CLI                  : {spread(ratio)}")


if __name__ == "__main__":
    a = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    a.add_argument("--n", type=int, default=1000)
    a.add_argument("--seeds", type=int, default=3)
    a.add_argument("--repeats", type=int, default=5)
    a.add_argument("--config", default=str(ROOT / "configs" / "paper" / "vs_n.toml"))
    a.add_argument("--cli", default=os.environ.get("MONOCULUS_BIN", str(ROOT / "target" / "release" / "monoculus")))
    args = a.parse_args()
    per_activation(args.n, args.seeds, args.repeats)
    vectorized(args.repeats)
    from_python(pathlib.Path(args.config).resolve(), args.repeats, args.cli)
