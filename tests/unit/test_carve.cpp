// Carving: exterior removal, volume holes, region attributes, open surfaces.
// Models whose subfaces are all in D1 already (no facet recovery needed) go
// through delaunay -> segments -> facet triangulation -> carve; a model with
// missing subfaces is skipped with a warning until facet recovery is linked
// into these tests.
#include <catch2/catch.hpp>

#include <cdt3d/cdt3d.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "carve.hpp"
#include "delaunay.hpp"
#include "segment_recovery.hpp"
#include "subfaces.hpp"
#include "tet_mesh.hpp"

using namespace cdt3d;

namespace {

struct Carved {
  Plc plc;
  TetMesh mesh;
  SegmentSet segs;
  Subfaces sf;
  CarveResult result;
  Status status;
  bool ready = false;  // every subface was a face of D1
};

double tet_volume(const TetMesh& mesh, TetId t) {
  const double* a = mesh.point(mesh.vertex(t, 0));
  const double* b = mesh.point(mesh.vertex(t, 1));
  const double* c = mesh.point(mesh.vertex(t, 2));
  const double* d = mesh.point(mesh.vertex(t, 3));
  const double u[3] = {a[0] - d[0], a[1] - d[1], a[2] - d[2]};
  const double v[3] = {b[0] - d[0], b[1] - d[1], b[2] - d[2]};
  const double w[3] = {c[0] - d[0], c[1] - d[1], c[2] - d[2]};
  return (u[0] * (v[1] * w[2] - v[2] * w[1]) + v[0] * (w[1] * u[2] - w[2] * u[1]) +
          w[0] * (u[1] * v[2] - u[2] * v[1])) /
         6.0;
}

double volume(const Carved& c, double attribute = NAN) {
  double v = 0;
  for (size_t i = 0; i < c.result.tets.size(); ++i)
    if (std::isnan(attribute) || c.result.attribute[i] == attribute)
      v += tet_volume(c.mesh, c.result.tets[i]);
  return v;
}

void prepare(const Plc& plc, Carved& c) {
  c.plc = plc;
  REQUIRE(delaunay_tetrahedralize(c.mesh, &c.plc.points[0].x, c.plc.points.size()).ok());
  init_segments(c.plc, c.segs);
  Status st = recover_segments(c.mesh, c.segs);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  st = triangulate_facets(c.plc, c.segs, c.mesh, {}, c.sf);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  size_t missing = 0;
  for (const auto& t : c.sf.tri) missing += c.mesh.find_face(t[0], t[1], t[2]) == kNone;
  c.ready = missing == 0;
  if (!c.ready) WARN("skipped: " << missing << " subfaces need facet recovery");
}

void carve_file(const std::string& file, bool keep_hull, Carved& c) {
  Plc plc;
  Status st = read_plc_file(std::string(CDT3D_TEST_DATA) + "/" + file, plc);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  prepare(plc, c);
  if (c.ready) c.status = carve(c.plc, c.mesh, c.sf, keep_hull, c.result);
}

// Every output face is a subface with a kept tet on one side, each once.
void check_faces(Carved& c) {
  std::vector<uint8_t> kept(c.mesh.num_tet_slots(), 0);
  for (TetId t : c.result.tets) kept[t] = 1;
  REQUIRE(c.result.faces.size() == c.result.face_facet.size());
  for (size_t i = 0; i < c.result.faces.size(); ++i) {
    const auto& f = c.result.faces[i];
    const HalfFace hf = c.mesh.find_face(f[0], f[1], f[2]);
    REQUIRE(hf != kNone);
    CHECK((kept[hf_tet(hf)] || kept[hf_tet(c.mesh.adjacent(hf))]));
    CHECK(c.result.face_facet[i] < c.plc.facets.size());
  }
}

}  // namespace

TEST_CASE("carving a convex model keeps its tets", "[carve]") {
  for (const char* file : {"tetrahedron.off", "cube_comments_colors.off", "cube_ascii.stl",
                           "right_prism.off", "octahedron_binary.stl"}) {
    INFO(file);
    Carved c;
    carve_file(file, false, c);
    if (!c.ready) continue;
    INFO(c.status.error.to_string());
    REQUIRE(c.status.ok());
    CHECK(c.result.regions == 1);
    // Every tet is kept, except that a Steiner point on a hull edge, rounded
    // to doubles (§5), may dent the surface and leave slivers outside it.
    if (c.segs.steiner.empty()) {
      CHECK(c.result.tets.size() == c.mesh.num_real_tets());
    } else {
      double all = 0;
      for (TetId t = 0; t < c.mesh.num_tet_slots(); ++t)
        if (!c.mesh.is_dead(t) && !c.mesh.is_ghost(t)) all += tet_volume(c.mesh, t);
      CHECK(volume(c) == Approx(all).epsilon(1e-12));
    }
    CHECK(c.result.faces.size() == c.sf.tri.size());
    for (double a : c.result.attribute) CHECK(a == 1.0);
    check_faces(c);
    for (TetId t : c.result.tets) CHECK((c.mesh.tflag[t] & kTetInside) != 0);
  }
  Carved c;
  carve_file("tetrahedron.off", false, c);
  REQUIRE(c.ready);
  CHECK(c.result.tets.size() == 1);
}

TEST_CASE("the cavity of nested cubes is a hole", "[carve]") {
  for (bool keep : {false, true}) {
    Carved c;
    carve_file("nested_cubes_cavity.poly", keep, c);
    if (!c.ready) continue;
    INFO(c.status.error.to_string());
    REQUIRE(c.status.ok());
    CHECK(volume(c) == Approx(26.0));
    CHECK(c.result.regions == 1);
    for (double a : c.result.attribute) CHECK(a == 7.0);  // its region point
    CHECK(c.result.faces.size() == c.sf.tri.size());
    check_faces(c);
  }
}

TEST_CASE("an internal facet separates two regions", "[carve]") {
  Carved c;
  carve_file("cube_internal_facet.poly", false, c);
  if (!c.ready) return;
  INFO(c.status.error.to_string());
  REQUIRE(c.status.ok());
  CHECK(c.result.regions == 2);
  CHECK(volume(c, 1.0) == Approx(4.0));
  CHECK(volume(c, 2.0) == Approx(4.0));
  CHECK(volume(c) == Approx(8.0));
  CHECK(c.result.faces.size() == c.sf.tri.size());
  check_faces(c);

  SECTION("without region points: automatic attributes 1 and 2") {
    Plc plc = c.plc;
    plc.regions.clear();
    Carved d;
    prepare(plc, d);
    REQUIRE(d.ready);
    REQUIRE(carve(d.plc, d.mesh, d.sf, false, d.result).ok());
    CHECK(d.result.regions == 2);
    CHECK(volume(d, 1.0) == Approx(4.0));
    CHECK(volume(d, 2.0) == Approx(4.0));
  }
  SECTION("one region point: the other region gets the next integer") {
    Plc plc = c.plc;
    plc.regions.resize(1);
    plc.regions[0].attribute = 5;
    Carved d;
    prepare(plc, d);
    REQUIRE(d.ready);
    REQUIRE(carve(d.plc, d.mesh, d.sf, false, d.result).ok());
    CHECK(volume(d, 5.0) == Approx(4.0));
    CHECK(volume(d, 6.0) == Approx(4.0));
  }
  SECTION("a hole point removes one region") {
    Plc plc = c.plc;
    plc.holes.push_back({1.5, 0.5, 0.5});
    plc.holes.push_back({10, 10, 10});  // outside the hull: ignored
    Carved d;
    prepare(plc, d);
    REQUIRE(d.ready);
    REQUIRE(carve(d.plc, d.mesh, d.sf, false, d.result).ok());
    CHECK(d.result.regions == 1);
    CHECK(volume(d) == Approx(4.0));
    CHECK(volume(d, 1.0) == Approx(4.0));
    // Facet x = 2 (index 1) now bounds nothing kept: its faces are dropped.
    for (uint32_t f : d.result.face_facet) CHECK(f != 1);
  }
}

TEST_CASE("keep_convex_hull keeps the hull of a non-convex model", "[carve]") {
  Carved c;
  carve_file("l_block.smesh", false, c);
  if (!c.ready) return;
  REQUIRE(c.status.ok());
  CHECK(volume(c) == Approx(5.0));
  CHECK(c.result.regions == 1);
  Carved k;
  carve_file("l_block.smesh", true, k);
  REQUIRE(k.ready);
  REQUIRE(k.status.ok());
  CHECK(volume(k) == Approx(7.0));  // hull: the L plus the triangle (3,1) (1,3) (3,3)
  CHECK(k.result.regions == 2);
  CHECK(k.result.faces.size() == k.sf.tri.size());
}

TEST_CASE("a dangling facet inside a cube stays, with both sides kept", "[carve]") {
  Carved c;
  carve_file("cube_dangling.poly", false, c);
  if (!c.ready) return;
  INFO(c.status.error.to_string());
  REQUIRE(c.status.ok());
  CHECK(volume(c) == Approx(8.0));
  CHECK(c.result.regions == 1);
  size_t dangling = 0;
  for (uint32_t f : c.result.face_facet) dangling += f == 6;
  CHECK(dangling >= 2);
  CHECK(c.result.faces.size() == c.sf.tri.size());
}

TEST_CASE("an open surface does not enclose a volume", "[carve]") {
  Carved c;
  carve_file("open_cube.off", false, c);
  if (!c.ready) return;
  CHECK(c.status.error.code == ErrorCode::OpenBoundary);
  CHECK(c.status.error.message.find("does not enclose a volume") != std::string::npos);
  CHECK(c.status.error.message.find("boundary edge") != std::string::npos);
  CHECK(c.status.error.facet >= 0);
  CHECK(c.status.error.vertex >= 0);
  // keep_convex_hull keeps the hull instead.
  Carved k;
  carve_file("open_cube.off", true, k);
  REQUIRE(k.ready);
  REQUIRE(k.status.ok());
  CHECK(k.result.tets.size() == k.mesh.num_real_tets());
}

TEST_CASE("a subface missing from the mesh is an internal error naming its facet", "[carve]") {
  // Vertex 4 is inside the circumsphere of 0 1 2 3, so D0 is the three tets
  // around edge 0-4, which crosses triangle 1 2 3.
  Plc plc;
  plc.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.9, 0.9, 0.9}};
  Carved c;
  prepare(plc, c);
  REQUIRE(c.mesh.find_face(0, 1, 4) != kNone);
  REQUIRE(c.mesh.find_face(1, 2, 3) == kNone);
  Subfaces sf;
  sf.tri = {{0, 1, 4}, {1, 2, 3}};
  sf.facet = {0, 1};
  CarveResult r;
  Status st = carve(c.plc, c.mesh, sf, false, r);
  CHECK(st.error.code == ErrorCode::Internal);
  CHECK(st.error.facet == 1);
}
