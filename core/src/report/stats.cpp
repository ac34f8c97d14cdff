// Quality statistics: dihedral angles and radius-edge ratios of the output
// tets, as TetGen and Gmsh users expect to see them. Floating point only:
// these numbers are reported, never used to decide anything.
#include "stats.hpp"

#include <algorithm>
#include <cmath>

#include "geometry.hpp"

namespace cdt3d {

namespace {

// Upper bounds of the radius-edge histogram bins (the last bin is open).
constexpr double kRatioBins[9] = {1, 1.5, 2, 3, 5, 10, 20, 50, 100};
// Upper bounds (degrees) of the per-tet smallest dihedral angle bins.
constexpr double kDihedralBins[9] = {1, 5, 10, 15, 20, 30, 40, 50, 60};

}  // namespace

void quality_statistics(const TetMeshData& mesh, Statistics& stats) {
  const double pi = 3.14159265358979323846;
  double min_dihedral = 180, max_dihedral = 0;
  stats.radius_edge_histogram.fill(0);
  stats.dihedral_histogram.fill(0);
  stats.flat_tets = 0;
  const size_t n = mesh.tets.size() / 4;
  for (size_t t = 0; t < n; ++t) {
    Vec3 p[4];
    for (int i = 0; i < 4; ++i) {
      const double* c = &mesh.points[3 * static_cast<size_t>(mesh.tets[4 * t + i])];
      p[i] = to_vec(c);
    }
    // Face normals (face i opposite vertex i), all pointing outward or all
    // inward: the dihedral angle at the edge shared by faces i and j is
    // pi minus the angle between their normals.
    Vec3 nrm[4];
    for (int i = 0; i < 4; ++i) {
      const Vec3 a = p[(i + 1) % 4], b = p[(i + 2) % 4], c = p[(i + 3) % 4];
      Vec3 m = cross(b - a, c - a);
      if (dot(m, p[i] - a) > 0) m = {-m.x, -m.y, -m.z};  // outward
      nrm[i] = m;
    }
    // The angle 180 - acos(c) * 180 / pi grows with the cosine c between
    // the normals (each step is monotonic), so the tet's smallest and
    // largest angles are those of its smallest and largest c: two acos
    // calls per tet instead of six (they were ~5% of a run).
    double len[4];
    for (int i = 0; i < 4; ++i) len[i] = norm(nrm[i]);
    double c_lo = HUGE_VAL, c_hi = -HUGE_VAL;
    bool degenerate = false;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const double d = len[i] * len[j];
        if (d == 0) {
          degenerate = true;
          continue;
        }
        const double c = std::max(-1.0, std::min(1.0, dot(nrm[i], nrm[j]) / d));
        c_lo = std::min(c_lo, c), c_hi = std::max(c_hi, c);
      }
    auto angle = [&](double c) { return 180 - std::acos(c) * 180 / pi; };
    double tet_min = degenerate ? 0 : 180;
    if (c_lo <= c_hi) {
      tet_min = std::min(tet_min, angle(c_lo));
      min_dihedral = std::min(min_dihedral, angle(c_lo));
      max_dihedral = std::max(max_dihedral, angle(c_hi));
    }
    size_t dbin = 0;
    while (dbin < 9 && tet_min >= kDihedralBins[dbin]) ++dbin;
    ++stats.dihedral_histogram[dbin];
    // Radius-edge ratio: circumradius over the shortest edge.
    const Vec3 a = p[0] - p[3], b = p[1] - p[3], c = p[2] - p[3];
    const double det = dot(a, cross(b, c));
    double shortest = HUGE_VAL, longest = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const double l = norm(p[i] - p[j]);
        shortest = std::min(shortest, l), longest = std::max(longest, l);
      }
    // Numerically flat (or inverted) in doubles: the exact orientation of the
    // stored points is positive, but a user's code that recomputes the volume
    // in floating point would see (almost) nothing.
    if (!(det > kFlatTetRatio * longest * longest * longest)) ++stats.flat_tets;
    double ratio = HUGE_VAL;
    if (det != 0 && shortest > 0) {
      const Vec3 o = sphere_center(p[0], p[1], p[2], p[3]);
      if (finite(o)) ratio = dist(o, p[0]) / shortest;
    }
    size_t bin = 0;
    while (bin < 9 && ratio >= kRatioBins[bin]) ++bin;
    ++stats.radius_edge_histogram[bin];
  }
  stats.min_dihedral = n ? min_dihedral : 0;
  stats.max_dihedral = n ? max_dihedral : 0;
}

}  // namespace cdt3d
