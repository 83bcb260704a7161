#!/bin/sh
# Paired study `--end-caps off` vs `auto` (docs/VALIDATION.md "Session 10: end caps, paired over
# many acquisitions"): the session-7 population (8 reference shapes, each draw scaled, bent, warped
# and posed at random), aligned and 2 mm / 2 deg misaligned, for several population seeds; every
# acquisition is reconstructed twice (off, auto) and the pairs are summarised by
# scripts/endcaps_paired.py.
# Usage: [SEEDS="1 2 3"] [COUNT=80] [REFS=1] [REF_SEEDS=4] scripts/endcaps_paired.sh [OUT_DIR]
# (REFS=0: population only; the 8 reference shapes are otherwise also run unwarped.)
set -e
OUT=${1:-/tmp/endcaps-paired}
mkdir -p "$OUT"
for s in ${SEEDS:-1 2 3}; do
  for v in off auto; do
    SEED=$s COUNT=${COUNT:-80} "$(dirname "$0")/population.sh" "$OUT" --end-caps $v --tag "$v-s$s" --quiet
  done
done
# The reference shapes themselves (no warp): aligned once, and 2 mm / 2 deg with REF_SEEDS seeds.
if [ "${REFS:-1}" = 1 ]; then
  M=${MESHES:-/work/shared/data/meshes}
  BIN=${HEARTMESH:-wasm-core/target/release/heartmesh}
  for v in off auto; do
    for lv in "0:0 1 ref0" "2:2 ${REF_SEEDS:-4} ref2"; do
      set -- $lv
      "$BIN" experiment misalignment \
        parametric-lv "$M/cap-atlas-mean-ED-LV_ENDO-open.obj" "$M/cardiomesh-spasm-LV_endo.obj" \
        "$M/bivme-patient1-ED-LV_ENDO-closed.obj" "$M/cap-atlas-mean-ED-LV_EPI-open.obj" \
        "$M/cardiomesh-spasm-LV_epi.obj" \
        "$M/bivme-patient1-ED-RV_ENDO-closed.obj@$M/bivme-patient1-ED-LV_ENDO-closed.obj" \
        "$M/cardiomesh-spasm-RV_endo.obj+$M/cardiomesh-spasm-LV_epi.obj@$M/cardiomesh-spasm-LV_endo.obj" \
        --levels "$1" --seeds "$2" --end-caps $v --tag "$v-$3" -o "$OUT" --quiet
    done
  done
fi
python3 "$(dirname "$0")/endcaps_paired.py" "$OUT"
