// Repair step 4: crossing facets. Two triangles whose interiors cross meet
// in a segment whose ends are where an edge of one pierces the other. Both
// ends become vertices of both triangles and the segment an edge of both:
// each affected triangle is replaced by the constrained triangulation of its
// corners, the new points on its edges and inside it, and the intersection
// segments (one facet per triangle, provenance kept). Where the segments of
// two crossings cross inside a triangle, three triangles meet in one point
// (the common point of their planes), which splits the segments in all
// three. A new point on an edge goes into every facet that has the edge.
//
// Exactness: which edges pierce which triangle is decided by orient3d signs.
// The piercing point itself is a constructed point, rounded to doubles (see
// pierce_point), so it lies near, not exactly on, both triangles. The
// triangulation of a triangle is done in the coordinate plane that drops one
// axis (exact), as a flat PLC handed to triangulate_surface. Because of the
// rounding the result is checked exactly again (find_self_intersections) and
// the step repeats on what rounding broke, at most kRounds times; whatever
// still intersects is reported by facet.
//
// Handled: triangle pairs whose contact is cut out by piercing points (an
// edge crossing the other triangle or one of its edges), with no vertex on
// the other's plane: crossings, and touching contacts at one point; and
// coplanar overlaps, where each triangle is cut along the other's edges and
// the two copies of the overlap are then one duplicate facet dropped.
// Contacts through a vertex, in-plane contacts other than overlaps and
// explicit segments are left and reported.
#include <algorithm>
#include <cmath>
#include <map>

#include "geometry.hpp"
#include "predicates.hpp"
#include "repair.hpp"

namespace cdt3d {
namespace repair_steps {
namespace {

constexpr size_t kRounds = 4;
/// An end of an intersection segment that is a vertex of both triangles.
constexpr int kExisting = -2;

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

// p + s (q - p), rounded to doubles. The exact s lies in (0, 1) (the
// orient3d signs say the crossing is inside pq); a computed s outside it, or
// not finite (planes or lines parallel in floating point), is brought back
// into [0, 1] (the midpoint when not finite), and the exact re-check judges
// the result like any other rounded point.
Vec3 along(const double* p, const double* q, long double s) {
  if (!std::isfinite(static_cast<double>(s))) s = 0.5L;
  s = std::min(1.0L, std::max(0.0L, s));
  Vec3 x;
  double* out = &x.x;
  for (int k = 0; k < 3; ++k)
    out[k] = static_cast<double>(p[k] + s * (static_cast<long double>(q[k]) - p[k]));
  return x;
}

// The point where segment pq crosses the plane of triangle t. Constructed
// in doubles and therefore ROUNDED: it lies within a few ulps of both pq and
// the plane, not exactly on them. The caller re-checks the result exactly.
// Always computed from the same inputs in the same order (the key sorts
// them), so every triangle that needs this point gets the same coordinates.
Vec3 pierce_point(const double* p, const double* q, const Tri& t, const Plc& plc) {
  using LD = long double;  // a little more precision where the planes are nearly parallel
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
  using LD = long double;
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

class Crossings {
 public:
  explicit Crossings(Work& w, RepairReport& report) : w_(w), report_(report) {}

  /// Records what the overlap of the coplanar triangles f and g adds to
  /// each: every edge of one cuts the other where it runs inside it (its
  /// ends: its own vertices inside the other, exact, and its crossings with
  /// the other's edges, constructed). Both then hold the overlap with the
  /// same vertices and edges; the copies of it are dropped as duplicate
  /// facets afterwards (tidy_after_rounding). False on a configuration this
  /// does not handle (a vertex on the other's edge without being its vertex).
  bool add_coplanar_pair(uint32_t f, uint32_t g) {
    const Tri t = tri(f), u = tri(g);
    const int drop = projection_axis(t);
    bool any = false;
    for (int side = 0; side < 2; ++side) {
      const Tri& host = side == 0 ? t : u;
      const Tri& cutter = side == 0 ? u : t;
      const uint32_t host_f = side == 0 ? f : g, cutter_f = side == 0 ? g : f;
      for (int i = 0; i < 3; ++i) {
        std::vector<VertexId> on;  // points of the edge inside the closed host
        const VertexId a = cutter[i], b = cutter[(i + 1) % 3];
        for (VertexId v : {a, b}) {
          const int where = locate_in(host, v, drop);
          if (where < 0) return false;  // on an edge of host without being its vertex
          if (where == 1) {
            on.push_back(v);
            if (std::find(host.begin(), host.end(), v) == host.end()) inserts_[host_f].inside.push_back(v);
          }
        }
        for (int j = 0; j < 3; ++j) {
          const VertexId c = host[j], d = host[(j + 1) % 3];
          if (a == c || a == d || b == c || b == d) continue;
          const double *pa = xyz(w_.plc, a), *pb = xyz(w_.plc, b);
          const double *pc = xyz(w_.plc, c), *pd = xyz(w_.plc, d);
          const int o1 = pred::orient2d_projected(pa, pb, pc, drop);
          const int o2 = pred::orient2d_projected(pa, pb, pd, drop);
          const int o3 = pred::orient2d_projected(pc, pd, pa, drop);
          const int o4 = pred::orient2d_projected(pc, pd, pb, drop);
          if (o1 * o2 < 0 && o3 * o4 < 0) on.push_back(point_on_edges(a, b, c, d));
          else if ((o1 == 0 || o2 == 0) && o3 * o4 < 0) return false;  // through a corner
        }
        std::sort(on.begin(), on.end());
        on.erase(std::unique(on.begin(), on.end()), on.end());
        if (on.size() > 2) return false;
        if (on.size() == 2) {
          inserts_[host_f].segments.push_back({on[0], on[1], cutter_f});
          any = true;
        }
      }
    }
    return any;
  }

  // Where point v lies relative to the triangle t (projection `drop`): 1 in
  // the closed triangle at a vertex or strictly inside, 0 outside, -1 on an
  // edge without being one of its vertices.
  int locate_in(const Tri& t, VertexId v, int drop) const {
    if (std::find(t.begin(), t.end(), v) != t.end()) return 1;
    const double* p = xyz(w_.plc, v);
    int o[3];
    for (int i = 0; i < 3; ++i) o[i] = pred::orient2d_projected(xyz(w_.plc, t[i]), xyz(w_.plc, t[(i + 1) % 3]), p, drop);
    const bool nonneg = o[0] >= 0 && o[1] >= 0 && o[2] >= 0;
    const bool nonpos = o[0] <= 0 && o[1] <= 0 && o[2] <= 0;
    if (!nonneg && !nonpos) return 0;
    return (o[0] != 0 && o[1] != 0 && o[2] != 0) ? 1 : -1;
  }

  /// Records what the crossing of facets f and g (both triangles) adds to
  /// each. False when the pair is not in general position.
  bool add_pair(uint32_t f, uint32_t g) {
    const Tri t = tri(f), u = tri(g);
    std::vector<std::pair<int, VertexId>> ends_f, ends_g;  // (own edge or -1, point)
    if (!pierce(t, u, ends_f, ends_g) || !pierce(u, t, ends_g, ends_f)) return false;
    for (auto* ends : {&ends_f, &ends_g}) {
      std::sort(ends->begin(), ends->end(), [](const auto& x, const auto& y) {
        return x.second != y.second ? x.second < y.second : x.first > y.first;
      });
      ends->erase(std::unique(ends->begin(), ends->end(),
                              [](const auto& x, const auto& y) { return x.second == y.second; }),
                  ends->end());
    }
    if (ends_f.empty() || ends_f.size() > 2) return false;
    for (int side = 0; side < 2; ++side) {
      Insert& in = inserts_[side == 0 ? f : g];
      const auto& ends = side == 0 ? ends_f : ends_g;
      for (const auto& e : ends)
        if (e.first == -1) in.inside.push_back(e.second);
      if (ends.size() == 2) in.segments.push_back({ends[0].second, ends[1].second, side == 0 ? g : f});
    }
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
        facets.push_back(part_of(facet, {t[0], t[1], t[2]}));
        source.push_back(src);
      }
    }
    w_.plc.facets = std::move(facets);
    w_.source = std::move(source);
    return split;
  }

 private:
  Tri tri(uint32_t f) const {
    const auto& l = w_.plc.facets[f].loops[0];
    return {l[0], l[1], l[2]};
  }

  // Edges of t that cross the closed triangle u away from u's corners: the
  // piercing points, as (edge of t, point) for t and (edge of u or -1 when
  // inside u, point) for u. An edge of t crossing an edge of u (exactly:
  // orient3d of the two edges is 0) meets it in one point for both. False
  // on a degeneracy this step does not handle (a vertex on the other's
  // plane, an edge through a corner of the other).
  bool pierce(const Tri& t, const Tri& u, std::vector<std::pair<int, VertexId>>& ends_t,
              std::vector<std::pair<int, VertexId>>& ends_u) {
    const Plc& plc = w_.plc;
    // Copies: a new point may grow plc.points and move its storage.
    double uc[3][3];
    for (int j = 0; j < 3; ++j)
      for (int k = 0; k < 3; ++k) uc[j][k] = xyz(plc, u[j])[k];
    const double *u0 = uc[0], *u1 = uc[1], *u2 = uc[2];
    for (int i = 0; i < 3; ++i) {
      const VertexId p = t[i], q = t[(i + 1) % 3];
      const int sp = pred::orient3d(u0, u1, u2, xyz(plc, p));
      const int sq = pred::orient3d(u0, u1, u2, xyz(plc, q));
      if (sp == 0 && sq == 0) return false;  // the edge lies in u's plane
      if (sp == 0 || sq == 0) {
        // One end on u's plane. After step 3 a vertex of t in the closed
        // triangle u is a vertex of u: then the contact starts there (an
        // existing point, kExisting); otherwise that end is outside u.
        const VertexId z = sp == 0 ? p : q;
        if (std::find(u.begin(), u.end(), z) != u.end()) {
          ends_t.push_back({kExisting, z});
          ends_u.push_back({kExisting, z});
        }
        continue;
      }
      if (sp == sq) continue;
      int s[3];
      for (int j = 0; j < 3; ++j)
        s[j] = pred::orient3d(xyz(plc, p), xyz(plc, q), uc[j], uc[(j + 1) % 3]);
      const bool nonneg = s[0] >= 0 && s[1] >= 0 && s[2] >= 0;
      const bool nonpos = s[0] <= 0 && s[1] <= 0 && s[2] <= 0;
      if (!nonneg && !nonpos) continue;  // the line passes beside u
      const int zeros = (s[0] == 0) + (s[1] == 0) + (s[2] == 0);
      if (zeros > 1) return false;       // through a corner of u
      if (zeros == 0) {
        const VertexId x = point_in_triangle(p, q, u);
        ends_t.push_back({i, x});
        ends_u.push_back({-1, x});
        continue;
      }
      const int j = s[0] == 0 ? 0 : (s[1] == 0 ? 1 : 2);
      const VertexId x = point_on_edges(p, q, u[j], u[(j + 1) % 3]);
      ends_t.push_back({i, x});
      ends_u.push_back({j, x});
    }
    return true;
  }

  // The point where edge (p, q) pierces the inside of triangle u: one id per
  // (edge, triangle).
  VertexId point_in_triangle(VertexId p, VertexId q, Tri u) {
    if (p > q) std::swap(p, q);
    std::sort(u.begin(), u.end());
    const std::array<VertexId, 5> key{p, q, u[0], u[1], u[2]};
    const auto it = made_.find(key);
    if (it != made_.end()) return it->second;
    return made_[key] = new_point(pierce_point(xyz(w_.plc, p), xyz(w_.plc, q), u, w_.plc), p, q);
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
    const VertexId id = new_point(line_crossing(xyz(w_.plc, p), xyz(w_.plc, q), xyz(w_.plc, a),
                                                xyz(w_.plc, b)),
                                  p, q);
    edge_points_[{a, b}].push_back(id);
    return made_[key] = id;
  }

  VertexId new_point(const Vec3& x, VertexId p, VertexId q) {
    const VertexId id = static_cast<VertexId>(w_.plc.points.size());
    w_.plc.points.push_back(x);
    edge_points_[{p, q}].push_back(id);
    ++report_.intersection_points;
    return id;
  }

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
      const double* a = xyz(plc, t[i]);
      const double* b = xyz(plc, t[(i + 1) % 3]);
      int k = 0;
      while (k < 2 && a[k] == b[k]) ++k;
      std::vector<VertexId> pts;
      for (const auto& e : in.on_edge)
        if (e.first == i) pts.push_back(e.second);
      std::sort(pts.begin(), pts.end(), [&](VertexId x, VertexId y) {
        return a[k] < b[k] ? xyz(plc, x)[k] < xyz(plc, y)[k] : xyz(plc, x)[k] > xyz(plc, y)[k];
      });
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
    std::vector<uint32_t> tris, tri_facet;
    if (!triangulate_surface(flat, tris, tri_facet).ok() || tris.empty()) return false;
    for (size_t k = 0; k + 2 < tris.size(); k += 3) out.push_back({ids[tris[k]], ids[tris[k + 1]], ids[tris[k + 2]]});
    return true;
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
    const VertexId id = static_cast<VertexId>(w_.plc.points.size());
    w_.plc.points.push_back(x);
    ++report_.intersection_points;
    return triples_[key] = id;
  }

  // The point common to the planes of three triangles (Cramer's rule in long
  // double, then ROUNDED to doubles). False when the planes are (nearly)
  // parallel in floating point.
  bool three_planes(const Tri& t1, const Tri& t2, const Tri& t3, Vec3& out) const {
    using LD = long double;
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
      o[k] = static_cast<double>((d[0] * c23[k] + d[1] * c31[k] + d[2] * c12[k]) / det);
      if (!std::isfinite(o[k])) return false;
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
        long double t = 0;
        for (int k = 0; k < 3; ++k) t += (static_cast<long double>(xyz(w_.plc, x)[k]) - a[k]) * (static_cast<long double>(b[k]) - a[k]);
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
  std::map<std::pair<VertexId, VertexId>, std::vector<VertexId>> edge_points_;
  std::map<std::pair<uint32_t, uint32_t>, std::vector<VertexId>> splits_;  ///< (facet, other) -> triple points
  std::map<std::array<uint32_t, 3>, VertexId> triples_;
  std::map<uint32_t, Insert> inserts_;
  std::map<std::array<VertexId, 5>, VertexId> made_;
};

// Crossings, and touching contacts (an edge crossing the other facet's edge
// or piercing it at one point, the facets on one side): both are cut by the
// same piercing points. Coplanar contacts and segments are not handled.
bool handled(const Intersection& x) {
  return x.kind == IntersectionKind::Cross || x.kind == IntersectionKind::VertexInFacet ||
         x.kind == IntersectionKind::CoplanarOverlap;
}

// Rounded points can break what steps 1-3 made true: a new point may land on
// an existing point, a thin new triangle may come out collinear, a polygon
// that took a point on an edge may no longer be planar, a point may land
// exactly on another facet. Those steps run again (they are exact; their
// counts go to a scratch report, since these are no input defects), and the
// input checks must pass before the exact intersection test runs again.
Status tidy_after_rounding(Work& w) {
  RepairReport scratch;
  weld_points(w, scratch);
  clean_polygons(w, scratch);
  split_nonplanar_facets(w, scratch);
  Status st = split_at_tjunctions(w, scratch);
  // Triangulating facets at T-junctions can make copies of a triangle.
  clean_polygons(w, scratch);
  drop_duplicate_facets(w, scratch);
  if (st.ok()) st = check_plc(w.plc);
  return st;
}

}  // namespace

Status resolve_crossings(Work& w, RepairReport& report, std::vector<Intersection>& left) {
  for (size_t round = 0;; ++round) {
    find_self_intersections(w.plc, left);
    const uint32_t facets = static_cast<uint32_t>(w.plc.facets.size());
    std::vector<uint8_t> involved(facets, 0);
    size_t crossing = 0;
    for (const Intersection& x : left) {
      if (!handled(x) || x.b >= facets) continue;
      involved[x.a] = involved[x.b] = 1;
      ++crossing;
    }
    if (round == 0) report.crossing_pairs = crossing;
    if (crossing == 0 || round == kRounds) return Status::success();
    report.rounds = round + 1;
    // Polygon facets in crossing pairs are triangulated first; the pairs are
    // then found again between triangles.
    std::vector<uint8_t> polygon(facets, 0);
    bool any_polygon = false;
    for (uint32_t f = 0; f < facets; ++f)
      if (involved[f] && !is_triangle(w.plc.facets[f])) {
        polygon[f] = 1;
        any_polygon = true;
      }
    if (any_polygon) {
      Status st = triangulate_in_place(w, polygon);
      if (!st.ok()) return st;
      find_self_intersections(w.plc, left);
    }
    Crossings c(w, report);
    size_t added = 0;
    for (const Intersection& x : left) {
      if (!handled(x) || x.b >= w.plc.facets.size()) continue;
      if (!is_triangle(w.plc.facets[x.a]) || !is_triangle(w.plc.facets[x.b])) continue;
      added += x.kind == IntersectionKind::CoplanarOverlap ? c.add_coplanar_pair(x.a, x.b)
                                                          : c.add_pair(x.a, x.b);
    }
    if (added == 0) {
      find_self_intersections(w.plc, left);
      return Status::success();
    }
    report.crossing_facets += c.apply();
    Status st = tidy_after_rounding(w);
    if (!st.ok()) return st;
  }
}

}  // namespace repair_steps
}  // namespace cdt3d
