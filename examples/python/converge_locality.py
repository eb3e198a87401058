"""ConvergeLocality (the paper's LD algorithm, docs/model.md) written in Python: a robot that
sees one point moves toward it, else toward a uniformly random far point, else stays.
Its goal is the built-in's, every robot within a disc of radius c (the paper's theorem),
so it gives the runs and verdicts of converge_locality, bit for bit
(python/tests/test_algorithms.py checks it).

    python examples/python/converge_locality.py
"""

import monoculus


@monoculus.algorithm("py_converge_locality", sensing="ld", goal="disc")
def converge_locality(obs, rng):
    toward = obs.sole_visible()
    if toward is not None:
        return toward
    return obs.random_far(rng)  # None (stay) if no visible point is far


if __name__ == "__main__":
    config = {
        "name": "python-locality",
        "seeds": 10,
        "swarm": {"n": 50, "init": "square", "side": 20.0},
        "algorithm": {"name": ["py_converge_locality", "converge_locality"]},
    }
    runs = monoculus.run(config)
    print(runs.groupby("algorithm")[["rho", "tau", "rounds"]].median())
