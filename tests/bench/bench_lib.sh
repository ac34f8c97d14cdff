# Helpers shared by bench_corpus.sh and bench_quality.sh (sourced, not run):
# reading cdt3d's --json output, formatting the tables' cells, tetgen's failures, building the CLI.

jnum() {  # jnum KEY JSON -> value of a number/true/false/null key, or "-"
  local v
  v=$(sed -n -E "s/.*\"$1\":([-0-9.eE+]+|true|false|null)[,}].*/\1/p" <<<"$2" | head -n 1)
  echo "${v:--}"
}
jmsg() {  # the error code and message of {"ok":false,"error":{...}}
  local code msg
  code=$(sed -n 's/.*"code":"\([^"]*\)".*/\1/p' <<<"$1" | head -n 1)
  msg=$(sed -n 's/.*"message":"\(\([^"\\]\|\\.\)*\)".*/\1/p' <<<"$1" | head -n 1)
  msg=$(sed -e 's/\\"/"/g' -e 's/\\\\/\\/g' <<<"$msg")
  echo "${code:-?}: ${msg:-$1}"
}
ratio() {  # a / b, or "-" unless both are positive numbers
  awk -v a="$1" -v b="$2" 'BEGIN{ n = "^[0-9]*[.]?[0-9]+([eE][-+]?[0-9]+)?$";
    if (a !~ n || b !~ n || b + 0 <= 0) print "-"; else printf "%.2f", a / b }'
}
mib() { awk -v k="$1" 'BEGIN{ if (k !~ /^[0-9]+$/) print "-"; else printf "%.1f", k / 1024 }'; }  # KiB -> MiB
why() {  # why RC -> short failure text
  case $1 in
    124) echo "timeout" ;;
    134) echo "abort" ;;
    139) echo "segfault" ;;
    *) echo "exit $1" ;;
  esac
}
tg_failed() {  # tg_failed RC OUT ERR: why a tetgen run failed, in F_WHY (timeout, abort, segfault,
  # "exit N", or "error" for exit 0 with an error message) and F_MSG (its error lines, or its stderr's tail)
  F_WHY=$(why "$1")
  [ "$1" -eq 0 ] && F_WHY=error
  F_MSG=$(grep -iE 'error|assert|terminate|warning|intersect' <<<"$2"$'\n'"$3" | head -n 3 | tr '\n' ' ')
  [ -n "$F_MSG" ] || F_MSG=$(tail -c 300 <<<"$3")
}

# build_cli TREE JOBS [CMAKE_ARGS...] (from the repository root): configures
# TREE as Release with CMAKE_ARGS when it has no CMakeCache.txt yet, then
# builds the target cdt3d_cli; when that fails, an existing TREE/core/cdt3d is
# used with a warning. Log: TREE/bench-build.log. Calls the script's die().
build_cli() {
  local tree=$1 jobs=$2 log=$1/bench-build.log
  shift 2
  mkdir -p "$tree"
  if [ ! -f "$tree/CMakeCache.txt" ]; then
    cmake -S . -B "$tree" -DCMAKE_BUILD_TYPE=Release "$@" >"$log" 2>&1 ||
      { cat "$log"; die "cmake configure of $tree failed"; }
  fi
  if ! cmake --build "$tree" -j"$jobs" --target cdt3d_cli >"$log" 2>&1; then
    tail -n 20 "$log"
    [ -x "$tree/core/cdt3d" ] || die "building $tree/core/cdt3d failed"
    echo "${0##*/}: WARNING: the build failed; using the existing, possibly stale $tree/core/cdt3d" >&2
  fi
}
