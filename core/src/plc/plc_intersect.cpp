// Exact self-intersection check of a PLC (Si & Gärtner 2005 §2: the cells of
// a PLC may meet only in common cells).
//
// Method:
//  1. Every facet is triangulated once in its own plane (ear clipping on the
//     projection that drops one axis; exact orient2d_projected). Loops nested
//     in a loop are bridged into it as holes; a nested loop is triangulated
//     on its own as well unless a facet hole point marks its region.
//  2. Explicit segments lying inside a facet (TetGen's 2-vertex polygons)
//     are found first and become part of that facet: V(F) is the set of loop
//     vertices plus the endpoints of such segments, E(F) the set of loop edges
//     plus those segments.
//  3. A uniform grid over the bounding boxes yields the candidate pairs of
//     primitives (triangles and explicit segments); each pair is visited once,
//     in the first grid cell that both boxes overlap.
//  4. Two triangles t1 of F and t2 of G (F != G) meet properly exactly when
//     t1 ∩ t2 lies in the union of the shared vertices V(F) ∩ V(G) and the
//     shared edges E(F) ∩ E(G). This is decided by signs of orient3d (plane
//     sides, segment-through-triangle) and, for coplanar configurations, of
//     orient2d_projected. No point is ever constructed.
#include "plc_intersect.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <unordered_map>
#include <utility>

#include "geometry.hpp"
#include "predicates.hpp"

namespace cdt3d {
namespace {

using EdgeKey = uint64_t;  // geometry.hpp's edge_key

// Coordinates in one flat array: the predicates take const double*.
class Points {
 public:
  explicit Points(const Plc& plc) : xyz_(3 * plc.points.size()) {
    for (size_t i = 0; i < plc.points.size(); ++i) {
      xyz_[3 * i] = plc.points[i].x;
      xyz_[3 * i + 1] = plc.points[i].y;
      xyz_[3 * i + 2] = plc.points[i].z;
    }
    box_ = pred::box_bounds(xyz_.data(), plc.points.size());
  }
  const double* operator[](uint32_t v) const { return &xyz_[3 * static_cast<size_t>(v)]; }
  /// pred::orient3d of four of these points: the test takes no other point,
  /// so the static bound of their box decides first (pred::orient3d_in_box).
  int orient3d(const double* a, const double* b, const double* c, const double* d) const {
    return box_.orient3d > 0 ? pred::orient3d_in_box(a, b, c, d, box_)
                             : pred::orient3d(a, b, c, d);
  }

 private:
  std::vector<double> xyz_;
  pred::BoxBounds box_;
};

inline int o2(const double* a, const double* b, const double* c, int drop) {
  return pred::orient2d_projected(a, b, c, drop);
}

// Lexicographic order of projected points, in the (u, v) frame of
// orient2d_projected. Comparing coordinates is exact.
bool lex_less(const double* a, const double* b, int drop) {
  const int u = (drop + 1) % 3, v = (drop + 2) % 3;
  if (a[u] != b[u]) return a[u] < b[u];
  return a[v] < b[v];
}

// For x collinear with p != q: is x on the closed (open) segment pq? Along
// the line any axis on which p and q differ orders the points, so one exact
// coordinate comparison decides.
int differing_axis(const double* p, const double* q) {
  int k = 0;
  while (k < 2 && p[k] == q[k]) ++k;
  return k;
}
bool between_closed(const double* p, const double* q, const double* x) {
  const int k = differing_axis(p, q);
  return std::min(p[k], q[k]) <= x[k] && x[k] <= std::max(p[k], q[k]);
}
bool between_open(const double* p, const double* q, const double* x) {
  const int k = differing_axis(p, q);
  return std::min(p[k], q[k]) < x[k] && x[k] < std::max(p[k], q[k]);
}

bool mixed_signs(int a, int b, int c) {
  return (a < 0 || b < 0 || c < 0) && (a > 0 || b > 0 || c > 0);
}

// p in the closed triangle abc; all coplanar, abc not degenerate in the
// projection.
bool in_tri(const double* a, const double* b, const double* c, const double* p, int drop) {
  return !mixed_signs(o2(a, b, p, drop), o2(b, c, p, drop), o2(c, a, p, drop));
}

// Points of two groups a and b (vertex ids, one or two each), all on one
// line: true when the hulls of the groups are disjoint or meet only in a
// vertex of both. An axis on which the points are not all equal is an affine
// one-to-one function of the position on the line, so comparing that
// coordinate orders them exactly. False also when the hulls touch at two
// distinct vertices of equal coordinates (the general test decides those).
bool hulls_on_line_apart(const Points& P, const uint32_t* a, int na, const uint32_t* b, int nb) {
  int k = -1;
  for (int axis = 0; axis < 3 && k < 0; ++axis) {
    const double x = P[a[0]][axis];
    for (int i = 0; i < na && k < 0; ++i) k = P[a[i]][axis] != x ? axis : -1;
    for (int i = 0; i < nb && k < 0; ++i) k = P[b[i]][axis] != x ? axis : -1;
  }
  if (k < 0) return na == 1 && nb == 1 && a[0] == b[0];  // a single point
  // Lowest and highest vertex of a group along axis k.
  auto ends = [&](const uint32_t* g, int n, uint32_t& lo, uint32_t& hi) {
    lo = hi = g[0];
    if (n == 2) (P[g[1]][k] < P[g[0]][k] ? lo : hi) = g[1];
  };
  uint32_t alo, ahi, blo, bhi;
  ends(a, na, alo, ahi);
  ends(b, nb, blo, bhi);
  if (P[ahi][k] < P[blo][k] || P[bhi][k] < P[alo][k]) return true;
  if (P[ahi][k] == P[blo][k] && P[alo][k] < P[bhi][k]) return ahi == blo;
  if (P[bhi][k] == P[alo][k] && P[blo][k] < P[ahi][k]) return bhi == alo;
  return false;  // they share a stretch of the line, or a point inside one
}

// Closed segments ab and cd meet; all four points in one plane that the
// projection maps bijectively.
bool seg_seg_closed_2d(const double* a, const double* b, const double* c, const double* d,
                       int drop) {
  const int s1 = o2(a, b, c, drop), s2 = o2(a, b, d, drop);
  const int s3 = o2(c, d, a, drop), s4 = o2(c, d, b, drop);
  if (s1 == 0 && between_closed(a, b, c)) return true;
  if (s2 == 0 && between_closed(a, b, d)) return true;
  if (s3 == 0 && between_closed(c, d, a)) return true;
  if (s4 == 0 && between_closed(c, d, b)) return true;
  return s1 * s2 < 0 && s3 * s4 < 0;
}

using TriPts = std::array<const double*, 3>;

// Closed segment ab meets the closed triangle t, all coplanar.
bool seg_tri_closed_2d(const double* a, const double* b, const TriPts& t, int drop) {
  if (in_tri(t[0], t[1], t[2], a, drop) || in_tri(t[0], t[1], t[2], b, drop)) return true;
  for (int i = 0; i < 3; ++i) {
    if (seg_seg_closed_2d(a, b, t[i], t[(i + 1) % 3], drop)) return true;
  }
  return false;
}

// Closed segment vw meets the closed triangle t at a point other than v (all
// coplanar). When v is in t the intersection is a segment starting at v, so
// it suffices to know whether the direction v -> w points into t at v.
bool ray_beyond_2d(const double* v, const double* w, const TriPts& t, int drop) {
  const int e0 = o2(t[0], t[1], v, drop), e1 = o2(t[1], t[2], v, drop),
            e2 = o2(t[2], t[0], v, drop);
  if (mixed_signs(e0, e1, e2)) return seg_tri_closed_2d(v, w, t, drop);
  const int zeros = (e0 == 0) + (e1 == 0) + (e2 == 0);
  if (zeros == 0) return true;  // v interior: every direction enters t
  if (zeros == 1) {             // v inside edge (p, q): w must not be on the far side
    const int i = e0 == 0 ? 0 : (e1 == 0 ? 1 : 2);
    const double *p = t[i], *q = t[(i + 1) % 3], *r = t[(i + 2) % 3];
    const int s = o2(p, q, w, drop);
    return s == 0 || s == o2(p, q, r, drop);
  }
  // v is the corner where the two zero edges meet: w in the closed angle.
  const int k = e0 != 0 ? 2 : (e1 != 0 ? 0 : 1);
  const double *c = t[k], *a = t[(k + 1) % 3], *b = t[(k + 2) % 3];
  const int o = o2(c, a, b, drop);
  const int c1 = o2(c, a, w, drop), c2 = o2(c, b, w, drop);
  return (c1 == 0 || c1 == o) && (c2 == 0 || c2 == -o);
}

/// A triangle of a facet's triangulation.
struct Tri {
  uint32_t v[3];
  uint32_t facet;
  uint8_t drop;       ///< axis dropped by the projection (non-degenerate for this triangle)
  uint8_t loop_mask;  ///< bit i: edge (v[i], v[i+1]) is a loop edge of the facet
  int8_t level_axis;  ///< k when the three vertices have equal coordinate k, else -1
  int8_t up;          ///< then orient3d(v0, v1, v2, p) for p above the plane (+k)
};

// Exact normal-axis choice: the float normal (Newell's) only orders the axes
// by how well conditioned the projection is; an axis is accepted when the
// exact projected orientation of a non-collinear triple is nonzero, which is
// exactly when the projection maps the plane bijectively.
int choose_drop(const Plc& plc, const Points& P, const std::vector<uint32_t>& loop) {
  const size_t m = loop.size();
  for (int d : axes_by_normal(newell_normal(plc, loop))) {
    for (size_t j = 1; j + 1 < m; ++j) {
      if (o2(P[loop[0]], P[loop[j]], P[loop[j + 1]], d) != 0) return d;
    }
  }
  return 2;  // all collinear: check_plc rejects such facets
}

// Sign of the orientation of a simple loop in the projection: its
// lexicographically smallest vertex is convex.
int loop_orientation(const Points& P, const std::vector<uint32_t>& loop, int drop) {
  const size_t m = loop.size();
  size_t best = 0;
  for (size_t i = 1; i < m; ++i) {
    if (lex_less(P[loop[i]], P[loop[best]], drop)) best = i;
  }
  const int o = o2(P[loop[(best + m - 1) % m]], P[loop[best]], P[loop[(best + 1) % m]], drop);
  return o == 0 ? 1 : o;
}

// Point against a loop in the projection: 1 inside, 0 on its boundary, -1
// outside. Crossing rule with a ray towards +u; the side of each crossing is
// an orientation sign, so nothing is rounded.
int point_in_loop(const Points& P, const double* p, const std::vector<uint32_t>& loop, int drop) {
  const int vax = (drop + 2) % 3;
  bool inside = false;
  const size_t m = loop.size();
  for (size_t i = 0; i < m; ++i) {
    const double* a = P[loop[i]];
    const double* b = P[loop[(i + 1) % m]];
    const int o = o2(a, b, p, drop);
    if (o == 0 && between_closed(a, b, p)) return 0;
    const bool ua = a[vax] > p[vax], ub = b[vax] > p[vax];
    if (ua != ub && ((ub && o > 0) || (!ub && o < 0))) inside = !inside;
  }
  return inside ? 1 : -1;
}

// Interior of the polygon (region on the left of prev -> v -> next) near v
// contains the open direction v -> w.
bool in_open_cone(const double* prev, const double* v, const double* next, const double* w,
                  int drop) {
  const int o = o2(prev, v, next, drop);
  const int l1 = o2(v, next, w, drop), l2 = o2(prev, v, w, drop);
  if (o > 0) return l1 > 0 && l2 > 0;
  if (o < 0) return l1 > 0 || l2 > 0;
  if (!between_open(prev, next, v)) return false;  // a spike: never bridge through it
  return l1 > 0;
}

// Ear clipping of a (weakly) simple polygon oriented positively in the
// projection. An ear is a strictly convex corner whose closed triangle holds
// no other polygon vertex (vertices with the ear's ids are the same points,
// e.g. both ends of a bridge). Returns false if it had to fall back to a fan
// (self-intersecting input loops).
bool ear_clip(const Points& P, const std::vector<uint32_t>& poly, int drop,
              std::vector<std::array<uint32_t, 3>>& out) {
  const size_t n = poly.size();
  if (n < 3) return false;
  std::vector<size_t> prv(n), nxt(n);
  for (size_t i = 0; i < n; ++i) {
    prv[i] = (i + n - 1) % n;
    nxt[i] = (i + 1) % n;
  }
  auto is_ear = [&](size_t a, size_t i, size_t c) {
    const uint32_t ia = poly[a], ib = poly[i], ic = poly[c];
    if (o2(P[ia], P[ib], P[ic], drop) <= 0) return false;
    for (size_t j = nxt[c]; j != a; j = nxt[j]) {
      const uint32_t x = poly[j];
      if (x == ia || x == ib || x == ic) continue;
      if (in_tri(P[ia], P[ib], P[ic], P[x], drop)) return false;
    }
    return true;
  };
  size_t remaining = n, i = 0, misses = 0;
  bool ok = true;
  while (remaining > 3) {
    const size_t a = prv[i], c = nxt[i];
    if (is_ear(a, i, c)) {
      out.push_back({poly[a], poly[i], poly[c]});
      nxt[a] = c;
      prv[c] = a;
      --remaining;
      i = a;
      misses = 0;
    } else {
      i = c;
      if (++misses > remaining) {
        // No ear: the loop is not simple. Cover the rest by a fan of its
        // non-degenerate triangles so the facet is still checked.
        ok = false;
        for (size_t j = nxt[i]; nxt[j] != i; j = nxt[j]) {
          const uint32_t x = poly[i], y = poly[j], z = poly[nxt[j]];
          const int o = o2(P[x], P[y], P[z], drop);
          if (o > 0) out.push_back({x, y, z});
          if (o < 0) out.push_back({x, z, y});
        }
        return ok;
      }
    }
  }
  const size_t a = prv[i], c = nxt[i];
  if (o2(P[poly[a]], P[poly[i]], P[poly[c]], drop) > 0) out.push_back({poly[a], poly[i], poly[c]});
  return ok;
}

// Segment (m, c) of a candidate bridge hits edge (x, y) somewhere other than
// at a shared endpoint.
bool bridge_blocked(const Points& P, uint32_t m, uint32_t c, uint32_t x, uint32_t y, int drop) {
  if ((x == m && y == c) || (x == c && y == m)) return true;
  uint32_t z = kNone, o = kNone, s = kNone;
  if (x == m || x == c) z = x, o = y;
  if (y == m || y == c) z = y, o = x;
  if (z != kNone) {
    s = z == m ? c : m;
    // Sharing an endpoint, they overlap only when collinear and on the same side.
    return o2(P[z], P[s], P[o], drop) == 0 && !between_open(P[o], P[s], P[z]);
  }
  return seg_seg_closed_2d(P[m], P[c], P[x], P[y], drop);
}

// Splices the hole loop `child` (oriented negatively) into `merged` (the
// outer loop, oriented positively, with the holes bridged so far) through a
// segment from a hole vertex to a merged vertex that touches no edge.
// `blockers` lists every loop edge still relevant (merged and unmerged).
bool bridge_hole(const Points& P, std::vector<uint32_t>& merged, const std::vector<uint32_t>& child,
                 const std::vector<std::pair<uint32_t, uint32_t>>& blockers, int drop) {
  const size_t nc = child.size(), nm = merged.size();
  size_t start = 0;
  for (size_t i = 1; i < nc; ++i) {
    if (lex_less(P[child[start]], P[child[i]], drop)) start = i;
  }
  for (size_t k = 0; k < nc; ++k) {
    const size_t ci = (start + k) % nc;
    const uint32_t c = child[ci];
    for (size_t mi = 0; mi < nm; ++mi) {
      const uint32_t m = merged[mi];
      if (m == c) continue;
      if (!in_open_cone(P[merged[(mi + nm - 1) % nm]], P[m], P[merged[(mi + 1) % nm]], P[c], drop))
        continue;
      if (!in_open_cone(P[child[(ci + nc - 1) % nc]], P[c], P[child[(ci + 1) % nc]], P[m], drop))
        continue;
      bool blocked = false;
      for (size_t e = 0; e < merged.size() && !blocked; ++e) {
        blocked = bridge_blocked(P, m, c, merged[e], merged[(e + 1) % nm], drop);
      }
      for (size_t e = 0; e < blockers.size() && !blocked; ++e) {
        blocked = bridge_blocked(P, m, c, blockers[e].first, blockers[e].second, drop);
      }
      if (blocked) continue;
      std::vector<uint32_t> out(merged.begin(), merged.begin() + static_cast<ptrdiff_t>(mi) + 1);
      for (size_t j = 0; j <= nc; ++j) out.push_back(child[(ci + j) % nc]);
      out.insert(out.end(), merged.begin() + static_cast<ptrdiff_t>(mi), merged.end());
      merged.swap(out);
      return true;
    }
  }
  return false;
}

// Triangulates one facet's region (union of loop interiors minus the areas
// of its hole points). Returns false when a fallback was needed.
bool triangulate_facet(const Points& P, const Facet& f, int drop,
                       std::vector<std::array<uint32_t, 3>>& out) {
  const size_t nl = f.loops.size();
  if (nl == 1 && f.holes.empty()) {
    std::vector<uint32_t> poly = f.loops[0];
    if (loop_orientation(P, poly, drop) < 0) std::reverse(poly.begin(), poly.end());
    return ear_clip(P, poly, drop, out);
  }
  // Nesting: loop j is inside loop i when a vertex of j not on i's boundary
  // is inside i.
  std::vector<int> depth(nl, 0), parent(nl, -1);
  std::vector<std::vector<char>> inside(nl, std::vector<char>(nl, 0));
  for (size_t i = 0; i < nl; ++i) {
    for (size_t j = 0; j < nl; ++j) {
      if (i == j) continue;
      for (uint32_t v : f.loops[j]) {
        const int r = point_in_loop(P, P[v], f.loops[i], drop);
        if (r != 0) {
          inside[i][j] = r > 0;
          break;
        }
      }
      depth[j] += inside[i][j];
    }
  }
  for (size_t j = 0; j < nl; ++j) {
    for (size_t i = 0; i < nl; ++i) {
      if (inside[i][j] && (parent[j] < 0 || depth[i] > depth[parent[j]]))
        parent[j] = static_cast<int>(i);
    }
  }
  // A hole point removes the region of the innermost loop around it.
  std::vector<char> removed(nl, 0);
  for (const Vec3& h : f.holes) {
    const double hp[3] = {h.x, h.y, h.z};
    int best = -1;
    for (size_t i = 0; i < nl; ++i) {
      if (point_in_loop(P, hp, f.loops[i], drop) > 0 && (best < 0 || depth[i] > depth[best]))
        best = static_cast<int>(i);
    }
    if (best >= 0) removed[best] = 1;
  }
  bool ok = true;
  for (size_t i = 0; i < nl; ++i) {
    if (removed[i]) continue;
    std::vector<uint32_t> merged = f.loops[i];
    if (loop_orientation(P, merged, drop) < 0) std::reverse(merged.begin(), merged.end());
    std::vector<std::vector<uint32_t>> children;
    for (size_t j = 0; j < nl; ++j) {
      if (parent[j] != static_cast<int>(i)) continue;
      children.push_back(f.loops[j]);
      if (loop_orientation(P, children.back(), drop) > 0)
        std::reverse(children.back().begin(), children.back().end());
    }
    // Children by decreasing lexicographic maximum (deterministic).
    auto lexmax = [&](const std::vector<uint32_t>& l) {
      uint32_t b = l[0];
      for (uint32_t v : l) {
        if (lex_less(P[b], P[v], drop)) b = v;
      }
      return b;
    };
    std::stable_sort(children.begin(), children.end(),
                     [&](const std::vector<uint32_t>& a, const std::vector<uint32_t>& b) {
                       return lex_less(P[lexmax(b)], P[lexmax(a)], drop);
                     });
    for (size_t k = 0; k < children.size(); ++k) {
      std::vector<std::pair<uint32_t, uint32_t>> blockers;
      for (size_t j = k; j < children.size(); ++j) {
        const auto& l = children[j];
        for (size_t e = 0; e < l.size(); ++e) blockers.emplace_back(l[e], l[(e + 1) % l.size()]);
      }
      if (!bridge_hole(P, merged, children[k], blockers, drop)) ok = false;
    }
    if (!ear_clip(P, merged, drop, out)) ok = false;
  }
  return ok;
}

struct Box {
  double lo[3], hi[3];
};

bool boxes_overlap(const Box& a, const Box& b) {
  for (int k = 0; k < 3; ++k) {
    if (a.hi[k] < b.lo[k] || b.hi[k] < a.lo[k]) return false;
  }
  return true;
}

class Checker {
 public:
  Checker(const Plc& plc, size_t limit) : plc_(plc), P_(plc), limit_(limit) {}

  void run(std::vector<Intersection>& out);

 private:
  void build_triangles();
  void set_level(Tri& t) const;
  void build_grid();
  void find_embedded_segments();
  void visit_pairs();
  void report(uint32_t a, uint32_t b, IntersectionKind kind);

  bool in_range(const std::vector<uint32_t>& off, const std::vector<uint64_t>& data, uint32_t f,
                uint64_t x) const {
    return std::binary_search(data.begin() + off[f], data.begin() + off[f + 1], x);
  }
  // The one triangle of facet f when f is a plain triangle (one loop of
  // three vertices, no holes), else null.
  const Tri* plain_triangle(uint32_t f) const {
    return first_tri_[f] == kNone ? nullptr : &tris_[first_tri_[f]];
  }
  bool in_v(uint32_t f, uint32_t x) const {
    const Tri* t = plain_triangle(f);
    return (t ? vertex_of(*t, x) : in_range(fv_off_, fv_, f, x)) ||
           (!emb_v_.empty() &&
            std::binary_search(emb_v_.begin(), emb_v_.end(), std::make_pair(f, EdgeKey(x))));
  }
  bool in_e(uint32_t f, EdgeKey k) const {
    const Tri* t = plain_triangle(f);
    return (t ? edge_of(*t, k) : in_range(fe_off_, fe_, f, k)) ||
           (!emb_e_.empty() &&
            std::binary_search(emb_e_.begin(), emb_e_.end(), std::make_pair(f, k)));
  }
  bool embedded(uint32_t s, uint32_t f) const {
    return std::binary_search(emb_sf_.begin(), emb_sf_.end(), std::make_pair(s, f));
  }
  TriPts pts(const Tri& t) const { return {P_[t.v[0]], P_[t.v[1]], P_[t.v[2]]}; }
  int side_of(const Tri& t, const double* p) const;
  bool vertex_of(const Tri& t, uint32_t x) const {
    return t.v[0] == x || t.v[1] == x || t.v[2] == x;
  }
  static bool edge_of(const Tri& t, EdgeKey k) {
    return edge_key(t.v[0], t.v[1]) == k || edge_key(t.v[1], t.v[2]) == k ||
           edge_key(t.v[2], t.v[0]) == k;
  }
  std::array<int32_t, 3> cell_of(const double* corner) const;

  bool seg_tri_beyond(uint32_t ia, uint32_t ib, const Tri& t, uint32_t v) const;
  bool tri_tri_beyond(const Tri& t1, const Tri& t2, uint32_t v) const;
  int test_tri_tri(const Tri& t1, const Tri& t2) const;
  bool separated_in_plane(const Tri& t1, const Tri& t2) const;
  bool meet_on_line_properly(const Tri& t1, const Tri& t2, const int* s1, const int* s2) const;
  int classify_tri_tri(const Tri& t1, const Tri& t2, const int* s1, const int* s2,
                       bool coplanar) const;
  int test_seg_tri(uint32_t s, const Tri& t) const;
  int test_seg_seg(uint32_t a, uint32_t b, uint32_t c, uint32_t d) const;

  const Plc& plc_;
  Points P_;
  size_t limit_;
  std::vector<Tri> tris_;
  // Per facet, sorted: loop vertices (fv_) and loop edges (fe_), CSR; empty
  // for a plain triangle, whose vertices and edges are those of its one
  // triangle (first_tri_; kNone for other facets): on a triangle surface
  // that spares 48 bytes a facet.
  std::vector<uint32_t> fv_off_, fe_off_, first_tri_;
  std::vector<uint64_t> fv_, fe_;
  // Explicit segments lying inside facets: (segment, facet) and what they add
  // to V(F) and E(F) as (facet, id / key). Sorted.
  std::vector<std::pair<uint32_t, uint32_t>> emb_sf_;
  std::vector<std::pair<uint32_t, uint64_t>> emb_v_, emb_e_;
  // Primitives: triangles 0..T-1, then explicit segments.
  std::vector<Box> box_;
  int32_t dims_[3] = {1, 1, 1};
  double origin_[3] = {0, 0, 0}, inv_ = 1;
  std::vector<uint32_t> cell_start_, cell_items_;
  // Results.
  std::vector<Intersection> found_;
  std::unordered_map<uint64_t, size_t> index_;  ///< pair -> position in found_ (lookup only)
  bool full_ = false;
};

void Checker::build_triangles() {
  const size_t nf = plc_.facets.size();
  fv_off_.assign(nf + 1, 0);
  fe_off_.assign(nf + 1, 0);
  first_tri_.assign(nf, kNone);
  std::vector<std::array<uint32_t, 3>> local;
  std::vector<uint64_t> scratch;
  for (size_t fi = 0; fi < nf; ++fi) {
    const Facet& f = plc_.facets[fi];
    const bool plain = f.loops.size() == 1 && f.loops[0].size() == 3 && f.holes.empty();
    size_t v0 = fv_.size(), e0 = fe_.size();
    for (const auto& loop : f.loops) {
      if (plain) break;
      for (size_t i = 0; i < loop.size(); ++i) {
        fv_.push_back(loop[i]);
        fe_.push_back(edge_key(loop[i], loop[(i + 1) % loop.size()]));
      }
    }
    std::sort(fv_.begin() + static_cast<ptrdiff_t>(v0), fv_.end());
    fv_.erase(std::unique(fv_.begin() + static_cast<ptrdiff_t>(v0), fv_.end()), fv_.end());
    std::sort(fe_.begin() + static_cast<ptrdiff_t>(e0), fe_.end());
    fe_.erase(std::unique(fe_.begin() + static_cast<ptrdiff_t>(e0), fe_.end()), fe_.end());
    fv_off_[fi + 1] = static_cast<uint32_t>(fv_.size());
    fe_off_[fi + 1] = static_cast<uint32_t>(fe_.size());
    if (f.loops.empty() || f.loops[0].size() < 3) continue;
    const int drop = choose_drop(plc_, P_, f.loops[0]);
    local.clear();
    if (plain) {
      first_tri_[fi] = static_cast<uint32_t>(tris_.size());
      local.push_back({f.loops[0][0], f.loops[0][1], f.loops[0][2]});
    } else {
      triangulate_facet(P_, f, drop, local);
    }
    for (const auto& t : local) {
      Tri tri;
      uint8_t mask = 0;
      for (int i = 0; i < 3; ++i) {
        tri.v[i] = t[i];
        if (plain ||
            in_range(fe_off_, fe_, static_cast<uint32_t>(fi), edge_key(t[i], t[(i + 1) % 3])))
          mask |= static_cast<uint8_t>(1u << i);
      }
      tri.facet = static_cast<uint32_t>(fi);
      tri.drop = static_cast<uint8_t>(drop);
      tri.loop_mask = mask;
      set_level(tri);
      tris_.push_back(tri);
    }
  }
}

// The grid cell holding a box corner (clamped to the grid).
std::array<int32_t, 3> Checker::cell_of(const double* corner) const {
  std::array<int32_t, 3> c;
  for (int k = 0; k < 3; ++k) {
    const double x = std::floor((corner[k] - origin_[k]) * inv_);
    c[k] = static_cast<int32_t>(std::min(std::max(x, 0.0), static_cast<double>(dims_[k] - 1)));
  }
  return c;
}

void Checker::build_grid() {
  const size_t nt = tris_.size(), ns = plc_.segments.size(), n = nt + ns;
  box_.resize(n);
  Box all{{HUGE_VAL, HUGE_VAL, HUGE_VAL}, {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL}};
  double extent_sum = 0;
  for (size_t i = 0; i < n; ++i) {
    Box& b = box_[i];
    const uint32_t* v = i < nt ? tris_[i].v : plc_.segments[i - nt].data();
    const int nv = i < nt ? 3 : 2;
    for (int k = 0; k < 3; ++k) {
      b.lo[k] = b.hi[k] = P_[v[0]][k];
      for (int j = 1; j < nv; ++j) {
        b.lo[k] = std::min(b.lo[k], P_[v[j]][k]);
        b.hi[k] = std::max(b.hi[k], P_[v[j]][k]);
      }
      all.lo[k] = std::min(all.lo[k], b.lo[k]);
      all.hi[k] = std::max(all.hi[k], b.hi[k]);
    }
    extent_sum += std::max({b.hi[0] - b.lo[0], b.hi[1] - b.lo[1], b.hi[2] - b.lo[2]});
  }
  if (n == 0) return;
  // Cell size: about twice the mean box extent, so a box spans few cells,
  // enlarged until the dense grid has at most ~4 cells per primitive. The
  // grid only buckets boxes; which pairs are tested is decided by exact box
  // comparisons, and the bucketing below is monotonic in each coordinate, so
  // overlapping boxes always share a cell.
  const double span =
      std::max({all.hi[0] - all.lo[0], all.hi[1] - all.lo[1], all.hi[2] - all.lo[2]});
  double h = 2 * extent_sum / static_cast<double>(n);
  if (!(h > 0)) h = span > 0 ? span / std::cbrt(static_cast<double>(n)) : 1;
  const double max_cells = 4.0 * static_cast<double>(n) + 64;
  for (;;) {
    double prod = 1;
    for (int k = 0; k < 3; ++k) prod *= std::floor((all.hi[k] - all.lo[k]) / h) + 1;
    if (prod <= max_cells) break;
    h *= 1.25;
  }
  for (int k = 0; k < 3; ++k) {
    origin_[k] = all.lo[k];
    dims_[k] = static_cast<int32_t>(std::floor((all.hi[k] - all.lo[k]) / h)) + 1;
  }
  inv_ = 1 / h;
  const size_t ncell = static_cast<size_t>(dims_[0]) * dims_[1] * dims_[2];
  cell_start_.assign(ncell + 1, 0);
  // A box's cells, computed again where needed rather than stored (24
  // bytes a primitive on models of millions of triangles).
  auto for_cells = [&](size_t i, auto&& fn) {
    const std::array<int32_t, 3> lo = cell_of(box_[i].lo), hi = cell_of(box_[i].hi);
    for (int32_t z = lo[2]; z <= hi[2]; ++z)
      for (int32_t y = lo[1]; y <= hi[1]; ++y)
        for (int32_t x = lo[0]; x <= hi[0]; ++x)
          fn((static_cast<size_t>(z) * dims_[1] + y) * dims_[0] + x);
  };
  for (size_t i = 0; i < n; ++i) for_cells(i, [&](size_t id) { ++cell_start_[id + 1]; });
  for (size_t i = 0; i < ncell; ++i) cell_start_[i + 1] += cell_start_[i];
  cell_items_.resize(cell_start_[ncell]);
  std::vector<uint32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (size_t i = 0; i < n; ++i)
    for_cells(i, [&](size_t id) { cell_items_[fill[id]++] = static_cast<uint32_t>(i); });
}

// An explicit segment is part of facet F when both endpoints lie in the
// closed region of F (then the whole segment does, unless it leaves F across
// a loop edge or through a loop vertex, which the loop-edge checks in
// test_seg_tri report).
void Checker::find_embedded_segments() {
  const size_t nt = tris_.size();
  std::vector<uint32_t> fa, fb;
  auto facets_holding = [&](uint32_t v, std::vector<uint32_t>& facets) {
    facets.clear();
    const double* p = P_[v];
    int32_t c[3];
    for (int k = 0; k < 3; ++k) {
      const double x = std::floor((p[k] - origin_[k]) * inv_);
      c[k] = static_cast<int32_t>(std::min(std::max(x, 0.0), static_cast<double>(dims_[k] - 1)));
    }
    const size_t id = (static_cast<size_t>(c[2]) * dims_[1] + c[1]) * dims_[0] + c[0];
    for (uint32_t j = cell_start_[id]; j < cell_start_[id + 1]; ++j) {
      const uint32_t i = cell_items_[j];
      if (i >= nt) continue;
      const Tri& t = tris_[i];
      const Box& b = box_[i];
      bool in_box = true;
      for (int k = 0; k < 3; ++k) in_box = in_box && b.lo[k] <= p[k] && p[k] <= b.hi[k];
      if (!in_box) continue;
      const TriPts q = pts(t);
      if (vertex_of(t, v) ||
          (side_of(t, p) == 0 && in_tri(q[0], q[1], q[2], p, t.drop)))
        facets.push_back(t.facet);
    }
    std::sort(facets.begin(), facets.end());
    facets.erase(std::unique(facets.begin(), facets.end()), facets.end());
  };
  for (size_t s = 0; s < plc_.segments.size(); ++s) {
    const uint32_t a = plc_.segments[s][0], b = plc_.segments[s][1];
    facets_holding(a, fa);
    if (fa.empty()) continue;
    facets_holding(b, fb);
    for (uint32_t f : fa) {
      if (!std::binary_search(fb.begin(), fb.end(), f)) continue;
      emb_sf_.emplace_back(static_cast<uint32_t>(s), f);
      emb_v_.emplace_back(f, a);
      emb_v_.emplace_back(f, b);
      emb_e_.emplace_back(f, edge_key(a, b));
    }
  }
  for (auto* v : {&emb_v_, &emb_e_}) {
    std::sort(v->begin(), v->end());
    v->erase(std::unique(v->begin(), v->end()), v->end());
  }
  std::sort(emb_sf_.begin(), emb_sf_.end());
}

// A triangle in a plane x_k = c (most triangles of CAD and voxel models):
// orient3d of its vertices and p is then (c - p_k) times their orientation
// in the projection that drops k, up to a fixed sign (orient3d is negative
// for a point above a triangle counterclockwise in that projection), so its
// sign is a comparison. Every other point of that plane is a zero of the
// floating-point filter, which would take the predicate's slow path.
void Checker::set_level(Tri& t) const {
  t.level_axis = -1;
  t.up = 0;
  for (int k = 0; k < 3 && t.level_axis < 0; ++k) {
    if (P_[t.v[0]][k] == P_[t.v[1]][k] && P_[t.v[0]][k] == P_[t.v[2]][k]) {
      t.level_axis = static_cast<int8_t>(k);
      t.up = static_cast<int8_t>(-o2(P_[t.v[0]], P_[t.v[1]], P_[t.v[2]], k));
    }
  }
}

// pred::orient3d(v0, v1, v2, p) of triangle t (set_level's shortcut for a
// triangle in an axis-parallel plane).
int Checker::side_of(const Tri& t, const double* p) const {
  if (t.level_axis >= 0) {
    const double c = P_[t.v[0]][t.level_axis], x = p[t.level_axis];
    return x > c ? t.up : (x < c ? -t.up : 0);
  }
  return P_.orient3d(P_[t.v[0]], P_[t.v[1]], P_[t.v[2]], p);
}

// Closed segment ab meets closed triangle t at a point other than vertex v
// (kNone: at any point). A segment not in the plane of t meets it in at most
// one point: an endpoint on the plane, or the crossing point, which lies in
// t exactly when the line ab passes the three edges of t on the same side
// (orient3d of ab with each edge).
bool Checker::seg_tri_beyond(uint32_t ia, uint32_t ib, const Tri& t, uint32_t v) const {
  const TriPts q = pts(t);
  const double *a = P_[ia], *b = P_[ib];
  const int sa = vertex_of(t, ia) ? 0 : side_of(t, a);
  const int sb = vertex_of(t, ib) ? 0 : side_of(t, b);
  if (sa * sb > 0) return false;
  if (sa == 0 && sb == 0) {
    if (v == kNone) return seg_tri_closed_2d(a, b, q, t.drop);
    if (v == ia) return ray_beyond_2d(a, b, q, t.drop);
    if (v == ib) return ray_beyond_2d(b, a, q, t.drop);
    const double* pv = P_[v];
    if (pred::collinear3d(a, b, pv) && between_open(a, b, pv))
      return ray_beyond_2d(pv, a, q, t.drop) || ray_beyond_2d(pv, b, q, t.drop);
    return seg_tri_closed_2d(a, b, q, t.drop);
  }
  if (sa == 0) return ia != v && in_tri(q[0], q[1], q[2], a, t.drop);
  if (sb == 0) return ib != v && in_tri(q[0], q[1], q[2], b, t.drop);
  const int o0 = P_.orient3d(a, b, q[0], q[1]);
  const int o1 = P_.orient3d(a, b, q[1], q[2]);
  const int o2v = P_.orient3d(a, b, q[2], q[0]);
  if (mixed_signs(o0, o1, o2v)) return false;
  if (v != kNone) {
    // The single crossing point is v exactly when v is on the open segment
    // and on the plane of t.
    const double* pv = P_[v];
    if ((vertex_of(t, v) || side_of(t, pv) == 0) &&
        pred::collinear3d(a, b, pv) && between_open(a, b, pv))
      return false;
  }
  return true;
}

// t1 ∩ t2 contains a point other than v. The intersection is convex; if it
// has a point other than v it has one on its relative boundary, which lies
// on an edge of t1 or t2 and in the other triangle.
bool Checker::tri_tri_beyond(const Tri& t1, const Tri& t2, uint32_t v) const {
  for (int i = 0; i < 3; ++i) {
    if (seg_tri_beyond(t1.v[i], t1.v[(i + 1) % 3], t2, v)) return true;
  }
  for (int i = 0; i < 3; ++i) {
    if (seg_tri_beyond(t2.v[i], t2.v[(i + 1) % 3], t1, v)) return true;
  }
  return false;
}

// Kind of an improper triangle pair. Coplanar: overlap when no edge line of
// either triangle weakly separates them (separating axis for convex
// polygons), else they only touch. Otherwise touching when one triangle lies
// in a closed half-space of the other's plane.
int Checker::classify_tri_tri(const Tri& t1, const Tri& t2, const int* s1, const int* s2,
                              bool coplanar) const {
  if (coplanar) {
    const TriPts q1 = pts(t1), q2 = pts(t2);
    const int d = t1.drop;
    for (int pass = 0; pass < 2; ++pass) {
      const TriPts& a = pass == 0 ? q1 : q2;
      const TriPts& b = pass == 0 ? q2 : q1;
      for (int i = 0; i < 3; ++i) {
        const int ref = o2(a[i], a[(i + 1) % 3], a[(i + 2) % 3], d);
        bool separates = true;
        for (int j = 0; j < 3 && separates; ++j) {
          const int s = o2(a[i], a[(i + 1) % 3], b[j], d);
          separates = s == 0 || s == -ref;
        }
        if (separates) return static_cast<int>(IntersectionKind::VertexInFacet);
      }
    }
    return static_cast<int>(IntersectionKind::CoplanarOverlap);
  }
  if (!mixed_signs(s1[0], s1[1], s1[2]) || !mixed_signs(s2[0], s2[1], s2[2]))
    return static_cast<int>(IntersectionKind::VertexInFacet);
  return static_cast<int>(IntersectionKind::Cross);
}

// Coplanar triangles, each proper in the projection, of which an edge line of
// one has the other in the closed half-plane beyond it: then t1 ∩ t2 lies
// in that edge and in the other's vertices on the line, and the pair meets
// properly when those meet at most in a vertex the two share
// (hulls_on_line_apart): the separating-axis test for convex polygons (as in
// classify_tri_tri) with touching allowed only at shared vertices. The
// general test of test_tri_tri finds the same at several times the cost;
// neighbouring triangles of one plane (grids of CAD and voxel models) nearly
// all end here.
bool Checker::separated_in_plane(const Tri& t1, const Tri& t2) const {
  const int d = t1.drop;
  const TriPts q1 = pts(t1), q2 = pts(t2);
  const int o1 = o2(q1[0], q1[1], q1[2], d), o2v = o2(q2[0], q2[1], q2[2], d);
  if (o1 == 0 || o2v == 0) return false;
  for (int pass = 0; pass < 2; ++pass) {
    const Tri& ta = pass == 0 ? t1 : t2;
    const Tri& tb = pass == 0 ? t2 : t1;
    const TriPts& a = pass == 0 ? q1 : q2;
    const TriPts& b = pass == 0 ? q2 : q1;
    const int inside = pass == 0 ? o1 : o2v;  // side of each edge line that holds a
    for (int i = 0; i < 3; ++i) {
      uint32_t on[3];  // tb's vertices on the edge line
      int n_on = 0;
      bool beyond = true;
      for (int j = 0; j < 3 && beyond; ++j) {
        const int s = o2(a[i], a[(i + 1) % 3], b[j], d);
        if (s == 0) on[n_on++] = tb.v[j];
        beyond = s == -inside || s == 0;
      }
      const uint32_t edge[2] = {ta.v[i], ta.v[(i + 1) % 3]};
      if (beyond && (n_on == 0 || (n_on < 3 && hulls_on_line_apart(P_, edge, 2, on, n_on))))
        return true;
    }
  }
  return false;
}

// Triangles in distinct planes, neither strictly crossing the other's plane
// (s1, s2: the sides of their vertices, shared ones 0): t1 meets the plane of
// t2 exactly in the vertex or edge of t1 spanned by its vertices on it,
// likewise t2, both on the line where the planes meet, and t1 ∩ t2 is the
// intersection of the two. True when that is empty or a shared vertex (which
// decides most pairs along the sharp edges of CAD models); false when the
// general test must decide.
bool Checker::meet_on_line_properly(const Tri& t1, const Tri& t2, const int* s1,
                                    const int* s2) const {
  if (mixed_signs(s1[0], s1[1], s1[2]) || mixed_signs(s2[0], s2[1], s2[2])) return false;
  uint32_t f1[3], f2[3];
  int n1 = 0, n2 = 0;
  for (int i = 0; i < 3; ++i) {
    if (s1[i] == 0) f1[n1++] = t1.v[i];
    if (s2[i] == 0) f2[n2++] = t2.v[i];
  }
  if (n1 == 0 || n2 == 0) return true;  // one triangle misses the other's plane
  if (n1 == 3 || n2 == 3) return false;  // degenerate triangle
  return hulls_on_line_apart(P_, f1, n1, f2, n2);
}

// 0 when triangles t1 (facet F) and t2 (facet G != F) meet properly, else the
// kind. See the file comment for the rule.
int Checker::test_tri_tri(const Tri& t1, const Tri& t2) const {
  const uint32_t F = t1.facet, G = t2.facet;
  const TriPts q1 = pts(t1), q2 = pts(t2);
  bool sh1[3], sh2[3];  // vertex is also a vertex of the other triangle
  int nc = 0;
  for (int i = 0; i < 3; ++i) {
    sh1[i] = vertex_of(t2, t1.v[i]);
    sh2[i] = vertex_of(t1, t2.v[i]);
    nc += sh2[i];
  }
  // When the unshared vertices of one triangle are strictly on one side of
  // the other's plane, the triangles meet at most in their shared vertices or
  // shared edge; that decides almost every neighbouring pair of a mesh.
  auto one_side = [](const int* s, const bool* sh) {
    int pos = 0, neg = 0, free = 0;
    for (int i = 0; i < 3; ++i) {
      if (sh[i]) continue;
      ++free;
      pos += s[i] > 0;
      neg += s[i] < 0;
    }
    return free > 0 && (pos == free || neg == free);
  };
  auto shared_verdict = [&]() {
    if (nc < 2) return 0;
    uint32_t u = kNone, w = kNone;
    for (int i = 0; i < 3; ++i) {
      if (!sh2[i]) continue;
      (u == kNone ? u : w) = t2.v[i];
    }
    const EdgeKey k = edge_key(u, w);
    return in_e(F, k) && in_e(G, k) ? 0 : static_cast<int>(IntersectionKind::VertexInFacet);
  };
  int s2[3], s1[3];
  for (int i = 0; i < 3; ++i) s2[i] = sh2[i] ? 0 : side_of(t1, q2[i]);
  if (one_side(s2, sh2)) return shared_verdict();
  for (int i = 0; i < 3; ++i) s1[i] = sh1[i] ? 0 : side_of(t2, q1[i]);
  if (one_side(s1, sh1)) return shared_verdict();

  const bool coplanar = s2[0] == 0 && s2[1] == 0 && s2[2] == 0;
  if (coplanar) {
    // Sharing an allowed edge: proper iff the third vertices are on opposite
    // sides of it.
    if (nc == 2) {
      int i1 = 0, i2 = 0;
      while (sh1[i1]) ++i1;
      while (sh2[i2]) ++i2;
      const uint32_t u = t1.v[(i1 + 1) % 3], w = t1.v[(i1 + 2) % 3];
      const EdgeKey k = edge_key(u, w);
      if (in_e(F, k) && in_e(G, k)) {
        const int a = o2(P_[u], P_[w], q1[i1], t1.drop), b = o2(P_[u], P_[w], q2[i2], t1.drop);
        if (a * b < 0) return 0;
        return static_cast<int>(IntersectionKind::CoplanarOverlap);
      }
    } else if (separated_in_plane(t1, t2)) {
      return 0;
    }
  } else {
    // An allowed edge on the line where the planes meet contains the whole
    // intersection (t1 ∩ t2 lies in that line and in each triangle).
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3;
      if (s2[i] == 0 && s2[j] == 0) {
        const EdgeKey k = edge_key(t2.v[i], t2.v[j]);
        if (in_e(F, k) && in_e(G, k)) return 0;
      }
      if (s1[i] == 0 && s1[j] == 0) {
        const EdgeKey k = edge_key(t1.v[i], t1.v[j]);
        if (in_e(F, k) && in_e(G, k)) return 0;
      }
    }
    if (meet_on_line_properly(t1, t2, s1, s2)) return 0;
  }
  // Otherwise the intersection may contain at most one point, an allowed
  // vertex (in V(F) ∩ V(G)) that lies in both triangles.
  uint32_t allowed[6];
  int na = 0;
  for (int i = 0; i < 3; ++i) {
    const uint32_t x = t1.v[i];
    if (sh1[i] || (s1[i] == 0 && in_v(G, x) && in_tri(q2[0], q2[1], q2[2], q1[i], t2.drop)))
      allowed[na++] = x;
  }
  for (int i = 0; i < 3; ++i) {
    const uint32_t x = t2.v[i];
    if (!sh2[i] && s2[i] == 0 && in_v(F, x) && in_tri(q1[0], q1[1], q1[2], q2[i], t1.drop))
      allowed[na++] = x;
  }
  if (na >= 2 || tri_tri_beyond(t1, t2, na == 1 ? allowed[0] : kNone))
    return classify_tri_tri(t1, t2, s1, s2, coplanar);
  return 0;
}

// Explicit segments s = (a, b) and (c, d), or a loop edge: 0 when they meet
// at most in a shared endpoint. Segments meet only when coplanar.
int Checker::test_seg_seg(uint32_t a, uint32_t b, uint32_t c, uint32_t d) const {
  if (edge_key(a, b) == edge_key(c, d)) return 0;
  const double *pa = P_[a], *pb = P_[b], *pc = P_[c], *pd = P_[d];
  if (P_.orient3d(pa, pb, pc, pd) != 0) return 0;
  const uint32_t shared = (a == c || a == d) ? a : ((b == c || b == d) ? b : kNone);
  const auto touch = static_cast<int>(IntersectionKind::VertexOnSegment);
  if (pred::collinear3d(pa, pb, pc) && pred::collinear3d(pa, pb, pd)) {
    const int k = differing_axis(pa, pb);
    const double lo = std::max(std::min(pa[k], pb[k]), std::min(pc[k], pd[k]));
    const double hi = std::min(std::max(pa[k], pb[k]), std::max(pc[k], pd[k]));
    if (lo > hi) return 0;
    if (lo == hi && shared != kNone) return 0;  // coordinate k is one-to-one on the line
    return touch;
  }
  if (shared != kNone) return 0;  // not collinear: they meet only at the shared end
  int drop = 0;
  while (drop < 2 && o2(pa, pb, pc, drop) == 0 && o2(pa, pb, pd, drop) == 0) ++drop;
  if (!seg_seg_closed_2d(pa, pb, pc, pd, drop)) return 0;
  const bool end_on = (pred::collinear3d(pa, pb, pc) && between_closed(pa, pb, pc)) ||
                      (pred::collinear3d(pa, pb, pd) && between_closed(pa, pb, pd)) ||
                      (pred::collinear3d(pc, pd, pa) && between_closed(pc, pd, pa)) ||
                      (pred::collinear3d(pc, pd, pb) && between_closed(pc, pd, pb));
  return end_on ? touch : static_cast<int>(IntersectionKind::SegmentsCross);
}

// Explicit segment s against triangle t of facet F. If s is part of F only
// its contacts with F's loop edges matter; otherwise s may meet t only in a
// shared vertex.
int Checker::test_seg_tri(uint32_t s, const Tri& t) const {
  const uint32_t a = plc_.segments[s][0], b = plc_.segments[s][1];
  if (embedded(s, t.facet)) {
    for (int i = 0; i < 3; ++i) {
      if (!(t.loop_mask & (1u << i))) continue;
      const int k = test_seg_seg(a, b, t.v[i], t.v[(i + 1) % 3]);
      if (k) return k;
    }
    return 0;
  }
  const uint32_t v = vertex_of(t, a) ? a : (vertex_of(t, b) ? b : kNone);
  if (!seg_tri_beyond(a, b, t, v)) return 0;
  const TriPts q = pts(t);
  for (uint32_t e : {a, b}) {
    if (e == v) continue;
    if (side_of(t, P_[e]) == 0 && in_tri(q[0], q[1], q[2], P_[e], t.drop))
      return static_cast<int>(IntersectionKind::VertexInFacet);
  }
  for (uint32_t x : t.v) {
    if (x == v) continue;
    if (pred::collinear3d(P_[a], P_[b], P_[x]) && between_closed(P_[a], P_[b], P_[x]))
      return static_cast<int>(IntersectionKind::VertexOnSegment);
  }
  return static_cast<int>(IntersectionKind::Cross);
}

void Checker::report(uint32_t a, uint32_t b, IntersectionKind kind) {
  if (a > b) std::swap(a, b);
  const uint64_t key = (static_cast<uint64_t>(a) << 32) | b;
  auto it = index_.find(key);
  if (it != index_.end()) {
    Intersection& x = found_[it->second];
    if (kind < x.kind) x.kind = kind;
    return;
  }
  index_.emplace(key, found_.size());
  found_.push_back(Intersection{a, b, kind});
  if (found_.size() >= limit_) full_ = true;
}

void Checker::visit_pairs() {
  const uint32_t nt = static_cast<uint32_t>(tris_.size());
  const uint32_t nf = static_cast<uint32_t>(plc_.facets.size());
  const size_t ncell = cell_start_.empty() ? 0 : cell_start_.size() - 1;
  // A cell's items are copied next to each other first (box and lowest
  // cell), so the pair loop reads contiguous memory instead of two random
  // records per pair.
  struct Local {
    Box box;
    int32_t c[3];
  };
  std::vector<Local> local;
  for (size_t cell = 0; cell < ncell && !full_; ++cell) {
    const uint32_t begin = cell_start_[cell], end = cell_start_[cell + 1];
    if (end - begin < 2) continue;
    const int32_t cx = static_cast<int32_t>(cell % dims_[0]);
    const int32_t cy = static_cast<int32_t>((cell / dims_[0]) % dims_[1]);
    const int32_t cz = static_cast<int32_t>(cell / (static_cast<size_t>(dims_[0]) * dims_[1]));
    local.resize(end - begin);
    for (uint32_t x = begin; x < end; ++x) {
      const uint32_t i = cell_items_[x];
      const std::array<int32_t, 3> c = cell_of(box_[i].lo);
      local[x - begin] = {box_[i], {c[0], c[1], c[2]}};
    }
    for (uint32_t x = begin; x < end && !full_; ++x) {
      const uint32_t i = cell_items_[x];
      const Local& li = local[x - begin];
      for (uint32_t y = x + 1; y < end && !full_; ++y) {
        const Local& lj = local[y - begin];
        // Visit the pair only in the first cell both boxes share.
        if (std::max(li.c[0], lj.c[0]) != cx || std::max(li.c[1], lj.c[1]) != cy ||
            std::max(li.c[2], lj.c[2]) != cz)
          continue;
        if (!boxes_overlap(li.box, lj.box)) continue;
        const uint32_t j = cell_items_[y];
        if (i < nt && j < nt) {
          const Tri &t1 = tris_[i], &t2 = tris_[j];
          if (t1.facet == t2.facet) continue;
          const int k = t1.facet < t2.facet ? test_tri_tri(t1, t2) : test_tri_tri(t2, t1);
          if (k) report(t1.facet, t2.facet, static_cast<IntersectionKind>(k));
        } else if (i < nt || j < nt) {
          const Tri& t = tris_[std::min(i, j)];
          const uint32_t s = std::max(i, j) - nt;
          const int k = test_seg_tri(s, t);
          if (k) report(t.facet, nf + s, static_cast<IntersectionKind>(k));
        } else {
          const uint32_t s = i - nt, r = j - nt;
          const int k = test_seg_seg(plc_.segments[s][0], plc_.segments[s][1], plc_.segments[r][0],
                                     plc_.segments[r][1]);
          if (k) report(nf + s, nf + r, static_cast<IntersectionKind>(k));
        }
      }
    }
  }
}

void Checker::run(std::vector<Intersection>& out) {
  out.clear();
  if (limit_ == 0) return;
  build_triangles();
  build_grid();
  if (!plc_.segments.empty()) find_embedded_segments();
  visit_pairs();
  std::sort(found_.begin(), found_.end(), [](const Intersection& x, const Intersection& y) {
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
  out.swap(found_);
}

const char* kind_phrase(IntersectionKind kind) {
  switch (kind) {
    case IntersectionKind::Cross:
      return "cross";
    case IntersectionKind::CoplanarOverlap:
      return "overlap in a common plane";
    case IntersectionKind::VertexInFacet:
      return "touch (a vertex or edge of one lies on the other without being shared)";
    case IntersectionKind::VertexOnSegment:
      return "touch (a vertex lies inside a segment)";
    case IntersectionKind::SegmentsCross:
      return "cross";
  }
  return "intersect";
}

}  // namespace

void find_self_intersections(const Plc& plc, std::vector<Intersection>& out, size_t limit) {
  Checker(plc, limit).run(out);
}

Status self_intersection_error(const Plc& plc, const std::vector<Intersection>& found) {
  if (found.empty()) return Status::success();
  const uint32_t nf = static_cast<uint32_t>(plc.facets.size());
  auto name = [&](uint32_t r) {
    return r < nf ? "facet " + std::to_string(r) : "segment " + std::to_string(r - nf);
  };
  auto short_name = [&](uint32_t r) {
    return r < nf ? std::to_string(r) : "s" + std::to_string(r - nf);
  };
  const Intersection& x = found[0];
  std::string msg = "The surface intersects itself: ";
  if (x.b < nf) {
    msg += "facets " + std::to_string(x.a) + " and " + std::to_string(x.b);
  } else {
    msg += name(x.a) + " and " + name(x.b);
  }
  msg += std::string(" ") + kind_phrase(x.kind);
  if (found.size() > 1) {
    const size_t more = found.size() - 1;
    msg += " (and " + std::to_string(more) + (more == 1 ? " more pair: " : " more pairs: ");
    const size_t shown = std::min<size_t>(more, 5);
    for (size_t i = 1; i <= shown; ++i) {
      if (i > 1) msg += ", ";
      msg += short_name(found[i].a) + "/" + short_name(found[i].b);
    }
    if (more > shown) msg += ", ...";
    msg += ")";
  }
  msg += ".";
  Status s;
  s.error.code = ErrorCode::SelfIntersection;
  s.error.message = std::move(msg);
  s.error.file = plc.file;
  if (x.a < nf) {
    s.error.facet = x.a;
    s.error.line = plc.facets[x.a].line;
    s.error.record = plc.facets[x.a].record;
  }
  if (x.b < nf) s.error.other_facet = x.b;
  const uint32_t seg_ref = x.a >= nf ? x.a : (x.b >= nf ? x.b : kNone);
  if (seg_ref != kNone && seg_ref - nf < plc.segments.size()) {
    const auto& sg = plc.segments[seg_ref - nf];
    const std::array<VertexId, 2> key = {std::min(sg[0], sg[1]), std::max(sg[0], sg[1])};
    const auto all = plc_segments(plc);
    const auto it = std::lower_bound(all.begin(), all.end(), key);
    if (it != all.end() && *it == key) s.error.segment = it - all.begin();
  }
  return s;
}

}  // namespace cdt3d
