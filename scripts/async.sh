#!/usr/bin/env bash
# The paper's sweeps under ASYNC (configs/async/, about 100 s on 2 cores) -> docs/async-table.md.
exec "$(dirname "$0")/run-configs.sh" configs/async docs/async-table.md "$@"
