#!/bin/sh
# The session-7 population study (docs/VALIDATION.md "Session 7: population"): 80 shapes drawn from
# 8 reference shapes (4 LV endo, 2 LV epi, 2 RV), aligned and 2 mm / 2 degree misaligned.
# Usage: [SEED=1] [COUNT=80] scripts/population.sh [OUT_DIR] [extra experiment flags]
set -e
M=${MESHES:-$(dirname "$0")/../../shared/data/meshes}
[ -d "$M" ] || M=/work/shared/data/meshes
OUT=${1:-docs/validation}
shift 2>/dev/null || true
BIN=${HEARTMESH:-wasm-core/target/release/heartmesh}
"$BIN" experiment population \
  lv-endo-param=parametric-lv \
  lv-endo-cap="$M/cap-atlas-mean-ED-LV_ENDO-open.obj" \
  lv-endo-spasm="$M/cardiomesh-spasm-LV_endo.obj" \
  lv-endo-bivme="$M/bivme-patient1-ED-LV_ENDO-closed.obj" \
  lv-epi-cap="$M/cap-atlas-mean-ED-LV_EPI-open.obj" \
  lv-epi-spasm="$M/cardiomesh-spasm-LV_epi.obj" \
  rv-bivme="$M/bivme-patient1-ED-RV_ENDO-closed.obj@$M/bivme-patient1-ED-LV_ENDO-closed.obj" \
  rv-spasm="$M/cardiomesh-spasm-RV_endo.obj+$M/cardiomesh-spasm-LV_epi.obj@$M/cardiomesh-spasm-LV_endo.obj" \
  --count "${COUNT:-80}" --seed "${SEED:-1}" -o "$OUT" "$@"
