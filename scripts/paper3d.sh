#!/usr/bin/env bash
# The paper's sweeps in three dimensions (configs/paper3d/) -> docs/paper3d-table.md.
exec "$(dirname "$0")/run-configs.sh" configs/paper3d docs/paper3d-table.md "$@"
