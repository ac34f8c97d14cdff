// Two helpers of tests/bench/bench_corpus.sh around cdt3d's flat-face merging
// (cdt3d::merge_flat_facets, the default of `cdt3d mesh`):
//
// 1. Is TetGen's `tetgen -p` mesh a CDT of the EXACTLY merged PLC? TetGen -p
//    merges coplanar facets within a tolerance, so it may drop, as inner
//    edges of a merged facet, segments whose facets are not exactly flat.
//    This reads the model as cdt3d does (cdt3d::read_plc_file), merges its
//    flat faces exactly, takes every segment of the merged PLC
//    (cdt3d::plc_segments: explicit segments and every facet loop edge) and
//    counts those that are not a chain of edges of TetGen's mesh
//    (`tetgen -pQe M.poly` with M.poly from plc_to_poly: M.1.node and
//    M.1.edge, which with -e lists every edge of the mesh). A segment ab is
//    covered when a and b are joined by a path of TetGen edges whose inner
//    vertices are TetGen Steiner points lying on ab. TetGen prints its
//    Steiner points with limited digits, so "on ab" is a tolerance test:
//    distance to the line ab at most 1e-9 |ab| (long double) and the
//    projection strictly between a and b; fine for a benchmark. TetGen's
//    first points are the input points in input order (checked).
//    Together with local_delaunay on the same mesh (interior faces not on
//    the surface that are not locally Delaunay), 0 missing and 0 non-locally
//    Delaunay faces mean that TetGen's -p mesh is a CDT of the exactly merged
//    PLC, so its Steiner point count is comparable with cdt3d's default.
//
//    usage: tetgen_vs_merged MODEL M.1.node M.1.edge
//    output, one line: "<missing> <segments> <flat_edges> <merged_facets>"
//      missing        segments of the merged PLC not covered by TetGen edges
//      segments       segments of the merged PLC (plc_segments)
//      flat_edges     flat edges merge_flat_facets found
//      merged_facets  facets of the merged PLC made of two or more input facets
//    With -v (first argument) the missing segments are listed on stderr.
//
// 2. The model as an OFF triangle surface for the Diazzi-Attene CDT
//    (github.com/MarcoAttene/CDT, which reads OFF triangles only, without
//    comments): the PLC cdt3d meshes (welded points, coordinates with %.17g,
//    which read back exactly), written only when every facet is one
//    triangle without holes and the PLC has no explicit segments, volume
//    holes or regions (else exit 3: the model is "n/a" for that program).
//
//    usage: tetgen_vs_merged --off MODEL OUT.off
//
// Build (bench_corpus.sh does this; needs the library):
//   c++ -O2 -std=c++17 -Icore/include tests/bench/tetgen_vs_merged.cpp
//       .build/bench/core/libcdt3d.a -o .build/bench/bench/tetgen_vs_merged   (one line)
//
// Exit codes: 0 done, 1 read or write error (message on stderr), 2 usage,
// 3 (--off) not a plain triangle surface (reason on stderr).
#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "tetgen_lines.hpp"

namespace {

using LD = long double;

int fail(const char* path, const std::string& what) { return bench::fail("tetgen_vs_merged", path, what); }

int write_off(const char* model, const char* out_path) {
  cdt3d::Plc plc;
  const cdt3d::Status st = cdt3d::read_plc_file(model, plc);
  if (!st.ok()) return fail(model, st.error.to_string());
  if (!plc.segments.empty() || !plc.holes.empty() || !plc.regions.empty()) {
    std::fprintf(stderr, "tetgen_vs_merged: %s: has explicit segments, volume holes or regions\n", model);
    return 3;
  }
  for (const cdt3d::Facet& f : plc.facets)
    if (f.loops.size() != 1 || f.loops[0].size() != 3 || !f.holes.empty()) {
      std::fprintf(stderr, "tetgen_vs_merged: %s: not a triangle surface (a facet with %zu loop(s), %zu vertices)\n",
                   model, f.loops.size(), f.loops.empty() ? size_t(0) : f.loops[0].size());
      return 3;
    }
  std::FILE* f = std::fopen(out_path, "wb");
  if (!f) return fail(out_path, "cannot create");
  std::fprintf(f, "OFF\n%zu %zu 0\n", plc.points.size(), plc.facets.size());
  for (const cdt3d::Vec3& p : plc.points) std::fprintf(f, "%.17g %.17g %.17g\n", p.x, p.y, p.z);
  for (const cdt3d::Facet& fc : plc.facets)
    std::fprintf(f, "3 %u %u %u\n", fc.loops[0][0], fc.loops[0][1], fc.loops[0][2]);
  if (std::fclose(f) != 0) return fail(out_path, "write error");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 4 && std::strcmp(argv[1], "--off") == 0) return write_off(argv[2], argv[3]);
  bool verbose = false;
  if (argc == 5 && std::strcmp(argv[1], "-v") == 0) {
    verbose = true;
    ++argv;
    --argc;
  }
  if (argc != 4) {
    std::fprintf(stderr,
                 "usage: tetgen_vs_merged [-v] MODEL M.1.node M.1.edge\n"
                 "       tetgen_vs_merged --off MODEL OUT.off\n");
    return 2;
  }
  cdt3d::Plc plc, merged;
  const cdt3d::Status st = cdt3d::read_plc_file(argv[1], plc);
  if (!st.ok()) return fail(argv[1], st.error.to_string());
  std::vector<uint32_t> merged_into;
  size_t flat_edges = 0;
  const size_t merged_facets = cdt3d::merge_flat_facets(plc, merged, merged_into, &flat_edges);
  const std::vector<std::array<cdt3d::VertexId, 2>> segments = cdt3d::plc_segments(merged);

  std::vector<double> xyz;
  long long first = 0;
  if (const std::string bad = bench::read_nodes(argv[2], xyz, first); !bad.empty()) return fail(argv[2], bad);
  const size_t n = xyz.size() / 3, n_in = plc.points.size();
  if (n < n_in) return fail(argv[2], "fewer points than the model");
  for (size_t i = 0; i < n_in; ++i) {  // TetGen's first points are the input points (%.16g or so)
    const cdt3d::Vec3& p = plc.points[i];
    const double c[3] = {p.x, p.y, p.z};
    for (int k = 0; k < 3; ++k)
      if (std::fabs(xyz[3 * i + k] - c[k]) > 1e-12 * (std::fabs(c[k]) + 1))
        return fail(argv[2], "point " + std::to_string(i) + " is not the model's point " + std::to_string(i));
  }

  std::vector<std::string> lines;
  if (!bench::read_lines(argv[3], lines) || lines.empty()) return fail(argv[3], "cannot read");
  long long ne = -1;
  std::istringstream(lines[0]) >> ne;
  if (ne < 0 || static_cast<long long>(lines.size()) - 1 < ne) return fail(argv[3], "bad header or too few lines");
  std::vector<std::vector<uint32_t>> adj(n);
  for (long long e = 0; e < ne; ++e) {
    std::istringstream s(lines[1 + e]);
    long long id, a, b;
    if (!(s >> id >> a >> b)) return fail(argv[3], "bad edge line " + std::to_string(e + 1));
    a -= first;
    b -= first;
    if (a < 0 || b < 0 || a >= static_cast<long long>(n) || b >= static_cast<long long>(n))
      return fail(argv[3], "node index out of range in edge " + std::to_string(id));
    adj[a].push_back(static_cast<uint32_t>(b));
    adj[b].push_back(static_cast<uint32_t>(a));
  }

  // on(p, a, b): TetGen Steiner point p lies on segment ab (tolerance above).
  auto on = [&](size_t p, size_t a, size_t b) {
    LD d[3], w[3];
    LD dd = 0, t = 0;
    for (int k = 0; k < 3; ++k) {
      d[k] = LD(xyz[3 * b + k]) - xyz[3 * a + k];
      w[k] = LD(xyz[3 * p + k]) - xyz[3 * a + k];
      dd += d[k] * d[k];
      t += w[k] * d[k];
    }
    if (dd == 0) return false;
    t /= dd;
    if (!(t > 0 && t < 1)) return false;
    LD r2 = 0;
    for (int k = 0; k < 3; ++k) {
      const LD e = w[k] - t * d[k];
      r2 += e * e;
    }
    return r2 <= 1e-18L * dd;  // (1e-9 |ab|)^2
  };

  size_t missing = 0;
  std::vector<uint32_t> seen(n, 0xffffffffu), stack;
  for (size_t s = 0; s < segments.size(); ++s) {
    const uint32_t a = segments[s][0], b = segments[s][1];
    bool found = false;
    stack.assign(1, a);
    seen[a] = static_cast<uint32_t>(s);
    while (!stack.empty() && !found) {
      const uint32_t u = stack.back();
      stack.pop_back();
      for (uint32_t v : adj[u]) {
        if (v == b) {
          found = true;
          break;
        }
        if (seen[v] == s || v < n_in || !on(v, a, b)) continue;
        seen[v] = static_cast<uint32_t>(s);
        stack.push_back(v);
      }
    }
    if (!found) {
      ++missing;
      if (verbose) std::fprintf(stderr, "missing segment %zu: %u %u\n", s, a, b);
    }
  }
  std::printf("%zu %zu %zu %zu\n", missing, segments.size(), flat_edges, merged_facets);
  return 0;
}
