#!/usr/bin/env bash
# Builds the Catch2 suite and the CLI with AddressSanitizer + UndefinedBehaviorSanitizer
# (-DCDT3D_SANITIZE=ON, -O1 -g) in .build/asan/ and runs it through ctest.
# Any sanitizer report fails the run: UBSan does not recover
# (-fno-sanitize-recover=all), ASan halts on the first error, LeakSanitizer is on.
#
#   bash tests/scripts/sanitize.sh            # configure (once), build, test
#   CC=clang CXX=clang++ bash tests/scripts/sanitize.sh   # with clang (fresh .build/asan/)
#
# About 6-7 minutes from scratch on a 2-core machine, most of it compiling.
set -euo pipefail
cd "$(dirname "$0")/../.."
JOBS=${JOBS:-$(nproc 2>/dev/null || echo 2)}
BUILD=.build/asan

cmake -S . -B "$BUILD" -DCDT3D_SANITIZE=ON -DCDT3D_BUILD_TESTS=ON -DCDT3D_BUILD_CLI=ON \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" >/dev/null
# The Catch2 suite, and the CLI that the corpus/<model> ctests run.
cmake --build "$BUILD" -j"$JOBS" --target cdt3d_tests cdt3d_cli

# Symbolized stacks when llvm-symbolizer is installed (it comes with llvm-14).
sym=$(command -v llvm-symbolizer || command -v llvm-symbolizer-14 || true)
# More checks, slower (about +35% on the slow tests):
#   CDT3D_ASAN_OPTIONS=detect_stack_use_after_return=1 bash tests/scripts/sanitize.sh
export ASAN_OPTIONS="halt_on_error=1:abort_on_error=1:detect_leaks=1:strict_string_checks=1:check_initialization_order=1${sym:+:external_symbolizer_path=$sym}${CDT3D_ASAN_OPTIONS:+:$CDT3D_ASAN_OPTIONS}"
export UBSAN_OPTIONS="halt_on_error=1:abort_on_error=1:print_stacktrace=1"
export LSAN_OPTIONS="report_objects=1"

echo "== native tests under ASan + UBSan (ctest in $BUILD)"
log="$BUILD/sanitize-ctest.log"
set +e
ctest --test-dir "$BUILD" --output-on-failure -j"$JOBS" 2>&1 | tee "$log"
rc=${PIPESTATUS[0]}
set -e
# A report in a test that still passed (e.g. printed from a child process)
# must fail the run too.
if grep -qE "ERROR: (Address|Leak)Sanitizer|runtime error:" "$log"; then
  echo "sanitize: sanitizer report found in $log" >&2
  exit 1
fi
exit "$rc"
