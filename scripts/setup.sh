#!/usr/bin/env bash
# Installs everything needed to build and test heartmesh on a machine that has only rustup,
# Node 20 and npm. Idempotent and quiet: a second run takes a few seconds and prints one line.
# Set HEARTMESH_SKIP_CHROMIUM=1 to skip the browser (only the end-to-end tests need it).
set -euo pipefail
source "$(dirname "$0")/lib.sh"
cd "$ROOT"

command -v cargo >/dev/null || { echo "cargo not found: install Rust with rustup first" >&2; exit 1; }
command -v npm >/dev/null || { echo "npm not found: install Node 20 first" >&2; exit 1; }

# Rust: wasm target, formatter and linter.
if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
  echo "setup: adding the wasm32-unknown-unknown target"
  quiet rustup target add wasm32-unknown-unknown
fi
for component in rustfmt clippy; do
  if ! rustup component list --installed | grep -q "^$component"; then
    echo "setup: adding $component"
    quiet rustup component add "$component"
  fi
done

# wasm-bindgen CLI at exactly the version of the wasm-bindgen crate in Cargo.lock.
want="$(wasm_bindgen_version)"
have="$(wasm-bindgen --version 2>/dev/null | awk '{print $2}' || true)"
if [ "$have" != "$want" ]; then
  echo "setup: installing wasm-bindgen-cli $want (compiles from source, a few minutes)"
  # --locked can fail when a locked dependency is missing from the registry index; retry unlocked.
  quiet cargo install wasm-bindgen-cli --version "$want" --locked 2>/dev/null ||
    quiet cargo install wasm-bindgen-cli --version "$want"
fi

# Node packages (vite, vitest, typescript, binaryen's wasm-opt, playwright-core, three).
if [ ! -f node_modules/.package-lock.json ] || [ package-lock.json -nt node_modules/.package-lock.json ]; then
  echo "setup: npm ci"
  quiet npm ci --no-audit --no-fund
fi

# Debian's chromium for the browser tests (never a downloaded browser build).
if [ -z "${HEARTMESH_SKIP_CHROMIUM:-}" ] && ! [ -x /usr/bin/chromium ]; then
  if command -v apt-get >/dev/null; then
    echo "setup: installing chromium (apt)"
    quiet as_root apt-get update
    quiet as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends chromium
  else
    echo "setup: chromium not found and no apt-get: browser tests will be skipped" >&2
  fi
fi

echo "setup: ok (rust $(rustc --version | awk '{print $2}'), wasm-bindgen $want, node $(node --version))"
