#!/usr/bin/env bash
# Release build of the wasm binding (simd128, see wasm-core/.cargo/config.toml), JS glue by
# wasm-bindgen (--target web: the worker calls init(), Node tests call initSync), then
# binaryen's wasm-opt -O3 from node_modules. Output: web/pkg/ (gitignored).
set -euo pipefail
source "$(dirname "$0")/lib.sh"
cd "$ROOT"

OUT="$ROOT/web/pkg"
WASM_IN="$ROOT/wasm-core/target/wasm32-unknown-unknown/release/heartmesh_wasm.wasm"

command -v wasm-bindgen >/dev/null || { echo "wasm-bindgen not found: run scripts/setup.sh" >&2; exit 1; }
[ -x node_modules/.bin/wasm-opt ] || { echo "wasm-opt not found: run scripts/setup.sh (npm ci)" >&2; exit 1; }

(cd wasm-core && cargo build --quiet --release --target wasm32-unknown-unknown -p heartmesh-wasm)
rm -rf "$OUT"
wasm-bindgen --target web --out-dir "$OUT" --out-name heartmesh_wasm "$WASM_IN"
before=$(wc -c <"$OUT/heartmesh_wasm_bg.wasm")
# Features rustc enables by default for wasm32 (plus simd128) must be enabled for wasm-opt too.
node_modules/.bin/wasm-opt -O3 \
  --enable-simd --enable-bulk-memory --enable-sign-ext --enable-mutable-globals \
  --enable-nontrapping-float-to-int --enable-reference-types --enable-multivalue \
  "$OUT/heartmesh_wasm_bg.wasm" -o "$OUT/heartmesh_wasm_bg.wasm"
after=$(wc -c <"$OUT/heartmesh_wasm_bg.wasm")
gz=$(gzip -9 -c "$OUT/heartmesh_wasm_bg.wasm" | wc -c)
printf 'build-wasm: web/pkg/heartmesh_wasm_bg.wasm %d KB (%d KB before wasm-opt, %d KB gzipped)\n' \
  $((after / 1024)) $((before / 1024)) $((gz / 1024))
