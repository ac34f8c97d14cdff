// check_plc on PLCs built in code, plc_info and plc_segments.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cdt3d/cdt3d.hpp>
#include <cmath>
#include <limits>

using namespace cdt3d;

namespace {

Facet tri(VertexId a, VertexId b, VertexId c, int64_t line = -1) {
  Facet f;
  f.loops.push_back({a, b, c});
  f.line = line;
  return f;
}

Plc tetrahedron() {
  Plc plc;
  plc.file = "code";
  plc.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  plc.facets = {tri(0, 2, 1, 10), tri(0, 1, 3, 11), tri(1, 2, 3, 12), tri(0, 3, 2, 13)};
  return plc;
}

}  // namespace

TEST_CASE("check_plc accepts a valid PLC", "[plc_check]") {
  CHECK(check_plc(tetrahedron()).ok());
  Plc empty;
  CHECK(check_plc(empty).ok());
}

TEST_CASE("check_plc: coordinates", "[plc_check]") {
  Plc plc = tetrahedron();
  plc.points[2].y = std::numeric_limits<double>::quiet_NaN();
  Status s = check_plc(plc);
  CHECK(s.error.code == ErrorCode::NonFinite);
  CHECK(s.error.vertex == 2);
  CHECK(s.error.file == "code");

  plc = tetrahedron();
  plc.points[3].z = -std::numeric_limits<double>::infinity();
  CHECK(check_plc(plc).error.code == ErrorCode::NonFinite);

  plc = tetrahedron();
  plc.points[1].x = 2 * kMaxCoordinate;
  s = check_plc(plc);
  CHECK(s.error.code == ErrorCode::CoordinateRange);
  CHECK(s.error.vertex == 1);

  plc = tetrahedron();
  plc.points[1].x = -kMaxCoordinate;
  CHECK(check_plc(plc).ok());
}

TEST_CASE("check_plc: points must be distinct", "[plc_check]") {
  Plc plc = tetrahedron();
  plc.points.push_back(plc.points[1]);
  const Status s = check_plc(plc);
  CHECK(s.error.code == ErrorCode::InvalidArgument);
  CHECK(s.error.vertex == 4);
  // -0 equals +0: the hash pass must see these two as the same point.
  Plc z = tetrahedron();
  z.points.push_back({-0.0, 7, 7});
  z.points.push_back({0.0, 7, 7});
  const Status sz = check_plc(z);
  CHECK(sz.error.code == ErrorCode::InvalidArgument);
  CHECK(sz.error.vertex == 5);
  // Many points, one pair equal: named as before (the later one).
  Plc many = tetrahedron();
  for (int i = 0; i < 1000; ++i) many.points.push_back({10.0 + i, 0.5 * i, -1.0 * i});
  many.points.push_back({10.0 + 321, 0.5 * 321, -1.0 * 321});
  const Status sm = check_plc(many);
  CHECK(sm.error.code == ErrorCode::InvalidArgument);
  CHECK(sm.error.vertex == 1004);
}

TEST_CASE("check_plc: indices in range", "[plc_check]") {
  Plc plc = tetrahedron();
  plc.facets[2].loops[0][1] = 4;
  const Status s = check_plc(plc);
  CHECK(s.error.code == ErrorCode::IndexOutOfRange);
  CHECK(s.error.facet == 2);
  CHECK(s.error.line == 12);

  plc = tetrahedron();
  plc.segments.push_back({0, kNone});
  CHECK(check_plc(plc).error.code == ErrorCode::IndexOutOfRange);
}

TEST_CASE("check_plc: degenerate loops", "[plc_check]") {
  SECTION("no loop") {
    Plc plc = tetrahedron();
    plc.facets[1].loops.clear();
    const Status s = check_plc(plc);
    CHECK(s.error.code == ErrorCode::DegenerateFacet);
    CHECK(s.error.facet == 1);
  }
  SECTION("two vertices") {
    Plc plc = tetrahedron();
    plc.facets[3].loops[0].pop_back();
    const Status s = check_plc(plc);
    CHECK(s.error.code == ErrorCode::DegenerateFacet);
    CHECK(s.error.facet == 3);
    CHECK(s.error.line == 13);
  }
  SECTION("repeated vertex") {
    Plc plc = tetrahedron();
    plc.facets[0].loops[0] = {0, 2, 1, 2};
    const Status s = check_plc(plc);
    CHECK(s.error.code == ErrorCode::DegenerateFacet);
    CHECK(s.error.vertex == 2);
  }
  SECTION("collinear, exactly") {
    Plc plc;
    // (0,0,0), (3,3,3)/10 rounded, ... : 0.1 * 3 is not exactly 0.3, so use
    // exact multiples of a power of two for the collinear case.
    plc.points = {{0, 0, 0}, {0.25, 0.5, 0.75}, {1, 2, 3}, {0.5, 1, 1.5}};
    plc.facets.push_back(tri(0, 1, 2));
    Status s = check_plc(plc);
    CHECK(s.error.code == ErrorCode::DegenerateFacet);
    Facet quad;
    quad.loops.push_back({0, 1, 3, 2});
    plc.facets = {quad};
    CHECK(check_plc(plc).error.code == ErrorCode::DegenerateFacet);
    // Off the line by one unit in the last place: a proper (thin) triangle.
    plc.points[2].z = std::nextafter(3.0, 4.0);
    plc.facets = {tri(0, 1, 2)};
    CHECK(check_plc(plc).ok());
  }
  SECTION("segment with identical endpoints") {
    Plc plc = tetrahedron();
    plc.segments.push_back({2, 2});
    CHECK(check_plc(plc).error.code == ErrorCode::DegenerateFacet);
  }
}

TEST_CASE("check_plc: planarity is exact", "[plc_check]") {
  Plc plc;
  plc.points = {{0, 0, 0}, {1e30, 0, 0}, {1e30, 1e30, 0}, {0, 1e30, 0}};
  Facet quad;
  quad.loops.push_back({0, 1, 2, 3});
  quad.record = 5;
  plc.facets.push_back(quad);
  CHECK(check_plc(plc).ok());
  // The smallest possible lift of one vertex.
  plc.points[2].z = std::numeric_limits<double>::denorm_min();
  Status s = check_plc(plc);
  CHECK(s.error.code == ErrorCode::NonPlanarFacet);
  CHECK(s.error.vertex == 3);  // off the plane through vertices 0, 1, 2
  CHECK(s.error.record == 5);
  // A slanted plane z = x + 2y with exact points, several loops.
  plc.points = {{0, 0, 0}, {4, 0, 4}, {4, 4, 12}, {0, 4, 8}, {1, 1, 3}, {2, 1, 4}, {1, 2, 5}};
  Facet f;
  f.loops.push_back({0, 1, 2, 3});
  f.loops.push_back({4, 5, 6});
  plc.facets = {f};
  CHECK(check_plc(plc).ok());
  plc.points[5].z = 4.5;
  s = check_plc(plc);
  CHECK(s.error.code == ErrorCode::NonPlanarFacet);
  CHECK(s.error.vertex == 5);
}

TEST_CASE("check_plc: duplicate facets", "[plc_check]") {
  Plc plc = tetrahedron();
  plc.facets.push_back(tri(3, 1, 0, 20));  // facet 1 reversed
  plc.facets.push_back(tri(2, 0, 1, 21));  // facet 0 rotated
  const Status s = check_plc(plc);
  CHECK(s.error.code == ErrorCode::DuplicateFacet);
  CHECK(s.error.facet == 4);
  CHECK(s.error.other_facet == 1);
  CHECK(s.error.line == 20);
}

// Facets are compared in groups that share their key's first vertex: a
// fan of many triangles around one vertex is one large group (sorted), a
// few facets are compared pairwise; facets with several loops too.
TEST_CASE("check_plc: duplicate facets in a fan and with holes", "[plc_check]") {
  Plc plc;
  plc.points.push_back({0, 0, 0});
  const int n = 40;
  for (int i = 0; i < n; ++i) {
    const double t = 6.283185307179586 * i / n;
    plc.points.push_back({std::cos(t), std::sin(t), 0});
  }
  for (int i = 0; i < n; ++i) {
    plc.facets.push_back(tri(0, static_cast<VertexId>(1 + i), static_cast<VertexId>(1 + (i + 1) % n)));
  }
  CHECK(check_plc(plc).ok());
  plc.facets.push_back(tri(static_cast<VertexId>(1 + 17), 0, static_cast<VertexId>(1 + 18), 30));
  Status s = check_plc(plc);
  CHECK(s.error.code == ErrorCode::DuplicateFacet);
  CHECK(s.error.facet == n);
  CHECK(s.error.other_facet == 17);
  CHECK(s.error.line == 30);
  // Two square facets with a square hole, in the plane z = 0; the second
  // lists its loops the other way round, then a third is the same facet.
  Plc holes;
  holes.points = {{0, 0, 0}, {4, 0, 0}, {4, 4, 0}, {0, 4, 0}, {1, 1, 0}, {2, 1, 0},
                  {2, 2, 0}, {1, 2, 0}, {3, 3, 0}, {3.5, 3, 0}, {3.5, 3.5, 0}};
  Facet a;
  a.loops = {{0, 1, 2, 3}, {4, 5, 6, 7}};
  Facet b;
  b.loops = {{8, 9, 10}, {0, 1, 2, 3}};
  holes.facets = {a, b};
  CHECK(check_plc(holes).ok());
  Facet c;
  c.loops = {{10, 8, 9}, {3, 0, 1, 2}};
  holes.facets.push_back(c);
  s = check_plc(holes);
  CHECK(s.error.code == ErrorCode::DuplicateFacet);
  CHECK(s.error.facet == 2);
  CHECK(s.error.other_facet == 1);
}

TEST_CASE("plc_segments: the same edges as sorting every facet edge", "[plc_check]") {
  // Random triangles over 60 points (valid or not: plc_segments only reads
  // the loops), with many edges shared by several triangles.
  Plc plc;
  for (int i = 0; i < 60; ++i) plc.points.push_back({double(i), double(i * i % 7), 0});
  uint64_t state = 12345;
  auto next = [&state] {
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    return static_cast<VertexId>(state % 60);
  };
  std::vector<std::array<VertexId, 2>> want;
  for (int f = 0; f < 3000; ++f) {
    const VertexId v[3] = {next(), next(), next()};
    plc.facets.push_back(tri(v[0], v[1], v[2]));
    for (int k = 0; k < 3; ++k) {
      const VertexId x = v[k], y = v[(k + 1) % 3];
      if (x != y) want.push_back({std::min(x, y), std::max(x, y)});
    }
  }
  std::sort(want.begin(), want.end());
  want.erase(std::unique(want.begin(), want.end()), want.end());
  CHECK(plc_segments(plc) == want);
  CHECK(plc_info(plc).segments == want.size());
}

TEST_CASE("check_plc: holes and regions must be finite", "[plc_check]") {
  Plc plc = tetrahedron();
  plc.holes.push_back({0.1, std::numeric_limits<double>::quiet_NaN(), 0.1});
  CHECK(check_plc(plc).error.code == ErrorCode::NonFinite);
  plc = tetrahedron();
  Region r;
  r.point = {0.1, 0.1, 0.1};
  r.attribute = std::numeric_limits<double>::infinity();
  plc.regions.push_back(r);
  CHECK(check_plc(plc).error.code == ErrorCode::NonFinite);
}

TEST_CASE("plc_segments: explicit and loop edges, sorted and unique", "[plc_check]") {
  Plc plc = tetrahedron();
  plc.points.push_back({5, 5, 5});
  plc.segments.push_back({4, 0});
  plc.segments.push_back({2, 1});  // also a facet edge
  const auto segs = plc_segments(plc);
  const std::vector<std::array<VertexId, 2>> want = {{0, 1}, {0, 2}, {0, 3}, {0, 4},
                                                     {1, 2}, {1, 3}, {2, 3}};
  CHECK(segs == want);
  const PlcInfo info = plc_info(plc);
  CHECK(info.segments == 7);
  CHECK(info.unreferenced == 0);
  CHECK(info.triangles == 4);
  CHECK(info.loops == 4);
  CHECK(info.bbox_max.x == 5);
  CHECK(info.bbox_min.y == 0);
}

TEST_CASE("plc_info of an empty PLC", "[plc_check]") {
  const PlcInfo info = plc_info(Plc());
  CHECK(info.points == 0);
  CHECK(info.triangles == 0);
  CHECK(info.bbox_min.x == 0);
  CHECK(info.bbox_max.z == 0);
}
