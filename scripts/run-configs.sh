#!/usr/bin/env bash
# Usage: scripts/run-configs.sh CONFIG_DIR TABLE.md [monoculus run options...]
# Runs every config in CONFIG_DIR (results in results/<dir>/<config>) and writes the
# table of rho and tau per cell to TABLE.md. Finished runs are kept: rerunning resumes
# (pass --force to start over). TABLE_ARGS adds options to `monoculus table`.
set -euo pipefail
cd "$(dirname "$0")/.."
configs="$1"; table="$2"; shift 2
cargo build --release --quiet
mkdir -p "$(dirname "$table")"
dirs=()
for config in "$configs"/*.toml; do
    out="results/$(basename "$configs")/$(basename "$config" .toml)"
    ./target/release/monoculus run "$config" --out "$out" "$@"
    dirs+=("$out")
done
# shellcheck disable=SC2086
./target/release/monoculus table ${TABLE_ARGS:-} "${dirs[@]}" > "$table"
echo "table written to $table"
