// Writes any model cdt3d reads (STL ASCII/binary, OFF, OBJ, PLY, .poly,
// .smesh) as a TetGen .poly file, so that Debian's `tetgen` (run as a separate
// process by tests/bench/bench_corpus.sh) meshes exactly the PLC cdt3d meshes:
// the same welded points, facets (polygons with facet holes), explicit
// segments, volume holes and regions.
//
// usage: plc_to_poly MODEL OUT.poly
// Build (bench_corpus.sh does this):
//   c++ -O2 -std=c++17 -Icore/include tests/bench/plc_to_poly.cpp
//       .build/bench/core/libcdt3d.a -o .build/bench/bench/plc_to_poly
//
// Output, numbered from 1, coordinates printed with %.17g (exact round trip):
//   part 1  nodes: every PLC point (isolated points too; TetGen keeps them)
//   part 2  facets with boundary markers; each facet's loops are its polygons,
//           its holes its facet holes. An explicit segment lying in a facet
//           (both endpoints in its plane, midpoint inside or on the facet) is
//           added to that facet as a 2-vertex polygon, as TetGen wants it
//           (TetGen 1.5 aborts in fillregion() when such a segment comes as
//           a facet of its own); any other explicit segment becomes a facet
//           with one 2-vertex polygon. The in-plane test uses long double
//           with a relative tolerance of 1e-12: fine for a benchmark tool.
//   part 3  volume holes
//   part 4  regions: point, attribute, max volume (-1: none)
// Exit codes: 0 written, 1 read or write error (message on stderr), 2 usage.
#include <cdt3d/cdt3d.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

namespace {

using cdt3d::Vec3;
using LD = long double;

void point(std::FILE* f, const Vec3& p) { std::fprintf(f, " %.17g %.17g %.17g", p.x, p.y, p.z); }

// True if segment a-b lies in facet fc: both endpoints in its plane and the
// midpoint inside (even-odd rule over all loops) or on a loop edge.
bool segment_in_facet(const cdt3d::Plc& plc, const cdt3d::Facet& fc, const Vec3& a, const Vec3& b) {
  const auto& outer = fc.loops[0];
  LD n[3] = {0, 0, 0};  // Newell normal of the first loop
  for (size_t i = 0; i < outer.size(); ++i) {
    const Vec3& p = plc.points[outer[i]];
    const Vec3& q = plc.points[outer[(i + 1) % outer.size()]];
    n[0] += (LD(p.y) - q.y) * (LD(p.z) + q.z);
    n[1] += (LD(p.z) - q.z) * (LD(p.x) + q.x);
    n[2] += (LD(p.x) - q.x) * (LD(p.y) + q.y);
  }
  const LD nn = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (nn == 0) return false;
  const Vec3& o = plc.points[outer[0]];
  LD scale = 0;
  for (const auto& loop : fc.loops)
    for (cdt3d::VertexId v : loop) {
      const Vec3& p = plc.points[v];
      scale = std::fmax(scale, std::fabs(LD(p.x) - o.x) + std::fabs(LD(p.y) - o.y) +
                                   std::fabs(LD(p.z) - o.z));
    }
  const LD eps = 1e-12L * (scale > 0 ? scale : 1);
  auto dist = [&](const Vec3& p) {
    return (n[0] * (LD(p.x) - o.x) + n[1] * (LD(p.y) - o.y) + n[2] * (LD(p.z) - o.z)) / nn;
  };
  if (std::fabs(dist(a)) > eps || std::fabs(dist(b)) > eps) return false;
  // Project to the plane dropping the largest normal component.
  int drop = 0;
  for (int k = 1; k < 3; ++k)
    if (std::fabs(n[k]) > std::fabs(n[drop])) drop = k;
  auto uv = [drop](const Vec3& p, LD& u, LD& v) {
    const LD c[3] = {p.x, p.y, p.z};
    u = c[drop == 0 ? 1 : 0];
    v = c[drop == 2 ? 1 : 2];
  };
  const Vec3 m{(a.x + b.x) / 2, (a.y + b.y) / 2, (a.z + b.z) / 2};
  LD mu, mv;
  uv(m, mu, mv);
  bool inside = false;
  for (const auto& loop : fc.loops)
    for (size_t i = 0; i < loop.size(); ++i) {
      LD pu, pv, qu, qv;
      uv(plc.points[loop[i]], pu, pv);
      uv(plc.points[loop[(i + 1) % loop.size()]], qu, qv);
      const LD cross = (qu - pu) * (mv - pv) - (qv - pv) * (mu - pu);
      const LD len = std::fabs(qu - pu) + std::fabs(qv - pv);
      if (std::fabs(cross) <= eps * len && (mu - pu) * (mu - qu) <= 0 && (mv - pv) * (mv - qv) <= 0)
        return true;  // on this edge
      if ((pv > mv) != (qv > mv) && mu < pu + (mv - pv) * (qu - pu) / (qv - pv)) inside = !inside;
    }
  return inside;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: plc_to_poly MODEL OUT.poly\n");
    return 2;
  }
  cdt3d::Plc plc;
  const cdt3d::Status st = cdt3d::read_plc_file(argv[1], plc);
  if (!st.ok()) {
    std::fprintf(stderr, "plc_to_poly: %s\n", st.error.to_string().c_str());
    return 1;
  }
  std::FILE* f = std::fopen(argv[2], "wb");
  if (!f) {
    std::perror(argv[2]);
    return 1;
  }
  std::fprintf(f, "# %s converted by cdt3d tests/bench/plc_to_poly\n", argv[1]);
  std::fprintf(f, "# part 1: nodes\n%zu 3 0 0\n", plc.points.size());
  for (size_t i = 0; i < plc.points.size(); ++i) {
    std::fprintf(f, "%zu", i + 1);
    point(f, plc.points[i]);
    std::fputc('\n', f);
  }
  // Explicit segments: into the facet they lie in, else a facet of their own.
  std::vector<std::vector<size_t>> in_facet(plc.facets.size());
  std::vector<size_t> alone;
  for (size_t s = 0; s < plc.segments.size(); ++s) {
    const Vec3& a = plc.points[plc.segments[s][0]];
    const Vec3& b = plc.points[plc.segments[s][1]];
    size_t k = 0;
    while (k < plc.facets.size() && !segment_in_facet(plc, plc.facets[k], a, b)) ++k;
    if (k < plc.facets.size())
      in_facet[k].push_back(s);
    else
      alone.push_back(s);
  }
  std::fprintf(f, "# part 2: facets\n%zu 1\n", plc.facets.size() + alone.size());
  for (size_t k = 0; k < plc.facets.size(); ++k) {
    const cdt3d::Facet& fc = plc.facets[k];
    std::fprintf(f, "%zu %zu %d\n", fc.loops.size() + in_facet[k].size(), fc.holes.size(),
                 fc.marker);
    for (const auto& loop : fc.loops) {
      std::fprintf(f, "%zu", loop.size());
      for (cdt3d::VertexId v : loop) std::fprintf(f, " %zu", size_t(v) + 1);
      std::fputc('\n', f);
    }
    for (size_t s : in_facet[k])
      std::fprintf(f, "2 %zu %zu\n", size_t(plc.segments[s][0]) + 1, size_t(plc.segments[s][1]) + 1);
    for (size_t h = 0; h < fc.holes.size(); ++h) {
      std::fprintf(f, "%zu", h + 1);
      point(f, fc.holes[h]);
      std::fputc('\n', f);
    }
  }
  for (size_t s : alone)
    std::fprintf(f, "1 0 0\n2 %zu %zu\n", size_t(plc.segments[s][0]) + 1,
                 size_t(plc.segments[s][1]) + 1);
  std::fprintf(f, "# part 3: volume holes\n%zu\n", plc.holes.size());
  for (size_t h = 0; h < plc.holes.size(); ++h) {
    std::fprintf(f, "%zu", h + 1);
    point(f, plc.holes[h]);
    std::fputc('\n', f);
  }
  std::fprintf(f, "# part 4: regions\n%zu\n", plc.regions.size());
  for (size_t r = 0; r < plc.regions.size(); ++r) {
    std::fprintf(f, "%zu", r + 1);
    point(f, plc.regions[r].point);
    std::fprintf(f, " %.17g %.17g\n", plc.regions[r].attribute, plc.regions[r].max_volume);
  }
  if (std::fclose(f) != 0) {
    std::fprintf(stderr, "plc_to_poly: error while writing %s\n", argv[2]);
    return 1;
  }
  return 0;
}
