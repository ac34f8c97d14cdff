#!/usr/bin/env bash
# Every test (`npm test`, and CI through .ci/run):
#   1. native build; the Catch2 suite and one ctest per corpus model
#   2. the same suite under AddressSanitizer + UndefinedBehaviorSanitizer
#   3. a short libFuzzer run of every reader and of the pipeline (60 s each)
#   4. the Node suites on the WASM package, with the real-browser tests
# Environment: FUZZ_SECONDS (default 60), CDT3D_SKIP_SANITIZE=1 and
# CDT3D_SKIP_FUZZ=1 skip steps 2 and 3 for a quick local run.
set -euo pipefail
cd "$(dirname "$0")/../.."
bash tests/scripts/setup.sh
bash tests/scripts/build.sh
JOBS=$(nproc 2>/dev/null || echo 2)

echo "== native tests (ctest)"
ctest --test-dir .build/native --output-on-failure -j"$JOBS"

if [ "${CDT3D_SKIP_SANITIZE:-0}" != 1 ]; then
  echo "== sanitizers"
  bash tests/scripts/sanitize.sh
fi
if [ "${CDT3D_SKIP_FUZZ:-0}" != 1 ]; then
  echo "== fuzzing (${FUZZ_SECONDS:-60} s per target)"
  # An internal error of the pipeline fails the run, like a crash, a
  # sanitizer report, a hang, a leak or nondeterminism.
  bash tests/scripts/fuzz.sh
fi

echo "== WASM package, worker (node --test)"
node --test $(ls tests/js/*.test.mjs | grep -v -e '/web\.test\.mjs$' -e '/browser\.test\.mjs$')
# The real-browser files run after the others and one at a time: the web
# page's test that the main thread never blocks for 200 ms measures time,
# and the WASM and CLI tests running beside it on two cores made it fail
# without any fault of the page (1 s long tasks at load 4; none when alone).
echo "== web page and bundles in Chromium (node --test, one file at a time)"
node --test --test-concurrency=1 tests/js/web.test.mjs tests/js/browser.test.mjs
