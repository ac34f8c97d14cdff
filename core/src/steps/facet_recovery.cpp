// Step 4 (Si & Gärtner 2005 §7, "Facet Recovery"): missing subfaces are
// grouped into missing regions and recovered by cavity retetrahedralization
// (cavity.cpp) until none is missing; subfaces that a recovery destroys are
// queued again (Theorem 4).
#include "facet_recovery.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <deque>
#include <memory>
#include <string>

#include "beside.hpp"
#include "cavity.hpp"
#include "geometry.hpp"
#include "predicates.hpp"
#include "radix_sort.hpp"
#include "status.hpp"

namespace cdt3d {

namespace {

// Face and edge lookups in the mesh through the star of a vertex, with
// reusable buffers (TetMesh::find_face allocates on every call).
class MeshQuery {
 public:
  explicit MeshQuery(TetMesh& m) : m_(m) {}

  bool has_face(VertexId a, VertexId b, VertexId c) {
    return walk_star(
        a, [&](TetId t) { return m_.index_in_tet(t, b) >= 0 && m_.index_in_tet(t, c) >= 0; });
  }
  bool has_edge(VertexId a, VertexId b) {
    return walk_star(a, [&](TetId t) { return m_.index_in_tet(t, b) >= 0; });
  }

 private:
  template <typename F>
  bool walk_star(VertexId a, F hit) {
    if (a >= m_.num_vertices() || m_.vtet[a] == kNone) return false;
    const uint32_t e = m_.next_epoch();
    queue_.clear();
    queue_.push_back(m_.vtet[a]);
    m_.stamp(m_.vtet[a], e);
    for (size_t k = 0; k < queue_.size(); ++k) {
      const TetId t = queue_[k];
      if (hit(t)) return true;
      const int ia = m_.index_in_tet(t, a);
      for (int i = 0; i < 4; ++i) {
        if (i == ia) continue;
        const TetId n = m_.neighbor(t, i);
        if (!m_.stamped(n, e)) {
          m_.stamp(n, e);
          queue_.push_back(n);
        }
      }
    }
    return false;
  }

  TetMesh& m_;
  std::vector<TetId> queue_;
};

VertexId max_vertex(const Subfaces& sf) {
  VertexId m = 0;
  for (const Triangle& t : sf.tri) m = std::max(m, std::max(t[0], std::max(t[1], t[2])));
  return m;
}

// Per subface and edge k (tri[k], tri[k+1]): the subface of the same facet
// across that edge, or kNone; and whether the edge is shared with another
// facet or by more than two subfaces (then it is a segment, never flipped).
void subface_adjacency(const Subfaces& sf, std::vector<uint32_t>& nbr,
                       std::vector<uint8_t>& fixed) {
  const size_t n = sf.tri.size();
  // (edge key, facet << 32 | slot): sorting pairs of integers is much faster
  // than a struct with a lambda on a few hundred thousand subfaces.
  std::vector<std::pair<uint64_t, uint64_t>> es;
  es.reserve(3 * n);
  for (uint32_t s = 0; s < n; ++s)
    for (int k = 0; k < 3; ++k) {
      const VertexId a = sf.tri[s][k], b = sf.tri[s][(k + 1) % 3];
      es.push_back({edge_key(a, b), uint64_t(sf.facet[s]) << 32 | (3 * s + k)});
    }
  // By edge alone, stably (radix on a compacted key of 2b bits): what is
  // decided below does not depend on the order within one edge's group.
  const int b = index_bits(size_t(max_vertex(sf)) + 2);
  const uint64_t mask = (uint64_t(1) << b) - 1;
  if (b <= 31)
    radix_sort_by(
        es, [b, mask](const std::pair<uint64_t, uint64_t>& e) {
          return ((e.first >> 32) << b) | (e.first & mask);
        },
        0, 2 * b);
  else
    std::sort(es.begin(), es.end());
  nbr.assign(3 * n, kNone);
  fixed.assign(3 * n, 0);
  auto facet = [](uint64_t x) { return uint32_t(x >> 32); };
  auto slot = [](uint64_t x) { return uint32_t(x & 0xffffffffu); };
  for (size_t i = 0; i < es.size();) {
    size_t j = i;
    while (j < es.size() && es[j].first == es[i].first) ++j;
    const bool pair = j - i == 2 && facet(es[i].second) == facet(es[i + 1].second);
    if (pair) {
      nbr[slot(es[i].second)] = slot(es[i + 1].second) / 3;
      nbr[slot(es[i + 1].second)] = slot(es[i].second) / 3;
    }
    for (size_t k = i; k < j; ++k) fixed[slot(es[k].second)] = !pair;
    i = j;
  }
}

// Sorted vertex triples of the subfaces, looked up by an open-addressing hash
// (lookups only; nothing is decided by iterating it).
class SubfaceIndex {
 public:
  explicit SubfaceIndex(const Subfaces& sf) {
    const size_t n = sf.tri.size();
    by_key_.resize(n);
    for (uint32_t s = 0; s < n; ++s) by_key_[s] = {sorted_triangle(sf.tri[s]), s};
    // By triple, then subface: a stable radix sort of the subfaces listed in
    // order gives std::sort's order of the pairs when a triple packs into 64
    // bits (cheaper than comparing the arrays).
    const int b = index_bits(size_t(max_vertex(sf)) + 1);
    if (3 * b <= 64)
      radix_sort_by(
          by_key_,
          [b](const std::pair<Triangle, uint32_t>& e) {
            return (uint64_t(e.first[0]) << (2 * b)) | (uint64_t(e.first[1]) << b) | e.first[2];
          },
          0, 3 * b);
    else
      std::sort(by_key_.begin(), by_key_.end());
    size_t cap = 16;
    while (cap < 2 * n + 16) cap *= 2;
    mask_ = cap - 1;
    slot_.assign(cap, kNone);
    for (uint32_t i = 0; i < n; ++i) {
      if (i > 0 && by_key_[i].first == by_key_[i - 1].first) continue;
      size_t h = hash(by_key_[i].first) & mask_;
      while (slot_[h] != kNone) h = (h + 1) & mask_;
      slot_[h] = i;
    }
  }
  /// Calls f(subface) for every subface with these sorted vertices.
  template <typename F>
  void for_each(const Triangle& key, F f) const {
    size_t h = hash(key) & mask_;
    for (; slot_[h] != kNone; h = (h + 1) & mask_) {
      if (by_key_[slot_[h]].first != key) continue;
      for (size_t i = slot_[h]; i < by_key_.size() && by_key_[i].first == key; ++i)
        f(by_key_[i].second);
      return;
    }
  }

 private:
  static size_t hash(const Triangle& k) {
    uint64_t x = (uint64_t(k[0]) * 0x9e3779b97f4a7c15ull) ^
                 (uint64_t(k[1]) * 0xc2b2ae3d27d4eb4full) ^
                 (uint64_t(k[2]) * 0x165667b19e3779f9ull);
    x ^= x >> 29;
    x *= 0xbf58476d1ce4e5b9ull;
    return static_cast<size_t>(x ^ (x >> 32));
  }
  std::vector<std::pair<Triangle, uint32_t>> by_key_;
  std::vector<uint32_t> slot_;
  size_t mask_ = 0;
};

// Subfaces are grouped by their smallest vertex (counting sort), each entry
// holding the other two vertices packed in one 64-bit key next to its
// subface, so a lookup scans a short contiguous run instead of chasing the
// subface's triangle; a pass over the real tets in slot order (memory order)
// checks each of their faces against the group of its smallest vertex:
// cheaper than a star walk per subface. Every face with finite vertices
// belongs to a real tet.
class SubfaceFaces {
 public:
  SubfaceFaces(const Subfaces& sf, size_t num_vertices)
      : start_(num_vertices + 1, 0), entries_(sf.tri.size()) {
    const size_t n = sf.tri.size();
    auto key_of = [&](uint32_t s) { return sorted_triangle(sf.tri[s]); };
    for (uint32_t s = 0; s < n; ++s) ++start_[key_of(s)[0] + 1];
    for (size_t v = 0; v < num_vertices; ++v) start_[v + 1] += start_[v];
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    for (uint32_t s = 0; s < n; ++s) {
      const Triangle k = key_of(s);
      entries_[fill[k[0]]++] = {(uint64_t(k[1]) << 32) | k[2], s};
    }
  }

  // out[s] = the first half-face in slot order, among the real tets of
  // slots [begin, end), that holds subface s (entries already set stay).
  void scan(const TetMesh& mesh, TetId begin, TetId end, std::vector<HalfFace>& out) const {
    for (TetId t = begin; t < end; ++t) {
      if (mesh.is_dead(t)) continue;
      const VertexId* w = mesh.tet_vertices(t);
      if (w[3] == kInfinite) continue;
      for (int i = 0; i < 4; ++i) {
        // A face between two real tets was checked with the first of them
        // in slot order, which is the one it gets: half the lookups.
        const HalfFace nb = mesh.adjacent(make_hf(t, i));
        if (nb != kNoHalfFace && hf_tet(nb) < t && !mesh.is_ghost(hf_tet(nb))) continue;
        const Triangle key =
            sorted_triangle({w[kFaceVertex[i][0]], w[kFaceVertex[i][1]], w[kFaceVertex[i][2]]});
        const uint64_t rest = (uint64_t(key[1]) << 32) | key[2];
        for (uint32_t j = start_[key[0]]; j < start_[key[0] + 1]; ++j)
          if (entries_[j].rest == rest && out[entries_[j].s] == kNone)
            out[entries_[j].s] = make_hf(t, i);
      }
    }
  }

 private:
  struct Entry {
    uint64_t rest;  // the two larger vertices, ascending, packed
    uint32_t s;
  };
  std::vector<uint32_t> start_;
  std::vector<Entry> entries_;
};

// missing[s] = 1 unless subface s is a face of the mesh; hf: subface_half_faces.
void find_missing(const TetMesh& mesh, const Subfaces& sf, std::vector<uint8_t>& missing,
                  std::vector<HalfFace>& hf) {
  subface_half_faces(mesh, sf, hf);
  for (size_t s = 0; s < hf.size(); ++s) missing[s] = hf[s] == kNone;
}

// Diagonal flips of missing facet edges that make the facet triangulation
// agree with the mesh where the two may legitimately differ. For a missing
// edge ab (not a segment) between subfaces abc and bad of one facet:
//  * Co-circular tie. For four exactly co-circular coplanar points the
//    symbolic perturbation of insphere (sos.cpp, pred::sos_raised_before)
//    puts the point raised first outside the circle of the other three, so the
//    perturbed Delaunay diagonal is the one not touching it. A facet
//    triangulated with the other diagonal has subfaces that are not
//    Delaunay in any perturbed sense, and no cavity could recover them.
//  * The quadrilateral is strictly convex in the facet's projection and d
//    lies strictly inside the circle of abc in the facet's own plane
//    (pred::incircle_coplanar). A triangulation made with incircle tests on
//    a projection to a coordinate plane is Delaunay there, not in the plane
//    of a tilted facet (projection distorts circles); a subface that is not
//    Delaunay in its plane is not strongly Delaunay in any cavity, and
//    recovering it would leave tets that are not constrained Delaunay.
//  * The quadrilateral is strictly convex and the mesh already holds both
//    triangles acd and dbc: the facet is only nearly planar (rounded Steiner
//    vertices) or nearly co-circular, the 2D and 3D tests disagree by
//    rounding, and recovering abc and bad would fold the facet along ab.
// Either flip leaves a triangulation of the same facet region whose subfaces
// the mesh can hold; it is counted in FacetRecoveryStats::subface_flips.
// `nbr`, `fixed` (subface_adjacency) and `missing` (per subface: not a face
// of the mesh) are kept up to date across the flips.
size_t flip_toward_mesh_impl(TetMesh& mesh, Subfaces& sf, MeshQuery& q, std::vector<uint32_t>& nbr,
                             std::vector<uint8_t>& fixed, std::vector<uint8_t>& missing) {
  size_t flips = 0;
  std::vector<uint32_t> todo;
  for (uint32_t s = 0; s < sf.tri.size(); ++s)
    if (missing[s]) todo.push_back(s);
  // Slot of edge {x, y} in subface s (edge k joins tri[k] and tri[k+1]).
  auto slot = [&](uint32_t s, VertexId x, VertexId y) {
    for (int k = 0; k < 3; ++k) {
      const VertexId u = sf.tri[s][k], w = sf.tri[s][(k + 1) % 3];
      if ((u == x && w == y) || (u == y && w == x)) return 3 * s + k;
    }
    return kNone;
  };
  std::vector<uint8_t> flipped(sf.tri.size(), 0);
  for (int pass = 0; pass < 64; ++pass) {
    const size_t before = flips;
    for (uint32_t s : todo) flipped[s] = 0;
    for (uint32_t s : todo) {
      for (int k = 0; k < 3 && !flipped[s] && missing[s]; ++k) {
        const uint32_t t = nbr[3 * s + k];
        if (t == kNone || !missing[t] || flipped[t] || fixed[3 * s + k]) continue;
        const VertexId a = sf.tri[s][k], b = sf.tri[s][(k + 1) % 3], c = sf.tri[s][(k + 2) % 3];
        int kt = 0;
        while (kt < 3 && (sf.tri[t][kt] == a || sf.tri[t][kt] == b)) ++kt;
        if (kt == 3) continue;
        const VertexId d = sf.tri[t][kt];
        if (c == d || q.has_edge(a, b)) continue;  // present: leave it
        const double *pa = mesh.point(a), *pb = mesh.point(b), *pc = mesh.point(c),
                     *pd = mesh.point(d);
        bool flip = false;
        if (pred::orient3d(pa, pb, pc, pd) == 0 && pred::incircle_coplanar(pa, pb, pc, pd) == 0) {
          const VertexId top = pred::sos_first(a, b, c, d);
          flip = top == a || top == b;
        }
        if (!flip) {
          const int drop = projection_axis(pa, pb, pc);
          const int o = pred::orient2d_projected(pa, pb, pc, drop);
          const bool convex = o != 0 && pred::orient2d_projected(pa, pb, pd, drop) == -o &&
                              pred::orient2d_projected(pa, pd, pc, drop) == o &&
                              pred::orient2d_projected(pd, pb, pc, drop) == o;
          flip = convex && (pred::incircle_coplanar(pa, pb, pc, pd) > 0 ||
                            (q.has_face(a, d, c) && q.has_face(d, b, c)));
        }
        if (!flip) continue;
        // Neighbours across the four outer edges, before the flip.
        const uint32_t sbc = slot(s, b, c), sca = slot(s, c, a), tad = slot(t, a, d),
                       tdb = slot(t, d, b);
        const uint32_t n_bc = nbr[sbc], n_ca = nbr[sca], n_ad = nbr[tad], n_db = nbr[tdb];
        const uint8_t f_bc = fixed[sbc], f_ca = fixed[sca], f_ad = fixed[tad], f_db = fixed[tdb];
        // Consistently oriented with s, t runs b -> a, so it is (b, a, d)
        // up to rotation and b follows d.
        const bool consistent = sf.tri[t][(kt + 1) % 3] == b;
        sf.tri[s] = {a, d, c};
        sf.tri[t] = consistent ? Triangle{d, b, c} : Triangle{d, c, b};
        auto set = [&](uint32_t x, VertexId u, VertexId w, uint32_t nb, uint8_t fx) {
          const uint32_t sl = slot(x, u, w);
          nbr[sl] = nb, fixed[sl] = fx;
          if (nb == kNone) return;
          const uint32_t back = slot(nb, u, w);
          if (back != kNone) nbr[back] = x;
        };
        set(s, a, d, n_ad, f_ad);
        set(s, c, a, n_ca, f_ca);
        set(s, d, c, t, 0);
        set(t, d, b, n_db, f_db);
        set(t, b, c, n_bc, f_bc);
        set(t, d, c, s, 0);
        missing[s] = !q.has_face(a, d, c);
        missing[t] = !q.has_face(d, b, c);
        flipped[s] = flipped[t] = 1;
        ++flips;
      }
    }
    if (flips == before) break;
  }
  return flips;
}

}  // namespace

size_t flip_subfaces_toward_mesh(TetMesh& mesh, Subfaces& subfaces) {
  MeshQuery q(mesh);
  std::vector<uint32_t> nbr;
  std::vector<uint8_t> fixed, missing(subfaces.tri.size());
  subface_adjacency(subfaces, nbr, fixed);
  std::vector<HalfFace> hf;
  find_missing(mesh, subfaces, missing, hf);
  return flip_toward_mesh_impl(mesh, subfaces, q, nbr, fixed, missing);
}

namespace {

// The subfaces are well formed: one facet each, vertices in the mesh, not
// degenerate.
Status check_subfaces(const TetMesh& mesh, const Subfaces& sf) {
  const size_t n = sf.tri.size();
  if (sf.facet.size() != n)
    return make_error(ErrorCode::InvalidArgument,
                      "Subfaces: facet list and triangle list differ in size.");
  for (size_t s = 0; s < n; ++s) {
    const Triangle& T = sf.tri[s];
    for (int k = 0; k < 3; ++k)
      if (T[k] >= mesh.num_vertices() || mesh.vtet[T[k]] == kNone)
        return make_error(ErrorCode::InvalidArgument,
                          "A subface uses a vertex that is not in the mesh.")
            .facet(sf.facet[s])
            .vertex(T[k]);
    if (T[0] == T[1] || T[1] == T[2] || T[0] == T[2] ||
        pred::collinear3d(mesh.point(T[0]), mesh.point(T[1]), mesh.point(T[2])))
      return make_error(ErrorCode::DegenerateFacet, "A subface is degenerate.").facet(sf.facet[s]);
  }
  return Status::success();
}

// The missing region of s0 (§7): the missing subfaces of its facet
// connected to it across edges missing from the mesh (subface_adjacency's
// nbr); a subface marked `single` is a region of its own. `mark` holds
// visit stamps, `epoch` is fresh.
void missing_region(uint32_t s0, const Subfaces& sf, MeshQuery& q, const std::vector<uint32_t>& nbr,
                    const std::vector<uint8_t>& single, uint32_t epoch, std::vector<uint32_t>& mark,
                    std::vector<uint32_t>& region) {
  region.assign(1, s0);
  mark[s0] = epoch;
  if (single[s0]) return;
  for (size_t k = 0; k < region.size(); ++k) {
    const uint32_t s = region[k];
    for (int e = 0; e < 3; ++e) {
      const uint32_t t = nbr[3 * s + e];
      if (t == kNone || mark[t] == epoch || single[t]) continue;
      if (q.has_edge(sf.tri[s][e], sf.tri[s][(e + 1) % 3])) continue;
      mark[t] = epoch;
      region.push_back(t);
    }
  }
}

// Below this many subfaces the first pass takes less than a second
// thread costs to start (tens of microseconds).
constexpr size_t kMinSubfacesBeside = 2000;

// Tet slots per piece of the shared scan below.
constexpr size_t kScanChunk = 1024;

// find_missing and subface_adjacency on two threads; both only read the mesh
// and the subfaces. The scan of the tets is most of the work, so it is
// shared: this thread indexes the subfaces while the other builds the
// adjacency, then both take pieces of the tet slots in turn, each into its
// own array, and the smaller half-face of the two (the first in slot order)
// is the one a single pass finds. As two fixed halves (find_missing beside
// the adjacency) the other core would idle for most of the pass:
// find_missing takes several times as long.
void missing_and_adjacency_beside(const TetMesh& mesh, const Subfaces& sf,
                                  std::vector<uint8_t>& missing, std::vector<HalfFace>& hf,
                                  std::vector<uint32_t>& nbr, std::vector<uint8_t>& fixed) {
  const size_t n = sf.tri.size(), slots = mesh.num_tet_slots();
  std::unique_ptr<SubfaceFaces> index;
  std::atomic<bool> indexed{false};
  std::atomic<size_t> next{0};
  auto scan_pieces = [&](std::vector<HalfFace>& out) {
    out.assign(n, kNone);
    for (size_t c; (c = next.fetch_add(kScanChunk)) < slots;)
      index->scan(mesh, TetId(c), TetId(std::min(slots, c + kScanChunk)), out);
  };
  std::vector<HalfFace> other;
  run_beside(
      true,
      [&] {
        try {
          index.reset(new SubfaceFaces(sf, mesh.num_vertices()));
        } catch (...) {
          indexed.store(true, std::memory_order_release);  // the other thread must not wait
          throw;
        }
        indexed.store(true, std::memory_order_release);
        scan_pieces(hf);
      },
      [&] {
        subface_adjacency(sf, nbr, fixed);
        wait_until(indexed);
        if (index) scan_pieces(other);
      });
  for (size_t s = 0; s < n; ++s) {  // both arrays are full size once both halves ran
    hf[s] = std::min(hf[s], other[s]);
    missing[s] = hf[s] == kNone;
  }
}

}  // namespace

Status recover_facets(TetMesh& mesh, Subfaces& subfaces, FacetRecoveryStats* stats,
                      const volatile bool* cancel, bool force_failure,
                      std::vector<HalfFace>* half_faces, bool beside,
                      const std::atomic<bool>* stop) {
  FacetRecoveryStats st;
  if (stats) *stats = st;
  // Statistics are reported on failure as well (what was done until then).
  struct Report {
    FacetRecoveryStats* out;
    const FacetRecoveryStats& st;
    ~Report() {
      if (out) *out = st;
    }
  } report{stats, st};
  Subfaces& sf = subfaces;
  const size_t n = sf.tri.size();
  st.subfaces = n;
  Status checked = check_subfaces(mesh, sf);
  if (!checked.ok()) return checked;
  MeshQuery q(mesh);
  auto present = [&](uint32_t s) { return q.has_face(sf.tri[s][0], sf.tri[s][1], sf.tri[s][2]); };

  std::vector<uint32_t> nbr;
  std::vector<uint8_t> fixed, missing(n);
  std::vector<HalfFace> hf;
  if (beside && n >= kMinSubfacesBeside) {
    missing_and_adjacency_beside(mesh, sf, missing, hf, nbr, fixed);
  } else {
    find_missing(mesh, sf, missing, hf);
    subface_adjacency(sf, nbr, fixed);
  }
  st.subface_flips = flip_toward_mesh_impl(mesh, sf, q, nbr, fixed, missing);
  const SubfaceIndex index(sf);  // after the flips

  std::deque<uint32_t> queue;
  std::vector<uint8_t> queued(n, 0), ever(n, 0), failures(n, 0), single(n, 0);
  for (uint32_t s = 0; s < n; ++s)
    if (missing[s]) queue.push_back(s), queued[s] = ever[s] = 1;
  st.missing_initially = queue.size();

  CavityMesher cm(mesh);
  cm.set_subface_test([&index](const Triangle& key) {
    bool found = false;
    index.for_each(key, [&](uint32_t) { found = true; });
    return found;
  });
  std::vector<uint32_t> region;
  std::vector<Triangle> tris;
  std::vector<uint32_t> mark(n, 0);
  uint32_t epoch = 0;
  const size_t max_attempts = 16 * st.missing_initially + 256;
  size_t attempts = 0;
  while (!queue.empty()) {
    if ((cancel && *cancel) || (stop && stop->load(std::memory_order_relaxed)))
      return make_error(ErrorCode::Cancelled, "Facet recovery was cancelled.");
    const uint32_t s0 = queue.front();
    queue.pop_front();
    queued[s0] = 0;
    if (present(s0)) continue;
    if (++attempts > max_attempts)
      return make_error(ErrorCode::LimitReached, "Facet recovery did not finish within " +
                                                     std::to_string(max_attempts) +
                                                     " region attempts.")
          .facet(sf.facet[s0]);
    missing_region(s0, sf, q, nbr, single, ++epoch, mark, region);
    tris.clear();
    for (uint32_t s : region) tris.push_back(sf.tri[s]);
    CavityReport rep;
    if (force_failure) {
      st.unrecovered = sf.tri[s0], st.unrecovered_facet = sf.facet[s0];
      return make_error(ErrorCode::Internal, "Facet recovery failed (forced for a test).")
          .facet(sf.facet[s0]);
    }
    const CavityOutcome out = cm.recover_region(tris, rep);
    if (out == CavityOutcome::Recovered) {
      ++st.regions;
      st.cavities += rep.cavities;
      st.expansions += rep.expansions;
      st.largest_cavity = std::max(st.largest_cavity, rep.largest_cavity);
      bool retried = false;
      for (uint32_t s : region) {
        retried |= failures[s] != 0;
        if (!present(s))
          return make_error(ErrorCode::Internal,
                            "Facet recovery: a recovered region lacks one of its subfaces.")
              .facet(sf.facet[s]);
      }
      if (retried || rep.gift_wraps > 0) ++st.fallbacks;
      // Subfaces that were faces of removed tets may be gone (Theorem 4).
      for (const Triangle& f : cm.removed_faces())
        index.for_each(f, [&](uint32_t s) {
          if (!queued[s] && !present(s)) queue.push_back(s), queued[s] = ever[s] = 1;
        });
      continue;
    }
    // Fallback (documented in facet_recovery.hpp): first retry the region
    // after the rest of the queue, then its subfaces one at a time; a single
    // subface failing again is an error naming its facet.
    if (single[s0] && failures[s0] >= 2) {
      st.unrecovered = sf.tri[s0], st.unrecovered_facet = sf.facet[s0];
      return make_error(out == CavityOutcome::Limit ? ErrorCode::LimitReached : ErrorCode::Internal,
                        "Facet recovery failed for a missing region of " +
                            std::to_string(region.size()) + " subface(s): " + rep.failure + ".")
          .facet(sf.facet[s0]);
    }
    for (uint32_t s : region) {
      if (failures[s] < 255) ++failures[s];
      if (failures[s] >= 2) single[s] = 1;
      if (!queued[s]) queue.push_back(s), queued[s] = 1;
    }
  }
  // A subface can only go missing as a face of a removed tet, and those were
  // queued again; the queue is empty, so every subface ever queued is
  // checked once more (the others were present and never touched).
  for (uint32_t s = 0; s < n; ++s)
    if (ever[s] && !present(s)) {
      st.unrecovered = sf.tri[s], st.unrecovered_facet = sf.facet[s];
      return make_error(ErrorCode::Internal, "Facet recovery ended with a subface missing.")
          .facet(sf.facet[s]);
    }
  // As found before the cavities changed the mesh: the user refreshes them
  // (refresh_subface_half_faces) once, after any later change too.
  if (half_faces) *half_faces = std::move(hf);
  return Status::success();
}

void subface_half_faces(const TetMesh& mesh, const Subfaces& sf, std::vector<HalfFace>& out) {
  const SubfaceFaces index(sf, mesh.num_vertices());
  out.assign(sf.tri.size(), kNone);
  index.scan(mesh, 0, static_cast<TetId>(mesh.num_tet_slots()), out);
}

void refresh_subface_half_faces(TetMesh& mesh, const Subfaces& sf, std::vector<HalfFace>& hf) {
  const size_t n = sf.tri.size();
  if (hf.size() != n) {
    subface_half_faces(mesh, sf, hf);
    return;
  }
  const size_t slots = mesh.num_tet_slots();
  for (size_t s = 0; s < n; ++s) {
    const Triangle& T = sf.tri[s];
    const HalfFace h = hf[s];
    if (h != kNone && hf_tet(h) < slots && !mesh.is_dead(hf_tet(h))) {
      const VertexId* w = mesh.tet_vertices(hf_tet(h));
      const int i = hf_face(h);
      if (sorted_triangle({w[kFaceVertex[i][0]], w[kFaceVertex[i][1]], w[kFaceVertex[i][2]]}) ==
          sorted_triangle(T))
        continue;
    }
    hf[s] = mesh.find_face(T[0], T[1], T[2]);
  }
}

}  // namespace cdt3d
