#!/usr/bin/env bash
# Benchmark of step 1 (Delaunay tetrahedralization of a point set):
# `cdt3d delaunay POINTS` against Debian's `tetgen -QNEF POINTS` (TetGen 1.5,
# run as a separate process only; -NEF: no output files, so both only read,
# tetrahedralize and exit).
#
# Usage, from a clean clone (after or instead of tests/scripts/build.sh):
#   bash tests/bench/bench_delaunay.sh
# What it does:
#   1. installs `tetgen` and `time` (/usr/bin/time) with apt-get if missing;
#   2. builds the native CLI in build/ (Release) if build/core/cdt3d is missing;
#   3. compiles tests/bench/gen_points.cpp and writes uniformly random points
#      (deterministic, seed 1) as .node files into build/bench/;
#   4. runs each program BENCH_RUNS times per size and keeps the fastest run
#      (by wall time) with its user time and peak RSS (from /usr/bin/time -v);
#   5. prints a table with the times, peak memory and program/tetgen ratios.
#      On a busy machine trust user_ratio more than wall_ratio.
# Targets (1M points): time ratio <= 0.5 and memory ratio <= 0.5.
#
# Environment:
#   BENCH_SIZES="100000 1000000"  point counts
#   BENCH_RUNS=3                  runs per program and size (best kept)
#   CDT3D_BIN=build/core/cdt3d    the native CLI to time
#   CDT3D_WASM_CMD=""             hook for the WASM build: a command that takes
#                                 a .node path and triangulates it, e.g.
#                                 CDT3D_WASM_CMD="node tests/bench/wasm_delaunay.mjs";
#                                 when set it gets its own rows (timed the same
#                                 way, peak RSS of the node process).
set -euo pipefail
cd "$(dirname "$0")/../.."

SIZES=${BENCH_SIZES:-"100000 1000000"}
RUNS=${BENCH_RUNS:-3}
BIN=${CDT3D_BIN:-build/core/cdt3d}
WASM_CMD=${CDT3D_WASM_CMD:-}
WORK=build/bench

# 1. Tools.
need=()
command -v tetgen >/dev/null 2>&1 || need+=(tetgen)
[ -x /usr/bin/time ] || need+=(time)
if [ ${#need[@]} -gt 0 ]; then
  echo "bench: installing ${need[*]}"
  SUDO=""
  [ "$(id -u)" -eq 0 ] || SUDO="sudo"
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${need[@]}" >/dev/null
fi

# 2. The native CLI.
if [ ! -x "$BIN" ]; then
  echo "bench: building $BIN (Release)"
  cmake -S . -B build -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build build -j"$(nproc 2>/dev/null || echo 2)" --target cdt3d_cli >/dev/null
fi

# 3. Inputs.
mkdir -p "$WORK"
if [ ! -x "$WORK/gen_points" ] || [ tests/bench/gen_points.cpp -nt "$WORK/gen_points" ]; then
  c++ -O2 -std=c++17 -o "$WORK/gen_points" tests/bench/gen_points.cpp
fi
for n in $SIZES; do
  f="$WORK/random_$n.node"
  [ -s "$f" ] || "$WORK/gen_points" "$n" "$f" 1
done

# 4. Timing. run_best LABEL CMD... -> "wall user maxrss_kb" of the fastest run.
run_once() {
  local log
  log=$(mktemp)
  if ! /usr/bin/time -v "$@" >/dev/null 2>"$log"; then
    echo "bench: command failed: $*" >&2
    cat "$log" >&2
    rm -f "$log"
    return 1
  fi
  local wall user rss
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/{n=split($2,t,":"); s=0; for(i=1;i<=n;i++) s=s*60+t[i]; print s}' "$log")
  user=$(awk -F': ' '/User time/{print $2}' "$log")
  rss=$(awk -F': ' '/Maximum resident set size/{print $2}' "$log")
  rm -f "$log"
  echo "$wall $user $rss"
}
run_best() {
  local best="" r
  for _ in $(seq "$RUNS"); do
    r=$(run_once "$@")
    if [ -z "$best" ] || awk -v a="$r" -v b="$best" 'BEGIN{split(a,x," "); split(b,y," "); exit !(x[1] < y[1])}'; then
      best=$r
    fi
  done
  echo "$best"
}

echo "bench: $(nproc 2>/dev/null || echo ?) cores, load $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo ?), best of $RUNS runs"
printf '%-9s %-8s %8s %8s %9s %10s %10s %9s\n' points program wall_s user_s peak_MiB wall_ratio user_ratio mem_ratio
for n in $SIZES; do
  f="$WORK/random_$n.node"
  read -r tw tu tm <<<"$(run_best tetgen -QNEF "$f")"
  read -r cw cu cm <<<"$(run_best "$BIN" delaunay "$f")"
  row() {  # program wall user rss_kb
    awk -v n="$n" -v p="$1" -v w="$2" -v u="$3" -v m="$4" -v tw="$tw" -v tu="$tu" -v tm="$tm" 'BEGIN{
      printf "%-9s %-8s %8.2f %8.2f %9.1f %10.2f %10.2f %9.2f\n", n, p, w, u, m/1024, w/tw, (tu > 0 ? u/tu : 0), m/tm }'
  }
  row tetgen "$tw" "$tu" "$tm"
  row cdt3d "$cw" "$cu" "$cm"
  if [ -n "$WASM_CMD" ]; then
    # shellcheck disable=SC2086  # the hook is a command line
    read -r ww wu wm <<<"$(run_best $WASM_CMD "$f")"
    row wasm "$ww" "$wu" "$wm"
  fi
done
