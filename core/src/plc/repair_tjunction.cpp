// Repair step 3: T-junctions. A vertex of the PLC that lies exactly on
// another facet (on one of its edges, or inside it) without being one of its
// vertices makes the two facets meet improperly. Making it a vertex of that
// facet repairs this without any new coordinate:
//  - a vertex on a polygon edge is inserted into that polygon between the
//    edge's ends (the polygon stays planar and simple);
//  - a facet with a vertex inside it is replaced by its constrained
//    triangulation with that vertex (triangulate_surface, which takes every
//    PLC point lying in a facet as a vertex), one facet per triangle.
// Decisions are exact: coordinate comparisons, orient3d for the facet's
// plane, orient2d in a projection that drops one axis (which rounds nothing).
#include <algorithm>
#include <cmath>

#include "predicates.hpp"
#include "repair.hpp"

namespace cdt3d {
namespace repair_steps {
namespace {

const double* xyz(const Plc& plc, VertexId v) { return &plc.points[v].x; }

// For x on the line through p != q: x strictly between them. Along the line
// any axis on which p and q differ orders the points exactly.
bool strictly_between(const double* p, const double* q, const double* x) {
  int k = 0;
  while (k < 2 && p[k] == q[k]) ++k;
  return std::min(p[k], q[k]) < x[k] && x[k] < std::max(p[k], q[k]);
}

// Where a point of the facet's plane lies relative to one polygon, in the
// projection: on edge i (returns i), inside (-1) or outside (-2). Crossing
// rule with a ray towards +u; the side of a crossing is an orient2d sign.
long locate(const Plc& plc, const std::vector<VertexId>& loop, const double* p, int drop) {
  const int vax = (drop + 2) % 3;
  bool inside = false;
  const size_t m = loop.size();
  for (size_t i = 0; i < m; ++i) {
    const double* a = xyz(plc, loop[i]);
    const double* b = xyz(plc, loop[(i + 1) % m]);
    const int o = pred::orient2d_projected(a, b, p, drop);
    if (o == 0 && strictly_between(a, b, p)) return static_cast<long>(i);
    if ((a[vax] > p[vax]) != (b[vax] > p[vax])) {
      const bool up = b[vax] > a[vax];
      if ((up && o > 0) || (!up && o < 0)) inside = !inside;
    }
  }
  return inside ? -1 : -2;
}

struct FacetPlane {
  const double *a = nullptr, *b = nullptr, *c = nullptr;
  int drop = 0;
};

FacetPlane plane_of(const Plc& plc, const Facet& f) {
  FacetPlane pl;
  const auto& first = f.loops[0];
  pl.a = xyz(plc, first[0]);
  pl.b = xyz(plc, first[1]);
  for (size_t i = 2; i < first.size() && !pl.c; ++i)
    if (!pred::collinear3d(pl.a, pl.b, xyz(plc, first[i]))) pl.c = xyz(plc, first[i]);
  while (pl.drop < 2 && pred::orient2d_projected(pl.a, pl.b, pl.c, pl.drop) == 0) ++pl.drop;
  return pl;
}

// What a facet must take in: vertices on its polygon edges (loop, edge,
// vertex) and vertices inside it.
struct Found {
  std::vector<std::array<size_t, 3>> on_edge;
  size_t inside = 0;
};

// Explicit segments by endpoint: (v, other end), both ways, sorted.
using SegmentEnds = std::vector<std::pair<VertexId, VertexId>>;

SegmentEnds segment_ends(const Plc& plc) {
  SegmentEnds ends;
  for (const auto& s : plc.segments) {
    ends.push_back({s[0], s[1]});
    ends.push_back({s[1], s[0]});
  }
  std::sort(ends.begin(), ends.end());
  return ends;
}

// The vertices of the PLC lying in a facet's closed region without being its
// vertices. The region of a facet with several polygons: inside an odd
// number of them when it has facet holes (the .poly convention for nested
// polygons), inside any of them otherwise. An explicit segment lying in the
// facet is part of it (TetGen's 2-vertex polygons; the self-intersection
// test counts its ends as the facet's vertices), so its ends inside the
// facet are no T-junctions; an end on a loop edge still is (the test
// reports it as a vertex on that edge), and goes into the loop.
Found find_in_facet(const Plc& plc, const PointGrid& grid, const SegmentEnds& ends, const Facet& f) {
  const FacetPlane pl = plane_of(plc, f);
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = hi[k] = pl.a[k];
  std::vector<VertexId> own;
  for (const auto& l : f.loops)
    for (VertexId v : l) {
      own.push_back(v);
      for (int k = 0; k < 3; ++k) {
        lo[k] = std::min(lo[k], xyz(plc, v)[k]);
        hi[k] = std::max(hi[k], xyz(plc, v)[k]);
      }
    }
  std::sort(own.begin(), own.end());
  struct Candidate {
    VertexId v;
    size_t loop;
    long at;  // edge index, or -1 inside
  };
  std::vector<Candidate> cand;
  grid.query(lo, hi, [&](VertexId v) {
    const double* p = xyz(plc, v);
    for (int k = 0; k < 3; ++k)
      if (p[k] < lo[k] || p[k] > hi[k]) return;
    if (std::binary_search(own.begin(), own.end(), v)) return;
    if (pred::orient3d(pl.a, pl.b, pl.c, p) != 0) return;
    size_t containing = 0;
    for (size_t li = 0; li < f.loops.size(); ++li) {
      const long at = locate(plc, f.loops[li], p, pl.drop);
      if (at >= 0) {
        cand.push_back({v, li, at});
        return;
      }
      containing += at == -1;
    }
    if (f.holes.empty() ? containing > 0 : containing % 2 == 1) cand.push_back({v, 0, -1});
  });
  std::vector<VertexId> in_facet = own;
  for (const Candidate& c : cand) in_facet.push_back(c.v);
  std::sort(in_facet.begin(), in_facet.end());
  Found found;
  for (const Candidate& c : cand) {
    auto it = std::lower_bound(ends.begin(), ends.end(), std::make_pair(c.v, VertexId{0}));
    bool embedded = false;
    for (; it != ends.end() && it->first == c.v && !embedded; ++it)
      embedded = std::binary_search(in_facet.begin(), in_facet.end(), it->second);
    if (embedded && c.at < 0) continue;
    if (c.at >= 0)
      found.on_edge.push_back({c.loop, static_cast<size_t>(c.at), c.v});
    else
      ++found.inside;
  }
  return found;
}

// Inserts the vertices found on polygon edges, each edge's vertices in order
// from its first end.
void insert_on_edges(const Plc& plc, Facet& f, std::vector<std::array<size_t, 3>> on_edge) {
  std::sort(on_edge.begin(), on_edge.end(), [&](const auto& x, const auto& y) {
    if (x[0] != y[0] || x[1] != y[1]) return x < y;
    const auto& loop = f.loops[x[0]];
    const double* a = xyz(plc, loop[x[1]]);
    const double* b = xyz(plc, loop[(x[1] + 1) % loop.size()]);
    int k = 0;
    while (k < 2 && a[k] == b[k]) ++k;
    const double dx = xyz(plc, static_cast<VertexId>(x[2]))[k];
    const double dy = xyz(plc, static_cast<VertexId>(y[2]))[k];
    return a[k] < b[k] ? dx < dy : dx > dy;
  });
  for (size_t li = 0; li < f.loops.size(); ++li) {
    const auto& loop = f.loops[li];
    std::vector<VertexId> grown;
    size_t at = 0;
    while (at < on_edge.size() && on_edge[at][0] < li) ++at;
    for (size_t i = 0; i < loop.size(); ++i) {
      grown.push_back(loop[i]);
      for (; at < on_edge.size() && on_edge[at][0] == li && on_edge[at][1] == i; ++at)
        grown.push_back(static_cast<VertexId>(on_edge[at][2]));
    }
    f.loops[li] = std::move(grown);
  }
}

}  // namespace

Status split_at_tjunctions(Work& w, RepairReport& report, bool isolated) {
  Plc& plc = w.plc;
  const PointGrid grid(plc, isolated);
  const SegmentEnds ends = segment_ends(plc);
  std::vector<uint8_t> triangulate(plc.facets.size(), 0);
  size_t to_triangulate = 0;
  for (size_t f = 0; f < plc.facets.size(); ++f) {
    Found found = find_in_facet(plc, grid, ends, plc.facets[f]);
    const size_t n = found.on_edge.size() + found.inside;
    if (n == 0) continue;
    report.tjunction_vertices += n;
    ++report.tjunction_facets;
    w.mark(w.source[f]);
    // The points on edges go into the loops first also for a facet that is
    // triangulated: triangulate_surface takes the points inside a facet but
    // fails on a point lying on one of its loop edges.
    insert_on_edges(plc, plc.facets[f], std::move(found.on_edge));
    if (found.inside > 0) {
      triangulate[f] = 1;
      ++to_triangulate;
    }
  }
  if (to_triangulate == 0) return Status::success();
  Status st = triangulate_in_place(w, triangulate);
  if (st.ok()) return st;
  if (st.error.facet >= 0) st.error.facet = -1;  // a facet of a temporary PLC: no input name
  return st;
}

Status triangulate_in_place(Work& w, const std::vector<uint8_t>& which) {
  Plc& plc = w.plc;
  // The flagged facets, triangulated together (same point ids).
  Plc part;
  part.points = plc.points;
  part.file = plc.file;
  for (size_t f = 0; f < plc.facets.size(); ++f)
    if (which[f]) part.facets.push_back(plc.facets[f]);
  if (part.facets.empty()) return Status::success();
  std::vector<uint32_t> tris, tri_facet;
  Status st = triangulate_surface(part, tris, tri_facet);
  if (!st.ok()) {
    // A facet whose triangulation fails (a PLC point lies exactly on a
    // segment that runs through it) stays as it is: the exact check at the
    // end reports what that leaves. The others are done one at a time,
    // from the last, so that the indices of those still to do stay valid
    // (each try copies the points: only on this rare path).
    if (part.facets.size() == 1) return Status::success();
    for (size_t f = plc.facets.size(); f-- > 0;) {
      if (!which[f]) continue;
      std::vector<uint8_t> one(plc.facets.size(), 0);
      one[f] = 1;
      triangulate_in_place(w, one);
    }
    return Status::success();
  }
  std::vector<std::vector<uint32_t>> tris_of(part.facets.size());
  for (size_t t = 0; t < tri_facet.size(); ++t) tris_of[tri_facet[t]].push_back(static_cast<uint32_t>(t));
  std::vector<Facet> facets;
  std::vector<uint32_t> source;
  size_t next = 0;
  for (size_t f = 0; f < plc.facets.size(); ++f) {
    if (!which[f]) {
      facets.push_back(std::move(plc.facets[f]));
      source.push_back(w.source[f]);
      continue;
    }
    for (uint32_t t : tris_of[next]) {
      facets.push_back(part_of(plc.facets[f], {tris[3 * t], tris[3 * t + 1], tris[3 * t + 2]}));
      source.push_back(w.source[f]);
    }
    ++next;
  }
  plc.facets = std::move(facets);
  w.source = std::move(source);
  return Status::success();
}

}  // namespace repair_steps
}  // namespace cdt3d
