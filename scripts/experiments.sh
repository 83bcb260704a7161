#!/usr/bin/env bash
# Regenerates the experiment tables and plots of docs/VALIDATION.md (docs/validation/*.csv, *.svg):
# the paper's SAX-count, LAX-count, misalignment and parameter-sweep experiments (Villard, Grau &
# Zacur, J. Imaging 2018, section 3) on the reference shapes in ../shared/data/meshes and the
# built-in parametric LV.
#
#   bash scripts/experiments.sh [sax-count|sax-count-no-lax|lax-count|misalignment|sweep|
#                                sweep-reduction ...]   (default: all six)
#
# Takes about 20 minutes on an idle 2-vCPU machine (see docs/VALIDATION.md for each experiment's
# time); every run is deterministic except the `seconds` column.
set -euo pipefail
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh"

DATA=""
for d in "$ROOT/../shared/data" "$ROOT/../../shared/data" "$ROOT/../../../shared/data"; do
  if [ -d "$d/meshes" ]; then DATA="$(cd "$d" && pwd)"; break; fi
done
[ -n "$DATA" ] || { echo "experiments.sh: shared/data/meshes not found beside the repository" >&2; exit 2; }
M="$DATA/meshes"
OUT="$ROOT/docs/validation"
mkdir -p "$OUT"

section "build heartmesh (release)"
(cd "$ROOT/wasm-core" && cargo build --release -q -p heartmesh-cli)
BIN="$ROOT/wasm-core/target/release/heartmesh"

# LV shapes on their own axes (3 LAX); the RV planned on the LV axis of the same subject (1 LAX).
SHAPES=(
  parametric-lv
  "$M/cap-atlas-mean-ED-LV_ENDO-open.obj"
  "$M/cap-atlas-mean-ED-LV_EPI-open.obj"
  "$M/cardiomesh-spasm-LV_endo.obj"
  "$M/cardiomesh-spasm-LV_epi.obj"
  "$M/bivme-patient1-ED-LV_ENDO-closed.obj"
  "$M/bivme-patient1-ED-RV_ENDO-closed.obj@$M/bivme-patient1-ED-LV_ENDO-closed.obj"
)
# The sweep runs on three shapes (one per kind of surface) to stay within minutes.
SWEEP_SHAPES=("${SHAPES[1]}" "${SHAPES[3]}" "${SHAPES[6]}")

KINDS=("$@")
[ ${#KINDS[@]} -gt 0 ] || KINDS=(sax-count sax-count-no-lax lax-count misalignment sweep sweep-reduction)
for kind in "${KINDS[@]}"; do
  section "experiment $kind"
  start=$SECONDS
  case "$kind" in
    sweep) "$BIN" experiment sweep "${SWEEP_SHAPES[@]}" -o "$OUT" ;;
    # Decimation beyond the x4 subdivision's balance point (0.75) coarsens the mesh every remesh.
    sweep-reduction)
      "$BIN" experiment sweep "${SWEEP_SHAPES[@]}" -o "$OUT" --target-reduction 0.72,0.8 \
        --smoothing-iterations 200 --attractor-spacing 0 --tag reduction ;;
    # Parallel SAX only (no LAX): the paper's "SAX only" case.
    sax-count-no-lax)
      "$BIN" experiment sax-count "${SHAPES[@]}" -o "$OUT" --lax 0 --from 4 --to 14 --step 2 --tag no-lax ;;
    sax-count | lax-count | misalignment) "$BIN" experiment "$kind" "${SHAPES[@]}" -o "$OUT" ;;
    *) echo "experiments.sh: unknown experiment $kind" >&2; exit 2 ;;
  esac
  echo "$kind: $((SECONDS - start)) s"
done
