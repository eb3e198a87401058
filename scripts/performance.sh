#!/usr/bin/env bash
# Measures every scale target of docs/performance.md once and prints the
# table (markdown) on stdout: `scripts/performance.sh [REPEATS]` (default 3: rounds are
# the best of REPEATS stress runs; whole runs are timed once). About 3 to 4 minutes on
# 2 cores, with numpy's 12 s if numpy is installed (`pip install numpy`).
# Details of every run go to results/performance/ (stress logs, results folders).
set -euo pipefail
cd "$(dirname "$0")/.."
repeats="${1:-3}"
cargo build --release --quiet
bin=./target/release/monoculus
out=results/performance
mkdir -p "$out"

# Best mean round time (s) and the peak memory (MB) of REPEATS stress runs.
stress() {
    local name="$1"; shift
    for k in $(seq "$repeats"); do
        "$bin" stress "$@" > "$out/$name.$k.log"
    done
    python3 - "$out" "$name" "$repeats" <<'PY'
import sys
out, name, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3])
best, peak = float("inf"), 0.0
for k in range(1, repeats + 1):
    for line in open(f"{out}/{name}.{k}.log"):
        if line.startswith("rounds="):
            best = min(best, float(line.split("mean_round_s=")[1]))
        if line.startswith("peak_memory_mb="):
            peak = max(peak, float(line.split("=")[1]))
print(f"{best:.4f} {peak:.0f}")
PY
}

# Microseconds per activation of the best of REPEATS stress runs.
per_activation() {
    local name="$1"; shift
    for k in $(seq "$repeats"); do
        "$bin" stress "$@" > "$out/$name.$k.log" 2>&1
    done
    python3 - "$out" "$name" "$repeats" <<'PY'
import sys
out, name, repeats = sys.argv[1], sys.argv[2], int(sys.argv[3])
best = 0.0
for k in range(1, repeats + 1):
    for line in open(f"{out}/{name}.{k}.log"):
        if line.startswith("activations_per_s="):
            best = max(best, float(line.split("=")[1]))
print(f"{1e6 / best:.3f}")
PY
}

# Wall time (s) of a whole experiment, from its runs.csv.
whole() {
    local name="$1" config="$2"; shift 2
    "$bin" run "$config" --out "$out/$name" --force "$@" > /dev/null 2>&1
    python3 - "$out/$name/runs.csv" <<'PY'
import csv, sys
print(f"{sum(float(r['wall_ms']) for r in csv.DictReader(open(sys.argv[1]))) / 1000:.2f}")
PY
}

read -r cl5 _ < <(stress cl_1e5 --n 100000 --rounds 5)
read -r cl5_one _ < <(stress cl_1e5_1thread --n 100000 --rounds 5 --threads 1)
read -r lattice _ < <(stress cl_1e5_lattice --n 100000 --rounds 5 --init lattice)
read -r cl6 cl6_mb < <(stress cl_1e6 --n 1000000 --rounds 2)
read -r cq6 cq6_mb < <(stress cq_1e6 --n 1000000 --rounds 3 --algorithm converge_quadrant)
fine="--idle uniform:1:1000 --compute uniform:1:500 --move exp:400"
# ASYNC against FSYNC at the same n, runs long enough for this VM's noise.
fsync_act=$(per_activation fsync_1e4 --n 10000 --rounds 40)
coarse_long=$(per_activation async_coarse_1e4_long --n 10000 --rounds 10 --scheduler async)
fsync5=$(per_activation fsync_1e5 --n 100000 --rounds 6)
coarse_act=$(per_activation async_coarse_1e4 --n 10000 --rounds 4 --scheduler async)
# shellcheck disable=SC2086
fine_act=$(per_activation async_x100_1e4 --n 10000 --rounds 2 --scheduler async $fine)
async5=$(per_activation async_1e5 --n 100000 --rounds 2 --scheduler async)
async5_one=$(per_activation async_1e5_1thread --n 100000 --rounds 2 --scheduler async --threads 1)
cl_run=$(whole locality_1e5 configs/bench/locality_1e5.toml)
cq_run=$(whole quadrant_1e4 configs/bench/quadrant_1e4.toml)
# The paper's experiments run many runs at once: their elapsed time, not the sum.
t0=$(date +%s.%N)
whole paper_vs_n configs/paper/vs_n.toml > /dev/null
whole paper_vs_side configs/paper/vs_side.toml > /dev/null
paper=$(python3 -c "print(f'{$(date +%s.%N) - $t0:.2f}')")
ours=$(whole numpy_comparison configs/bench/numpy_comparison.toml --threads 1)
if python3 -c "import numpy" 2> /dev/null; then
    numpy=$(python3 scripts/numpy_baseline.py | sed -n 's/.*wall_s=\([0-9.]*\).*/\1/p')
else
    numpy=""
fi

python3 - "$cl5" "$cl5_one" "$lattice" "$cl6" "$cl6_mb" "$cq6" "$cq6_mb" "$cl_run" "$cq_run" "$paper" "$ours" "$fsync_act" "$coarse_act" "$fine_act" "$async5" "$async5_one" "$coarse_long" "$fsync5" "$numpy" <<'PY'
import sys
cl5, cl5_one, lattice, cl6, cl6_mb, cq6, cq6_mb, cl_run, cq_run, paper, ours = map(float, sys.argv[1:12])
fsync_act, coarse_act, fine_act, async5, async5_one, coarse_long, fsync5 = map(float, sys.argv[12:19])
numpy = float(sys.argv[19]) if sys.argv[19] else None
# Rounds are means over the rounds of the best stress run (the first round of
# ConvergeQuadrant builds what later rounds reuse, and counts in its mean).
rows = [
    ("ConvergeLocality round, n = 10^5 (s)", cl5, cl5 <= 0.15, "<= 0.15"),
    ("ConvergeLocality round, n = 10^6 (s)", cl6, cl6 <= 3.0, "<= 3"),
    ("ConvergeQuadrant round, n = 10^6 (s)", cq6, cq6 <= 0.3, "<= 0.3"),
    ("peak memory, n = 10^6 (MB)", max(cl6_mb, cq6_mb), max(cl6_mb, cq6_mb) <= 300, "<= 300"),
    ("2 threads against 1, n = 10^5 round", cl5_one / cl5, cl5_one / cl5 >= 1.7, ">= 1.7x"),
    ("whole ConvergeLocality run, n = 10^5, default settings (s)", cl_run, cl_run <= 45, "<= 45"),
    ("whole ConvergeQuadrant run, n = 10^4 (s)", cq_run, cq_run <= 60, "<= 60"),
    ("configs/paper/ (s)", paper, paper <= 60, "<= 60"),
    ("lattice against uniform start, n = 10^5 round", lattice / cl5, lattice / cl5 <= 3, "<= 3x"),
    ("ASYNC x100 against coarse durations, n = 10^4, per activation", fine_act / coarse_act, fine_act / coarse_act <= 1.5, "<= 1.5x"),
    ("ASYNC coarse against FSYNC, n = 10^4, per activation (us: %.2f against %.2f)" % (coarse_long, fsync_act), coarse_long / fsync_act, coarse_long / fsync_act <= 2, "<= 2x"),
    ("ASYNC coarse against FSYNC, n = 10^5, per activation (us: %.2f against %.2f)" % (async5, fsync5), async5 / fsync5, async5 / fsync5 <= 2, "<= 2x"),
    ("ASYNC 2 threads against 1, n = 10^5", async5_one / async5, async5_one / async5 >= 1.6, ">= 1.6x"),
]
if numpy is not None:
    rows.append(("numpy against monoculus (1 thread)", numpy / ours, numpy / ours >= 100, ">= 100x"))
print("| target | measured | limit | met |")
print("| --- | --- | --- | --- |")
for name, value, met, limit in rows:
    shown = f"{value:.0f}" if value >= 100 else f"{value:.3g}"
    print(f"| {name} | {shown} | {limit} | {'yes' if met else 'no'} |")
if numpy is None:
    print("| numpy against monoculus | not measured (`pip install numpy`) | >= 100x | - |")
PY
