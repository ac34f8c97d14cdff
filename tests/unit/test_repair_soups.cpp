// Random triangle soups on small integer grids, repaired and meshed: the
// acceptance test of issue 43 ("200 random soups of every kind, 100% repair
// and mesh into a valid result"). On a grid of a few steps, vertices land on
// other triangles' edges and planes, edges run through corners and lie in
// other triangles' planes, and coplanar triangles overlap in every shape:
// every contact configuration of the arrangement comes up many times.
//
// A soup counts as valid when repair succeeds, the repaired PLC passes
// check_plc() and the exact self-intersection test, and it meshes into a
// result validate() accepts. The test prints the share and fails below
// kExpectedValid (the share reached so far, so that it cannot drop).
#include <catch2/catch.hpp>
#include <cdt3d/cdt3d.hpp>

#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

#include "plc_intersect.hpp"

using namespace cdt3d;

namespace {

constexpr int kSoups = 200;
constexpr int kExpectedValid = 200;

// Our own generator (STYLE.md: the same sequence on every standard library).
class Lcg {
 public:
  explicit Lcg(uint64_t seed) : state_(seed) {}
  int below(int n) {
    state_ = state_ * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<int>((state_ >> 33) % static_cast<uint64_t>(n));
  }

 private:
  uint64_t state_;
};

VertexId add_point(Plc& plc, double x, double y, double z) {
  plc.points.push_back(Vec3{x, y, z});
  return static_cast<VertexId>(plc.points.size() - 1);
}

void add_triangle(Plc& plc, VertexId a, VertexId b, VertexId c) {
  Facet f;
  f.loops.push_back({a, b, c});
  plc.facets.push_back(f);
}

// n triangles with corners on the grid {0..g-1}^3 (open, degenerate ones
// included: repair drops them).
Plc triangle_soup(Lcg& rng, int n, int g) {
  Plc plc;
  for (int t = 0; t < n; ++t) {
    VertexId v[3];
    for (auto& x : v) x = add_point(plc, rng.below(g), rng.below(g), rng.below(g));
    add_triangle(plc, v[0], v[1], v[2]);
  }
  return plc;
}

// Closed parts that interpenetrate: axis-aligned boxes (two triangles a
// side) and tetrahedra with grid corners.
void add_box(Plc& plc, Lcg& rng, int g) {
  int lo[3], hi[3];
  for (int k = 0; k < 3; ++k) {
    lo[k] = rng.below(g - 1);
    hi[k] = lo[k] + 1 + rng.below(g - 1 - lo[k]);
  }
  VertexId v[8];
  for (int i = 0; i < 8; ++i)
    v[i] = add_point(plc, (i & 1) ? hi[0] : lo[0], (i & 2) ? hi[1] : lo[1], (i & 4) ? hi[2] : lo[2]);
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                           {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& q : quads) {
    add_triangle(plc, v[q[0]], v[q[1]], v[q[2]]);
    add_triangle(plc, v[q[0]], v[q[2]], v[q[3]]);
  }
}

void add_tetrahedron(Plc& plc, Lcg& rng, int g) {
  for (;;) {
    double p[4][3];
    for (auto& c : p)
      for (double& x : c) x = rng.below(g);
    const double u[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
    const double v[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
    const double w[3] = {p[3][0] - p[0][0], p[3][1] - p[0][1], p[3][2] - p[0][2]};
    const double det = u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                       u[2] * (v[0] * w[1] - v[1] * w[0]);
    if (det == 0) continue;
    VertexId id[4];
    for (int i = 0; i < 4; ++i) id[i] = add_point(plc, p[i][0], p[i][1], p[i][2]);
    if (det < 0) std::swap(id[0], id[1]);
    add_triangle(plc, id[0], id[2], id[1]);
    add_triangle(plc, id[0], id[1], id[3]);
    add_triangle(plc, id[1], id[2], id[3]);
    add_triangle(plc, id[2], id[0], id[3]);
    return;
  }
}

Plc parts(Lcg& rng, int n, int g, bool boxes) {
  Plc plc;
  for (int i = 0; i < n; ++i) {
    if (boxes && i % 2 == 0) add_box(plc, rng, g);
    else add_tetrahedron(plc, rng, g);
  }
  return plc;
}

// Soup `i`: four kinds in turn (triangles on a 5-grid and on a 3-grid,
// boxes and tetrahedra, tetrahedra only), open kinds meshed with their
// convex hull kept.
Plc make_soup(int i, bool& open) {
  Lcg rng(1000003ull * static_cast<uint64_t>(i) + 17);
  switch (i % 4) {
    case 0: open = true; return triangle_soup(rng, 2 + i % 11, 5);
    case 1: open = true; return triangle_soup(rng, 2 + i % 7, 3);
    case 2: open = false; return parts(rng, 2 + i % 2, 5, true);
    default: open = false; return parts(rng, 2 + i % 3, 4, false);
  }
}

// Empty when soup i ends valid, else what failed.
std::string try_soup(int i) {
  bool open = false;
  const Plc in = make_soup(i, open);
  Plc out;
  RepairReport rep;
  const Status st = repair(in, out, rep);
  if (!st.ok()) return "repair: " + st.error.to_string();
  if (out.facets.empty()) return "";  // only degenerate triangles: nothing to mesh
  const Status checked = check_plc(out);
  if (!checked.ok()) return "check_plc: " + checked.error.to_string();
  std::vector<Intersection> found;
  find_self_intersections(out, found);
  if (!found.empty()) return "self-intersection: " + self_intersection_error(out, found).error.to_string();
  Options opt;
  opt.keep_convex_hull = open;
  const Result r = tetrahedralize(out, opt);
  if (!r.status.ok()) return "mesh: " + r.status.error.to_string();
  const Status v = validate(out, r);
  if (!v.ok()) return "validate: " + v.error.to_string();
  if (r.stats.flat_tets > 0) return std::to_string(r.stats.flat_tets) + " numerically flat tets";
  return "";
}

}  // namespace

TEST_CASE("repair: 200 random integer-grid soups repair and mesh into valid results",
          "[repair][soups]") {
  int valid = 0;
  for (int i = 0; i < kSoups; ++i) {
    const std::string failed = try_soup(i);
    if (failed.empty()) {
      ++valid;
    } else {
      UNSCOPED_INFO("soup " << i << " (kind " << i % 4 << "): " << failed);
    }
  }
  std::cout << "random soups: " << valid << " of " << kSoups << " valid\n";
  CHECK(valid >= kExpectedValid);
}
