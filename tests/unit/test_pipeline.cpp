// tetrahedralize(): hand-made PLCs with known answers (a facet with a hole,
// regions, hole points, the convex hull option), progress, cancellation and
// stop_after. Every successful result must pass validate(). The corpus models
// run one ctest each (tests/CMakeLists.txt).
#include <catch2/catch.hpp>

#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <cmath>
#include <sched.h>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "beside.hpp"
#include "delaunay.hpp"

using namespace cdt3d;

namespace {

double volume(const Result& r) {
  const auto& P = r.mesh.points;
  double sum = 0;
  for (size_t t = 0; t < r.mesh.tets.size(); t += 4) {
    const double* a = &P[3 * r.mesh.tets[t]];
    const double* b = &P[3 * r.mesh.tets[t + 1]];
    const double* c = &P[3 * r.mesh.tets[t + 2]];
    const double* d = &P[3 * r.mesh.tets[t + 3]];
    const double u[3] = {a[0] - d[0], a[1] - d[1], a[2] - d[2]};
    const double v[3] = {b[0] - d[0], b[1] - d[1], b[2] - d[2]};
    const double w[3] = {c[0] - d[0], c[1] - d[1], c[2] - d[2]};
    sum += std::fabs(u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) +
                     u[2] * (v[0] * w[1] - v[1] * w[0])) / 6;
  }
  return sum;
}

VertexId add(Plc& plc, double x, double y, double z) {
  plc.points.push_back({x, y, z});
  return static_cast<VertexId>(plc.points.size() - 1);
}

void quad(Plc& plc, VertexId a, VertexId b, VertexId c, VertexId d) {
  Facet f;
  f.loops.push_back({a, b, c, d});
  plc.facets.push_back(f);
}

// The unit box [0,4]^2 x [0,2] with a square pocket [1,3]^2 x [1,2] cut into
// its top: the top facet is a square with a square hole (a second loop and a
// hole point in it), the pocket has four walls and a floor.
Plc box_with_pocket() {
  Plc plc;
  VertexId b[4], t[4], h[4], f[4];
  const double X[4] = {0, 4, 4, 0}, Y[4] = {0, 0, 4, 4};
  const double x[4] = {1, 3, 3, 1}, y[4] = {1, 1, 3, 3};
  for (int i = 0; i < 4; ++i) b[i] = add(plc, X[i], Y[i], 0);
  for (int i = 0; i < 4; ++i) t[i] = add(plc, X[i], Y[i], 2);
  for (int i = 0; i < 4; ++i) h[i] = add(plc, x[i], y[i], 2);
  for (int i = 0; i < 4; ++i) f[i] = add(plc, x[i], y[i], 1);
  quad(plc, b[0], b[3], b[2], b[1]);  // bottom
  for (int i = 0; i < 4; ++i) quad(plc, b[i], b[(i + 1) % 4], t[(i + 1) % 4], t[i]);
  Facet top;
  top.loops.push_back({t[0], t[1], t[2], t[3]});
  top.loops.push_back({h[0], h[1], h[2], h[3]});
  top.holes.push_back({2, 2, 2});
  plc.facets.push_back(top);
  for (int i = 0; i < 4; ++i) quad(plc, f[i], f[(i + 1) % 4], h[(i + 1) % 4], h[i]);
  quad(plc, f[0], f[3], f[2], f[1]);  // pocket floor
  return plc;
}

Plc cube(double lo, double hi, Plc plc = Plc()) {
  VertexId v[8];
  for (int i = 0; i < 8; ++i) v[i] = add(plc, i & 1 ? hi : lo, i & 2 ? hi : lo, i & 4 ? hi : lo);
  quad(plc, v[0], v[2], v[3], v[1]);
  quad(plc, v[4], v[5], v[7], v[6]);
  quad(plc, v[0], v[1], v[5], v[4]);
  quad(plc, v[2], v[6], v[7], v[3]);
  quad(plc, v[0], v[4], v[6], v[2]);
  quad(plc, v[1], v[3], v[7], v[5]);
  return plc;
}

Result run(const Plc& plc, Options opt = Options()) {
  opt.validate = true;
  Result r = tetrahedralize(plc, opt);
  INFO(r.status.error.to_string());
  REQUIRE(r.status.ok());
  return r;
}

}  // namespace

TEST_CASE("a facet with a hole: the pocket is not meshed", "[pipeline]") {
  const Plc plc = box_with_pocket();
  REQUIRE(check_plc(plc).ok());
  const Result r = run(plc);
  CHECK(volume(r) == Approx(4 * 4 * 2 - 2 * 2 * 1));
  std::set<uint32_t> facets(r.face_facet.begin(), r.face_facet.end());
  CHECK(facets.size() == plc.facets.size());
}

TEST_CASE("nested cubes: a hole point empties the inner cube, a region point labels it", "[pipeline]") {
  Plc plc = cube(1, 2, cube(0, 3));
  SECTION("hole") {
    plc.holes.push_back({1.5, 1.5, 1.5});
    const Result r = run(plc);
    CHECK(volume(r) == Approx(27 - 1));
  }
  SECTION("regions") {
    plc.regions.push_back({{1.5, 1.5, 1.5}, 5.0, -1});
    plc.regions.push_back({{0.5, 0.5, 0.5}, 9.0, -1});
    const Result r = run(plc);
    CHECK(volume(r) == Approx(27));
    double inner = 0;
    for (size_t t = 0; t < r.mesh.tet_attributes.size(); ++t) {
      const double a = r.mesh.tet_attributes[t];
      CHECK((a == 5.0 || a == 9.0));
    }
    Result only_inner = r;
    only_inner.mesh.tets.clear();
    for (size_t t = 0; t < r.mesh.tet_attributes.size(); ++t)
      if (r.mesh.tet_attributes[t] == 5.0)
        for (int k = 0; k < 4; ++k) only_inner.mesh.tets.push_back(r.mesh.tets[4 * t + k]);
    inner = volume(only_inner);
    CHECK(inner == Approx(1));
  }
  SECTION("automatic attributes without region points (like tetgen -AA)") {
    const Result r = run(plc);
    const std::set<double> attrs(r.mesh.tet_attributes.begin(), r.mesh.tet_attributes.end());
    CHECK(attrs == std::set<double>{1.0, 2.0});
  }
}

TEST_CASE("keep_convex_hull meshes an open surface inside its hull", "[pipeline]") {
  Plc plc = cube(0, 1);
  plc.facets.pop_back();  // open box
  Options opt;
  Result open = tetrahedralize(plc, opt);
  CHECK(open.status.error.code == ErrorCode::OpenBoundary);
  CHECK(open.status.error.facet >= 0);
  opt.keep_convex_hull = true;
  const Result r = run(plc, opt);
  CHECK(volume(r) == Approx(1));
}

TEST_CASE("a self-intersecting PLC names its facets and lists every pair", "[pipeline]") {
  Plc plc = cube(1, 3, cube(0, 2));
  const Result r = tetrahedralize(plc);
  CHECK(r.status.error.code == ErrorCode::SelfIntersection);
  CHECK(r.status.error.facet >= 0);
  CHECK(r.status.error.other_facet >= 0);
  CHECK(!r.intersecting_facets.empty());
}

TEST_CASE("the work on a second thread changes nothing", "[pipeline]") {
  // With Options::threads (the default) the self-intersection test runs
  // beside step 1, and half of the facet triangulations and of the quality
  // statistics beside the other half: the same mesh, the same statistics,
  // the same error with the same pairs as on one thread.
  Plc plc;
  REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/elephant.obj", plc).ok());
  Options one;
  one.threads = false;
  const Result a = tetrahedralize(plc), b = tetrahedralize(plc, one);
  REQUIRE(a.status.ok());
  REQUIRE(b.status.ok());
  REQUIRE(a.mesh.tets.size() / 4 >= 20000);  // enough tets for the statistics' split
  CHECK(a.mesh.points == b.mesh.points);
  CHECK(a.mesh.tets == b.mesh.tets);
  CHECK(a.mesh.faces == b.mesh.faces);
  CHECK(a.mesh.face_markers == b.mesh.face_markers);
  CHECK(a.stats.min_dihedral == b.stats.min_dihedral);
  CHECK(a.stats.max_dihedral == b.stats.max_dihedral);
  CHECK(a.stats.radius_edge_histogram == b.stats.radius_edge_histogram);
  CHECK(a.stats.dihedral_histogram == b.stats.dihedral_histogram);
  CHECK(a.stats.flat_tets == b.stats.flat_tets);
  CHECK(a.stats.missing_subfaces == b.stats.missing_subfaces);
  // Both halves of the statistics are counted: every tet is in one bin.
  const size_t tets = a.mesh.tets.size() / 4;
  size_t in_ratio_bins = 0, in_angle_bins = 0;
  for (size_t k = 0; k < 10; ++k) {
    in_ratio_bins += a.stats.radius_edge_histogram[k];
    in_angle_bins += a.stats.dihedral_histogram[k];
  }
  CHECK(in_ratio_bins == tets);
  CHECK(in_angle_bins == tets);

  // The elephant (12k facets: enough for the second thread) cut by one big
  // triangle through the middle of its bounding box.
  Plc bad = plc;
  Vec3 lo = bad.points[0], hi = bad.points[0];
  for (const Vec3& p : bad.points) {
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)};
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  }
  const double zm = (lo.z + hi.z) / 2;
  const VertexId p = add(bad, 2 * lo.x - hi.x, 2 * lo.y - hi.y, zm);
  const VertexId q = add(bad, 2 * hi.x - lo.x, 2 * lo.y - hi.y, zm);
  const VertexId r = add(bad, (lo.x + hi.x) / 2, 2 * hi.y - lo.y, zm);
  bad.facets.push_back(Facet{{{p, q, r}}, {}, 0, -1, -1});
  REQUIRE(bad.facets.size() >= 5000);
  const Result x = tetrahedralize(bad), y = tetrahedralize(bad, one);
  CHECK(x.status.error.code == ErrorCode::SelfIntersection);
  CHECK(x.status.error.message == y.status.error.message);
  CHECK(x.intersecting_facets == y.intersecting_facets);
  CHECK(x.mesh.tets.empty());
}

TEST_CASE("check_plc's errors come out the same with its checks beside step 1", "[pipeline]") {
  // A PLC of fewer than kMinTwoThreadDelaunayPoints points and enough facets
  // has check_plc and the segments' list made on the second thread while
  // step 1 runs on the points: every check_plc error must still be the
  // run's error, as on one thread, and a bad point stops the run before.
  Plc plc;
  REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/elephant.obj", plc).ok());
  REQUIRE(plc.points.size() < kMinTwoThreadDelaunayPoints);
  REQUIRE(plc.facets.size() >= 5000);
  Options one;
  one.threads = false;
  std::vector<Plc> bad(5, plc);
  bad[0].facets[4000].loops[0][1] = bad[0].facets[4000].loops[0][0];  // repeated vertex
  bad[1].facets[4100].loops[0][2] = static_cast<VertexId>(plc.points.size() + 7);  // beyond
  bad[2].facets.push_back(plc.facets[4200]);                                        // twice
  bad[3].points[3000].y = std::nan("");                                             // a point
  bad[4].points[3001] = bad[4].points[3002];                                        // the same
  for (size_t i = 0; i < bad.size(); ++i) {
    INFO("case " << i);
    const Status expected = check_plc(bad[i]);
    REQUIRE(!expected.ok());
    const Result x = tetrahedralize(bad[i]), y = tetrahedralize(bad[i], one);
    CHECK(x.status.error.code == expected.error.code);
    CHECK(x.status.error.message == expected.error.message);
    CHECK(x.status.error.facet == expected.error.facet);
    CHECK(x.status.error.vertex == expected.error.vertex);
    CHECK(y.status.error.message == expected.error.message);
    CHECK(x.mesh.tets.empty());
  }
}

namespace {
// A box [0, k-1]^2 x [0, ~10] whose top is a grid of k x k points at
// pseudo-random heights (two triangles per cell) and whose sides are
// polygons through the grid's border.
Plc bumpy_box(int k) {
  Plc plc;
  auto height = [](int i, int j) {
    const double s = std::sin(i * 12.9898 + j * 78.233) * 43758.5453;
    return 10 + 0.5 * (s - std::floor(s));
  };
  for (int i = 0; i < k; ++i)
    for (int j = 0; j < k; ++j) add(plc, i, j, height(i, j));
  auto g = [k](int i, int j) { return VertexId(i * k + j); };
  const double m = k - 1;
  const VertexId b00 = add(plc, 0, 0, 0), b10 = add(plc, m, 0, 0), b11 = add(plc, m, m, 0),
                 b01 = add(plc, 0, m, 0);
  quad(plc, b00, b01, b11, b10);
  for (int i = 0; i + 1 < k; ++i)
    for (int j = 0; j + 1 < k; ++j) {
      plc.facets.push_back(Facet{{{g(i, j), g(i + 1, j), g(i + 1, j + 1)}}, {}, 0, -1, -1});
      plc.facets.push_back(Facet{{{g(i, j), g(i + 1, j + 1), g(i, j + 1)}}, {}, 0, -1, -1});
    }
  // The four sides: a bottom edge, then the grid's border back along the top.
  const VertexId corners[4][2] = {{b00, b10}, {b10, b11}, {b11, b01}, {b01, b00}};
  for (int side = 0; side < 4; ++side) {
    std::vector<VertexId> loop = {corners[side][0], corners[side][1]};
    for (int t = k - 1; t >= 0; --t) {
      const int i = side == 0 ? t : side == 1 ? k - 1 : side == 2 ? k - 1 - t : 0;
      const int j = side == 0 ? 0 : side == 1 ? t : side == 2 ? k - 1 : k - 1 - t;
      loop.push_back(g(i, j));
    }
    Facet f;
    f.loops.push_back(loop);
    plc.facets.push_back(f);
  }
  return plc;
}
}  // namespace

TEST_CASE("large PLCs: step 1 on two threads, the self-intersection test after it",
          "[pipeline]") {
  // From kMinTwoThreadDelaunayPoints points on, step 1 takes both cores and
  // the self-intersection test runs beside step 2, which it stops when it
  // finds a pair; either way the result is the one-thread result.
  const Plc plc = bumpy_box(145);
  REQUIRE(plc.points.size() >= kMinTwoThreadDelaunayPoints);
  Options one;
  one.threads = false;
  const Result a = run(plc), b = run(plc, one);
  CHECK(a.mesh.points == b.mesh.points);
  CHECK(a.mesh.tets == b.mesh.tets);
  CHECK(a.mesh.faces == b.mesh.faces);
  CHECK(a.stats.steiner_segment == b.stats.steiner_segment);

  // Cut by a triangle through the middle of the box.
  Plc bad = plc;
  const VertexId p = add(bad, -50, -50, 5), q = add(bad, 300, -50, 5), r = add(bad, 72, 300, 5);
  bad.facets.push_back(Facet{{{p, q, r}}, {}, 0, -1, -1});
  const Result x = tetrahedralize(bad), y = tetrahedralize(bad, one);
  CHECK(x.status.error.code == ErrorCode::SelfIntersection);
  CHECK(x.status.error.message == y.status.error.message);
  CHECK(x.intersecting_facets == y.intersecting_facets);
  CHECK(!x.intersecting_facets.empty());
  CHECK(x.mesh.tets.empty());
}

TEST_CASE("tetrahedralize() runs on several threads at once", "[pipeline]") {
  // Two runs at once give what one gives alone, here on a CAD plate full of
  // co-spherical ties (the search for the perturbation order reads the tie
  // counter, which is per thread like the predicates' memos). A smoke test:
  // a data race would show here only by chance (no ThreadSanitizer build).
  Plc plc;
  REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/thin_plate.off", plc).ok());
  const Result alone = tetrahedralize(plc);
  REQUIRE(alone.status.ok());
  Result r[2];
  std::thread other([&] { r[1] = tetrahedralize(plc); });
  r[0] = tetrahedralize(plc);
  other.join();
  for (const Result& x : r) {
    CHECK(x.status.ok());
    CHECK(x.mesh.tets == alone.mesh.tets);
    CHECK(x.mesh.points == alone.mesh.points);
  }
}

// The second thread of run_beside and of the self-intersection test runs
// its job once, off the calling thread, and is joined; on Linux it starts on
// another core than its creator's (beside.cpp) and then widens its affinity
// back to the creator's, so that it is not pinned for good.
TEST_CASE("a thread beside runs its job on another thread, free to move", "[pipeline]") {
  if (!threads_available()) return;
  std::thread::id id;
  int runs = 0;
#ifdef CDT3D_PLACES_THREADS
  cpu_set_t creator, seen;
  CPU_ZERO(&creator);
  CPU_ZERO(&seen);
  REQUIRE(sched_getaffinity(0, sizeof(creator), &creator) == 0);
#endif
  {
    BesideThread t;
    const bool started = t.start([&] {
      id = std::this_thread::get_id();
      ++runs;
#ifdef CDT3D_PLACES_THREADS
      sched_getaffinity(0, sizeof(seen), &seen);
#endif
    });
    REQUIRE(started);
    t.join();
    t.join();  // a second join does nothing
  }
  CHECK(runs == 1);
  CHECK(id != std::thread::id());
  CHECK(id != std::this_thread::get_id());
#ifdef CDT3D_PLACES_THREADS
  CHECK(CPU_EQUAL(&seen, &creator));
#endif
  // run_beside: both halves, each once, whatever the threads.
  int first = 0, second = 0;
  run_beside(
      true, [&] { ++first; }, [&] { ++second; });
  CHECK((first == 1 && second == 1));
}

namespace {
struct Recorder {
  std::vector<Phase> phases;
  std::vector<double> fractions;
  bool cancel_at_segments = false;
  volatile bool cancel = false;
  static void report(void* user, Phase phase, double fraction) {
    auto* self = static_cast<Recorder*>(user);
    self->phases.push_back(phase);
    self->fractions.push_back(fraction);
    if (self->cancel_at_segments && phase == Phase::Segments) self->cancel = true;
  }
};
}  // namespace

TEST_CASE("progress reports every phase in order and ends at 1, and cancel stops the run", "[pipeline]") {
  const Plc plc = box_with_pocket();
  Recorder rec;
  Options opt;
  opt.progress = &Recorder::report;
  opt.progress_user = &rec;
  opt.cancel = &rec.cancel;
  run(plc, opt);
  REQUIRE(!rec.phases.empty());
  CHECK(rec.phases.front() == Phase::Read);
  CHECK(rec.phases.back() == Phase::Done);
  CHECK(rec.fractions.back() == 1.0);
  for (size_t i = 1; i < rec.fractions.size(); ++i) CHECK(rec.fractions[i] >= rec.fractions[i - 1]);

  Recorder stop;
  stop.cancel_at_segments = true;
  opt.progress_user = &stop;
  opt.cancel = &stop.cancel;
  const Result r = tetrahedralize(plc, opt);
  CHECK(r.status.error.code == ErrorCode::Cancelled);
  CHECK(stop.phases.back() == Phase::Segments);
}

TEST_CASE("stop_after returns the intermediate tetrahedralization and its subsegments", "[pipeline]") {
  const Plc plc = box_with_pocket();
  Options opt;
  opt.stop_after = Phase::Segments;
  const Result r = tetrahedralize(plc, opt);
  REQUIRE(r.status.ok());
  CHECK(r.mesh.faces.empty());
  CHECK(r.edge_segment.size() >= plc_segments(plc).size());
  // The convex hull of the points is filled: volume 4 x 4 x 2.
  CHECK(volume(r) == Approx(32));
}

TEST_CASE("merge_flat_facets joins the two triangles of each cube face", "[pipeline]") {
  Plc plc;
  REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/cube_ascii.stl", plc).ok());
  Plc merged;
  std::vector<uint32_t> into;
  size_t flat = 0;
  CHECK(merge_flat_facets(plc, merged, into, &flat) == 6);
  CHECK(flat == 6);
  CHECK(merged.facets.size() == 6);
  for (const Facet& f : merged.facets) {
    CHECK(f.loops.size() == 1);
    CHECK(f.loops.at(0).size() == 4);
    CHECK(f.even_odd);
  }
  const Result joined = run(plc);  // the default merges
  Options opt;
  opt.keep_triangles = true;
  const Result kept = run(plc, opt);
  CHECK(joined.flat_faces_merged);
  CHECK_FALSE(kept.flat_faces_merged);
  CHECK(joined.stats.merged_facets == 6);
  CHECK(joined.stats.flat_edges == 6);
  CHECK(kept.stats.flat_edges == 0);
  CHECK(joined.stats.input_segments == 12);
  CHECK(joined.stats.input_segments < kept.stats.input_segments);
  for (uint32_t f : joined.face_facet) CHECK(f < plc.facets.size());
  // Faces name the smallest input facet of their flat face; flat_face_of
  // maps every input facet to it (the two triangles of each cube face).
  REQUIRE(joined.flat_face_of.size() == plc.facets.size());
  for (uint32_t f : joined.face_facet) CHECK(joined.flat_face_of[f] == f);
  for (uint32_t f = 0; f < plc.facets.size(); ++f) CHECK(into[joined.flat_face_of[f]] == into[f]);
  CHECK(std::set<uint32_t>(joined.flat_face_of.begin(), joined.flat_face_of.end()).size() == 6);
  CHECK(kept.flat_face_of.empty());
  CHECK(volume(joined) == Approx(1));
  CHECK(validate(plc, joined).ok());
  CHECK(validate(plc, kept).ok());
}

TEST_CASE("a region facet recovery gives up on gets a Steiner point in its facet", "[pipeline]") {
  // Facet recovery is forced to give up on its first missing region twice;
  // each time the pipeline puts a point inside the failing subface and runs
  // steps 1-4 again. The result is a valid CDT with those facet points.
  Plc plc;
  const Status st = read_plc_file(std::string(CDT3D_TEST_DATA) + "/chazelle_n3.off", plc);
  REQUIRE(st.ok());
  Options opt;
  const Result plain = run(plc, opt);
  REQUIRE(plain.stats.missing_subfaces > 0);
  CHECK(plain.stats.facet_splits == 0);
  opt.debug_forced_facet_splits = 2;
  const Result r = run(plc, opt);
  CHECK(r.stats.facet_splits == 2);
  CHECK(r.stats.steiner_facet == 2);
  CHECK(r.stats.flat_tets == 0);
  size_t in_facets = 0;
  for (size_t i = 0; i < r.steiner_kind.size(); ++i) {
    if (r.steiner_kind[i] != SteinerKind::Facet) continue;
    ++in_facets;
    CHECK(r.steiner_parent[i] >= 0);
    CHECK(r.steiner_parent[i] < static_cast<int64_t>(plc.facets.size()));
  }
  CHECK(in_facets == 2);
}

TEST_CASE("flat tets that step 4 leaves are flipped away and the result stays valid", "[pipeline]") {
  // fandisk: facet planes through many input points; the CDT holds flat
  // tets, all outside the domain, where carving removes them: the flips
  // (after carving, among the kept tets) have nothing to do. With the convex
  // hull kept, some are inside and are flipped away.
  Plc plc;
  REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/fandisk.off", plc).ok());
  const Result r = run(plc);  // validates
  CHECK(r.stats.flat_flips == 0);
  CHECK(r.stats.flat_tets == 0);
  Options hull;
  hull.keep_convex_hull = true;
  const Result h = run(plc, hull);
  CHECK(h.stats.flat_flips >= 1);
}

TEST_CASE("with the hull kept, flat tets on the hull are left out and the hull stays convex",
          "[pipeline]") {
  // tray_bottom: hull vertices in nearly one plane; no flip removes the 18
  // flat tets the kept hull held between them, all reachable from the hull.
  // fandisk: only some are (most others lie against the model's facets).
  // run() validates, which checks the kept boundary's convexity.
  Plc plc;
  REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/tray_bottom_ascii.stl", plc).ok());
  Options hull;
  hull.keep_convex_hull = true;
  const Result r = run(plc, hull);
  CHECK(r.stats.flat_peeled >= 1);
  CHECK(r.stats.flat_tets == 0);
  Plc fandisk;
  REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/fandisk.off", fandisk).ok());
  const Result f = run(fandisk, hull);
  CHECK(f.stats.flat_peeled >= 1);
  // Without the hull kept nothing is peeled.
  CHECK(run(plc).stats.flat_peeled == 0);
}

TEST_CASE("split points exactly on their segment's line make no flat tets in a facet plane",
          "[pipeline]") {
  // A facet plane through two input points outside the facet (kept with the
  // convex hull): a split point rounded a few ulps off that plane made flat
  // tets with the plane's other points; on these short coordinates a double
  // exactly on the segment's line exists next to each split point.
  Plc plc;
  const Status st =
      read_plc_file(std::string(CDT3D_TEST_DATA) + "/regress/pipeline-hull-flat-facet-plane.poly", plc);
  REQUIRE(st.ok());
  Options opt;
  opt.keep_convex_hull = true;
  const Result r = run(plc, opt);  // validates
  REQUIRE(r.stats.steiner_segment >= 1);
  CHECK(r.stats.flat_tets == 0);
  const auto segs = plc_segments(plc);
  for (size_t i = 0; i < r.steiner_kind.size(); ++i) {
    if (r.steiner_kind[i] != SteinerKind::Segment) continue;
    const auto& e = segs[static_cast<size_t>(r.steiner_parent[i])];
    const double* v = &r.mesh.points[3 * (r.input_points + i)];
    const double* a = &plc.points[e[0]].x;
    const double* b = &plc.points[e[1]].x;
    // Exactly collinear: the cross product of (b - a) and (v - a) vanishes in
    // doubles here (short coordinates, exact differences and products).
    const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double av[3] = {v[0] - a[0], v[1] - a[1], v[2] - a[2]};
    CHECK(ab[1] * av[2] - ab[2] * av[1] == 0);
    CHECK(ab[2] * av[0] - ab[0] * av[2] == 0);
    CHECK(ab[0] * av[1] - ab[1] * av[0] == 0);
  }
}

TEST_CASE("the fuzz findings with the hull kept end with no flat tet", "[pipeline]") {
  for (const char* name : {"edge-removal-fan", "facet", "flat-facet-plane", "flip-breaks-delaunay",
                           "hole-touches-hull", "rounded-segment-face", "segment-between-holes",
                           "two-facet-planes"}) {
    INFO(name);
    Plc plc;
    REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/regress/pipeline-hull-" + name + ".poly", plc).ok());
    Options opt;
    opt.keep_convex_hull = true;
    const Result r = run(plc, opt);  // validates
    CHECK(r.stats.flat_tets == 0);
  }
}

TEST_CASE("the perturbation order is chosen to keep segments, and ids are reported as input ids",
          "[pipeline]") {
  // The boundary of a 10x10x10 grid: every face square is co-circular, so
  // which diagonals D0 keeps depends on the order of the perturbation.
  Plc plc;
  REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) + "/grid_10x10x10_boundary.off", plc).ok());
  const Result r = run(plc);
  CHECK(r.stats.missing_segments < 200);  // 289 in input order
  // Input points keep their index and coordinates.
  REQUIRE(r.mesh.points.size() >= 3 * plc.points.size());
  for (size_t i = 0; i < plc.points.size(); ++i) {
    CHECK(r.mesh.points[3 * i] == plc.points[i].x);
    CHECK(r.mesh.points[3 * i + 1] == plc.points[i].y);
    CHECK(r.mesh.points[3 * i + 2] == plc.points[i].z);
  }
  // Every subsegment lies on the input segment it names.
  const auto segs = plc_segments(plc);
  for (size_t e = 0; e < r.edge_segment.size(); ++e) {
    const auto& s = segs[r.edge_segment[e]];
    for (int k = 0; k < 2; ++k) {
      const uint32_t v = r.edges[2 * e + k];
      if (v < plc.points.size()) CHECK((v == s[0] || v == s[1]));
    }
  }
}

namespace {

// A thin slab whose top and bottom faces are fans of coplanar triangles
// around a centre vertex, with coordinates that are no short binary
// fractions (a rim of radius 1e-2, like a CAD part in metres): with every
// triangle kept, the fan edges are segments that the vertices of the other
// face encroach upon, and their split points round off the fan's plane.
Plc slab_of_fans(size_t n, double radius, double thickness) {
  Plc plc;
  const double pi = std::acos(-1.0);
  for (int level = 0; level < 2; ++level) {
    const double z = level == 0 ? 0.0 : thickness;
    plc.points.push_back({0.0013, -0.0007, z});  // the fan's centre
    for (size_t i = 0; i < n; ++i) {
      const double a = 2 * pi * (static_cast<double>(i) + 0.1 * level) / static_cast<double>(n);
      plc.points.push_back({radius * std::cos(a), radius * std::sin(a), z});
    }
  }
  const VertexId nb = static_cast<VertexId>(n + 1);  // first vertex of the top
  auto rim = [n](VertexId base, size_t i) { return base + 1 + static_cast<VertexId>(i % n); };
  for (size_t i = 0; i < n; ++i) {
    Facet bottom, top, side1, side2;
    bottom.loops = {{0, rim(0, i + 1), rim(0, i)}};
    top.loops = {{nb, rim(nb, i), rim(nb, i + 1)}};
    side1.loops = {{rim(0, i), rim(0, i + 1), rim(nb, i + 1)}};
    side2.loops = {{rim(0, i), rim(nb, i + 1), rim(nb, i)}};
    for (Facet* f : {&bottom, &top, &side1, &side2}) plc.facets.push_back(*f);
  }
  return plc;
}

}  // namespace

TEST_CASE("coplanar fans with their triangles kept: split points stay usable", "[pipeline]") {
  // Issue 41, point 4: with --keep-triangles, the Steiner points on edges
  // between coplanar triangles must not make flat tets, crossing faces or a
  // tet whose four vertices lie in one fan's plane.
  for (double thickness : {5e-4, 2e-4, 1e-3}) {
    INFO("thickness " << thickness);
    const Plc plc = slab_of_fans(24, 0.01, thickness);
    REQUIRE(check_plc(plc).ok());
    Options opt;
    opt.keep_triangles = true;
    opt.validate = true;
    const Result r = tetrahedralize(plc, opt);
    INFO(r.status.error.to_string());
    REQUIRE(r.status.ok());
    CHECK(r.stats.steiner_segment > 0);  // the fans' edges were split
    CHECK(r.stats.flat_tets == 0);
    // Which fan (0 bottom, 1 top) each output point lies in, by provenance:
    // input points by their z, split points by their segment's ends.
    const auto segs = plc_segments(plc);
    auto level_of_input = [&](uint32_t v) { return plc.points[v].z == 0 ? 0 : 1; };
    std::vector<int> level(r.mesh.points.size() / 3, -1);
    for (uint32_t v = 0; v < r.input_points; ++v) level[v] = level_of_input(v);
    for (size_t i = 0; i < r.steiner_kind.size(); ++i) {
      if (r.steiner_kind[i] != SteinerKind::Segment) continue;
      const auto& e = segs.at(static_cast<size_t>(r.steiner_parent[i]));
      if (level_of_input(e[0]) == level_of_input(e[1])) level[r.input_points + i] = level_of_input(e[0]);
    }
    size_t in_one_plane = 0;
    for (size_t t = 0; t < r.mesh.tets.size(); t += 4) {
      const int l = level[r.mesh.tets[t]];
      bool same = l >= 0;
      for (int k = 1; k < 4; ++k) same = same && level[r.mesh.tets[t + k]] == l;
      in_one_plane += same;
    }
    CHECK(in_one_plane == 0);
    // The default (the fans merged) needs no point on them at all.
    const Result merged = tetrahedralize(plc);
    REQUIRE(merged.status.ok());
    CHECK(merged.stats.merged_facets == 2);
    CHECK(validate(plc, merged).ok());
  }
}

TEST_CASE("a facet standing on an inner edge of a flat face keeps that edge a segment", "[pipeline]") {
  // A unit cube whose bottom face is a fan of four triangles around its
  // centre c, and a dangling triangle standing on the fan edge (0, c): the
  // bottom merges into one facet, but (0, c) has three facets and stays a
  // segment inside it.
  Plc plc;
  plc.points = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}, {0.5, 0.5, 0}};
  auto tri = [&](VertexId a, VertexId b, VertexId c) {
    Facet f;
    f.loops = {{a, b, c}};
    plc.facets.push_back(f);
  };
  for (VertexId i = 0; i < 4; ++i) tri(8, (i + 1) % 4, i);  // the bottom fan
  tri(4, 5, 6), tri(4, 6, 7);                                // top
  tri(0, 1, 5), tri(0, 5, 4), tri(1, 2, 6), tri(1, 6, 5);    // sides
  tri(2, 3, 7), tri(2, 7, 6), tri(3, 0, 4), tri(3, 4, 7);
  plc.points.push_back({0.4, 0.3, 0.6});
  tri(0, 8, 9);  // standing on (0, c), up to the extra point
  REQUIRE(check_plc(plc).ok());
  Plc merged;
  std::vector<uint32_t> into;
  size_t flat = 0;
  merge_flat_facets(plc, merged, into, &flat);
  CHECK(flat == 3 + 5);  // three fan edges on the bottom, one diagonal per other face
  CHECK(into[0] == into[1]);
  CHECK(into[0] == into[3]);
  const auto segs = plc_segments(merged);
  CHECK(std::binary_search(segs.begin(), segs.end(), std::array<VertexId, 2>{0, 8}));
  CHECK_FALSE(std::binary_search(segs.begin(), segs.end(), std::array<VertexId, 2>{1, 8}));
  const Result r = run(plc);
  CHECK(r.flat_faces_merged);
  CHECK(r.stats.merged_facets == 6);
  CHECK(volume(r) == Approx(1));
}

TEST_CASE("two flat faces that cross along an edge inside both keep that edge a segment",
          "[pipeline]") {
  // p = (0,0,0), q = (0,2.5,0). In z = 0 a fan of four triangles around q
  // with p on its rim; in x = 0 a fan of four triangles around p with q on
  // its rim. The fans meet exactly along pq, which is inside each merged
  // fan and on none of their loops: without pq as a segment both fans were
  // triangulated across it (their Delaunay triangulations do not use it),
  // the subfaces crossed, and facet recovery recovered each fan by
  // destroying the other until its attempt limit. An open surface: meshed
  // with its hull.
  Plc plc;
  plc.points = {{0, 0, 0},  {0, 2.5, 0},  {1, 1, 0},   {0, 4, 0}, {-1, 1, 0},
                {0, 1.5, 1}, {0, -1.5, 0}, {0, 1.5, -1}, {5, 5, 5}};
  auto tri = [&](VertexId a, VertexId b, VertexId c) {
    Facet f;
    f.loops = {{a, b, c}};
    plc.facets.push_back(f);
  };
  tri(0, 2, 1), tri(2, 3, 1), tri(3, 4, 1), tri(4, 0, 1);  // around q in z = 0
  tri(1, 5, 0), tri(5, 6, 0), tri(6, 7, 0), tri(7, 1, 0);  // around p in x = 0
  REQUIRE(check_plc(plc).ok());
  Plc merged;
  std::vector<uint32_t> into;
  size_t flat = 0;
  CHECK(merge_flat_facets(plc, merged, into, &flat) == 2);
  CHECK(flat == 6);
  const auto segs = plc_segments(merged);
  CHECK(std::binary_search(segs.begin(), segs.end(), std::array<VertexId, 2>{0, 1}));
  Options opt;
  opt.keep_convex_hull = true;
  const Result r = run(plc, opt);  // validates
  CHECK(r.stats.merged_facets == 2);
  CHECK(validate(plc, r).ok());
  CHECK(r.stats.flat_tets == 0);
}

TEST_CASE("a repaired soup with flat faces crossing along an edge meshes", "[pipeline]") {
  // From repair of a random triangle soup: two flat faces (of 9 and 7
  // triangles, some vertices rounded) cross along the edge (25, 26), which
  // is inside both. Facet recovery ended at its attempt limit, each face's
  // region destroying the other's. An open surface: with the hull kept it
  // meshes; without, the open boundary is the error, not the limit.
  Plc plc;
  REQUIRE(read_plc_file(std::string(CDT3D_TEST_DATA) +
                            "/regress/pipeline-hull-crossing-flat-faces.poly",
                        plc)
              .ok());
  Options opt;
  opt.keep_convex_hull = true;
  const Result r = run(plc, opt);  // validates
  CHECK(validate(plc, r).ok());
  CHECK(r.stats.flat_tets == 0);
  const Result open = tetrahedralize(plc);
  CHECK(open.status.error.code == ErrorCode::OpenBoundary);
}

TEST_CASE("two segments that pass within rounding of each other leave no flat tet", "[pipeline]") {
  // Segments in a box, d apart (no contact: a valid PLC), perpendicular
  // (both are edges of the Delaunay tetrahedralization of their ends, and
  // the tet of those four vertices has 6V = 36 d) or oblique (recovery must
  // split them, and split points clustered about the crossing made flat
  // needles with the box's corners). Step 2 splits both where their lines
  // pass nearest and at a spacing on either side.
  for (const bool oblique : {false, true})
    for (double d : {1e-11, 1e-12, 1e-13, 1e-14}) {
      INFO((oblique ? "oblique" : "perpendicular") << ", d = " << d);
      Plc plc = cube(0, 10);
      const VertexId a = oblique ? add(plc, 1.3, 2.7, 5) : add(plc, 2, 5, 5);
      const VertexId b = oblique ? add(plc, 8.9, 6.1, 5) : add(plc, 8, 5, 5);
      const VertexId c = oblique ? add(plc, 3.1, 7.7, 5 + d) : add(plc, 5, 2, 5 + d);
      const VertexId e = oblique ? add(plc, 6.7, 1.9, 5 + d) : add(plc, 5, 8, 5 + d);
      plc.segments.push_back({a, b});
      plc.segments.push_back({c, e});
      const Result r = run(plc);
      CHECK(r.stats.flat_tets == 0);
      CHECK(volume(r) == Approx(1000));
      Options quality;
      quality.quality.enabled = true;
      const Result q = run(plc, quality);
      CHECK(q.stats.flat_tets == 0);
    }
}

TEST_CASE("random pairs of nearly crossing free segments leave no flat tet", "[pipeline]") {
  // Pairs of segments through a common point in a box, one of them moved
  // 1e-14 to 1e-9 along their common normal (random angles, lengths and
  // gaps, a fixed seed), one to three pairs per box.
  uint64_t state = 0x9e3779b97f4a7c15ull;
  auto uniform = [&](double lo, double hi) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return lo + (hi - lo) * static_cast<double>(state >> 11) * 0x1.0p-53;
  };
  auto direction = [&] {
    for (;;) {
      const double x = uniform(-1, 1), y = uniform(-1, 1), z = uniform(-1, 1);
      const double n = std::sqrt(x * x + y * y + z * z);
      if (n > 0.2 && n <= 1) return std::array<double, 3>{x / n, y / n, z / n};
    }
  };
  size_t pairs = 0;
  for (int box = 0; box < 30; ++box) {
    INFO("box " << box);
    Plc plc = cube(0, 10);
    const int n = 1 + box % 3;
    for (int k = 0; k < n; ++k) {
      const double c[3] = {uniform(3, 7), uniform(3, 7), uniform(3, 7)};
      const auto u = direction(), v = direction();
      double w[3] = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
      const double wn = std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]);
      if (wn < 0.1) continue;
      const double gap = std::pow(10.0, uniform(-14, -9));
      const double la = uniform(0.5, 2.5), lb = uniform(0.5, 2.5);
      VertexId e[4];
      for (int s = 0; s < 2; ++s) {
        const double sign = s == 0 ? -1 : 1;
        e[s] = add(plc, c[0] + sign * la * u[0], c[1] + sign * la * u[1], c[2] + sign * la * u[2]);
        e[2 + s] = add(plc, c[0] + gap * w[0] / wn + sign * lb * v[0],
                       c[1] + gap * w[1] / wn + sign * lb * v[1],
                       c[2] + gap * w[2] / wn + sign * lb * v[2]);
      }
      plc.segments.push_back({e[0], e[1]});
      plc.segments.push_back({e[2], e[3]});
      ++pairs;
    }
    const Result r = run(plc);
    CHECK(r.stats.flat_tets == 0);
  }
  CHECK(pairs >= 40);
}
