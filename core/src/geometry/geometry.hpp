// The small helpers every step shares, written once: the 3-vector
// arithmetic on the public Vec3, edge and triangle keys, the projection axis
// of a facet, and the flat-tet test. The floating-point ones place points,
// rank candidates or report numbers; no topological decision rests on them
// (those go through predicates.hpp). IEEE +, -, *, /, sqrt round identically
// natively and in WebAssembly, and the build forbids contraction into FMA,
// so each expression gives the same double on both.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "predicates.hpp"

namespace cdt3d {

/// A length far below any coordinate difference the core meets (the
/// smallest normal double is 2.2e-308), added to a tolerance or padding
/// that is relative to some size so that it stays positive when that size is
/// 0 (a zero-radius ball, a zero-volume mesh).
constexpr double kTinyLength = 1e-300;

// --- 3-vectors: the public Vec3 is the one vector type of the core ---

inline Vec3 to_vec(const double* p) { return {p[0], p[1], p[2]}; }
inline Vec3 operator+(const Vec3& a, const Vec3& b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
inline Vec3 operator-(const Vec3& a, const Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
inline Vec3 operator*(double s, const Vec3& a) { return {s * a.x, s * a.y, s * a.z}; }
inline double dot(const Vec3& a, const Vec3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
inline Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
inline double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }
inline double dist(const Vec3& a, const Vec3& b) { return norm(a - b); }
inline bool finite(const Vec3& a) {
  return std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
}

// --- keys: a vertex pair or triple in a canonical order, for sorting and lookup ---

/// Edge {a, b} as one integer, smaller id in the high word: sorting such
/// keys sorts edges lexicographically, and integers sort fast.
inline uint64_t edge_key(uint32_t a, uint32_t b) {
  return a < b ? (uint64_t{a} << 32) | b : (uint64_t{b} << 32) | a;
}

/// Edge {a, b} as (smaller, larger).
inline std::array<VertexId, 2> sorted_edge(VertexId a, VertexId b) {
  return a < b ? std::array<VertexId, 2>{a, b} : std::array<VertexId, 2>{b, a};
}

/// Triangle {a, b, c} with its ids ascending: the key of a face whatever its
/// orientation.
inline std::array<VertexId, 3> sorted_triangle(VertexId a, VertexId b, VertexId c) {
  std::array<VertexId, 3> k{a, b, c};
  if (k[0] > k[1]) std::swap(k[0], k[1]);
  if (k[1] > k[2]) std::swap(k[1], k[2]);
  if (k[0] > k[1]) std::swap(k[0], k[1]);
  return k;
}
inline std::array<VertexId, 3> sorted_triangle(const std::array<VertexId, 3>& t) {
  return sorted_triangle(t[0], t[1], t[2]);
}

// --- projection of a planar facet to a coordinate plane ---

/// The axis of the largest |component| of normal n (0 = x), the lower axis on
/// ties. Dropping it projects the facet to the coordinate plane where it is
/// least foreshortened; exact 2D tests there (pred::orient2d_projected) then
/// decide in-plane questions for coplanar points without constructing any.
inline int largest_axis(double nx, double ny, double nz) {
  const double ax = std::fabs(nx), ay = std::fabs(ny), az = std::fabs(nz);
  return ax >= ay && ax >= az ? 0 : (ay >= az ? 1 : 2);
}

/// The three axes in the order a projection should try them for a plane of
/// normal n: the largest |component| first (largest_axis's choice), then the
/// next, ties to the lower axis. A caller whose points happen to project
/// degenerately on the first (the normal is rounded) takes the next.
inline std::array<int, 3> axes_by_normal(const Vec3& n) {
  const double a[3] = {std::fabs(n.x), std::fabs(n.y), std::fabs(n.z)};
  std::array<int, 3> order = {0, 1, 2};
  std::sort(order.begin(), order.end(),
            [&](int i, int j) { return a[i] != a[j] ? a[i] > a[j] : i < j; });
  return order;
}

/// Newell's normal of a polygon of PLC points (not unit): twice its
/// vector area, for a planar loop of any shape, convex or not.
inline Vec3 newell_normal(const Plc& plc, const std::vector<VertexId>& loop) {
  Vec3 n{0, 0, 0};
  for (size_t i = 0; i < loop.size(); ++i) {
    const Vec3& p = plc.points[loop[i]];
    const Vec3& q = plc.points[loop[(i + 1) % loop.size()]];
    n.x += (p.y - q.y) * (p.z + q.z);
    n.y += (p.z - q.z) * (p.x + q.x);
    n.z += (p.x - q.x) * (p.y + q.y);
  }
  return n;
}

/// Orientation of a planar simple loop in the projection that drops axis
/// `drop`: the exact turn at its lexicographically smallest projected vertex,
/// an extreme vertex of the polygon and so a strictly convex corner.
inline int loop_orientation(const Plc& plc, const std::vector<VertexId>& loop, int drop) {
  const int u = (drop + 1) % 3, w = (drop + 2) % 3;
  const auto at = [&](size_t i) { return &plc.points[loop[i]].x; };
  size_t best = 0;
  for (size_t i = 1; i < loop.size(); ++i) {
    const double *p = at(i), *q = at(best);
    if (p[u] < q[u] || (p[u] == q[u] && p[w] < q[w])) best = i;
  }
  const size_t n = loop.size();
  return pred::orient2d_projected(at((best + n - 1) % n), at(best), at((best + 1) % n), drop);
}

/// Cross product (b - a) x (c - a) in doubles: the (unnormalised) normal of
/// triangle (a, b, c).
inline Vec3 triangle_normal(const double* a, const double* b, const double* c) {
  const double ux = b[0] - a[0], uy = b[1] - a[1], uz = b[2] - a[2];
  const double vx = c[0] - a[0], vy = c[1] - a[1], vz = c[2] - a[2];
  return {uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx};
}

/// The axis whose dropping projects triangle (a, b, c) best: the largest
/// component of its normal. Rounding can make the projected triangle
/// degenerate when the normal is tiny; callers that need a proper triangle
/// check pred::orient2d_projected and fall back to another axis.
inline int projection_axis(const double* a, const double* b, const double* c) {
  const Vec3 n = triangle_normal(a, b, c);
  return largest_axis(n.x, n.y, n.z);
}

/// Cosines of the smallest and largest dihedral angle of tet p[0..3], in
/// doubles: for statistics and for ranking tets, never for a topological
/// decision. A face of zero area counts as a zero angle (cosine 1).
inline void dihedral_cosines(const Vec3 p[4], double& cos_min_angle, double& cos_max_angle) {
  // Face normals (face i opposite vertex i), all turned outward: the
  // dihedral angle at the edge of faces i and j is 180 degrees minus the
  // angle between their normals, so its cosine is -n_i.n_j / |n_i||n_j|.
  Vec3 nrm[4];
  double len[4];
  for (int i = 0; i < 4; ++i) {
    const Vec3 a = p[(i + 1) % 4], b = p[(i + 2) % 4], c = p[(i + 3) % 4];
    Vec3 m = cross(b - a, c - a);
    if (dot(m, p[i] - a) > 0) m = {-m.x, -m.y, -m.z};
    nrm[i] = m;
    len[i] = norm(m);
  }
  cos_min_angle = -1, cos_max_angle = 1;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double d = len[i] * len[j];
      const double c = d == 0 ? 1 : std::max(-1.0, std::min(1.0, -dot(nrm[i], nrm[j]) / d));
      cos_min_angle = std::max(cos_min_angle, c), cos_max_angle = std::min(cos_max_angle, c);
    }
}

/// Smallest and largest dihedral angle (degrees) of tet p[0..3], in doubles
/// (see dihedral_cosines).
inline void dihedral_range(const Vec3 p[4], double& lo, double& hi) {
  const double deg = 180 / 3.14159265358979323846;
  double c_lo, c_hi;
  dihedral_cosines(p, c_lo, c_hi);
  lo = std::acos(c_lo) * deg, hi = std::acos(c_hi) * deg;
}

/// 6V of tet (a, b, c, d) in doubles, from u = a - d, v = b - d, w = c - d:
/// the one expression volume_ratio and numerically_flat share, so both see
/// the same rounded value.
inline double six_volume(const double u[3], const double v[3], const double w[3]) {
  return u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) +
         u[2] * (v[0] * w[1] - v[1] * w[0]);
}

/// 6V / l_max^3 of tet (a, b, c, d) in doubles: 6V = (a - d) . ((b - d) x
/// (c - d)) evaluated in floating point, l_max its longest edge. Positive for
/// a positively oriented tet (tet_mesh.hpp), up to rounding.
inline double volume_ratio(const double* a, const double* b, const double* c, const double* d) {
  const double u[3] = {a[0] - d[0], a[1] - d[1], a[2] - d[2]};
  const double v[3] = {b[0] - d[0], b[1] - d[1], b[2] - d[2]};
  const double w[3] = {c[0] - d[0], c[1] - d[1], c[2] - d[2]};
  const double det = six_volume(u, v, w);
  const double* p[4] = {a, b, c, d};
  double l2 = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double x = p[i][0] - p[j][0], y = p[i][1] - p[j][1], z = p[i][2] - p[j][2];
      l2 = std::max(l2, x * x + y * y + z * z);
    }
  const double l = std::sqrt(l2);
  return l > 0 ? det / (l * l * l) : 0;
}

/// Whether tet (a, b, c, d) is numerically flat or inverted in doubles:
/// volume_ratio <= kFlatTetRatio. This is the usability test of the output
/// (cdt3d.hpp), applied to the stored coordinates as a user's code would.
///
/// Most tets are far from flat, so a filter decides them first, without the
/// six edge lengths and the square root of volume_ratio (every tet of a mesh
/// is tested before carving).
/// With m2 the largest squared length of u, v, w (edges at d), every edge is
/// at most 2 sqrt(m2) long (triangle inequality), so l_max^3 <= 8 m2^1.5, and
/// 6V^2 > 128 kFlatTetRatio^2 m2^3 gives volume_ratio > 1.41 kFlatTetRatio:
/// a margin far above the few ulps of rounding of either side. The range of
/// m2 keeps the squares and cubes clear of overflow and underflow; outside
/// it, and for nearly flat tets, volume_ratio decides.
inline bool numerically_flat(const double* a, const double* b, const double* c, const double* d) {
  const double u[3] = {a[0] - d[0], a[1] - d[1], a[2] - d[2]};
  const double v[3] = {b[0] - d[0], b[1] - d[1], b[2] - d[2]};
  const double w[3] = {c[0] - d[0], c[1] - d[1], c[2] - d[2]};
  const double det = six_volume(u, v, w);
  if (!(det > 0)) return true;  // volume_ratio <= 0 (or NaN)
  const double m2 =
      std::max({u[0] * u[0] + u[1] * u[1] + u[2] * u[2], v[0] * v[0] + v[1] * v[1] + v[2] * v[2],
                w[0] * w[0] + w[1] * w[1] + w[2] * w[2]});
  constexpr double kFilter = 128 * kFlatTetRatio * kFlatTetRatio;
  if (m2 > 1e-60 && m2 < 1e60 && det * det > kFilter * (m2 * m2 * m2)) return false;
  return !(volume_ratio(a, b, c, d) > kFlatTetRatio);
}

/// Whether some four of the five points are numerically flat. A face between
/// two tets whose five vertices pass this test may fail the exact insphere
/// test: the Delaunay choice there would be a flat tet, which the pipeline
/// flips away (flat_flips.hpp); validate() accepts such faces (its check 9).
inline bool has_flat_quadruple(const double* const p[5]) {
  for (int skip = 0; skip < 5; ++skip) {
    const double* q[4];
    for (int i = 0, k = 0; i < 5; ++i)
      if (i != skip) q[k++] = p[i];
    if (std::fabs(volume_ratio(q[0], q[1], q[2], q[3])) <= kFlatTetRatio) return true;
  }
  return false;
}

/// Centre of the circle through a, b, c, in their plane; not finite when
/// they are (nearly) collinear. Floating point: it places points (Steiner
/// points of steps 3 and refinement), it decides nothing.
inline Vec3 circle_center(Vec3 a, Vec3 b, Vec3 c) {
  const Vec3 u = b - a, w = c - a, n = cross(u, w);
  const double d = 2 * dot(n, n);
  return a + (1 / d) * (dot(u, u) * cross(w, n) + dot(w, w) * cross(n, u));
}

/// Centre of the sphere through a, b, c, d; not finite when they are
/// (nearly) coplanar. Floating point, like circle_center.
inline Vec3 sphere_center(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  const Vec3 u = b - a, v = c - a, w = d - a;
  const double den = 2 * dot(u, cross(v, w));
  return a + (1 / den) * (dot(u, u) * cross(v, w) + dot(v, v) * cross(w, u) + dot(w, w) * cross(u, v));
}

/// Radius-edge ratio of tet p[0..3] (circumradius over shortest edge) in
/// doubles; HUGE_VAL when the tet is degenerate. A measure, never a
/// topological decision.
inline double radius_edge_ratio(const Vec3 p[4]) {
  double shortest = HUGE_VAL;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) shortest = std::min(shortest, norm(p[i] - p[j]));
  const Vec3 o = sphere_center(p[0], p[1], p[2], p[3]);
  return shortest > 0 && finite(o) ? dist(o, p[0]) / shortest : HUGE_VAL;
}

/// A point of the open segment (u, w) exactly on its line (collinear by the
/// exact test) at a dyadic fraction g = k / 2^n near f, for n from max_bits
/// down to min_bits (|g - f| <= 2^-(n+1)); the point is evaluated in doubles
/// and kept only if that evaluation was exact. Split points of segments use
/// it so that a subsegment stays exactly on its segment's line when it can.
inline bool point_exactly_on_segment(const double* pu, const double* pw, double f, int max_bits,
                                     int min_bits, Vec3& q, double& tf) {
  for (int n = max_bits; n >= min_bits; --n) {
    const double scale = std::ldexp(1.0, n);
    const double g = std::round(f * scale) / scale;
    if (!(g > 0 && g < 1)) continue;
    const double x[3] = {pu[0] + g * (pw[0] - pu[0]), pu[1] + g * (pw[1] - pu[1]),
                         pu[2] + g * (pw[2] - pu[2])};
    const bool inside = (x[0] - pu[0]) * (pw[0] - pu[0]) + (x[1] - pu[1]) * (pw[1] - pu[1]) +
                                (x[2] - pu[2]) * (pw[2] - pu[2]) > 0 &&
                        (x[0] - pw[0]) * (pu[0] - pw[0]) + (x[1] - pw[1]) * (pu[1] - pw[1]) +
                                (x[2] - pw[2]) * (pu[2] - pw[2]) > 0;
    if (inside && pred::collinear3d(pu, pw, x)) {
      q = {x[0], x[1], x[2]};
      tf = g;
      return true;
    }
  }
  return false;
}

/// Renames every vertex reference of the PLC's facets and segments through
/// `id` (old id -> new id); the points themselves are the caller's to move.
inline void renumber_vertices(Plc& plc, const std::vector<VertexId>& id) {
  for (Facet& f : plc.facets)
    for (auto& loop : f.loops)
      for (VertexId& v : loop) v = id[v];
  for (auto& s : plc.segments)
    for (VertexId& v : s) v = id[v];
}

}  // namespace cdt3d
