// find_self_intersections: hand-made configurations of each kind, the models
// of tests/data (valid ones must be clean, the intersecting ones not) and,
// hidden behind [.slow], the shared corpus with timings.
#include <catch2/catch.hpp>
#include <cdt3d/cdt3d.hpp>
#include <chrono>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "corpus.hpp"

#include "plc_intersect.hpp"

using namespace cdt3d;

namespace {

Facet poly(std::vector<VertexId> loop) {
  Facet f;
  f.loops.push_back(std::move(loop));
  return f;
}

std::vector<Intersection> find(const Plc& plc, size_t limit = SIZE_MAX) {
  REQUIRE(check_plc(plc).ok());
  std::vector<Intersection> out;
  find_self_intersections(plc, out, limit);
  return out;
}

// Two triangles: facet 0 = p0 p1 p2, facet 1 = p3 p4 p5 (ids shared by
// passing the same coordinates is not possible: points are distinct).
Plc two_triangles(std::vector<Vec3> pts, std::vector<VertexId> t0, std::vector<VertexId> t1) {
  Plc plc;
  plc.points = std::move(pts);
  plc.facets = {poly(std::move(t0)), poly(std::move(t1))};
  return plc;
}

void add_cube(Plc& plc, double x0, double y0, double z0, double s) {
  const VertexId b = static_cast<VertexId>(plc.points.size());
  for (int i = 0; i < 8; ++i) {
    plc.points.push_back({x0 + s * (i & 1), y0 + s * ((i >> 1) & 1), z0 + s * ((i >> 2) & 1)});
  }
  const VertexId q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                            {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (const auto& f : q) {
    plc.facets.push_back(poly({b + f[0], b + f[1], b + f[2]}));
    plc.facets.push_back(poly({b + f[0], b + f[2], b + f[3]}));
  }
}

std::string describe(const Plc& plc, const std::vector<Intersection>& found) {
  return self_intersection_error(plc, found).error.message;
}

}  // namespace

TEST_CASE("intersect: two crossing triangles", "[intersect]") {
  Plc plc =
      two_triangles({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, -1}, {0.5, 0.5, 1}, {3, 3, 0}},
                    {0, 1, 2}, {3, 4, 5});
  auto f = find(plc);
  REQUIRE(f.size() == 1);
  CHECK(f[0].a == 0);
  CHECK(f[0].b == 1);
  CHECK(f[0].kind == IntersectionKind::Cross);
  // Moved away along z the second triangle no longer meets the first.
  for (int i = 3; i < 6; ++i) plc.points[i].z += 1.5;
  CHECK(find(plc).empty());
}

TEST_CASE("intersect: coplanar overlap", "[intersect]") {
  Plc plc =
      two_triangles({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, 0}, {3, 0.5, 0}, {0.5, 3, 0}},
                    {0, 1, 2}, {3, 4, 5});
  auto f = find(plc);
  REQUIRE(f.size() == 1);
  CHECK(f[0].kind == IntersectionKind::CoplanarOverlap);
}

TEST_CASE("intersect: coplanar triangles sharing an edge", "[intersect]") {
  Plc plc;
  plc.points = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {2, 2, 0}, {1, 0.5, 0}};
  SECTION("opposite sides: proper") {
    plc.facets = {poly({0, 1, 2}), poly({1, 3, 2})};
    CHECK(find(plc).empty());
  }
  SECTION("same side: overlap") {
    plc.facets = {poly({0, 1, 2}), poly({1, 4, 2})};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == IntersectionKind::CoplanarOverlap);
  }
}

TEST_CASE("intersect: shared vertex or edge only", "[intersect]") {
  Plc plc;
  plc.points = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 2}, {-1, -1, 1}, {1, 1, -1}};
  SECTION("edge, folded") {
    plc.facets = {poly({0, 1, 2}), poly({0, 1, 3})};
    CHECK(find(plc).empty());
  }
  SECTION("vertex, other vertices straddling the plane") {
    // Triangle 1 has vertices above and below the plane of triangle 0 but
    // passes beside it.
    plc.facets = {poly({0, 1, 2}), poly({0, 4, 5})};
    plc.points[5] = {-1, 1, -1};
    plc.points[4] = {-1, -1, 1};
    CHECK(find(plc).empty());
  }
  SECTION("vertex, the other triangle passes through") {
    plc.points[4] = {1, 0.2, -1};
    plc.points[5] = {0.2, 1, 1};
    plc.facets = {poly({0, 1, 2}), poly({0, 4, 5})};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == IntersectionKind::Cross);
  }
  SECTION("vertex, coplanar, angles apart") {
    plc.points[4] = {-1, 0, 0};
    plc.points[5] = {0, -1, 0};
    plc.facets = {poly({0, 1, 2}), poly({0, 4, 5})};
    CHECK(find(plc).empty());
  }
  SECTION("vertex, coplanar, angles overlapping") {
    plc.points[4] = {1, 1, 0};
    plc.points[5] = {-1, 1, 0};
    plc.facets = {poly({0, 1, 2}), poly({0, 4, 5})};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == IntersectionKind::CoplanarOverlap);
  }
}

// Contacts along a line: coplanar triangles with an edge line between them,
// and triangles of distinct planes neither of which crosses the other's
// plane. The pair is proper only when the contact is a shared vertex.
TEST_CASE("intersect: contacts along a line", "[intersect]") {
  Plc plc;
  SECTION("coplanar, edge lines apart along the line") {
    plc.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {3, 0, 0}, {3, -1, 0}};
    plc.facets = {poly({0, 1, 2}), poly({3, 5, 4})};
    CHECK(find(plc).empty());
  }
  SECTION("coplanar, a vertex on the other's edge") {
    plc.points = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 0, 0}, {3, -1, 0}, {1, -1, 0}};
    plc.facets = {poly({0, 1, 2}), poly({3, 5, 4})};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == IntersectionKind::VertexInFacet);
  }
  SECTION("coplanar, a shared vertex, edges along one line in opposite directions") {
    plc.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {-1, -1, 0}};
    plc.facets = {poly({0, 1, 2}), poly({0, 4, 3})};
    CHECK(find(plc).empty());
  }
  SECTION("coplanar, a shared vertex, edges along one line overlapping") {
    plc.points = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, -1, 0}};
    plc.facets = {poly({0, 1, 2}), poly({0, 4, 3})};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == IntersectionKind::VertexInFacet);
  }
  SECTION("folded at a shared vertex, edges on the planes' line apart") {
    // A floor triangle and a wall triangle at x = 0 whose edges on the line
    // x = z = 0 leave the shared vertex in opposite directions.
    plc.points = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, -1, 0}, {0, 0, 1}};
    plc.facets = {poly({0, 1, 2}), poly({0, 3, 4})};
    CHECK(find(plc).empty());
  }
  SECTION("folded at a shared vertex, edges on the planes' line overlapping") {
    plc.points = {{0, 0, 0}, {0, 2, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    plc.facets = {poly({0, 1, 2}), poly({0, 3, 4})};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == IntersectionKind::VertexInFacet);
  }
  SECTION("folded, apart along the planes' line, no shared vertex") {
    plc.points = {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {0, 2, 0}, {0, 3, 0}, {0, 2, 1}};
    plc.facets = {poly({0, 1, 2}), poly({3, 4, 5})};
    CHECK(find(plc).empty());
  }
}

// Triangles in axis-parallel planes take a shortcut for their orientation
// tests (a comparison of coordinates): random soups on an integer grid, half
// of their triangles in such planes, must give the same pairs after an
// integer map of determinant 1, which keeps every incidence and maps those
// planes to planes that are not axis-parallel.
TEST_CASE("intersect: axis-parallel planes agree with a sheared copy", "[intersect]") {
  std::mt19937 rng(20261129);
  const int64_t M[3][3] = {{1, 1, 1}, {1, 2, 3}, {1, 3, 6}};  // determinant 1
  size_t pairs = 0;
  for (int c = 0; c < 3000; ++c) {
    const int g = 1 + static_cast<int>(rng() % 4);
    const auto id = [g](int x, int y, int z) { return VertexId((x * (g + 1) + y) * (g + 1) + z); };
    Plc plc, sheared;
    for (int x = 0; x <= g; ++x)
      for (int y = 0; y <= g; ++y)
        for (int z = 0; z <= g; ++z) {
          plc.points.push_back({double(x), double(y), double(z)});
          const int64_t p[3] = {x, y, z};
          double q[3];
          for (int i = 0; i < 3; ++i) q[i] = double(M[i][0] * p[0] + M[i][1] * p[1] + M[i][2] * p[2]);
          sheared.points.push_back({q[0], q[1], q[2]});
        }
    const int n = 2 + static_cast<int>(rng() % 5);
    while (static_cast<int>(plc.facets.size()) < n) {
      int v[3][3];
      for (auto& p : v)
        for (int& x : p) x = static_cast<int>(rng() % (g + 1));
      if (rng() % 2) {  // in the plane x_k = const of the first vertex
        const int k = static_cast<int>(rng() % 3);
        v[1][k] = v[2][k] = v[0][k];
      }
      const int u[3] = {v[1][0] - v[0][0], v[1][1] - v[0][1], v[1][2] - v[0][2]};
      const int w[3] = {v[2][0] - v[0][0], v[2][1] - v[0][1], v[2][2] - v[0][2]};
      if (u[1] * w[2] - u[2] * w[1] == 0 && u[2] * w[0] - u[0] * w[2] == 0 &&
          u[0] * w[1] - u[1] * w[0] == 0)
        continue;  // collinear
      const Facet f = poly({id(v[0][0], v[0][1], v[0][2]), id(v[1][0], v[1][1], v[1][2]),
                            id(v[2][0], v[2][1], v[2][2])});
      plc.facets.push_back(f);
      sheared.facets.push_back(f);
    }
    std::vector<Intersection> a, b;
    find_self_intersections(plc, a);
    find_self_intersections(sheared, b);
    REQUIRE(a.size() == b.size());
    for (size_t i = 0; i < a.size(); ++i) {
      CHECK(a[i].a == b[i].a);
      CHECK(a[i].b == b[i].b);
      CHECK(a[i].kind == b[i].kind);
    }
    pairs += a.size();
  }
  CHECK(pairs > 1000);  // the soups do touch and cross
}

TEST_CASE("intersect: T-junction and vertex in a facet", "[intersect]") {
  Plc plc;
  plc.points = {{0, 0, 0},  {2, 0, 0},     {0, 2, 0},  {1, 0, 0},
                {1, -1, 0}, {0.5, 0.5, 0}, {2, -1, 1}, {0, -1, 1}};
  SECTION("coplanar T-junction: a vertex on an edge, sharing a corner") {
    plc.facets = {poly({0, 1, 2}), poly({0, 4, 3})};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == IntersectionKind::VertexInFacet);
  }
  SECTION("a vertex on an edge from above") {
    plc.facets = {poly({0, 1, 2}), poly({3, 6, 7})};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == IntersectionKind::VertexInFacet);
  }
  SECTION("a vertex in the interior from above") {
    plc.facets = {poly({0, 1, 2}), poly({5, 6, 7})};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == IntersectionKind::VertexInFacet);
  }
  SECTION("a mesh with a T-junction: fan split on one side only") {
    // Square [0,2]^2 split into two triangles on one side of its diagonal and
    // three on the other, with the middle vertex on the diagonal.
    plc.points = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {1, 1, 0}};
    plc.facets = {poly({0, 1, 2}), poly({0, 4, 3}), poly({4, 2, 3})};
    auto f = find(plc);
    REQUIRE(f.size() == 2);
    CHECK(f[0].a == 0);
    CHECK(f[0].b == 1);
    CHECK(f[1].a == 0);
    CHECK(f[1].b == 2);
  }
}

TEST_CASE("intersect: closed cubes", "[intersect]") {
  Plc plc;
  add_cube(plc, 0, 0, 0, 2);
  CHECK(find(plc).empty());
  SECTION("a second, separate cube") {
    add_cube(plc, 3, 0, 0, 1);
    CHECK(find(plc).empty());
  }
  SECTION("a second cube through the first") {
    add_cube(plc, 1, 1, 1, 2);
    auto f = find(plc);
    CHECK(!f.empty());
    for (const auto& x : f) {
      CHECK(x.a < 12);
      CHECK(x.b >= 12);
    }
    Status s = self_intersection_error(plc, f);
    CHECK(s.error.code == ErrorCode::SelfIntersection);
    CHECK(s.error.facet == f[0].a);
    CHECK(s.error.other_facet == f[0].b);
    CHECK(s.error.message.find("The surface intersects itself: facets ") == 0);
    CHECK(s.error.message.find("more pairs") != std::string::npos);
    // The limit stops the search early.
    CHECK(find(plc, 1).size() == 1);
    CHECK(find(plc, 0).empty());
  }
  SECTION("a tetrahedron touching a face with its apex") {
    // Apex (2, 1, 1) lies inside the face x = 2 (on the diagonal of its two
    // triangles).
    const VertexId b = static_cast<VertexId>(plc.points.size());
    plc.points.push_back({2, 1, 1});
    plc.points.push_back({3, 0.5, 0.5});
    plc.points.push_back({3, 1.5, 0.5});
    plc.points.push_back({3, 1, 1.5});
    plc.facets.push_back(poly({b, b + 1, b + 2}));
    plc.facets.push_back(poly({b, b + 2, b + 3}));
    plc.facets.push_back(poly({b, b + 3, b + 1}));
    plc.facets.push_back(poly({b + 1, b + 3, b + 2}));
    auto f = find(plc);
    REQUIRE(f.size() == 6);  // 2 face triangles x 3 tetrahedron faces at the apex
    for (const auto& x : f) CHECK(x.kind == IntersectionKind::VertexInFacet);
  }
  SECTION("a second cube sharing part of a face but no vertices") {
    add_cube(plc, 2, 0.5, 0.5, 1);
    auto f = find(plc);
    REQUIRE(!f.empty());
    bool overlap = false;
    for (const auto& x : f) overlap = overlap || x.kind == IntersectionKind::CoplanarOverlap;
    CHECK(overlap);
  }
  CHECK(self_intersection_error(plc, {}).ok());
}

TEST_CASE("intersect: polygon facets", "[intersect]") {
  // Square 0..3 in z = 0, with an inner square 4..7.
  Plc plc;
  plc.points = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0},  {0, 4, 0},   {1, 1, 0},  {3, 1, 0},
                {3, 3, 0}, {1, 3, 0}, {2, 2, -1}, {2.5, 2, 1}, {2, 2.5, 1}};
  Facet f;
  f.loops = {{0, 1, 2, 3}, {4, 5, 6, 7}};
  SECTION("a hole: a triangle through it does not touch the facet") {
    f.holes.push_back({2, 2, 0});
    plc.facets = {f, poly({8, 9, 10})};
    CHECK(find(plc).empty());
  }
  SECTION("no hole point: the inner loop is only a constraint") {
    plc.facets = {f, poly({8, 9, 10})};
    auto r = find(plc);
    REQUIRE(r.size() == 1);
    CHECK(r[0].kind == IntersectionKind::Cross);
  }
  SECTION("a triangle standing on an inner loop edge is proper") {
    plc.points[9] = {2, 1, 1};
    plc.facets = {f, poly({4, 5, 9})};
    CHECK(find(plc).empty());
  }
  SECTION("a triangle standing on a diagonal is not") {
    // Quad 0..3 has no edge 0-2: the triangle touches its interior,
    // whichever diagonal the triangulation of the quad uses.
    plc.points[9] = {2, 2, 1};
    plc.facets = {poly({0, 1, 2, 3}), poly({0, 2, 9})};
    auto r = find(plc);
    REQUIRE(r.size() == 1);
    CHECK(r[0].kind == IntersectionKind::VertexInFacet);
  }
  SECTION("non-convex loop: a triangle in the notch is free") {
    plc.points = {{0, 0, 0}, {4, 0, 0},  {4, 4, 0},   {2, 1, 0},
                  {0, 4, 0}, {2, 3, -1}, {2.5, 3, 1}, {1.5, 3, 1}};
    plc.facets = {poly({0, 1, 2, 3, 4}), poly({5, 6, 7})};
    CHECK(find(plc).empty());
    plc.points[5] = {2, 0.5, -1};
    plc.points[6] = {2.5, 0.5, 1};
    plc.points[7] = {1.5, 0.5, 1};
    CHECK(find(plc).size() == 1);
  }
}

TEST_CASE("intersect: a facet standing on a segment inside another", "[intersect]") {
  // As in cube_dangling.poly: segment 4-5 lies inside the square 0..3 (a
  // 2-vertex polygon of that facet in TetGen's .poly), and the triangle
  // 4 5 6 stands on it.
  Plc plc;
  plc.points = {{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {0.5, 1, 0}, {1.5, 1, 0}, {1, 1, 1}};
  plc.facets = {poly({0, 1, 2, 3}), poly({4, 5, 6})};
  SECTION("with the segment: proper") {
    plc.segments = {{4, 5}};
    CHECK(find(plc).empty());
  }
  SECTION("without it the triangle's edge lies in the square's interior") {
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == IntersectionKind::VertexInFacet);
  }
  SECTION("the segment covers only part of the edge") {
    plc.points.push_back({1, 1, 0});
    plc.segments = {{4, 7}};
    CHECK(!find(plc).empty());
  }
}

TEST_CASE("intersect: a facet of two loops sharing an edge", "[intersect]") {
  Plc plc;
  plc.points = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {1, 1, 0}, {2, 1, 0}, {1, 0.5, 1}};
  Facet f;
  f.loops = {{0, 1, 4, 3}, {1, 2, 5, 4}};
  plc.facets = {f, poly({1, 4, 6})};
  CHECK(find(plc).empty());  // standing on the shared loop edge 1-4
  plc.points[6] = {0.5, 0.5, 1};
  plc.facets = {f, poly({0, 4, 6})};  // standing on the diagonal 0-4
  CHECK(find(plc).size() == 1);
}

TEST_CASE("intersect: explicit segments", "[intersect]") {
  Plc plc;
  plc.points = {{0, 0, 0},     {2, 0, 0},     {0, 2, 0},  {0.5, 0.5, -1}, {0.5, 0.5, 1},
                {0.5, 0.5, 0}, {0.6, 0.8, 0}, {-1, 1, 0}, {1, -1, 0},     {2, 2, 5}};
  plc.facets = {poly({0, 1, 2})};
  const uint32_t nf = 1;
  SECTION("a segment through a facet") {
    plc.segments = {{3, 4}};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].a == 0);
    CHECK(f[0].b == nf + 0);
    CHECK(f[0].kind == IntersectionKind::Cross);
    Status s = self_intersection_error(plc, f);
    CHECK(s.error.facet == 0);
    CHECK(s.error.other_facet == -1);
    CHECK(s.error.segment >= 0);
    CHECK(s.error.message.find("facet 0 and segment 0 cross") != std::string::npos);
  }
  SECTION("a segment standing on a facet with an endpoint") {
    plc.segments = {{5, 4}};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == IntersectionKind::VertexInFacet);
  }
  SECTION("a segment from a facet vertex away from it") {
    plc.segments = {{0, 9}};
    CHECK(find(plc).empty());
  }
  SECTION("a segment inside the facet is part of it") {
    plc.segments = {{5, 6}};
    CHECK(find(plc).empty());
  }
  SECTION("a segment in the plane of the facet leaving it") {
    plc.segments = {{5, 8}};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == IntersectionKind::VertexInFacet);
  }
  SECTION("two segments crossing") {
    plc.facets.clear();
    plc.segments = {{6, 3}, {7, 8}};
    plc.points[3] = {0, 0, 0.5};
    plc.points[6] = {1, 1, 0.5};
    plc.points[7] = {0, 1, 0.5};
    plc.points[8] = {1, 0, 0.5};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].a == 0);
    CHECK(f[0].b == 1);
    CHECK(f[0].kind == IntersectionKind::SegmentsCross);
  }
  SECTION("a vertex inside a segment") {
    plc.facets.clear();
    plc.points[6] = {1, 1, 0};
    plc.points[7] = {-1, -1, 0};
    plc.points[3] = {0, 0, 3};
    plc.segments = {{6, 7}, {0, 3}};
    auto f = find(plc);
    REQUIRE(f.size() == 1);
    CHECK(f[0].kind == IntersectionKind::VertexOnSegment);
  }
}

TEST_CASE("intersect: models in tests/data", "[intersect]") {
  const std::string dir = CDT3D_TEST_DATA;
  SECTION("intersecting models") {
    for (const char* name : {"intersecting_cubes.off", "triangle_soup.stl"}) {
      INFO(name);
      Plc plc;
      REQUIRE(read_plc_file(dir + "/" + name, plc).ok());
      std::vector<Intersection> f;
      find_self_intersections(plc, f);
      CHECK(!f.empty());
      WARN(name << ": " << f.size() << " pairs; " << describe(plc, f));
    }
  }
  SECTION("valid models are clean") {
    size_t checked = 0;
    for (const auto& row : corpus::read_manifest(dir + "/MANIFEST.tsv")) {
      if (!row.valid()) continue;
      INFO(row.file);
      Plc plc;
      REQUIRE(read_plc_file(dir + "/" + row.file, plc).ok());
      std::vector<Intersection> f;
      find_self_intersections(plc, f);
      CHECK(describe(plc, f) == "");
      ++checked;
    }
    CHECK(checked >= 20);
  }
}

TEST_CASE("intersect: shared corpus (slow)", "[intersect][.slow]") {
  // The shared corpus next to the repository (../shared/corpus), when present.
  const std::string dir = corpus::kData + "/../../../shared/corpus";
  for (const auto& row : corpus::read_manifest(dir + "/MANIFEST.tsv")) {
    const bool valid = row.valid();
    if (!valid && row.expected != "invalid-selfintersect") continue;
    INFO(row.file);
    Plc plc;
    if (!read_plc_file(dir + "/" + row.file, plc).ok()) {
      WARN(row.file << ": not readable, skipped");
      continue;
    }
    std::vector<Intersection> f;
    const auto t0 = std::chrono::steady_clock::now();
    find_self_intersections(plc, f);
    const double ms =
        std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    WARN(row.file << ": " << plc.facets.size() << " facets, " << f.size() << " pairs, " << ms
                  << " ms");
    if (valid) {
      CHECK(describe(plc, f) == "");
    } else {
      CHECK(!f.empty());
    }
  }
}
