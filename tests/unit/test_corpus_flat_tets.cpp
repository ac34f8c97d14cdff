// No numerically flat tets in the output of any valid model of tests/data.
// A tet is numerically flat when 6V, computed in doubles from the output
// coordinates, is not above kFlatTetRatio * (longest edge)^3 (cdt3d.hpp);
// output tets are positively oriented, so a zero or negative 6V counts too.
// The count is recomputed here from r.mesh.points / r.mesh.tets, so the
// check does not rely on Statistics::flat_tets (stats.cpp).
//
// Hidden from the default Catch2 run: tests/CMakeLists.txt registers one ctest
// per model, "corpus/<model>/flat-tets", which runs this test case with
// CDT3D_MODEL=<model>. Without CDT3D_MODEL it runs every valid model:
//   cdt3d_tests "[flat-tets]"
#include <catch2/catch.hpp>

#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include "corpus.hpp"

using namespace cdt3d;

namespace {

// 6V of tet (a, b, c, d) in doubles: (a - d) . ((b - d) x (c - d)).
double six_volume(const double* a, const double* b, const double* c, const double* d) {
  const double u[3] = {a[0] - d[0], a[1] - d[1], a[2] - d[2]};
  const double v[3] = {b[0] - d[0], b[1] - d[1], b[2] - d[2]};
  const double w[3] = {c[0] - d[0], c[1] - d[1], c[2] - d[2]};
  const double x[3] = {v[1] * w[2] - v[2] * w[1], v[2] * w[0] - v[0] * w[2], v[0] * w[1] - v[1] * w[0]};
  return u[0] * x[0] + u[1] * x[1] + u[2] * x[2];
}

struct FlatCount {
  size_t flat = 0;
  size_t nonpositive = 0;   ///< of which 6V <= 0
  double worst_ratio = HUGE_VAL;  ///< smallest 6V / l_max^3 over all tets
};

FlatCount count_flat_tets(const TetMeshData& m) {
  FlatCount out;
  const size_t n = m.tets.size() / 4;
  for (size_t t = 0; t < n; ++t) {
    const double* p[4];
    for (int k = 0; k < 4; ++k) p[k] = &m.points[3 * static_cast<size_t>(m.tets[4 * t + k])];
    double l2 = 0;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const double dx = p[i][0] - p[j][0], dy = p[i][1] - p[j][1], dz = p[i][2] - p[j][2];
        l2 = std::max(l2, dx * dx + dy * dy + dz * dz);
      }
    const double l = std::sqrt(l2);
    const double v6 = six_volume(p[0], p[1], p[2], p[3]);
    if (!(v6 > kFlatTetRatio * l * l * l)) {
      ++out.flat;
      if (!(v6 > 0)) ++out.nonpositive;
    }
    if (l > 0) out.worst_ratio = std::min(out.worst_ratio, v6 / (l * l * l));
  }
  return out;
}

}  // namespace

TEST_CASE("corpus: no numerically flat tets in the output", "[.][flat-tets][corpus]") {
  std::vector<std::string> models;
  const char* only = std::getenv("CDT3D_MODEL");
  if (only && *only) {
    const std::vector<std::string> valid = corpus::valid_models();
    INFO("CDT3D_MODEL=" << only);
    REQUIRE(std::find(valid.begin(), valid.end(), std::string(only)) != valid.end());
    models.push_back(only);
  } else {
    models = corpus::valid_models();
    REQUIRE(!models.empty());
  }
  for (const std::string& file : models) {
    INFO(file);
    Plc plc;
    const Status read = read_plc_file(corpus::kData + "/" + file, plc);
    INFO(read.error.to_string());
    REQUIRE(read.ok());
    const Result r = tetrahedralize(plc);
    INFO(r.status.error.to_string());
    REQUIRE(r.status.ok());
    REQUIRE(r.mesh.tets.size() == 4 * r.stats.tets);
    const FlatCount c = count_flat_tets(r.mesh);
    INFO("recomputed: " << c.flat << " flat tets (" << c.nonpositive << " with 6V <= 0) of "
                        << r.stats.tets << ", smallest 6V / l_max^3 = " << c.worst_ratio
                        << "; Statistics::flat_tets = " << r.stats.flat_tets
                        << ", flat_flips = " << r.stats.flat_flips);
    CHECK(c.flat == 0);
    CHECK(r.stats.flat_tets == c.flat);
    REQUIRE(r.stats.flat_tets == 0);
  }
}

TEST_CASE("the flat-tet count of the corpus check", "[flat-tets-count]") {
  // Unit tet, a sliver of height 1e-13 (6V / l^3 below 1e-12), the unit tet
  // inverted, and a tet of height 1e-6 (not flat).
  TetMeshData m;
  m.points = {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 0.25, 0.25, 1e-13, 0.25, 0.25, 1e-6};
  // six_volume(a, b, c, d) = (a - d) . ((b - d) x (c - d)) > 0 for (1, 2, 3, 0).
  m.tets = {1, 2, 3, 0, 1, 2, 4, 0, 2, 1, 3, 0, 1, 2, 5, 0};
  const FlatCount c = count_flat_tets(m);
  CHECK(c.flat == 2);
  CHECK(c.nonpositive == 1);
}
