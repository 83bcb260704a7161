# Shared helpers for the scripts in this folder (sourced, not run).
# shellcheck shell=bash

ROOT="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
export PATH="${CARGO_HOME:-$HOME/.cargo}/bin:$ROOT/node_modules/.bin:$PATH"

# Runs a command silently; shows its output only when it fails.
quiet() {
  local log
  log="$(mktemp)"
  if "$@" >"$log" 2>&1; then
    rm -f "$log"
  else
    local status=$?
    echo "FAILED ($status): $*" >&2
    tail -n 60 "$log" >&2
    rm -f "$log"
    return "$status"
  fi
}

# The wasm-bindgen version locked in Cargo.lock (the CLI must match it exactly).
wasm_bindgen_version() {
  awk '/^name = "wasm-bindgen"$/ { getline; gsub(/version = |"/, ""); print; exit }' \
    "$ROOT/wasm-core/Cargo.lock"
}

as_root() {
  if [ "$(id -u)" = 0 ]; then "$@"; elif command -v sudo >/dev/null; then sudo "$@"; else
    echo "need root for: $*" >&2
    return 1
  fi
}

# Each section says when it starts (minutes into the script), so a slow CI shows where time went.
section() { printf '\n== %s (at %dm%02ds)\n' "$*" $((SECONDS / 60)) $((SECONDS % 60)); }

# Runs a test command with a wall-clock bound: a hung browser or server then fails this step with a
# clear line instead of holding CI until its 90-minute limit (where nothing at all is reported).
bounded() {
  local seconds=$1
  shift
  local status=0
  timeout --kill-after=30 "$seconds" "$@" || status=$?
  if [ "$status" = 124 ] || [ "$status" = 137 ]; then
    echo "TIMED OUT after ${seconds}s: $*" >&2
  fi
  return "$status"
}
