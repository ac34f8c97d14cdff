#!/usr/bin/env bash
# Builds the libFuzzer targets of tests/fuzz in .build/fuzz/ (Debian's clang 14,
# -fsanitize=fuzzer,address,undefined) and runs each for FUZZ_SECONDS on its
# seed corpus (.build/fuzz/corpus/<target>, from tests/fuzz/make_corpus.sh;
# new inputs the fuzzer finds are kept there for the next run). Fails when any
# target finds a crash, a sanitizer report, a timeout, a leak or runs out of
# memory; the input is saved as .build/fuzz/artifacts/<target>-crash-<sha1>
# (or -timeout-, -leak-, -oom-). Reproduce one with
#   .build/fuzz/tests/fuzz/<target> .build/fuzz/artifacts/<target>-crash-<sha1>
#
# Environment:
#   FUZZ_SECONDS=60   time per target (CI). A longer local run, e.g. an hour each:
#                       FUZZ_SECONDS=3600 bash tests/scripts/fuzz.sh
#   FUZZ_JOBS=2       targets run at the same time (one core each)
#   FUZZ_TARGETS="fuzz_read_ply fuzz_pipeline"   a subset (default: all seven)
#   CDT3D_FUZZ_ALLOW_INTERNAL=1   fuzz_pipeline lets ErrorCode::Internal results
#                     through (by default they count as crashes: they are bugs)
#
# To keep exploring after a finding (collects every artifact; no pass/fail):
#   .build/fuzz/tests/fuzz/fuzz_pipeline .build/fuzz/corpus/fuzz_pipeline -max_len=64 \
#     -fork=1 -ignore_crashes=1 -max_total_time=1800 -artifact_prefix=/tmp/finds/
# Replay a pipeline input as a .poly model for the CLI:
#   CDT3D_FUZZ_DUMP=/tmp/x.poly .build/fuzz/tests/fuzz/fuzz_pipeline ARTIFACT
#
# Needs clang-14, libclang-rt-14-dev (libFuzzer and the sanitizer runtimes)
# and llvm-14 (llvm-symbolizer, for readable stacks); tests/scripts/setup.sh
# installs them when missing.
set -euo pipefail
cd "$(dirname "$0")/../.."
FUZZ_SECONDS=${FUZZ_SECONDS:-60}
FUZZ_JOBS=${FUZZ_JOBS:-2}
ALL_TARGETS="fuzz_read_stl fuzz_read_off fuzz_read_obj fuzz_read_ply fuzz_read_poly fuzz_read_smesh fuzz_pipeline"
FUZZ_TARGETS=${FUZZ_TARGETS:-$ALL_TARGETS}
BUILD=.build/fuzz

# --- packages: clang-14, libclang-rt-14-dev, llvm-14 come with setup.sh ------
bash tests/scripts/setup.sh

# --- build -------------------------------------------------------------------
cmake -S . -B "$BUILD" -DCMAKE_CXX_COMPILER=clang++-14 \
  -DCDT3D_FUZZ=ON -DCDT3D_SANITIZE=ON -DCDT3D_BUILD_TESTS=OFF -DCDT3D_BUILD_CLI=OFF \
  -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g" >/dev/null
# shellcheck disable=SC2086
cmake --build "$BUILD" -j"$FUZZ_JOBS" --target $FUZZ_TARGETS
bash tests/fuzz/make_corpus.sh "$BUILD/corpus" >/dev/null
mkdir -p "$BUILD/artifacts" "$BUILD/logs"

# --- run ---------------------------------------------------------------------
max_len() {
  case "$1" in
    fuzz_read_stl) echo 16384 ;;  # binary STL: 84 + 50 bytes per triangle
    fuzz_pipeline) echo 64 ;;     # the decoder reads at most ~60 bytes
    *) echo 8192 ;;               # text formats
  esac
}

sym=$(command -v llvm-symbolizer-14 || command -v llvm-symbolizer || true)
export ASAN_OPTIONS="halt_on_error=1:abort_on_error=1:detect_leaks=1${sym:+:external_symbolizer_path=$sym}"
export UBSAN_OPTIONS="halt_on_error=1:abort_on_error=1:print_stacktrace=1"

run_target() {
  local t=$1 rc=0
  "$BUILD/tests/fuzz/$t" "$BUILD/corpus/$t" \
    -max_total_time="$FUZZ_SECONDS" -max_len="$(max_len "$t")" -timeout=10 \
    -rss_limit_mb=2048 -print_final_stats=1 \
    -artifact_prefix="$BUILD/artifacts/$t-" >"$BUILD/logs/$t.log" 2>&1 || rc=$?
  echo "$rc" >"$BUILD/logs/$t.rc"
}

echo "== fuzzing ${FUZZ_SECONDS}s per target, $FUZZ_JOBS at a time (logs in $BUILD/logs)"
start=$(date +%s)
running=0
for t in $FUZZ_TARGETS; do
  rm -f "$BUILD/logs/$t.rc"
  run_target "$t" &
  running=$((running + 1))
  if [ "$running" -ge "$FUZZ_JOBS" ]; then
    wait -n || true
    running=$((running - 1))
  fi
done
wait || true

failed=0
printf '%-18s %12s %8s %6s  %s\n' target executions exec/s corpus result
for t in $FUZZ_TARGETS; do
  log="$BUILD/logs/$t.log"
  rc=$(cat "$BUILD/logs/$t.rc" 2>/dev/null || echo 1)
  execs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  speed=$(sed -n 's/^stat::average_exec_per_sec: *//p' "$log" | tail -1)
  corpus=$(ls "$BUILD/corpus/$t" | wc -l)
  result=ok
  if [ "$rc" != 0 ]; then
    result="FAILED (exit $rc): $(grep -m1 -E 'ERROR: |runtime error:|ALARM|fuzz_read|fuzz_pipeline:' "$log" || echo 'see log')"
    failed=1
  fi
  printf '%-18s %12s %8s %6s  %s\n' "$t" "${execs:-?}" "${speed:-?}" "$corpus" "$result"
done
echo "fuzz: $(($(date +%s) - start)) s of fuzzing"
if [ "$failed" -ne 0 ]; then
  echo "fuzz: inputs saved in $BUILD/artifacts:" >&2
  ls -1 "$BUILD/artifacts" >&2 || true
  for t in $FUZZ_TARGETS; do
    [ "$(cat "$BUILD/logs/$t.rc" 2>/dev/null || echo 1)" = 0 ] && continue
    echo "---- $t (tail of $BUILD/logs/$t.log)" >&2
    tail -40 "$BUILD/logs/$t.log" >&2
  done
  exit 1
fi
