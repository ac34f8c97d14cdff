#!/usr/bin/env bash
# Builds the seed corpora of the fuzz targets in <out>/<target>/ (default
# .build/fuzz/corpus): the models of tests/data by extension, cut to the
# target's max_len when larger, plus a few tiny hand-written files for the
# formats that tests/data covers thinly, and encoded PLCs for fuzz_pipeline.
# Idempotent: existing files are overwritten, files the fuzzers added stay.
#   bash tests/fuzz/make_corpus.sh [out-dir]
set -euo pipefail
cd "$(dirname "$0")/../.."
OUT=${1:-.build/fuzz/corpus}
DATA=tests/data

# Must match fuzz.sh.
max_len() {
  case "$1" in
    stl) echo 16384 ;;
    pipeline) echo 64 ;;
    *) echo 8192 ;;
  esac
}

# put <target> <name> <printf-format>: writes a hand-made seed.
put() { printf "$3" >"$OUT/$1/$2"; }

for ext in stl off obj ply poly smesh; do
  dir="$OUT/fuzz_read_$ext"
  mkdir -p "$dir"
  limit=$(max_len "$ext")
  for f in "$DATA"/*; do
    name=$(basename "$f")
    lower=$(printf '%s' "$name" | tr 'A-Z' 'a-z')
    [ "${lower##*.}" = "$ext" ] || continue
    if [ "$(stat -c %s "$f")" -le "$limit" ]; then
      cp "$f" "$dir/$name"
    else
      head -c "$limit" "$f" >"$dir/$name.head"
    fi
  done
done

# STL: a tiny ASCII file; a binary tetrahedron whose header begins with "solid".
put fuzz_read_stl tiny_ascii.stl 'solid t\nfacet normal 0 0 1\n outer loop\n  vertex 0 0 0\n  vertex 1 0 0\n  vertex 0 1 0\n endloop\nendfacet\nendsolid t\n'
{
  printf 'solid binary header'; head -c 61 /dev/zero
  printf '\x04\x00\x00\x00'
  Z='\x00\x00\x00\x00'; O='\x00\x00\x80\x3f'
  for tri in "$Z$Z$Z $O$Z$Z $Z$O$Z" "$Z$Z$Z $Z$Z$O $O$Z$Z" "$Z$Z$Z $Z$O$Z $Z$Z$O" "$O$Z$Z $Z$Z$O $Z$O$Z"; do
    printf "$Z$Z$Z"
    for v in $tri; do printf "$v"; done
    printf '\x00\x00'
  done
} >"$OUT/fuzz_read_stl/tet_binary.stl"

# OFF: keyword variants, comments, colours, a polygon face.
put fuzz_read_off tet_coff.off 'COFF\n# tetrahedron\n4 4 6\n0 0 0 1 0 0 1\n1 0 0 0 1 0 1\n0 1 0 0 0 1 1\n0 0 1 1 1 1 1\n3 0 2 1 255 0 0\n3 0 1 3\n3 0 3 2\n3 1 2 3\n'
put fuzz_read_off pyramid_noff.off 'NOFF 5 5 0\n0 0 0 0 0 -1\n1 0 0 0 0 -1\n1 1 0 0 0 -1\n0 1 0 0 0 -1\n.5 .5 1e0 0 0 1\n4 3 2 1 0\n3 0 1 4\n3 1 2 4\n3 2 3 4\n3 3 0 4\n'

# OBJ: every corner syntax, relative indices, polylines, points, ignored records.
put fuzz_read_obj tet.obj '# tet\nmtllib x.mtl\no tet\nv 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1 1.0\nvt 0 0\nvn 0 0 1\ng side\ns off\nusemtl m\nf 1 3 2\nf 1/1 2/1 4/1\nf 1//1 4//1 3//1\nf -3/1/1 -2/1/1 -1/1/1\nl 1 2 3\np 4\n'
put fuzz_read_obj quad_crlf.obj 'v 0 0 0\r\nv 2 0 0\r\nv 2 2 0\r\nv 0 2 0\r\nv 1 1 2\r\nf 4 3 2 1\r\nf 1 2 5\r\nf 2 3 5\r\nf 3 4 5\r\nf 4 1 5\r\n'

# PLY: ASCII with extra elements and properties; binary little and big endian.
put fuzz_read_ply tet_ascii.ply 'ply\nformat ascii 1.0\ncomment c\nobj_info o\nelement vertex 4\nproperty double x\nproperty double y\nproperty double z\nproperty uchar red\nproperty list uchar float extra\nelement face 4\nproperty uchar flags\nproperty list uint8 uint32 vertex_index\nelement edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n0 0 0 255 0\n1 0 0 0 1 2.5\n0 1 0 0 2 1 2\n0 0 1 0 0\n0 3 0 2 1\n0 3 0 1 3\n0 3 0 3 2\n0 3 1 2 3\n0 1\n'
ply_bin() { # <format> <zero> <one> <int0..3 as printf escapes>
  printf 'ply\nformat %s 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n' "$1"
  local z=$2 o=$3
  printf "$z$z$z$o$z$z$z$o$z$z$z$o"
  local i0=$4 i1=$5 i2=$6 i3=$7
  printf "\x03$i0$i2$i1\x03$i0$i1$i3\x03$i0$i3$i2\x03$i1$i2$i3"
}
ply_bin binary_little_endian '\x00\x00\x00\x00' '\x00\x00\x80\x3f' \
  '\x00\x00\x00\x00' '\x01\x00\x00\x00' '\x02\x00\x00\x00' '\x03\x00\x00\x00' \
  >"$OUT/fuzz_read_ply/tet_le.ply"
ply_bin binary_big_endian '\x00\x00\x00\x00' '\x3f\x80\x00\x00' \
  '\x00\x00\x00\x00' '\x00\x00\x00\x01' '\x00\x00\x00\x02' '\x00\x00\x00\x03' \
  >"$OUT/fuzz_read_ply/tet_be.ply"

# .poly: 0-based nodes with attributes and markers, a facet with a hole,
# volume holes and regions.
put fuzz_read_poly box_hole_region.poly '# box with a square hole in its top facet\n12 3 1 1\n0 0 0 0 5 1\n1 4 0 0 5 1\n2 4 4 0 5 1\n3 0 4 0 5 1\n4 0 0 2 5 1\n5 4 0 2 5 1\n6 4 4 2 5 1\n7 0 4 2 5 1\n8 1 1 2 0 2\n9 3 1 2 0 2\n10 3 3 2 0 2\n11 1 3 2 0 2\n6 1\n1 0 1\n4 0 3 2 1\n2 1 2\n4 4 5 6 7\n4 8 9 10 11\n1 2 1 3\n1 0 3\n4 0 1 5 4\n1 0 4\n4 1 2 6 5\n1 0 5\n4 2 3 7 6\n1 0 6\n4 3 0 4 7\n1\n0 9 9 9\n2\n0 2 2 1 7.5 0.1\n1 0.5 0.5 0.5 3\n'

# .smesh: 0-based, facet markers, holes and regions present.
put fuzz_read_smesh tet.smesh '# tetrahedron\n4 3 0 1\n0 0 0 0 1\n1 1 0 0 1\n2 0 1 0 1\n3 0 0 1 1\n4 1\n3 0 2 1 1\n3 0 1 3 2\n3 0 3 2 3\n3 1 2 3 4\n1\n0 5 5 5\n1\n0 0.1 0.1 0.1 1 -1\n'

# fuzz_pipeline: see decode() in pipeline_fuzzer.cpp. [flags][n-4][points][facets-1][facets...]
mkdir -p "$OUT/fuzz_pipeline"
put fuzz_pipeline tet '\x00\x00\x00\x03\x0c\x30\x03\x00\x00\x02\x01\x00\x00\x01\x03\x00\x00\x03\x02\x00\x01\x02\x03'
put fuzz_pipeline tet_hull_segment '\x03\x01\x00\x03\x0c\x30\x15\x03\x00\x00\x02\x01\x00\x00\x01\x03\x00\x00\x03\x02\x00\x01\x02\x03\x00\x00\x04'
put fuzz_pipeline cube_quads '\x00\x04\x00\x03\x0c\x0f\x30\x33\x3c\x3f\x05\x03\x00\x02\x03\x01\x07\x04\x05\x07\x06\x0b\x00\x01\x05\x04\x0f\x02\x06\x07\x03\x13\x00\x04\x06\x02\x17\x01\x03\x07\x05'
put fuzz_pipeline octahedron_hull '\x01\x02\x05\x16\x19\x14\x11\x25\x07\x00\x00\x02\x01\x00\x00\x03\x02\x00\x00\x04\x03\x00\x00\x01\x04\x00\x05\x01\x02\x00\x05\x02\x03\x00\x05\x03\x04\x00\x05\x04\x01'

for d in "$OUT"/*/; do
  echo "corpus: $(basename "$d"): $(ls "$d" | wc -l) files"
done
