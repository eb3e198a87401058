"""WaitForMovers (examples/wait-for-movers) written in Python: ConvergeLocality whose
robots show a light, `resting` or `moving`. A robot that sees a robot showing `moving`
stays and shows `resting`; any other robot decides as ConvergeLocality does and shows
`moving` if it steps. It gives the runs of the Rust example, bit for bit
(python/tests/test_lights.py checks it).

    python examples/python/wait_for_movers.py
"""

import monoculus


@monoculus.algorithm(
    "py_wait_for_movers", sensing="ld", lights=["resting", "moving"], goal="disc"
)
def wait_for_movers(obs, rng, state):
    if obs.sees_light("moving"):
        state.light = "resting"
        return None
    toward = obs.sole_visible()
    if toward is None:
        toward = obs.random_far(rng)
    state.light = "moving" if toward is not None else "resting"
    return toward


if __name__ == "__main__":
    config = {
        "name": "python-wait-for-movers",
        "seeds": 10,
        "swarm": {"n": 20, "init": "square", "side": 20.0},
        "algorithm": {"name": ["py_wait_for_movers", "converge_locality"]},
    }
    runs = monoculus.run(config)
    print(runs.groupby("algorithm")[["converged", "rho", "tau", "rounds"]].median())
    sim = monoculus.Simulation(dict(config, algorithm={"name": "py_wait_for_movers"}), seed=1)
    sim.step()
    print("after one round:", [sim.light_names[k] for k in sim.lights])
