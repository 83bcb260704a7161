#!/bin/sh
# The session-10 end-caps study: scripts/paired.sh with `--end-caps off` (A) vs `auto` (B).
# Usage: [SEEDS="1 2 3"] [COUNT=80] [REFS=1] [REF_SEEDS=4] scripts/endcaps_paired.sh [OUT_DIR]
ARGS_A="--end-caps off" ARGS_B="--end-caps auto" NAME_A=off NAME_B=auto \
  exec "$(dirname "$0")/paired.sh" "${1:-/tmp/endcaps-paired}"
