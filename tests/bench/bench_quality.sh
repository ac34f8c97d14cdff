#!/usr/bin/env bash
# Quality benchmark (issue 17): cdt3d's quality refinement against Debian's
# TetGen 1.5 (`tetgen -pq1.414Q`, run as a separate process only), in one run,
# on tests/data/bunny.off and, when the shared corpus is there, on classic
# models of it (armadillo and bunny by default). Both programs' meshes are
# measured by the same tool, tests/bench/mesh_quality.cpp.
#
# One command (builds what it needs):
#   bash tests/bench/bench_quality.sh                # bunny; + shared classic models if present
#   CORPUS=data bash tests/bench/bench_quality.sh    # tests/data/bunny.off only
#   CORPUS=shared bash tests/bench/bench_quality.sh  # the shared classic models required
#   CORPUS=all bash tests/bench/bench_quality.sh     # issue 42's set: every valid model of
#                                                    # tests/data, then the ten classic models
#
# Per model:
#   plc_to_poly MODEL M.poly                      the PLC as cdt3d reads it, as a TetGen .poly
#                                                 (tetgen cannot read OBJ; tests/bench/plc_to_poly.cpp)
#   tetgen -pq1.414Q M.poly                       timed (wall, user CPU, peak RSS); writes M.1.*
#   mesh_quality M.1.node M.1.ele MODEL           tets, radius-edge > 2, min dihedral, flat tets,
#                                                 and which of them touch an input angle below 10
#                                                 degrees (excused, issue 42); of the tets below 10
#                                                 degrees not excused, those inside such an angle
#                                                 (reported only)
#   cdt3d mesh MODEL --quality 1.414 --min-dihedral 15 --json -o C  timed; writes C.node/.ele/... like tetgen does,
#                                                 so both timed runs include writing the mesh
#   mesh_quality C.node C.ele MODEL               the same numbers for cdt3d's mesh
#   cdt3d mesh MODEL --quality 1.414 --min-dihedral 15 --json --validate   the validator's verdict (untimed)
# Every process runs under `timeout` (BENCH_TIMEOUT, default 600 s); a hang or
# crash becomes a row that says so. Everything runs in .build/bench/quality/;
# the meshes are deleted after measuring (BENCH_KEEP=1 keeps them).
#
# Output: Markdown tables (1: the comparison issue 17 is judged by; 2: details
# and cdt3d's own statistics from its JSON, as a cross-check of mesh_quality),
# then the issue's targets per model (for issue 42 also time and peak memory
# summed over the models both programs meshed, and the models slower than
# tetgen where it takes at least 0.1 s), then failures verbatim.
#
# Environment:
#   CORPUS=auto|data|shared  auto (default): the shared models when the shared corpus exists
#   SHARED_MODELS="classic/bunny.off classic/armadillo.obj"   paths in the shared corpus;
#                            a model whose file is identical to one already listed is skipped
#   QUALITY=1.414            radius-edge bound of both programs (tetgen -qQUALITY, cdt3d --quality)
#   MIN_DIHEDRAL=15          cdt3d's improvement pass (--min-dihedral; 0: none), the counterpart
#                            of the mesh optimisation tetgen -q runs by default (-O2/7)
#   BENCH_TIMEOUT=600        seconds per process
#   BENCH_JOBS=2             parallel jobs when (re)building .build/native
#   BENCH_KEEP=0             1: keep the meshes in .build/bench/quality/MODEL/
#   CDT3D_BIN=.build/native/core/cdt3d   the CLI to use (not rebuilt if set; plc_to_poly
#                            links the libcdt3d.a next to it)
set -uo pipefail
cd "$(dirname "$0")/../.."
ROOT=$PWD
. tests/bench/bench_lib.sh  # jnum, jmsg, ratio, mib, why, tg_failed, build_cli

CORPUS=${CORPUS:-auto}
QUALITY=${QUALITY:-1.414}
MIN_DIHEDRAL=${MIN_DIHEDRAL:-15}
TIMEOUT=${BENCH_TIMEOUT:-600}
JOBS=${BENCH_JOBS:-2}
KEEP=${BENCH_KEEP:-0}
read -r -a SHARED_LIST <<<"${SHARED_MODELS:-classic/bunny.off classic/armadillo.obj}"
SHARED=/work/shared/corpus  # as in bench_corpus.sh
WORK=$ROOT/.build/bench/quality
TG_FLAGS=-pq${QUALITY}Q

die() { echo "bench_quality: $*" >&2; exit 1; }
case $CORPUS in auto | data | shared | all) ;; *) die "CORPUS must be auto, data, shared or all (got '$CORPUS')" ;; esac
mkdir -p "$WORK/bin"

# 1. Tools: Debian's tetgen and GNU time, through the project's set-up only if missing.
if ! command -v tetgen >/dev/null || [ ! -x /usr/bin/time ]; then
  CDT3D_EXTRA_APT=tetgen bash tests/scripts/setup.sh || die "tests/scripts/setup.sh failed"
fi

# 2. The CLI (the tree's own .build/native, Release) and the two bench tools.
if [ -n "${CDT3D_BIN:-}" ]; then
  BIN=$CDT3D_BIN
else
  BIN=$ROOT/.build/native/core/cdt3d
  build_cli .build/native "$JOBS"
fi
[ -x "$BIN" ] || die "$BIN missing"
LIB=$(dirname "$BIN")/libcdt3d.a
[ -f "$LIB" ] || die "$LIB missing (plc_to_poly links it)"
BUILD_TYPE=$(sed -n 's/^CMAKE_BUILD_TYPE:[A-Z]*=//p' "$(dirname "$(dirname "$BIN")")/CMakeCache.txt" 2>/dev/null)
[ "$BUILD_TYPE" = Release ] ||
  echo "bench_quality: WARNING: $BIN is not a Release build (CMAKE_BUILD_TYPE='${BUILD_TYPE:-?}')" >&2

tool() {  # tool NAME [LIB]: tests/bench/NAME.cpp -> $WORK/bin/NAME, rebuilt when older than an input
  local name=$1 lib=${2:-} out=$WORK/bin/$1 dep stale=0
  [ -x "$out" ] || stale=1
  for dep in "tests/bench/$name.cpp" tests/bench/tetgen_lines.hpp core/include/cdt3d/cdt3d.hpp $lib; do
    [ "$dep" -nt "$out" ] && stale=1
  done
  if [ "$stale" = 1 ]; then
    c++ -O2 -std=c++17 -I core/include "tests/bench/$name.cpp" $lib -o "$out" || die "cannot build tests/bench/$name.cpp"
  fi
}
tool plc_to_poly "$LIB"
tool mesh_quality "$LIB"
CONV=$WORK/bin/plc_to_poly MQ=$WORK/bin/mesh_quality

# 3. The models: "path<TAB>name" lines.
MODELS=("$ROOT/tests/data/bunny.off"$'\t'"bunny.off") NOTES=()
if [ "$CORPUS" = all ]; then
  [ -d "$SHARED/classic" ] || die "$SHARED/classic not found"
  MODELS=()
  while IFS=$'\t' read -r file _ _ _ _ _ expected _; do
    case $expected in valid | valid-plc) MODELS+=("$ROOT/tests/data/$file"$'\t'"$file") ;; esac
  done < <(tail -n +2 tests/data/MANIFEST.tsv)
  SHARED_LIST=()
  for m in "$SHARED"/classic/*; do SHARED_LIST+=("classic/$(basename "$m")"); done
fi
if [ "$CORPUS" = shared ] || [ "$CORPUS" = all ] || { [ "$CORPUS" = auto ] && [ -d "$SHARED" ]; }; then
  [ -d "$SHARED" ] || die "$SHARED not found"
  for m in "${SHARED_LIST[@]}"; do
    [ -f "$SHARED/$m" ] || die "$SHARED/$m not found"
    same=""
    for line in "${MODELS[@]}"; do
      cmp -s "$SHARED/$m" "${line%%$'\t'*}" && same=${line#*$'\t'}
    done
    if [ -n "$same" ]; then
      NOTES+=("$m: skipped, the same file as $same")
    else
      MODELS+=("$SHARED/$m"$'\t'"$m")
    fi
  done
fi

# 4. Running.
# run DIR CMD... (in DIR, under timeout and /usr/bin/time) sets R_RC (124 =
# timeout), R_WALL (s), R_USER (s), R_RSS (KiB), R_OUT (stdout), R_ERR (stderr tail).
run() {
  local dir=$1 log=$WORK/time.log out=$WORK/out.txt
  shift
  (cd "$dir" && /usr/bin/time -f '%e %U %M' -o "$log" timeout "$TIMEOUT" "$@" >"$out" 2>"$out.err")
  R_RC=$?
  R_WALL="" R_USER="" R_RSS=""
  read -r R_WALL R_USER R_RSS < <(grep -E '^[0-9.]+ [0-9.]+ [0-9]+$' "$log" | tail -n 1) || true
  R_OUT=$(cat "$out")
  R_ERR=$(tail -c 600 "$out.err")
  rm -f "$log" "$out" "$out.err"
}
jshare() {  # jshare JSON -> % of tets in radiusEdgeHistogram bins 3..9 (ratio >= 2), or "-"
  sed -n -E 's/.*"radiusEdgeHistogram":\[([0-9,]*)\].*/\1/p' <<<"$1" | head -n 1 |
    awk -F, '{ for (i = 1; i <= NF; ++i) { all += $i; if (i >= 4) bad += $i } }
      END { if (NF != 10 || all == 0) print "-"; else printf "%.2f%%", 100 * bad / all }'
}
pct() { awk -v b="$1" -v n="$2" 'BEGIN{ if (n !~ /^[0-9]+$/ || n == 0) print "-"; else printf "%.2f%%", 100 * b / n }'; }
deg() { awk -v d="$1" 'BEGIN{ if (d !~ /^[0-9.]+([eE][-+]?[0-9]+)?$/) print "-"; else printf (d < 1 ? "%.2g\n" : "%.2f\n"), d }'; }
# measure NODE ELE MODEL -> Q_TETS Q_BAD Q_SHARE Q_MIND (degrees, as printed) Q_FLAT Q_MAXR
# Q_POINTS, and (issue 42) Q_BADX (bad tets excused by an input angle below 10 degrees),
# Q_KSHARE (share of bad tets not excused), Q_BELOW / Q_BELOWX (tets with a dihedral angle
# below 10 degrees / of them excused), Q_MINK (min dihedral of tets not excused), Q_BELOWS
# (tets below 10 degrees not excused with a vertex in a small input angle's triangle);
# "-" on failure, with mesh_quality's message in Q_MSG
measure() {
  local out
  Q_TETS=- Q_BAD=- Q_SHARE=- Q_MIND=- Q_FLAT=- Q_MAXR=- Q_POINTS=- Q_MSG=""
  Q_BADX=- Q_KSHARE=- Q_BELOW=- Q_BELOWX=- Q_MINK=- Q_BELOWS=-
  if out=$("$MQ" "$1" "$2" "$3" 2>&1); then
    read -r Q_TETS Q_BAD Q_MIND Q_FLAT Q_MAXR Q_BADX Q_BELOW Q_BELOWX Q_MINK Q_BELOWS <<<"$out"
    Q_SHARE=$(pct "$Q_BAD" "$Q_TETS")
    Q_KSHARE=$(pct "$((Q_BAD - Q_BADX))" "$Q_TETS")
    Q_POINTS=$(grep -v -E '^[[:space:]]*(#|$)' "$1" | head -n 1 | awk '{ print $1 }')
  else
    Q_MSG=$out
  fi
}
meets() {  # meets CONDITION (awk) A B -> "yes" / "NO" / "-"
  awk -v a="$2" -v b="$3" "BEGIN{ n = \"^[0-9]*[.]?[0-9]+([eE][-+]?[0-9]+)?\$\"; if (a !~ n || b !~ n) print \"-\"; else print (($1) ? \"yes\" : \"NO\") }"
}

T1=() T2=() T3=() TARGETS=() TARGETS42=()
# Issue 42's time and memory targets: sums over the models both programs
# meshed (wall s, peak RSS KiB), and the models slower than tetgen.
SUMS="0 0 0 0 0" SLOW=()
total=${#MODELS[@]} i=0
for line in "${MODELS[@]}"; do
  path=${line%%$'\t'*} name=${line#*$'\t'}
  i=$((i + 1))
  stem=$(echo "$name" | tr '/' '_')
  stem=${stem%.*}
  dir=$WORK/$stem
  rm -rf "$dir" && mkdir -p "$dir"

  # tetgen on the converted PLC: timed, then its mesh measured.
  printf '\rbench_quality: %d/%d %-30s tetgen   ' "$i" "$total" "$name" >&2
  t_wall=- t_user=- t_rss=-
  tq=(- - - - - - - -)  # tets share min-dihedral flat max-ratio points bad min-dihedral-unrounded
  tx=(- - - - - -)      # bad-excused share-not-excused below-10 below-10-excused min-dihedral-not-excused below-10-in-sector
  if "$CONV" "$path" "$dir/$stem.poly" 2>"$dir/conv.err"; then
    run "$dir" tetgen "$TG_FLAGS" "$stem.poly"
    if [ "$R_RC" -eq 0 ] && ! grep -qiE 'error|assert|terminate' <<<"$R_OUT$R_ERR" && [ -f "$dir/$stem.1.ele" ]; then
      t_wall=$R_WALL t_user=$R_USER t_rss=$R_RSS
      measure "$dir/$stem.1.node" "$dir/$stem.1.ele" "$path"
      tq=("$Q_TETS" "$Q_SHARE" "$(deg "$Q_MIND")" "$Q_FLAT" "$Q_MAXR" "$Q_POINTS" "$Q_BAD" "$Q_MIND")
      tx=("$Q_BADX" "$Q_KSHARE" "$Q_BELOW" "$Q_BELOWX" "$Q_MINK" "$Q_BELOWS")
      [ -n "$Q_MSG" ] && NOTES+=("$name: mesh_quality on tetgen's mesh: $Q_MSG")
    else
      tg_failed "$R_RC" "$R_OUT" "$R_ERR"
      t_wall=$F_WHY
      NOTES+=("$name: tetgen $TG_FLAGS: $F_WHY $F_MSG")
    fi
  else
    t_wall=conv
    NOTES+=("$name: plc_to_poly: $(cat "$dir/conv.err")")
  fi
  [ "$KEEP" = 1 ] || rm -f "$dir/$stem".1.*

  # cdt3d: timed with its mesh written (as tetgen writes its), measured, then validated.
  printf '\rbench_quality: %d/%d %-30s cdt3d    ' "$i" "$total" "$name" >&2
  c_wall=- c_user=- c_rss=- c_json="" valid=-
  cq=(- - - - - - - -)
  cx=(- - - - -)
  run "$dir" "$BIN" mesh "$path" --quality "$QUALITY" --min-dihedral "$MIN_DIHEDRAL" --json -o "$dir/cdt3d"
  if [ "$R_RC" -eq 0 ]; then
    c_wall=$R_WALL c_user=$R_USER c_rss=$R_RSS c_json=$R_OUT
    measure "$dir/cdt3d.node" "$dir/cdt3d.ele" "$path"
    cq=("$Q_TETS" "$Q_SHARE" "$(deg "$Q_MIND")" "$Q_FLAT" "$Q_MAXR" "$Q_POINTS" "$Q_BAD" "$Q_MIND")
    cx=("$Q_BADX" "$Q_KSHARE" "$Q_BELOW" "$Q_BELOWX" "$Q_MINK" "$Q_BELOWS")
    [ -n "$Q_MSG" ] && NOTES+=("$name: mesh_quality on cdt3d's mesh: $Q_MSG")
    printf '\rbench_quality: %d/%d %-30s validate ' "$i" "$total" "$name" >&2
    run "$dir" "$BIN" mesh "$path" --quality "$QUALITY" --min-dihedral "$MIN_DIHEDRAL" --json --validate
    if [ "$R_RC" -eq 0 ]; then
      case $(jnum valid "$R_OUT") in true) valid=yes ;; false) valid=NO ;; *) valid=$(jnum valid "$R_OUT") ;; esac
      if [ "$valid" != yes ]; then
        vm=$(sed -n 's/.*"validation":"\(\([^"\\]\|\\.\)*\)".*/\1/p' <<<"$R_OUT" | head -n 1)
        NOTES+=("$name: cdt3d --validate: valid=$valid $vm")
      fi
    else
      valid=$([ "$R_RC" -eq 1 ] && echo NO || why "$R_RC")
      NOTES+=("$name: cdt3d --validate: $([ "$R_RC" -eq 1 ] && jmsg "$R_OUT" || echo "$(why "$R_RC") $R_ERR")")
    fi
  else
    c_wall=$(why "$R_RC")
    if [ "$R_RC" -eq 1 ]; then
      c_wall=error
      NOTES+=("$name: cdt3d mesh: $(jmsg "$R_OUT")")
    else
      NOTES+=("$name: cdt3d mesh: $(why "$R_RC") $R_ERR")
    fi
  fi

  [ "$KEEP" = 1 ] || rm -f "$dir"/cdt3d.*
  t_mib=$(mib "$t_rss") c_mib=$(mib "$c_rss")
  time_r=$(ratio "$c_wall" "$t_wall") mem_r=$(ratio "$c_rss" "$t_rss")
  SUMS=$(awk -v s="$SUMS" -v tw="$t_wall" -v cw="$c_wall" -v tr="$t_rss" -v cr="$c_rss" 'BEGIN{
    n = "^[0-9]*[.]?[0-9]+$"; split(s, a, " ");
    if (tw ~ n && cw ~ n && tr ~ n && cr ~ n) { a[1] += tw; a[2] += cw; a[3] += tr; a[4] += cr; a[5]++ }
    printf "%.2f %.2f %d %d %d", a[1], a[2], a[3], a[4], a[5] }')
  # Slower than tetgen, where its time is at least 0.1 s (below, the 10 ms
  # steps of /usr/bin/time decide the ratio).
  if awk -v tw="$t_wall" -v r="$time_r" 'BEGIN{ n = "^[0-9]*[.]?[0-9]+$"; exit !(tw ~ n && r ~ n && tw + 0 >= 0.1 && r + 0 > 1.0) }'; then
    SLOW+=("$name ($time_r)")
  fi
  T1+=("| $name | ${tq[0]} / ${cq[0]} | ${tq[1]} / ${cq[1]} | ${tq[2]} / ${cq[2]} | $t_wall / $c_wall / $time_r | $t_mib / $c_mib / $mem_r | $valid |")
  mind_j=$(jnum minDihedral "$c_json")
  mind_j=$(deg "$mind_j")
  T2+=("| $name | ${tq[5]} / ${cq[5]} | $t_user / $c_user / $(ratio "$c_user" "$t_user") | ${tq[3]} / ${cq[3]} | ${tq[4]} / ${cq[4]} | $(jnum points "$c_json") | $(jnum tets "$c_json") | $(jshare "$c_json") | $mind_j | $(jnum refineSkipped "$c_json") | $(jnum refineCapped "$c_json") | $(jnum msRefine "$c_json") | $(jnum msTotal "$c_json") |")
  # Issue 17's targets; the share compared as counts over tets (no rounding).
  s_ok=$(awk -v bt="${tq[6]}" -v nt="${tq[0]}" -v bc="${cq[6]}" -v nc="${cq[0]}" 'BEGIN{ n = "^[0-9]+$";
    if (bt !~ n || nt !~ n || bc !~ n || nc !~ n || nt == 0 || nc == 0) print "-"; else print (bc / nc <= bt / nt ? "yes" : "NO") }')
  T3+=("| $name | ${tx[1]} / ${cx[1]} | $(deg "${tx[4]}") / $(deg "${cx[4]}") | ${tq[6]} / ${cq[6]} | ${tx[0]} / ${cx[0]} | ${cx[2]} | ${cx[3]} | $(awk -v a="${cx[2]}" -v b="${cx[3]}" 'BEGIN{ n = "^[0-9]+$"; print (a ~ n && b ~ n) ? a - b : "-" }') | ${cx[5]} | $(awk -v a="${tx[2]}" -v b="${tx[3]}" 'BEGIN{ n = "^[0-9]+$"; print (a ~ n && b ~ n) ? a - b : "-" }') / ${tx[5]} |")
  k_ok=$(awk -v bt="${tq[6]}" -v xt="${tx[0]}" -v nt="${tq[0]}" -v bc="${cq[6]}" -v xc="${cx[0]}" -v nc="${cq[0]}" 'BEGIN{ n = "^[0-9]+$";
    if (bt !~ n || xt !~ n || nt !~ n || bc !~ n || xc !~ n || nc !~ n || nt == 0 || nc == 0) print "-"; else print ((bc - xc) / nc <= (bt - xt) / nt ? "yes" : "NO") }')
  TARGETS42+=("- $name: share not excused ${cx[1]} <= ${tx[1]}: $k_ok; min dihedral ${cq[2]} >= ${tq[2]}: $(meets 'a + 0 >= b + 0' "${cq[7]}" "${tq[7]}"); tets below 10 degrees not excused: $(awk -v a="${cx[2]}" -v b="${cx[3]}" 'BEGIN{ n = "^[0-9]+$"; print (a ~ n && b ~ n) ? a - b : "-" }') (0: $(meets 'a - b == 0' "${cx[2]}" "${cx[3]}")), of them in a small angle's triangle: ${cx[5]}")
  TARGETS+=("- $name: share radius-edge>2 ${cq[1]} <= ${tq[1]}: $s_ok; min dihedral ${cq[2]} >= ${tq[2]}: $(meets 'a + 0 >= b + 0' "${cq[7]}" "${tq[7]}"); time ratio $time_r <= 0.5: $(meets 'a + 0 <= 0.5' "$time_r" 0); memory ratio $mem_r <= 0.5: $(meets 'a + 0 <= 0.5' "$mem_r" 0); valid: $valid")
done
printf '\r%80s\r' '' >&2

# 5. Tables.
echo "bench_quality: ${#MODELS[@]} models (CORPUS=$CORPUS), $(nproc 2>/dev/null || echo ?) cores, load $(cut -d' ' -f1-3 /proc/loadavg) at end, $(date -u '+%Y-%m-%d %H:%M UTC')"
echo "  tetgen $(dpkg-query -W -f='${Version}' tetgen 2>/dev/null) $TG_FLAGS M.poly (plc_to_poly of the model); cdt3d: $BIN (${BUILD_TYPE:-?})"
echo "  mesh MODEL --quality $QUALITY --min-dihedral $MIN_DIHEDRAL --json -o PREFIX; both timed runs write their mesh; one run each; timeout ${TIMEOUT}s"
echo
echo "Table 1: quality refinement, cdt3d against tetgen. tets, share and min dihedral measured by mesh_quality on both"
echo "programs' .node/.ele; share = tets with radius-edge ratio > 2; time = wall s, peak = peak RSS MiB (/usr/bin/time);"
echo "ratio = cdt3d / tetgen (below 1: cdt3d faster or smaller); valid = cdt3d --validate"
echo
echo "| model | tets tetgen / cdt3d | share radius-edge>2 tetgen / cdt3d | min dihedral tetgen / cdt3d | time s tetgen / cdt3d / ratio | peak MiB tetgen / cdt3d / ratio | cdt3d valid |"
echo "|---|---|---|---|---|---|---|"
printf '%s\n' "${T1[@]}"
echo
echo "Table 2: details. points of both meshes; user CPU s (not inflated by waiting for a core); flat tets and the largest"
echo "radius-edge ratio (mesh_quality); then cdt3d's own statistics (--json): share = radiusEdgeHistogram bins [2,inf),"
echo "minDihedral, refineSkipped (bad tets refinement left, before the pass), refineCapped, msRefine, msTotal"
echo
echo "| model | points tetgen / cdt3d | user s tetgen / cdt3d / ratio | flat tetgen / cdt3d | max ratio tetgen / cdt3d | json points | json tets | json share | json minDihedral | refineSkipped | refineCapped | msRefine | msTotal |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
printf '%s\n' "${T2[@]}"
echo
echo "Table 3 (issue 42): tets excused by a small input angle. A tet is excused when a vertex of it lies at a facet"
echo "corner of less than 10 degrees or on an input edge where two facets meet at less than 10 degrees (mesh_quality with"
echo "the model); share not excused = bad tets (radius-edge > 2) that are not excused, over all tets; min dihedral over"
echo "tets not excused; then cdt3d's tets with a dihedral angle below 10 degrees, excused, and not excused; of the"
echo "latter, those with a vertex in the triangle of a facet corner below 10 degrees and its two neighbours (inside the"
echo "small angle, away from its corner: on a thin input triangle, anywhere on it); last, tetgen's not excused / in it"
echo
echo "| model | share not excused tetgen / cdt3d | min dihedral not excused tetgen / cdt3d | bad tetgen / cdt3d | bad excused tetgen / cdt3d | cdt3d tets < 10 deg | excused | not excused | in a small angle's triangle | tetgen not excused / in it |"
echo "|---|---|---|---|---|---|---|---|---|---|"
printf '%s\n' "${T3[@]}"
echo
echo "Targets of issue 42 (share of bad tets not excused at most tetgen's, min dihedral at least tetgen's, no tet below"
echo "10 degrees that is not excused; then time and peak memory summed, at most 0.5x tetgen's, and no model above 1.0x):"
printf '%s\n' "${TARGETS42[@]}"
read -r sum_tw sum_cw sum_tr sum_cr sum_n <<<"$SUMS"
sum_tr_mib=$(mib "$sum_tr") sum_cr_mib=$(mib "$sum_cr")
echo "- time over the $sum_n models both meshed: $sum_cw s against tetgen's $sum_tw s, ratio $(ratio "$sum_cw" "$sum_tw") <= 0.5: $(meets 'a + 0 <= 0.5' "$(ratio "$sum_cw" "$sum_tw")" 0)"
echo "- models above 1.0x tetgen's time (where tetgen takes at least 0.1 s): ${SLOW[*]:-none}"
echo "- peak memory summed over them: $sum_cr_mib MiB against tetgen's $sum_tr_mib MiB, ratio $(ratio "$sum_cr" "$sum_tr") <= 0.5: $(meets 'a + 0 <= 0.5' "$(ratio "$sum_cr" "$sum_tr")" 0)"
echo
echo "Targets of issue 17 (bunny and armadillo: share and min dihedral at least as good as tetgen's, time and peak memory"
echo "at most 0.5x tetgen's, the mesh valid):"
printf '%s\n' "${TARGETS[@]}"
if [ ${#NOTES[@]} -gt 0 ]; then
  echo
  echo "Notes and failures (verbatim):"
  printf '  %s\n' "${NOTES[@]}"
fi
