// Repair step 4: the arrangement of the triangles that meet improperly. For
// every such pair, in any configuration (crossing, touching at a point or
// along a segment, an edge in the other's plane or through its corner,
// coplanar overlap of any shape), the points that bound the contact are
// found (contact_points) and go into both triangles where they lie, and the
// segments between them become edges: each affected triangle is replaced by
// the constrained triangulation of its corners, the new points on its edges
// and inside it, and the contact segments (one facet per triangle,
// provenance kept). Where the segments of two contacts cross inside a
// triangle, three triangles meet in one point (the common point of their
// planes), which splits the segments in all three. A new point on an edge
// goes into every facet that has the edge.
//
// Exactness: where the contact lies is decided by orient3d and orient2d
// signs. The points where edges cross planes or edges are constructed and
// ROUNDED, to a grid (snapped(): snap rounding after Greene & Yao 1986 and
// Hobby 1999, iterated with an exact re-check as in the iterated snap
// rounding of Halperin & Packer 2002, here without its guarantee): before
// the first round every point of a PLC
// with improper pairs is snapped to the grid, then every constructed point
// is. Points on one grid point or on neighbouring ones become one point
// (merge_neighbouring_points) instead of needles that
// segment recovery cannot split. Rounding moves points off the lines they
// were made on, so the result is checked exactly again
// (find_self_intersections) and the step repeats on what rounding broke, at
// most kRounds times; whatever still intersects is reported by facet. The
// triangulation of a triangle is done in the coordinate plane that drops one
// axis (exact), as a flat PLC handed to triangulate_surface.
//
// Explicit segments take part in the same rounds, as a triangle with one
// edge would: a segment crossing a triangle's plane is split at the
// (constructed, ROUNDED) crossing point, which goes into the triangle
// inside or on its edge; a corner of the triangle or an end of another
// segment lying on it splits it there; two crossing segments are split at
// their (ROUNDED) crossing point; a segment in a triangle's plane is split
// where it crosses the triangle's edges and its pieces inside become
// constrained edges of the triangle's triangulation. All splitting goes
// through the points put on edges (add_edge_point), so a point on an edge
// that is both a facet edge and a segment goes into both. Pieces keep their
// input segment (Work::segment_source).
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <cstdio>
#include <cstdlib>

#include "double_double.hpp"
#include "geometry.hpp"
#include "predicates.hpp"
#include "repair.hpp"

namespace cdt3d {
namespace repair_steps {
namespace {

constexpr size_t kRounds = 8;
/// A round with more than kGrowth times the first round's pairs (plus a
/// few) ends the rounds.
constexpr size_t kGrowth = 4;

const double* xyz(const Plc& plc, VertexId v) { return &plc.points[v].x; }

using Tri = std::array<VertexId, 3>;

bool is_triangle(const Facet& f) { return f.loops.size() == 1 && f.loops[0].size() == 3; }

// What one triangle must take in.
struct Insert {
  std::vector<std::pair<int, VertexId>> on_edge;  ///< (edge i = (v[i], v[i+1]), point)
  std::vector<VertexId> inside;
  struct Segment {
    VertexId a, b;
    uint32_t other;  ///< the facet whose crossing made it
  };
  std::vector<Segment> segments;
};

// Sorts `pts` (points on or, rounded, next to edge ab) in order from a to
// b: by the coordinate on which a and b differ most (exact comparisons; a
// rounded point is off the line by far less than that extent), ties by id.
void sort_along(const Plc& plc, VertexId a, VertexId b, std::vector<VertexId>& pts) {
  const double *pa = xyz(plc, a), *pb = xyz(plc, b);
  int k = 0;
  for (int j = 1; j < 3; ++j)
    if (std::fabs(pb[j] - pa[j]) > std::fabs(pb[k] - pa[k])) k = j;
  const bool up = pa[k] < pb[k];
  std::sort(pts.begin(), pts.end(), [&](VertexId x, VertexId y) {
    const double cx = xyz(plc, x)[k], cy = xyz(plc, y)[k];
    if (cx != cy) return up ? cx < cy : cx > cy;
    return x < y;
  });
}

// p + s (q - p), rounded to doubles. The exact s lies in (0, 1) (the
// orient3d signs say the crossing is inside pq); a computed s outside it, or
// not finite (planes or lines parallel in floating point), is brought back
// into [0, 1] (the midpoint when not finite), and the exact re-check judges
// the result like any other rounded point.
Vec3 along(const double* p, const double* q, DoubleDouble s) {
  if (!std::isfinite(s.hi) || !std::isfinite(s.lo)) s = 0.5;
  if (s < DoubleDouble(0)) s = 0;
  if (DoubleDouble(1) < s) s = 1;
  Vec3 x;
  double* out = &x.x;
  for (int k = 0; k < 3; ++k) out[k] = (p[k] + s * (DoubleDouble(q[k]) - p[k])).value();
  return x;
}

// The point where segment pq crosses the plane of triangle t. Constructed
// in doubles and therefore ROUNDED: it lies within a few ulps of both pq and
// the plane, not exactly on them. The caller re-checks the result exactly.
// Always computed from the same inputs in the same order (the key sorts
// them), so every triangle that needs this point gets the same coordinates.
Vec3 pierce_point(const double* p, const double* q, const Tri& t, const Plc& plc) {
  // Double-double: more precision where the planes are nearly parallel, and
  // the same result in every build (double_double.hpp).
  using LD = DoubleDouble;
  const double* a = xyz(plc, t[0]);
  const double* b = xyz(plc, t[1]);
  const double* c = xyz(plc, t[2]);
  LD u[3], v[3], n[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = LD(b[k]) - a[k];
    v[k] = LD(c[k]) - a[k];
  }
  n[0] = u[1] * v[2] - u[2] * v[1];
  n[1] = u[2] * v[0] - u[0] * v[2];
  n[2] = u[0] * v[1] - u[1] * v[0];
  LD dp = 0, dq = 0;
  for (int k = 0; k < 3; ++k) {
    dp += n[k] * (LD(p[k]) - a[k]);
    dq += n[k] * (LD(q[k]) - a[k]);
  }
  return along(p, q, dp / (dp - dq));
}

// The crossing point of the coplanar segments pq and ab (known to cross),
// constructed like pierce_point and ROUNDED the same way.
Vec3 line_crossing(const double* p, const double* q, const double* a, const double* b) {
  using LD = DoubleDouble;
  LD d[3], e[3], w[3], n[3], m[3];
  for (int k = 0; k < 3; ++k) {
    d[k] = LD(q[k]) - p[k];
    e[k] = LD(b[k]) - a[k];
    w[k] = LD(a[k]) - p[k];
  }
  auto cross = [](const LD* x, const LD* y, LD* out) {
    out[0] = x[1] * y[2] - x[2] * y[1];
    out[1] = x[2] * y[0] - x[0] * y[2];
    out[2] = x[0] * y[1] - x[1] * y[0];
  };
  cross(d, e, n);
  cross(w, e, m);
  const LD nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
  return along(p, q, (m[0] * n[0] + m[1] * n[1] + m[2] * n[2]) / nn);
}

}  // namespace

// The snap grid: a power of two kSnapBits binary orders below the largest
// coordinate magnitude of the points in use, so that x / grid and back is
// exact and the same in every build.
constexpr int kSnapBits = 40;

double snap_grid(const Plc& plc) {
  double big = 0;
  for (const Facet& f : plc.facets)
    for (const auto& l : f.loops)
      for (VertexId v : l) big = std::max({big, std::fabs(plc.points[v].x), std::fabs(plc.points[v].y),
                                           std::fabs(plc.points[v].z)});
  if (big == 0) return 0;
  return std::ldexp(1.0, std::ilogb(big) - kSnapBits);
}

// x ROUNDED to the nearest multiple of the grid (each coordinate; a grid of
// 0 leaves it as it is). Snap rounding (Hobby 1999; Greene & Yao 1986): the
// points that end in one grid cell become one point, so two features closer
// than the grid are made to meet instead of crossing again a few ulps apart.
Vec3 snapped(Vec3 x, double grid) {
  if (grid == 0) return x;
  for (double* c : {&x.x, &x.y, &x.z}) *c = std::nearbyint(*c / grid) * grid;
  return x;
}

namespace {

// A plane through three points of the PLC.
using Plane = std::array<const double*, 3>;

using Edge = std::pair<VertexId, VertexId>;
Edge edge_key(VertexId a, VertexId b) { return {std::min(a, b), std::max(a, b)}; }

// How far (grid steps on each axis) snapped_on_planes may move a point to
// keep it on its planes: plain rounding moves it half a step. In 7,000
// random soups (1,000 of each kind of the soup test) 1 step left 7 failing,
// 2 steps 8 (and one repair that no longer converged), half a step 9.
constexpr double kPlaneSnapSteps = 1;

// Candidates near x for snapped_on_planes: x's grid point with one
// coordinate solved from plane a (n its normal in doubles), or, with two
// planes, two coordinates solved from both (the third, along their common
// line, kept), each solved coordinate ROUNDED to the grid again.
void plane_candidates(const Vec3& r, const Plane* a, const Plane* b, double grid, std::vector<Vec3>& out) {
  auto at = [](const Vec3& v, int k) { return (&v.x)[k]; };
  auto snap = [&](double c) { return std::nearbyint(c / grid) * grid; };
  const Vec3 na = triangle_normal((*a)[0], (*a)[1], (*a)[2]);
  const double da = na.x * (*a)[0][0] + na.y * (*a)[0][1] + na.z * (*a)[0][2];
  if (!b) {
    for (int k = 0; k < 3; ++k) {
      if (at(na, k) == 0) continue;
      Vec3 c = r;
      (&c.x)[k] = 0;
      (&c.x)[k] = snap((da - dot(na, c)) / at(na, k));
      out.push_back(c);
    }
    return;
  }
  const Vec3 nb = triangle_normal((*b)[0], (*b)[1], (*b)[2]);
  const double db = nb.x * (*b)[0][0] + nb.y * (*b)[0][1] + nb.z * (*b)[0][2];
  for (int m = 0; m < 3; ++m) {  // m kept; i, j solved
    const int i = (m + 1) % 3, j = (m + 2) % 3;
    const double det = at(na, i) * at(nb, j) - at(na, j) * at(nb, i);
    if (det == 0) continue;
    const double ra = da - at(na, m) * at(r, m), rb = db - at(nb, m) * at(r, m);
    Vec3 c = r;
    (&c.x)[i] = snap((ra * at(nb, j) - rb * at(na, j)) / det);
    (&c.x)[j] = snap((at(na, i) * rb - at(nb, i) * ra) / det);
    out.push_back(c);
  }
}

// x ROUNDED to the grid so that it stays exactly on as many of `planes` as
// a grid point near it can (x was constructed on all of them): the nearest
// grid point, or one with one or two coordinates solved from the planes
// (plane_candidates), whichever lies exactly (orient3d) on the most planes,
// the nearer to x on a tie; never more than kPlaneSnapSteps from x on any
// axis. A crossing point rounded off the plane of the facet it pierces
// leaves four points of the repaired PLC within rounding of one plane (the
// facet's own corners and the point), which the CDT can hold only as a
// numerically flat tet; a point kept on that plane makes them exactly
// coplanar, and no tet of them exists.
Vec3 snapped_on_planes(const Vec3& x, double grid, const std::vector<Plane>& planes) {
  const Vec3 r = snapped(x, grid);
  if (planes.empty() || grid == 0) return r;
  std::vector<Vec3> cands{r};
  for (size_t i = 0; i < planes.size(); ++i) {
    plane_candidates(r, &planes[i], nullptr, grid, cands);
    for (size_t j = i + 1; j < planes.size(); ++j) plane_candidates(r, &planes[i], &planes[j], grid, cands);
  }
  // Bit i: on planes[i]. A candidate must keep every plane r is on (the
  // coordinate planes of an axis-aligned facet, which rounding keeps).
  auto planes_of = [&](const Vec3& c) {
    uint32_t bits = 0;
    for (size_t i = 0; i < planes.size(); ++i)
      if (pred::orient3d(planes[i][0], planes[i][1], planes[i][2], &c.x) == 0) bits |= 1u << i;
    return bits;
  };
  const uint32_t base = planes_of(r);
  Vec3 best = r;
  int best_on = __builtin_popcount(base);
  double best_d = dot(r - x, r - x);
  for (size_t k = 1; k < cands.size(); ++k) {
    const Vec3& c = cands[k];
    if (!finite(c) || std::fabs(c.x - x.x) > kPlaneSnapSteps * grid || std::fabs(c.y - x.y) > kPlaneSnapSteps * grid ||
        std::fabs(c.z - x.z) > kPlaneSnapSteps * grid)
      continue;
    // A coordinate the construction gave exactly on the grid stays: it
    // holds the point on a plane of the model that `planes` may not name
    // (an edge along y = 2 of an open surface has one facet's plane only).
    if ((x.x == r.x && c.x != r.x) || (x.y == r.y && c.y != r.y) || (x.z == r.z && c.z != r.z)) continue;
    const uint32_t bits = planes_of(c);
    if ((bits & base) != base) continue;
    const int on = __builtin_popcount(bits);
    const double d = dot(c - x, c - x);
    if (on > best_on || (on == best_on && d < best_d)) best = c, best_on = on, best_d = d;
  }
  return best;
}

// Where a contact point lies in a triangle: on edge i (0..2), at vertex k
// (at_vertex(k)), inside, or outside.
constexpr int kInside = -1;
constexpr int kOutside = -2;
constexpr int at_vertex(int k) { return 3 + k; }

struct ContactPoint {
  VertexId v;
  int at[2];  ///< where v lies in the first and the second triangle
};

// For x on the line through p != q: x strictly between them. Along the line
// any axis on which p and q differ orders the points exactly.
bool strictly_between(const double* p, const double* q, const double* x) {
  int k = 0;
  while (k < 2 && p[k] == q[k]) ++k;
  return std::min(p[k], q[k]) < x[k] && x[k] < std::max(p[k], q[k]);
}

class Crossings {
 public:
  Crossings(Work& w, RepairReport& report, double grid) : w_(w), report_(report), grid_(grid) {}

  /// Records what the contact of triangles f and g adds to each, in every
  /// configuration: the points of the contact (see contact_points) go into
  /// both triangles where they lie (a vertex, an edge, the inside), and the
  /// segments between them become edges. Crossing or touching triangles meet
  /// in one segment of the line common to their planes: its points in order
  /// along it, chained. Coplanar triangles overlap in a convex polygon
  /// bounded by pieces of both triangles' edges: each triangle takes the
  /// pieces of the other's edges that run inside it, and the facet of
  /// higher id drops its copy of the overlap (is_covered).
  /// False when the pair adds nothing.
  bool add_contact(uint32_t f, uint32_t g) {
    const Tri tri_of[2] = {tri(f), tri(g)};
    const uint32_t facet_of[2] = {f, g};
    std::vector<ContactPoint> pts;
    contact_points(tri_of[0], tri_of[1], pts);
    if (pts.empty()) return false;
    bool coplanar = true;
    for (int j = 0; j < 3 && coplanar; ++j)
      coplanar = pred::orient3d(xyz(w_.plc, tri_of[0][0]), xyz(w_.plc, tri_of[0][1]),
                                xyz(w_.plc, tri_of[0][2]), xyz(w_.plc, tri_of[1][j])) == 0;
    if (coplanar) {
      std::vector<VertexId> overlap;
      for (const ContactPoint& c : pts) overlap.push_back(c.v);
      std::sort(overlap.begin(), overlap.end());
      covered_[std::max(f, g)].push_back({std::move(overlap), tri(std::min(f, g))});
    }
    bool any = false;
    for (int side = 0; side < 2; ++side) {
      const Tri& host = tri_of[side];
      Insert& in = inserts_[facet_of[side]];
      for (const ContactPoint& c : pts) {
        if (c.at[side] == kInside) {
          in.inside.push_back(c.v);
          any = true;
        } else if (c.at[side] >= 0 && c.at[side] < 3) {
          add_edge_point(host[c.at[side]], host[(c.at[side] + 1) % 3], c.v);
          any = true;
        }
      }
      std::vector<std::pair<size_t, size_t>> pieces;
      if (coplanar) {
        for (int j = 0; j < 3; ++j) chain_along(pts, 1 - side, j, tri_of[1 - side], pieces);
      } else {
        chain_along(pts, -1, -1, host, pieces);
      }
      for (const auto& [a, b] : pieces) {
        if (pts[a].v == pts[b].v || on_one_edge(pts[a].at[side], pts[b].at[side])) continue;
        in.segments.push_back({pts[a].v, pts[b].v, facet_of[1 - side]});
        any = true;
      }
    }
    return any;
  }

  /// Records what explicit segment s adds to triangle f (`cell`: s's
  /// reference in Intersection terms, facets first, so no facet id; it is
  /// the `other` of the pieces constrained in f). The points where the segment meets the closed triangle split the
  /// segment and go into the triangle where they lie, like the contact
  /// points of an edge of a triangle in add_contact (the segment plays a
  /// triangle with one edge, edge 0; an end is at_vertex(0) or
  /// at_vertex(1)). A segment in the plane of f also leaves its pieces
  /// inside f as constrained edges, so the facet's triangulation has them as
  /// edges. False when the pair adds nothing.
  bool add_segment_contact(uint32_t f, uint32_t s, uint32_t cell) {
    const Tri t = tri(f);
    const VertexId p = w_.plc.segments[s][0], q = w_.plc.segments[s][1];
    double oc[3][3], pq[2][3];
    for (int k = 0; k < 3; ++k) {
      for (int j = 0; j < 3; ++j) oc[j][k] = xyz(w_.plc, t[j])[k];
      pq[0][k] = xyz(w_.plc, p)[k];
      pq[1][k] = xyz(w_.plc, q)[k];
    }
    const int drop = projection_axis(t);
    const int sp = pred::orient3d(oc[0], oc[1], oc[2], pq[0]);
    const int sq = pred::orient3d(oc[0], oc[1], oc[2], pq[1]);
    std::vector<ContactPoint> pts;
    if (sp == 0) add_point(pts, 0, p, at_vertex(0), where_in(t, p, drop));
    if (sq == 0) add_point(pts, 0, q, at_vertex(1), where_in(t, q, drop));
    if (sp != 0 && sq != 0 && sp != sq) edge_through_plane(pts, 0, 0, p, q, pq, t, oc);
    if (sp == 0 && sq == 0) edge_in_plane(pts, 0, 0, p, q, t, drop);
    if (pts.empty()) return false;
    Insert& in = inserts_[f];
    for (const ContactPoint& c : pts) {
      if (c.at[0] == 0) add_edge_point(p, q, c.v);  // inside the segment: split it there
      if (c.at[1] == kInside) in.inside.push_back(c.v);
      else if (c.at[1] >= 0 && c.at[1] < 3) add_edge_point(t[c.at[1]], t[(c.at[1] + 1) % 3], c.v);
    }
    if (sp == 0 && sq == 0) {
      // The contact points all lie on pq and in the closed (convex) t:
      // consecutive ones bound the pieces of pq inside t.
      std::vector<std::pair<size_t, size_t>> pieces;
      chain_along(pts, -1, -1, t, pieces);
      for (const auto& [a, b] : pieces) {
        if (pts[a].v == pts[b].v || on_one_edge(pts[a].at[1], pts[b].at[1])) continue;
        in.segments.push_back({pts[a].v, pts[b].v, cell});
      }
    }
    return true;
  }

  /// Explicit segments s and r meeting improperly (coplanar): an end of one
  /// strictly inside the other splits it there, and a proper crossing
  /// splits both at the crossing point (point_on_edges: constructed,
  /// ROUNDED). The decisions are orient3d / orient2d signs.
  bool add_segment_pair(uint32_t s, uint32_t r) {
    const VertexId p = w_.plc.segments[s][0], q = w_.plc.segments[s][1];
    const VertexId c = w_.plc.segments[r][0], d = w_.plc.segments[r][1];
    const double *pp = xyz(w_.plc, p), *pq = xyz(w_.plc, q), *pc = xyz(w_.plc, c), *pd = xyz(w_.plc, d);
    if (pred::orient3d(pp, pq, pc, pd) != 0) return false;
    bool any = false;
    auto on = [&](VertexId a, VertexId b, VertexId x) {
      if (x == a || x == b) return;
      if (!pred::collinear3d(xyz(w_.plc, a), xyz(w_.plc, b), xyz(w_.plc, x)) ||
          !strictly_between(xyz(w_.plc, a), xyz(w_.plc, b), xyz(w_.plc, x)))
        return;
      add_edge_point(a, b, x);
      any = true;
    };
    on(p, q, c), on(p, q, d), on(c, d, p), on(c, d, q);
    if (any || p == c || p == d || q == c || q == d) return any;
    // A projection in which the two segments are not both degenerate.
    int drop = 0;
    while (drop < 2 && pred::orient2d_projected(pp, pq, pc, drop) == 0 &&
           pred::orient2d_projected(pp, pq, pd, drop) == 0)
      ++drop;
    const int o1 = pred::orient2d_projected(pp, pq, pc, drop);
    const int o2 = pred::orient2d_projected(pp, pq, pd, drop);
    const int o3 = pred::orient2d_projected(pc, pd, pp, drop);
    const int o4 = pred::orient2d_projected(pc, pd, pq, drop);
    if (o1 * o2 >= 0 || o3 * o4 >= 0) return false;
    point_on_edges(p, q, c, d);  // puts the point on both
    return true;
  }

  /// Re-triangulates every triangle that got something, on its edges (from
  /// any pair: a point on an edge belongs to every facet with that edge) or
  /// inside; a polygon facet with a point on one of its edges gets it in its
  /// loop. Returns the number of facets changed.
  size_t apply() {
    find_triple_points();
    std::vector<Facet> facets;
    std::vector<uint32_t> source;
    size_t split = 0;
    for (size_t f = 0; f < w_.plc.facets.size(); ++f) {
      Facet& facet = w_.plc.facets[f];
      const uint32_t src = w_.source[f];
      const auto it = inserts_.find(static_cast<uint32_t>(f));
      Insert in = it == inserts_.end() ? Insert() : it->second;
      const bool tri_facet = is_triangle(facet);
      bool on_edges = false;
      for (auto& loop : facet.loops) on_edges |= take_edge_points(loop, tri_facet ? &in : nullptr);
      std::vector<Tri> tris;
      if (!tri_facet || (in.inside.empty() && in.on_edge.empty()) ||
          !retriangulate(static_cast<uint32_t>(f), in, tris)) {
        split += on_edges;
        if (on_edges) w_.mark(src);
        facets.push_back(std::move(facet));
        source.push_back(src);
        continue;
      }
      ++split;
      w_.mark(src);
      for (const Tri& t : tris) {
        if (is_covered(static_cast<uint32_t>(f), t)) continue;
        facets.push_back(part_of(facet, {t[0], t[1], t[2]}));
        source.push_back(src);
      }
    }
    w_.plc.facets = std::move(facets);
    w_.source = std::move(source);
    split_segments();
    return split;
  }

  /// Every explicit segment with points on it (add_edge_point: from a
  /// facet's contact, another segment or its own) replaced by its pieces,
  /// in order along it, each keeping the segment's input segment.
  void split_segments() {
    Plc& plc = w_.plc;
    std::vector<std::array<VertexId, 2>> segments;
    std::vector<uint32_t> source;
    for (size_t s = 0; s < plc.segments.size(); ++s) {
      const VertexId a = plc.segments[s][0], b = plc.segments[s][1];
      const auto it = edge_points_.find({std::min(a, b), std::max(a, b)});
      if (it == edge_points_.end()) {
        segments.push_back(plc.segments[s]);
        source.push_back(w_.segment_source[s]);
        continue;
      }
      std::vector<VertexId> pts = it->second;
      sort_along(plc, a, b, pts);
      pts.push_back(b);
      VertexId from = a;
      for (VertexId x : pts) {
        if (x == from) continue;
        if (from != a) ++report_.segment_splits;  // a piece beyond the first
        segments.push_back({from, x});
        source.push_back(w_.segment_source[s]);
        from = x;
      }
    }
    plc.segments = std::move(segments);
    w_.segment_source = std::move(source);
  }

 private:
  Tri tri(uint32_t f) const {
    const auto& l = w_.plc.facets[f].loops[0];
    return {l[0], l[1], l[2]};
  }

  // Where point z of the plane of triangle o lies in it (projection
  // `drop`): at(vertex k), edge j, kInside, or kOutside.
  int where_in(const Tri& o, VertexId z, int drop) const {
    for (int k = 0; k < 3; ++k)
      if (o[k] == z) return at_vertex(k);
    int s[3];
    for (int j = 0; j < 3; ++j)
      s[j] = pred::orient2d_projected(xyz(w_.plc, o[j]), xyz(w_.plc, o[(j + 1) % 3]), xyz(w_.plc, z), drop);
    const bool nonneg = s[0] >= 0 && s[1] >= 0 && s[2] >= 0;
    const bool nonpos = s[0] <= 0 && s[1] <= 0 && s[2] <= 0;
    if (!nonneg && !nonpos) return kOutside;
    const int zeros = (s[0] == 0) + (s[1] == 0) + (s[2] == 0);
    if (zeros == 0) return kInside;
    if (zeros == 1) return s[0] == 0 ? 0 : (s[1] == 0 ? 1 : 2);
    return kOutside;  // two welded-apart points with one projection: not on o
  }

  // The points of the closed triangles t and u in common that bound their
  // contact, with where each lies in both (ContactPoint::at). Every end of
  // the contact is a vertex of one lying in the other, or where an edge of
  // one meets the other: crossing its plane (inside it, across one of its
  // edges, or through one of its corners), or, for an edge in the other's
  // plane, crossing its edges or passing its corners. Every decision is an
  // orient3d or orient2d sign; only the crossing points are constructed
  // (point_in_triangle, point_on_edges: ROUNDED).
  void contact_points(const Tri& t, const Tri& u, std::vector<ContactPoint>& pts) {
    const Tri tris[2] = {t, u};
    for (int side = 0; side < 2; ++side) {
      const Tri& h = tris[side];
      const Tri& o = tris[1 - side];
      const int drop = projection_axis(o);
      for (int i = 0; i < 3; ++i) {
        const VertexId p = h[i], q = h[(i + 1) % 3];
        // Copies: a new point may grow plc.points and move its storage.
        double oc[3][3], pq[2][3];
        for (int k = 0; k < 3; ++k) {
          for (int j = 0; j < 3; ++j) oc[j][k] = xyz(w_.plc, o[j])[k];
          pq[0][k] = xyz(w_.plc, p)[k];
          pq[1][k] = xyz(w_.plc, q)[k];
        }
        const int sp = pred::orient3d(oc[0], oc[1], oc[2], pq[0]);
        const int sq = pred::orient3d(oc[0], oc[1], oc[2], pq[1]);
        if (sp == 0) add_point(pts, side, p, at_vertex(i), where_in(o, p, drop));
        if (sq == 0) add_point(pts, side, q, at_vertex((i + 1) % 3), where_in(o, q, drop));
        if (sp != 0 && sq != 0 && sp != sq) edge_through_plane(pts, side, i, p, q, pq, o, oc);
        if (sp == 0 && sq == 0) edge_in_plane(pts, side, i, p, q, o, drop);
      }
    }
  }

  // Edge i = (p, q) of the triangle of `side` crosses the plane of o (its
  // ends strictly on either side): where, if inside the closed o.
  void edge_through_plane(std::vector<ContactPoint>& pts, int side, int i, VertexId p, VertexId q,
                          const double (&pq)[2][3], const Tri& o, const double (&oc)[3][3]) {
    int s[3];
    for (int j = 0; j < 3; ++j) s[j] = pred::orient3d(pq[0], pq[1], oc[j], oc[(j + 1) % 3]);
    const bool nonneg = s[0] >= 0 && s[1] >= 0 && s[2] >= 0;
    const bool nonpos = s[0] <= 0 && s[1] <= 0 && s[2] <= 0;
    if (!nonneg && !nonpos) return;  // the line passes beside o
    const int zeros = (s[0] == 0) + (s[1] == 0) + (s[2] == 0);
    if (zeros == 0) {
      add_point(pts, side, point_in_triangle(p, q, o), i, kInside);
    } else if (zeros == 1) {
      const int j = s[0] == 0 ? 0 : (s[1] == 0 ? 1 : 2);
      add_point(pts, side, point_on_edges(p, q, o[j], o[(j + 1) % 3]), i, j);
    } else {
      // Through a corner of o: the edge not through it is the nonzero one.
      const int m = s[0] != 0 ? 0 : (s[1] != 0 ? 1 : 2);
      const int k = (m + 2) % 3;
      add_point(pts, side, o[k], i, at_vertex(k));
    }
  }

  // Edge i = (p, q) of the triangle of `side` lies in the plane of o: where
  // it crosses o's edges and which corners of o it passes through (its own
  // ends are placed by contact_points).
  void edge_in_plane(std::vector<ContactPoint>& pts, int side, int i, VertexId p, VertexId q,
                     const Tri& o, int drop) {
    for (int j = 0; j < 3; ++j) {
      const VertexId c = o[j], d = o[(j + 1) % 3];
      if (c != p && c != q &&
          pred::orient2d_projected(xyz(w_.plc, p), xyz(w_.plc, q), xyz(w_.plc, c), drop) == 0 &&
          strictly_between(xyz(w_.plc, p), xyz(w_.plc, q), xyz(w_.plc, c)))
        add_point(pts, side, c, i, at_vertex(j));
      if (c == p || c == q || d == p || d == q) continue;
      const int o1 = pred::orient2d_projected(xyz(w_.plc, p), xyz(w_.plc, q), xyz(w_.plc, c), drop);
      const int o2 = pred::orient2d_projected(xyz(w_.plc, p), xyz(w_.plc, q), xyz(w_.plc, d), drop);
      const int o3 = pred::orient2d_projected(xyz(w_.plc, c), xyz(w_.plc, d), xyz(w_.plc, p), drop);
      const int o4 = pred::orient2d_projected(xyz(w_.plc, c), xyz(w_.plc, d), xyz(w_.plc, q), drop);
      if (o1 * o2 < 0 && o3 * o4 < 0) add_point(pts, side, point_on_edges(p, q, c, d), i, j);
    }
  }

  // Adds v (where it lies: at_side in the triangle of `side`, at_other in
  // the other) unless it is outside the other or already there.
  static void add_point(std::vector<ContactPoint>& pts, int side, VertexId v, int at_side, int at_other) {
    if (at_other == kOutside) return;
    for (const ContactPoint& c : pts)
      if (c.v == v) return;
    ContactPoint c;
    c.v = v;
    c.at[side] = at_side;
    c.at[1 - side] = at_other;
    pts.push_back(c);
  }

  // Pieces between consecutive contact points, in order along a line: for
  // side < 0 all the points (they lie on the line common to two planes),
  // else those on edge j of `tri` (the triangle of `side`), along that edge.
  // The order is by the coordinate on which the points spread most (they
  // are collinear up to rounding), ties by id.
  void chain_along(const std::vector<ContactPoint>& pts, int side, int j, const Tri& tri,
                   std::vector<std::pair<size_t, size_t>>& pieces) const {
    std::vector<size_t> on;
    for (size_t k = 0; k < pts.size(); ++k)
      if (side < 0 || (location_edges(pts[k].at[side]) & (1 << j))) on.push_back(k);
    if (on.size() < 2) return;
    int axis = 0;
    double spread = -1;
    for (int k = 0; k < 3; ++k) {
      double lo = xyz(w_.plc, pts[on[0]].v)[k], hi = lo;
      if (side >= 0) {
        lo = std::min(xyz(w_.plc, tri[j])[k], xyz(w_.plc, tri[(j + 1) % 3])[k]);
        hi = std::max(xyz(w_.plc, tri[j])[k], xyz(w_.plc, tri[(j + 1) % 3])[k]);
      } else {
        for (size_t x : on) {
          lo = std::min(lo, xyz(w_.plc, pts[x].v)[k]);
          hi = std::max(hi, xyz(w_.plc, pts[x].v)[k]);
        }
      }
      if (hi - lo > spread) {
        spread = hi - lo;
        axis = k;
      }
    }
    std::sort(on.begin(), on.end(), [&](size_t a, size_t b) {
      const double xa = xyz(w_.plc, pts[a].v)[axis], xb = xyz(w_.plc, pts[b].v)[axis];
      return xa != xb ? xa < xb : pts[a].v < pts[b].v;
    });
    for (size_t k = 0; k + 1 < on.size(); ++k) pieces.push_back({on[k], on[k + 1]});
  }

  // The edges of a triangle a location touches, as bits: edge i, a vertex's
  // two edges, none inside.
  static int location_edges(int at) {
    if (at >= 0 && at < 3) return 1 << at;
    if (at >= 3) return (1 << (at - 3)) | (1 << ((at - 3 + 2) % 3));
    return 0;
  }

  // Two points on one edge of the triangle: the piece between them runs
  // along its boundary, which is already an edge.
  static bool on_one_edge(int a, int b) { return (location_edges(a) & location_edges(b)) != 0; }

  void add_edge_point(VertexId a, VertexId b, VertexId v) {
    if (v == a || v == b) return;
    auto& pts = edge_points_[{std::min(a, b), std::max(a, b)}];
    if (std::find(pts.begin(), pts.end(), v) == pts.end()) pts.push_back(v);
  }

  // The point where edge (p, q) pierces the inside of triangle u: one id per
  // (edge, triangle).
  VertexId point_in_triangle(VertexId p, VertexId q, Tri u) {
    if (p > q) std::swap(p, q);
    std::sort(u.begin(), u.end());
    const std::array<VertexId, 5> key{p, q, u[0], u[1], u[2]};
    const auto it = made_.find(key);
    if (it != made_.end()) return it->second;
    std::vector<Plane> planes{plane_of(u)};
    add_planes_of_edge(p, q, planes);
    return made_[key] = new_point(pierce_point(xyz(w_.plc, p), xyz(w_.plc, q), u, w_.plc), p, q, planes);
  }

  Plane plane_of(const Tri& t) const { return {xyz(w_.plc, t[0]), xyz(w_.plc, t[1]), xyz(w_.plc, t[2])}; }

  // The planes of the triangles that have edge (p, q), at most two.
  void add_planes_of_edge(VertexId p, VertexId q, std::vector<Plane>& planes) {
    if (edge_facets_.empty())
      for (uint32_t f = 0; f < w_.plc.facets.size(); ++f) {
        if (!is_triangle(w_.plc.facets[f])) continue;
        const auto& l = w_.plc.facets[f].loops[0];
        for (int k = 0; k < 3; ++k) edge_facets_[edge_key(l[k], l[(k + 1) % 3])].push_back(f);
      }
    const auto it = edge_facets_.find(edge_key(p, q));
    if (it == edge_facets_.end()) return;
    for (uint32_t f : it->second) {
      if (planes.size() >= 3) break;
      const Plane pl = plane_of(tri(f));
      bool same = false;  // a plane listed already (coplanar triangles)
      for (const Plane& o : planes)
        same = same || (pred::orient3d(o[0], o[1], o[2], pl[0]) == 0 &&
                        pred::orient3d(o[0], o[1], o[2], pl[1]) == 0 &&
                        pred::orient3d(o[0], o[1], o[2], pl[2]) == 0);
      if (!same) planes.push_back(pl);
    }
  }

  // The crossing point of edges (p, q) and (a, b), which lie in one plane:
  // one id per pair of edges, computed with the edges in a fixed order.
  VertexId point_on_edges(VertexId p, VertexId q, VertexId a, VertexId b) {
    if (p > q) std::swap(p, q);
    if (a > b) std::swap(a, b);
    if (std::make_pair(a, b) < std::make_pair(p, q)) {
      std::swap(p, a);
      std::swap(q, b);
    }
    const std::array<VertexId, 5> key{p, q, a, b, kNone};
    const auto it = made_.find(key);
    if (it != made_.end()) return it->second;
    std::vector<Plane> planes;
    add_planes_of_edge(p, q, planes);
    add_planes_of_edge(a, b, planes);
    const VertexId id = new_point(line_crossing(xyz(w_.plc, p), xyz(w_.plc, q), xyz(w_.plc, a),
                                                xyz(w_.plc, b)),
                                  p, q, planes);
    add_edge_point(a, b, id);
    return made_[key] = id;
  }

  VertexId new_point(const Vec3& x, VertexId p, VertexId q, const std::vector<Plane>& planes) {
    const VertexId id = point_at(snapped_on_planes(x, grid_, planes));
    add_edge_point(p, q, id);
    return id;
  }

  // A triangle of facet f's retriangulation that lies in the overlap of f
  // with a coplanar facet of lower id. That facet keeps the overlap and f
  // drops its copy, so two differently triangulated copies cannot overlap
  // again in the next round. Decided by ids when the corners of t are all
  // corners of the (convex) overlap; otherwise t also has points of other
  // contacts as corners (a third facet crossing the overlap cuts both
  // copies), and t lies in the overlap when its centroid lies in the closed
  // lower triangle (exact signs). t is a piece of f, so lying in the lower
  // triangle means lying in the overlap; the centroid decides for the
  // pieces whose rounded corners lie a grid step off its edges.
  bool is_covered(uint32_t f, const Tri& t) const {
    const auto it = covered_.find(f);
    if (it == covered_.end()) return false;
    for (const Overlap& overlap : it->second) {
      bool all = true;
      for (VertexId v : t) all = all && std::binary_search(overlap.corners.begin(), overlap.corners.end(), v);
      if (all || centroid_in(t, overlap.lower)) return true;
    }
    return false;
  }

  // The centroid of t in the closed triangle u, in u's projection.
  bool centroid_in(const Tri& t, const Tri& u) const {
    const int drop = projection_axis(u);
    const double* c[3] = {xyz(w_.plc, t[0]), xyz(w_.plc, t[1]), xyz(w_.plc, t[2])};
    const int turn = pred::orient2d_projected(xyz(w_.plc, u[0]), xyz(w_.plc, u[1]), xyz(w_.plc, u[2]), drop);
    for (int j = 0; j < 3; ++j)
      if (turn * pred::orient2d_centroid_projected(xyz(w_.plc, u[j]), xyz(w_.plc, u[(j + 1) % 3]), c, drop) < 0)
        return false;
    return true;
  }

  // The point at x: the one already there (a constructed point that snaps
  // onto a point is that point), or a new one.
  VertexId point_at(const Vec3& x) {
    if (at_.empty())
      for (VertexId v = 0; v < w_.plc.points.size(); ++v) at_.emplace(key_of(w_.plc.points[v]), v);
    const auto [it, added] = at_.emplace(key_of(x), static_cast<VertexId>(w_.plc.points.size()));
    if (!added) return it->second;
    w_.plc.points.push_back(x);
    ++report_.intersection_points;
    return it->second;
  }

  static std::array<double, 3> key_of(const Vec3& x) { return {x.x, x.y, x.z}; }

  // The constrained triangulation of triangle t with the inserted points and
  // segments, computed on the projection that drops the axis of t's largest
  // normal component: a flat PLC (coordinates (u, v, 0), exact copies) whose
  // one facet is t's boundary with the edge points, plus the inside points
  // and segments, which triangulate_surface takes as lying in the facet.
  bool retriangulate(uint32_t fid, Insert& in, std::vector<Tri>& out) {
    const Tri t = tri(fid);
    const Plc& plc = w_.plc;
    const int drop = projection_axis(t);
    const int ua = (drop + 1) % 3, va = (drop + 2) % 3;
    std::vector<VertexId> ids;  // flat id -> PLC id
    auto flat_id = [&](VertexId v) {
      const auto it = std::find(ids.begin(), ids.end(), v);
      if (it != ids.end()) return static_cast<VertexId>(it - ids.begin());
      ids.push_back(v);
      return static_cast<VertexId>(ids.size() - 1);
    };
    // Edge points in order along each edge (by the distance from its start
    // along an axis where the edge's ends differ; coordinates compare exactly).
    std::sort(in.on_edge.begin(), in.on_edge.end());
    in.on_edge.erase(std::unique(in.on_edge.begin(), in.on_edge.end()), in.on_edge.end());
    std::vector<VertexId> loop;
    for (int i = 0; i < 3; ++i) {
      loop.push_back(flat_id(t[i]));
      std::vector<VertexId> pts;
      for (const auto& e : in.on_edge)
        if (e.first == i) pts.push_back(e.second);
      sort_along(plc, t[i], t[(i + 1) % 3], pts);
      for (VertexId x : pts) loop.push_back(flat_id(x));
    }
    for (VertexId x : in.inside) flat_id(x);
    for (const auto& s : in.segments)
      for (VertexId x : split_chain(fid, s)) flat_id(x);
    Plc flat;
    for (VertexId v : ids) flat.points.push_back(Vec3{xyz(plc, v)[ua], xyz(plc, v)[va], 0});
    // Two points with one projection would be one flat point: give up.
    {
      std::vector<std::pair<double, double>> seen;
      for (const Vec3& p : flat.points) seen.push_back({p.x, p.y});
      std::sort(seen.begin(), seen.end());
      if (std::adjacent_find(seen.begin(), seen.end()) != seen.end()) return false;
    }
    Facet f;
    f.loops.push_back(loop);
    flat.facets.push_back(f);
    for (const auto& s : in.segments) {
      const std::vector<VertexId> chain = split_chain(fid, s);
      for (size_t k = 0; k + 1 < chain.size(); ++k) {
        const VertexId a = flat_id(chain[k]), b = flat_id(chain[k + 1]);
        if (a != b) flat.segments.push_back({a, b});
      }
    }
    if (ids.size() != flat.points.size()) return false;
    split_at_points(flat);
    std::vector<uint32_t> tris, tri_facet;
    if (!triangulate_surface(flat, tris, tri_facet).ok() || tris.empty()) {
      // Rounded points can make two contact segments cross without a
      // triple point, or a point lie on a segment in the projection: the
      // points alone are triangulated instead, and the contacts those
      // triangles still have are found exactly in the next round.
      if (flat.segments.empty()) return false;
      flat.segments.clear();
      tris.clear();
      tri_facet.clear();
      if (!triangulate_surface(flat, tris, tri_facet).ok() || tris.empty()) return false;
    }
    for (size_t k = 0; k + 2 < tris.size(); k += 3) out.push_back({ids[tris[k]], ids[tris[k + 1]], ids[tris[k + 2]]});
    return true;
  }

  // Every segment of the flat PLC split at the flat points lying on it
  // (orient2d exactly 0, strictly between its ends): the end of one contact
  // segment on another (three triangles meeting where one's contact ends on
  // another's), or a rounded point that landed on one. Collinear overlaps
  // become shared pieces, kept once.
  static void split_at_points(Plc& flat) {
    std::vector<std::array<VertexId, 2>> pieces;
    for (const auto& seg : flat.segments) {
      const double *a = &flat.points[seg[0]].x, *b = &flat.points[seg[1]].x;
      std::vector<VertexId> on;
      for (VertexId v = 0; v < flat.points.size(); ++v) {
        if (v == seg[0] || v == seg[1]) continue;
        const double* p = &flat.points[v].x;
        if (pred::orient2d_projected(a, b, p, 2) == 0 && strictly_between(a, b, p)) on.push_back(v);
      }
      // Along the segment by a coordinate on which its ends differ (exact).
      const int k = a[0] != b[0] ? 0 : 1;
      const bool up = b[k] > a[k];
      std::sort(on.begin(), on.end(), [&](VertexId x, VertexId y) {
        const double cx = (&flat.points[x].x)[k], cy = (&flat.points[y].x)[k];
        return up ? cx < cy : cx > cy;
      });
      VertexId from = seg[0];
      for (VertexId v : on) {
        pieces.push_back({std::min(from, v), std::max(from, v)});
        from = v;
      }
      pieces.push_back({std::min(from, seg[1]), std::max(from, seg[1])});
    }
    std::sort(pieces.begin(), pieces.end());
    pieces.erase(std::unique(pieces.begin(), pieces.end()), pieces.end());
    flat.segments = std::move(pieces);
  }

  // Where three triangles meet: inside triangle t the intersection segments
  // with u1 and with u2 cross at the point common to the three planes. It
  // splits both segments in t, and the segments (u1, t), (u1, u2) in u1 and
  // (u2, t), (u2, u1) in u2. Crossing is decided exactly (orient2d in t's
  // projection) on the segments' rounded ends; the point is constructed
  // once per triple of triangles (three_planes, ROUNDED).
  void find_triple_points() {
    const Plc& plc = w_.plc;
    for (auto& [f, in] : inserts_) {
      const int drop = projection_axis(tri(f));
      for (size_t i = 0; i < in.segments.size(); ++i)
        for (size_t j = i + 1; j < in.segments.size(); ++j) {
          const Insert::Segment &s1 = in.segments[i], &s2 = in.segments[j];
          if (s1.other == s2.other) continue;
          // A piece of an explicit segment has no plane to meet: where a
          // contact crosses it, the triangulation fails and falls back to
          // the points alone, and the next round finds that crossing as a
          // segment through a triangle.
          if (s1.other >= w_.plc.facets.size() || s2.other >= w_.plc.facets.size()) continue;
          if (s1.a == s2.a || s1.a == s2.b || s1.b == s2.a || s1.b == s2.b) continue;
          const double *a = xyz(plc, s1.a), *b = xyz(plc, s1.b);
          const double *c = xyz(plc, s2.a), *d = xyz(plc, s2.b);
          const int o1 = pred::orient2d_projected(a, b, c, drop);
          const int o2 = pred::orient2d_projected(a, b, d, drop);
          const int o3 = pred::orient2d_projected(c, d, a, drop);
          const int o4 = pred::orient2d_projected(c, d, b, drop);
          if (o1 * o2 >= 0 || o3 * o4 >= 0) continue;  // no proper crossing
          const VertexId x = triple_point(f, s1.other, s2.other, s1, s2);
          const uint32_t g = s1.other, h = s2.other;
          for (auto key : {std::make_pair(f, g), std::make_pair(f, h), std::make_pair(g, f),
                           std::make_pair(g, h), std::make_pair(h, f), std::make_pair(h, g)})
            splits_[key].push_back(x);
        }
    }
  }

  VertexId triple_point(uint32_t f, uint32_t g, uint32_t h, const Insert::Segment& s1,
                        const Insert::Segment& s2) {
    std::array<uint32_t, 3> key{f, g, h};
    std::sort(key.begin(), key.end());
    const auto it = triples_.find(key);
    if (it != triples_.end()) return it->second;
    Vec3 x;
    if (!three_planes(tri(key[0]), tri(key[1]), tri(key[2]), x))
      x = line_crossing(xyz(w_.plc, s1.a), xyz(w_.plc, s1.b), xyz(w_.plc, s2.a), xyz(w_.plc, s2.b));
    return triples_[key] = point_at(snapped(x, grid_));
  }

  // The point common to the planes of three triangles (Cramer's rule in
  // double-double, then ROUNDED to doubles). False when the planes are (nearly)
  // parallel in floating point.
  bool three_planes(const Tri& t1, const Tri& t2, const Tri& t3, Vec3& out) const {
    using LD = DoubleDouble;
    LD n[3][3], d[3];
    const Tri* ts[3] = {&t1, &t2, &t3};
    for (int i = 0; i < 3; ++i) {
      const double *a = xyz(w_.plc, (*ts[i])[0]), *b = xyz(w_.plc, (*ts[i])[1]), *c = xyz(w_.plc, (*ts[i])[2]);
      LD u[3], v[3];
      for (int k = 0; k < 3; ++k) {
        u[k] = LD(b[k]) - a[k];
        v[k] = LD(c[k]) - a[k];
      }
      n[i][0] = u[1] * v[2] - u[2] * v[1];
      n[i][1] = u[2] * v[0] - u[0] * v[2];
      n[i][2] = u[0] * v[1] - u[1] * v[0];
      d[i] = n[i][0] * a[0] + n[i][1] * a[1] + n[i][2] * a[2];
    }
    auto cross = [](const LD* x, const LD* y, LD* o) {
      o[0] = x[1] * y[2] - x[2] * y[1];
      o[1] = x[2] * y[0] - x[0] * y[2];
      o[2] = x[0] * y[1] - x[1] * y[0];
    };
    LD c12[3], c23[3], c31[3];
    cross(n[1], n[2], c23);
    cross(n[2], n[0], c31);
    cross(n[0], n[1], c12);
    const LD det = n[0][0] * c23[0] + n[0][1] * c23[1] + n[0][2] * c23[2];
    double* o = &out.x;
    for (int k = 0; k < 3; ++k) {
      const LD x = (d[0] * c23[k] + d[1] * c31[k] + d[2] * c12[k]) / det;
      o[k] = x.value();
      if (!std::isfinite(o[k]) || !std::isfinite(x.lo)) return false;
    }
    return true;
  }

  // The segment with its triple points, in order from a to b.
  std::vector<VertexId> split_chain(uint32_t f, const Insert::Segment& s) const {
    std::vector<VertexId> chain{s.a};
    const auto it = splits_.find({f, s.other});
    if (it != splits_.end()) {
      std::vector<VertexId> mid = it->second;
      std::sort(mid.begin(), mid.end());
      mid.erase(std::unique(mid.begin(), mid.end()), mid.end());
      const double *a = xyz(w_.plc, s.a), *b = xyz(w_.plc, s.b);
      auto param = [&](VertexId x) {  // only orders points along the segment
        DoubleDouble t = 0;
        for (int k = 0; k < 3; ++k) t = t + (DoubleDouble(xyz(w_.plc, x)[k]) - a[k]) * (DoubleDouble(b[k]) - a[k]);
        return t;
      };
      std::sort(mid.begin(), mid.end(), [&](VertexId x, VertexId y) { return param(x) < param(y); });
      chain.insert(chain.end(), mid.begin(), mid.end());
    }
    chain.push_back(s.b);
    return chain;
  }

  // geometry.hpp's triangle normal; ties go to the last axis (largest_axis
  // sends them to the first): any axis of a largest component projects the
  // triangle without degeneracy, and keeping this order keeps repaired PLCs
  // identical to those of earlier versions (the 2D triangulations depend on
  // the projection).
  int projection_axis(const Tri& t) const {
    const Vec3 v = triangle_normal(xyz(w_.plc, t[0]), xyz(w_.plc, t[1]), xyz(w_.plc, t[2]));
    const double n[3] = {v.x, v.y, v.z};
    int drop = 2;
    for (int k = 0; k < 2; ++k)
      if (std::fabs(n[k]) > std::fabs(n[drop])) drop = k;
    return drop;
  }

  // The new points on a loop's edges: for a triangle (in != nullptr) as
  // Insert::on_edge, else inserted into the loop in order along each edge.
  bool take_edge_points(std::vector<VertexId>& loop, Insert* in) const {
    const Plc& plc = w_.plc;
    std::vector<VertexId> grown;
    bool any = false;
    for (size_t i = 0; i < loop.size(); ++i) {
      const VertexId a = loop[i], b = loop[(i + 1) % loop.size()];
      grown.push_back(a);
      const auto it = edge_points_.find({std::min(a, b), std::max(a, b)});
      if (it == edge_points_.end()) continue;
      any = true;
      std::vector<VertexId> pts = it->second;
      const double *pa = xyz(plc, a), *pb = xyz(plc, b);
      int k = 0;
      while (k < 2 && pa[k] == pb[k]) ++k;
      std::sort(pts.begin(), pts.end(), [&](VertexId x, VertexId y) {
        return pa[k] < pb[k] ? xyz(plc, x)[k] < xyz(plc, y)[k] : xyz(plc, x)[k] > xyz(plc, y)[k];
      });
      for (VertexId x : pts) {
        if (in) in->on_edge.push_back({static_cast<int>(i), x});
        else grown.push_back(x);
      }
    }
    if (!in) loop = std::move(grown);
    return any;
  }

  Work& w_;
  RepairReport& report_;
  double grid_;
  std::map<std::pair<VertexId, VertexId>, std::vector<VertexId>> edge_points_;
  std::map<std::pair<uint32_t, uint32_t>, std::vector<VertexId>> splits_;  ///< (facet, other) -> triple points
  std::map<std::array<uint32_t, 3>, VertexId> triples_;
  std::map<uint32_t, Insert> inserts_;
  std::map<std::array<VertexId, 5>, VertexId> made_;
  std::map<std::array<double, 3>, VertexId> at_;  ///< point by coordinates, built on first use
  /// Triangle facets by edge (add_planes_of_edge), built on first use.
  std::map<Edge, std::vector<uint32_t>> edge_facets_;
  struct Overlap {
    std::vector<VertexId> corners;  ///< sorted
    Tri lower;                      ///< the facet of lower id, which keeps the overlap
  };
  /// Per facet: its coplanar overlaps with facets of lower id.
  std::map<uint32_t, std::vector<Overlap>> covered_;
};

// Crossings, and touching contacts (an edge crossing the other facet's edge
// or piercing it at one point, the facets on one side): both are cut by the
// same piercing points. Coplanar contacts are cut along the overlap's
// boundary. A pair with an explicit segment is handled in every kind.
bool handled(const Intersection& x) {
  return x.kind == IntersectionKind::Cross || x.kind == IntersectionKind::VertexInFacet ||
         x.kind == IntersectionKind::CoplanarOverlap;
}

// Needles (collapse_needles) are triangles thinner than this many grid
// steps: 2^22 steps, 2^-18 of the binary order of the largest coordinate,
// about 32 float32 units in the last place there. Models that need repair
// mostly come from float32 data (STL stores float32, OBJ exporters print
// 6 or 7 digits), so features that thin are noise of the export, and two
// copies of one part that differ by it meet in needles. chair_model.obj
// (two such copies) does not mesh at 2^18. At 2^20 it meshed with two
// numerically flat tets: a needle (2.4e-6 rad at a corner, 7.4e-7 wide at
// coordinates of 0.3) was left, and segment recovery split its two long
// sides at points 6.5e-12 apart. At 2^22: no flat tet, and half the segment
// Steiner points (106,753 -> 51,021).
constexpr double kNeedleGridSteps = 0x1p+22;
// A point of one facet this many grid steps or closer to another facet's
// edge goes into that edge (add_points_close_to_edges): a few steps are
// the rounding of points constructed on one line; features of the export
// (copies of a part a few float32 units apart, about 2^17 steps) are left
// to the needle collapse, and 2^22 steps here changed chair_model.obj's
// repair so that it meshed with numerically flat tets.
constexpr double kHotPixelSteps = 0x1p+10;
/// Collapsing needles can make new ones beside them (a corner put into an
/// edge makes the triangle across a cap again where many points lie near
/// one line); passes beyond this are left to the exact check.
constexpr int kNeedlePasses = 4;

// Grid coordinates of a snapped point (exact: x is a multiple of the grid,
// a power of two, at most about 2^41 of them from 0).
std::array<int64_t, 3> cell_of(const Vec3& x, double grid) {
  return {static_cast<int64_t>(x.x / grid), static_cast<int64_t>(x.y / grid),
          static_cast<int64_t>(x.z / grid)};
}

// Snapped points on neighbouring grid points (one step apart on each axis
// at most) are made one point: the lowest id of each such cluster gives its
// coordinates to the others, which weld_points then merges. One point
// constructed twice from different rounded inputs lands on two neighbouring
// grid points as often as on one (its exact place lies between them), and
// the needle triangles between such copies cross each other again in every
// round, since a point constructed there snaps back onto them. What the
// merge breaks (a triangle collapsed, a point moved onto a facet) is
// repaired and checked exactly again like any other rounding.
void merge_neighbouring_points(Plc& plc, double grid) {
  if (grid == 0) return;
  const std::vector<uint8_t> used = used_points(plc);
  std::vector<std::pair<std::array<int64_t, 3>, VertexId>> cells;
  for (VertexId v = 0; v < plc.points.size(); ++v)
    if (used[v]) cells.push_back({cell_of(plc.points[v], grid), v});
  std::sort(cells.begin(), cells.end());
  std::vector<VertexId> root(plc.points.size());
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](VertexId v) {
    while (root[v] != v) v = root[v] = root[root[v]];
    return v;
  };
  for (const auto& [c, v] : cells)
    for (int d = 0; d < 27; ++d) {
      const std::array<int64_t, 3> n{c[0] + d % 3 - 1, c[1] + d / 3 % 3 - 1, c[2] + d / 9 - 1};
      auto it = std::lower_bound(cells.begin(), cells.end(), std::make_pair(n, VertexId(0)));
      for (; it != cells.end() && it->first == n; ++it) {
        const VertexId a = find(v), b = find(it->second);
        if (a != b) root[std::max(a, b)] = std::min(a, b);
      }
    }
  for (const auto& cv : cells) plc.points[cv.second] = plc.points[find(cv.second)];
}

// The ends of every loop edge no longer than `delta` on every axis are made
// one point, with the coordinates of the lowest id (an input point before a
// constructed one); weld_points then merges them. Returns the merges.
size_t merge_short_edges(Plc& plc, double delta) {
  std::vector<VertexId> root(plc.points.size());
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](VertexId v) {
    while (root[v] != v) v = root[v] = root[root[v]];
    return v;
  };
  size_t merged = 0;
  for (const Facet& f : plc.facets)
    for (const auto& l : f.loops)
      for (size_t i = 0; i < l.size(); ++i) {
        const Vec3 d = plc.points[l[i]] - plc.points[l[(i + 1) % l.size()]];
        if (std::max({std::fabs(d.x), std::fabs(d.y), std::fabs(d.z)}) > delta) continue;
        const VertexId a = find(l[i]), b = find(l[(i + 1) % l.size()]);
        if (a == b) continue;
        root[std::max(a, b)] = std::min(a, b);
        ++merged;
      }
  for (VertexId v = 0; v < plc.points.size(); ++v) plc.points[v] = plc.points[find(v)];
  return merged;
}

/// Points to put into edges, by edge_key, in order from its lower id.
using EdgePoints = std::map<Edge, std::vector<VertexId>>;

// `loop` with the points of `on_edge` inserted into its edges, in order.
std::vector<VertexId> with_points_on_edges(const std::vector<VertexId>& loop, const EdgePoints& on_edge) {
  std::vector<VertexId> grown;
  for (size_t i = 0; i < loop.size(); ++i) {
    const VertexId a = loop[i], b = loop[(i + 1) % loop.size()];
    grown.push_back(a);
    const auto it = on_edge.find(edge_key(a, b));
    if (it == on_edge.end()) continue;
    if (a < b) grown.insert(grown.end(), it->second.begin(), it->second.end());
    else grown.insert(grown.end(), it->second.rbegin(), it->second.rend());
  }
  return grown;
}

// Points of other facets lying within `delta` of a facet edge and
// projecting inside it, added to `on_edge` (unsorted). Snap rounding's hot
// pixels (Hobby 1999): an edge that passes that close to a point is routed
// through it. Rounded points constructed on one line (the crossings of
// several facets with one plane) come out up to a grid step off it, and a
// facet edge along the line then passes a point of the next facet at 1e-13
// of its length without touching it; segment recovery cannot make such a
// segment an edge of a Delaunay tetrahedralization with a finite number of
// splits. Only near the facets steps 1-4 changed (`active`): their points
// against every edge, every point against their edges; candidates from the
// points' grid in each edge's box.
void add_points_close_to_edges(const Plc& plc, double delta, const std::vector<uint8_t>& active,
                               EdgePoints& on_edge) {
  // Each edge once, active when a facet steps 1-4 changed has it; the
  // points of those facets.
  std::vector<std::pair<Edge, bool>> edges;
  std::vector<uint8_t> active_point(plc.points.size(), 0);
  for (size_t f = 0; f < plc.facets.size(); ++f)
    for (const auto& l : plc.facets[f].loops)
      for (size_t i = 0; i < l.size(); ++i) {
        const bool on = f < active.size() && active[f];
        edges.push_back({edge_key(l[i], l[(i + 1) % l.size()]), on});
        if (on) active_point[l[i]] = 1;
      }
  std::sort(edges.begin(), edges.end());  // an active copy of an edge sorts last
  const PointGrid grid(plc, false);
  for (size_t k = 0; k < edges.size(); ++k) {
    // Plain names: a lambda may not capture a structured binding in C++17.
    const Edge& e = edges[k].first;
    const bool on = edges[k].second;
    if (k + 1 < edges.size() && edges[k + 1].first == e) continue;
    const double *pa = xyz(plc, e.first), *pb = xyz(plc, e.second);
    double lo[3], hi[3];
    for (int c = 0; c < 3; ++c) lo[c] = std::min(pa[c], pb[c]) - delta, hi[c] = std::max(pa[c], pb[c]) + delta;
    const Vec3 a = plc.points[e.first], ab = plc.points[e.second] - a;
    const double len2 = dot(ab, ab);
    grid.query(lo, hi, [&](VertexId v) {
      if (v == e.first || v == e.second || !(on || active_point[v])) return;
      const Vec3 av = plc.points[v] - a;
      const double along = dot(av, ab);
      if (!(along > 0 && along < len2)) return;
      const Vec3 nrm = cross(ab, av);
      if (dot(nrm, nrm) > delta * delta * len2) return;
      // A point exactly on the edge is a T-junction (split_at_tjunctions).
      if (pred::collinear3d(pa, pb, xyz(plc, v))) return;
      auto& pts = on_edge[e];
      if (std::find(pts.begin(), pts.end(), v) == pts.end()) pts.push_back(v);
    });
  }
}

// Corners of triangle facets lying within `delta` of the line of their
// opposite edge and projecting inside it, and points of other facets within
// `foreign` of an edge (add_points_close_to_edges), by edge.
EdgePoints close_corners(const Plc& plc, double delta, double foreign, const std::vector<uint8_t>& active) {
  EdgePoints on_edge;
  for (const Facet& f : plc.facets) {
    if (!is_triangle(f)) continue;
    const auto& l = f.loops[0];
    for (int i = 0; i < 3; ++i) {
      const VertexId a = l[i], b = l[(i + 1) % 3], v = l[(i + 2) % 3];
      const Vec3 ab = plc.points[b] - plc.points[a], av = plc.points[v] - plc.points[a];
      const double len2 = dot(ab, ab), t = dot(av, ab);
      if (!(t > 0 && t < len2)) continue;
      const Vec3 n = cross(ab, av);  // |n| = |ab| times the distance
      if (dot(n, n) > delta * delta * len2) continue;
      auto& pts = on_edge[edge_key(a, b)];
      if (std::find(pts.begin(), pts.end(), v) == pts.end()) pts.push_back(v);
    }
  }
  add_points_close_to_edges(plc, foreign, active, on_edge);
  for (auto& [e, pts] : on_edge) {
    const Vec3 a = plc.points[e.first], ab = plc.points[e.second] - a;
    std::sort(pts.begin(), pts.end(), [&](VertexId x, VertexId y) {
      const double tx = dot(plc.points[x] - a, ab), ty = dot(plc.points[y] - a, ab);
      return tx != ty ? tx < ty : x < y;
    });
  }
  return on_edge;
}

// Triangle `t` with the points of its own edges (`own`: the edges of the
// facet it was cut from) taken in: cut into the fan from the corner opposite
// such an edge, the pieces cut again at the facet's other edges (each once,
// so the cutting ends even where the close points have edges of their own).
// Ear clipping of the grown loop could cut the needle off again. A needle,
// whose corner is one of the points of its own edge, goes: its other two
// edges now border the pieces of the triangle across.
void cut_at_edge_points(Facet t, const std::array<Edge, 3>& own, const EdgePoints& on_edge,
                        std::vector<Facet>& out) {
  std::vector<Facet> work{std::move(t)};
  while (!work.empty()) {
    Facet piece = std::move(work.back());
    work.pop_back();
    const auto& l = piece.loops[0];
    int cut = -1;
    bool needle = false;
    for (int i = 0; i < 3; ++i) {
      const Edge e = edge_key(l[i], l[(i + 1) % 3]);
      const auto it = on_edge.find(e);
      if (it == on_edge.end() || std::find(own.begin(), own.end(), e) == own.end()) continue;
      if (cut < 0) cut = i;
      needle |= std::find(it->second.begin(), it->second.end(), l[(i + 2) % 3]) != it->second.end();
    }
    if (needle) continue;
    if (cut < 0) {
      out.push_back(std::move(piece));
      continue;
    }
    const VertexId a = l[cut], b = l[(cut + 1) % 3], x = l[(cut + 2) % 3];
    const std::vector<VertexId> chain = with_points_on_edges({a, b}, on_edge);  // a, points, b, points, (a)
    const size_t n = std::find(chain.begin() + 1, chain.end(), b) - chain.begin();
    for (size_t k = 0; k < n; ++k) work.push_back(part_of(piece, {chain[k], chain[k + 1], x}));
  }
}

// Puts the close corners into their edges, in every facet with such an
// edge (triangles by cut_at_edge_points, polygons in their loops). Returns
// how many edges took points.
size_t put_close_corners_on_edges(Work& w, double delta, double foreign) {
  Plc& plc = w.plc;
  std::vector<uint8_t> active(plc.facets.size(), 0);
  for (size_t f = 0; f < plc.facets.size(); ++f) active[f] = w.changed[w.source[f]];
  const EdgePoints on_edge = close_corners(plc, delta, foreign, active);
  if (on_edge.empty()) return 0;
  std::vector<Facet> facets;
  std::vector<uint32_t> source;
  for (size_t f = 0; f < plc.facets.size(); ++f) {
    Facet& facet = plc.facets[f];
    if (is_triangle(facet)) {
      const auto& l = facet.loops[0];
      const std::array<Edge, 3> own{edge_key(l[0], l[1]), edge_key(l[1], l[2]), edge_key(l[2], l[0])};
      cut_at_edge_points(std::move(facet), own, on_edge, facets);
    } else {
      for (auto& l : facet.loops) l = with_points_on_edges(l, on_edge);
      facets.push_back(std::move(facet));
    }
    source.resize(facets.size(), w.source[f]);
  }
  plc.facets = std::move(facets);
  w.source = std::move(source);
  return on_edge.size();
}

// Needles: triangles with an edge no longer than `delta`, or with a corner
// closer than `delta` to the line of its opposite edge. The arrangement of
// nearly coincident facets (a part and its copy a few float32 units apart)
// is full of them, and segment recovery cannot split two long segments
// meeting at an angle of 1e-9 into edges of a Delaunay tetrahedralization
// (it needs about 1 / angle points). The short edge's ends merge; the close
// corner goes into the edge. Deciding what is a needle is snap rounding at
// a coarser scale than the grid, in floating point: like the rounding it
// only moves points and joins features, and the result is checked exactly
// again like any other rounding. True when something changed.
bool collapse_needles(Work& w, double grid) {
  const double delta = grid * kNeedleGridSteps;
  RepairReport scratch;
  const size_t merged = merge_short_edges(w.plc, delta);
  if (merged > 0) {
    weld_points(w, scratch);
    clean_polygons(w, scratch);
  }
  const size_t put = put_close_corners_on_edges(w, delta, grid * kHotPixelSteps);
  if (put > 0) clean_polygons(w, scratch);
  return merged + put > 0;
}

// Rounded points can break what steps 1-3 made true: a new point may land on
// an existing point, a thin new triangle may come out collinear, a polygon
// that took a point on an edge may no longer be planar, a point may land
// exactly on another facet. Those steps run again (they are exact; their
// counts go to a scratch report, since these are no input defects), and the
// input checks must pass before the exact intersection test runs again.
Status tidy_after_rounding(Work& w, double grid) {
  merge_neighbouring_points(w.plc, grid);
  RepairReport scratch;
  weld_points(w, scratch);
  clean_polygons(w, scratch);
  clean_segments(w, true);
  Status st;
  for (int pass = 0; pass < kNeedlePasses; ++pass) {
    const bool any = collapse_needles(w, grid);
    split_nonplanar_facets(w, scratch);
    st = split_at_tjunctions(w, scratch);
    // Triangulating facets at T-junctions can make copies of a triangle.
    clean_polygons(w, scratch);
    drop_duplicate_facets(w, scratch);
    if (!st.ok() || !any) break;
  }
  clean_segments(w, true);  // collapsed needles may have welded a segment's ends
  if (st.ok()) st = check_plc(w.plc);
  return st;
}

}  // namespace

// Before the first round, on a PLC with improper pairs, every point is
// snapped to the grid (snapped()): CAD exports carry noise far below their
// precision (a coordinate of 1e-33 where its neighbour has 0), and points
// that close make constructed points land among them and segment recovery
// split needles without end. The exact steps then weld, clean and split
// what the snapping moved. Valid models never get here: they have no pairs.
Status snap_all(Work& w, double grid) {
  for (Vec3& p : w.plc.points) p = snapped(p, grid);
  return tidy_after_rounding(w, grid);
}

// The points no facet or segment uses, by coordinates.
std::vector<Vec3> unused_points(const Plc& plc) {
  const std::vector<uint8_t> used = used_points(plc);
  std::vector<Vec3> out;
  for (VertexId v = 0; v < used.size(); ++v)
    if (!used[v]) out.push_back(plc.points[v]);
  return out;
}

bool lex_less(const Vec3& a, const Vec3& b) {
  return a.x != b.x ? a.x < b.x : (a.y != b.y ? a.y < b.y : a.z < b.z);
}

// Drops the points that the rounds left unused (a constructed point whose
// triangle was not retriangulated, a vertex merged or cut away), keeping
// the isolated points of the input (`isolated`): a free point is part of
// the PLC, and one left behind on a facet or an edge would make it invalid.
void drop_unused_points(Work& w, std::vector<Vec3> isolated) {
  std::sort(isolated.begin(), isolated.end(), lex_less);
  Plc& plc = w.plc;
  const std::vector<uint8_t> used = used_points(plc);
  std::vector<VertexId> id(plc.points.size(), kNone);
  std::vector<Vec3> kept;
  for (VertexId v = 0; v < plc.points.size(); ++v) {
    if (!used[v] && !std::binary_search(isolated.begin(), isolated.end(), plc.points[v], lex_less)) continue;
    id[v] = static_cast<VertexId>(kept.size());
    kept.push_back(plc.points[v]);
  }
  if (kept.size() == plc.points.size()) return;
  plc.points = std::move(kept);
  renumber_vertices(plc, id);
}

// Flags in `out` the polygon facets (not triangles) that are `involved` or
// share an edge with an involved facet. True when there is one.
bool polygons_near(const Plc& plc, const std::vector<uint8_t>& involved, std::vector<uint8_t>& out) {
  using Edge = std::pair<VertexId, VertexId>;
  auto edge = [](VertexId a, VertexId b) { return a < b ? Edge{a, b} : Edge{b, a}; };
  std::vector<Edge> edges;
  for (size_t f = 0; f < involved.size(); ++f)
    if (involved[f])
      for (const auto& l : plc.facets[f].loops)
        for (size_t i = 0; i < l.size(); ++i) edges.push_back(edge(l[i], l[(i + 1) % l.size()]));
  std::sort(edges.begin(), edges.end());
  out.assign(plc.facets.size(), 0);
  bool any = false;
  for (size_t f = 0; f < plc.facets.size(); ++f) {
    if (is_triangle(plc.facets[f])) continue;
    bool near = involved[f];
    for (const auto& l : plc.facets[f].loops)
      for (size_t i = 0; i < l.size() && !near; ++i)
        near = std::binary_search(edges.begin(), edges.end(), edge(l[i], l[(i + 1) % l.size()]));
    out[f] = near;
    any |= near;
  }
  return any;
}

// Rounds of exact detection, snapping (first round), and resolution of
// every handled pair, until nothing is left or kRounds.
Status resolve_rounds(Work& w, RepairReport& report, std::vector<Intersection>& left) {
  const double grid = snap_grid(w.plc);
  size_t first_pairs = 0;
  for (size_t round = 0;; ++round) {
    find_self_intersections(w.plc, left);
    const uint32_t facets = static_cast<uint32_t>(w.plc.facets.size());
    std::vector<uint8_t> involved(facets, 0);
    size_t crossing = 0, with_segments = 0;
    std::vector<uint32_t> segments_met;
    for (const Intersection& x : left) {
      if (x.b >= facets) {  // a segment with a facet or another segment
        if (x.a < facets) involved[x.a] = 1;
        else segments_met.push_back(x.a - facets);
        segments_met.push_back(x.b - facets);
        ++with_segments;
        continue;
      }
      if (!handled(x)) continue;
      involved[x.a] = involved[x.b] = 1;
      ++crossing;
    }
    if (round == 0) {
      report.crossing_pairs = crossing;
      std::sort(segments_met.begin(), segments_met.end());
      report.crossing_segments = static_cast<size_t>(
          std::unique(segments_met.begin(), segments_met.end()) - segments_met.begin());
      first_pairs = crossing + with_segments;
    }
    if (crossing + with_segments == 0 || round == kRounds) return Status::success();
    // Rounds that multiply the pairs do not converge (rounding keeps
    // cutting what it cut before): stop, and the pairs left are reported.
    if (round > 1 && crossing + with_segments > kGrowth * first_pairs + 64) return Status::success();
    report.rounds = round + 1;
    if (round == 0) {
      Status st = snap_all(w, grid);
      if (!st.ok()) return st;
      continue;
    }
    // Polygon facets in improper pairs, or with an edge of one, are
    // triangulated first (a polygon that took rounded points on its edges
    // could stop being simple); the pairs are then found again between
    // triangles.
    std::vector<uint8_t> polygon;
    if (polygons_near(w.plc, involved, polygon)) {
      Status st = triangulate_in_place(w, polygon);
      if (!st.ok()) return st;
      // A polygon that had taken a T-junction's point can come out as
      // copies of the triangles beside it (a duplicate of a facet whose
      // edge the point split): copies go as in step 1.
      RepairReport again;
      drop_duplicate_facets(w, again);
      report.duplicate_facets += again.duplicate_facets;
      find_self_intersections(w.plc, left);
    }
    Crossings c(w, report, grid);
    size_t added = 0;
    const uint32_t nf = static_cast<uint32_t>(w.plc.facets.size());
    for (const Intersection& x : left) {
      if (x.b >= nf) {
        if (x.a >= nf) added += c.add_segment_pair(x.a - nf, x.b - nf);
        else if (is_triangle(w.plc.facets[x.a])) added += c.add_segment_contact(x.a, x.b - nf, x.b);
        continue;
      }
      if (!handled(x)) continue;
      if (!is_triangle(w.plc.facets[x.a]) || !is_triangle(w.plc.facets[x.b])) continue;
      added += c.add_contact(x.a, x.b);
    }
    if (added == 0) {
      find_self_intersections(w.plc, left);
      return Status::success();
    }
    report.crossing_facets += c.apply();
    Status st = tidy_after_rounding(w, grid);
    if (!st.ok()) return st;
  }
}

// The rounds, then the unused points go.
Status resolve_crossings(Work& w, RepairReport& report, std::vector<Intersection>& left) {
  const std::vector<Vec3> isolated = unused_points(w.plc);
  Status st = resolve_rounds(w, report, left);
  if (st.ok() && report.rounds > 0) {
    drop_unused_points(w, isolated);
    find_self_intersections(w.plc, left);
  }
  return st;
}

Status snap_to_grid(Work& w) { return snap_all(w, snap_grid(w.plc)); }

}  // namespace repair_steps
}  // namespace cdt3d
