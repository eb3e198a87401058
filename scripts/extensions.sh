#!/usr/bin/env bash
# The experiments beyond the paper (configs/extensions/: limited visibility, schedules from
# files, faulty robots, the adversary, fat robots, the impossibility construction; about
# 80 s on 2 cores) -> docs/extensions-table.md, and the figures docs/extensions.md shows.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/run-configs.sh configs/extensions docs/extensions-table.md "$@"
./target/release/monoculus plot results/extensions/range_locality > /dev/null
cp results/extensions/range_locality/figures/rho_vs_vision_range.png docs/figures/range_locality_rho.png
./target/release/monoculus plot results/extensions/file_schedule > /dev/null
cp results/extensions/file_schedule/figures/rho_vs_scheduler_file.png docs/figures/file_schedule_rho.png
./target/release/monoculus plot results/extensions/faults_crash_locality > /dev/null
cp results/extensions/faults_crash_locality/figures/rho_vs_faults_count.png docs/figures/faults_crash_locality_rho.png
./target/release/monoculus plot results/extensions/adversary_locality > /dev/null
cp results/extensions/adversary_locality/figures/tau_vs_scheduler_fairness.png docs/figures/adversary_locality_tau.png
./target/release/monoculus plot results/extensions/fat_quadrant > /dev/null
cp results/extensions/fat_quadrant/figures/rho_vs_vision_robot_radius.png docs/figures/fat_quadrant_rho.png
./target/release/monoculus impossibility --out results/extensions/impossibility > /dev/null
cp results/extensions/impossibility/impossibility.png docs/figures/impossibility.png
