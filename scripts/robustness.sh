#!/usr/bin/env bash
# Both algorithms under observation and movement errors (configs/robustness/, about
# 10 s on 2 cores) -> docs/robustness-table.md.
exec "$(dirname "$0")/run-configs.sh" configs/robustness docs/robustness-table.md "$@"
