#!/usr/bin/env bash
# Benchmark of step 1 (issue 3): Delaunay tetrahedralization of uniformly
# random points, native cdt3d and its WASM build under Node against Debian's
# TetGen 1.5 (`tetgen -QNEF POINTS.node`: Delaunay only, no output files; run
# as a separate process only).
#
# One command, from a clean clone (builds what it needs):
#   bash tests/bench/bench_delaunay.sh
#
# What it does:
#   1. installs `tetgen` and `time` (/usr/bin/time) with apt-get if missing;
#   2. builds the native CLI in .build/bench/ (Release, no tests); the WASM rows
#      use the package as built in wasm/dist (npm run build); without it, or
#      without cdt.delaunay in it, the WASM rows say why and are skipped;
#   3. compiles tests/bench/gen_points.cpp and writes uniformly random points
#      in the unit cube (deterministic, seed 1) to .build/bench/bench/random_N.node;
#   4. runs each program BENCH_RUNS times per size, keeps the fastest run (by
#      wall time) with its user CPU time and peak RSS (/usr/bin/time), and runs
#      `tetgen -VNEF` once more to read its own "Delaunay seconds";
#   5. prints one table: times, memory, tet counts (must agree: same points,
#      same Delaunay tetrahedralization up to co-spherical ties, which random
#      points do not have) and the ratios; then the targets for the largest size.
#
# Columns:
#   wall_s     wall time of the whole process (reading the .node text included)
#   user_s     user CPU time of the process: trust it more than wall_s when the
#              machine is busy (it is not inflated by waiting for a core)
#   peak_MiB   peak resident set size of the process (Node's own ~40 MiB and the
#              never-shrinking WASM heap included for wasm)
#   algo_s     the tetrahedralization alone, as each program times it: tetgen's
#              "Delaunay seconds" (-V), cdt3d's sort + insert (`delaunay --json`
#              "ms"), wasm: the module's own msDelaunay (see wasm_delaunay.mjs)
#   */tetgen   program / tetgen for wall, user, memory, algo (< 1: faster/smaller)
#   /native    wasm / native cdt3d for algo_s and user_s (target <= 1.6)
#
# Environment:
#   BENCH_SIZES="100000 1000000"  point counts
#   BENCH_RUNS=3                  runs per program and size (fastest kept)
#   BENCH_TIMEOUT=600             seconds before a run is killed ("timeout")
#   BENCH_WASM=1                  0: skip the WASM rows
#   CDT3D_BIN=.build/bench/core/cdt3d   the native CLI to time (not rebuilt if set)
set -uo pipefail
cd "$(dirname "$0")/../.."

SIZES=${BENCH_SIZES:-"100000 1000000"}
RUNS=${BENCH_RUNS:-3}
TIMEOUT=${BENCH_TIMEOUT:-600}
DO_WASM=${BENCH_WASM:-1}
WORK=.build/bench/bench

die() { echo "bench_delaunay: $*" >&2; exit 1; }

# 1. Tools: the project's set-up plus Debian's tetgen (the reference).
CDT3D_EXTRA_APT=tetgen bash tests/scripts/setup.sh || die "tests/scripts/setup.sh failed"

# 2. The native CLI (incremental: cheap when up to date).
if [ -n "${CDT3D_BIN:-}" ]; then
  BIN=$CDT3D_BIN
else
  BIN=.build/bench/core/cdt3d
  mkdir -p .build/bench
  if [ ! -f .build/bench/CMakeCache.txt ]; then
    cmake -S . -B .build/bench -DCMAKE_BUILD_TYPE=Release -DCDT3D_BUILD_TESTS=OFF \
      >.build/bench/bench-build.log 2>&1 || { cat .build/bench/bench-build.log; die "cmake configure failed"; }
  fi
  cmake --build .build/bench -j"$(nproc 2>/dev/null || echo 2)" --target cdt3d_cli \
    >.build/bench/bench-build.log 2>&1 || { cat .build/bench/bench-build.log; die "building .build/bench/core/cdt3d failed"; }
fi
[ -x "$BIN" ] || die "$BIN missing"

# 3. Inputs.
mkdir -p "$WORK"
if [ ! -x "$WORK/gen_points" ] || [ tests/bench/gen_points.cpp -nt "$WORK/gen_points" ]; then
  c++ -O2 -std=c++17 -o "$WORK/gen_points" tests/bench/gen_points.cpp || die "cannot build gen_points"
fi
for n in $SIZES; do
  f="$WORK/random_$n.node"
  [ -s "$f" ] || "$WORK/gen_points" "$n" "$f" 1 || die "gen_points $n failed"
done

# 4. Timing.
# run_once CMD... sets R_RC (exit code, 124 = timeout), R_WALL (s, from bash's
# microsecond clock), R_USER (s), R_RSS (KiB) and R_OUT (stdout).
run_once() {
  local out log t0 t1
  out=$(mktemp) log=$(mktemp)
  t0=$EPOCHREALTIME
  timeout "$TIMEOUT" /usr/bin/time -f '%U %S %M' -o "$log" "$@" >"$out" 2>"$out.err"
  R_RC=$?
  t1=$EPOCHREALTIME
  R_WALL=$(awk -v a="$t0" -v b="$t1" 'BEGIN{printf "%.3f", b - a}')
  read -r R_USER _ R_RSS < <(tail -n 1 "$log") || true
  R_OUT=$(cat "$out")
  R_ERR=$(tail -c 400 "$out.err")
  rm -f "$out" "$out.err" "$log"
}
# run_best CMD... : the fastest successful run of RUNS (B_* like R_*).
run_best() {
  B_RC=1 B_WALL="" B_USER="" B_RSS="" B_OUT="" B_ERR=""
  for _ in $(seq "$RUNS"); do
    run_once "$@"
    if [ "$R_RC" -ne 0 ]; then
      B_RC=$R_RC B_OUT=$R_OUT B_ERR=$R_ERR
      return
    fi
    if [ -z "$B_WALL" ] || awk -v a="$R_WALL" -v b="$B_WALL" 'BEGIN{exit !(a < b)}'; then
      B_RC=0 B_WALL=$R_WALL B_USER=$R_USER B_RSS=$R_RSS B_OUT=$R_OUT
    fi
  done
}
json_num() {  # json_num KEY TEXT -> the number after "KEY":
  sed -n "s/.*\"$1\":\(-\{0,1\}[0-9.eE+-]*\).*/\1/p" <<<"$2" | head -n 1
}
ratio() { awk -v a="$1" -v b="$2" 'BEGIN{ if (a == "" || b == "" || b + 0 <= 0) print "-"; else printf "%.2f", a / b }'; }
num() { awk -v a="$1" -v d="$2" 'BEGIN{ if (a == "") print "-"; else printf "%." d "f", a }'; }

WASM_NOTE=""
if [ "$DO_WASM" = 1 ]; then
  if [ ! -f wasm/dist/cdt3d.js ] || [ ! -f wasm/dist/cdt3d.wasm ]; then
    # A clean clone: build the package first (setup.sh above installed emscripten).
    echo "bench: building the WASM package (tests/scripts/build.sh)"
    bash tests/scripts/build.sh >/dev/null || true
  fi
  if [ ! -f wasm/dist/cdt3d.js ] || [ ! -f wasm/dist/cdt3d.wasm ]; then
    WASM_NOTE="wasm rows skipped: wasm/dist could not be built (npm run build)"
  elif ! command -v node >/dev/null 2>&1; then
    WASM_NOTE="wasm rows skipped: node not found"
  fi
else
  WASM_NOTE="wasm rows skipped: BENCH_WASM=0"
fi

echo "bench_delaunay: $(nproc 2>/dev/null || echo ?) cores, load $(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo ?) at start, fastest of $RUNS runs, $(date -u '+%Y-%m-%d %H:%M UTC')"
echo "  tetgen: $(command -v tetgen) (Debian $(dpkg-query -W -f='${Version}' tetgen 2>/dev/null || echo '?')), flags -QNEF; cdt3d: $BIN delaunay --json"
hdr='%-8s %-7s %9s %8s %8s %9s %8s | %6s %6s %6s %6s | %7s %7s\n'
printf "$hdr" points program tets wall_s user_s peak_MiB algo_s wall/t user/t mem/t algo/t algo/n user/n
printf '%s\n' "--------------------------------------------------------------------------------------------------------------"
declare -A SUMMARY
for n in $SIZES; do
  f="$WORK/random_$n.node"
  # tetgen: timed runs with -Q, its own Delaunay time from one -V run.
  run_best tetgen -QNEF "$f"
  t_rc=$B_RC t_wall=$B_WALL t_user=$B_USER t_rss=$B_RSS
  t_algo="" t_tets=""
  if [ "$t_rc" -eq 0 ]; then
    run_once tetgen -VNEF "$f"
    t_algo=$(sed -n 's/^Delaunay seconds: *\([0-9.eE+-]*\).*/\1/p' <<<"$R_OUT" | head -n 1)
    t_tets=$(sed -n 's/^ *Mesh tetrahedra: *\([0-9]*\).*/\1/p' <<<"$R_OUT" | head -n 1)
  fi
  row() {  # program rc tets wall user rss_kb algo_s [algo_native user_native]
    local p=$1 rc=$2
    if [ "$rc" -ne 0 ]; then
      local why="failed (exit $rc)"
      [ "$rc" -eq 124 ] && why="timeout after ${TIMEOUT}s"
      printf '%-8s %-7s %s\n' "$n" "$p" "$why"
      return
    fi
    printf "$hdr" "$n" "$p" "${3:--}" "$(num "$4" 2)" "$(num "$5" 2)" "$(num "$(awk -v k="$6" 'BEGIN{print k/1024}')" 1)" \
      "$(num "$7" 3)" "$(ratio "$4" "$t_wall")" "$(ratio "$5" "$t_user")" "$(ratio "$6" "$t_rss")" \
      "$(ratio "$7" "$t_algo")" "$( [ -n "${8:-}" ] && ratio "$7" "$8" || echo -)" "$( [ -n "${9:-}" ] && ratio "$5" "$9" || echo -)"
  }
  row tetgen "$t_rc" "$t_tets" "$t_wall" "$t_user" "$t_rss" "$t_algo"
  [ "$t_rc" -ne 0 ] && echo "  tetgen: $B_ERR"

  run_best "$BIN" delaunay --json "$f"
  c_rc=$B_RC c_wall=$B_WALL c_user=$B_USER c_rss=$B_RSS c_algo="" c_tets=""
  if [ "$c_rc" -eq 0 ]; then
    c_algo=$(awk -v m="$(json_num ms "$B_OUT")" 'BEGIN{print m / 1000}')
    c_tets=$(json_num tets "$B_OUT")
  fi
  row cdt3d "$c_rc" "$c_tets" "$c_wall" "$c_user" "$c_rss" "$c_algo"
  [ "$c_rc" -ne 0 ] && echo "  cdt3d: $B_ERR"
  SUMMARY[$n]="$t_wall $t_user $t_rss $t_algo $c_wall $c_user $c_rss $c_algo"

  if [ -z "$WASM_NOTE" ]; then
    run_best node tests/bench/wasm_delaunay.mjs "$f"
    if [ "$B_RC" -eq 3 ]; then
      WASM_NOTE="wasm rows skipped: $(sed -n 's/.*"error":"\(.*\)".*/\1/p' <<<"$B_OUT")"
    elif [ "$B_RC" -ne 0 ]; then
      row wasm "$B_RC"
      echo "  wasm: $B_OUT $B_ERR"
    else
      w_algo=$(awk -v m="$(json_num msAlgo "$B_OUT")" 'BEGIN{print m / 1000}')
      WASM_API=$(sed -n 's/.*"api":"\([a-z]*\)".*/\1/p' <<<"$B_OUT")
      row wasm 0 "$(json_num tets "$B_OUT")" "$B_WALL" "$B_USER" "$B_RSS" "$w_algo" "$c_algo" "$c_user"
      SUMMARY[$n]+=" $w_algo $B_USER"
    fi
  fi
done
[ -n "$WASM_NOTE" ] && echo "($WASM_NOTE)"
case ${WASM_API:-} in
  delaunay) echo "(wasm: cdt.delaunay(points); algo_s = the module's msDelaunay, or the call's wall time if it reports none)" ;;
  tetrahedralize) echo "(wasm: no cdt.delaunay in this package build; used cdt.tetrahedralize({points, triangles: []}, {stopAfter: 'delaunay'}); algo_s = its stats.msDelaunay; wall/user/peak include copying the mesh out and quality statistics)" ;;
esac

# 5. Targets, for the largest size.
last=""
for n in $SIZES; do last=$n; done
read -r tw tu tm ta cw cu cm ca wa wu <<<"${SUMMARY[$last]:-}"
if [ -n "${cu:-}" ] && [ -n "${tu:-}" ]; then
  verdict() { awk -v r="$1" -v t="$2" 'BEGIN{ if (r == "-") print "n/a"; else print (r + 0 <= t ? "met" : "NOT met") }'; }
  echo
  echo "targets at $last points:"
  r=$(ratio "$cu" "$tu"); echo "  native time   <= 0.5 x tetgen: user $r, wall $(ratio "$cw" "$tw"), algo $(ratio "$ca" "$ta")  -> $(verdict "$r" 0.5) (on user CPU)"
  r=$(ratio "$cm" "$tm"); echo "  native memory <= 0.5 x tetgen: peak RSS $r  -> $(verdict "$r" 0.5)"
  if [ -n "${wa:-}" ]; then
    r=$(ratio "$wa" "$ca"); echo "  wasm time     <= 1.6 x native: algo $r, user $(ratio "$wu" "$cu")  -> $(verdict "$r" 1.6) (on algo time)"
  else
    echo "  wasm time     <= 1.6 x native: not measured"
  fi
fi
