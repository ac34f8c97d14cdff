#!/usr/bin/env bash
# Every test: native Catch2 suite (ctest) and the Node suites on the WASM package.
set -euo pipefail
cd "$(dirname "$0")/../.."
bash tests/scripts/setup.sh
bash tests/scripts/build.sh

echo "== native tests (ctest)"
ctest --test-dir build --output-on-failure -j"$(nproc 2>/dev/null || echo 2)"

echo "== WASM package tests (node --test)"
node --test tests/js/
