#!/usr/bin/env python3
"""A straightforward vectorised numpy implementation of the FSYNC ConvergeLocality
experiment (opaque point robots, locality c, rigid steps b), as the speed baseline for
monoculus: `python3 scripts/numpy_baseline.py --n 200 --side 20 --seeds 10`.

Per round and observer it builds the n x n blocking test in numpy (O(n^2) per
observer, O(n^3) per round), then applies the algorithm: move toward the only visible
robot, else toward a uniformly random visible far robot, else stay. It stops when the
diameter is at most c or nobody moves. Co-located robots are not merged (random
starts have none). Prints the median rho and tau and the wall time.
"""
import argparse
import time

import numpy as np


def run(n, side, seed, b=1.0, c=2.0, eps_pos=1e-9, eps_ang=1e-9, max_rounds=100000):
    rng = np.random.default_rng(seed)
    pos = rng.uniform(0.0, side, size=(n, 2))
    g = pos.mean(axis=0)
    d = np.linalg.norm(pos - g, axis=1)
    d_opt, d_max = np.maximum(0.0, d - c / 2).sum(), d.max()
    rounds = moves = 0
    while rounds < max_rounds:
        diff = pos[None, :, :] - pos[:, None, :]           # diff[i, j] = p_j - p_i
        dist = np.linalg.norm(diff, axis=2)
        if dist.max() <= c:
            break
        step = np.zeros_like(pos)
        for i in range(n):
            v = diff[i]                                        # (n, 2)
            r = dist[i]
            cross = np.abs(v[:, None, 0] * v[None, :, 1] - v[:, None, 1] * v[None, :, 0])
            dot = v @ v.T
            ang = np.arctan2(cross, dot)                       # ang[r, q]
            blocks = (r[:, None] > eps_pos) & (r[:, None] < r[None, :] - eps_pos) & (ang <= eps_ang)
            np.fill_diagonal(blocks, False)
            visible = (r > eps_pos) & ~blocks.any(axis=0)
            visible[i] = False
            idx = np.flatnonzero(visible)
            if len(idx) == 1:
                target = idx[0]
            else:
                far = idx[r[idx] > c]
                if len(far) == 0:
                    continue
                target = far[rng.integers(len(far))]
            step[i] = b * v[target] / r[target]
        moved = np.count_nonzero(np.any(step != 0.0, axis=1))
        if moved == 0:
            break
        pos = pos + step
        moves += moved
        rounds += 1
    return moves * b / d_opt, rounds / d_max


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=200)
    ap.add_argument("--side", type=float, default=20.0)
    ap.add_argument("--seeds", type=int, default=10)
    a = ap.parse_args()
    start = time.perf_counter()
    results = [run(a.n, a.side, s) for s in range(a.seeds)]
    wall = time.perf_counter() - start
    rho, tau = np.median([r for r, _ in results]), np.median([t for _, t in results])
    print(f"numpy: n={a.n} side={a.side} seeds={a.seeds} rho_median={rho:.3f} tau_median={tau:.3f} wall_s={wall:.2f}")


if __name__ == "__main__":
    main()
