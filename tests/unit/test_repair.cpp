// repair(): each step on small hand-made PLCs (counts, provenance, exact
// geometry kept), and the acceptance tests over tests/data: every defective
// model of a repairable kind becomes a PLC that passes check_plc() and the
// exact self-intersection test, meshes, and validates; every valid model
// comes out unchanged.
#include <catch2/catch.hpp>
#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "corpus.hpp"
#include "geometry.hpp"
#include "plc_intersect.hpp"
#include "repair.hpp"

using namespace cdt3d;

namespace {

Plc from_text(const std::string& text, const std::string& name) {
  Plc plc;
  const Status st =
      read_plc(reinterpret_cast<const uint8_t*>(text.data()), text.size(), name, plc, false);
  REQUIRE(st.ok());
  return plc;
}

// The repaired PLC is a valid PLC: input checks and the exact
// self-intersection test pass, it meshes and the result validates.
// keep_hull: for a model that is open once repaired (chair_model.obj).
Result require_meshable(const Plc& plc, bool keep_hull = false) {
  const Status checked = check_plc(plc);
  INFO(checked.error.to_string());
  REQUIRE(checked.ok());
  std::vector<Intersection> found;
  find_self_intersections(plc, found);
  REQUIRE(self_intersection_error(plc, found).error.to_string() == Status().error.to_string());
  Options opt;
  opt.keep_convex_hull = keep_hull;
  Result r = tetrahedralize(plc, opt);
  INFO(r.status.error.to_string());
  REQUIRE(r.status.ok());
  const Status v = validate(plc, r);
  INFO(v.error.to_string());
  REQUIRE(v.ok());
  // Every tet usable: repair collapses the needles whose splits would make
  // numerically flat tets (chair_model.obj had two before kNeedleGridSteps
  // was raised to 2^22).
  CHECK(r.stats.flat_tets == 0);
  return r;
}

// Point v of the output is point v of the input moved by at most half a
// step of the snap grid (repair_crossing.cpp: 2^-40 below the binary order of
// the largest coordinate).
bool moved_by_snapping(const Plc& in, const Plc& out, size_t v) {
  double big = 0;
  for (const Vec3& p : in.points) big = std::max({big, std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)});
  const double half = std::ldexp(1.0, std::ilogb(big) - 41);
  const Vec3 &a = in.points[v], &b = out.points[v];
  return std::fabs(a.x - b.x) <= half && std::fabs(a.y - b.y) <= half && std::fabs(a.z - b.z) <= half;
}

// repair() with fill_holes on a surface with one hole: it is filled.
RepairReport fill_one_hole(const Plc& in, Plc& out) {
  RepairReport rep;
  RepairOptions options;
  options.fill_holes = true;
  REQUIRE(repair(in, out, rep, options).ok());
  CHECK(rep.filled_holes == 1);
  CHECK(rep.unfilled_holes == 0);
  return rep;
}

const char* kCube =
    "OFF\n8 12 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
    "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n"
    "3 1 2 6\n3 1 6 5\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n";

}  // namespace

TEST_CASE("repair: a valid PLC comes out unchanged", "[repair]") {
  const Plc in = from_text(kCube, "cube.off");
  Plc out;
  RepairReport rep;
  REQUIRE(repair(in, out, rep).ok());
  CHECK_FALSE(rep.changed());
  CHECK(rep.changed_facets.empty());
  REQUIRE(out.facets.size() == in.facets.size());
  for (size_t f = 0; f < in.facets.size(); ++f) {
    CHECK(out.facets[f].loops == in.facets[f].loops);
    CHECK(rep.facet_source[f] == f);
  }
  CHECK(out.points.size() == in.points.size());
}

TEST_CASE("repair step 1: welding, repeated vertices, zero area, duplicates", "[repair]") {
  std::string text = kCube;
  // Facet 12 repeats facet 3 backwards, 13 repeats a vertex (a triangle
  // that is only an edge), 14 has collinear vertices.
  text.replace(text.find("8 12 0"), 6, "8 15 0");
  text += "3 7 6 4\n3 0 0 1\n3 0 1 1\n";
  Plc in = from_text(text, "cube.off");
  // An identical point added by hand (readers weld on their own): facet 0
  // uses it instead of point 0.
  in.points.push_back(in.points[0]);
  in.facets[0].loops[0][0] = 8;
  Plc out;
  RepairReport rep;
  REQUIRE(repair(in, out, rep).ok());
  CHECK(rep.welded_points == 1);
  CHECK(rep.duplicate_facets == 1);
  CHECK(rep.repeated_vertices == 2);
  CHECK(rep.zero_area_polygons == 2);
  CHECK(rep.degenerate_facets == 2);
  CHECK(out.points.size() == 8);
  CHECK(out.facets.size() == 12);
  CHECK(rep.changed_facets == std::vector<uint32_t>{0, 12, 13, 14});
  CHECK(out.facets[0].loops[0] == std::vector<VertexId>{0, 2, 1});
  require_meshable(out);
}

TEST_CASE("repair step 1: a polygon that comes back to a vertex is cut into its lobes",
          "[repair]") {
  // Two squares of the plane z = 0 joined at (1,1,0) written as one polygon.
  Plc in;
  in.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {2, 1, 0}, {2, 2, 0}, {1, 2, 0}};
  Facet f;
  f.loops = {{0, 1, 2, 4, 5, 6, 2, 3}};
  f.marker = 7;
  in.facets.push_back(f);
  Plc out;
  RepairReport rep;
  repair(in, out, rep);  // an open surface: only the facets matter here
  CHECK(rep.repeated_vertices == 1);
  REQUIRE(out.facets.size() == 2);
  CHECK(out.facets[0].loops[0] == std::vector<VertexId>{2, 4, 5, 6});
  CHECK(out.facets[1].loops[0] == std::vector<VertexId>{0, 1, 2, 3});
  CHECK(out.facets[1].marker == 7);
  CHECK(rep.facet_source == std::vector<uint32_t>{0, 0});
  CHECK(check_plc(out).ok());
}

TEST_CASE("repair step 2: a non-planar quad becomes two planar triangles", "[repair]") {
  const Plc in = from_text(
      "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1.25\nv 0 1 1\n"
      "f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 4 8 7 3\nf 1 5 8 4\nf 2 3 7 6\n",
      "hex.obj");
  REQUIRE(check_plc(in).error.code == ErrorCode::NonPlanarFacet);
  Plc out;
  RepairReport rep;
  REQUIRE(repair(in, out, rep).ok());
  CHECK(rep.nonplanar_facets == 1);
  REQUIRE(out.facets.size() == 7);
  CHECK(rep.facet_source == std::vector<uint32_t>{0, 1, 1, 2, 3, 4, 5});
  CHECK(rep.changed_facets == std::vector<uint32_t>{1});
  // The two triangles cover the quad's four corners, and keep its line.
  std::vector<VertexId> corners;
  for (int k : {1, 2}) {
    REQUIRE(out.facets[k].loops[0].size() == 3);
    CHECK(out.facets[k].line == in.facets[1].line);
    corners.insert(corners.end(), out.facets[k].loops[0].begin(), out.facets[k].loops[0].end());
  }
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  CHECK(corners == std::vector<VertexId>{4, 5, 6, 7});
  require_meshable(out);
}

TEST_CASE("repair step 3: T-junctions on an edge and inside a facet", "[repair]") {
  const std::string dir = corpus::kData + "/";
  SECTION("vertices inside the edges of two quads are inserted into them") {
    Plc in, out;
    REQUIRE(read_plc_file(dir + "tjunction_box.off", in).ok());
    std::vector<Intersection> found;
    find_self_intersections(in, found);
    REQUIRE_FALSE(found.empty());
    RepairReport rep;
    REQUIRE(repair(in, out, rep).ok());
    CHECK(rep.tjunction_vertices == 2);
    CHECK(rep.tjunction_facets == 2);
    CHECK(out.points.size() == in.points.size());  // no new coordinates
    REQUIRE(out.facets.size() == 7);
    CHECK(out.facets[3].loops[0] == std::vector<VertexId>{0, 1, 5, 8, 4});
    CHECK(out.facets[4].loops[0] == std::vector<VertexId>{3, 7, 9, 6, 2});
    CHECK(rep.changed_facets == std::vector<uint32_t>{3, 4});
    require_meshable(out);
  }
  SECTION("a facet with a vertex inside it is triangulated with that vertex") {
    Plc in, out;
    REQUIRE(read_plc_file(dir + "tjunction_apex.off", in).ok());
    RepairReport rep;
    REQUIRE(repair(in, out, rep).ok());
    CHECK(rep.tjunction_vertices == 1);
    CHECK(rep.changed_facets == std::vector<uint32_t>{1});
    CHECK(out.points.size() == in.points.size());
    size_t with_apex = 0;
    for (size_t f = 0; f < out.facets.size(); ++f) {
      if (rep.facet_source[f] != 1) continue;
      const auto& l = out.facets[f].loops[0];
      CHECK(l.size() == 3);
      with_apex += std::count(l.begin(), l.end(), VertexId{8});
    }
    CHECK(with_apex == 4);  // the top quad became 4 triangles around the apex
    require_meshable(out);
  }
}

TEST_CASE("repair: results are mapped back to input facets", "[repair]") {
  Plc in, out;
  REQUIRE(read_plc_file(corpus::kData + "/tjunction_apex.off", in).ok());
  RepairReport rep;
  REQUIRE(repair(in, out, rep).ok());
  Result r = tetrahedralize(out);
  REQUIRE(r.status.ok());
  REQUIRE(validate(out, r).ok());
  map_to_input_facets(rep, r);
  std::vector<size_t> faces_of(in.facets.size(), 0);
  for (uint32_t f : r.face_facet) {
    REQUIRE(f < in.facets.size());
    ++faces_of[f];
  }
  for (size_t f = 0; f < in.facets.size(); ++f) CHECK(faces_of[f] > 0);
}

TEST_CASE("repair: what cannot be repaired names the input", "[repair]") {
  Plc in = from_text(kCube, "cube.off");
  in.points[3].x = std::numeric_limits<double>::quiet_NaN();
  Plc out;
  RepairReport rep;
  const Status st = repair(in, out, rep);
  CHECK(st.error.code == ErrorCode::NonFinite);
  CHECK(st.error.vertex == 3);
}

TEST_CASE("write_poly: a repaired PLC reads back as the same PLC", "[repair][io]") {
  Plc in, out, back;
  REQUIRE(read_plc_file(corpus::kData + "/cube_dangling.poly", in).ok());
  const std::string text = write_poly(in);
  REQUIRE(read_plc(reinterpret_cast<const uint8_t*>(text.data()), text.size(), "x.poly", back).ok());
  CHECK(back.points.size() == in.points.size());
  REQUIRE(back.facets.size() == in.facets.size());
  for (size_t f = 0; f < in.facets.size(); ++f) {
    CHECK(back.facets[f].loops == in.facets[f].loops);
    CHECK(back.facets[f].marker == in.facets[f].marker);
  }
  CHECK(back.segments == in.segments);
  CHECK(plc_segments(back) == plc_segments(in));
}

namespace {

bool repairable(const std::string& expected) {
  return expected == "invalid-selfintersect" || expected == "invalid-duplicate" ||
         expected == "invalid-degenerate" || expected == "invalid-nonplanar";
}

}  // namespace

// The acceptance tests of the repair issue over tests/data.
TEST_CASE("repair: tests/data models", "[repair][corpus]") {
  size_t valid = 0, repaired = 0;
  for (const corpus::Row& row : corpus::read_manifest()) {
    if (!row.valid() && !repairable(row.expected)) continue;
    INFO(row.file << " (" << row.expected << ")");
    Plc in, out;
    REQUIRE(read_plc_file(corpus::kData + "/" + row.file, in, false).ok());
    RepairReport rep;
    const Status st = repair(in, out, rep);
    INFO(st.error.to_string());
    REQUIRE(st.ok());
    if (row.valid()) {
      ++valid;
      CHECK_FALSE(rep.changed());
      REQUIRE(out.facets.size() == in.facets.size());
      bool same = out.points.size() == in.points.size();
      for (size_t f = 0; f < in.facets.size() && same; ++f)
        same = out.facets[f].loops == in.facets[f].loops;
      CHECK(same);
      continue;
    }
    ++repaired;
    CHECK(rep.changed());
    require_meshable(out);
  }
  CHECK(valid >= 20);
  CHECK(repaired >= 5);
}

TEST_CASE("repair step 4: crossing models of tests/data", "[repair][corpus]") {
  for (const char* name : {"intersecting_cubes.off", "crossing_tets.off", "coplanar_boxes.off"}) {
    INFO(name);
    Plc in, out;
    REQUIRE(read_plc_file(corpus::kData + "/" + name, in, false).ok());
    RepairReport rep;
    RepairOptions every_cell;  // step 4 alone: the union (step 5) drops points
    every_cell.union_of_parts = false;
    const Status st = repair(in, out, rep, every_cell);
    INFO(st.error.to_string());
    REQUIRE(st.ok());
    CHECK(rep.crossing_pairs > 0);
    CHECK(rep.intersection_points > 0);
    CHECK(rep.unresolved_pairs == 0);
    // The input's points are the first points of the output, snap rounded:
    // each moved by at most half a grid step (the grid is 2^-40 of the
    // largest coordinate's binary order), and every output facet names an
    // input facet.
    REQUIRE(out.points.size() > in.points.size());
    for (size_t v = 0; v < in.points.size(); ++v) CHECK(moved_by_snapping(in, out, v));
    for (uint32_t f : rep.facet_source) CHECK(f < in.facets.size());
    require_meshable(out);
  }
}

TEST_CASE("repair step 4: a soup of crossing triangles, with triple points", "[repair]") {
  // 100 random triangles of tests/data (an open soup): many triangles cross
  // several others, so intersection segments cross inside triangles.
  Plc in, out;
  REQUIRE(read_plc_file(corpus::kData + "/triangle_soup.stl", in, false).ok());
  RepairReport rep;
  const Status st = repair(in, out, rep);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  CHECK(rep.crossing_pairs > 1000);
  // More new points than crossing pairs: the triple points.
  CHECK(rep.intersection_points > rep.crossing_pairs);
  CHECK(rep.unresolved_pairs == 0);
  REQUIRE(check_plc(out).ok());
  std::vector<Intersection> found;
  find_self_intersections(out, found);
  CHECK(found.empty());
  for (size_t v = 0; v < in.points.size(); ++v) CHECK(moved_by_snapping(in, out, v));
  // Still open: meshing says so, naming an input facet after the mapping.
  Result r = tetrahedralize(out);
  CHECK(r.status.error.code == ErrorCode::OpenBoundary);
  map_to_input_facets(rep, r);
  CHECK(r.status.error.facet >= 0);
  CHECK(r.status.error.facet < static_cast<int64_t>(in.facets.size()));
}

TEST_CASE("repair step 4: triangles that share a vertex and cross", "[repair]") {
  Plc in;
  in.points = {{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {1, 0.5, 1}, {0.5, 1, -1}};
  for (auto t : {std::vector<VertexId>{0, 1, 2}, std::vector<VertexId>{0, 3, 4}}) {
    Facet f;
    f.loops.push_back(t);
    in.facets.push_back(f);
  }
  std::vector<Intersection> found;
  find_self_intersections(in, found);
  REQUIRE(found.size() == 1);
  Plc out;
  RepairReport rep;
  REQUIRE(repair(in, out, rep).ok());
  CHECK(rep.crossing_pairs == 1);
  CHECK(rep.intersection_points == 1);  // the segment runs from the shared vertex
  REQUIRE(out.points.size() == 6);
  CHECK(out.points[5] == Vec3{0.75, 0.75, 0});  // exact here: every step is a dyadic
  find_self_intersections(out, found);
  CHECK(found.empty());
}

TEST_CASE("repair step 4: a box and its near copy meet in no needle", "[repair]") {
  // A unit box and a copy moved by 3e-9 and sheared by 2e-9: the exact
  // arrangement has triangles 1e-9 thin and 1 long, which segment recovery
  // cannot split; repair collapses them (thinner than 2^-20 of the
  // coordinates' binary order).
  Plc in;
  for (int copy = 0; copy < 2; ++copy)
    for (int i = 0; i < 8; ++i) {
      const double z = (i >> 2) & 1;
      in.points.push_back({copy * (3e-9 + 2e-9 * z) + (i & 1), copy * 0.3 + ((i >> 1) & 1), copy * 0.2 + z});
    }
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  for (VertexId base : {0u, 8u})
    for (const auto& q : quads)
      for (const auto& t : {std::vector<VertexId>{base + q[0], base + q[1], base + q[2]},
                            std::vector<VertexId>{base + q[0], base + q[2], base + q[3]}}) {
        Facet f;
        f.loops.push_back(t);
        in.facets.push_back(f);
      }
  Plc out;
  RepairReport rep;
  REQUIRE(repair(in, out, rep).ok());
  CHECK(rep.crossing_pairs > 0);
  double thinnest = 1;
  for (const Facet& f : out.facets) {
    const auto& l = f.loops[0];
    const Vec3 &a = out.points[l[0]], &b = out.points[l[1]], &c = out.points[l[2]];
    const double longest = std::max({dist(a, b), dist(b, c), dist(c, a)});
    const Vec3 n = cross(b - a, c - a);
    thinnest = std::min(thinnest, std::sqrt(dot(n, n)) / longest);
  }
  CHECK(thinnest > 1e-6);
  require_meshable(out, true);
}

TEST_CASE("repair: degenerate soups end repaired or with an error naming input facets",
          "[repair]") {
  // Triangles with corners on a 5x5x5 integer grid: vertices on other
  // triangles' edges and planes, shared lines, coplanar pieces. Whatever
  // repair cannot resolve must be reported as such, never as an internal
  // error, and what it reports as repaired must be a valid PLC.
  uint64_t state = 12345;
  auto next = [&state]() {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<int>((state >> 33) % 5);
  };
  size_t repaired = 0;
  for (int soup = 0; soup < 30; ++soup) {
    Plc in;
    const int n = 2 + soup % 12;
    for (int t = 0; t < n; ++t) {
      Facet f;
      for (int k = 0; k < 3; ++k) {
        f.loops.resize(1);
        f.loops[0].push_back(static_cast<VertexId>(in.points.size()));
        in.points.push_back(Vec3{double(next()), double(next()), double(next())});
      }
      in.facets.push_back(f);
    }
    INFO("soup " << soup);
    Plc out;
    RepairReport rep;
    const Status st = repair(in, out, rep);
    INFO(st.error.to_string());
    CHECK(st.error.code != ErrorCode::Internal);
    if (!st.ok()) {
      CHECK((st.error.code == ErrorCode::SelfIntersection ||
             st.error.code == ErrorCode::DegenerateFacet));
      CHECK(st.error.facet < static_cast<int64_t>(in.facets.size()));
      continue;
    }
    ++repaired;
    REQUIRE(check_plc(out).ok());
    std::vector<Intersection> found;
    find_self_intersections(out, found);
    CHECK(found.empty());
  }
  CHECK(repaired >= 10);
}

TEST_CASE("repair --fill-holes: every boundary loop closed, oriented like the surface", "[repair]") {
  // The cube without its top (4-5-6, 4-6-7) and side triangle 1-6-5: one
  // hole, the loop 4-5-1-6-7 (not planar), closed by three triangles.
  const std::string open =
      "OFF\n8 9 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
      "3 0 2 1\n3 0 3 2\n3 0 1 5\n3 0 5 4\n"
      "3 1 2 6\n3 2 3 7\n3 2 7 6\n3 3 0 4\n3 3 4 7\n";
  const Plc in = from_text(open, "open.off");
  Plc out;
  RepairReport rep = fill_one_hole(in, out);
  CHECK(rep.fill_triangles == 3);
  // Its triangles are as large as the cube's already: nothing to refine.
  CHECK(rep.fill_points == 0);
  REQUIRE(out.facets.size() == in.facets.size() + 3);
  // Each new facet names the input facet along its hole (provenance).
  for (size_t f = in.facets.size(); f < out.facets.size(); ++f) CHECK(rep.facet_source[f] < in.facets.size());
  // Closed and consistently oriented: every edge is used once in each direction.
  std::vector<std::pair<VertexId, VertexId>> directed;
  for (const Facet& f : out.facets)
    for (const auto& loop : f.loops)
      for (size_t i = 0; i < loop.size(); ++i) directed.emplace_back(loop[i], loop[(i + 1) % loop.size()]);
  for (const auto& [a, b] : directed) {
    CHECK(std::count(directed.begin(), directed.end(), std::make_pair(a, b)) == 1);
    CHECK(std::count(directed.begin(), directed.end(), std::make_pair(b, a)) == 1);
  }
  require_meshable(out);
  // Without the option the surface stays open; on a closed one nothing is filled.
  REQUIRE(repair(in, out, rep).ok());
  CHECK(rep.filled_holes == 0);
  CHECK(tetrahedralize(out).status.error.code == ErrorCode::OpenBoundary);
  RepairOptions options;
  options.fill_holes = true;
  REQUIRE(repair(from_text(kCube, "cube.off"), out, rep, options).ok());
  CHECK_FALSE(rep.changed());
}

TEST_CASE("repair --fill-holes: a hole that ends at an edge two parts share is closed there", "[repair]") {
  // The unit cube without its side triangle 2-7-6 (at y = 1), and the cube
  // [0,1] x [1,2] x [1,2] sharing its edge 7-6: the hole's rim runs 2-7 and
  // 6-2 (one facet each) and closes along 7-6, which three facets use.
  const std::string text =
      "OFF\n14 23 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n0 0 1\n1 0 1\n1 1 1\n0 1 1\n"
      "0 2 1\n1 2 1\n0 1 2\n1 1 2\n0 2 2\n1 2 2\n"
      "3 0 2 1\n3 0 3 2\n3 4 5 6\n3 4 6 7\n3 0 1 5\n3 0 5 4\n3 1 2 6\n3 1 6 5\n3 2 3 7\n"
      "3 3 0 4\n3 3 4 7\n3 7 8 9\n3 7 9 6\n3 10 11 13\n3 10 13 12\n3 7 6 11\n3 7 11 10\n"
      "3 8 12 13\n3 8 13 9\n3 7 10 12\n3 7 12 8\n3 6 9 13\n3 6 13 11\n";
  const Plc in = from_text(text, "shared_edge.off");
  Plc out;
  const RepairReport rep = fill_one_hole(in, out);
  CHECK(rep.fill_triangles == 1);
  require_meshable(out);
}

TEST_CASE("repair --fill-holes: an open tetrahedron's rim is not closed by its own faces", "[repair]") {
  // Two faces of a tetrahedron sharing its short edge 0-1: their rim
  // 0-2-1-3 has the least area closed by the two faces themselves
  // (reversed), which would leave the surface as open as before; the patch
  // must use the other diagonal, 2-3.
  const std::string text = "OFF\n4 2 0\n0 0 0\n2 0 0\n1 6 0\n1 -6 2\n3 0 2 1\n3 0 1 3\n";
  const Plc in = from_text(text, "open_tet.off");
  Plc out;
  RepairReport rep = fill_one_hole(in, out);
  CHECK(rep.fill_triangles == 2);
  REQUIRE(out.facets.size() == 4);
  CHECK(out.points.size() == 4);
  require_meshable(out);
}

TEST_CASE("repair: an isolated point on a facet edge goes into the edge", "[repair]") {
  // The cube and a point no facet uses, in the middle of edge 1-2 (x = 1,
  // z = 0): a PLC with a vertex inside a segment is not valid.
  Plc in = from_text(kCube, "cube_point.off");
  in.points.push_back({1, 0.5, 0});
  CHECK(tetrahedralize(in).status.error.code == ErrorCode::InvalidPlc);
  Plc out;
  RepairReport rep;
  REQUIRE(repair(in, out, rep).ok());
  CHECK(rep.tjunction_vertices >= 1);
  require_meshable(out);
}

TEST_CASE("repair --fill-holes: a lone triangle beside a closed part goes", "[repair]") {
  // The cube and a triangle of its own far from it: its rim is closed only
  // by its own copy, and it bounds no volume.
  Plc in = from_text(kCube, "cube_sheet.off");
  for (const Vec3& p : {Vec3{3, 0, 0}, Vec3{4, 0, 0}, Vec3{3, 1, 1}}) in.points.push_back(p);
  Facet sheet;
  sheet.loops.push_back({8, 9, 10});
  in.facets.push_back(sheet);
  Plc out;
  RepairReport rep;
  RepairOptions options;
  options.fill_holes = true;
  REQUIRE(repair(in, out, rep, options).ok());
  CHECK(rep.outside_facets >= 1);
  CHECK(out.facets.size() == 12);
  require_meshable(out);
}

TEST_CASE("repair: a copy of a triangle that a T-junction split goes", "[repair]") {
  // The cube (coordinates doubled): its triangle 1-2-6 at x = 2 is split at
  // the midpoint 8 of its side 1-6, the triangle beside it (1-6-5) is not,
  // and 1-2-6 is listed again unsplit. After the T-junction step the copy
  // is a polygon over both halves, and its triangulation repeats them.
  Plc in = from_text(kCube, "tjunction_copy.off");
  for (Vec3& p : in.points) p = Vec3{2 * p.x, 2 * p.y, 2 * p.z};
  in.points.push_back({2, 1, 1});
  REQUIRE(in.facets[6].loops[0] == std::vector<VertexId>{1, 2, 6});
  Facet copy = in.facets[6];
  in.facets[6].loops[0] = {1, 2, 8};
  Facet half = in.facets[6];
  half.loops[0] = {8, 2, 6};
  in.facets.push_back(half);
  in.facets.push_back(copy);
  Plc out;
  RepairReport rep;
  const Status st = repair(in, out, rep);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  CHECK(rep.duplicate_facets >= 1);
  require_meshable(out);
}

namespace {

// A UV sphere of radius 1 (outward) without a cap whose edge zigzags: in
// column j the rings above cut + round(wave sin(3 phi_j)) are left out. One
// hole, a disc whose rim is far from planar.
Plc open_sphere(int rings, int segments, int cut, int wave) {
  Plc plc;
  const double pi = std::acos(-1.0);
  plc.points.push_back({0, 0, 1});
  for (int i = 1; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const double theta = pi * i / rings, phi = 2 * pi * j / segments;
      plc.points.push_back({std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)});
    }
  plc.points.push_back({0, 0, -1});
  auto at = [&](int i, int j) -> VertexId {  // ring i: 0 the north pole, `rings` the south pole
    if (i == 0) return 0;
    if (i == rings) return static_cast<VertexId>(plc.points.size() - 1);
    return static_cast<VertexId>(1 + (i - 1) * segments + j % segments);
  };
  auto add = [&](VertexId a, VertexId b, VertexId c) {
    Facet f;
    f.loops.push_back({a, b, c});
    plc.facets.push_back(f);
  };
  for (int j = 0; j < segments; ++j)
    for (int i = static_cast<int>(cut + std::lround(wave * std::sin(3 * 2 * pi * j / segments))); i < rings; ++i) {
      if (i + 1 < rings) add(at(i, j), at(i + 1, j), at(i + 1, j + 1));
      if (i > 0) add(at(i, j), at(i + 1, j + 1), at(i, j + 1));
    }
  return plc;
}

}  // namespace

TEST_CASE("repair --fill-holes: a non-planar hole's patch is refined to its rim's scale", "[repair]") {
  const Plc in = open_sphere(24, 48, 8, 3);  // 84 rim edges
  // The rim: the edges one input triangle uses.
  std::map<std::pair<VertexId, VertexId>, int> uses;
  for (const Facet& f : in.facets)
    for (size_t i = 0; i < 3; ++i) {
      const VertexId a = f.loops[0][i], b = f.loops[0][(i + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  double rim_length = 0;
  size_t rim_edges = 0;
  for (const auto& [e, n] : uses)
    if (n == 1) rim_length += dist(in.points[e.first], in.points[e.second]), ++rim_edges;
  REQUIRE(rim_edges >= 40);
  const double rim_mean = rim_length / double(rim_edges);

  Plc out;
  const RepairReport rep = fill_one_hole(in, out);
  // (a) The patch has points of its own, counted in the report.
  CHECK(rep.fill_points > 0);
  CHECK(out.points.size() == in.points.size() + rep.fill_points);
  // (b) Its triangles are about as large as the surface's around the hole:
  // no edge of a facet that is not an input triangle is longer than 3 rim
  // edges (the least-area patch alone spans the hole with edges ~2 long).
  std::vector<std::array<VertexId, 3>> input;
  for (const Facet& f : in.facets) input.push_back(sorted_triangle(f.loops[0][0], f.loops[0][1], f.loops[0][2]));
  std::sort(input.begin(), input.end());
  double longest = 0;
  size_t patch = 0;
  for (const Facet& f : out.facets) {
    const auto& l = f.loops[0];
    if (l.size() == 3 && std::binary_search(input.begin(), input.end(), sorted_triangle(l[0], l[1], l[2]))) continue;
    ++patch;
    for (size_t i = 0; i < l.size(); ++i) longest = std::max(longest, dist(out.points[l[i]], out.points[l[(i + 1) % l.size()]]));
  }
  CHECK(patch > rim_edges);
  // Faired as a thin plate, the patch keeps the sphere's curvature: its
  // points lie near the sphere (a membrane, U = 0 alone, sags to radius 0.68).
  for (size_t v = in.points.size(); v < out.points.size(); ++v) CHECK(std::fabs(norm(out.points[v]) - 1) < 0.15);
  INFO("longest patch edge " << longest << ", rim mean " << rim_mean);
  CHECK(longest <= 3 * rim_mean);
  // (c) Closed, and it meshes and validates.
  require_meshable(out);
}

TEST_CASE("repair --fill-holes: a hole of over 240 rim edges (ear clipping) refined without crossing the surface",
          "[repair]") {
  // Most of a hemisphere: the ear-clipped patch folds, and edge swaps across
  // its folds once made it cross the sphere.
  const Plc in = open_sphere(64, 192, 28, 6);
  Plc out;
  const RepairReport rep = fill_one_hole(in, out);
  CHECK(rep.fill_triangles > 240);
  CHECK(rep.fill_points > 240);
  CHECK(rep.crossing_pairs == 0);
  require_meshable(out);
}

namespace {

// Sum of the tets' volumes, and the constrained faces with a tet on both
// sides (facets inside the domain).
struct DomainShape {
  double volume = 0;
  size_t inner_faces = 0;
};

DomainShape domain_shape(const Result& r) {
  DomainShape d;
  const auto& p = r.mesh.points;
  std::vector<std::array<uint32_t, 3>> tet_faces;
  for (size_t t = 0; t < r.mesh.tets.size() / 4; ++t) {
    const uint32_t* v = &r.mesh.tets[4 * t];
    auto at = [&](int i, int k) { return p[3 * size_t(v[i]) + k] - p[3 * size_t(v[0]) + k]; };
    d.volume += std::fabs(at(1, 0) * (at(2, 1) * at(3, 2) - at(2, 2) * at(3, 1)) -
                          at(1, 1) * (at(2, 0) * at(3, 2) - at(2, 2) * at(3, 0)) +
                          at(1, 2) * (at(2, 0) * at(3, 1) - at(2, 1) * at(3, 0))) / 6;
    for (int i = 0; i < 4; ++i) {
      std::array<uint32_t, 3> k{};
      for (int j = 0, m = 0; j < 4; ++j)
        if (j != i) k[m++] = v[j];
      std::sort(k.begin(), k.end());
      tet_faces.push_back(k);
    }
  }
  std::sort(tet_faces.begin(), tet_faces.end());
  for (size_t i = 0; i < r.mesh.faces.size() / 3; ++i) {
    std::array<uint32_t, 3> k = {r.mesh.faces[3 * i], r.mesh.faces[3 * i + 1], r.mesh.faces[3 * i + 2]};
    std::sort(k.begin(), k.end());
    const auto range = std::equal_range(tet_faces.begin(), tet_faces.end(), k);
    if (range.second - range.first == 2) ++d.inner_faces;
  }
  return d;
}

Plc reversed(Plc plc, size_t first, size_t last) {
  for (size_t f = first; f < last; ++f)
    for (auto& loop : plc.facets[f].loops) std::reverse(loop.begin(), loop.end());
  return plc;
}

// Repairs `in`; where step 5 forms the union, again with its fallback (a
// tetrahedralization of the arrangement instead of rays), which must find
// the same winding numbers: the same PLC and the same regions.
Plc repair_both_ways(const Plc& in, RepairOptions options, RepairReport& rep) {
  Plc out;
  const Status st = repair(in, out, rep, options);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  if (!options.union_of_parts || rep.union_skipped) return out;
  Plc by_mesh;
  RepairReport mesh_rep;
  options.debug_union_by_mesh = true;
  REQUIRE(repair(in, by_mesh, mesh_rep, options).ok());
  CHECK(mesh_rep.inner_facets == rep.inner_facets);
  CHECK(write_poly(by_mesh) == write_poly(out));
  CHECK(mesh_rep.facet_regions == rep.facet_regions);
  CHECK(mesh_rep.region_parts == rep.region_parts);
  return out;
}

DomainShape repaired_domain(const Plc& in, bool union_of_parts, RepairReport& rep) {
  RepairOptions options;
  options.union_of_parts = union_of_parts;
  const Plc out = repair_both_ways(in, options, rep);
  require_meshable(out);
  Result r = tetrahedralize(out);
  REQUIRE(r.status.ok());
  return domain_shape(r);
}

}  // namespace

TEST_CASE("repair step 5: interpenetrating parts become their union", "[repair]") {
  Plc cubes;
  REQUIRE(read_plc_file(corpus::kData + "/intersecting_cubes.off", cubes, false).ok());
  REQUIRE(cubes.facets.size() == 24);
  RepairReport rep;
  // Two cubes of side 2 overlapping in a unit cube: union volume 8 + 8 - 1.
  const DomainShape arrangement = repaired_domain(cubes, false, rep);
  CHECK(rep.inner_facets == 0);
  CHECK(std::fabs(arrangement.volume - 15) < 1e-12);
  CHECK(arrangement.inner_faces > 0);  // the overlap is a cell of its own
  const DomainShape united = repaired_domain(cubes, true, rep);
  CHECK(rep.union_skipped == 0);
  CHECK(rep.inner_facets == 12);
  CHECK(std::fabs(united.volume - 15) < 1e-12);
  CHECK(united.inner_faces == 0);
  // Turned inside out (every normal inwards): the same union.
  const DomainShape inverted = repaired_domain(reversed(cubes, 0, 24), true, rep);
  CHECK(rep.union_skipped == 0);
  CHECK(rep.inner_facets == 12);
  CHECK(inverted.inner_faces == 0);
  // One cube's normals reversed: it winds -1 around its inside, so the
  // cells of winding >= 1 are the other cube minus the overlap (8 - 1).
  const DomainShape difference = repaired_domain(reversed(cubes, 0, 12), true, rep);
  CHECK(rep.union_skipped == 0);
  CHECK(difference.inner_faces == 0);
  CHECK(std::fabs(difference.volume - 7) < 1e-12);
  // Half of one cube reversed: the facets do not close up; all are kept.
  const DomainShape broken = repaired_domain(reversed(cubes, 0, 6), true, rep);
  CHECK(rep.union_skipped == 1);
  CHECK(rep.inner_facets == 0);
  CHECK(broken.inner_faces == arrangement.inner_faces);

  Plc tets;
  REQUIRE(read_plc_file(corpus::kData + "/crossing_tets.off", tets, false).ok());
  const DomainShape tets_arrangement = repaired_domain(tets, false, rep);
  const DomainShape tets_union = repaired_domain(tets, true, rep);
  CHECK(rep.inner_facets > 0);
  CHECK(tets_union.inner_faces == 0);
  CHECK(std::fabs(tets_union.volume - tets_arrangement.volume) < 1e-9 * tets_arrangement.volume);
}

TEST_CASE("repair step 5: where the union is not formed, fins outside the model go", "[repair]") {
  Plc cubes;
  REQUIRE(read_plc_file(corpus::kData + "/intersecting_cubes.off", cubes, false).ok());
  // A fin: a triangle hinged on the first cube's top edge from (0,0,2) to
  // (2,0,2) (vertices 4 and 5), leaning out over the outside. Its free
  // edges make the facets not close up: there are no winding numbers.
  REQUIRE(cubes.points[4] == Vec3{0, 0, 2});
  REQUIRE(cubes.points[5] == Vec3{2, 0, 2});
  cubes.points.push_back(Vec3{1, -1, 3});
  Facet fin_facet;
  fin_facet.loops.push_back({4, 5, 16});
  cubes.facets.push_back(fin_facet);
  const size_t fin = cubes.facets.size() - 1;

  RepairReport rep;
  Plc out;
  const Status st = repair(cubes, out, rep);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  CHECK(rep.crossing_pairs > 0);
  CHECK(rep.union_skipped == 1);
  CHECK(rep.outside_facets == 1);
  CHECK(std::count(rep.facet_source.begin(), rep.facet_source.end(), fin) == 0);
  require_meshable(out);
  // Kept, the fin touches no tet of the domain: meshing ends on it.
  Plc with_fin = out;
  VertexId ends[2] = {kNone, kNone};
  for (VertexId v = 0; v < out.points.size(); ++v)
    for (int e = 0; e < 2; ++e)
      if (out.points[v] == cubes.points[4 + e]) ends[e] = v;
  REQUIRE(ends[1] != kNone);
  with_fin.points.push_back(Vec3{1, -1, 3});
  fin_facet.loops[0] = {ends[0], ends[1], static_cast<VertexId>(with_fin.points.size() - 1)};
  with_fin.facets.push_back(fin_facet);
  CHECK(tetrahedralize(with_fin).status.error.code == ErrorCode::OpenBoundary);

  // An open soup of crossing triangles has no inside: every facet stays,
  // and meshing reports the opening.
  Plc soup;
  REQUIRE(read_plc_file(corpus::kData + "/triangle_soup.stl", soup, false).ok());
  RepairReport soup_rep;
  Plc soup_out;
  REQUIRE(repair(soup, soup_out, soup_rep).ok());
  CHECK(soup_rep.crossing_pairs > 0);
  CHECK(soup_rep.outside_facets == 0);
  // Asked for a solid (fill_holes), what bounds no volume goes whatever its
  // share: the pockets that the crossing triangles close are left, and mesh.
  RepairOptions solid;
  solid.fill_holes = true;
  Plc pockets;
  RepairReport pockets_rep;
  REQUIRE(repair(soup, pockets, pockets_rep, solid).ok());
  CHECK(pockets_rep.outside_facets > 0);
  CHECK(pockets.facets.size() < soup_out.facets.size());
  require_meshable(pockets);
}

namespace {

// Volume per region attribute of a result (in doubles: the test models'
// tets have small integer and half-integer coordinates).
std::map<double, double> volume_by_region(const Result& r) {
  std::map<double, double> volume;
  const auto& p = r.mesh.points;
  for (size_t t = 0; t < r.mesh.tets.size() / 4; ++t) {
    const uint32_t* v = &r.mesh.tets[4 * t];
    double e[3][3];
    for (int i = 0; i < 3; ++i)
      for (int k = 0; k < 3; ++k) e[i][k] = p[3 * size_t(v[i + 1]) + k] - p[3 * size_t(v[0]) + k];
    const double det = e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1]) -
                       e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0]) +
                       e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]);
    volume[r.mesh.tet_attributes.at(t)] += std::fabs(det) / 6;
  }
  return volume;
}

// Repairs `in` with parts as regions (by rays, and checks the fallback by a
// tetrahedralization labels the same), meshes, validates and maps back.
Result mesh_parts_as_regions(const Plc& in, RepairReport& rep, const Options& opt = {}) {
  RepairOptions options;
  options.parts_as_regions = true;
  const Plc out = repair_both_ways(in, options, rep);
  REQUIRE(rep.union_skipped == 0);
  require_meshable(out);
  Result r = tetrahedralize(out, opt);
  REQUIRE(r.status.ok());
  if (!opt.quality.enabled) REQUIRE(validate(out, r).ok());
  map_to_input_facets(rep, r);
  REQUIRE(r.mesh.tet_attributes.size() == r.mesh.tets.size() / 4);
  return r;
}

// The second cube of intersecting_cubes.off (points 8-15, [1,3]^3) moved
// by p -> p * scale + shift.
Plc second_cube_moved(const Plc& cubes, double scale, double shift) {
  Plc moved = cubes;
  for (size_t v = 8; v < 16; ++v) {
    Vec3& p = moved.points[v];
    p = {p.x * scale + shift, p.y * scale + shift, p.z * scale + shift};
  }
  return moved;
}

bool near(double a, double b) { return std::fabs(a - b) < 1e-12; }

}  // namespace

TEST_CASE("repair step 5: parts as regions", "[repair]") {
  Plc cubes;
  REQUIRE(read_plc_file(corpus::kData + "/intersecting_cubes.off", cubes, false).ok());
  RepairReport rep;
  // Two cubes of side 2 overlapping in a unit cube: each cube alone (7),
  // and the overlap a region of its own (1).
  Result r = mesh_parts_as_regions(cubes, rep);
  CHECK(rep.parts == 2);
  CHECK(rep.inner_facets == 0);  // every piece separates two different sets of parts
  CHECK(rep.region_parts == std::vector<std::vector<uint32_t>>{{0}, {1}, {0, 1}});
  std::map<double, double> volume = volume_by_region(r);
  REQUIRE(volume.size() == 3);
  CHECK(near(volume[1], 7));
  CHECK(near(volume[2], 7));
  CHECK(near(volume[3], 1));

  SECTION("written on its own, the repaired PLC carries a region point per region") {
    RepairOptions options;
    options.parts_as_regions = true;
    Plc out;
    RepairReport again;
    REQUIRE(repair(cubes, out, again, options).ok());
    REQUIRE(out.regions.empty());
    REQUIRE(repair_steps::add_part_region_points(out, again).ok());
    CHECK(out.regions.size() == 3);
    Plc read;
    const std::string text = write_poly(out);
    REQUIRE(read_plc(reinterpret_cast<const uint8_t*>(text.data()), text.size(), "repaired.poly", read).ok());
    // Meshed without the option: the same attributes on the same volumes.
    CHECK(volume_by_region(tetrahedralize(read)) == volume);
  }

  SECTION("the hull kept: tets outside the union get 0") {
    Options opt;
    opt.keep_convex_hull = true;
    volume = volume_by_region(mesh_parts_as_regions(cubes, rep, opt));
    REQUIRE(volume.size() == 4);
    CHECK(volume[0] > 1);  // between the union and its convex hull
    CHECK(near(volume[1], 7));
    CHECK(near(volume[3], 1));
  }
  SECTION("quality refinement keeps the regions") {
    Options opt;
    opt.quality.enabled = true;
    opt.quality.max_volume = 0.05;
    Result fine = mesh_parts_as_regions(cubes, rep, opt);
    CHECK(fine.mesh.tets.size() > 4 * r.mesh.tets.size());
    volume = volume_by_region(fine);
    REQUIRE(volume.size() == 3);
    CHECK(std::fabs(volume[1] - 7) < 1e-9);
    CHECK(std::fabs(volume[3] - 1) < 1e-9);
  }
  SECTION("a part inside another, no crossing: it is the overlap") {
    // The second cube shrunk into [0.5, 1.5]^3, inside the first.
    volume = volume_by_region(mesh_parts_as_regions(second_cube_moved(cubes, 0.5, 0), rep));
    CHECK(rep.crossing_pairs == 0);
    CHECK(rep.region_parts == std::vector<std::vector<uint32_t>>{{0}, {}, {0, 1}});
    REQUIRE(volume.size() == 2);
    CHECK(near(volume[1], 7));
    CHECK(near(volume[3], 1));
  }
  SECTION("a hollow part: the inner surface reversed bounds a cavity") {
    const Plc hollow = reversed(second_cube_moved(cubes, 0.5, 0), 12, 24);
    volume = volume_by_region(mesh_parts_as_regions(hollow, rep));
    CHECK(rep.region_parts == std::vector<std::vector<uint32_t>>{{0}, {}});
    // The cavity is outside the union (winding 0): tetrahedralize() meshes
    // it as an enclosed region, and it gets 0 like the hull.
    REQUIRE(volume.size() == 2);
    CHECK(near(volume[0], 1));
    CHECK(near(volume[1], 7));
  }
  SECTION("disjoint parts") {
    volume = volume_by_region(mesh_parts_as_regions(second_cube_moved(cubes, 1, 10), rep));
    CHECK(rep.region_parts == std::vector<std::vector<uint32_t>>{{0}, {1}});
    REQUIRE(volume.size() == 2);
    CHECK(near(volume[1], 8));
    CHECK(near(volume[2], 8));
  }
  SECTION("three parts: overlaps are numbered after the parts") {
    // A third cube, the first one moved to [10,12]^3, disjoint from both.
    Plc three = cubes;
    const VertexId base = static_cast<VertexId>(three.points.size());
    for (size_t v = 0; v < 8; ++v) three.points.push_back({cubes.points[v].x + 10, cubes.points[v].y + 10, cubes.points[v].z + 10});
    for (size_t f = 0; f < 12; ++f) {
      Facet copy = cubes.facets[f];
      for (auto& loop : copy.loops)
        for (VertexId& v : loop) v += base;
      three.facets.push_back(copy);
    }
    volume = volume_by_region(mesh_parts_as_regions(three, rep));
    CHECK(rep.parts == 3);
    CHECK(rep.region_parts == std::vector<std::vector<uint32_t>>{{0}, {1}, {2}, {0, 1}});
    REQUIRE(volume.size() == 4);
    CHECK(near(volume[3], 8));
    CHECK(near(volume[4], 1));
  }
  SECTION("it needs the union") {
    Plc out;
    RepairOptions options;
    options.parts_as_regions = true;
    options.union_of_parts = false;
    CHECK(repair(cubes, out, rep, options).error.code == ErrorCode::InvalidArgument);
  }
}

TEST_CASE("repair step 5: parts as regions on two tets in general position", "[repair]") {
  Plc tets;
  REQUIRE(read_plc_file(corpus::kData + "/crossing_tets.off", tets, false).ok());
  RepairReport rep;
  const std::map<double, double> volume = volume_by_region(mesh_parts_as_regions(tets, rep));
  // Every region is a set of parts, and together they fill the union.
  RepairReport union_rep;
  const DomainShape united = repaired_domain(tets, true, union_rep);
  double total = 0;
  for (const auto& [attribute, v] : volume) {
    REQUIRE(attribute >= 1);
    REQUIRE(attribute <= rep.region_parts.size());
    CHECK(!rep.region_parts[size_t(attribute) - 1].empty());
    total += v;
  }
  CHECK(volume.size() > rep.parts);  // some parts overlap
  CHECK(std::fabs(total - united.volume) < 1e-9 * united.volume);
}

namespace {

// The cube [0,2]^3 as a .poly (quads 1-8), with `extra` points (numbered
// from 9) and `segments` (2-vertex polygons, each a facet of its own, which
// the reader makes explicit segments).
Plc cube_with_segments(const std::vector<Vec3>& extra, const std::vector<std::array<int, 2>>& segments) {
  std::string text = std::to_string(8 + extra.size()) + " 3 0 0\n"
      "1 0 0 0\n2 2 0 0\n3 2 2 0\n4 0 2 0\n5 0 0 2\n6 2 0 2\n7 2 2 2\n8 0 2 2\n";
  char line[160];
  for (size_t i = 0; i < extra.size(); ++i) {
    std::snprintf(line, sizeof line, "%zu %.17g %.17g %.17g\n", 9 + i, extra[i].x, extra[i].y, extra[i].z);
    text += line;
  }
  text += std::to_string(6 + segments.size()) + " 0\n";
  for (const char* quad : {"1 2 3 4", "5 6 7 8", "1 2 6 5", "2 3 7 6", "3 4 8 7", "4 1 5 8"})
    text += std::string("1\n4 ") + quad + "\n";
  for (const auto& sg : segments) text += "1\n2 " + std::to_string(sg[0]) + " " + std::to_string(sg[1]) + "\n";
  text += "0\n0\n";
  Plc plc = from_text(text, "cube_segments.poly");
  REQUIRE(plc.segments.size() == segments.size());
  return plc;
}

// repair() resolves every contact of the explicit segments: the result is
// valid (check_plc, the exact self-intersection test), meshes, validates,
// without numerically flat tets, and every output segment names an input
// segment.
Plc repair_segments(const Plc& in, RepairReport& rep) {
  Plc out;
  const Status st = repair(in, out, rep);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  CHECK(rep.changed());
  CHECK(rep.unresolved_pairs == 0);
  REQUIRE(rep.segment_source.size() == out.segments.size());
  for (uint32_t s : rep.segment_source) CHECK(s < in.segments.size());
  CHECK(out.segments.size() == in.segments.size() + rep.segment_splits);
  const Result r = require_meshable(out, true);
  CHECK(r.stats.flat_tets == 0);
  return out;
}

// Output segments that are pieces of input segment s, and whether their
// points all lie within `tol` of the input segment's line.
size_t pieces_of(const Plc& in, const Plc& out, const RepairReport& rep, uint32_t s) {
  size_t n = 0;
  const Vec3 a = in.points[in.segments[s][0]], d = in.points[in.segments[s][1]] - a;
  for (size_t k = 0; k < out.segments.size(); ++k) {
    if (rep.segment_source[k] != s) continue;
    ++n;
    for (VertexId v : out.segments[k]) {
      const Vec3 c = cross(out.points[v] - a, d);
      CHECK(std::sqrt(dot(c, c) / dot(d, d)) < 1e-9);
    }
  }
  return n;
}

}  // namespace

TEST_CASE("repair step 4: a segment piercing a facet is split there", "[repair]") {
  SECTION("from inside the cube through its top") {
    const Plc in = cube_with_segments({{0.5, 1.25, 1}, {0.7, 1.3, 3}}, {{9, 10}});
    RepairReport rep;
    const Plc out = repair_segments(in, rep);
    CHECK(rep.crossing_segments == 1);
    CHECK(rep.segment_splits == 1);
    CHECK(pieces_of(in, out, rep, 0) == 2);
  }
  SECTION("through two faces of the cube") {
    const Plc in = cube_with_segments({{-1, 0.3, 0.7}, {3.1, 1.1, 1.3}}, {{9, 10}});
    RepairReport rep;
    const Plc out = repair_segments(in, rep);
    CHECK(rep.crossing_segments == 1);
    CHECK(rep.segment_splits == 2);
    CHECK(pieces_of(in, out, rep, 0) == 3);
  }
  SECTION("through a corner of the cube") {
    const Plc in = cube_with_segments({{1, 1, 1}, {3, 3, 3}}, {{9, 10}});
    RepairReport rep;
    const Plc out = repair_segments(in, rep);
    CHECK(rep.segment_splits == 1);
    CHECK(pieces_of(in, out, rep, 0) == 2);
    CHECK(rep.intersection_points == 0);  // split at the corner itself
  }
}

TEST_CASE("repair step 4: crossing segments are split at their crossing", "[repair]") {
  const Plc in = cube_with_segments({{0.5, 0.5, 1}, {1.5, 1.5, 1}, {0.5, 1.5, 1}, {1.7, 0.3, 1}},
                                    {{9, 10}, {11, 12}});
  RepairReport rep;
  const Plc out = repair_segments(in, rep);
  CHECK(rep.crossing_segments == 2);
  CHECK(rep.segment_splits == 2);
  CHECK(pieces_of(in, out, rep, 0) == 2);
  CHECK(pieces_of(in, out, rep, 1) == 2);
  // Both are split at one (constructed) point.
  std::map<VertexId, int> uses;
  for (const auto& sg : out.segments)
    for (VertexId v : sg) ++uses[v];
  CHECK(std::count_if(uses.begin(), uses.end(), [](const auto& u) { return u.second == 4; }) == 1);
}

TEST_CASE("repair step 4: a segment in a face's plane crossing its boundary", "[repair]") {
  SECTION("one end inside the face") {
    const Plc in = cube_with_segments({{0.5, 0.75, 0}, {1.25, -0.625, 0}}, {{9, 10}});
    RepairReport rep;
    const Plc out = repair_segments(in, rep);
    CHECK(rep.crossing_segments == 1);
    CHECK(pieces_of(in, out, rep, 0) >= 2);
    // The piece inside the bottom face is an edge of its triangles.
    size_t with_end = 0;
    for (const Facet& f : out.facets)
      for (VertexId v : f.loops[0]) with_end += out.points[v] == in.points[8];
    CHECK(with_end >= 2);
  }
  SECTION("lying in the face, ending on its edge (step 3 puts the end into both faces)") {
    // And a second segment ending inside the front face: that face takes a
    // point inside and one on its edge.
    const Plc in = cube_with_segments({{0.5, 0.75, 0}, {1.25, 0, 0}, {0.75, 0, 1.25}, {0.5, -1, 0.5}},
                                      {{9, 10}, {11, 12}});
    RepairReport rep;
    repair_segments(in, rep);
    CHECK(rep.tjunction_vertices >= 3);
  }
  SECTION("across the whole top face") {
    const Plc in = cube_with_segments({{-0.5, 0.6, 2}, {2.5, 1.3, 2}}, {{9, 10}});
    RepairReport rep;
    const Plc out = repair_segments(in, rep);
    CHECK(rep.crossing_segments == 1);
    CHECK(pieces_of(in, out, rep, 0) >= 3);
  }
}

TEST_CASE("repair step 4: a vertex on a segment splits it", "[repair]") {
  // The end (1, 1, 1) of the second segment is the midpoint of the first.
  const Plc in = cube_with_segments({{0.5, 0.5, 0.5}, {1.5, 1.5, 1.5}, {1, 1, 1}, {1, 0.2, 1.7}},
                                    {{9, 10}, {11, 12}});
  RepairReport rep;
  const Plc out = repair_segments(in, rep);
  CHECK(rep.crossing_segments == 2);
  CHECK(rep.segment_splits == 1);
  CHECK(rep.intersection_points == 0);  // split at the vertex itself
  CHECK(pieces_of(in, out, rep, 0) == 2);
  CHECK(pieces_of(in, out, rep, 1) == 1);
}

TEST_CASE("repair: valid PLCs with explicit segments come out unchanged", "[repair]") {
  for (const char* name : {"cube_dangling.poly", "cube_internal_facet.poly"}) {
    INFO(name);
    Plc in, out;
    REQUIRE(read_plc_file(corpus::kData + "/" + name, in, false).ok());
    RepairReport rep;
    REQUIRE(repair(in, out, rep).ok());
    CHECK_FALSE(rep.changed());
    CHECK(rep.crossing_segments == 0);
    CHECK(rep.segment_splits == 0);
    CHECK(out.segments == in.segments);
    CHECK(out.points.size() == in.points.size());
    REQUIRE(out.facets.size() == in.facets.size());
    for (size_t f = 0; f < in.facets.size(); ++f) CHECK(out.facets[f].loops == in.facets[f].loops);
    std::vector<uint32_t> all(in.segments.size());
    for (uint32_t s = 0; s < all.size(); ++s) all[s] = s;
    CHECK(rep.segment_source == all);
  }
}
