#!/bin/sh
# Paired study of two sets of reconstruction flags, A and B (first used for `--end-caps off` vs
# `auto`, docs/VALIDATION.md "Session 10: end caps, paired over many acquisitions"): the session-7
# population (8 reference shapes, each draw scaled, bent, warped and posed at random), aligned and
# 2 mm / 2 deg misaligned, for several population seeds, plus the 8 reference shapes unwarped; every
# acquisition is reconstructed twice (A, B) and the pairs are summarised by scripts/paired.py.
# Usage: ARGS_A="--end-caps off" ARGS_B="--end-caps auto" [NAME_A=a] [NAME_B=b] [SEEDS="1 2 3"]
#        [COUNT=80] [REFS=1] [REF_SEEDS=4] scripts/paired.sh [OUT_DIR]
# (names: letters and digits only, they tag the CSV files; REFS=0: population only.)
# Short-axis-only arm (session 12: ends no long-axis curve reaches): add --lax 0 to both flag sets,
# e.g. ARGS_A="--end-caps off --lax 0" ARGS_B="--end-caps auto --lax 0" (every shape, LV or RV,
# sliced without long-axis views; `experiment population|misalignment --lax K`).
# Such stacks get the apex floor by default since session 14: the paper's extrapolation there is
# --no-apex-floor (session 14's study: ARGS_A="--lax 0 --no-apex-floor" ARGS_B="--lax 0").
set -e
OUT=${1:-/tmp/paired}
A=${NAME_A:-a}
B=${NAME_B:-b}
mkdir -p "$OUT"
for s in ${SEEDS:-1 2 3}; do
  for v in "$A" "$B"; do
    if [ "$v" = "$A" ]; then args=${ARGS_A-}; else args=${ARGS_B-}; fi
    # shellcheck disable=SC2086 # the flags are meant to split
    SEED=$s COUNT=${COUNT:-80} "$(dirname "$0")/population.sh" "$OUT" $args --tag "$v-s$s" --quiet
  done
done
# The reference shapes themselves (no warp): aligned once, and 2 mm / 2 deg with REF_SEEDS seeds.
if [ "${REFS:-1}" = 1 ]; then
  M=${MESHES:-/work/shared/data/meshes}
  BIN=${HEARTMESH:-wasm-core/target/release/heartmesh}
  for v in "$A" "$B"; do
    if [ "$v" = "$A" ]; then args=${ARGS_A-}; else args=${ARGS_B-}; fi
    for lv in "0:0 1 ref0" "2:2 ${REF_SEEDS:-4} ref2"; do
      set -- $lv
      # shellcheck disable=SC2086
      "$BIN" experiment misalignment \
        parametric-lv "$M/cap-atlas-mean-ED-LV_ENDO-open.obj" "$M/cardiomesh-spasm-LV_endo.obj" \
        "$M/bivme-patient1-ED-LV_ENDO-closed.obj" "$M/cap-atlas-mean-ED-LV_EPI-open.obj" \
        "$M/cardiomesh-spasm-LV_epi.obj" \
        "$M/bivme-patient1-ED-RV_ENDO-closed.obj@$M/bivme-patient1-ED-LV_ENDO-closed.obj" \
        "$M/cardiomesh-spasm-RV_endo.obj+$M/cardiomesh-spasm-LV_epi.obj@$M/cardiomesh-spasm-LV_endo.obj" \
        --levels "$1" --seeds "$2" $args --tag "$v-$3" -o "$OUT" --quiet
    done
  done
fi
python3 "$(dirname "$0")/paired.py" "$OUT" "$A" "$B"
