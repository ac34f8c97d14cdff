#!/usr/bin/env bash
# Repair benchmark: the time of `cdt3d repair` against the time of meshing
# the repaired PLC, on a generated ~100k-triangle sphere with a tilted box
# through its surface (a few hundred crossing triangle pairs;
# gen_crossing_sphere.mjs). The issue asks that repair take at most as long
# as meshing. Prints one line; not a timed test.
#   bash tests/bench/bench_repair.sh [rings]     (rings 224: 99,916 sphere triangles)
set -euo pipefail
cd "$(dirname "$0")/../.."
RINGS=${1:-224}
OUT=.build/bench/repair
mkdir -p "$OUT"
if [ ! -x .build/native/core/cdt3d ]; then
  cmake -S . -B .build/native -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build .build/native -j"$(nproc)" --target cdt3d_cli >/dev/null
fi
CDT3D=.build/native/core/cdt3d
node tests/bench/gen_crossing_sphere.mjs "$OUT/sphere_box.off" "$RINGS" >/dev/null
field() { grep -o "\"$1\":[0-9.]*" | head -1 | cut -d: -f2; }
rep=$("$CDT3D" repair "$OUT/sphere_box.off" -o "$OUT/sphere_box_repaired" --json)
mesh=$("$CDT3D" mesh "$OUT/sphere_box_repaired.poly" --json)
valid=$("$CDT3D" mesh "$OUT/sphere_box_repaired.poly" --json --validate | grep -o "\"valid\":[a-z]*" | cut -d: -f2 || true)
repair_ms=$(echo "$rep" | field ms)
mesh_ms=$(echo "$mesh" | field msTotal)
echo "repair: sphere_box.off $(echo "$rep" | field inputFacets) triangles," \
  "$(echo "$rep" | field crossingPairs) crossing pairs -> $(echo "$rep" | field intersectionPoints) new points," \
  "$(echo "$rep" | field unresolvedPairs) left; repair ${repair_ms} ms, mesh ${mesh_ms} ms," \
  "ratio $(awk -v r="$repair_ms" -v m="$mesh_ms" 'BEGIN{printf "%.3f", r/m}'), mesh valid: ${valid:-?}"
