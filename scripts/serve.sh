#!/usr/bin/env bash
# Sets up, builds the wasm and the static site, and serves dist/ at a fixed local address.
# PORT=5173 by default; HEARTMESH_DEV=1 serves the vite dev server (live reload) instead.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
cd "$ROOT"
PORT="${PORT:-5173}"

HEARTMESH_SKIP_CHROMIUM=1 bash scripts/setup.sh
bash scripts/build-wasm.sh
if [ -n "${HEARTMESH_DEV:-}" ]; then
  echo "heartmesh (dev): http://127.0.0.1:$PORT/"
  exec vite --port "$PORT" --strictPort --host 127.0.0.1
fi
vite build --logLevel warn
echo "heartmesh: http://127.0.0.1:$PORT/"
exec vite preview --port "$PORT" --strictPort --host 127.0.0.1
