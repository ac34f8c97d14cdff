// Step 1: Delaunay tetrahedralization. Each case validates the mesh
// (check_mesh, check_delaunay), the Euler characteristic of the real
// simplices, that the hull faces bound every point, and determinism.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <thread>
#include <vector>

#include "delaunay.hpp"
#include "spatial_sort.hpp"
#include "tet_mesh.hpp"

using namespace cdt3d;

namespace {

std::vector<double> random_cube(size_t n, uint64_t seed) {
  Rng rng(seed);
  std::vector<double> pts(3 * n);
  for (double& x : pts) x = double(rng.next() >> 11) * 0x1p-53;
  return pts;
}

// All integer points with x^2 + y^2 + z^2 == r^2: exactly co-spherical.
std::vector<double> integer_sphere(int r) {
  std::vector<double> pts;
  for (int x = -r; x <= r; ++x)
    for (int y = -r; y <= r; ++y)
      for (int z = -r; z <= r; ++z)
        if (x * x + y * y + z * z == r * r)
          pts.insert(pts.end(), {double(x), double(y), double(z)});
  return pts;
}

std::vector<double> grid(int nx, int ny, int nz, double step = 1.0) {
  std::vector<double> pts;
  for (int i = 0; i < nx; ++i)
    for (int j = 0; j < ny; ++j)
      for (int k = 0; k < nz; ++k) pts.insert(pts.end(), {i * step, j * step, k * step});
  return pts;
}

uint64_t key2(uint32_t a, uint32_t b) {
  if (a > b) std::swap(a, b);
  return (uint64_t(a) << 32) | b;
}

// V - E + F - T over the real simplices; 1 for a triangulated 3-ball.
// The real tets of m, each with sorted vertices, in sorted order: equal for
// equal triangulations, whatever the slot order.
std::vector<std::array<uint32_t, 4>> canonical_tets(const TetMesh& m) {
  std::vector<uint32_t> t;
  m.real_tets(t);
  std::vector<std::array<uint32_t, 4>> out;
  for (size_t k = 0; k < t.size(); k += 4) {
    std::array<uint32_t, 4> x = {t[k], t[k + 1], t[k + 2], t[k + 3]};
    std::sort(x.begin(), x.end());
    out.push_back(x);
  }
  std::sort(out.begin(), out.end());
  return out;
}

long long euler_characteristic(const TetMesh& m) {
  std::vector<uint32_t> tets;
  m.real_tets(tets);
  std::vector<uint64_t> edges;
  std::vector<std::array<uint32_t, 3>> faces;
  std::vector<uint32_t> verts;
  for (size_t k = 0; k < tets.size(); k += 4) {
    uint32_t t[4] = {tets[k], tets[k + 1], tets[k + 2], tets[k + 3]};
    std::sort(t, t + 4);
    for (int i = 0; i < 4; ++i) {
      verts.push_back(t[i]);
      for (int j = i + 1; j < 4; ++j) edges.push_back(key2(t[i], t[j]));
    }
    faces.push_back({t[0], t[1], t[2]});
    faces.push_back({t[0], t[1], t[3]});
    faces.push_back({t[0], t[2], t[3]});
    faces.push_back({t[1], t[2], t[3]});
  }
  auto uniq = [](auto& v) {
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    return static_cast<long long>(v.size());
  };
  const long long V = uniq(verts), E = uniq(edges), F = uniq(faces);
  return V - E + F - static_cast<long long>(tets.size() / 4);
}

// Every inserted vertex lies on the inner side of (or on) every hull face
// (a strided sample of the vertices when that would be slow).
void check_hull_bounds_points(const TetMesh& m) {
  std::vector<uint32_t> hull;
  m.hull_faces(hull);
  REQUIRE(!hull.empty());
  size_t bad = 0;
  const size_t work = m.num_vertices() * (hull.size() / 3);
  const size_t stride = work > 30000000 ? work / 30000000 + 1 : 1;
  for (VertexId v = 0; v < m.num_vertices(); v += VertexId(stride)) {
    if (m.vtet[v] == kNone) continue;
    for (size_t k = 0; k < hull.size(); k += 3)
      if (pred::orient3d(m.point(hull[k]), m.point(hull[k + 1]), m.point(hull[k + 2]), m.point(v)) <
          0)
        ++bad;
  }
  CHECK(bad == 0);
}

void validate(const TetMesh& m) {
  const Status sm = check_mesh(m);
  INFO(sm.error.message);
  REQUIRE(sm.ok());
  const Status sd = check_delaunay(m);
  INFO(sd.error.message);
  REQUIRE(sd.ok());
  CHECK(euler_characteristic(m) == 1);
  check_hull_bounds_points(m);
}

// Builds twice and requires identical arrays.
DelaunayStats build_checked(const std::vector<double>& pts, TetMesh& m,
                            std::vector<VertexId>* map = nullptr) {
  DelaunayStats st;
  const Status s = delaunay_tetrahedralize(m, pts.data(), pts.size() / 3, map, &st);
  INFO(s.error.message);
  REQUIRE(s.ok());
  validate(m);
  TetMesh again;
  REQUIRE(delaunay_tetrahedralize(again, pts.data(), pts.size() / 3).ok());
  CHECK(again.tv == m.tv);
  CHECK(again.tadj == m.tadj);
  CHECK(again.vtet == m.vtet);
  CHECK(st.tets == m.num_real_tets());
  CHECK(st.hull_faces == m.num_ghost_tets());
  return st;
}

}  // namespace

TEST_CASE("random points in a cube", "[delaunay]") {
  for (size_t n : {4, 5, 10, 100, 1000, 10000, 100000}) {
    INFO("n = " << n);
    const std::vector<double> pts = random_cube(n, 1000 + n);
    TetMesh m;
    const DelaunayStats st = build_checked(pts, m);
    CHECK(st.points == n);
    CHECK(st.vertices == n);
    CHECK(st.duplicates == 0);
    if (n >= 10000) {  // about 6.5-6.8 tets per point for uniform points
      CHECK(double(st.tets) / double(n) > 6.0);
      CHECK(double(st.tets) / double(n) < 7.0);
    }
  }
}

TEST_CASE("insertion order does not change the triangulation", "[delaunay]") {
  const std::vector<double> pts = random_cube(3000, 5);
  TetMesh a, b;
  REQUIRE(delaunay_tetrahedralize(a, pts.data(), 3000).ok());
  DelaunayOptions plain;
  plain.spatial_sort = false;
  REQUIRE(delaunay_tetrahedralize(b, pts.data(), 3000, nullptr, nullptr, plain).ok());
  validate(b);
  CHECK(canonical_tets(a) == canonical_tets(b));
}

TEST_CASE("SmallDelaunay reused equals a fresh unsorted build, degenerate sets included",
          "[delaunay]") {
  // One builder for many sets in a row (sos_order.cpp's cells): each result
  // must be the tetrahedralization a fresh delaunay_tetrahedralize without
  // the spatial sort gives (the same perturbation by index).
  std::vector<std::vector<double>> sets = {grid(2, 2, 2), integer_sphere(5), grid(3, 3, 2, 0.1),
                                           random_cube(40, 3), integer_sphere(3), grid(2, 2, 2)};
  // Sphere points in a scrambled order: another perturbation, another result.
  std::vector<double> shuffled = integer_sphere(5);
  for (size_t i = 0; i + 1 < shuffled.size() / 3; i += 2)
    for (int c = 0; c < 3; ++c) std::swap(shuffled[3 * i + c], shuffled[3 * (i + 1) + c]);
  sets.push_back(shuffled);
  SmallDelaunay small;
  DelaunayOptions plain;
  plain.spatial_sort = false;
  for (const auto& pts : sets) {
    const size_t n = pts.size() / 3;
    INFO(n << " points");
    TetMesh fresh;
    REQUIRE(delaunay_tetrahedralize(fresh, pts.data(), n, nullptr, nullptr, plain).ok());
    REQUIRE(small.build(pts.data(), n).ok());
    validate(small.mesh());
    CHECK(canonical_tets(small.mesh()) == canonical_tets(fresh));
  }
  const double flat[12] = {0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 1, 0};
  CHECK(small.build(flat, 4).error.code == ErrorCode::Coplanar);
}

namespace {

// Appends each point set again with its points in reverse order (another
// perturbation order).
void add_reversed(std::vector<std::vector<double>>& sets) {
  for (size_t k = 0, n = sets.size(); k < n; ++k) {
    std::vector<double> reversed;
    for (size_t i = sets[k].size() / 3; i-- > 0;)
      reversed.insert(reversed.end(), &sets[k][3 * i], &sets[k][3 * i] + 3);
    sets.push_back(reversed);
  }
}

}  // namespace

TEST_CASE("SmallDelaunay's co-spherical mode gives the same tetrahedralization",
          "[delaunay][sos]") {
  // Exactly co-spherical sets (a cube's corners, integer points on spheres,
  // in two orders each): skipping the exact insphere zero must not change
  // what the perturbation decides.
  std::vector<std::vector<double>> sets = {grid(2, 2, 2), integer_sphere(3), integer_sphere(5),
                                           integer_sphere(9)};
  add_reversed(sets);
  SmallDelaunay plain, cospherical;
  for (const auto& pts : sets) {
    const size_t n = pts.size() / 3;
    INFO(n << " points");
    REQUIRE(plain.build(pts.data(), n).ok());
    REQUIRE(cospherical.build(pts.data(), n, /*cospherical=*/true).ok());
    validate(cospherical.mesh());
    CHECK(canonical_tets(cospherical.mesh()) == canonical_tets(plain.mesh()));
  }
}

TEST_CASE("a translated co-spherical set gets the same tetrahedralization", "[delaunay][sos]") {
  // What the perturbation-order search's cache of cell tetrahedralizations
  // (sos_order.cpp) relies on: points moved by an exact translation, in the
  // same order, are tetrahedralized alike, ties and all.
  std::vector<std::vector<double>> sets = {grid(2, 2, 2), integer_sphere(5), integer_sphere(9)};
  add_reversed(sets);
  SmallDelaunay here, there;
  for (const auto& pts : sets) {
    const size_t n = pts.size() / 3;
    INFO(n << " points");
    std::vector<double> moved = pts;
    const double offset[3] = {1024, -3, 0.5};  // exact on these coordinates
    for (size_t i = 0; i < moved.size(); ++i) moved[i] += offset[i % 3];
    REQUIRE(here.build(pts.data(), n, true).ok());
    REQUIRE(there.build(moved.data(), n, true).ok());
    CHECK(canonical_tets(there.mesh()) == canonical_tets(here.mesh()));
  }
}

TEST_CASE("integer points on spheres (co-spherical)", "[delaunay]") {
  for (int r : {3, 5, 7, 13, 25, 65, 85}) {
    INFO("r = " << r);
    std::vector<double> pts = integer_sphere(r);
    TetMesh m;
    build_checked(pts, m);
    // With the center added, every tet has the center as a vertex or not;
    // either way the result must be valid.
    pts.insert(pts.end(), {0.0, 0.0, 0.0});
    TetMesh c;
    build_checked(pts, c);
  }
}

TEST_CASE("points on a sphere scaled by powers of two", "[delaunay]") {
  // Pythagorean quadruples scaled: exact doubles, still co-spherical.
  std::vector<double> pts = integer_sphere(9);
  for (double& x : pts) x *= 0x1p-20;
  TetMesh m;
  build_checked(pts, m);
}

TEST_CASE("regular grids (heavily degenerate)", "[delaunay]") {
  for (int n : {2, 3, 4, 5, 8, 12, 16}) {
    INFO("n = " << n);
    const std::vector<double> pts = grid(n, n, n);
    TetMesh m;
    const DelaunayStats st = build_checked(pts, m);
    CHECK(st.vertices == size_t(n) * n * n);
    // The hull of an n^3 grid is a cube: 6 (n-1)^2 squares, 2 triangles each.
    CHECK(st.hull_faces == size_t(12) * (n - 1) * (n - 1));
  }
  TetMesh flat;  // a thin slab: 10 x 10 x 2
  build_checked(grid(10, 10, 2, 0.5), flat);
}

TEST_CASE("duplicates are counted and mapped", "[delaunay]") {
  std::vector<double> pts = random_cube(1000, 77);
  Rng rng(3);
  std::vector<size_t> source;
  for (int i = 0; i < 200; ++i) {
    const size_t s = rng.below(1000);
    source.push_back(s);
    pts.insert(pts.end(), {pts[3 * s], pts[3 * s + 1], pts[3 * s + 2]});
  }
  TetMesh m;
  std::vector<VertexId> map;
  const DelaunayStats st = build_checked(pts, m, &map);
  CHECK(st.points == 1200);
  CHECK(st.duplicates == 200);
  CHECK(st.vertices == 1000);
  REQUIRE(map.size() == 1200);
  for (size_t i = 0; i < 1200; ++i) {
    const VertexId v = map[i];
    CHECK(m.vtet[v] != kNone);
    CHECK(m.point(v)[0] == pts[3 * i]);
    CHECK(m.point(v)[1] == pts[3 * i + 1]);
    CHECK(m.point(v)[2] == pts[3 * i + 2]);
    if (v != i) CHECK(m.vkind[i] == kVertexDuplicate);
  }
}

TEST_CASE("degenerate inputs are reported", "[delaunay]") {
  TetMesh m;
  auto code = [&](const std::vector<double>& p) {
    return delaunay_tetrahedralize(m, p.data(), p.size() / 3).error.code;
  };
  CHECK(code({}) == ErrorCode::TooFewPoints);
  CHECK(code({0, 0, 0, 1, 0, 0, 0, 1, 0}) == ErrorCode::TooFewPoints);
  CHECK(code({0, 0, 0, 1, 0, 0, 0, 1, 0, 1, 0, 0}) == ErrorCode::TooFewPoints);  // 3 distinct
  CHECK(code({1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 2, 3, 1, 2, 3}) == ErrorCode::TooFewPoints);
  CHECK(code({0, 0, 0, 1, 1, 1, 0, 0, 0, 1, 1, 1, 2, 2, 2}) == ErrorCode::TooFewPoints);

  std::vector<double> line;
  for (int i = 0; i < 20; ++i) line.insert(line.end(), {0.5 * i, 2.0 * i, -3.0 * i});
  line.insert(line.end(), {0, 0, 0});  // duplicates do not matter
  CHECK(code(line) == ErrorCode::Collinear);

  std::vector<double> plane;  // x + y + z = 10 on integers: exact
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 10; ++j)
      plane.insert(plane.end(), {double(i), double(j), double(10 - i - j)});
  CHECK(code(plane) == ErrorCode::Coplanar);
  CHECK(code(grid(7, 7, 1)) == ErrorCode::Coplanar);

  std::vector<double> nan = random_cube(10, 1);
  nan[13] = std::nan("");
  const Status s = delaunay_tetrahedralize(m, nan.data(), 10);
  CHECK(s.error.code == ErrorCode::NonFinite);
  CHECK(s.error.vertex == 4);
  std::vector<double> huge = random_cube(10, 1);
  huge[5] = 1e300;
  CHECK(code(huge) == ErrorCode::CoordinateRange);
}

TEST_CASE("insert_point one by one after a build", "[delaunay]") {
  const std::vector<double> all = random_cube(1000, 11);
  TetMesh m;
  REQUIRE(delaunay_tetrahedralize(m, all.data(), 500).ok());
  PointInserter ins(m);
  TetId hint = kNone;
  for (size_t i = 500; i < 1000; ++i) {
    InsertResult r;
    REQUIRE(ins.insert_point(&all[3 * i], hint, kVertexSteiner, &r).ok());
    CHECK(r.vertex == i);
    CHECK(!r.duplicate);
    CHECK(!ins.new_tets().empty());
    for (TetId t : ins.new_tets()) CHECK(m.index_in_tet(t, r.vertex) >= 0);
    hint = ins.last_tet();
    if (i % 100 == 0) REQUIRE(check_mesh(m).ok());
  }
  validate(m);
  TetMesh whole;
  REQUIRE(delaunay_tetrahedralize(whole, all.data(), 1000).ok());
  CHECK(whole.num_real_tets() == m.num_real_tets());

  // A duplicate adds nothing; a point far outside the hull extends it.
  InsertResult r;
  const size_t nv = m.num_vertices();
  REQUIRE(ins.insert_point(&all[3 * 123], kNone, kVertexSteiner, &r).ok());
  CHECK(r.duplicate);
  CHECK(r.vertex == 123u);
  CHECK(m.num_vertices() == nv);
  const double far[3] = {10, -3, 0.5};
  std::vector<TetId> created;
  REQUIRE(insert_point(m, far, 0, &r, &created).ok());
  CHECK(!r.duplicate);
  CHECK(m.find_edge(r.vertex, kInfinite) != kNone);
  CHECK(!created.empty());
  validate(m);
}

TEST_CASE("insert_point with static bounds drops them at the first point outside their box",
          "[delaunay]") {
  std::vector<double> all = random_cube(1000, 12);
  for (size_t i = 3 * 500; i < 3 * 900; ++i) all[i] = 0.25 + all[i] / 2;  // well inside
  all[3 * 950] = 1.25;  // outside
  TetMesh m;
  REQUIRE(delaunay_tetrahedralize(m, all.data(), 500).ok());
  PointInserter ins(m);
  ins.set_box_bounds(pred::box_bounds(m.coords.data(), m.num_vertices(), 0x1p-20));
  REQUIRE(ins.box_bounds().insphere > 0);
  for (size_t i = 500; i < 1000; ++i) {
    InsertResult r;
    REQUIRE(ins.insert_point(&all[3 * i], ins.last_tet(), kVertexSteiner, &r).ok());
    // Point 950 lies outside the box of the first 500.
    CHECK((ins.box_bounds().insphere > 0) == (i < 950));
  }
  CHECK(ins.box_bounds().insphere == 0);
  const double far[3] = {10, -3, 0.5};
  REQUIRE(ins.insert_point(far, kNone).ok());
  validate(m);
  TetMesh whole;
  all.insert(all.end(), far, far + 3);
  REQUIRE(delaunay_tetrahedralize(whole, all.data(), 1001).ok());
  CHECK(whole.num_real_tets() == m.num_real_tets());
  // probe drops them too, and answers as without them.
  PointInserter with(m), without(m);
  with.set_box_bounds(pred::box_bounds(all.data(), 1000));
  const double out[3] = {-5, 0.5, 0.5}, in[3] = {0.5, 0.5, 0.5};
  std::vector<std::array<VertexId, 4>> fa, fb;
  REQUIRE(with.probe(in, kNone, fa));
  REQUIRE(without.probe(in, kNone, fb));
  CHECK(fa == fb);
  CHECK(with.box_bounds().insphere > 0);
  REQUIRE(with.probe(out, kNone, fa));
  REQUIRE(without.probe(out, kNone, fb));
  CHECK(fa == fb);
  CHECK(with.box_bounds().insphere == 0);
}

TEST_CASE("insert_point into a degenerate grid", "[delaunay]") {
  const std::vector<double> pts = grid(5, 5, 5);
  TetMesh m;
  REQUIRE(delaunay_tetrahedralize(m, pts.data(), pts.size() / 3).ok());
  PointInserter ins(m);
  // Cell centres, face centres and edge midpoints: all co-spherical cases,
  // plus points on the hull's planes outside it.
  for (double x = 0.5; x < 4; x += 1)
    for (double y = 0; y <= 4; y += 0.5) {
      const double p[3] = {x, y, 2.0};
      InsertResult r;
      REQUIRE(ins.insert_point(p, ins.last_tet(), kVertexSteiner, &r).ok());
    }
  for (double y = -1; y <= 5; y += 1) {
    const double p[3] = {0, y, 6};  // on the plane x = 0 of a hull facet
    REQUIRE(ins.insert_point(p, kNone).ok());
  }
  validate(m);
}

TEST_CASE("subset triangulation keeps global ids", "[delaunay]") {
  const std::vector<double> pts = grid(4, 4, 4);
  TetMesh m;
  m.coords = pts;
  std::vector<VertexId> subset;
  for (VertexId v = 0; v < 64; v += 2) subset.push_back(v);
  std::vector<VertexId> map;
  REQUIRE(delaunay_tetrahedralize_vertices(m, subset, &map).ok());
  validate(m);
  for (VertexId v = 0; v < 64; ++v) CHECK((m.vtet[v] != kNone) == (v % 2 == 0));
  CHECK(m.vkind[1] == kVertexNotInserted);
  CHECK(map == subset);
}

// The Delaunay tetrahedralization under the perturbation is unique, so these
// numbers depend neither on the insertion order nor on the platform: the
// native (libstdc++, x86-64) and WASM (libc++, wasm32) builds must agree.
// With duplicates, the copy inserted first stays, and its id enters the
// perturbation: the slab's numbers follow the spatial order (BRIO rounds from
// a fixed seed, the same on every platform). The hash is FNV-1a over the
// sorted list of sorted tets.
TEST_CASE("pinned tet counts and canonical hashes", "[delaunay]") {
  struct Case {
    const char* name;
    std::vector<double> pts;
    size_t tets, hull, duplicates;
    uint64_t hash;
  };
  std::vector<double> slab;
  Rng r(9);
  for (int i = 0; i < 5000; ++i)
    slab.insert(slab.end(), {double(r.below(20)), double(r.below(20)), r.below(3) * 0.5});
  std::vector<Case> cases = {
      {"random20k", random_cube(20000, 5), 133653, 280, 0, 0x923524aa45abac4eull},
      {"grid10", grid(10, 10, 10), 4374, 972, 0, 0x55820baff47d3853ull},
      {"sphere25", integer_sphere(25), 648, 296, 0, 0x2e1a56936e262cf7ull},
      {"slab with duplicates", slab, 4233, 1706, 3825, 0x365fdce62e3e3a20ull},
  };
  for (const Case& c : cases) {
    INFO(c.name);
    TetMesh m;
    DelaunayStats st;
    REQUIRE(delaunay_tetrahedralize(m, c.pts.data(), c.pts.size() / 3, nullptr, &st).ok());
    CHECK(st.tets == c.tets);
    CHECK(st.hull_faces == c.hull);
    CHECK(st.duplicates == c.duplicates);
    const auto canon = canonical_tets(m);
    uint64_t h = 1469598103934665603ull;
    for (const auto& x : canon)
      for (uint32_t v : x) h = (h ^ v) * 1099511628211ull;
    CHECK(h == c.hash);
  }
}

TEST_CASE(".node points: parse and errors", "[delaunay]") {
  std::vector<double> c;
  int first = -1;
  const std::string ok =
      "# comment\n4 3 1 1\n1 0 0 0 7 1\n2 1e0 0 0 7 0 # tail\n\n3 0 +1 0 7 1\n4 0 0 -0.5 7 0\n";
  REQUIRE(parse_node_points(ok.data(), ok.size(), "a.node", c, &first).ok());
  CHECK(first == 1);
  CHECK(c == std::vector<double>{0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, -0.5});

  const std::string trunc = "3 3 0 0\n0 0 0 0\n1 1 1 1\n";
  Status s = parse_node_points(trunc.data(), trunc.size(), "t.node", c);
  CHECK(s.error.code == ErrorCode::Truncated);
  const std::string nan = "2 3 0 0\n0 0 0 0\n1 nan 1 1\n";
  s = parse_node_points(nan.data(), nan.size(), "n.node", c);
  CHECK(s.error.code == ErrorCode::NonFinite);
  CHECK(s.error.line == 3);
  const std::string bad = "2 3 0 0\n0 0 0 0\n1 1x 1 1\n";
  CHECK(parse_node_points(bad.data(), bad.size(), "b.node", c).error.code == ErrorCode::Parse);
  const std::string dim2 = "2 2 0 0\n0 0 0\n1 1 1\n";
  CHECK(parse_node_points(dim2.data(), dim2.size(), "d.node", c).error.code == ErrorCode::Parse);
  CHECK(parse_node_points("", 0, "e.node", c).error.code == ErrorCode::Empty);
  const std::string gap = "2 3 0 0\n0 0 0 0\n2 1 1 1\n";
  CHECK(parse_node_points(gap.data(), gap.size(), "g.node", c).error.code == ErrorCode::Parse);

  // Duplicates stay (vertex i of the output is point i); -0 reads as +0 and
  // 17 digits (%.17g) give back the exact double.
  const std::string dup = "3 3\n0 1 1 1\n1 1 1 1\n2 -0 0.1 0.30000000000000004\n";
  REQUIRE(parse_node_points(dup.data(), dup.size(), "p.node", c, &first).ok());
  CHECK(first == 0);
  CHECK(c == std::vector<double>{1, 1, 1, 1, 1, 1, 0, 0.1, 0.30000000000000004});
  CHECK_FALSE(std::signbit(c[6]));
}

TEST_CASE("write_node_ele writes TetGen files numbered from 1", "[delaunay]") {
  namespace fs = std::filesystem;
  std::vector<double> pts = random_cube(200, 8);
  pts.insert(pts.end(), {pts[0], pts[1], pts[2]});  // a duplicate is still listed
  TetMesh m;
  REQUIRE(delaunay_tetrahedralize(m, pts.data(), 201).ok());
  const fs::path prefix = fs::temp_directory_path() / "cdt3d_test_write_node_ele";
  REQUIRE(write_node_ele(m, prefix.string()).ok());
  std::vector<double> back;
  int first = -1;
  REQUIRE(read_node_points_file(prefix.string() + ".node", back, &first).ok());
  CHECK(first == 1);
  CHECK(back == pts);  // %.17g round-trips exactly
  std::FILE* f = std::fopen((prefix.string() + ".ele").c_str(), "r");
  REQUIRE(f);
  size_t count = 0, seen = 0, wrong = 0;
  REQUIRE(std::fscanf(f, "%zu %*d %*d", &count) == 1);
  char line[256];
  while (std::fgets(line, sizeof line, f)) {
    unsigned long i, a, b, c, d;
    if (std::sscanf(line, "%lu %lu %lu %lu %lu", &i, &a, &b, &c, &d) != 5) continue;
    ++seen;
    CHECK(i == seen);
    // TetGen's orientation is the reverse of ours.
    if (pred::orient3d(&pts[3 * (a - 1)], &pts[3 * (b - 1)], &pts[3 * (c - 1)],
                       &pts[3 * (d - 1)]) >= 0)
      ++wrong;
  }
  std::fclose(f);
  CHECK(count == m.num_real_tets());
  CHECK(seen == count);
  CHECK(wrong == 0);
  fs::remove(prefix.string() + ".node");
  fs::remove(prefix.string() + ".ele");
}

TEST_CASE("Delaunay of the vertices of every model in tests/data", "[delaunay]") {
  namespace fs = std::filesystem;
  const fs::path dir = CDT3D_TEST_DATA;
  if (!fs::is_directory(dir)) return;
  std::vector<fs::path> files;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());  // deterministic order
  size_t meshed = 0;
  for (const fs::path& f : files) {
    Plc plc;
    if (!read_plc_file(f.string(), plc).ok()) continue;  // not a model, or invalid on purpose
    std::vector<double> pts;
    for (const Vec3& p : plc.points) pts.insert(pts.end(), {p.x, p.y, p.z});
    INFO(f.string() << ": " << plc.points.size() << " points");
    TetMesh m;
    DelaunayStats st;
    const Status s = delaunay_tetrahedralize(m, pts.data(), plc.points.size(), nullptr, &st);
    if (!s.ok()) {  // only a flat or tiny model may fail
      const ErrorCode c = s.error.code;
      CHECK(
          (c == ErrorCode::Coplanar || c == ErrorCode::Collinear || c == ErrorCode::TooFewPoints));
      continue;
    }
    ++meshed;
    CHECK(st.duplicates == 0);  // read_plc welds identical points
    const Status sm = check_mesh(m);
    INFO(sm.error.message);
    REQUIRE(sm.ok());
    const Status sd = check_delaunay(m);
    INFO(sd.error.message);
    REQUIRE(sd.ok());
    CHECK(euler_characteristic(m) == 1);
    check_hull_bounds_points(m);
  }
  WARN("Delaunay ran on " << meshed << " models from " << dir.string());
}

TEST_CASE("the two-thread build gives the one-thread tetrahedralization, slot for slot",
          "[delaunay]") {
  // From kMinTwoThreadDelaunayPoints on, the later BRIO rounds go to two
  // threads that lock the tets they touch, and the tets are then numbered
  // canonically: the mesh must equal the one-thread build's exactly, on
  // random points, on a co-spherical grid whose duplicates (two copies of
  // the grid, interleaved) make the two-thread build start over on one
  // thread, and on points of a sphere (every point on the hull).
  const size_t n = kMinTwoThreadDelaunayPoints + 5000;
  std::vector<double> sphere;
  Rng rng(17);
  while (sphere.size() < 3 * n) {
    double p[3], r2 = 0;
    for (double& x : p) x = 2 * (double(rng.next() >> 11) * 0x1p-53) - 1, r2 += x * x;
    if (r2 < 1e-3 || r2 > 1) continue;
    for (double x : p) sphere.push_back(x / std::sqrt(r2));
  }
  std::vector<double> twice = grid(24, 24, 24);
  const std::vector<double> copy = twice;
  twice.insert(twice.end(), copy.begin(), copy.end());
  const std::vector<double> sets[3] = {random_cube(n, 5), twice, sphere};
  for (int k = 0; k < 3; ++k) {
    const std::vector<double>& pts = sets[k];
    TetMesh one, two;
    DelaunayStats s1, s2;
    DelaunayOptions o1, o2;
    o2.threads = true;
    REQUIRE(delaunay_tetrahedralize(one, pts.data(), pts.size() / 3, nullptr, &s1, o1).ok());
    REQUIRE(delaunay_tetrahedralize(two, pts.data(), pts.size() / 3, nullptr, &s2, o2).ok());
    INFO("set " << k);
    REQUIRE(check_mesh(two).ok());
    CHECK(two.tv == one.tv);
    CHECK(two.tadj == one.tadj);
    CHECK(two.vtet == one.vtet);
    CHECK(two.vkind == one.vkind);
    CHECK(s2.tets == s1.tets);
    CHECK(s2.duplicates == s1.duplicates);
    CHECK(s1.points_beside == 0);
    if (k == 0 && std::thread::hardware_concurrency() > 1) CHECK(s2.points_beside > n / 4);
    if (k == 1) CHECK(s1.duplicates == copy.size() / 3);
  }
}
