// Repair step 2: a facet whose vertices do not lie in one plane (typically a
// non-planar OBJ quad) is split into triangles, each of which is planar.
//
// The split is an ear clipping of the polygon projected onto the coordinate
// plane that drops the largest component of its (floating-point) Newell
// normal. The normal only picks the projection; every decision is an exact
// orient2d of projected points (dropping a coordinate rounds nothing). An
// ear is a strictly convex corner, so every triangle has nonzero area in 3D
// too. If the projection is not a simple polygon no ear may be found; the
// rest is then cut into a fan that skips collinear corners, and the exact
// self-intersection test reports whatever that fan gets wrong.
#include <algorithm>
#include <cmath>

#include "geometry.hpp"
#include "predicates.hpp"
#include "repair.hpp"

namespace cdt3d {
namespace repair_steps {
namespace {

const double* xyz(const Plc& plc, VertexId v) { return &plc.points[v].x; }

bool planar(const Plc& plc, const Facet& f) {
  const auto& first = f.loops[0];
  const double* a = xyz(plc, first[0]);
  const double* b = xyz(plc, first[1]);
  const double* c = nullptr;
  for (size_t i = 2; i < first.size() && !c; ++i)
    if (!pred::collinear3d(a, b, xyz(plc, first[i]))) c = xyz(plc, first[i]);
  if (!c) return true;  // zero area: step 1 dropped such polygons
  for (const auto& loop : f.loops)
    for (VertexId v : loop)
      if (pred::orient3d(a, b, c, xyz(plc, v)) != 0) return false;
  return true;
}

int projection_axis(const Plc& plc, const std::vector<VertexId>& loop) {
  const Vec3 n = newell_normal(plc, loop);
  return largest_axis(n.x, n.y, n.z);
}

// Orientation of the projected polygon: the sign of the corner at its
// lexicographically smallest vertex (a convex corner of any simple polygon).
int orientation(const Plc& plc, const std::vector<VertexId>& poly, int drop) {
  const int u = (drop + 1) % 3, v = (drop + 2) % 3;
  size_t best = 0;
  for (size_t i = 1; i < poly.size(); ++i) {
    const double *p = xyz(plc, poly[i]), *q = xyz(plc, poly[best]);
    if (p[u] < q[u] || (p[u] == q[u] && p[v] < q[v])) best = i;
  }
  const size_t m = poly.size();
  const int o = pred::orient2d_projected(xyz(plc, poly[(best + m - 1) % m]), xyz(plc, poly[best]),
                                         xyz(plc, poly[(best + 1) % m]), drop);
  return o == 0 ? 1 : o;
}

bool is_ear(const Plc& plc, const std::vector<VertexId>& poly, size_t i, int drop, int sign) {
  const size_t m = poly.size();
  const VertexId a = poly[(i + m - 1) % m], b = poly[i], c = poly[(i + 1) % m];
  const double *pa = xyz(plc, a), *pb = xyz(plc, b), *pc = xyz(plc, c);
  if (pred::orient2d_projected(pa, pb, pc, drop) != sign) return false;
  for (VertexId v : poly) {
    if (v == a || v == b || v == c) continue;
    const double* p = xyz(plc, v);
    const int s0 = pred::orient2d_projected(pa, pb, p, drop);
    const int s1 = pred::orient2d_projected(pb, pc, p, drop);
    const int s2 = pred::orient2d_projected(pc, pa, p, drop);
    if (s0 != -sign && s1 != -sign && s2 != -sign) return false;  // in the closed triangle
  }
  return true;
}

void triangulate_loop(const Plc& plc, std::vector<VertexId> poly,
                      std::vector<std::array<VertexId, 3>>& out) {
  const int drop = projection_axis(plc, poly);
  const int sign = orientation(plc, poly, drop);
  while (poly.size() > 3) {
    size_t ear = poly.size();
    for (size_t i = 0; i < poly.size() && ear == poly.size(); ++i)
      if (is_ear(plc, poly, i, drop, sign)) ear = i;
    if (ear == poly.size()) break;
    const size_t m = poly.size();
    out.push_back({poly[(ear + m - 1) % m], poly[ear], poly[(ear + 1) % m]});
    poly.erase(poly.begin() + static_cast<std::ptrdiff_t>(ear));
  }
  // Three corners left, or no ear (projection not simple): a fan that skips
  // collinear corners.
  for (size_t i = 1; i + 1 < poly.size(); ++i) {
    if (pred::collinear3d(xyz(plc, poly[0]), xyz(plc, poly[i]), xyz(plc, poly[i + 1]))) continue;
    out.push_back({poly[0], poly[i], poly[i + 1]});
  }
}

}  // namespace

void split_nonplanar_facets(Work& w, RepairReport& report) {
  Plc& plc = w.plc;
  std::vector<Facet> facets;
  std::vector<uint32_t> source;
  facets.reserve(plc.facets.size());
  source.reserve(plc.facets.size());
  std::vector<std::array<VertexId, 3>> tris;
  for (size_t f = 0; f < plc.facets.size(); ++f) {
    Facet& facet = plc.facets[f];
    if (planar(plc, facet)) {
      facets.push_back(std::move(facet));
      source.push_back(w.source[f]);
      continue;
    }
    ++report.nonplanar_facets;
    w.mark(w.source[f]);
    // Each polygon on its own: facet holes of a non-planar facet have no
    // meaning, so nested polygons are triangulated like the others.
    tris.clear();
    for (const auto& loop : facet.loops) triangulate_loop(plc, loop, tris);
    for (const auto& t : tris) {
      facets.push_back(part_of(facet, {t[0], t[1], t[2]}));
      source.push_back(w.source[f]);
    }
  }
  plc.facets = std::move(facets);
  w.source = std::move(source);
}

}  // namespace repair_steps
}  // namespace cdt3d
