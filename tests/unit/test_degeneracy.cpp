// Step 3, local degeneracy removal (Si & Gärtner 2005 §6): detection on
// hand-made configurations, Fig. 5's grid facet, co-spherical models, and
// every valid model of tests/data.
#include <catch2/catch.hpp>

#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "degeneracy.hpp"
#include "delaunay.hpp"
#include "corpus.hpp"
#include "predicates.hpp"
#include "segment_recovery.hpp"
#include "tet_mesh.hpp"

using namespace cdt3d;

namespace {

struct Run {
  TetMesh mesh;
  SegmentSet segs;
  std::vector<std::vector<VertexId>> facet_interior;
  std::vector<VertexId> volume_points;
  DegeneracyStats stats;
  size_t steiner_before = 0;  // segment Steiner vertices after step 2
  size_t seeded = 0;          // Steiner vertices in facet_interior before step 3
  Status status;
  double ms = 0;
};

// D0, step 2, then step 3. `interior` seeds facet_interior (input points that
// lie inside a facet).
void run_steps(const Plc& plc, Run& r, const std::vector<std::vector<VertexId>>& interior = {}) {
  Status st = delaunay_tetrahedralize(r.mesh, &plc.points[0].x, plc.points.size());
  REQUIRE(st.ok());
  init_segments(plc, r.segs);
  st = recover_segments(r.mesh, r.segs);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  r.steiner_before = r.segs.steiner.size();
  r.facet_interior = interior;
  r.facet_interior.resize(plc.facets.size());
  const auto t0 = std::chrono::steady_clock::now();
  r.status = remove_local_degeneracies(plc, r.mesh, r.segs, r.facet_interior, r.volume_points,
                                       &r.stats);
  r.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// Every interior face has the opposite vertex strictly outside the
// circumsphere, by the unperturbed exact test (so D2 is the unique Delaunay
// tetrahedralization of its vertices on the interior faces); coplanar hull
// neighbours are strictly outside each other's circles.
bool strictly_delaunay(const TetMesh& m) {
  for (size_t t = 0; t < m.num_tet_slots(); ++t) {
    if (m.is_dead(TetId(t))) continue;
    const VertexId* w = &m.tv[4 * t];
    const bool ghost = w[3] == kInfinite;
    for (int i = 0; i < (ghost ? 3 : 4); ++i) {
      const HalfFace hf = m.tadj[4 * t + i];
      const VertexId e = m.tv[4 * size_t(hf_tet(hf)) + hf_face(hf)];
      const bool n_ghost = m.is_ghost(hf_tet(hf));
      if (!ghost && !n_ghost) {
        if (pred::insphere(m.point(w[0]), m.point(w[1]), m.point(w[2]), m.point(w[3]), m.point(e)) >= 0)
          return false;
      } else if (ghost && n_ghost) {
        const double *a = m.point(w[0]), *b = m.point(w[1]), *c = m.point(w[2]);
        if (pred::orient3d(a, b, c, m.point(e)) == 0 && pred::incircle_coplanar(a, b, c, m.point(e)) >= 0)
          return false;
      }
    }
  }
  return true;
}

// The postconditions of step 3.
void require_d2(const Plc& plc, Run& r) {
  INFO(r.status.error.to_string());
  REQUIRE(r.status.ok());
  std::vector<LocalDegeneracy> degs;
  find_local_degeneracies(r.mesh, degs);
  CHECK(degs.empty());
  std::vector<std::array<uint32_t, 3>> missing;
  missing_subsegments(r.mesh, r.segs, missing);
  CHECK(missing.empty());
  Status st = check_mesh(r.mesh);
  INFO(st.error.to_string());
  CHECK(st.ok());
  st = check_delaunay(r.mesh);
  INFO(st.error.to_string());
  CHECK(st.ok());
  CHECK(strictly_delaunay(r.mesh));
  // Bookkeeping: every added vertex is recorded exactly once.
  CHECK(r.volume_points.size() == r.stats.break_points);
  size_t facet_points = 0;
  for (size_t f = 0; f < r.facet_interior.size(); ++f)
    for (VertexId v : r.facet_interior[f]) facet_points += v >= plc.points.size();
  CHECK(facet_points == r.seeded + r.stats.protect_facet);
  CHECK(r.segs.steiner.size() - r.steiner_before == r.stats.protect_segment + r.stats.resplit);
  size_t protect = 0;
  for (const SegmentVertex& sv : r.segs.steiner) {
    protect += sv.rule == SplitRule::Protect;
    const auto& chain = r.segs.chain[sv.segment];
    CHECK(std::find(chain.begin(), chain.end(), sv.vertex) != chain.end());
    CHECK(sv.t > 0);
    CHECK(sv.t < 1);
  }
  CHECK(protect == r.stats.protect_segment);
  for (VertexId v : r.volume_points) CHECK(r.mesh.vtet[v] != kNone);
  // Input vertices never move; Steiner vertices on segments stay where their
  // parameter says (up to rounding), also after a perturbation.
  for (VertexId v = 0; v < plc.points.size(); ++v) {
    const double* p = r.mesh.point(v);
    CHECK((p[0] == plc.points[v].x && p[1] == plc.points[v].y && p[2] == plc.points[v].z));
  }
  for (const SegmentVertex& sv : r.segs.steiner) {
    const double* a = r.mesh.point(r.segs.input[sv.segment][0]);
    const double* b = r.mesh.point(r.segs.input[sv.segment][1]);
    const double* p = r.mesh.point(sv.vertex);
    double d2 = 0, len2 = 0;
    for (int k = 0; k < 3; ++k) {
      const double q = a[k] + sv.t * (b[k] - a[k]);
      d2 += (p[k] - q) * (p[k] - q);
      len2 += (b[k] - a[k]) * (b[k] - a[k]);
    }
    CHECK(d2 <= 1e-20 * len2);
  }
}

void add_triangle(Plc& plc, VertexId a, VertexId b, VertexId c) {
  Facet f;
  f.loops.push_back({a, b, c});
  plc.facets.push_back(f);
}

std::string counts(const Run& r) {
  std::ostringstream o;
  o << "initial " << r.stats.initial << ", perturbations " << r.stats.perturbations
    << ", break points " << r.stats.break_points << ", protect segment "
    << r.stats.protect_segment << ", protect facet " << r.stats.protect_facet << ", resplit "
    << r.stats.resplit << ", rounds " << r.stats.rounds;
  return o.str();
}

}  // namespace

TEST_CASE("points in general position have no local degeneracy", "[degeneracy]") {
  std::vector<double> xyz;
  Rng rng(7);
  for (int i = 0; i < 300; ++i)
    for (int d = 0; d < 3; ++d) xyz.push_back(static_cast<double>(rng.next() >> 11) * 0x1.0p-53);
  TetMesh mesh;
  REQUIRE(delaunay_tetrahedralize(mesh, xyz.data(), xyz.size() / 3).ok());
  std::vector<LocalDegeneracy> degs;
  find_local_degeneracies(mesh, degs);
  CHECK(degs.empty());
}

TEST_CASE("a cube's corners are one local degeneracy set", "[degeneracy]") {
  // The 8 corners are co-spherical: every pair of adjacent tets is degenerate,
  // and the 6 square faces on the hull are coplanar co-circular hull pairs.
  std::vector<double> xyz;
  for (int i = 0; i < 8; ++i) {
    xyz.push_back(i & 1);
    xyz.push_back((i >> 1) & 1);
    xyz.push_back((i >> 2) & 1);
  }
  TetMesh mesh;
  REQUIRE(delaunay_tetrahedralize(mesh, xyz.data(), 8).ok());
  std::vector<LocalDegeneracy> degs;
  find_local_degeneracies(mesh, degs);
  size_t hull = 0;
  for (const auto& d : degs) {
    CHECK(std::is_sorted(d.begin(), d.end()));
    CHECK(std::adjacent_find(d.begin(), d.end()) == d.end());
    hull += d[4] == kInfinite;
  }
  CHECK(hull == 6);
  CHECK(degs.size() > hull);
  // Deterministic and each once.
  std::vector<LocalDegeneracy> again;
  find_local_degeneracies(mesh, again);
  CHECK(again == degs);
}

TEST_CASE("a square pyramid: four co-circular points on the hull", "[degeneracy]") {
  // The square base is on the hull and co-circular. The two tets on the base
  // share a face through the apex, and their five vertices include the four
  // co-circular ones, so they are co-spherical whatever the apex (any sphere
  // through three of them holds the fourth); the two hull faces of the base
  // are coplanar and co-circular: a hull degeneracy (fifth id kInfinite).
  const std::vector<double> xyz = {0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.3, 0.4, 0.9};
  TetMesh mesh;
  REQUIRE(delaunay_tetrahedralize(mesh, xyz.data(), 5).ok());
  std::vector<LocalDegeneracy> degs;
  find_local_degeneracies(mesh, degs);
  REQUIRE(degs.size() == 2);
  CHECK(degs[0] == LocalDegeneracy{0, 1, 2, 3, 4});
  CHECK(degs[1] == LocalDegeneracy{0, 1, 2, 3, kInfinite});
}

TEST_CASE("a square pyramid loses its degeneracies", "[degeneracy]") {
  Plc plc;
  plc.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.3, 0.4, 0.9}};
  Facet base;
  base.loops.push_back({0, 3, 2, 1});
  plc.facets.push_back(base);
  for (VertexId i = 0; i < 4; ++i) add_triangle(plc, i, (i + 1) % 4, 4);
  Run r;
  run_steps(plc, r);
  INFO(counts(r));
  require_d2(plc, r);
  CHECK(r.stats.initial == 2);
  // The break point of the base's circle lies in the base facet: it must not
  // be inserted as a volume point; the base gets a protection point instead.
  CHECK(r.stats.protect_facet + r.stats.protect_segment > 0);
}

TEST_CASE("the unit cube loses its degeneracies", "[degeneracy]") {
  Plc plc;
  REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/cube_ascii.stl", plc).ok());
  Run r;
  run_steps(plc, r);
  INFO(counts(r));
  require_d2(plc, r);
  CHECK(r.stats.initial > 0);
  CHECK(r.stats.perturbations == 0);  // only input vertices: nothing may move
  CHECK(r.stats.break_points + r.stats.protect_facet + r.stats.protect_segment > 0);
}

TEST_CASE("the 3x3 grid facet of Fig. 5", "[degeneracy]") {
  // A square facet [0,2]^2 whose vertices are a 3x3 grid (8 on the boundary
  // loop, the center inside the facet), plus a point above it. Every unit
  // square of the grid is co-circular and all input vertices are
  // unperturbable, so only break points and protection remove them.
  Plc plc;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) plc.points.push_back({double(i), double(j), 0});
  plc.points.push_back({1, 1, 1.5});
  Facet f;
  f.loops.push_back({0, 1, 2, 5, 8, 7, 6, 3});
  plc.facets.push_back(f);
  Run r;
  run_steps(plc, r, {{4}});
  INFO(counts(r));
  require_d2(plc, r);
  CHECK(r.stats.initial > 0);
  // Every point added inside the facet's plane is recorded as a facet point
  // or a segment point: no break point lies in the facet.
  for (VertexId v : r.volume_points) {
    const double* p = r.mesh.point(v);
    const bool inside_square = p[0] > 0 && p[0] < 2 && p[1] > 0 && p[1] < 2;
    CHECK(!(inside_square && std::fabs(p[2]) < 1e-9));
  }
}

TEST_CASE("Fig. 5: a perturbable vertex that is not segment-safe", "[degeneracy]") {
  // The 3x3 grid split into a diamond facet (the four edge midpoints) and
  // four corner triangles, so the diamond's edges are segments; points above
  // and below make the grid's center interior. The center is a Steiner
  // vertex inside the diamond facet, hence perturbable, and it lies on the
  // diametral circles of all four diamond edges: wherever it moves in the
  // plane, one of them stops being Delaunay. No perturbation may be kept.
  Plc plc;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i)
      if (i != 1 || j != 1) plc.points.push_back({double(i), double(j), 0});
  // Ids: 0 (0,0) 1 (1,0) 2 (2,0) 3 (0,1) 4 (2,1) 5 (0,2) 6 (1,2) 7 (2,2).
  plc.points.push_back({1, 1, 1.5});
  plc.points.push_back({1.1, 0.9, -1.7});
  Facet diamond;
  diamond.loops.push_back({1, 4, 6, 3});
  plc.facets.push_back(diamond);
  add_triangle(plc, 0, 1, 3);
  add_triangle(plc, 1, 2, 4);
  add_triangle(plc, 4, 7, 6);
  add_triangle(plc, 3, 6, 5);
  Run r;
  Status st = delaunay_tetrahedralize(r.mesh, &plc.points[0].x, plc.points.size());
  REQUIRE(st.ok());
  init_segments(plc, r.segs);
  REQUIRE(recover_segments(r.mesh, r.segs).ok());
  const double center[3] = {1, 1, 0};
  InsertResult ins;
  REQUIRE(insert_point(r.mesh, center, r.mesh.vtet[0], &ins).ok());
  const VertexId p = ins.vertex;
  REQUIRE(p == plc.points.size());
  REQUIRE(recover_segments(r.mesh, r.segs).ok());
  r.steiner_before = r.segs.steiner.size();
  r.facet_interior.assign(plc.facets.size(), {});
  r.facet_interior[0] = {p};
  r.seeded = 1;
  std::vector<LocalDegeneracy> degs;
  find_local_degeneracies(r.mesh, degs);
  bool p_degenerate = false;
  for (const auto& d : degs) p_degenerate |= std::find(d.begin(), d.end(), p) != d.end();
  REQUIRE(p_degenerate);
  r.status = remove_local_degeneracies(plc, r.mesh, r.segs, r.facet_interior, r.volume_points,
                                       &r.stats);
  INFO(counts(r));
  require_d2(plc, r);
  // While the four diamond edges are whole subsegments no move of p is
  // segment-safe, so p can have moved only after boundary protection split
  // one of them.
  bool split = false;
  for (uint32_t s = 0; s < r.segs.input.size(); ++s) {
    const auto& e = r.segs.input[s];
    const bool diamond_edge = (e[0] == 1 || e[0] == 3 || e[0] == 4 || e[0] == 6) &&
                              (e[1] == 1 || e[1] == 3 || e[1] == 4 || e[1] == 6);
    if (diamond_edge && r.segs.chain[s].size() > 2) split = true;
  }
  const double* q = r.mesh.point(p);
  const bool moved = !(q[0] == 1 && q[1] == 1 && q[2] == 0);
  CHECK(moved == (r.stats.perturbations > 0));
  if (moved) CHECK(split);
}

TEST_CASE("Steiner vertices on segments are perturbed when it is segment-safe", "[degeneracy]") {
  // Chazelle's polyhedron: segment recovery adds points whose degeneracies
  // can be removed by sliding them along their segments.
  Plc plc;
  REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/chazelle_n3.off", plc).ok());
  Run r;
  run_steps(plc, r);
  INFO(counts(r));
  require_d2(plc, r);
  CHECK(r.stats.perturbations > 0);
}

TEST_CASE("the regular octahedron loses its degeneracies", "[degeneracy]") {
  Plc plc;
  REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/octahedron_binary.stl", plc).ok());
  Run r;
  run_steps(plc, r);
  INFO(counts(r));
  require_d2(plc, r);
  CHECK(r.stats.initial > 0);
}

TEST_CASE("co-spherical and grid models lose their degeneracies", "[degeneracy]") {
  for (const char* file : {"cospherical_r2_50.off", "grid_10x10x10_boundary.off"}) {
    DYNAMIC_SECTION(file) {
      Plc plc;
      REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/" + file, plc).ok());
      Run r;
      run_steps(plc, r);
      INFO(counts(r));
      require_d2(plc, r);
      CHECK(r.stats.initial > 0);
    }
  }
}

TEST_CASE("degeneracy removal is deterministic", "[degeneracy]") {
  Plc plc;
  REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/cospherical_r2_50.off", plc).ok());
  Run a, b;
  run_steps(plc, a);
  run_steps(plc, b);
  REQUIRE(a.status.ok());
  REQUIRE(b.status.ok());
  CHECK(counts(a) == counts(b));
  CHECK(a.mesh.coords == b.mesh.coords);
  CHECK(a.mesh.tv == b.mesh.tv);
}

TEST_CASE("degeneracy removal on every valid model of tests/data", "[degeneracy][corpus]") {
  int models = 0;
  for (const std::string& file : corpus::valid_models()) {
    DYNAMIC_SECTION(file) {
      Plc plc;
      Status st = read_plc_file(std::string(CDT3D_TEST_DATA) + "/" + file, plc);
      INFO(st.error.to_string());
      REQUIRE(st.ok());
      Run r;
      run_steps(plc, r);
      INFO(counts(r));
      require_d2(plc, r);
      // The per-model table of the report (stdout, one line per model).
      std::printf("[degeneracy] %-28s vertices %6zu  %s  (%.1f ms)\n", file.c_str(),
                  plc.points.size(), counts(r).c_str(), r.ms);
    }
    ++models;
  }
  CHECK(models >= 10);
}
