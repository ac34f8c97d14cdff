#!/usr/bin/env bash
# Scale bench (issue 46; not run by CI): generated closed surfaces of 1M, 3M
# and 10M triangles, meshed by the native CLI, by Debian's `tetgen -p` (a
# separate process, only up to TETGEN_MAX triangles and TETGEN_TIMEOUT
# seconds: beyond, the row says it was not run or did not finish) and by the
# npm package under Node; then step 1 alone on 1M random points, with and
# without threads, against `tetgen -QNEF`.
#
#   bash tests/bench/bench_scale.sh
#
# Models (tests/bench/gen_surface.cpp, deterministic), written to SCALE_DIR:
#   torus  a bumpy torus: smooth, every triangle in its own plane;
#   steps  a step pyramid on a lattice: CAD-like, a few hundred large flat
#          faces split into unit squares (cdt3d merges them, like tetgen -p).
# Each model is an OFF text file (tetgen reads OFF; the Node rows read the
# same file through the package's reader).
#
# Rows (one process each, timed by run_timed: wall, user CPU, peak RSS):
#   cdt3d         `cdt3d mesh MODEL --json` with its phase clocks (ms)
#   cdt3d@PHASE   `--stop-after PHASE`: the peak memory up to the end of
#                 that phase (delaunay, segments, facets; the full run is
#                 the peak through carving)
#   tetgen -p     `tetgen -pQNEF MODEL` (no output files, like cdt3d without -o)
#   node          `node tests/bench/wasm_scale.mjs MODEL`: the package's
#                 tetrahedralize() in a fresh process (peak: Node plus the
#                 WASM heap, which never shrinks); a model that does not fit
#                 the 4 GiB heap shows the package's error
#   page          `node tests/bench/page_scale.mjs MODEL...`: the demo page
#                 in headless Chromium, each model through its file input
#                 (a table of its own: state, tets, seconds; no memory)
#   reading       `cdt3d info MODEL` against `node tests/bench/wasm_scale.mjs
#                 MODEL --read` (a table of its own: the first read in a
#                 fresh WebAssembly instance against the native reader)
# B/tet is the peak RSS over the final tets of the full native run (for the
# tetgen and node rows, over the same count), so the phases compare.
#
# Environment:
#   SCALE_SIZES="1000000 3000000 10000000"   triangles per model
#   SCALE_KINDS="torus steps"
#   SCALE_DIR=/tmp/cdt3d-scale               where the models go (large files)
#   TETGEN_MAX=3500000                       tetgen only up to this many triangles (both 3M models)
#   TETGEN_TIMEOUT=900  TIMEOUT=900          seconds before tetgen / cdt3d is killed
#   SCALE_MESH=1  SCALE_PHASES=1  SCALE_NODE=1  SCALE_PAGE=1  SCALE_READ=1  SCALE_DELAUNAY=1
#                                            0 skips those rows (SCALE_MESH: the meshing table)
#   READ_RUNS=3                              runs of each reader in the reading table
#   CDT3D_BIN=path                           the native CLI (default .build/native, built)
set -uo pipefail
cd "$(dirname "$0")/../.."
. tests/bench/bench_lib.sh

SIZES=${SCALE_SIZES:-"1000000 3000000 10000000"}
KINDS=${SCALE_KINDS:-"torus steps"}
DIR=${SCALE_DIR:-/tmp/cdt3d-scale}
TG_MAX=${TETGEN_MAX:-3500000}
TG_TIMEOUT=${TETGEN_TIMEOUT:-900}
TIMEOUT=${TIMEOUT:-900}
TOOLS=.build/bench-scale

die() { echo "bench_scale: $*" >&2; exit 1; }

command -v tetgen >/dev/null || CDT3D_EXTRA_APT=tetgen bash tests/scripts/setup.sh ||
  die "tests/scripts/setup.sh failed"
if [ -n "${CDT3D_BIN:-}" ]; then
  BIN=$CDT3D_BIN
else
  build_cli .build/native "$(nproc 2>/dev/null || echo 2)"
  BIN=.build/native/core/cdt3d
fi
[ -x "$BIN" ] || die "$BIN missing"
mkdir -p "$TOOLS" "$DIR" || die "cannot create $TOOLS or $DIR"
for t in gen_surface gen_points run_timed; do
  if [ ! -x "$TOOLS/$t" ] || [ "tests/bench/$t.cpp" -nt "$TOOLS/$t" ]; then
    c++ -O2 -std=c++17 -o "$TOOLS/$t" "tests/bench/$t.cpp" || die "cannot build $t"
  fi
done

# timed LOG_TAG TIMEOUT CMD...: sets T_RC, T_WALL (s), T_USER (s), T_KIB, T_OUT (stdout).
timed() {
  local log out
  log=$(mktemp) out=$(mktemp)
  shift
  local limit=$1
  shift
  "$TOOLS/run_timed" "$limit" "$log" "$@" >"$out" 2>"$out.err"
  T_RC=$?
  local ms
  read -r ms T_USER _ T_KIB <"$log" || true
  T_WALL=$(awk -v m="${ms:-}" 'BEGIN{ if (m == "") print "-"; else printf "%.2f", m / 1000 }')
  T_OUT=$(cat "$out")
  T_ERR=$(tail -c 300 "$out.err")
  rm -f "$log" "$out" "$out.err"
}
s_of() { awk -v m="$1" 'BEGIN{ if (m !~ /^[0-9.]+$/) print "-"; else printf "%.1f", m / 1000 }'; }  # ms -> s
per_tet() { awk -v k="$1" -v t="$2" 'BEGIN{ if (k !~ /^[0-9]+$/ || t !~ /^[0-9]+$/ || t == 0) print "-"; else printf "%.0f", k * 1024 / t }'; }

echo "bench_scale: $(nproc 2>/dev/null || echo ?) cores, load $(cut -d' ' -f1-3 /proc/loadavg) at start, $(date -u '+%Y-%m-%d %H:%M UTC')"
echo "  cdt3d: $BIN; tetgen: $(command -v tetgen) $(dpkg-query -W -f='${Version}' tetgen 2>/dev/null) -pQNEF up to $TG_MAX triangles, ${TG_TIMEOUT}s"
echo
echo "| model | triangles | program | tets | wall s | user s | peak MiB | B/tet | read | delaunay | segments | facets | carve | time/tg | mem/tg |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for n in $SIZES; do
  for kind in $KINDS; do
    model="$DIR/${kind}_$n.off"
    if [ ! -s "$model" ]; then
      "$TOOLS/gen_surface" "$kind" "$n" "$model" >/dev/null || die "gen_surface $kind $n failed"
    fi
    tris=$(sed -n 2p "$model" | awk '{print $2}')
    name="${kind}_$n"
    [ "${SCALE_MESH:-1}" = 1 ] || continue  # the model only (for the later tables)
    # Native, full run.
    timed x "$TIMEOUT" "$BIN" mesh "$model" --json
    tets=$(jnum tets "$T_OUT")
    c_wall=$T_WALL c_user=$T_USER c_kib=$T_KIB
    if [ "$T_RC" -ne 0 ] || [ "$(jnum ok "$T_OUT")" != true ]; then
      echo "| $name | $tris | cdt3d | $(why "$T_RC") $(jmsg "$T_OUT") | $T_WALL | $T_USER | $(mib "$T_KIB") | | | | | | | | |"
      c_wall=- c_kib=-
    else
      echo "| $name | $tris | cdt3d | $tets | $T_WALL | $T_USER | $(mib "$T_KIB") | $(per_tet "$T_KIB" "$tets") | $(s_of "$(jnum msRead "$T_OUT")") | $(s_of "$(jnum msDelaunay "$T_OUT")") | $(s_of "$(jnum msSegments "$T_OUT")") | $(s_of "$(jnum msFacets "$T_OUT")") | $(s_of "$(jnum msCarve "$T_OUT")") | | |"
    fi
    c_row_tets=$tets
    if [ "${SCALE_PHASES:-1}" = 1 ]; then
      for phase in delaunay segments facets; do
        timed x "$TIMEOUT" "$BIN" mesh "$model" --stop-after "$phase"
        echo "| $name | $tris | cdt3d@$phase | | $T_WALL | $T_USER | $(mib "$T_KIB") | $(per_tet "$T_KIB" "$c_row_tets") | | | | | | | |"
      done
    fi
    # TetGen -p (it merges coplanar facets like cdt3d's default).
    if [ "$tris" -le "$TG_MAX" ]; then
      timed x "$TG_TIMEOUT" tetgen -pQNEF "$model"
      if [ "$T_RC" -eq 0 ]; then
        echo "| $name | $tris | tetgen -p | | $T_WALL | $T_USER | $(mib "$T_KIB") | $(per_tet "$T_KIB" "$c_row_tets") | | | | | | $(ratio "$c_wall" "$T_WALL") | $(ratio "$c_kib" "$T_KIB") |"
      else
        echo "| $name | $tris | tetgen -p | $(why "$T_RC") after $T_WALL s | | | $(mib "$T_KIB") | | | | | | | | |"
      fi
    else
      echo "| $name | $tris | tetgen -p | not run (over TETGEN_MAX=$TG_MAX) | | | | | | | | | | | |"
    fi
    if [ "${SCALE_NODE:-1}" = 1 ]; then
      timed x "$TIMEOUT" node tests/bench/wasm_scale.mjs "$model"
      if [ "$(jnum ok "$T_OUT")" = true ]; then
        echo "| $name | $tris | node | $(jnum tets "$T_OUT") | $T_WALL | $T_USER | $(mib "$T_KIB") | $(per_tet "$T_KIB" "$c_row_tets") | $(s_of "$(jnum msRead "$T_OUT")") | $(s_of "$(jnum msDelaunay "$T_OUT")") | $(s_of "$(jnum msSegments "$T_OUT")") | $(s_of "$(jnum msFacets "$T_OUT")") | $(s_of "$(jnum msCarve "$T_OUT")") | | |"
      else
        msg=$(sed -n 's/.*"error":"\(\([^"\\]\|\\.\)*\)".*/\1/p' <<<"$T_OUT")
        code=$(sed -n 's/.*"code":"\([^"]*\)".*/\1/p' <<<"$T_OUT")
        echo "| $name | $tris | node | refused or failed ($(why "$T_RC")): ${code:-?}: ${msg:-$T_ERR} | $T_WALL | $T_USER | $(mib "$T_KIB") | | | | | | | | |"
      fi
    fi
  done
done

# The page: every model through the demo page's file input (page_scale.mjs,
# headless Chromium, a fresh page each), after the other rows.
if [ "${SCALE_PAGE:-1}" = 1 ]; then
  page_models=()
  for n in $SIZES; do
    for kind in $KINDS; do page_models+=("$DIR/${kind}_$n.off"); done
  done
  echo
  echo "The page (headless Chromium, SwiftShader, the page's default options, a fresh page per model):"
  echo
  echo "| model | state | tets | s to meshed | s to shown | threads | error |"
  echo "|---|---|---|---|---|---|---|"
  node tests/bench/page_scale.mjs "${page_models[@]}" 2>/dev/null | while IFS= read -r line; do
    node -e 'const r = JSON.parse(process.argv[1]); const f = (x) => (x == null ? "" : Number(x).toFixed(1));
      console.log(`| ${r.model} | ${r.state} | ${r.tets ?? ""} | ${f(r.meshS)} | ${f(r.shownS)} | ${r.threaded ? 2 : 1} | ${r.code ? r.code + ": " : ""}${r.message ?? ""} |`);' "$line"
  done
fi

# The first read in WebAssembly (issue 46: within 1.5x of native): per
# model, READ_RUNS alternating runs of the native reader (`cdt3d info`, its
# "read time": reading the file, parsing, check_plc) and of the package's
# readPlc() in a fresh Node process (wasm_scale.mjs --read: the first call
# in a fresh instance, then a second); the ratio is of the medians.
if [ "${SCALE_READ:-1}" = 1 ]; then
  runs=${READ_RUNS:-3}
  echo
  echo "Reading (ms, $runs runs each, alternating; median first):"
  echo
  echo "| model | native read | node first readPlc | node second readPlc | first/native |"
  echo "|---|---|---|---|---|"
  median() { tr ' ' '\n' | grep . | sort -n | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
  for n in $SIZES; do
    for kind in $KINDS; do
      model="$DIR/${kind}_$n.off"
      [ -s "$model" ] || continue
      nat="" first="" second=""
      for _ in $(seq "$runs"); do
        nat="$nat $("$BIN" info "$model" 2>/dev/null | awk '/read time/ {printf "%d", $3}')"
        o=$(node tests/bench/wasm_scale.mjs "$model" --read 2>/dev/null)
        first="$first $(jnum msFirst "$o")" second="$second $(jnum msSecond "$o")"
      done
      mn=$(echo "$nat" | median) mf=$(echo "$first" | median) ms=$(echo "$second" | median)
      echo "| ${kind}_$n | $mn ($nat ) | $mf ($first ) | $ms ($second ) | $(ratio "$mf" "$mn") |"
    done
  done
fi

if [ "${SCALE_DELAUNAY:-1}" = 1 ]; then
  pts="$DIR/random_1000000.node"
  [ -s "$pts" ] || "$TOOLS/gen_points" 1000000 "$pts" 1 || die "gen_points failed"
  echo
  echo "Step 1 alone, 1M random points (gen_points seed 1):"
  echo
  echo "| program | tets | wall s | user s | peak MiB | B/tet | mem/tg |"
  echo "|---|---|---|---|---|---|---|"
  timed x "$TG_TIMEOUT" tetgen -QNEF "$pts"
  tg_kib=$T_KIB
  echo "| tetgen -QNEF | | $T_WALL | $T_USER | $(mib "$T_KIB") | | |"
  for flags in "" "--one-thread"; do
    timed x "$TIMEOUT" "$BIN" delaunay --json $flags "$pts"
    tets=$(jnum tets "$T_OUT")
    echo "| cdt3d delaunay ${flags:-(two threads)} | $tets | $T_WALL | $T_USER | $(mib "$T_KIB") | $(per_tet "$T_KIB" "$tets") | $(ratio "$T_KIB" "$tg_kib") |"
  done
fi
echo
echo "load at end: $(cut -d' ' -f1-3 /proc/loadavg)"
