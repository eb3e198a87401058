#!/usr/bin/env bash
# The paper's simulation section (configs/paper/, about 30 s on 2 cores) -> docs/paper-table.md.
exec "$(dirname "$0")/run-configs.sh" configs/paper docs/paper-table.md "$@"
