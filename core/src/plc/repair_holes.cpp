// Repair step 3b (RepairOptions::fill_holes, after the T-junctions): every boundary loop of an open
// surface is closed by triangles. A boundary edge is a polygon edge that one
// facet alone uses; the loops are traced against the facets' orientation, so
// the patch continues the surface's sides. Each loop is triangulated with the
// smallest total area (the dynamic programme of Liepa 2003, "Filling holes in
// meshes", with area as the weight; no triangle of three collinear points),
// from the loop's own vertices: no point is constructed. A planar loop is
// triangulated as the polygon it is (planar_triangulation). The T-junction step
// and step 4 then treat the patch like any other facets (a patch that crosses the surface is
// cut along the crossing in step 4).
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <vector>

#include "geometry.hpp"
#include "predicates.hpp"
#include "repair.hpp"

namespace cdt3d {
namespace repair_steps {
namespace {

// Loops above this size are closed by clipping the ear of least area, one
// at a time (the dynamic programme is cubic in the loop's size).
constexpr size_t kMaxOptimalLoop = 240;

uint64_t undirected(VertexId a, VertexId b) {
  return (uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

double area(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u = b - a, v = c - a;
  return 0.5 * norm(cross(u, v));
}

// A boundary edge in the direction the patch uses it (against its facet's
// loop), with the facet it borders.
struct FillEdge {
  VertexId from, to;
  uint32_t facet;
};

// The boundary edges of the PLC, reversed: one facet uses the edge and no
// explicit segment is along it (a facet standing on a segment is closed
// there, as the self-intersection test treats it).
std::vector<FillEdge> boundary_edges(const Plc& plc) {
  std::unordered_map<uint64_t, uint32_t> uses;
  for (const Facet& f : plc.facets)
    for (const auto& loop : f.loops)
      for (size_t i = 0; i < loop.size(); ++i) ++uses[undirected(loop[i], loop[(i + 1) % loop.size()])];
  std::vector<uint64_t> segments;
  for (const auto& s : plc.segments) segments.push_back(undirected(s[0], s[1]));
  std::sort(segments.begin(), segments.end());
  std::vector<FillEdge> out;
  for (uint32_t fi = 0; fi < plc.facets.size(); ++fi)
    for (const auto& loop : plc.facets[fi].loops)
      for (size_t i = 0; i < loop.size(); ++i) {
        const VertexId a = loop[i], b = loop[(i + 1) % loop.size()];
        const uint64_t key = undirected(a, b);
        const auto it = uses.find(key);
        if (it == uses.end() || it->second != 1) continue;
        if (std::binary_search(segments.begin(), segments.end(), key)) continue;
        out.push_back({b, a, fi});
      }
  return out;
}

// Closed loops of fill edges. At a vertex where several boundary loops
// touch (a non-manifold vertex) the walk takes any unused edge; a walk that
// comes back to a vertex of its own path cuts the cycle off there, so every
// loop is simple. Edges that close no loop are left.
std::vector<std::vector<FillEdge>> trace_loops(const std::vector<FillEdge>& edges) {
  std::unordered_map<VertexId, std::vector<size_t>> out_of;
  for (size_t e = 0; e < edges.size(); ++e) out_of[edges[e].from].push_back(e);
  std::vector<char> used(edges.size(), 0);
  std::vector<std::vector<FillEdge>> loops;
  for (size_t start = 0; start < edges.size(); ++start) {
    if (used[start]) continue;
    std::vector<size_t> path{start};
    std::unordered_map<VertexId, size_t> at;  // vertex -> its index in path (as `from`)
    at[edges[start].from] = 0;
    used[start] = 1;
    while (!path.empty()) {
      const VertexId v = edges[path.back()].to;
      if (auto it = at.find(v); it != at.end()) {
        // A cycle from path[first] to the end.
        const size_t first = it->second;
        std::vector<FillEdge> loop;
        for (size_t k = first; k < path.size(); ++k) {
          loop.push_back(edges[path[k]]);
          at.erase(edges[path[k]].from);
        }
        path.resize(first);
        loops.push_back(std::move(loop));
        if (path.empty()) break;
        continue;
      }
      size_t next = edges.size();
      for (size_t e : out_of[v])
        if (!used[e]) {
          next = e;
          break;
        }
      if (next == edges.size()) break;  // open chain: no loop here
      used[next] = 1;
      at[v] = path.size();
      path.push_back(next);
    }
  }
  return loops;
}

// Triangles of the loop's vertices with the smallest total area, none of
// three collinear points; empty when there is no such triangulation.
std::vector<std::array<VertexId, 3>> min_area_triangulation(const Plc& plc,
                                                            const std::vector<VertexId>& v) {
  const size_t n = v.size();
  const double inf = std::numeric_limits<double>::infinity();
  auto weight = [&](size_t i, size_t k, size_t j) {
    const Vec3 &a = plc.points[v[i]], &b = plc.points[v[k]], &c = plc.points[v[j]];
    if (pred::collinear3d(&a.x, &b.x, &c.x)) return inf;
    return area(a, b, c);
  };
  std::vector<double> cost(n * n, 0);
  std::vector<uint32_t> split(n * n, 0);
  for (size_t len = 2; len < n; ++len)
    for (size_t i = 0; i + len < n; ++i) {
      const size_t j = i + len;
      double best = inf;
      uint32_t arg = 0;
      for (size_t k = i + 1; k < j; ++k) {
        const double c = cost[i * n + k] + cost[k * n + j] + weight(i, k, j);
        if (c < best) best = c, arg = static_cast<uint32_t>(k);
      }
      cost[i * n + j] = best;
      split[i * n + j] = arg;
    }
  std::vector<std::array<VertexId, 3>> tris;
  if (!std::isfinite(cost[n - 1])) return tris;
  std::vector<std::pair<size_t, size_t>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j - i < 2) continue;
    const size_t k = split[i * n + j];
    tris.push_back({v[i], v[k], v[j]});
    stack.push_back({i, k});
    stack.push_back({k, j});
  }
  return tris;
}

// Large loops: the ear of least area first, again and again (quadratic).
std::vector<std::array<VertexId, 3>> ear_triangulation(const Plc& plc, std::vector<VertexId> v) {
  std::vector<std::array<VertexId, 3>> tris;
  while (v.size() > 3) {
    size_t best = v.size();
    double best_area = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < v.size(); ++i) {
      const Vec3& a = plc.points[v[(i + v.size() - 1) % v.size()]];
      const Vec3& b = plc.points[v[i]];
      const Vec3& c = plc.points[v[(i + 1) % v.size()]];
      if (pred::collinear3d(&a.x, &b.x, &c.x)) continue;
      const double s = area(a, b, c);
      if (s < best_area) best_area = s, best = i;
    }
    if (best == v.size()) return {};
    tris.push_back({v[(best + v.size() - 1) % v.size()], v[best], v[(best + 1) % v.size()]});
    v.erase(v.begin() + static_cast<std::ptrdiff_t>(best));
  }
  const Vec3 &a = plc.points[v[0]], &b = plc.points[v[1]], &c = plc.points[v[2]];
  if (pred::collinear3d(&a.x, &b.x, &c.x)) return {};
  tris.push_back({v[0], v[1], v[2]});
  return tris;
}

// A loop whose vertices are exactly coplanar: its constrained triangulation
// as a polygon (triangulate_surface), each triangle turned like the loop.
// A least-area set of triangles of a non-convex planar loop can fold over
// itself; the polygon's own triangulation cannot. Empty when the loop is
// not planar or not a simple polygon in its plane.
std::vector<std::array<VertexId, 3>> planar_triangulation(const Plc& plc,
                                                          const std::vector<VertexId>& v) {
  const double* a = &plc.points[v[0]].x;
  size_t ib = 1, ic = 0;
  for (; ib < v.size() && plc.points[v[ib]] == plc.points[v[0]]; ++ib) {
  }
  if (ib >= v.size()) return {};
  const double* b = &plc.points[v[ib]].x;
  for (size_t i = ib + 1; i < v.size() && ic == 0; ++i)
    if (!pred::collinear3d(a, b, &plc.points[v[i]].x)) ic = i;
  if (ic == 0) return {};
  const double* c = &plc.points[v[ic]].x;
  for (VertexId x : v)
    if (pred::orient3d(a, b, c, &plc.points[x].x) != 0) return {};
  int drop = 0;
  while (drop < 2 && pred::orient2d_projected(a, b, c, drop) == 0) ++drop;
  // The loop's turn: at its lowest vertex (in the projection) it is convex.
  const int ua = (drop + 1) % 3, va = (drop + 2) % 3;
  size_t low = 0;
  for (size_t i = 1; i < v.size(); ++i) {
    const double *p = &plc.points[v[i]].x, *q = &plc.points[v[low]].x;
    if (p[ua] < q[ua] || (p[ua] == q[ua] && p[va] < q[va])) low = i;
  }
  const size_t n = v.size();
  const int turn = pred::orient2d_projected(&plc.points[v[(low + n - 1) % n]].x, &plc.points[v[low]].x,
                                            &plc.points[v[(low + 1) % n]].x, drop);
  if (turn == 0) return {};
  Plc part;
  part.points = plc.points;
  Facet f;
  f.loops.push_back(v);
  part.facets.push_back(f);
  std::vector<uint32_t> tris, tri_facet;
  if (!triangulate_surface(part, tris, tri_facet).ok()) return {};
  std::vector<std::array<VertexId, 3>> out;
  for (size_t k = 0; k + 2 < tris.size(); k += 3) {
    std::array<VertexId, 3> t{tris[k], tris[k + 1], tris[k + 2]};
    if (pred::orient2d_projected(&plc.points[t[0]].x, &plc.points[t[1]].x, &plc.points[t[2]].x, drop) != turn)
      std::swap(t[1], t[2]);
    out.push_back(t);
  }
  return out;
}

}  // namespace

bool has_boundary(const Plc& plc) { return !boundary_edges(plc).empty(); }

void fill_holes(Work& w, RepairReport& report) {
  for (const std::vector<FillEdge>& loop : trace_loops(boundary_edges(w.plc))) {
    std::vector<VertexId> v;
    for (const FillEdge& e : loop) v.push_back(e.from);
    if (v.size() < 3) continue;  // two facets' edges on one line: nothing to fill
    std::vector<std::array<VertexId, 3>> tris = planar_triangulation(w.plc, v);
    if (tris.empty())
      tris = v.size() <= kMaxOptimalLoop ? min_area_triangulation(w.plc, v) : ear_triangulation(w.plc, v);
    if (tris.empty()) {
      ++report.unfilled_holes;
      continue;
    }
    // The patch belongs to the facet along the loop's first edge (marker,
    // source line or record, provenance).
    const uint32_t next_to = loop.front().facet;
    const Facet beside = w.plc.facets[next_to];  // a copy: push_back may move the facets
    for (const auto& t : tris) {
      w.plc.facets.push_back(part_of(beside, {t[0], t[1], t[2]}));
      w.source.push_back(w.source[next_to]);
    }
    w.mark(w.source[next_to]);
    ++report.filled_holes;
    report.fill_triangles += tris.size();
  }
}

}  // namespace repair_steps
}  // namespace cdt3d
