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
    double tet_min, tet_max;
    dihedral_range(p, tet_min, tet_max);
    min_dihedral = std::min(min_dihedral, tet_min);
    max_dihedral = std::max(max_dihedral, tet_max);
    size_t dbin = 0;
    while (dbin < 9 && tet_min >= kDihedralBins[dbin]) ++dbin;
    ++stats.dihedral_histogram[dbin];
    // Radius-edge ratio: circumradius over the shortest edge.
    const Vec3 a = p[0] - p[3], b = p[1] - p[3], c = p[2] - p[3];
    const double det = dot(a, cross(b, c));
    double longest = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) longest = std::max(longest, norm(p[i] - p[j]));
    // Numerically flat (or inverted) in doubles: the exact orientation of the
    // stored points is positive, but a user's code that recomputes the volume
    // in floating point would see (almost) nothing.
    if (!(det > kFlatTetRatio * longest * longest * longest)) ++stats.flat_tets;
    const double ratio = det != 0 ? radius_edge_ratio(p) : HUGE_VAL;
    size_t bin = 0;
    while (bin < 9 && ratio >= kRatioBins[bin]) ++bin;
    ++stats.radius_edge_histogram[bin];
  }
  stats.min_dihedral = n ? min_dihedral : 0;
  stats.max_dihedral = n ? max_dihedral : 0;
}

void size_statistics(Result& result) {
  Statistics& s = result.stats;
  s.points = result.mesh.points.size() / 3;
  s.tets = result.mesh.tets.size() / 4;
  s.faces = result.mesh.faces.size() / 3;
  s.steiner_segment = s.steiner_facet = s.steiner_volume = 0;
  for (SteinerKind k : result.steiner_kind) {
    if (k == SteinerKind::Segment) ++s.steiner_segment;
    if (k == SteinerKind::Facet) ++s.steiner_facet;
    if (k == SteinerKind::Volume) ++s.steiner_volume;
  }
}

}  // namespace cdt3d
