#!/usr/bin/env bash
# The naive strategies against ConvergeLocality (configs/scenarios/, about 80 s on 2
# cores) -> docs/scenarios-table.md, with how often and how much the hull grew.
TABLE_ARGS="--hull" exec "$(dirname "$0")/run-configs.sh" configs/scenarios docs/scenarios-table.md "$@"
