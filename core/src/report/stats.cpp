// Quality statistics: dihedral angles and radius-edge ratios of the output
// tets, as TetGen and Gmsh users expect to see them. Floating point only:
// these numbers are reported, never used to decide anything.
#include "stats.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "beside.hpp"
#include "geometry.hpp"

namespace cdt3d {

namespace {

// Upper bounds of the radius-edge histogram bins (the last bin is open), as
// squares: the ratio is compared squared, so no tet costs a square root for it.
constexpr double kRatioBinsSquared[9] = {1, 2.25, 4, 9, 25, 100, 400, 2500, 10000};
// Upper bounds of the per-tet smallest dihedral angle bins, 1, 5, 10, 15,
// 20, 30, 40, 50 and 60 degrees, as their cosines (decreasing): an angle is
// at least a bound when its cosine is at most the bound's cosine, so a tet
// costs no arccosine. Literals, so every platform bins alike.
constexpr double kDihedralBinCosines[9] = {
    0.9998476951563913, 0.9961946980917455, 0.984807753012208, 0.9659258262890683,
    0.9396926207859084, 0.8660254037844387, 0.766044443118978, 0.6427876096865394, 0.5};

double squared(const Vec3& v) { return dot(v, v); }

// The quality numbers of tets [begin, end): cosines of the smallest and the
// largest angle over them, the two histograms and the flat count.
struct QualityPart {
  double cos_min_dihedral = -1, cos_max_dihedral = 1;  // of the smallest / largest angle
  std::array<size_t, 10> radius_edge{}, dihedral{};
  size_t flat = 0;
};

void quality_of_range(const TetMeshData& mesh, size_t begin, size_t end, QualityPart& q) {
  for (size_t t = begin; t < end; ++t) {
    Vec3 p[4];
    for (int i = 0; i < 4; ++i) {
      const double* c = &mesh.points[3 * static_cast<size_t>(mesh.tets[4 * t + i])];
      p[i] = to_vec(c);
    }
    double c_lo, c_hi;  // cosines of the tet's smallest and largest angle
    dihedral_cosines(p, c_lo, c_hi);
    q.cos_min_dihedral = std::max(q.cos_min_dihedral, c_lo);
    q.cos_max_dihedral = std::min(q.cos_max_dihedral, c_hi);
    size_t dbin = 0;
    while (dbin < 9 && c_lo <= kDihedralBinCosines[dbin]) ++dbin;
    ++q.dihedral[dbin];
    // Radius-edge ratio: circumradius over the shortest edge.
    const Vec3 a = p[0] - p[3], b = p[1] - p[3], c = p[2] - p[3];
    const double det = dot(a, cross(b, c));
    double longest2 = 0, shortest2 = HUGE_VAL;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const double l2 = squared(p[i] - p[j]);
        longest2 = std::max(longest2, l2), shortest2 = std::min(shortest2, l2);
      }
    // Numerically flat (or inverted) in doubles: the exact orientation of the
    // stored points is positive, but a user's code that recomputes the volume
    // in floating point would see (almost) nothing.
    const double longest = std::sqrt(longest2);
    if (!(det > kFlatTetRatio * longest * longest * longest)) ++q.flat;
    double ratio2 = HUGE_VAL;
    if (det != 0 && shortest2 > 0) {
      const Vec3 o = sphere_center(p[0], p[1], p[2], p[3]);
      if (finite(o)) ratio2 = squared(o - p[0]) / shortest2;
    }
    size_t bin = 0;
    while (bin < 9 && ratio2 >= kRatioBinsSquared[bin]) ++bin;
    ++q.radius_edge[bin];
  }
}

// Below this many tets a second thread costs more than it saves: starting
// and joining one costs about as much as the statistics of a thousand
// tets.
constexpr size_t kMinTetsBeside = 4000;

}  // namespace

void quality_statistics(const TetMeshData& mesh, Statistics& stats, bool beside) {
  constexpr double kDegrees = 180 / 3.14159265358979323846;
  const size_t n = mesh.tets.size() / 4;
  // Two halves of the tets, the second on the other core: the sums and
  // extremes merge exactly, so the numbers do not depend on the split.
  QualityPart lo, hi;
  run_beside(
      beside && n >= kMinTetsBeside, [&] { quality_of_range(mesh, 0, n / 2, lo); },
      [&] { quality_of_range(mesh, n / 2, n, hi); });
  for (size_t k = 0; k < 10; ++k) {
    stats.radius_edge_histogram[k] = lo.radius_edge[k] + hi.radius_edge[k];
    stats.dihedral_histogram[k] = lo.dihedral[k] + hi.dihedral[k];
  }
  stats.flat_tets = lo.flat + hi.flat;
  const double cos_min_dihedral = std::max(lo.cos_min_dihedral, hi.cos_min_dihedral);
  const double cos_max_dihedral = std::min(lo.cos_max_dihedral, hi.cos_max_dihedral);
  stats.min_dihedral = n ? std::acos(cos_min_dihedral) * kDegrees : 0;
  stats.max_dihedral = n ? std::acos(cos_max_dihedral) * kDegrees : 0;
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
