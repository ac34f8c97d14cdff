// The quality numbers of a TetGen .node/.ele mesh that issue 17 (quality
// refinement) is judged by: the share of tets whose radius-edge ratio is above
// 2, the smallest dihedral angle, and the numerically flat tets. Used by
// tests/bench/bench_quality.sh on both programs' output (TetGen's M.1.node/.ele
// and cdt3d's `-o PREFIX` files), so that both are measured by the same code,
// not each by its own statistics.
//
// usage: mesh_quality MESH.node MESH.ele [MODEL]
// Build (bench_quality.sh does this, linking the library for MODEL's reader):
//   c++ -O2 -std=c++17 -Icore/include tests/bench/mesh_quality.cpp LIBCDT3D.a -o mesh_quality
//
// With MODEL (the PLC both meshes were made from), a tet is excused when it
// touches an input angle below kSmallAngle degrees (issue 42): a vertex at
// a facet corner of such an angle (an input triangle's angle), or a point
// on an input edge where two facets meet at such a dihedral angle. No
// Delaunay refiner can bound the tets there.
//
// Output, one line: "<tets> <bad> <min dihedral> <flat> <max ratio>":
//   bad          tets whose radius-edge ratio (circumradius / shortest edge) is
//                above 2, or undefined (zero volume or a zero-length edge)
//   min dihedral the smallest dihedral angle of all tets, in degrees (%.6g)
//   flat         numerically flat tets as flat_tets.cpp counts them
//                (bench::count_flat: 6V in doubles not above kFlatTetRatio *
//                (longest edge)^3 in the majority orientation; zero and
//                inverted tets count)
//   max ratio    the largest radius-edge ratio (%.4g; "inf" with a flat tet)
// and with MODEL five more: "<bad excused> <below> <below excused>
// <min dihedral not excused> <below in sector>": bad tets that are excused,
// tets with a dihedral angle below kSmallAngle, those of them excused, the
// smallest dihedral angle over tets not excused (degrees; 180 if none), and
// the tets below kSmallAngle not excused with a vertex inside the triangle
// of a small facet corner and its two neighbours (sector_points; reported,
// not excused).
// The dihedral angle at edge ij is the angle between the normals e x u and
// e x v (e = pj - pi, u and v from pi to the other two corners), taken with
// atan2 so that angles near 0 and 180 degrees keep their digits.
// Numbering, comments and extra columns as in flat_tets.cpp.
// Exit codes: 0 measured, 1 read error (message on stderr), 2 usage.
#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "tetgen_lines.hpp"

namespace {

struct V3 {
  double x, y, z;
};
V3 sub(const double* a, const double* b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V3 cross(const V3& a, const V3& b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double len(const V3& a) { return std::sqrt(dot(a, a)); }

// The smallest of the tet's six dihedral angles, in radians.
double min_dihedral(const double* const p[4]) {
  // Each edge (i, j) with its opposite corners (k, l).
  static const int kEdges[6][4] = {{0, 1, 2, 3}, {0, 2, 1, 3}, {0, 3, 1, 2},
                                   {1, 2, 0, 3}, {1, 3, 0, 2}, {2, 3, 0, 1}};
  double best = HUGE_VAL;
  for (const auto& e : kEdges) {
    const V3 axis = sub(p[e[1]], p[e[0]]);
    const V3 n1 = cross(axis, sub(p[e[2]], p[e[0]]));
    const V3 n2 = cross(axis, sub(p[e[3]], p[e[0]]));
    best = std::min(best, std::atan2(len(cross(n1, n2)), dot(n1, n2)));
  }
  return best;
}

// Circumradius over shortest edge; infinite when either is undefined.
double radius_edge(const double* const p[4]) {
  // The circumcentre relative to p[3] solves 2 [a b c]^T x = (|a|^2 |b|^2 |c|^2).
  const V3 a = sub(p[0], p[3]), b = sub(p[1], p[3]), c = sub(p[2], p[3]);
  const V3 bc = cross(b, c), ca = cross(c, a), ab = cross(a, b);
  const double det = dot(a, bc);
  double shortest = HUGE_VAL;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) shortest = std::min(shortest, len(sub(p[i], p[j])));
  if (det == 0 || !(shortest > 0)) return HUGE_VAL;
  const double wa = dot(a, a), wb = dot(b, b), wc = dot(c, c);
  const V3 centre = {wa * bc.x + wb * ca.x + wc * ab.x, wa * bc.y + wb * ca.y + wc * ab.y,
                     wa * bc.z + wb * ca.z + wc * ab.z};
  return len(centre) / (2 * std::fabs(det)) / shortest;
}

constexpr double kSmallAngle = 10;  // degrees
constexpr double kPi = 3.14159265358979323846;

double angle_deg(const V3& a, const V3& b) { return std::atan2(len(cross(a, b)), dot(a, b)) * 180 / kPi; }
V3 vsub(const cdt3d::Vec3& a, const cdt3d::Vec3& b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }

// Where the input has angles below kSmallAngle: corner points and edges, and
// per small facet corner the triangle of the corner and its two neighbours
// on the facet's boundary (for a triangle facet the facet itself).
struct SmallAngles {
  std::vector<cdt3d::Vec3> corners;
  std::vector<std::array<cdt3d::Vec3, 2>> edges;
  std::vector<std::array<cdt3d::Vec3, 3>> sectors;
};

SmallAngles small_angles(const cdt3d::Plc& plc) {
  SmallAngles out;
  std::unordered_set<uint32_t> corner_ids;
  // Facets by edge, with a point of the facet off that edge's line.
  std::unordered_map<uint64_t, std::vector<size_t>> by_edge;
  auto key = [](uint32_t a, uint32_t b) { return (uint64_t{std::min(a, b)} << 32) | std::max(a, b); };
  for (size_t f = 0; f < plc.facets.size(); ++f)
    for (const auto& loop : plc.facets[f].loops)
      for (size_t i = 0; i < loop.size(); ++i) {
        const uint32_t a = loop[(i + loop.size() - 1) % loop.size()], v = loop[i], b = loop[(i + 1) % loop.size()];
        const double corner = angle_deg(vsub(plc.points[a], plc.points[v]), vsub(plc.points[b], plc.points[v]));
        if (corner < kSmallAngle) out.sectors.push_back({plc.points[a], plc.points[v], plc.points[b]});
        if (corner < kSmallAngle && corner_ids.insert(v).second) out.corners.push_back(plc.points[v]);
        by_edge[key(v, b)].push_back(f);
      }
  for (const auto& [k, facets] : by_edge) {
    if (facets.size() < 2) continue;
    const uint32_t a = static_cast<uint32_t>(k >> 32), b = static_cast<uint32_t>(k & 0xffffffffu);
    const V3 e = vsub(plc.points[b], plc.points[a]);
    // Each facet's direction away from the edge, in its plane: the farthest
    // of its vertices from the edge's line, made perpendicular to it.
    std::vector<V3> dirs;
    for (size_t f : facets) {
      V3 best = {0, 0, 0};
      double best_len = 0;
      for (const auto& loop : plc.facets[f].loops)
        for (uint32_t v : loop) {
          const V3 d = vsub(plc.points[v], plc.points[a]);
          const double t = dot(d, e) / dot(e, e);
          const V3 perp = {d.x - t * e.x, d.y - t * e.y, d.z - t * e.z};
          if (len(perp) > best_len) best_len = len(perp), best = perp;
        }
      dirs.push_back(best);
    }
    bool small = false;
    for (size_t i = 0; i < dirs.size() && !small; ++i)
      for (size_t j = i + 1; j < dirs.size() && !small; ++j)
        small = angle_deg(dirs[i], dirs[j]) < kSmallAngle;
    if (small) out.edges.push_back({plc.points[a], plc.points[b]});
  }
  return out;
}

// Per mesh point: on a small-angle corner or edge (within a relative
// tolerance; the meshes' points on edges are rounded). A grid of sample
// cells along the edges keeps it linear.
std::vector<char> excused_points(const std::vector<double>& xyz, const SmallAngles& sa) {
  const size_t n = xyz.size() / 3;
  std::vector<char> out(n, 0);
  if (n == 0 || (sa.corners.empty() && sa.edges.empty())) return out;
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], xyz[3 * i + c]), hi[c] = std::max(hi[c], xyz[3 * i + c]);
  const double diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                (hi[2] - lo[2]) * (hi[2] - lo[2]));
  const double h = diag / 256 + 1e-300, tol = 1e-9 * diag;
  auto cell = [&](const double* p) {
    int64_t c[3];
    for (int k = 0; k < 3; ++k) c[k] = static_cast<int64_t>(std::floor((p[k] - lo[k]) / h));
    return (c[0] * 73856093) ^ (c[1] * 19349663) ^ (c[2] * 83492791);
  };
  std::unordered_map<int64_t, std::vector<uint32_t>> grid;  // cell -> edges
  for (uint32_t e = 0; e < sa.edges.size(); ++e) {
    const cdt3d::Vec3& a = sa.edges[e][0];
    const cdt3d::Vec3& b = sa.edges[e][1];
    const double l = len(vsub(b, a));
    const size_t steps = static_cast<size_t>(std::ceil(4 * l / h)) + 1;
    for (size_t s = 0; s <= steps; ++s) {
      const double t = static_cast<double>(s) / static_cast<double>(steps);
      for (int dx = -1; dx <= 1; ++dx)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dz = -1; dz <= 1; ++dz) {
            const double p[3] = {a.x + t * (b.x - a.x) + dx * h, a.y + t * (b.y - a.y) + dy * h,
                                 a.z + t * (b.z - a.z) + dz * h};
            auto& list = grid[cell(p)];
            if (list.empty() || list.back() != e) list.push_back(e);
          }
    }
  }
  std::unordered_set<int64_t> corner_cells;
  std::vector<std::array<double, 3>> corners;
  for (const cdt3d::Vec3& c : sa.corners) corners.push_back({c.x, c.y, c.z});
  std::sort(corners.begin(), corners.end());
  for (size_t i = 0; i < n; ++i) {
    const double* p = &xyz[3 * i];
    if (std::binary_search(corners.begin(), corners.end(), std::array<double, 3>{p[0], p[1], p[2]})) {
      out[i] = 1;
      continue;
    }
    const auto it = grid.find(cell(p));
    if (it == grid.end()) continue;
    for (uint32_t e : it->second) {
      const cdt3d::Vec3& a = sa.edges[e][0];
      const cdt3d::Vec3& b = sa.edges[e][1];
      const V3 ab = vsub(b, a), ap = {p[0] - a.x, p[1] - a.y, p[2] - a.z};
      const double t = dot(ap, ab) / dot(ab, ab);
      if (t < -1e-12 || t > 1 + 1e-12) continue;
      if (len(cross(ab, ap)) / len(ab) <= tol) {
        out[i] = 1;
        break;
      }
    }
  }
  return out;
}

// Per mesh point: inside (or on the border of) one of the triangles of
// sa.sectors, within a relative tolerance of its plane. Every point of such
// a triangle lies between the two sides of its small angle, as far as they
// go; on a thin input triangle (a needle or a cap) the whole facet does.
// Only reported: such points are not excused (issue 42 excuses the corner).
std::vector<char> sector_points(const std::vector<double>& xyz, const SmallAngles& sa,
                                const std::vector<char>& wanted) {
  const size_t n = xyz.size() / 3;
  std::vector<char> out(n, 0);
  if (n == 0 || sa.sectors.empty()) return out;
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) lo[c] = std::min(lo[c], xyz[3 * i + c]), hi[c] = std::max(hi[c], xyz[3 * i + c]);
  const double tol = 1e-9 * std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                      (hi[2] - lo[2]) * (hi[2] - lo[2]));
  // Every wanted point against every sector: the wanted points are those of
  // the few tets below the angle, so no grid is needed.
  for (size_t i = 0; i < n; ++i) {
    if (!wanted[i]) continue;
    const double* p = &xyz[3 * i];
    for (const auto& t : sa.sectors) {
      const V3 nrm = cross(vsub(t[1], t[0]), vsub(t[2], t[0]));
      const double area2 = len(nrm);
      if (!(area2 > 0)) continue;
      const V3 ap = {p[0] - t[0].x, p[1] - t[0].y, p[2] - t[0].z};
      if (std::fabs(dot(ap, nrm)) / area2 > tol) continue;
      bool inside = true;
      for (int k = 0; k < 3 && inside; ++k) {
        const V3 e = vsub(t[(k + 1) % 3], t[k]), up = {p[0] - t[k].x, p[1] - t[k].y, p[2] - t[k].z};
        // Signed distance of p from edge k in the triangle's plane.
        inside = dot(cross(e, up), nrm) / area2 >= -tol * len(e);
      }
      if (inside) {
        out[i] = 1;
        break;
      }
    }
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3 && argc != 4) {
    std::fprintf(stderr, "usage: mesh_quality MESH.node MESH.ele [MODEL]\n");
    return 2;
  }
  std::vector<double> xyz;
  long long first = 0;
  if (const std::string bad = bench::read_nodes(argv[1], xyz, first); !bad.empty())
    return bench::fail("mesh_quality", argv[1], bad);
  std::vector<std::array<long long, 4>> tets;
  if (const std::string bad = bench::read_tets(argv[2], static_cast<long long>(xyz.size() / 3), first, tets);
      !bad.empty())
    return bench::fail("mesh_quality", argv[2], bad);

  std::vector<char> excused, in_sector;
  if (argc == 4) {
    cdt3d::Plc plc;
    const cdt3d::Status st = cdt3d::read_plc_file(argv[3], plc);
    if (!st.ok()) return bench::fail("mesh_quality", argv[3], st.error.message);
    const SmallAngles sa = small_angles(plc);
    excused = excused_points(xyz, sa);
    // The points of the tets below kSmallAngle not excused, then which of
    // them lie in a small angle's triangle.
    std::vector<char> wanted(xyz.size() / 3, 0);
    for (const auto& t : tets) {
      const double* p[4];
      bool touches = false;
      for (int k = 0; k < 4; ++k) {
        p[k] = &xyz[3 * static_cast<size_t>(t[k])];
        touches = touches || excused[static_cast<size_t>(t[k])];
      }
      if (!touches && min_dihedral(p) * 180 / kPi < kSmallAngle)
        for (int k = 0; k < 4; ++k) wanted[static_cast<size_t>(t[k])] = 1;
    }
    in_sector = sector_points(xyz, sa, wanted);
  }
  size_t bad = 0, bad_excused = 0, below = 0, below_excused = 0, below_sector = 0;
  double min_angle = HUGE_VAL, min_kept = HUGE_VAL, max_ratio = 0;
  for (size_t t = 0; t < tets.size(); ++t) {
    const double* p[4];
    bool touches = false;
    for (int k = 0; k < 4; ++k) {
      p[k] = &xyz[3 * static_cast<size_t>(tets[t][k])];
      touches = touches || (!excused.empty() && excused[static_cast<size_t>(tets[t][k])]);
    }
    const double ratio = radius_edge(p);
    const double angle = min_dihedral(p) * 180 / kPi;
    if (!(ratio <= 2)) ++bad, bad_excused += touches;
    if (angle < kSmallAngle) ++below, below_excused += touches;
    if (angle < kSmallAngle && !touches && !in_sector.empty()) {
      bool sector = false;
      for (int k = 0; k < 4; ++k) sector = sector || in_sector[static_cast<size_t>(tets[t][k])];
      below_sector += sector;
    }
    max_ratio = std::max(max_ratio, ratio);
    min_angle = std::min(min_angle, angle);
    if (!touches) min_kept = std::min(min_kept, angle);
  }
  const size_t flat = bench::count_flat(xyz, tets, cdt3d::kFlatTetRatio).flat;
  std::printf("%zu %zu %.6g %zu %.4g", tets.size(), bad, tets.empty() ? 0.0 : min_angle, flat, max_ratio);
  if (argc == 4)
    std::printf(" %zu %zu %zu %.6g %zu", bad_excused, below, below_excused,
                std::isfinite(min_kept) ? min_kept : 180.0, below_sector);
  std::printf("\n");
  return 0;
}
