#!/usr/bin/env bash
# Runs every experiment of the paper's simulation section (configs/paper/) and writes
# the table of rho and tau to docs/paper-table.md. Extra arguments go to `monoculus run`
# (e.g. --threads 2, --force). Finished runs are kept: rerunning resumes.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --quiet
mkdir -p docs
dirs=()
for config in configs/paper/*.toml; do
    out="results/paper/$(basename "$config" .toml)"
    ./target/release/monoculus run "$config" --out "$out" "$@"
    dirs+=("$out")
done
./target/release/monoculus table "${dirs[@]}" > docs/paper-table.md
echo "table written to docs/paper-table.md"
