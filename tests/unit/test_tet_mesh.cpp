// TetMesh storage and queries: slot reuse, epochs, star traversal, edge and
// face lookup, compaction; spatial sort properties.
#include <algorithm>
#include <catch2/catch.hpp>
#include <set>
#include <vector>

#include "blocks.hpp"
#include "delaunay.hpp"
#include "radix_sort.hpp"
#include "spatial_sort.hpp"
#include "tet_mesh.hpp"

using namespace cdt3d;

namespace {

// The unit tet's corners plus one interior point (id 4): 4 real tets.
TetMesh tet_with_center() {
  const std::vector<double> pts = {0, 0, 0, 4, 0, 0, 0, 4, 0, 0, 0, 4, 1, 1, 1};
  TetMesh m;
  REQUIRE(delaunay_tetrahedralize(m, pts.data(), 5).ok());
  return m;
}

}  // namespace

TEST_CASE("kFaceVertex lists each face counterclockwise from outside", "[tet_mesh]") {
  // Even permutations: orient3d(face, opposite) has the tet's sign.
  const double p[4][3] = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}};
  REQUIRE(pred::orient3d(p[0], p[1], p[2], p[3]) > 0);
  for (int i = 0; i < 4; ++i) {
    const int* f = kFaceVertex[i];
    CHECK(pred::orient3d(p[f[0]], p[f[1]], p[f[2]], p[i]) > 0);
    std::set<int> s{f[0], f[1], f[2], i};
    CHECK(s.size() == 4);
  }
}

TEST_CASE("half-face ids pack tet and face", "[tet_mesh]") {
  const HalfFace hf = make_hf(12345, 3);
  CHECK(hf_tet(hf) == 12345u);
  CHECK(hf_face(hf) == 3);
}

TEST_CASE("alloc_tet reuses freed slots last-in first-out", "[tet_mesh]") {
  TetMesh m;
  const TetId a = m.alloc_tet(), b = m.alloc_tet(), c = m.alloc_tet();
  CHECK(m.live_tets == 3);
  m.free_tet(a);
  m.free_tet(c);
  CHECK(m.live_tets == 1);
  CHECK(m.is_dead(a));
  CHECK(m.alloc_tet() == c);
  CHECK(m.alloc_tet() == a);
  CHECK(!m.is_dead(a));
  CHECK(m.alloc_tet() == 3u);
  CHECK(m.num_tet_slots() == 4);
  (void)b;
}

TEST_CASE("epochs make stamps fresh without clearing", "[tet_mesh]") {
  TetMesh m;
  const TetId t = m.alloc_tet();
  const uint32_t e1 = m.next_epoch();
  m.stamp(t, e1);
  CHECK(m.stamped(t, e1));
  const uint32_t e2 = m.next_epoch();
  CHECK(!m.stamped(t, e2));
  m.epoch = 0xffffffffu;  // force the wrap-around
  const uint32_t e3 = m.next_epoch();
  CHECK(e3 == 1u);
  CHECK(!m.stamped(t, e3));
}

TEST_CASE("star, edge and face queries on a small mesh", "[tet_mesh]") {
  TetMesh m = tet_with_center();
  REQUIRE(check_mesh(m).ok());
  CHECK(m.num_real_tets() == 4);
  CHECK(m.num_ghost_tets() == 4);

  std::vector<TetId> star;
  m.vertex_star(4, star);  // interior vertex: the 4 real tets
  CHECK(star.size() == 4);
  for (TetId t : star) CHECK(!m.is_ghost(t));
  m.vertex_star(0, star);  // corner: 3 real tets + 3 ghosts
  CHECK(star.size() == 6);

  std::vector<VertexId> nb;
  m.vertex_neighbors(4, nb);
  CHECK(nb == std::vector<VertexId>{0, 1, 2, 3});

  for (VertexId a = 0; a < 5; ++a)
    for (VertexId b = 0; b < 5; ++b) {
      if (a == b) continue;
      const TetId t = m.find_edge(a, b);  // the complete graph K5 is present
      REQUIRE(t != kNone);
      CHECK(m.index_in_tet(t, a) >= 0);
      CHECK(m.index_in_tet(t, b) >= 0);
    }
  CHECK(m.find_edge(0, 0) == kNone);
  CHECK(m.find_edge(0, kInfinite) != kNone);  // hull vertex
  CHECK(m.find_edge(4, kInfinite) == kNone);  // interior vertex

  const HalfFace hf = m.find_face(1, 2, 3);  // hull face
  REQUIRE(hf != kNone);
  const TetId t = hf_tet(hf);
  CHECK(m.vertex(t, hf_face(hf)) != 1);
  CHECK(m.index_in_tet(t, 1) >= 0);
  CHECK(m.find_face(0, 1, 4) != kNone);

  std::vector<uint32_t> hull;
  m.hull_faces(hull);
  CHECK(hull.size() == 12);
  const double* c = m.point(4);
  for (size_t k = 0; k < hull.size(); k += 3)  // center below every outward face
    CHECK(pred::orient3d(m.point(hull[k]), m.point(hull[k + 1]), m.point(hull[k + 2]), c) > 0);
}

TEST_CASE("compact removes dead slots and keeps the mesh valid", "[tet_mesh]") {
  std::vector<double> pts;
  Rng rng(7);
  for (int i = 0; i < 3 * 300; ++i) pts.push_back(double(rng.below(1000)) / 7.0);
  TetMesh m;
  REQUIRE(delaunay_tetrahedralize(m, pts.data(), 300).ok());
  // Insert more points so that some slots die.
  PointInserter ins(m);
  for (int i = 0; i < 50; ++i) {
    const double p[3] = {double(rng.below(1000)) / 7.0 + 0.01, double(rng.below(1000)) / 7.0,
                         double(rng.below(1000)) / 7.0};
    REQUIRE(ins.insert_point(p, ins.last_tet()).ok());
  }
  std::vector<uint32_t> before;
  m.real_tets(before);
  m.compact();
  CHECK(m.free_tets.empty());
  CHECK(m.num_tet_slots() == m.live_tets);
  REQUIRE(check_mesh(m).ok());
  REQUIRE(check_delaunay(m).ok());
  std::vector<uint32_t> after;
  m.real_tets(after);
  CHECK(before == after);  // survivors keep their order
}

TEST_CASE("Hilbert keys walk the grid cell by cell", "[tet_mesh][spatial_sort]") {
  const int bits = 3;
  const uint32_t side = 1u << bits;
  std::vector<std::array<uint32_t, 3>> by_key(side * side * side, {~0u, ~0u, ~0u});
  for (uint32_t x = 0; x < side; ++x)
    for (uint32_t y = 0; y < side; ++y)
      for (uint32_t z = 0; z < side; ++z) {
        const uint64_t k = hilbert_key(x, y, z, bits);
        REQUIRE(k < by_key.size());
        REQUIRE(by_key[k][0] == ~0u);  // a bijection
        by_key[k] = {x, y, z};
      }
  for (size_t k = 1; k < by_key.size(); ++k) {
    int dist = 0;
    for (int a = 0; a < 3; ++a) dist += std::abs(int(by_key[k][a]) - int(by_key[k - 1][a]));
    CHECK(dist == 1);  // consecutive cells are face neighbours
  }
}

TEST_CASE("brio_order is a deterministic permutation", "[tet_mesh][spatial_sort]") {
  std::vector<double> pts;
  Rng rng(99);
  const size_t n = 5000;
  for (size_t i = 0; i < 3 * n; ++i) pts.push_back(double(rng.next() >> 11) * 0x1p-53);
  std::vector<VertexId> ids(n);
  for (size_t i = 0; i < n; ++i) ids[i] = VertexId(i);
  std::vector<VertexId> a, b, c;
  brio_order(pts.data(), ids, 1, a);
  brio_order(pts.data(), ids, 1, b);
  brio_order(pts.data(), ids, 2, c);
  CHECK(a == b);
  CHECK(a != c);
  std::vector<VertexId> sorted = a;
  std::sort(sorted.begin(), sorted.end());
  CHECK(sorted == ids);
}

TEST_CASE("radix_sort_by: the pass and the comparison paths sort alike", "[tet_mesh][spatial_sort]") {
  // Both must give the stable order by the bits of whole 11-bit passes from
  // lo ([lo, lo + 11k) covering [lo, hi)): small arrays take comparisons,
  // larger ones the passes. Keys with bits outside [lo, hi) and many equal
  // keys (their payloads must keep their order).
  Rng rng(5);
  for (size_t n : {size_t(0), size_t(1), size_t(2), size_t(7), size_t(100), kSmallSort - 1,
                   kSmallSort, size_t(3000)}) {
    for (const auto& [lo, hi] : {std::pair{0, 20}, {32, 55}, {3, 64}, {40, 64}}) {
      std::vector<std::pair<uint64_t, uint32_t>> a(n);
      for (size_t i = 0; i < n; ++i) {
        uint64_t k = rng.next();
        if (i % 3) k &= ~(uint64_t(0xfff) << lo);  // frequent equal digits
        a[i] = {k, uint32_t(i)};
      }
      const int top = lo + 11 * ((hi - lo + 10) / 11);
      const uint64_t mask = top - lo >= 64 ? ~uint64_t(0) : (uint64_t(1) << (top - lo)) - 1;
      auto want = a;
      std::stable_sort(want.begin(), want.end(), [&](const auto& x, const auto& y) {
        return ((x.first >> lo) & mask) < ((y.first >> lo) & mask);
      });
      radix_sort_by(a, [](const std::pair<uint64_t, uint32_t>& x) { return x.first; }, lo, hi);
      CHECK(a == want);
    }
  }
}

TEST_CASE("Rng is splitmix64", "[tet_mesh][spatial_sort]") {
  Rng r(0);  // reference values of splitmix64 seeded with 0
  CHECK(r.next() == 0xe220a8397b1dcdafull);
  CHECK(r.next() == 0x6e789e6aa1b965f4ull);
  for (int i = 0; i < 1000; ++i) CHECK(r.below(7) < 7u);
}

TEST_CASE("replace_tets rewires a region and refuses tets that do not fill it", "[tet_mesh]") {
  // The 4 tets around the centre of the unit tet become the unit tet (a 4-1
  // flip: the faces on the region's boundary match exactly).
  TetMesh m = tet_with_center();
  std::vector<TetId> around;
  m.vertex_star(4, around);
  REQUIRE(around.size() == 4);
  std::vector<TetId> kept_copy = around;
  const size_t live = m.live_tets;
  // A wrong replacement (a tet not filling the region) changes nothing.
  const std::array<VertexId, 4> wrong[1] = {{0, 1, 2, 4}};
  CHECK_FALSE(m.replace_tets(around.data(), around.size(), wrong, 1));
  CHECK(m.live_tets == live);
  REQUIRE(check_mesh(m).ok());
  // The unit tet itself, positively oriented, fills it (vertex 4 leaves the
  // triangulation, which replace_tets does not track: mark it like a vertex
  // that was never inserted so that the invariants hold).
  std::array<VertexId, 4> whole = {0, 1, 2, 3};
  if (pred::orient3d(m.point(0), m.point(1), m.point(2), m.point(3)) < 0) std::swap(whole[0], whole[1]);
  std::vector<TetId> created;
  REQUIRE(m.replace_tets(kept_copy.data(), kept_copy.size(), &whole, 1, &created));
  m.vtet[4] = kNone;
  m.vkind[4] = kVertexNotInserted;
  CHECK(created.size() == 1);
  CHECK(created[0] == kept_copy[0]);  // fresh tet j takes old[j]
  CHECK(m.live_tets == live - 3);
  const Status st = check_mesh(m);
  INFO(st.error.message);
  CHECK(st.ok());
  // The leftover slots come back out in the order of `old`.
  CHECK(m.alloc_tet() == kept_copy[1]);
  CHECK(m.alloc_tet() == kept_copy[2]);
}

TEST_CASE("replace_tets matches the faces of new ghost tets", "[tet_mesh]") {
  // The whole mesh (4 tets around the centre and their 4 ghosts) becomes the
  // unit tet and 4 new ghosts: every face pairs two new tets.
  TetMesh m = tet_with_center();
  std::vector<TetId> all;
  for (TetId t = 0; t < m.num_tet_slots(); ++t)
    if (!m.is_dead(t)) all.push_back(t);
  REQUIRE(all.size() == 8);
  std::array<VertexId, 4> fresh[5] = {{0, 1, 2, 3}};
  if (pred::orient3d(m.point(0), m.point(1), m.point(2), m.point(3)) < 0)
    std::swap(fresh[0][0], fresh[0][1]);
  // Ghost i over face i of the unit tet: that face seen from the other side.
  for (int i = 0; i < 4; ++i) {
    const int* f = kFaceVertex[i];
    fresh[1 + i] = {fresh[0][f[0]], fresh[0][f[2]], fresh[0][f[1]], kInfinite};
  }
  std::vector<TetId> created;
  REQUIRE(m.replace_tets(all.data(), all.size(), fresh, 5, &created));
  m.vtet[4] = kNone;
  m.vkind[4] = kVertexNotInserted;
  CHECK(m.num_real_tets() == 1);
  CHECK(m.num_ghost_tets() == 4);
  const Status st = check_mesh(m);
  INFO(st.error.message);
  CHECK(st.ok());
}

TEST_CASE("for_blocks covers 0..n-1 in order and stops when asked", "[tet_mesh][blocks]") {
  for (size_t n : {size_t(0), size_t(1), kBlockItems - 1, kBlockItems, kBlockItems + 1,
                   3 * kBlockItems + 5}) {
    std::vector<size_t> seen;
    size_t calls = 0;
    CHECK(for_blocks(n, [&](size_t begin, size_t end) {
      ++calls;
      CHECK(end - begin <= kBlockItems);
      for (size_t i = begin; i < end; ++i) seen.push_back(i);
      return true;
    }));
    CHECK(calls == (n + kBlockItems - 1) / kBlockItems);
    REQUIRE(seen.size() == n);
    for (size_t i = 0; i < n; ++i) CHECK(seen[i] == i);
  }
  // A body that returns false ends the loop: no later block runs.
  const uint64_t n = uint64_t(5) * kBlockItems;
  uint64_t last = 0;
  CHECK_FALSE(for_blocks(n, [&](uint64_t begin, uint64_t end) {
    last = end;
    return begin < 2 * kBlockItems;
  }));
  CHECK(last == 3 * kBlockItems);
}
