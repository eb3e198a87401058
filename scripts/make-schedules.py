#!/usr/bin/env python3
"""Writes the schedules of configs/extensions/file_schedule.toml (30 robots) to
configs/extensions/schedules/: each a CSV with header round,robot (SPEC 9.4).

  every_round  every robot in every round (FSYNC written out), 100 rounds
  halves       even robots in odd rounds, odd robots in even rounds, 200 rounds
  lagging      robots 0-9 only in every 5th round, the others in every round, 300 rounds
  one_by_one   robot (k - 1) mod 30 alone in round k (round robin), 1500 rounds
"""
from pathlib import Path

N = 30
OUT = Path(__file__).resolve().parent.parent / "configs" / "extensions" / "schedules"

SCHEDULES = {
    "every_round": (100, lambda k, i: True),
    "halves": (200, lambda k, i: i % 2 == k % 2),
    "lagging": (300, lambda k, i: i >= 10 or k % 5 == 0),
    "one_by_one": (1500, lambda k, i: i == (k - 1) % N),
}

OUT.mkdir(parents=True, exist_ok=True)
for name, (rounds, active) in SCHEDULES.items():
    rows = ["round,robot"]
    rows += [f"{k},{i}" for k in range(1, rounds + 1) for i in range(N) if active(k, i)]
    (OUT / f"{name}.csv").write_text("\n".join(rows) + "\n")
    print(f"{OUT / name}.csv: {rounds} rounds, {len(rows) - 1} activations")
