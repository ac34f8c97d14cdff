// Facet triangulation (subfaces of X1/X2, Si & Gärtner 2005 §2, §7): hand-made
// facets with known answers, facets of tests/data models after segment
// recovery, and the 2D constrained Delaunay properties checked exactly.
#include <catch2/catch.hpp>

#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "delaunay.hpp"
#include "corpus.hpp"
#include "plc_intersect.hpp"
#include "predicates.hpp"
#include "segment_recovery.hpp"
#include "subfaces.hpp"
#include "tet_mesh.hpp"

using namespace cdt3d;

namespace {

using Edge = std::pair<VertexId, VertexId>;
Edge edge(VertexId a, VertexId b) { return a < b ? Edge{a, b} : Edge{b, a}; }

// A mesh holding only coordinates (triangulate_facets reads nothing else).
void coords_mesh(const Plc& plc, TetMesh& mesh) {
  mesh.clear();
  for (const Vec3& p : plc.points) mesh.add_vertex(&p.x, kVertexInput);
}

// Splits segment (a, b) of `segs` at the given points (parameters from a).
void split_segment(TetMesh& mesh, SegmentSet& segs, VertexId a, VertexId b,
                   const std::vector<double>& ts) {
  const std::array<VertexId, 2> k = {std::min(a, b), std::max(a, b)};
  const size_t s = std::lower_bound(segs.input.begin(), segs.input.end(), k) - segs.input.begin();
  REQUIRE(s < segs.input.size());
  REQUIRE(segs.input[s] == k);
  const double* A = mesh.point(k[0]);
  const double* B = mesh.point(k[1]);
  std::vector<VertexId> chain = {k[0]};
  for (double t : ts) {
    const double p[3] = {A[0] + t * (B[0] - A[0]), A[1] + t * (B[1] - A[1]),
                         A[2] + t * (B[2] - A[2])};
    chain.push_back(mesh.add_vertex(p, kVertexSteiner));
  }
  chain.push_back(k[1]);
  segs.chain[s].assign(chain.data(), chain.data() + chain.size());
}

std::vector<VertexId> chain_of(const SegmentSet& segs, VertexId a, VertexId b) {
  const std::array<VertexId, 2> k = {std::min(a, b), std::max(a, b)};
  const size_t s = std::lower_bound(segs.input.begin(), segs.input.end(), k) - segs.input.begin();
  std::vector<VertexId> c = segs.chain.at(s).to_vector();
  if (c.front() != a) std::reverse(c.begin(), c.end());
  return c;
}

std::array<double, 3> newell(const TetMesh& mesh, const std::vector<VertexId>& loop) {
  std::array<double, 3> n = {0, 0, 0};
  for (size_t i = 0; i < loop.size(); ++i) {
    const double* p = mesh.point(loop[i]);
    const double* q = mesh.point(loop[(i + 1) % loop.size()]);
    n[0] += (p[1] - q[1]) * (p[2] + q[2]);
    n[1] += (p[2] - q[2]) * (p[0] + q[0]);
    n[2] += (p[0] - q[0]) * (p[1] + q[1]);
  }
  return n;
}

double tri_area(const TetMesh& mesh, const std::array<VertexId, 3>& t) {
  const double* a = mesh.point(t[0]);
  const double* b = mesh.point(t[1]);
  const double* c = mesh.point(t[2]);
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double x = u[1] * w[2] - u[2] * w[1], y = u[2] * w[0] - u[0] * w[2],
               z = u[0] * w[1] - u[1] * w[0];
  return 0.5 * std::sqrt(x * x + y * y + z * z);
}

// Checks the subfaces of facet f: non-degenerate and consistently oriented in
// the projection (like loop 0), loop chain edges are edges, edges used once
// are exactly the chain edges, every other edge is locally Delaunay, and the
// area equals `area` (< 0: the area of loop 0).
std::set<Edge> all_subsegments(const SegmentSet& segs) {
  std::set<Edge> out;
  for (const auto& c : segs.chain)
    for (size_t k = 0; k + 1 < c.size(); ++k) out.insert(edge(c[k], c[k + 1]));
  return out;
}

void check_facet(const Plc& plc, const SegmentSet& segs, const TetMesh& mesh, const Subfaces& sf,
                 size_t f, double area = -1, const std::set<Edge>* subsegs = nullptr) {
  INFO("facet " << f);
  const Facet& facet = plc.facets[f];
  const std::array<double, 3> n = newell(mesh, facet.loops[0]);
  const int drop = std::fabs(n[0]) >= std::fabs(n[1])
                       ? (std::fabs(n[0]) >= std::fabs(n[2]) ? 0 : 2)
                       : (std::fabs(n[1]) >= std::fabs(n[2]) ? 1 : 2);
  const int sign = n[drop] > 0 ? 1 : -1;
  std::set<Edge> chain_edges;
  std::set<VertexId> chain_vertices;
  for (const auto& L : facet.loops)
    for (size_t i = 0; i < L.size(); ++i) {
      const auto c = chain_of(segs, L[i], L[(i + 1) % L.size()]);
      for (size_t k = 0; k + 1 < c.size(); ++k) chain_edges.insert(edge(c[k], c[k + 1]));
      chain_vertices.insert(c.begin(), c.end());
    }
  // Subsegments of every segment: constrained wherever they lie.
  const std::set<Edge> own = subsegs ? std::set<Edge>() : all_subsegments(segs);
  const std::set<Edge>& subsegments = subsegs ? *subsegs : own;
  std::map<Edge, std::vector<size_t>> uses;
  double sum = 0;
  size_t count = 0;
  const auto range = std::equal_range(sf.facet.begin(), sf.facet.end(), static_cast<uint32_t>(f));
  for (size_t i = range.first - sf.facet.begin(); i < size_t(range.second - sf.facet.begin()); ++i) {
    ++count;
    const auto& t = sf.tri[i];
    CHECK(pred::orient2d_projected(mesh.point(t[0]), mesh.point(t[1]), mesh.point(t[2]), drop) ==
          sign);
    sum += tri_area(mesh, t);
    for (int k = 0; k < 3; ++k) uses[edge(t[k], t[(k + 1) % 3])].push_back(i);
  }
  CHECK(count > 0);
  for (const Edge& e : chain_edges) {
    INFO("chain edge " << e.first << " " << e.second);
    CHECK(uses.count(e) == 1);
  }
  for (VertexId v : chain_vertices) {
    bool used = false;
    for (const auto& u : uses) used |= u.first.first == v || u.first.second == v;
    CHECK(used);
  }
  for (const auto& u : uses) {
    INFO("edge " << u.first.first << " " << u.first.second);
    CHECK(u.second.size() <= 2);
    if (u.second.size() == 1) CHECK(chain_edges.count(u.first) == 1);
    if (u.second.size() != 2 || subsegments.count(u.first)) continue;
    // Locally Delaunay in the projection (unperturbed: cocircular is fine).
    const auto& t1 = sf.tri[u.second[0]];
    const auto& t2 = sf.tri[u.second[1]];
    VertexId d = kNone;
    for (VertexId v : t2)
      if (v != u.first.first && v != u.first.second) d = v;
    double p[4][3];
    const VertexId ids[4] = {t1[0], t1[1], t1[2], d};
    for (int k = 0; k < 4; ++k) {
      const double* x = mesh.point(ids[k]);
      p[k][0] = x[(drop + 1) % 3];
      p[k][1] = x[(drop + 2) % 3];
    }
    const int ccw = pred::orient2d(p[0], p[1], p[2]) > 0;
    const int ic = ccw ? pred::incircle(p[0], p[1], p[2], p[3]) : pred::incircle(p[0], p[2], p[1], p[3]);
    CHECK(ic <= 0);
  }
  if (area < 0) {
    area = 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  }
  CHECK(sum == Approx(area).epsilon(1e-9));
}

Plc square_plc(double z = 0) {
  Plc plc;
  plc.points = {{0, 0, z}, {4, 0, z}, {4, 4, z}, {0, 4, z}};
  plc.facets.resize(1);
  plc.facets[0].loops = {{0, 1, 2, 3}};
  return plc;
}

Status run(const Plc& plc, const SegmentSet& segs, const TetMesh& mesh, Subfaces& sf,
           const std::vector<std::vector<VertexId>>& interior = {}) {
  return triangulate_facets(plc, segs, mesh, interior, sf);
}

// The model's points -> D0 -> segment recovery -> facet triangulation.
struct Pipeline {
  Plc plc;
  TetMesh mesh;
  SegmentSet segs;
  Subfaces sf;
  Status status;
};

void pipeline(const std::string& file, Pipeline& p) {
  Status st = read_plc_file(std::string(CDT3D_TEST_DATA) + "/" + file, p.plc);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  st = delaunay_tetrahedralize(p.mesh, &p.plc.points[0].x, p.plc.points.size());
  REQUIRE(st.ok());
  init_segments(p.plc, p.segs);
  st = recover_segments(p.mesh, p.segs);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  p.status = run(p.plc, p.segs, p.mesh, p.sf);
}

}  // namespace

TEST_CASE("an unsplit triangle facet is itself", "[subfaces]") {
  Plc plc;
  plc.points = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  plc.facets.resize(1);
  plc.facets[0].loops = {{0, 2, 1}};
  TetMesh mesh;
  coords_mesh(plc, mesh);
  SegmentSet segs;
  init_segments(plc, segs);
  Subfaces sf;
  REQUIRE(run(plc, segs, mesh, sf).ok());
  REQUIRE(sf.tri.size() == 1);
  CHECK(sf.tri[0] == std::array<VertexId, 3>{0, 2, 1});
  CHECK(sf.facet[0] == 0);
}

TEST_CASE("a triangle with k Steiner points on its edges gives k + 1 triangles", "[subfaces]") {
  // Tilted plane, rounded Steiner points: only nearly coplanar.
  Plc plc;
  plc.points = {{0.1, 0.2, 0.7}, {3.3, 0.4, -0.3}, {0.7, 2.9, 1.9}};
  plc.facets.resize(1);
  for (int orient = 0; orient < 2; ++orient) {
    plc.facets[0].loops = {orient ? std::vector<VertexId>{0, 1, 2} : std::vector<VertexId>{0, 2, 1}};
    for (int k0 = 0; k0 <= 3; ++k0)
      for (int k1 = 0; k1 <= 2; ++k1)
        for (int k2 = 0; k2 <= 4; k2 += 2) {
          TetMesh mesh;
          coords_mesh(plc, mesh);
          SegmentSet segs;
          init_segments(plc, segs);
          auto ts = [](int k) {
            std::vector<double> t;
            for (int i = 1; i <= k; ++i) t.push_back(std::pow(double(i) / (k + 1), 1.3));
            return t;
          };
          split_segment(mesh, segs, 0, 1, ts(k0));
          split_segment(mesh, segs, 1, 2, ts(k1));
          split_segment(mesh, segs, 0, 2, ts(k2));
          Subfaces sf;
          Status st = run(plc, segs, mesh, sf);
          INFO(st.error.to_string());
          REQUIRE(st.ok());
          CHECK(sf.tri.size() == size_t(k0 + k1 + k2 + 1));
          check_facet(plc, segs, mesh, sf, 0);
        }
  }
}

TEST_CASE("a square with a square hole", "[subfaces]") {
  Plc plc = square_plc();
  plc.points.push_back({1, 1, 0});
  plc.points.push_back({3, 1, 0});
  plc.points.push_back({3, 3, 0});
  plc.points.push_back({1, 3, 0});
  plc.facets[0].loops.push_back({4, 5, 6, 7});
  TetMesh mesh;
  coords_mesh(plc, mesh);
  SegmentSet segs;
  init_segments(plc, segs);
  Subfaces sf;

  SECTION("with a hole point the hole is removed") {
    plc.facets[0].holes.push_back({2, 2, 0});
    REQUIRE(run(plc, segs, mesh, sf).ok());
    CHECK(sf.tri.size() == 8);
    check_facet(plc, segs, mesh, sf, 0, 12.0);
  }
  SECTION("a hole point outside the facet removes nothing") {
    plc.facets[0].holes.push_back({7, 7, 0});
    REQUIRE(run(plc, segs, mesh, sf).ok());
    check_facet(plc, segs, mesh, sf, 0, 16.0);
  }
  SECTION("without a hole point the inner loop is an internal constraint") {
    REQUIRE(run(plc, segs, mesh, sf).ok());
    CHECK(sf.tri.size() == 10);
    check_facet(plc, segs, mesh, sf, 0, 16.0);
  }
  SECTION("split edges on both loops, hole point") {
    plc.facets[0].holes.push_back({2, 2, 0});
    split_segment(mesh, segs, 0, 1, {0.25, 0.5, 0.75});
    split_segment(mesh, segs, 5, 6, {0.3});
    REQUIRE(run(plc, segs, mesh, sf).ok());
    CHECK(sf.tri.size() == 12);
    check_facet(plc, segs, mesh, sf, 0, 12.0);
  }
}

TEST_CASE("an interior vertex splits the triangulation", "[subfaces]") {
  Plc plc = square_plc(2.5);
  plc.points.push_back({1, 1.5, 2.5});
  TetMesh mesh;
  coords_mesh(plc, mesh);
  SegmentSet segs;
  init_segments(plc, segs);
  Subfaces sf;
  REQUIRE(run(plc, segs, mesh, sf, {{4}}).ok());
  CHECK(sf.tri.size() == 4);
  check_facet(plc, segs, mesh, sf, 0);
}

TEST_CASE("a lattice facet large enough for point insertion", "[subfaces]") {
  // 17 x 17 lattice points (more than the sweep takes): rows and columns of
  // collinear points, split hull edges, every unit square cocircular.
  const int n = 16;
  Plc plc;
  plc.points = {{0, 0, 3}, {n, 0, 3}, {n, n, 3}, {0, n, 3}};
  std::vector<VertexId> interior;
  for (int i = 1; i < n; ++i)
    for (int j = 1; j < n; ++j) {
      interior.push_back(VertexId(plc.points.size()));
      plc.points.push_back({double(i), double(j), 3});
    }
  plc.facets.resize(1);
  plc.facets[0].loops = {{0, 1, 2, 3}};
  TetMesh mesh;
  coords_mesh(plc, mesh);
  SegmentSet segs;
  init_segments(plc, segs);
  std::vector<double> ts;
  for (int k = 1; k < n; ++k) ts.push_back(double(k) / n);  // exact: n is a power of 2
  for (int e = 0; e < 4; ++e) split_segment(mesh, segs, VertexId(e), VertexId((e + 1) % 4), ts);
  Subfaces sf;
  Status st = run(plc, segs, mesh, sf, {interior});
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  CHECK(sf.tri.size() == size_t(2 * n * n));
  check_facet(plc, segs, mesh, sf, 0, double(n * n));
}

TEST_CASE("cocircular vertices give one triangulation, whatever the loop order", "[subfaces]") {
  // A regular 12-gon (cocircular up to rounding; the square corners exactly).
  const double pi = 3.14159265358979323846;
  Plc plc;
  for (int i = 0; i < 12; ++i) plc.points.push_back({std::cos(2 * pi * i / 12), std::sin(2 * pi * i / 12), 5});
  plc.points.push_back({0, 0, 5});  // an isolated point in the facet: a vertex
  // Exactly cocircular: a square and an 8-gon on integer points of radius 5.
  Plc sq;
  sq.points = {{5, 0, 1}, {4, 3, 1}, {3, 4, 1}, {0, 5, 1}, {-3, 4, 1}, {-4, 3, 1},
               {-5, 0, 1}, {-4, -3, 1}, {-3, -4, 1}, {0, -5, 1}, {3, -4, 1}, {4, -3, 1}};
  for (Plc* p : {&plc, &sq}) {
    std::set<std::array<VertexId, 3>> first;
    for (int rot = 0; rot < 12; rot += 5) {
      std::vector<VertexId> loop;
      for (int i = 0; i < 12; ++i) loop.push_back(VertexId((i + rot) % 12));
      p->facets.assign(1, Facet());
      p->facets[0].loops = {loop};
      TetMesh mesh;
      coords_mesh(*p, mesh);
      SegmentSet segs;
      init_segments(*p, segs);
      Subfaces sf;
      REQUIRE(run(*p, segs, mesh, sf).ok());
      CHECK(sf.tri.size() == (p == &plc ? 12u : 10u));
      check_facet(*p, segs, mesh, sf, 0);
      std::set<std::array<VertexId, 3>> canon;
      for (auto t : sf.tri) {
        std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
        canon.insert(t);
      }
      if (rot == 0) first = canon;
      else CHECK(canon == first);
    }
  }
}

TEST_CASE("a non-convex star polygon with many vertices", "[subfaces]") {
  const double pi = 3.14159265358979323846;
  Plc plc;
  const int n = 300;
  std::vector<VertexId> loop;
  for (int i = 0; i < n; ++i) {
    const double r = (i % 2) ? 1.0 : 0.35 + 0.3 * std::sin(i * 0.37);
    const double a = 2 * pi * i / n;
    // In the plane x - 2 y + 0.5 z = 0.3 (rounded: nearly coplanar).
    const double x = r * std::cos(a), y = r * std::sin(a);
    plc.points.push_back({x, 0.3 * y + 0.1, (0.3 - x + 2 * (0.3 * y + 0.1)) / 0.5});
    loop.push_back(VertexId(i));
  }
  plc.facets.resize(1);
  plc.facets[0].loops = {loop};
  TetMesh mesh;
  coords_mesh(plc, mesh);
  SegmentSet segs;
  init_segments(plc, segs);
  Subfaces sf;
  Status st = run(plc, segs, mesh, sf);
  INFO(st.error.to_string());
  REQUIRE(st.ok());
  CHECK(sf.tri.size() == size_t(n - 2));
  check_facet(plc, segs, mesh, sf, 0);
}

TEST_CASE("facets of tests/data models after segment recovery", "[subfaces]") {
  for (const char* file : {"l_block.smesh", "hexagonal_prism_polygons.ply", "cube_internal_facet.poly",
                           "cube_dangling.poly", "nested_cubes_cavity.poly", "tetrahedron.off",
                           "cube_comments_colors.off", "right_prism.off", "schonhardt.off",
                           "fandisk.off"}) {
    INFO(file);
    Pipeline p;
    pipeline(file, p);
    INFO(p.status.error.to_string());
    REQUIRE(p.status.ok());
    const std::set<Edge> subsegs = all_subsegments(p.segs);
    for (size_t f = 0; f < p.plc.facets.size(); ++f)
      check_facet(p.plc, p.segs, p.mesh, p.sf, f, -1, &subsegs);
  }
}

// The pipeline skips the search for embedded points and segments on PLCs
// that passed the self-intersection test without explicit segments or
// loose points: the subfaces must be exactly those of the full search.
TEST_CASE("without embedded points the shortcut gives the same subfaces", "[subfaces]") {
  for (const char* file : {"fandisk.off", "bunny.off", "plate_holes_binary.stl",
                           "hexagonal_prism_polygons.ply", "l_block.smesh", "schonhardt.off"}) {
    INFO(file);
    Pipeline p;
    pipeline(file, p);
    REQUIRE(p.status.ok());
    REQUIRE(p.plc.segments.empty());
    std::vector<Intersection> found;
    find_self_intersections(p.plc, found);
    REQUIRE(found.empty());
    Subfaces fast;
    const Status st = triangulate_facets(p.plc, p.segs, p.mesh, {}, fast, true);
    INFO(st.error.to_string());
    REQUIRE(st.ok());
    CHECK(fast.tri == p.sf.tri);
    CHECK(fast.facet == p.sf.facet);
  }
}

TEST_CASE("the L-shaped hexagon keeps its notch empty", "[subfaces]") {
  Pipeline p;
  pipeline("l_block.smesh", p);
  REQUIRE(p.status.ok());
  for (size_t f : {0, 1}) {
    size_t n = 0;
    double area = 0;
    for (size_t i = 0; i < p.sf.tri.size(); ++i)
      if (p.sf.facet[i] == f) ++n, area += tri_area(p.mesh, p.sf.tri[i]);
    CHECK(area == Approx(5.0));
    CHECK(n >= 4);
  }
}

TEST_CASE("PLC points and segments lying in a facet are part of it", "[subfaces]") {
  SECTION("an explicit diagonal segment") {
    Plc plc = square_plc();
    plc.segments.push_back({1, 3});
    TetMesh mesh;
    coords_mesh(plc, mesh);
    SegmentSet segs;
    init_segments(plc, segs);
    Subfaces sf;
    REQUIRE(run(plc, segs, mesh, sf).ok());
    REQUIRE(sf.tri.size() == 2);
    for (const auto& t : sf.tri) {
      CHECK(std::count(t.begin(), t.end(), 1u) == 1);
      CHECK(std::count(t.begin(), t.end(), 3u) == 1);
    }
  }
  SECTION("a split segment inside, a point outside the facet in its plane") {
    Plc plc = square_plc();
    plc.points.push_back({1, 2, 0});   // 4
    plc.points.push_back({3, 2, 0});   // 5
    plc.points.push_back({9, 9, 0});   // 6: outside the box
    plc.points.push_back({2, 2, 1});   // 7: off the plane
    plc.facets.push_back(Facet());     // a vertical facet standing on segment 4-5
    plc.facets[1].loops = {{4, 5, 7}};
    TetMesh mesh;
    coords_mesh(plc, mesh);
    SegmentSet segs;
    init_segments(plc, segs);
    split_segment(mesh, segs, 4, 5, {0.5});
    Subfaces sf;
    REQUIRE(run(plc, segs, mesh, sf).ok());
    check_facet(plc, segs, mesh, sf, 1);
    std::set<Edge> edges;
    size_t n0 = 0;
    for (size_t i = 0; i < sf.tri.size(); ++i) {
      if (sf.facet[i] != 0) continue;
      ++n0;
      for (int k = 0; k < 3; ++k) edges.insert(edge(sf.tri[i][k], sf.tri[i][(k + 1) % 3]));
      for (VertexId v : sf.tri[i]) CHECK(v != 6);
    }
    CHECK(n0 == 8);  // 4 corners + 3 inner vertices: 2 * 7 - 4 - 2
    CHECK(edges.count(edge(4, 8)) == 1);
    CHECK(edges.count(edge(8, 5)) == 1);
  }
  SECTION("cube_dangling.poly: the bottom holds the dangling facet's edge") {
    Pipeline p;
    pipeline("cube_dangling.poly", p);
    REQUIRE(p.status.ok());
    const auto c = chain_of(p.segs, 8, 9);
    std::set<Edge> edges;
    for (size_t i = 0; i < p.sf.tri.size(); ++i)
      if (p.sf.facet[i] == 0)
        for (int k = 0; k < 3; ++k) edges.insert(edge(p.sf.tri[i][k], p.sf.tri[i][(k + 1) % 3]));
    for (size_t k = 0; k + 1 < c.size(); ++k) CHECK(edges.count(edge(c[k], c[k + 1])) == 1);
  }
}

TEST_CASE("a loop edge that is not a segment is an error naming the facet", "[subfaces]") {
  Plc plc = square_plc();
  TetMesh mesh;
  coords_mesh(plc, mesh);
  SegmentSet segs;
  init_segments(plc, segs);
  plc.facets.push_back(Facet());
  plc.facets[1].loops = {{0, 1, 2}};  // edge (0, 2) is no segment
  Subfaces sf;
  Status st = run(plc, segs, mesh, sf);
  CHECK(st.error.code == ErrorCode::Internal);
  CHECK(st.error.facet == 1);
}

TEST_CASE("facet triangulation on every valid model of tests/data", "[subfaces][corpus]") {
  int models = 0;
  for (const std::string& file : corpus::valid_models()) {
    DYNAMIC_SECTION(file) {
      Pipeline p;
      pipeline(file, p);
      INFO(p.status.error.to_string());
      REQUIRE(p.status.ok());
        const std::set<Edge> subsegs = all_subsegments(p.segs);
      for (size_t f = 0; f < p.plc.facets.size(); ++f)
        check_facet(p.plc, p.segs, p.mesh, p.sf, f, -1, &subsegs);
    }
    ++models;
  }
  CHECK(models >= 10);
}
