// merge_flat_facets(): flat faces as one facet each (the default of
// tetrahedralize(), like TetGen's -p without -M).
//
// A CAD part exported as triangles splits every planar face along diagonals
// that mean nothing. An edge is *flat* when exactly two facets use it, both
// are single-loop polygons without facet holes and with equal markers, it is
// no explicit segment, their vertices are exactly coplanar (orient3d = 0) and
// the two facets lie on opposite sides of it in their plane. Facets joined by
// flat edges form one merged facet: a planar region, possibly with holes,
// pinches and input vertices inside it. Every other edge (one facet, three or
// more, a fold, different planes, an explicit segment) stays a segment: on
// the loop of a facet that uses it, or, when it lies inside every merged
// facet that uses it (two flat faces crossing along it), as an explicit
// segment of the merged PLC.
//
// The merged facet is represented without any constructed point: its loops
// are the cycles of its boundary edges (the edges an odd number of its
// triangles use), and its region is the even-odd rule over those loops
// (Facet::even_odd). For triangles with disjoint interiors the parity of
// the loops around a point equals the number of input facets covering it,
// modulo 2, so the region is exactly the union of the input facets. Input
// vertices strictly inside the region stay PLC points; facet triangulation
// finds them (facet_triangulate.cpp, step 1). All tests are exact.
#include <algorithm>
#include <array>
#include <cdt3d/cdt3d.hpp>
#include <numeric>
#include <vector>

#include "facet_merge.hpp"
#include "geometry.hpp"
#include "predicates.hpp"
#include "radix_sort.hpp"

namespace cdt3d {
namespace {

struct EdgeUse {
  VertexId lo, hi;
  uint32_t facet;
  bool forward;  // the loop runs lo -> hi
  bool operator<(const EdgeUse& o) const {
    return lo != o.lo ? lo < o.lo : hi != o.hi ? hi < o.hi : facet < o.facet;
  }
};

uint32_t find_root(std::vector<uint32_t>& parent, uint32_t x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

const double* xyz(const Plc& plc, VertexId v) { return &plc.points[v].x; }

// A facet that may join others: one loop of >= 3 valid indices, no holes.
// (The input need not have passed check_plc yet: bad facets stay as they
// are and check_plc reports them.)
bool mergeable(const Plc& plc, const Facet& f) {
  if (f.loops.size() != 1 || !f.holes.empty() || f.loops[0].size() < 3) return false;
  for (VertexId v : f.loops[0])
    if (v >= plc.points.size()) return false;
  return true;
}

// The facet's plane: three non-collinear loop vertices and an axis whose
// projection keeps them non-collinear; false for a degenerate loop.
struct Plane {
  const double *a, *b, *c;
  int drop;
};
bool facet_plane(const Plc& plc, const Facet& f, Plane& p) {
  const auto& L = f.loops[0];
  p.a = xyz(plc, L[0]), p.b = xyz(plc, L[1]), p.c = nullptr;
  for (size_t i = 2; i < L.size() && !p.c; ++i)
    if (!pred::collinear3d(p.a, p.b, xyz(plc, L[i]))) p.c = xyz(plc, L[i]);
  if (!p.c) return false;
  p.drop = projection_axis(p.a, p.b, p.c);
  for (int k = 0; k < 3 && pred::orient2d_projected(p.a, p.b, p.c, p.drop) == 0; ++k) p.drop = k;
  return pred::orient2d_projected(p.a, p.b, p.c, p.drop) != 0;
}

// g lies in the plane through a, b, c (three vertices of f): its vertices
// that are no vertices of f (those lie in it; testing them would take the
// predicates' slow exact path, as every zero does) are exactly in it.
bool in_plane(const Plc& plc, const double* a, const double* b, const double* c,
              const Facet& f, const Facet& g) {
  const auto& F = f.loops[0];
  for (VertexId v : g.loops[0])
    if (std::find(F.begin(), F.end(), v) == F.end() && pred::orient3d(a, b, c, xyz(plc, v)) != 0)
      return false;
  return true;
}

// Splits the boundary edges of a group into simple cycles. Directed by the
// loops when every vertex has as many boundary edges in as out (consistent
// orientation), else undirected. A walk that comes back to a vertex of its
// own path cuts the cycle off there, so every cycle is simple.
void boundary_cycles(std::vector<std::array<VertexId, 2>> edges,
                     std::vector<std::vector<VertexId>>& cycles) {
  cycles.clear();
  const size_t m = edges.size();
  std::vector<std::array<VertexId, 2>> out_of;  // (tail, edge) sorted
  bool directed = true;
  {
    std::vector<VertexId> tails, heads;
    for (const auto& e : edges) tails.push_back(e[0]), heads.push_back(e[1]);
    std::sort(tails.begin(), tails.end());
    std::sort(heads.begin(), heads.end());
    directed = tails == heads;
  }
  for (uint32_t e = 0; e < m; ++e) {
    out_of.push_back({edges[e][0], e});
    if (!directed) out_of.push_back({edges[e][1], e});
  }
  std::sort(out_of.begin(), out_of.end());
  std::vector<uint8_t> used(m, 0);
  auto first_at = [&](VertexId v) {
    return std::lower_bound(out_of.begin(), out_of.end(), std::array<VertexId, 2>{v, 0}) -
           out_of.begin();
  };
  auto take = [&](VertexId v, uint32_t& e, VertexId& to) {
    for (size_t i = first_at(v); i < out_of.size() && out_of[i][0] == v; ++i) {
      const uint32_t k = out_of[i][1];
      if (used[k]) continue;
      used[k] = 1;
      e = k;
      to = edges[k][0] == v ? edges[k][1] : edges[k][0];
      return true;
    }
    return false;
  };
  std::vector<VertexId> path;
  for (uint32_t s = 0; s < m; ++s) {
    if (used[s]) continue;
    used[s] = 1;
    path.assign({edges[s][0], edges[s][1]});
    for (;;) {
      uint32_t e;
      VertexId to;
      if (!take(path.back(), e, to)) break;  // cannot happen on an Eulerian edge set
      auto it = std::find(path.begin(), path.end(), to);
      if (it != path.end()) {
        cycles.emplace_back(it, path.end());
        path.erase(it + 1, path.end());
        if (path.size() == 1) break;
      } else {
        path.push_back(to);
      }
    }
    if (path.size() > 2 && path.front() == path.back()) {
      path.pop_back();
      cycles.push_back(path);
    }
  }
}

}  // namespace

size_t merge_flat_facets(const Plc& plc, Plc& out, std::vector<uint32_t>& merged_into,
                         size_t* flat_edges) {
  return merge_flat_facets(plc, out, merged_into, flat_edges, nullptr);
}

size_t merge_flat_facets(const Plc& plc, Plc& out, std::vector<uint32_t>& merged_into,
                         size_t* flat_edges, FlatFaceInsides* insides) {
  const uint32_t nf = static_cast<uint32_t>(plc.facets.size());
  // Per facet: 1 mergeable, 0 not; planes and orientations are made on the
  // first coplanar neighbour (most edges of a curved surface fail the quick
  // test below first): 2 once made, 0 when the loop turned out degenerate.
  std::vector<uint8_t> ok(nf, 0);
  std::vector<Plane> plane(nf);
  std::vector<int> orient(nf, 0);
  for (uint32_t f = 0; f < nf; ++f) ok[f] = mergeable(plc, plc.facets[f]);
  auto with_plane = [&](uint32_t f) {
    if (ok[f] == 1) {
      ok[f] = 0;
      if (facet_plane(plc, plc.facets[f], plane[f])) {
        orient[f] = loop_orientation(plc, plc.facets[f].loops[0], plane[f].drop);
        if (orient[f] != 0) ok[f] = 2;
      }
    }
    return ok[f] == 2;
  };
  // g in f's plane. Its first three vertices decide at once on a curved
  // surface (the predicate's filter, before any plane is made); only when
  // they are collinear does the plane's own triple have to decide again.
  auto coplanar = [&](uint32_t f, uint32_t g) {
    const Facet &F = plc.facets[f], &G = plc.facets[g];
    const auto& L = F.loops[0];
    const double* c = xyz(plc, L[2]);
    if (!in_plane(plc, xyz(plc, L[0]), xyz(plc, L[1]), c, F, G) || !with_plane(f) ||
        !with_plane(g))
      return false;
    const Plane& p = plane[f];  // p.a, p.b are L[0], L[1]
    return p.c == c || in_plane(plc, p.a, p.b, p.c, F, G);
  };
  std::vector<EdgeUse> uses;
  for (uint32_t f = 0; f < nf; ++f)
    for (const auto& L : plc.facets[f].loops)
      for (size_t i = 0; i < L.size(); ++i) {
        const VertexId p = L[i], q = L[(i + 1) % L.size()];
        uses.push_back({std::min(p, q), std::max(p, q), f, p < q});
      }
  // By edge, then facet: uses are made in facet order and the radix sort is
  // stable (cheaper than std::sort's comparisons).
  const int b = index_bits(plc.points.size() + 1);
  if (2 * b <= 64)
    radix_sort_by(uses, [b](const EdgeUse& u) { return (uint64_t(u.lo) << b) | u.hi; }, 0, 2 * b);
  else
    std::sort(uses.begin(), uses.end());
  std::vector<std::array<VertexId, 2>> explicit_segs;
  for (const auto& s : plc.segments) explicit_segs.push_back({std::min(s[0], s[1]), std::max(s[0], s[1])});
  std::sort(explicit_segs.begin(), explicit_segs.end());

  std::vector<uint32_t> parent(nf);
  std::iota(parent.begin(), parent.end(), 0u);
  size_t nflat = 0;
  for (size_t i = 0; i < uses.size();) {
    size_t j = i;
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) ++j;
    const EdgeUse &x = uses[i], &y = uses[i + 1];
    if (j - i == 2 && x.facet != y.facet && ok[x.facet] && ok[y.facet] && x.lo != x.hi &&
        plc.facets[x.facet].marker == plc.facets[y.facet].marker &&
        !std::binary_search(explicit_segs.begin(), explicit_segs.end(),
                            std::array<VertexId, 2>{x.lo, x.hi}) &&
        coplanar(x.facet, y.facet)) {
      // Same projection for both (one plane). The interior of a loop lies
      // left of its edges when it turns counterclockwise: the facets are on
      // opposite sides of lo -> hi when those sides differ.
      const int drop = plane[x.facet].drop;
      const int sy = plane[y.facet].drop == drop
                         ? orient[y.facet]
                         : loop_orientation(plc, plc.facets[y.facet].loops[0], drop);
      const int side_x = orient[x.facet] * (x.forward ? 1 : -1);
      const int side_y = sy * (y.forward ? 1 : -1);
      if (sy != 0 && side_x != side_y) {
        ++nflat;
        const uint32_t a = find_root(parent, x.facet), b = find_root(parent, y.facet);
        if (a != b) parent[std::max(a, b)] = std::min(a, b);  // root: smallest facet id
      }
    }
    i = j;
  }
  if (flat_edges) *flat_edges = nflat;
  if (nflat == 0 && insides) {
    // Nothing to merge: the pipeline goes on with the input itself (most
    // curved models), so no copy of it is made.
    out = Plc();
    merged_into.resize(nf);
    std::iota(merged_into.begin(), merged_into.end(), 0u);
    *insides = FlatFaceInsides();
    return 0;
  }

  std::vector<uint32_t> root(nf), size(nf, 0);
  for (uint32_t f = 0; f < nf; ++f) ++size[root[f] = find_root(parent, f)];
  std::vector<std::vector<uint32_t>> members(insides ? nf : 0);  // per group root
  if (insides) {
    insides->vertices.clear();
    insides->segments = 0;
    for (uint32_t f = 0; f < nf; ++f)
      if (size[root[f]] > 1) members[root[f]].push_back(f);
  }
  // Per group: its boundary edges, directed as its facets' loops run them
  // (the edges used an odd number of times by its facets).
  std::vector<std::vector<std::array<VertexId, 2>>> boundary(nf);
  std::vector<std::array<VertexId, 2>> crossing_edges;
  for (size_t i = 0; i < uses.size();) {
    size_t j = i;
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi) ++j;
    bool on_a_loop = false, several_groups = false;
    for (size_t k = i; k < j; ++k) {
      const uint32_t r = root[uses[k].facet];
      several_groups = several_groups || r != root[uses[i].facet];
      if (size[r] < 2) {
        on_a_loop = true;  // a facet merged with none keeps its loop
        continue;
      }
      size_t same = 0;
      for (size_t m = i; m < j; ++m) same += root[uses[m].facet] == r;
      on_a_loop = on_a_loop || same % 2 == 1;
      bool first = true;  // the group's first use of this edge stands for it
      for (size_t m = i; m < k; ++m) first = first && root[uses[m].facet] != r;
      if (same % 2 == 1 && first) {
        const EdgeUse& u = uses[k];
        boundary[r].push_back(u.forward ? std::array<VertexId, 2>{u.lo, u.hi}
                                        : std::array<VertexId, 2>{u.hi, u.lo});
      }
      // An inner edge of the group that another facet or an explicit
      // segment also uses stays a segment inside the merged facet.
      if (insides && same % 2 == 0 && first &&
          (same < j - i || std::binary_search(explicit_segs.begin(), explicit_segs.end(),
                                              std::array<VertexId, 2>{uses[k].lo, uses[k].hi})))
        ++insides->segments;
    }
    // An edge inside two or more merged facets and on none of their loops
    // (two flat faces that cross along it, each with facets on both of its
    // sides) would be no segment of the merged PLC: each facet would then be
    // triangulated across it, their subfaces would cross, and facet recovery
    // would recover one facet's subfaces by destroying the other's forever.
    // The facets meet along it, so it is a segment: kept as an explicit one.
    const std::array<VertexId, 2> edge = {uses[i].lo, uses[i].hi};
    if (!on_a_loop && several_groups &&
        !std::binary_search(explicit_segs.begin(), explicit_segs.end(), edge))
      crossing_edges.push_back(edge);
    i = j;
  }

  out.points = plc.points;
  out.segments = plc.segments;
  out.segments.insert(out.segments.end(), crossing_edges.begin(), crossing_edges.end());
  out.holes = plc.holes;
  out.regions = plc.regions;
  out.marker_names = plc.marker_names;
  out.file = plc.file;
  out.file_vertices = plc.file_vertices;
  out.welded_vertices = plc.welded_vertices;
  out.facets.clear();
  merged_into.assign(nf, kNone);
  size_t groups = 0;
  std::vector<std::vector<VertexId>> cycles;
  for (uint32_t f = 0; f < nf; ++f) {
    if (root[f] != f) {
      merged_into[f] = merged_into[root[f]];
      continue;
    }
    merged_into[f] = static_cast<uint32_t>(out.facets.size());
    if (size[f] < 2) {
      out.facets.push_back(plc.facets[f]);
      continue;
    }
    ++groups;
    boundary_cycles(std::move(boundary[f]), cycles);
    // The loop through the lexicographically smallest projected vertex is an
    // outer one: first, and turning like the group's first facet, whose
    // orientation the merged facet's subfaces keep.
    const int drop = plane[f].drop, u = (drop + 1) % 3, w = (drop + 2) % 3;
    size_t outer = 0;
    const double* best = nullptr;
    for (size_t c = 0; c < cycles.size(); ++c)
      for (VertexId v : cycles[c]) {
        const double* p = xyz(plc, v);
        if (!best || p[u] < best[u] || (p[u] == best[u] && p[w] < best[w])) best = p, outer = c;
      }
    std::swap(cycles[0], cycles[outer]);
    if (loop_orientation(plc, cycles[0], drop) != orient[f])
      std::reverse(cycles[0].begin(), cycles[0].end());
    if (insides) {
      // The group's vertices on none of its loops.
      std::vector<VertexId> on_loops, inner;
      for (const auto& c : cycles) on_loops.insert(on_loops.end(), c.begin(), c.end());
      std::sort(on_loops.begin(), on_loops.end());
      for (uint32_t g : members[f])
        for (VertexId v : plc.facets[g].loops[0])
          if (!std::binary_search(on_loops.begin(), on_loops.end(), v)) inner.push_back(v);
      std::sort(inner.begin(), inner.end());
      inner.erase(std::unique(inner.begin(), inner.end()), inner.end());
      insides->vertices.resize(out.facets.size() + 1);
      insides->vertices.back() = std::move(inner);
    }
    Facet m = plc.facets[f];
    m.loops = cycles;
    m.even_odd = true;
    out.facets.push_back(std::move(m));
  }
  if (insides) insides->vertices.resize(out.facets.size());
  return groups;
}

}  // namespace cdt3d
