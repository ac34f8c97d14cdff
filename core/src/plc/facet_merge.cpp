// merge_coplanar_facets(): TetGen's default (without -M) as an option. Facets
// that share an edge and lie in one plane (exact orient3d) are joined into one
// polygon facet, so their common edges stop being segments and the mesh needs
// no Steiner points on them (§5 splits missing segments; fewer segments, fewer
// splits).
//
// Conservative by design, each rule keeping the merged PLC valid without any
// construction:
//  * only single-loop facets without facet holes, with equal markers, are
//    merged, across an edge used by exactly those two facets;
//  * a group is merged only when its boundary (the edges used by exactly one
//    of its facets) is one simple cycle: a simply connected polygon. Groups
//    whose union has a hole or a pinch keep their facets (a hole would need a
//    hole point, i.e. a constructed, rounded point);
//  * vertices strictly inside the merged polygon stay PLC points; facet
//    triangulation finds them (facet_triangulate.cpp, step 1).
#include <algorithm>
#include <array>
#include <cdt3d/cdt3d.hpp>
#include <numeric>
#include <vector>

#include "predicates.hpp"

namespace cdt3d {
namespace {

struct Edge {
  VertexId lo, hi;
  uint32_t facet;
  bool operator<(const Edge& o) const {
    return lo != o.lo ? lo < o.lo : hi != o.hi ? hi < o.hi : facet < o.facet;
  }
};

uint32_t find_root(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

bool mergeable(const Facet& f) { return f.loops.size() == 1 && f.holes.empty(); }

// Exact: every vertex of g lies in the plane of f's first non-collinear triple.
bool coplanar(const Plc& plc, const Facet& f, const Facet& g) {
  const auto& L = f.loops[0];
  const double* a = &plc.points[L[0]].x;
  const double* b = &plc.points[L[1]].x;
  const double* c = nullptr;
  for (size_t i = 2; i < L.size() && !c; ++i)
    if (!pred::collinear3d(a, b, &plc.points[L[i]].x)) c = &plc.points[L[i]].x;
  if (!c) return false;
  for (VertexId v : g.loops[0])
    if (pred::orient3d(a, b, c, &plc.points[v].x) != 0) return false;
  return true;
}

// The boundary of a group as one cycle, or false (several cycles, pinches).
bool boundary_cycle(const std::vector<std::array<VertexId, 2>>& edges, std::vector<VertexId>& loop) {
  loop.clear();
  if (edges.size() < 3) return false;
  std::vector<std::array<VertexId, 3>> inc;  // (vertex, other end, edge)
  for (uint32_t e = 0; e < edges.size(); ++e) {
    inc.push_back({edges[e][0], edges[e][1], e});
    inc.push_back({edges[e][1], edges[e][0], e});
  }
  std::sort(inc.begin(), inc.end());
  for (size_t i = 0; i < inc.size(); i += 2)
    if (i + 1 >= inc.size() || inc[i][0] != inc[i + 1][0] ||
        (i + 2 < inc.size() && inc[i + 2][0] == inc[i][0]))
      return false;  // every boundary vertex has exactly two boundary edges
  auto next = [&](VertexId v, VertexId from) {
    auto it = std::lower_bound(inc.begin(), inc.end(), std::array<VertexId, 3>{v, 0, 0});
    return it[0][1] == from ? it[1][1] : it[0][1];
  };
  VertexId prev = edges[0][0], cur = edges[0][1];
  loop.push_back(prev);
  while (cur != edges[0][0] && loop.size() <= edges.size()) {
    loop.push_back(cur);
    const VertexId n = next(cur, prev);
    prev = cur, cur = n;
  }
  return loop.size() == edges.size();
}

}  // namespace

size_t merge_coplanar_facets(const Plc& plc, Plc& out, std::vector<uint32_t>& merged_into) {
  const uint32_t nf = static_cast<uint32_t>(plc.facets.size());
  std::vector<Edge> edges;
  for (uint32_t f = 0; f < nf; ++f)
    for (const auto& L : plc.facets[f].loops)
      for (size_t i = 0; i < L.size(); ++i) {
        const VertexId p = L[i], q = L[(i + 1) % L.size()];
        edges.push_back({std::min(p, q), std::max(p, q), f});
      }
  std::sort(edges.begin(), edges.end());
  std::vector<uint32_t> parent(nf);
  std::iota(parent.begin(), parent.end(), 0u);
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    if (j - i == 2) {
      const Facet& f = plc.facets[edges[i].facet];
      const Facet& g = plc.facets[edges[i + 1].facet];
      if (mergeable(f) && mergeable(g) && f.marker == g.marker && coplanar(plc, f, g)) {
        const uint32_t a = find_root(parent, edges[i].facet), b = find_root(parent, edges[i + 1].facet);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);  // root: smallest facet id
      }
    }
    i = j;
  }
  // Per group: its boundary edges (used by exactly one of its facets).
  std::vector<uint32_t> root(nf);
  for (uint32_t f = 0; f < nf; ++f) root[f] = find_root(parent, f);
  std::vector<std::vector<std::array<VertexId, 2>>> boundary(nf);
  for (size_t i = 0; i < edges.size();) {
    size_t j = i;
    while (j < edges.size() && edges[j].lo == edges[i].lo && edges[j].hi == edges[i].hi) ++j;
    for (size_t k = i; k < j; ++k) {
      size_t same = 0;
      for (size_t m = i; m < j; ++m) same += root[edges[m].facet] == root[edges[k].facet];
      if (same == 1) boundary[root[edges[k].facet]].push_back({edges[k].lo, edges[k].hi});
    }
    i = j;
  }
  out = plc;
  out.facets.clear();
  merged_into.assign(nf, kNone);
  std::vector<uint32_t> group_size(nf, 0);
  for (uint32_t f = 0; f < nf; ++f) ++group_size[root[f]];
  std::vector<VertexId> loop;
  std::vector<uint8_t> merged(nf, 0);
  size_t joined = 0;
  for (uint32_t f = 0; f < nf; ++f) {
    if (root[f] != f || group_size[f] < 2) continue;
    // Keep the orientation of the group's first facet: walk the cycle in the
    // direction that facet's boundary edges run.
    if (!boundary_cycle(boundary[f], loop)) continue;
    const auto& L = plc.facets[f].loops[0];
    bool reverse = false;
    for (size_t i = 0; i < loop.size(); ++i) {
      const VertexId p = loop[i], q = loop[(i + 1) % loop.size()];
      for (size_t k = 0; k < L.size(); ++k) {
        if (L[k] == q && L[(k + 1) % L.size()] == p) reverse = true;
      }
    }
    if (reverse) std::reverse(loop.begin(), loop.end());
    merged[f] = 1;
    Facet m = plc.facets[f];
    m.loops.assign(1, loop);
    merged_into[f] = static_cast<uint32_t>(out.facets.size());
    out.facets.push_back(std::move(m));
    joined += group_size[f] - 1;
  }
  for (uint32_t f = 0; f < nf; ++f) {
    if (merged[root[f]]) {
      merged_into[f] = merged_into[root[f]];
      continue;
    }
    merged_into[f] = static_cast<uint32_t>(out.facets.size());
    out.facets.push_back(plc.facets[f]);
  }
  return joined;
}

}  // namespace cdt3d
