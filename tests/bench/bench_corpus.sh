#!/usr/bin/env bash
# Corpus benchmark (issues 4, 5, 6): the whole CDT pipeline of cdt3d against
# Debian's TetGen 1.5 (`tetgen -pMQ`, run as a separate process only) on every
# model the manifest expects to be valid, with cdt3d's own validation, both
# programs' Steiner point counts by kind and both programs' numerically flat
# tets.
#
# One command, from a clean clone (builds what it needs):
#   bash tests/bench/bench_corpus.sh                # tests/data (MANIFEST.tsv)
#   CORPUS=shared bash tests/bench/bench_corpus.sh  # /work/shared/corpus: classic/ degenerate/ tiny/
#   CORPUS=all bash tests/bench/bench_corpus.sh     # both
#
# Per model (rows of MANIFEST.tsv with expected = valid or valid-plc):
#   cdt3d mesh MODEL --json                  timed run (wall, user CPU, peak RSS)
#   cdt3d mesh MODEL --json --validate       the validator's verdict (untimed)
#   cdt3d mesh MODEL --json --stop-after segments    Steiner points of segment recovery
#   cdt3d mesh MODEL --json --stop-after degeneracy  step 3 (perturbations, break points,
#                                            protection: all 0 with the default symbolic
#                                            perturbation; see CDT3D_FLAGS)
#   plc_to_poly MODEL M.poly                 the same PLC as a TetGen .poly (tetgen cannot
#                                            read OBJ, binary STL or OFF with comments)
#   tetgen -pMQNEF M.poly                    timed run (no output files, like cdt3d without -o)
#   tetgen -pMVNEF M.poly                    its "Steiner points on segments / inside facets /
#                                            inside domain" lines (untimed)
#   tetgen -pMQ M.poly                       once more with output files (untimed): flat_tets
#                                            counts the numerically flat tets of M.1.node/.ele,
#                                            local_delaunay its unconstrained faces that are not
#                                            locally Delaunay (a CDT has none)
# Every process runs under tests/bench/run_timed.cpp, which times it from its
# fork to its end (no shell or /usr/bin/time in the interval), takes user CPU
# and peak RSS from its rusage, and kills it after BENCH_TIMEOUT (default
# 300 s); a hang or a crash becomes a row that says so. tetgen runs in a scratch folder
# (.build/bench/bench/corpus/) so nothing is written next to the models.
#
# Tables:
#   1  time, memory, Steiner points seg/facet/vol, validation, tetgen's, ratios
#      cdt3d/tetgen of wall time, user CPU time and peak RSS (< 1: cdt3d better)
#   2  Steiner points by kind (cdt3d's facet splits too) and numerically flat
#      tets (|6V| / l_max^3 < 1e-12 in doubles), cdt3d beside tetgen, and whether
#      tetgen's mesh is a CDT (its faces that are not locally Delaunay)
#   3  segment recovery (issue 4) and degeneracy removal (issue 5)
#   4  facet recovery (issue 6) and the time of each phase (cdt3d's own ms)
# Failures are printed after the tables with cdt3d's message verbatim.
#
# Environment:
#   CORPUS=data|shared|all   which manifest(s) (default data)
#   BENCH_TIMEOUT=300        seconds per process
#   BENCH_RUNS=1             timed runs per program and model (fastest kept)
#   BENCH_MIN_MS=300         ... and more, up to BENCH_MAX_RUNS=30, until the runs of
#                            that program on that model took this many ms together:
#                            a model of a few ms gets tens of runs on both sides, so
#                            its fastest is not one scheduler hiccup (0: RUNS only)
#   BENCH_FILTER=REGEX       only models whose manifest path matches (grep -E)
#   TETGEN_FLAGS=-pMQNEF     flags of the timed tetgen run (the stats run swaps Q for V,
#                            the run with output files drops N, E and F)
#   CDT3D_FLAGS=             extra flags of every cdt3d mesh run, e.g. --paper-degeneracy
#   CDT3D_BIN=.build/bench/core/cdt3d   the CLI to use (not rebuilt if set)
#   BENCH_WASM=1             0: skip the WASM runs (node tests/bench/wasm_mesh.mjs MODEL,
#                            the package in wasm/ as built in wasm/dist; Table 4's wasm
#                            columns: the module's own msTotal of one call in a fresh
#                            Node process, and its ratio to native msTotal)
set -uo pipefail
cd "$(dirname "$0")/../.."
ROOT=$PWD
. tests/bench/bench_lib.sh  # jnum, jmsg, ratio, mib, why, tg_failed, build_cli

CORPUS=${CORPUS:-data}
TIMEOUT=${BENCH_TIMEOUT:-300}
RUNS=${BENCH_RUNS:-1}
MIN_MS=${BENCH_MIN_MS:-300}
MAX_RUNS=${BENCH_MAX_RUNS:-30}
[ "$MAX_RUNS" -ge "$RUNS" ] || MAX_RUNS=$RUNS
FILTER=${BENCH_FILTER:-}
DO_WASM=${BENCH_WASM:-1}
[ -f wasm/dist/cdt3d.js ] || DO_WASM=0
TG_FLAGS=${TETGEN_FLAGS:--pMQNEF}
TG_VFLAGS=${TG_FLAGS//Q/}V
TG_OFLAGS=${TG_FLAGS//[NEF]/}
read -r -a C_FLAGS <<<"${CDT3D_FLAGS:-}"
STEP3="symbolic perturbation (cdt3d's default: no points; pert/brk/protS/protF are 0)"
for f in "${C_FLAGS[@]}"; do
  [ "$f" = --paper-degeneracy ] && STEP3="Si & Gaertner section 6 (--paper-degeneracy)"
done
WORK=$ROOT/.build/bench/bench/corpus
SHARED=/work/shared/corpus

die() { echo "bench_corpus: $*" >&2; exit 1; }

# 1. Tools: the project's set-up plus Debian's tetgen (the reference).
CDT3D_EXTRA_APT=tetgen bash tests/scripts/setup.sh || die "tests/scripts/setup.sh failed"

# 2. The CLI and the converter (library from the same build tree).
mkdir -p "$WORK"
if [ -n "${CDT3D_BIN:-}" ]; then
  BIN=$CDT3D_BIN
  LIB=$(dirname "$BIN")/libcdt3d.a
else
  BIN=$ROOT/.build/bench/core/cdt3d
  LIB=$ROOT/.build/bench/core/libcdt3d.a
  build_cli .build/bench "$(nproc 2>/dev/null || echo 2)" -DCDT3D_BUILD_TESTS=OFF
fi
[ -x "$BIN" ] || die "$BIN missing"
CONV=$ROOT/.build/bench/bench/plc_to_poly
if [ ! -x "$CONV" ] || [ tests/bench/plc_to_poly.cpp -nt "$CONV" ] || [ "$LIB" -nt "$CONV" ]; then
  c++ -O2 -std=c++17 -I core/include tests/bench/plc_to_poly.cpp "$LIB" -o "$CONV" ||
    die "cannot build tests/bench/plc_to_poly.cpp"
fi
FLAT=$ROOT/.build/bench/bench/flat_tets
if [ ! -x "$FLAT" ] || [ tests/bench/flat_tets.cpp -nt "$FLAT" ] || [ tests/bench/tetgen_lines.hpp -nt "$FLAT" ] || [ core/include/cdt3d/cdt3d.hpp -nt "$FLAT" ]; then
  c++ -O2 -std=c++17 -I core/include tests/bench/flat_tets.cpp -o "$FLAT" ||
    die "cannot build tests/bench/flat_tets.cpp"
fi
LD=$ROOT/.build/bench/bench/local_delaunay
if [ ! -x "$LD" ] || [ tests/bench/local_delaunay.cpp -nt "$LD" ] || [ tests/bench/tetgen_lines.hpp -nt "$LD" ] || [ "$LIB" -nt "$LD" ]; then
  c++ -O2 -std=c++17 -I core/include -I core/src/geometry -I core/src/mesh tests/bench/local_delaunay.cpp "$LIB" -o "$LD" ||
    die "cannot build tests/bench/local_delaunay.cpp"
fi
TIMED=$ROOT/.build/bench/bench/run_timed
if [ ! -x "$TIMED" ] || [ tests/bench/run_timed.cpp -nt "$TIMED" ]; then
  c++ -O2 -std=c++17 tests/bench/run_timed.cpp -o "$TIMED" || die "cannot build tests/bench/run_timed.cpp"
fi
GEN=$ROOT/.build/bench/bench/gen_points
if [ ! -x "$GEN" ] || [ tests/bench/gen_points.cpp -nt "$GEN" ]; then
  c++ -O2 -std=c++17 tests/bench/gen_points.cpp -o "$GEN" || die "cannot build tests/bench/gen_points.cpp"
fi

# Whether run I (1-based) of a program on a model is due: the first RUNS
# always, then more while the runs so far took less than MIN_MS together.
more_runs() {
  [ "$1" -le "$RUNS" ] || awk -v s="$2" -v m="$MIN_MS" 'BEGIN{exit !(s < m)}'
}

# The Delaunay phase against random points (issue 14): the same CLI's
# `delaunay --json` time ("ms": sort and insertion) on as many uniformly
# random points as the model has, generated once per count (seed 1); the
# fastest of as many runs as the model's mesh had (run_best's B_RUNS), as
# the model's own Delaunay time (run_best's B_DEL), so both sides of
# del/rand are measured alike.
random_ms() {
  local n=$1 runs=$2 f="$ROOT/.build/bench/bench/random_$1.node" i ms best=-
  [ -s "$f" ] || "$GEN" "$n" "$f" 1 >/dev/null 2>&1 || { echo -; return; }
  for i in $(seq "$runs"); do
    run_once "$WORK" "$BIN" delaunay "$f" --json
    [ "$R_RC" -eq 0 ] || { echo -; return; }
    ms=$(jnum ms "$R_OUT")
    if [ "$best" = - ] || awk -v a="$ms" -v b="$best" 'BEGIN{exit !(a < b)}'; then best=$ms; fi
  done
  echo "$best"
}

# 3. The models: "path<TAB>name" lines.
models() {
  local manifest dir
  if [ "$CORPUS" = data ] || [ "$CORPUS" = all ]; then
    manifest=tests/data/MANIFEST.tsv dir=$ROOT/tests/data
    awk -F'\t' -v d="$dir" 'NR > 1 && ($7 == "valid" || $7 == "valid-plc") { print d "/" $1 "\t" $1 }' "$manifest"
  fi
  if [ "$CORPUS" = shared ] || [ "$CORPUS" = all ]; then
    manifest=$SHARED/MANIFEST.tsv
    [ -f "$manifest" ] || die "$manifest not found"
    awk -F'\t' -v d="$SHARED" 'NR > 1 && ($7 == "valid" || $7 == "valid-plc") && $1 ~ /^(classic|degenerate|tiny)\// { print d "/" $1 "\t" $1 }' "$manifest"
  fi
}
mapfile -t MODELS < <(models | { if [ -n "$FILTER" ]; then grep -E -- "$FILTER" || true; else cat; fi; })
[ ${#MODELS[@]} -gt 0 ] || die "no models selected (CORPUS=$CORPUS BENCH_FILTER=$FILTER)"

# 4. Running.
# run_once DIR CMD... (in DIR) sets R_RC (124 = timeout), R_WALL (ms, from
# just before the command's fork to its end, by run_timed), R_USER (s),
# R_RSS (KiB), R_OUT (stdout), R_ERR (stderr tail).
run_once() {
  local dir=$1 out log
  shift
  out=$(mktemp) log=$(mktemp)
  (cd "$dir" && exec "$TIMED" "$TIMEOUT" "$log" "$@" >"$out" 2>"$out.err")
  R_RC=$?
  R_WALL="" R_USER="" R_RSS=""
  read -r R_WALL R_USER _ R_RSS < <(grep -E '^[0-9.]+ [0-9.]+ [0-9.]+ [0-9]+$' "$log" | tail -n 1) || true
  [ -n "$R_WALL" ] && R_WALL=$(awk -v w="$R_WALL" 'BEGIN{printf "%.1f", w}')
  R_OUT=$(cat "$out")
  R_ERR=$(tail -c 600 "$out.err")
  rm -f "$out" "$out.err" "$log"
}
smaller() {  # smaller A B: the smaller number, "-" standing for none
  if [ "$2" = - ] || { [ "$1" != - ] && awk -v a="$1" -v b="$2" 'BEGIN{exit !(a < b)}'; }; then
    echo "$1"
  else
    echo "$2"
  fi
}
run_best() {  # run_best DIR CMD... -> B_* of the fastest successful run (or the failure)
  local i spent=0
  B_DEL=-  # the smallest msDelaunay of the runs (the Delaunay phase's own fastest)
  B_TOT=-  # the smallest msTotal of the runs (the mesher's own fastest, start-up apart)
  B_RUNS=0
  for i in $(seq "$MAX_RUNS"); do
    more_runs "$i" "$spent" || break
    B_RUNS=$i
    run_once "$@"
    if [ "$R_RC" -ne 0 ]; then
      B_RC=$R_RC B_WALL=$R_WALL B_USER=$R_USER B_RSS=$R_RSS B_OUT=$R_OUT B_ERR=$R_ERR
      return
    fi
    spent=$(awk -v a="$spent" -v b="$R_WALL" 'BEGIN{print a + b}')
    if [ "$i" = 1 ] || awk -v a="$R_WALL" -v b="$B_WALL" 'BEGIN{exit !(a < b)}'; then
      B_RC=0 B_WALL=$R_WALL B_USER=$R_USER B_RSS=$R_RSS B_OUT=$R_OUT B_ERR=$R_ERR
    fi
    B_DEL=$(smaller "$(jnum msDelaunay "$R_OUT")" "$B_DEL")
    B_TOT=$(smaller "$(jnum msTotal "$R_OUT")" "$B_TOT")
  done
}
tg_steiner() {  # tg_steiner KIND TEXT: sum of "Steiner points <on|in|inside> ...KIND...: N" lines
  awk -v k="$1" 'tolower($0) ~ /steiner points (on|in|inside)/ && tolower($0) ~ k {
      n = split($0, a, ":"); v = a[n]; gsub(/[^0-9]/, "", v); s += v; f = 1 }
    END { print (f ? s : 0) }' <<<"$2"
}

T1=() TK=() T2=() T3=() NOTES=()
total=${#MODELS[@]} i=0
for line in "${MODELS[@]}"; do
  path=${line%%$'\t'*} name=${line#*$'\t'}
  i=$((i + 1))
  printf '\rbench_corpus: %d/%d %-50s' "$i" "$total" "$name" >&2
  stem=$(echo "$name" | tr '/' '_')
  stem=${stem%.*}
  dir=$WORK/$stem
  rm -rf "$dir" && mkdir -p "$dir"

  # cdt3d: timed, then validate, then the two intermediate phases.
  run_best "$dir" "$BIN" mesh "$path" --json "${C_FLAGS[@]}"
  c_rc=$B_RC c_wall=$B_WALL c_user=$B_USER c_rss=$B_RSS c_json=$B_OUT c_err=$B_ERR c_del=$B_DEL c_tot=$B_TOT c_runs=$B_RUNS
  if [ "$c_rc" -eq 0 ]; then
    c_ms=$c_wall
    c_st="$(jnum steinerSegment "$c_json")/$(jnum steinerFacet "$c_json")/$(jnum steinerVolume "$c_json")"
    c_kinds=$(printf '%7s %7s %7s %7s %6s' "$(jnum steinerSegment "$c_json")" "$(jnum steinerFacet "$c_json")" \
      "$(jnum facetSplits "$c_json")" "$(jnum steinerVolume "$c_json")" "$(jnum flatTets "$c_json")")
    run_once "$dir" "$BIN" mesh "$path" --json --validate "${C_FLAGS[@]}"
    if [ "$R_RC" -eq 0 ]; then
      v=$(jnum valid "$R_OUT")
      case $v in true) valid=yes ;; false) valid=NO ;; *) valid=$v ;; esac
      if [ "$v" != true ]; then
        vm=$(sed -n 's/.*"validation":"\(\([^"\\]\|\\.\)*\)".*/\1/p' <<<"$R_OUT" | head -n 1)
        NOTES+=("$name: cdt3d --validate: valid=$v ${vm}")
      fi
    elif [ "$R_RC" -eq 1 ]; then
      valid=NO
      NOTES+=("$name: cdt3d --validate: $(jmsg "$R_OUT")")
    else
      valid=$(why "$R_RC")
      NOTES+=("$name: cdt3d --validate: $(why "$R_RC") ${R_ERR}")
    fi
  else
    c_ms=$(why "$c_rc") c_st="-" valid="-" c_user="" c_rss=""
    c_kinds=$(printf '%7s %7s %7s %7s %6s' - - - - -)
    [ "$c_rc" -eq 1 ] && c_ms=error
    if [ "$c_rc" -eq 1 ]; then
      NOTES+=("$name: cdt3d mesh: $(jmsg "$c_json")")
    else
      NOTES+=("$name: cdt3d mesh: $(why "$c_rc") ${c_err}")
    fi
  fi
  run_once "$dir" "$BIN" mesh "$path" --json --stop-after segments "${C_FLAGS[@]}"
  s_json=$R_OUT s_rc=$R_RC
  run_once "$dir" "$BIN" mesh "$path" --json --stop-after degeneracy "${C_FLAGS[@]}"
  d_json=$R_OUT d_rc=$R_RC
  [ "$s_rc" -ne 0 ] && NOTES+=("$name: cdt3d --stop-after segments: $([ "$s_rc" -eq 1 ] && jmsg "$s_json" || echo "$(why "$s_rc") $R_ERR")")
  [ "$d_rc" -ne 0 ] && NOTES+=("$name: cdt3d --stop-after degeneracy: $([ "$d_rc" -eq 1 ] && jmsg "$d_json" || echo "$(why "$d_rc") $R_ERR")")

  # tetgen on the converted PLC.
  t_ms="-" t_user="" t_rss="" t_st="-" t_ok="-" t_seg="-"
  t_kinds=$(printf '%7s %7s %7s %6s %6s' - - - - -)
  if "$CONV" "$path" "$dir/$stem.poly" 2>"$dir/conv.err"; then
    run_best "$dir" tetgen "$TG_FLAGS" "$stem.poly"
    t_rc=$B_RC
    if [ "$t_rc" -eq 0 ] && ! grep -qiE 'error|assert|terminate' <<<"$B_OUT$B_ERR"; then
      t_ms=$B_WALL t_user=$B_USER t_rss=$B_RSS t_ok=yes
      run_once "$dir" tetgen "$TG_VFLAGS" "$stem.poly"
      t_fac="-" t_vol="-" t_flat="-" t_nld="-"
      if [ "$R_RC" -eq 0 ]; then
        t_seg=$(tg_steiner segment "$R_OUT")
        t_fac=$(tg_steiner facet "$R_OUT") t_vol=$(tg_steiner 'domain|volume' "$R_OUT")
        t_st="$t_seg/$t_fac/$t_vol"
      fi
      # Once more with output files, for its flat tets.
      run_once "$dir" tetgen "$TG_OFLAGS" "$stem.poly"
      if [ "$R_RC" -eq 0 ] && [ -f "$dir/$stem.1.node" ] && [ -f "$dir/$stem.1.ele" ]; then
        if flat_out=$("$FLAT" "$dir/$stem.1.node" "$dir/$stem.1.ele" 2>&1); then
          t_flat=${flat_out%% *}
        else
          t_flat=error
          NOTES+=("$name: flat_tets on tetgen's output: $flat_out")
        fi
        # Is tetgen's mesh a CDT? Unconstrained faces that are not locally
        # Delaunay (tests/bench/local_delaunay.cpp); its .face lists the faces
        # on the input facets.
        if [ -f "$dir/$stem.1.face" ] && ld_out=$("$LD" "$dir/$stem.1.node" "$dir/$stem.1.ele" "$dir/$stem.1.face" 2>&1); then
          t_nld=${ld_out%% *}
        else
          t_nld=error
          NOTES+=("$name: local_delaunay on tetgen's output: ${ld_out:-no .face file}")
        fi
      else
        t_flat=$(why "$R_RC")
        NOTES+=("$name: tetgen $TG_OFLAGS (output files): $(why "$R_RC") $(tail -c 300 <<<"$R_ERR")")
      fi
      rm -f "$dir/$stem".1.*
      t_kinds=$(printf '%7s %7s %7s %6s %6s' "$t_seg" "$t_fac" "$t_vol" "$t_flat" "$t_nld")
    else
      tg_failed "$t_rc" "$B_OUT" "$B_ERR"
      t_ok=$F_WHY
      NOTES+=("$name: tetgen $TG_FLAGS: $F_WHY $F_MSG")
    fi
  else
    t_ok="conv"
    NOTES+=("$name: plc_to_poly: $(cat "$dir/conv.err")")
  fi

  T1+=("$(printf '%-40s %9s %6s %7s %13s %6s | %9s %6s %7s %13s %6s | %6s %6s %6s' \
    "$name" "$c_ms" "${c_user:--}" "$(mib "${c_rss:-}")" "$c_st" "$valid" \
    "$t_ms" "${t_user:--}" "$(mib "$t_rss")" "$t_st" "$t_ok" \
    "$(ratio "$c_ms" "$t_ms")" "$(ratio "${c_user:-}" "$t_user")" "$(ratio "${c_rss:-}" "$t_rss")")")
  c_total=$(awk -v s="$c_st" 'BEGIN{ n = split(s, a, "/"); if (n != 3) print "-"; else print a[1] + a[2] + a[3] }')
  t_total=$(awk -v s="$t_st" 'BEGIN{ n = split(s, a, "/"); if (n != 3) print "-"; else print a[1] + a[2] + a[3] }')
  TK+=("$(printf '%-40s %s | %s | %7s %7s %6s' "$name" "$c_kinds" "$t_kinds" "$c_total" "$t_total" \
    "$(ratio "$c_total" "$t_total")")")
  if [ "$s_rc" -eq 0 ]; then
    s_seg=$(jnum steinerSegment "$s_json") s_miss=$(jnum missingSegments "$s_json")
    s_rules="$(jnum rule1 "$s_json")/$(jnum rule2 "$s_json")/$(jnum rule3 "$s_json")"
    s_split="$(jnum splitProjection "$s_json")/$(jnum splitShell "$s_json")/$(jnum splitRemoved "$s_json")"
    s_acute=$(jnum acuteBoth "$s_json") s_max=$(jnum maxSplits "$s_json") s_ms=$(jnum msSegments "$s_json")
  else
    s_seg=$(why "$s_rc") s_miss="-" s_rules="-" s_split="-" s_acute="-" s_max="-" s_ms="-"
    [ "$s_rc" -eq 1 ] && s_seg=error
  fi
  if [ "$d_rc" -eq 0 ]; then
    # Points added by step 3: Steiner points after it minus after step 2.
    d_added=-
    if [ "$s_rc" -eq 0 ]; then
      d_added=$(awk -v a="$(jnum points "$d_json")" -v b="$(jnum points "$s_json")" 'BEGIN{ print a - b }')
    fi
    d_pert=$(jnum perturbations "$d_json") d_brk=$(jnum breakPoints "$d_json")
    d_ps=$(jnum protectSegment "$d_json") d_pf=$(jnum protectFacet "$d_json")
    d_cols="$(printf '%6s %6s %7s %7s %7s %9s' "$d_pert" "$d_brk" "$d_ps" "$d_pf" "$d_added" \
      "$(jnum msDegeneracy "$d_json")")"
  else
    d_cols="$(printf '%6s' "$([ "$d_rc" -eq 1 ] && echo error || why "$d_rc")")"
  fi
  T2+=("$(printf '%-40s %7s %7s %17s %11s %6s %5s %8s %7s %6s | %s' "$name" "$s_miss" "$s_seg" "$s_split" "$s_rules" "$s_acute" \
    "$s_max" "$s_ms" "$t_seg" "$(ratio "$s_seg" "$t_seg")" "$d_cols")")
  if [ "$c_rc" -eq 0 ]; then
    w_ms="-" w_ratio="-" w_warm="-" w_wratio="-"
    if [ "$DO_WASM" = 1 ]; then
      run_once "$dir" node "$ROOT/tests/bench/wasm_mesh.mjs" "$path"
      if [ "$R_RC" -eq 0 ]; then
        w_ms=$(jnum msTotal "$R_OUT")
        w_ratio=$(ratio "$w_ms" "$c_tot")
        w_warm=$(jnum msTotalWarm "$R_OUT")
        w_wratio=$(ratio "$w_warm" "$c_tot")
      else
        w_ms=$(why "$R_RC")
        NOTES+=("$name: wasm_mesh.mjs: $(why "$R_RC") $R_OUT")
      fi
    fi
    r_ms=$(random_ms "$(jnum inputPoints "$c_json")" "$c_runs")
    T3+=("$(printf '%-40s %7s %7s %7s %8s %7s %8s %6s %6s | %8s %8s %8s %8s %8s %8s %9s | %8s %8s | %9s %6s %9s %6s' "$name" \
      "$(jnum points "$c_json")" "$(jnum tets "$c_json")" "$(jnum missingSubfaces "$c_json")" \
      "$(jnum regions "$c_json")" "$(jnum cavities "$c_json")" "$(jnum largestCavity "$c_json")" \
      "$(jnum fallbacks "$c_json")" "$(printf '%.1f' "$(jnum minDihedral "$c_json")" 2>/dev/null || echo -)" \
      "$(jnum msRead "$c_json")" "$c_del" "$(jnum msSegments "$c_json")" \
      "$(jnum msDegeneracy "$c_json")" "$(jnum msFacets "$c_json")" "$(jnum msCarve "$c_json")" \
      "$(jnum msTotal "$c_json")" "$r_ms" "$(ratio "$c_del" "$r_ms")" "$w_ms" "$w_ratio" \
      "$w_warm" "$w_wratio")")
  else
    T3+=("$(printf '%-40s %7s' "$name" "$c_ms")")
  fi
done
printf '\r%80s\r' '' >&2

# 5. Tables.
echo "bench_corpus: CORPUS=$CORPUS, ${#MODELS[@]} models, $(nproc 2>/dev/null || echo ?) cores, load $(cut -d' ' -f1-3 /proc/loadavg) at end, $(date -u '+%Y-%m-%d %H:%M UTC')"
echo "  cdt3d: $BIN mesh MODEL --json ${CDT3D_FLAGS:+$CDT3D_FLAGS }(timed) / --validate; tetgen $(dpkg-query -W -f='${Version}' tetgen 2>/dev/null) $TG_FLAGS on the converted .poly (Steiner counts from $TG_VFLAGS, flat tets from $TG_OFLAGS); timeout ${TIMEOUT}s; fastest of $RUNS runs (of up to $MAX_RUNS while the runs took under $MIN_MS ms together)"
echo
echo "Table 1: full pipeline. ms = process wall time (fork to exit); user = user CPU s; MiB = peak RSS; Steiner = on segments/in facets/in volume"
h1='%-40s %9s %6s %7s %13s %6s | %9s %6s %7s %13s %6s | %6s %6s %6s\n'
printf "$h1" model cdt3d_ms user MiB Steiner valid tetgen_ms user MiB Steiner ok ms/t user/t mem/t
printf '%s\n' "$(printf '%.0s-' {1..170})"
printf '%s\n' "${T1[@]}"
echo
echo "Table 2: Steiner points by kind and numerically flat tets (|6V| / l_max^3 < 1e-12 in doubles; zero or inverted counts too)"
echo "  seg/facet/vol = Steiner points on segments/in facets/in the volume; fsplit = cdt3d facetSplits (in facets where a"
echo "  missing region could not be recovered otherwise; counted in facet too); flat = cdt3d --json flatTets, tg_flat = flat_tets"
echo "  on tetgen's M.1.node/.ele; tg_nLD = unconstrained interior faces of tetgen's mesh that are not locally Delaunay"
echo "  (exact; > 0: tetgen's output is not a CDT; cdt3d's is checked by --validate); total = all Steiner points,"
echo "  St/t = cdt3d total / tetgen total"
hk='%-40s %7s %7s %7s %7s %6s | %7s %7s %7s %6s %6s | %7s %7s %6s\n'
printf "$hk" model seg facet fsplit vol flat tg_seg tg_fac tg_vol tg_flat tg_nLD total tg_tot St/t
printf '%s\n' "$(printf '%.0s-' {1..140})"
printf '%s\n' "${TK[@]}"
echo
echo "Table 3: segment recovery (issue 4: --stop-after segments) and degeneracy removal (issue 5: --stop-after degeneracy)"
echo "  miss = input segments missing from the Delaunay tetrahedralization (missingSegments); seg_St = cdt3d Steiner points"
echo "  after segment recovery; proj/shell/rm = splitProjection/splitShell/splitRemoved (the default splits, and"
echo "  split points removed again); rules = rule1/rule2/rule3 splits; acute = acuteBoth; max = maxSplits"
echo "  tg_seg = tetgen \"Steiner points on segments\" (whole run); step 3: $STEP3;"
echo "  pert/brk/protS/protF = perturbations/breakPoints/protectSegment/protectFacet; +St3 = points added by step 3"
h2='%-40s %7s %7s %17s %11s %6s %5s %8s %7s %6s | %6s %6s %7s %7s %7s %9s\n'
printf "$h2" model miss seg_St proj/shell/rm rules acute max ms_seg tg_seg seg/t pert brk protS protF +St3 ms_degen
printf '%s\n' "$(printf '%.0s-' {1..178})"
printf '%s\n' "${T2[@]}"
echo
echo "Table 4: facet recovery (issue 6) and cdt3d's own time per phase (ms) in the timed run"
[ "$DO_WASM" = 1 ] && echo "  wasm_ms = msTotal of the WASM package in Node (the first call in a fresh process: V8 compiles each function"
[ "$DO_WASM" = 1 ] && echo "  on its first call and runs most of it in its baseline compiler, Liftoff), wasm/n = wasm_ms / native total;"
[ "$DO_WASM" = 1 ] && echo "  warm_ms = the fastest of more calls in that process (at least 4 and 1.5 s: V8 then runs TurboFan's code),"
[ "$DO_WASM" = 1 ] && echo "  warm/n = warm_ms / native total; native total (for both ratios) = the fastest msTotal of the native timed runs,"
[ "$DO_WASM" = 1 ] && echo "  a fastest-of-runs like warm_ms (the total column below is the fastest run's by wall time)"
echo "  rand_ms = \`cdt3d delaunay\` on as many uniformly random points as the model has (sort + insertion, its --json ms),"
echo "  fastest of as many runs as the model's mesh had; delaunay = the fastest msDelaunay of the model's timed runs (the other phases: the fastest run's)"
echo "  del/rand = delaunay / rand_ms (issue 14: at most 2; delaunay is D0 alone, the perturbation-order search is degen)"
h3='%-40s %7s %7s %7s %8s %7s %8s %6s %6s | %8s %8s %8s %8s %8s %8s %9s | %8s %8s | %9s %6s %9s %6s\n'
printf "$h3" model points tets missing regions cavities largest fallbk minDih read delaunay segments degen facets carve total rand_ms del/rand wasm_ms wasm/n warm_ms warm/n
printf '%s\n' "$(printf '%.0s-' {1..225})"
printf '%s\n' "${T3[@]}"
if [ ${#NOTES[@]} -gt 0 ]; then
  echo
  echo "Failures and messages (verbatim):"
  printf '  %s\n' "${NOTES[@]}"
fi
