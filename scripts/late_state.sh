#!/usr/bin/env bash
# One ASYNC epoch from a late ConvergeLocality state, where most robots are packed in a
# core whose grid cells are crowded: `scripts/late_state.sh [COPIES]` (default 10).
# The state is the positions of configs/bench/async_1e5.toml (seed 0) at epoch 40,
# each robot replaced by COPIES robots within 0.05 of it (COPIES = 10: 10^6 robots,
# diameter 67, half of them within 1 of the centre). Prints the epoch's wall time and
# peak memory; about 1 minute for the trace, then 2.5 minutes for the epoch at 10^6 on
# 2 cores. Files go to results/late_state/.
set -euo pipefail
cd "$(dirname "$0")/.."
copies="${1:-10}"
cargo build --release --quiet
bin=./target/release/monoculus
out=results/late_state
mkdir -p "$out"

if [ ! -s "$out/epoch40.csv" ]; then
    "$bin" trace configs/bench/async_1e5.toml --seed 0 --out "$out/trace.csv" --positions > /dev/null
    python3 - "$out/trace.positions.csv" "$out/epoch40.csv" <<'PY'
import csv, sys
with open(sys.argv[1]) as f, open(sys.argv[2], "w") as g:
    g.write("x,y\n")
    for row in csv.DictReader(f):
        if row["round"] == "40":
            g.write(f"{row['x']},{row['y']}\n")
PY
    rm "$out/trace.positions.csv"
fi

python3 - "$out/epoch40.csv" "$out/late.csv" "$copies" <<'PY'
import csv, math, random, sys
random.seed(1)
copies = int(sys.argv[3])
with open(sys.argv[1]) as f, open(sys.argv[2], "w") as g:
    g.write("x,y\n")
    for row in csv.DictReader(f):
        x, y = float(row["x"]), float(row["y"])
        for _ in range(copies):
            a, s = random.random() * 2 * math.pi, 0.05 * math.sqrt(random.random())
            g.write(f"{x + s * math.cos(a)!r},{y + s * math.sin(a)!r}\n")
PY

cat > "$out/late.toml" <<'TOML'
name = "late-state"
seeds = 1

[swarm]
init = "file"
file = "late.csv"

[algorithm]
name = "converge_locality"

[scheduler]
kind = "async"
idle = { kind = "uniform", min = 1, max = 10 }
compute = { kind = "uniform", min = 1, max = 5 }
move = { kind = "exponential", mean = 4.0 }
start = "random"

[stop]
max_rounds = 1
TOML

if [ -x /usr/bin/time ]; then
    /usr/bin/time -f "wall %e s, peak %M kB" "$bin" run "$out/late.toml" --out "$out/run" --force
else
    time "$bin" run "$out/late.toml" --out "$out/run" --force
fi
