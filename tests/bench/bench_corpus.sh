#!/usr/bin/env bash
# Corpus benchmark (issues 4, 5, 6): the whole CDT pipeline of cdt3d against
# Debian's TetGen 1.5 (`tetgen -pMQ` and `tetgen -pQ`, run as separate
# processes only) and, when ATTENE_CDT names its binary, the Diazzi-Attene CDT
# (github.com/MarcoAttene/CDT; never part of this repository), on every model
# the manifest expects to be valid, with cdt3d's own validation, the
# programs' Steiner point counts by kind and numerically flat tets.
#
# cdt3d's default (the timed run) merges exactly coplanar facets into flat
# faces (merge_flat_facets), like `tetgen -p` without -M and like the
# Diazzi-Attene CDT; `--keep-triangles` keeps every triangle a facet, like
# `tetgen -pM`. So the like-for-like pairs are cdt3d default / tetgen -p /
# Attene and cdt3d --keep-triangles / tetgen -pM (Tables 5 and 6). TetGen -p
# merges within a tolerance, so its mesh may miss segments of the exactly
# merged PLC; tetgen_vs_merged (tg_p_missing) and local_delaunay (tg_p_nLD)
# tell whether it is a CDT of that PLC (cdt_ok).
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
#   cdt3d mesh MODEL --json --keep-triangles Steiner points without flat-face merging (untimed)
#   tetgen -pQNEF M.poly                     tetgen -p (flat faces merged by TetGen): timed like
#                                            -pMQNEF; Steiner points from -pVNEF (untimed)
#   tetgen -pQe M.poly                       with output files (untimed), -e for M.1.edge (every
#                                            edge): tetgen_vs_merged MODEL M.1.node M.1.edge counts
#                                            the segments of the exactly merged PLC (merge_flat_facets,
#                                            plc_segments) that are no chain of TetGen edges
#                                            (tg_p_missing), local_delaunay the faces that are not
#                                            locally Delaunay (tg_p_nLD); both 0: cdt_ok = yes, the
#                                            -p mesh is a CDT of the exactly merged PLC
#   tetgen_vs_merged --off MODEL M.off       (with ATTENE_CDT) the PLC as a plain OFF triangle
#                                            surface in a scratch folder (models that are not one:
#                                            polygons, explicit segments, holes, regions: "n/a")
#   $ATTENE_CDT -l M.off                     timed like the others (in that folder; it writes
#                                            M.off.tet there and appends a row to ./cdt_log.csv):
#                                            Steiner points and its own time (the sum of its 4 phase
#                                            columns, fastest of the runs) from cdt_log.csv
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
#   5  flat faces: cdt3d default vs --keep-triangles vs tetgen -p (by kind,
#      tg_p_missing, tg_p_nLD, cdt_ok) vs Diazzi-Attene (Steiner points, its
#      algorithm ms, its process wall ms, cdt3d default / Attene)
#   6  summary: per model the Steiner points of cdt3d default, Attene and
#      tetgen -p (with cdt_ok); the models where cdt3d adds more than Attene,
#      or more than tetgen -p where tetgen -p's mesh is cdt_ok; the total wall
#      time over the models of cdt3d default, tetgen -p and tetgen -pM (and of
#      cdt3d and Attene over the models Attene ran), and the ratios of totals
# Table 1 ends with tetgen -p's wall/user/RSS/Steiner and ms/tp = cdt3d wall /
# tetgen -p wall. Failures are printed after the tables with cdt3d's message verbatim.
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
#   TETGEN_P_FLAGS=-pQNEF    flags of the timed tetgen -p run (default: TETGEN_FLAGS without M;
#                            stats run: Q swapped for V; output files: N, E, F dropped, e added)
#   ATTENE_CDT=              the Diazzi-Attene `cdt` binary (e.g. /tmp/attene/build/cdt); unset:
#                            no Attene columns
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
TGP_FLAGS=${TETGEN_P_FLAGS:-${TG_FLAGS//M/}}
TGP_VFLAGS=${TGP_FLAGS//Q/}V
TGP_OFLAGS=${TGP_FLAGS//[NEF]/}e
ATT=${ATTENE_CDT:-}
read -r -a C_FLAGS <<<"${CDT3D_FLAGS:-}"
STEP3="symbolic perturbation (cdt3d's default: no points; pert/brk/protS/protF are 0)"
for f in "${C_FLAGS[@]}"; do
  [ "$f" = --paper-degeneracy ] && STEP3="Si & Gaertner section 6 (--paper-degeneracy)"
done
WORK=$ROOT/.build/bench/bench/corpus
SHARED=/work/shared/corpus

die() { echo "bench_corpus: $*" >&2; exit 1; }
[ -z "$ATT" ] || [ -x "$ATT" ] || die "ATTENE_CDT=$ATT is not an executable"

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
TVM=$ROOT/.build/bench/bench/tetgen_vs_merged
if [ ! -x "$TVM" ] || [ tests/bench/tetgen_vs_merged.cpp -nt "$TVM" ] || [ tests/bench/tetgen_lines.hpp -nt "$TVM" ] || [ "$LIB" -nt "$TVM" ]; then
  c++ -O2 -std=c++17 -I core/include tests/bench/tetgen_vs_merged.cpp "$LIB" -o "$TVM" ||
    die "cannot build tests/bench/tetgen_vs_merged.cpp"
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

isnum() { [[ $1 =~ ^[0-9]+([.][0-9]+)?$ ]]; }
st_total() {  # st_total "seg/facet/vol" -> their sum, or "-"
  awk -v s="$1" 'BEGIN{ n = split(s, a, "/"); if (n != 3 || s ~ /[^0-9\/]/) print "-"; else print a[1] + a[2] + a[3] }'
}
addto() { awk -v a="$1" -v b="$2" 'BEGIN{ print a + b }'; }

T1=() TK=() T2=() T3=() T5=() T6=() NOTES=() MORE_ATT=() MORE_TGP=()
# Totals (Table 6): wall ms of cdt3d default, tetgen -p, tetgen -pM over the models all
# three meshed; cdt3d wall and msTotal, Attene wall and algorithm ms over the models both meshed.
sum_c=0 sum_tp=0 sum_tm=0 n_sum=0 sum_ca=0 sum_cat=0 sum_aw=0 sum_aa=0 n_att=0
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
  conv_ok=0
  if "$CONV" "$path" "$dir/$stem.poly" 2>"$dir/conv.err"; then
    conv_ok=1
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

  # cdt3d --keep-triangles (untimed): every input facet kept, like tetgen -pM.
  k_seg=- k_fac=- k_vol=- k_total=-
  run_once "$dir" "$BIN" mesh "$path" --json --keep-triangles "${C_FLAGS[@]}"
  if [ "$R_RC" -eq 0 ]; then
    k_seg=$(jnum steinerSegment "$R_OUT") k_fac=$(jnum steinerFacet "$R_OUT") k_vol=$(jnum steinerVolume "$R_OUT")
    k_total=$(st_total "$k_seg/$k_fac/$k_vol")
  else
    k_seg=$([ "$R_RC" -eq 1 ] && echo error || why "$R_RC")
    NOTES+=("$name: cdt3d --keep-triangles: $([ "$R_RC" -eq 1 ] && jmsg "$R_OUT" || echo "$(why "$R_RC") $R_ERR")")
  fi

  # tetgen -p on the same .poly: TetGen merges coplanar facets itself (within its tolerance).
  p_ms="-" p_user="" p_rss="" p_st="-" p_ok="-" p_seg="-" p_fac="-" p_vol="-" p_miss="-" p_nld="-"
  if [ "$conv_ok" = 1 ]; then
    run_best "$dir" tetgen "$TGP_FLAGS" "$stem.poly"
    if [ "$B_RC" -eq 0 ] && ! grep -qiE 'error|assert|terminate' <<<"$B_OUT$B_ERR"; then
      p_ms=$B_WALL p_user=$B_USER p_rss=$B_RSS p_ok=yes
      run_once "$dir" tetgen "$TGP_VFLAGS" "$stem.poly"
      if [ "$R_RC" -eq 0 ]; then
        p_seg=$(tg_steiner segment "$R_OUT")
        p_fac=$(tg_steiner facet "$R_OUT") p_vol=$(tg_steiner 'domain|volume' "$R_OUT")
        p_st="$p_seg/$p_fac/$p_vol"
      fi
      # With output files (and every edge, -e): is the -p mesh a CDT of the exactly merged PLC?
      run_once "$dir" tetgen "$TGP_OFLAGS" "$stem.poly"
      if [ "$R_RC" -eq 0 ] && [ -f "$dir/$stem.1.node" ] && [ -f "$dir/$stem.1.ele" ] && [ -f "$dir/$stem.1.edge" ]; then
        if [ -f "$dir/$stem.1.face" ] && ld_out=$("$LD" "$dir/$stem.1.node" "$dir/$stem.1.ele" "$dir/$stem.1.face" 2>&1); then
          p_nld=${ld_out%% *}
        else
          p_nld=error
          NOTES+=("$name: local_delaunay on tetgen $TGP_OFLAGS's output: ${ld_out:-no .face file}")
        fi
        if tv_out=$("$TVM" "$path" "$dir/$stem.1.node" "$dir/$stem.1.edge" 2>&1); then
          p_miss=${tv_out%% *}
        else
          p_miss=error
          NOTES+=("$name: tetgen_vs_merged: $tv_out")
        fi
      else
        p_miss=$(why "$R_RC") p_nld=$(why "$R_RC")
        NOTES+=("$name: tetgen $TGP_OFLAGS (output files): $(why "$R_RC") $(tail -c 300 <<<"$R_ERR")")
      fi
      rm -f "$dir/$stem".1.*
    else
      tg_failed "$B_RC" "$B_OUT" "$B_ERR"
      p_ok=$F_WHY
      NOTES+=("$name: tetgen $TGP_FLAGS: $F_WHY $F_MSG")
    fi
  else
    p_ok=conv
  fi
  p_total=$(st_total "$p_st")
  p_cdt=-
  if isnum "$p_miss" && isnum "$p_nld"; then
    p_cdt=no
    [ "$p_miss" -eq 0 ] && [ "$p_nld" -eq 0 ] && p_cdt=yes
  fi

  # The Diazzi-Attene CDT on the PLC as an OFF triangle surface, in a scratch folder.
  a_st=- a_alg=- a_wall=-
  if [ -n "$ATT" ]; then
    adir=$dir/attene
    mkdir -p "$adir"
    "$TVM" --off "$path" "$adir/$stem.off" 2>"$dir/off.err"
    off_rc=$?
    if [ "$off_rc" -eq 0 ]; then
      rm -f "$adir/cdt_log.csv"
      run_best "$adir" "$ATT" -l "$stem.off"
      # One row per run: Steiner (column 10), the fastest sum of the 4 phase columns.
      arow=$(awk -F', ' 'NR > 1 && NF >= 15 { t = $2 + $3 + $4 + $5; if (best == "" || t < best) best = t;
          st = $10; poly = $7 } END { if (st != "") print st, best, poly }' "$adir/cdt_log.csv" 2>/dev/null)
      if [ "$B_RC" -eq 0 ] && [ -n "$arow" ]; then
        read -r a_st a_alg a_poly <<<"$arow"
        a_wall=$B_WALL
        [ "$a_poly" = True ] || NOTES+=("$name: Attene cdt: Is_Polyhedron=$a_poly (then every tet but the ghosts is inner)")
      else
        a_st=$(why "$B_RC")
        [ "$B_RC" -eq 0 ] && a_st=error
        NOTES+=("$name: Attene cdt -l: $a_st $(tail -c 300 <<<"$B_OUT"$'\n'"$B_ERR" | tr '\n' ' ')")
      fi
      rm -f "$adir/$stem.off.tet"
    elif [ "$off_rc" -eq 3 ]; then
      a_st=n/a
      NOTES+=("$name: Attene cdt: n/a: $(sed 's/^tetgen_vs_merged: [^:]*: //' "$dir/off.err")")
    else
      a_st=conv
      NOTES+=("$name: tetgen_vs_merged --off: $(cat "$dir/off.err")")
    fi
  fi

  T1+=("$(printf '%-40s %9s %6s %7s %13s %6s | %9s %6s %7s %13s %6s | %6s %6s %6s | %9s %6s %7s %13s %6s | %6s' \
    "$name" "$c_ms" "${c_user:--}" "$(mib "${c_rss:-}")" "$c_st" "$valid" \
    "$t_ms" "${t_user:--}" "$(mib "$t_rss")" "$t_st" "$t_ok" \
    "$(ratio "$c_ms" "$t_ms")" "$(ratio "${c_user:-}" "$t_user")" "$(ratio "${c_rss:-}" "$t_rss")" \
    "$p_ms" "${p_user:--}" "$(mib "$p_rss")" "$p_st" "$p_ok" "$(ratio "$c_ms" "$p_ms")")")
  c_total=$(awk -v s="$c_st" 'BEGIN{ n = split(s, a, "/"); if (n != 3) print "-"; else print a[1] + a[2] + a[3] }')
  t_total=$(awk -v s="$t_st" 'BEGIN{ n = split(s, a, "/"); if (n != 3) print "-"; else print a[1] + a[2] + a[3] }')
  # Table 5 (flat faces) and Table 6 (summary).
  c_seg=- c_fac=- c_vol=- c_fe=- c_mf=-
  if [ "$c_rc" -eq 0 ]; then
    c_seg=$(jnum steinerSegment "$c_json") c_fac=$(jnum steinerFacet "$c_json") c_vol=$(jnum steinerVolume "$c_json")
    c_fe=$(jnum flatEdges "$c_json") c_mf=$(jnum mergedFacets "$c_json")
  fi
  T5+=("$(printf '%-40s %6s %6s %6s %7s %6s %6s | %6s %6s %6s %7s %6s | %6s %6s %6s %7s %6s | %7s %7s %6s | %7s %8s %8s %6s' \
    "$name" "$c_seg" "$c_fac" "$c_vol" "$c_total" "$c_fe" "$c_mf" \
    "$k_seg" "$k_fac" "$k_vol" "$k_total" "$(ratio "$k_total" "$t_total")" \
    "$p_seg" "$p_fac" "$p_vol" "$p_total" "$(ratio "$c_total" "$p_total")" \
    "$p_miss" "$p_nld" "$p_cdt" "$a_st" "$a_alg" "$a_wall" "$(ratio "$c_total" "$a_st")")")
  more=""
  if isnum "$c_total" && isnum "$a_st" && [ "$c_total" -gt "$a_st" ]; then
    more="> Attene"
    MORE_ATT+=("$name ($c_total > $a_st)")
  fi
  if [ "$p_cdt" = yes ] && isnum "$c_total" && isnum "$p_total" && [ "$c_total" -gt "$p_total" ]; then
    more="${more:+$more, }> tetgen -p"
    MORE_TGP+=("$name ($c_total > $p_total)")
  fi
  T6+=("$(printf '%-40s %7s %7s %7s %7s %6s | %7s %7s | %s' "$name" "$c_total" "$k_total" "$a_st" "$p_total" "$p_cdt" \
    "$(ratio "$c_total" "$a_st")" "$(ratio "$c_total" "$p_total")" "${more:--}")")
  if isnum "$c_ms" && isnum "$p_ms" && isnum "$t_ms"; then
    sum_c=$(addto "$sum_c" "$c_ms") sum_tp=$(addto "$sum_tp" "$p_ms") sum_tm=$(addto "$sum_tm" "$t_ms")
    n_sum=$((n_sum + 1))
  fi
  if isnum "$c_ms" && isnum "$a_wall" && isnum "$c_tot" && isnum "$a_alg"; then
    sum_ca=$(addto "$sum_ca" "$c_ms") sum_cat=$(addto "$sum_cat" "$c_tot")
    sum_aw=$(addto "$sum_aw" "$a_wall") sum_aa=$(addto "$sum_aa" "$a_alg")
    n_att=$((n_att + 1))
  fi
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
echo "  cdt3d: $BIN mesh MODEL --json ${CDT3D_FLAGS:+$CDT3D_FLAGS }(timed; flat faces merged) / --validate / --keep-triangles (untimed); tetgen $(dpkg-query -W -f='${Version}' tetgen 2>/dev/null) $TG_FLAGS on the converted .poly (Steiner counts from $TG_VFLAGS, flat tets from $TG_OFLAGS); timeout ${TIMEOUT}s; fastest of $RUNS runs (of up to $MAX_RUNS while the runs took under $MIN_MS ms together)"
echo "  tetgen -p: $TGP_FLAGS (timed), $TGP_VFLAGS (Steiner counts), $TGP_OFLAGS (CDT check); Diazzi-Attene CDT: ${ATT:-not run (set ATTENE_CDT)}${ATT:+ -l M.off (timed)}"
echo
echo "Table 1: full pipeline. ms = process wall time (fork to exit); user = user CPU s; MiB = peak RSS; Steiner = on segments/in facets/in volume"
echo "  cdt3d: its default (flat faces merged); tetgen: $TG_FLAGS; ms/t user/t mem/t: cdt3d / tetgen $TG_FLAGS;"
echo "  tgp_*: tetgen $TGP_FLAGS (TetGen merges coplanar facets, within its tolerance); ms/tp = cdt3d_ms / tgp_ms (totals: Table 6)"
h1='%-40s %9s %6s %7s %13s %6s | %9s %6s %7s %13s %6s | %6s %6s %6s | %9s %6s %7s %13s %6s | %6s\n'
printf "$h1" model cdt3d_ms user MiB Steiner valid tetgen_ms user MiB Steiner ok ms/t user/t mem/t tgp_ms user MiB tgp_Steiner tgp_ok ms/tp
printf '%s\n' "$(printf '%.0s-' {1..221})"
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
echo
echo "Table 5: flat faces. Steiner points (seg/facet/vol, total) of cdt3d's default (flat faces merged exactly;"
echo "  flatE = flatEdges, mrgF = mergedFacets), of cdt3d --keep-triangles (kt/tM = its total / tetgen $TG_FLAGS total),"
echo "  of tetgen $TGP_FLAGS (St/tp = cdt3d default total / tetgen -p total) and of the Diazzi-Attene CDT (att_St;"
echo "  att_ms = its own time, the sum of its 4 phases, fastest run; att_wall = its process wall ms (writes M.off.tet);"
echo "  St/att = cdt3d default total / att_St; n/a: not a plain triangle surface). tg_p_missing = segments of the exactly"
echo "  merged PLC that are no chain of edges of tetgen -p's mesh (TetGen merges within a tolerance), tg_p_nLD = its"
echo "  unconstrained faces that are not locally Delaunay; cdt_ok = yes when both are 0: tetgen -p's mesh is a CDT of"
echo "  the exactly merged PLC, so its Steiner count compares with cdt3d's default"
h5='%-40s %6s %6s %6s %7s %6s %6s | %6s %6s %6s %7s %6s | %6s %6s %6s %7s %6s | %7s %7s %6s | %7s %8s %8s %6s\n'
printf "$h5" model seg facet vol total flatE mrgF kt_seg kt_fac kt_vol kt_tot kt/tM tp_seg tp_fac tp_vol tp_tot St/tp \
  tg_p_missing tg_p_nLD cdt_ok att_St att_ms att_wall St/att
printf '%s\n' "$(printf '%.0s-' {1..205})"
printf '%s\n' "${T5[@]}"
echo
echo "Table 6: summary. Steiner points in all: cdt3d default (flat faces merged), cdt3d --keep-triangles, Diazzi-Attene,"
echo "  tetgen $TGP_FLAGS (cdt_ok: its mesh is a CDT of the exactly merged PLC); St/att, St/tp = cdt3d default / theirs;"
echo "  more = cdt3d default adds more than Attene, or more than tetgen -p where cdt_ok = yes"
h6='%-40s %7s %7s %7s %7s %6s | %7s %7s | %s\n'
printf "$h6" model cdt3d kt att_St tp_tot cdt_ok St/att St/tp more
printf '%s\n' "$(printf '%.0s-' {1..120})"
printf '%s\n' "${T6[@]}"
echo
if [ -n "$ATT" ]; then
  echo "cdt3d default adds more Steiner points than Attene on ${#MORE_ATT[@]} model(s)${MORE_ATT[*]:+:}"
  [ ${#MORE_ATT[@]} -gt 0 ] && printf '  %s\n' "${MORE_ATT[@]}"
fi
echo "cdt3d default adds more Steiner points than tetgen -p (where cdt_ok) on ${#MORE_TGP[@]} model(s)${MORE_TGP[*]:+:}"
[ ${#MORE_TGP[@]} -gt 0 ] && printf '  %s\n' "${MORE_TGP[@]}"
echo "Total wall time (ms, the fastest run of each model) over the $n_sum models that cdt3d, tetgen -p and tetgen -pM all meshed:"
echo "  cdt3d default $sum_c, tetgen $TGP_FLAGS $sum_tp, tetgen $TG_FLAGS $sum_tm;" \
  "cdt3d/tetgen -p $(ratio "$sum_c" "$sum_tp"), cdt3d/tetgen -pM $(ratio "$sum_c" "$sum_tm")"
if [ -n "$ATT" ]; then
  echo "Over the $n_att models that cdt3d and Attene both meshed: wall ms cdt3d $sum_ca, Attene $sum_aw (ratio $(ratio "$sum_ca" "$sum_aw"));"
  echo "  own time ms cdt3d msTotal $sum_cat, Attene phases $sum_aa (ratio $(ratio "$sum_cat" "$sum_aa"))"
fi
if [ ${#NOTES[@]} -gt 0 ]; then
  echo
  echo "Failures and messages (verbatim):"
  printf '  %s\n' "${NOTES[@]}"
fi
