// PointIndex: box queries return exactly the points in the closed box,
// whatever the leaf splits, for clustered points, points on cell borders and
// points outside the root box.
#include <algorithm>
#include <catch2/catch.hpp>
#include <vector>

#include "point_index.hpp"
#include "spatial_sort.hpp"

using namespace cdt3d;

namespace {

std::vector<uint32_t> brute_force(const std::vector<double>& xyz, const double lo[3],
                                  const double hi[3]) {
  std::vector<uint32_t> out;
  for (uint32_t i = 0; 3 * i < xyz.size(); ++i) {
    bool in = true;
    for (int d = 0; d < 3; ++d) in = in && lo[d] <= xyz[3 * i + d] && xyz[3 * i + d] <= hi[d];
    if (in) out.push_back(i);
  }
  return out;
}

}  // namespace

TEST_CASE("PointIndex queries equal a brute-force scan", "[point_index]") {
  Rng rng(7);
  auto coord = [&](uint32_t grid) { return static_cast<double>(rng.below(grid)) / 8; };
  std::vector<double> xyz;
  // A coarse grid (points on cell borders, repeated coordinates), a tight
  // cluster (deep splits) and points outside the root box [0, 8]^3.
  for (int i = 0; i < 2000; ++i)
    for (int d = 0; d < 3; ++d) xyz.push_back(coord(65));
  for (int i = 0; i < 300; ++i)
    for (int d = 0; d < 3; ++d) xyz.push_back(1 + 1e-9 * rng.below(1000));
  for (int i = 0; i < 20; ++i)
    for (int d = 0; d < 3; ++d) xyz.push_back(coord(65) * (d == i % 3 ? -1 : 1) - (d == i % 3));
  PointIndex index;
  const double root_lo[3] = {0, 0, 0}, root_hi[3] = {8, 8, 8};
  index.reset(root_lo, root_hi);
  for (uint32_t i = 0; 3 * i < xyz.size(); ++i) index.insert(i, &xyz[3 * i]);

  std::vector<uint32_t> got;
  for (int q = 0; q < 200; ++q) {
    double lo[3], hi[3];
    for (int d = 0; d < 3; ++d) {
      const double a = coord(80) - 1, b = coord(80) - 1;
      lo[d] = std::min(a, b), hi[d] = std::max(a, b);
    }
    if (q % 10 == 0)
      for (int d = 0; d < 3; ++d) lo[d] = 1, hi[d] = 1 + 5e-7;  // inside the cluster
    index.query(lo, hi, got);
    std::sort(got.begin(), got.end());
    REQUIRE(got == brute_force(xyz, lo, hi));
  }
}

TEST_CASE("PointIndex keeps every copy of a point a leaf cannot split", "[point_index]") {
  // 3 * kLeafSize copies of one point end in a cell of the deepest level,
  // which holds them all (three blocks), beside a few other points.
  PointIndex index;
  const double root_lo[3] = {0, 0, 0}, root_hi[3] = {1, 1, 1};
  index.reset(root_lo, root_hi);
  const double same[3] = {0.25, 0.5, 0.75}, other[3] = {0.75, 0.5, 0.25};
  const uint32_t copies = 3 * PointIndex::kLeafSize;
  for (uint32_t i = 0; i < copies; ++i) index.insert(i, i % 7 == 3 ? other : same);
  std::vector<uint32_t> got, want;
  index.query(same, same, got);
  std::sort(got.begin(), got.end());
  for (uint32_t i = 0; i < copies; ++i)
    if (i % 7 != 3) want.push_back(i);
  REQUIRE(got == want);
  index.query(root_lo, root_hi, got);
  REQUIRE(got.size() == copies);
}
