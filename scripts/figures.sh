#!/usr/bin/env bash
# Reruns the paper's experiments (finished runs are kept; pass --force to start over),
# writes every figure next to the results (results/<...>/figures/*.png|svg), traces a
# ConvergeLocality run and the Figure 1 scenario, draws the README's replay GIF, and copies
# the figures the docs show to docs/figures/.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/paper.sh "$@"
bin=./target/release/monoculus
for dir in results/paper/*/; do
    "$bin" plot "$dir" > /dev/null
done
mkdir -p results/traces docs/figures
"$bin" trace configs/paper/vs_n.toml --cell 4 --seed 1 --out results/traces/locality_n50.csv --positions
"$bin" trace configs/scenarios/figure1.toml --cell 0 --seed 0 --out results/traces/figure1_median.csv --positions
"$bin" trace configs/scenarios/figure1.toml --cell 1 --seed 0 --out results/traces/figure1_bisector.csv --positions
"$bin" trace configs/scenarios/figure1.toml --cell 2 --seed 0 --out results/traces/figure1_locality.csv --positions
for trace in results/traces/*[a-z0-9].csv; do
    case "$trace" in *.positions.csv) continue ;; esac
    "$bin" plot "$trace" > /dev/null
done
cp results/paper/vs_n/figures/{rho,tau}_vs_n.png results/paper/vs_side/figures/{rho,tau}_vs_side.png docs/figures/
"$bin" replay configs/replay/paper_run.toml --gif docs/figures/replay.gif > /dev/null
cp results/traces/{locality_n50_run,locality_n50_series,figure1_median_run,figure1_bisector_run,figure1_locality_run,figure1_median_series}.png docs/figures/
echo "figures written to docs/figures/ and results/*/figures/"
