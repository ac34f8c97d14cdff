// The quality numbers of a TetGen .node/.ele mesh that issue 17 (quality
// refinement) is judged by: the share of tets whose radius-edge ratio is above
// 2, the smallest dihedral angle, and the numerically flat tets. Used by
// tests/bench/bench_quality.sh on both programs' output (TetGen's M.1.node/.ele
// and cdt3d's `-o PREFIX` files), so that both are measured by the same code,
// not each by its own statistics.
//
// usage: mesh_quality MESH.node MESH.ele
// Build (bench_quality.sh does this; only the header is used):
//   c++ -O2 -std=c++17 -Icore/include tests/bench/mesh_quality.cpp -o mesh_quality
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
// The dihedral angle at edge ij is the angle between the normals e x u and
// e x v (e = pj - pi, u and v from pi to the other two corners), taken with
// atan2 so that angles near 0 and 180 degrees keep their digits.
// Numbering, comments and extra columns as in flat_tets.cpp.
// Exit codes: 0 measured, 1 read error (message on stderr), 2 usage.
#include <cdt3d/cdt3d.hpp>

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
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

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: mesh_quality MESH.node MESH.ele\n");
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

  const double pi = 3.14159265358979323846;
  size_t bad = 0;
  double min_angle = HUGE_VAL, max_ratio = 0;
  for (size_t t = 0; t < tets.size(); ++t) {
    const double* p[4];
    for (int k = 0; k < 4; ++k) p[k] = &xyz[3 * static_cast<size_t>(tets[t][k])];
    const double ratio = radius_edge(p);
    if (!(ratio <= 2)) ++bad;
    max_ratio = std::max(max_ratio, ratio);
    min_angle = std::min(min_angle, min_dihedral(p));
  }
  const size_t flat = bench::count_flat(xyz, tets, cdt3d::kFlatTetRatio).flat;
  std::printf("%zu %zu %.6g %zu %.4g\n", tets.size(), bad, tets.empty() ? 0.0 : min_angle * 180 / pi, flat,
              max_ratio);
  return 0;
}
