#!/usr/bin/env bash
# The whole test sequence (`npm test`, and so CI): setup, Rust format/lint/tests, wasm build,
# TypeScript type check, vitest units, Node tests of the built wasm (including the native/wasm
# differential test), then the site build and the browser end-to-end tests when present.
# Fails at the first failing stage.
set -euo pipefail
source "$(dirname "$0")/lib.sh"
cd "$ROOT"

section "setup"
bash scripts/setup.sh

section "cargo fmt --check"
(cd wasm-core && cargo fmt --all -- --check)

section "cargo clippy --all-targets -D warnings"
(cd wasm-core && cargo clippy --quiet --workspace --all-targets -- -D warnings)

# The `ci` profile (wasm-core/Cargo.toml): release optimisation without LTO, a third of the build.
section "cargo test --profile ci"
(cd wasm-core && cargo test --quiet --profile ci --workspace)
# The differential test runs the native CLI against the wasm build.
(cd wasm-core && cargo build --quiet --release -p heartmesh-cli)

section "wasm build"
bash scripts/build-wasm.sh

section "typescript"
tsc --noEmit -p tsconfig.json

section "vitest"
vitest run

section "node tests of the wasm build"
node_tests=(tests/node/*.test.mjs)
bounded 1200 node --test --test-timeout=600000 "${node_tests[@]}"
vitest run -c tests/node/vitest.config.ts

section "core client in chromium (worker + wasm)"
bounded 900 node --test --test-timeout=600000 tests/browser/*.test.mjs

section "site build"
vite build --logLevel warn

e2e_tests=()
for f in tests/e2e/*.test.mjs tests/e2e/*.spec.mjs; do [ -f "$f" ] && e2e_tests+=("$f"); done
if node -e 'process.exit(require("./package.json").scripts?.["test:e2e"] ? 0 : 1)'; then
  section "browser end-to-end tests (npm run test:e2e)"
  npm run --silent test:e2e
elif [ ${#e2e_tests[@]} -gt 0 ]; then
  if [ -x "${CHROMIUM_PATH:-/usr/bin/chromium}" ]; then
    section "browser end-to-end tests"
    bounded 2400 node --test --test-concurrency=1 --test-timeout=600000 "${e2e_tests[@]}"
  else
    echo "browser end-to-end tests need chromium (scripts/setup.sh installs it with apt)" >&2
    exit 1
  fi
fi

section "all tests passed"
