// cdt3d::validate: valid results pass; corrupted copies fail with the right
// message. Results are assembled from delaunay -> segments -> facet
// triangulation -> carve for models that need no facet recovery.
#include <catch2/catch.hpp>

#include <cdt3d/cdt3d.hpp>

#include <string>
#include <vector>

#include "carve.hpp"
#include "delaunay.hpp"
#include "predicates.hpp"
#include "segment_recovery.hpp"
#include "subfaces.hpp"
#include "tet_mesh.hpp"

using namespace cdt3d;

namespace {

// Builds the public Result; false when a subface is not in D1 (facet
// recovery would be needed).
bool build_result(const Plc& plc, bool keep_hull, Result& r) {
  TetMesh mesh;
  REQUIRE(delaunay_tetrahedralize(mesh, &plc.points[0].x, plc.points.size()).ok());
  SegmentSet segs;
  init_segments(plc, segs);
  Status st = recover_segments(mesh, segs);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  Subfaces sf;
  st = triangulate_facets(plc, segs, mesh, {}, sf);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  for (const auto& t : sf.tri)
    if (mesh.find_face(t[0], t[1], t[2]) == kNone) return false;
  CarveResult cr;
  st = carve(plc, mesh, sf, keep_hull, cr);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  r = Result();
  r.mesh.points = mesh.coords;
  for (size_t i = 0; i < cr.tets.size(); ++i)
    for (int k = 0; k < 4; ++k) r.mesh.tets.push_back(mesh.vertex(cr.tets[i], k));
  r.mesh.tet_attributes = cr.attribute;
  for (size_t i = 0; i < cr.faces.size(); ++i) {
    for (int k = 0; k < 3; ++k) r.mesh.faces.push_back(cr.faces[i][k]);
    r.mesh.face_markers.push_back(plc.facets[cr.face_facet[i]].marker);
    r.face_facet.push_back(cr.face_facet[i]);
  }
  r.input_points = plc.points.size();
  const size_t ns = mesh.num_vertices() - plc.points.size();
  r.steiner_kind.assign(ns, SteinerKind::Volume);
  r.steiner_parent.assign(ns, -1);
  for (const SegmentVertex& sv : segs.steiner) {
    r.steiner_kind[sv.vertex - plc.points.size()] = SteinerKind::Segment;
    r.steiner_parent[sv.vertex - plc.points.size()] = sv.segment;
  }
  return true;
}

Plc read(const std::string& file) {
  Plc plc;
  Status st = read_plc_file(std::string(CDT3D_TEST_DATA) + "/" + file, plc);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  return plc;
}

void require_error(const Plc& plc, const Result& r, const std::string& what) {
  const Status st = validate(plc, r);
  INFO(st.error.to_string());
  CHECK(st.error.code == ErrorCode::Internal);
  CHECK(st.error.message.find(what) != std::string::npos);
}

// A tetrahedron with isolated points inside: many interior faces, no
// co-spherical sets.
Plc tetrahedron_with_points() {
  Plc plc;
  plc.points = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 10}};
  Rng rng(12345);
  for (int i = 0; i < 40; ++i) {
    double x, y, z;
    do {
      x = 0.25 + 9.5 * (rng.next() >> 11) * 0x1p-53;
      y = 0.25 + 9.5 * (rng.next() >> 11) * 0x1p-53;
      z = 0.25 + 9.5 * (rng.next() >> 11) * 0x1p-53;
    } while (x + y + z > 9.5);
    plc.points.push_back({x, y, z});
  }
  for (auto l : {std::vector<VertexId>{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}) {
    Facet f;
    f.loops = {l};
    plc.facets.push_back(f);
  }
  return plc;
}

}  // namespace

TEST_CASE("valid results pass validation", "[validate]") {
  for (const char* file : {"tetrahedron.off", "cube_comments_colors.off", "cube_ascii.stl",
                           "right_prism.off", "nested_cubes_cavity.poly",
                           "cube_internal_facet.poly", "cube_dangling.poly", "l_block.smesh",
                           "hexagonal_prism_polygons.ply", "octahedron_binary.stl"}) {
    for (bool keep : {false, true}) {
      INFO(file << (keep ? " keeping the hull" : ""));
      const Plc plc = read(file);
      Result r;
      if (!build_result(plc, keep, r)) {
        WARN("skipped " << file << ": needs facet recovery");
        continue;
      }
      const Status st = validate(plc, r);
      INFO(st.error.to_string());
      CHECK(st.ok());
    }
  }
  const Plc plc = tetrahedron_with_points();
  Result r;
  REQUIRE(build_result(plc, false, r));
  const Status st = validate(plc, r);
  INFO(st.error.to_string());
  CHECK(st.ok());
}

TEST_CASE("corrupted results fail validation", "[validate]") {
  const Plc plc = tetrahedron_with_points();
  Result good;
  REQUIRE(build_result(plc, false, good));
  REQUIRE(validate(plc, good).ok());
  const size_t nt = good.mesh.tets.size() / 4;
  REQUIRE(nt > 20);

  SECTION("a flipped tet") {
    Result r = good;
    std::swap(r.mesh.tets[4 * 7], r.mesh.tets[4 * 7 + 1]);
    require_error(plc, r, "is not positively oriented");
  }
  SECTION("a removed interior tet") {
    // A tet none of whose vertices is a corner of the big tetrahedron.
    Result r = good;
    size_t t = 0;
    for (; t < nt; ++t) {
      bool inner = true;
      for (int k = 0; k < 4; ++k) inner = inner && r.mesh.tets[4 * t + k] >= 4;
      if (inner) break;
    }
    REQUIRE(t < nt);
    r.mesh.tets.erase(r.mesh.tets.begin() + 4 * t, r.mesh.tets.begin() + 4 * t + 4);
    r.mesh.tet_attributes.erase(r.mesh.tet_attributes.begin() + t);
    require_error(plc, r, "the boundary of the kept tets is not convex");
  }
  SECTION("a duplicated tet") {
    Result r = good;
    for (int k = 0; k < 4; ++k) r.mesh.tets.push_back(r.mesh.tets[k]);
    r.mesh.tet_attributes.push_back(r.mesh.tet_attributes[0]);
    require_error(plc, r, "tets");
  }
  SECTION("a missing constrained face") {
    Result r = good;
    r.mesh.faces.erase(r.mesh.faces.begin(), r.mesh.faces.begin() + 3);
    r.mesh.face_markers.erase(r.mesh.face_markers.begin());
    r.face_facet.erase(r.face_facet.begin());
    // The model is convex, so the face passes as a hull face; the facet is
    // no longer covered.
    require_error(plc, r, "facet");
  }
  SECTION("a constrained face that is no face of a tet") {
    Result r = good;
    r.mesh.faces[0] = 4, r.mesh.faces[1] = 5, r.mesh.faces[2] = 6;
    require_error(plc, r, "is not a face of a tet");
  }
  SECTION("a face given to the wrong facet") {
    Result r = good;
    r.face_facet[0] = (r.face_facet[0] + 1) % 4;
    r.mesh.face_markers[0] = plc.facets[r.face_facet[0]].marker;
    require_error(plc, r, "does not belong to the facet");
  }
  SECTION("a non-Delaunay interior face made by a 2-3 flip") {
    // Find two tets sharing an interior face whose union is convex (the
    // edge between the apexes crosses the shared triangle), and flip.
    Result r = good;
    const std::vector<double>& P = r.mesh.points;
    auto p = [&P](uint32_t v) { return &P[3 * static_cast<size_t>(v)]; };
    bool flipped = false;
    for (size_t a = 0; a < nt && !flipped; ++a) {
      for (int i = 0; i < 4 && !flipped; ++i) {
        uint32_t f[3];
        for (int k = 0; k < 3; ++k) f[k] = r.mesh.tets[4 * a + kFaceVertex[i][k]];
        const uint32_t d = r.mesh.tets[4 * a + i];
        for (size_t b = a + 1; b < nt && !flipped; ++b) {
          int shared = 0;
          uint32_t e = kNone;
          for (int k = 0; k < 4; ++k) {
            const uint32_t v = r.mesh.tets[4 * b + k];
            if (v == f[0] || v == f[1] || v == f[2]) ++shared;
            else e = v;
          }
          if (shared != 3) continue;
          // f is counterclockwise from outside a; e is beyond it. Convex iff
          // segment d e crosses triangle f.
          if (pred::orient3d(p(d), p(e), p(f[0]), p(f[1])) <= 0 ||
              pred::orient3d(p(d), p(e), p(f[1]), p(f[2])) <= 0 ||
              pred::orient3d(p(d), p(e), p(f[2]), p(f[0])) <= 0) {
            if (pred::orient3d(p(d), p(e), p(f[0]), p(f[1])) >= 0 ||
                pred::orient3d(p(d), p(e), p(f[1]), p(f[2])) >= 0 ||
                pred::orient3d(p(d), p(e), p(f[2]), p(f[0])) >= 0)
              continue;
          }
          // Replace by three tets around edge d e, positively oriented.
          std::vector<std::array<uint32_t, 4>> nts = {
              {d, e, f[0], f[1]}, {d, e, f[1], f[2]}, {d, e, f[2], f[0]}};
          for (auto& t : nts)
            if (pred::orient3d(p(t[0]), p(t[1]), p(t[2]), p(t[3])) < 0) std::swap(t[0], t[1]);
          for (int k = 0; k < 4; ++k) r.mesh.tets[4 * a + k] = nts[0][k];
          for (int k = 0; k < 4; ++k) r.mesh.tets[4 * b + k] = nts[1][k];
          for (int k = 0; k < 4; ++k) r.mesh.tets.push_back(nts[2][k]);
          r.mesh.tet_attributes.push_back(r.mesh.tet_attributes[a]);
          flipped = true;
        }
      }
    }
    REQUIRE(flipped);
    require_error(plc, r, "not locally Delaunay");
  }
  SECTION("a segment that is not a chain of edges") {
    // The same result against a PLC with one more segment between two
    // interior points that are not joined by a mesh edge.
    Plc plc2 = plc;
    uint32_t u = 4, v = kNone;
    for (uint32_t w = 5; w < plc.points.size() && v == kNone; ++w) {
      bool edge = false;
      for (size_t t = 0; t < nt && !edge; ++t) {
        int hits = 0;
        for (int k = 0; k < 4; ++k) hits += good.mesh.tets[4 * t + k] == u || good.mesh.tets[4 * t + k] == w;
        edge = hits == 2;
      }
      if (!edge) v = w;
    }
    REQUIRE(v != kNone);
    plc2.segments.push_back({u, v});
    const Status st = validate(plc2, good);
    INFO(st.error.to_string());
    CHECK(st.error.code == ErrorCode::Internal);
    CHECK(st.error.message.find("is not a chain of mesh edges") != std::string::npos);
    CHECK(st.error.segment >= 0);
  }
  SECTION("a Steiner point with a bad parent") {
    Result r = good;
    for (double x : {5.0, 0.0, 0.0}) r.mesh.points.push_back(x);
    r.steiner_kind.push_back(SteinerKind::Segment);
    r.steiner_parent.push_back(1000);
    require_error(plc, r, "has no valid parent segment");
  }
}

TEST_CASE("facets without faces and internal facets", "[validate]") {
  Plc plc = read("cube_internal_facet.poly");
  SECTION("a hole region's bounding facet has no faces: valid") {
    plc.holes.push_back({1.5, 0.5, 0.5});
    Result r;
    REQUIRE(build_result(plc, false, r));
    for (uint32_t f : r.face_facet) CHECK(f != 1);
    const Status st = validate(plc, r);
    INFO(st.error.to_string());
    CHECK(st.ok());
  }
  SECTION("the internal facet's faces dropped") {
    Result r;
    REQUIRE(build_result(plc, false, r));
    Result c = r;
    c.mesh.faces.clear();
    c.mesh.face_markers.clear();
    c.face_facet.clear();
    for (size_t i = 0; i < r.face_facet.size(); ++i) {
      if (r.face_facet[i] == 2) continue;
      for (int k = 0; k < 3; ++k) c.mesh.faces.push_back(r.mesh.faces[3 * i + k]);
      c.mesh.face_markers.push_back(r.mesh.face_markers[i]);
      c.face_facet.push_back(r.face_facet[i]);
    }
    REQUIRE(c.face_facet.size() < r.face_facet.size());
    const Status st = validate(plc, c);
    CHECK(st.error.code == ErrorCode::Internal);
    CHECK(st.error.message.find("lies in facet 2 but is not constrained") != std::string::npos);
    CHECK(st.error.facet == 2);
  }
  SECTION("one region's attribute does not matter to validation") {
    Result r;
    REQUIRE(build_result(plc, false, r));
    CHECK(validate(plc, r).ok());
  }
}

TEST_CASE("validation of carved models of tests/data that need no facet recovery",
          "[validate][corpus]") {
  int checked = 0;
  for (const char* file : {"bunny.off", "decimated_knight.off", "dragon_decimated.off", "spot.obj",
                           "cospherical_r2_50.off", "grid_10x10x10_boundary.off",
                           "menger_sponge_l2.off", "thin_plate.off", "xyz_cube_20mm_binary.stl",
                           "plate_holes_binary.stl", "cubes_shared_edge.off", "chazelle_n3.off",
                           "fandisk.off", "tray_bottom_ascii.stl"}) {
    INFO(file);
    const Plc plc = read(file);
    Result r;
    if (!build_result(plc, false, r)) continue;
    ++checked;
    const Status st = validate(plc, r);
    INFO(st.error.to_string());
    CHECK(st.ok());
  }
  WARN(checked << " corpus models validated without facet recovery");
}
