// TetMesh storage helpers: slot allocation, epochs, star traversal, edge and
// face lookup, compaction and export. See tet_mesh.hpp for the invariants.
#include "tet_mesh.hpp"

#include <algorithm>

#include "geometry.hpp"

namespace cdt3d {

namespace {

// Below this many bytes a full array doubles; above, it grows by 1.25x.
// Each growth copies the array into fresh pages (page faults included), and
// at 1.25x the many small meshes of segment recovery would grow far more
// often; with ~100 MB arrays the standard library's 2x growth would double
// the peak memory for a moment.
constexpr size_t kDoublingBytes = size_t(16) << 20;

// Grows a vector's capacity when full: 2x while small, 1.25x when large.
template <typename T>
void grow_gently(std::vector<T>& v, size_t extra) {
  if (v.size() + extra > v.capacity()) {
    const size_t step = v.capacity() * sizeof(T) < kDoublingBytes ? v.capacity() : v.capacity() / 4;
    v.reserve(v.capacity() + step + extra + 64);
  }
}

}  // namespace

size_t TetMesh::num_real_tets() const {
  size_t n = 0;
  const size_t slots = num_tet_slots();
  for (size_t t = 0; t < slots; ++t)
    if (!(tflag[t] & kTetDead) && tv[4 * t + 3] != kInfinite) ++n;
  return n;
}

size_t TetMesh::num_ghost_tets() const {
  size_t n = 0;
  const size_t slots = num_tet_slots();
  for (size_t t = 0; t < slots; ++t)
    if (!(tflag[t] & kTetDead) && tv[4 * t + 3] == kInfinite) ++n;
  return n;
}

void TetMesh::clear() {
  coords.clear();
  vkind.clear();
  vtet.clear();
  tv.clear();
  tadj.clear();
  tstamp.clear();
  tflag.clear();
  free_tets.clear();
  epoch = 0;
  live_tets = 0;
}

void TetMesh::reserve(size_t vertices, size_t tets) {
  coords.reserve(3 * vertices);
  vkind.reserve(vertices);
  vtet.reserve(vertices);
  tv.reserve(4 * tets);
  tadj.reserve(4 * tets);
  tstamp.reserve(tets);
  tflag.reserve(tets);
}

VertexId TetMesh::add_vertex(const double* xyz, uint8_t kind) {
  grow_gently(coords, 3);
  grow_gently(vkind, 1);
  grow_gently(vtet, 1);
  const VertexId v = static_cast<VertexId>(num_vertices());
  coords.push_back(xyz[0]);
  coords.push_back(xyz[1]);
  coords.push_back(xyz[2]);
  vkind.push_back(kind);
  vtet.push_back(kNone);
  return v;
}

TetId TetMesh::alloc_tet() {
  ++live_tets;
  if (!free_tets.empty()) {
    const TetId t = free_tets.back();
    free_tets.pop_back();
    tflag[t] = 0;
    return t;
  }
  grow_gently(tv, 4);
  grow_gently(tadj, 4);
  grow_gently(tstamp, 1);
  grow_gently(tflag, 1);
  const TetId t = static_cast<TetId>(num_tet_slots());
  for (int i = 0; i < 4; ++i) tv.push_back(kNone);
  for (int i = 0; i < 4; ++i) tadj.push_back(kNone);
  tstamp.push_back(0);
  tflag.push_back(0);
  return t;
}

void TetMesh::free_tet(TetId t) {
  --live_tets;
  tflag[t] = kTetDead;
  free_tets.push_back(t);
}

bool TetMesh::replace_tets(const TetId* old, size_t n_old, const std::array<VertexId, 4>* fresh,
                           size_t n_fresh, std::vector<TetId>* created) {
  // Every face to match, keyed by its sorted vertices: each face of the old
  // region toward the rest of the mesh (kOuter | the half-face beyond it)
  // and each face of each fresh tet (4 * j + i). Sorted, the fresh side of a
  // pair comes first; a valid replacement pairs every key exactly once, a
  // fresh face with an outer one or with another fresh one.
  constexpr uint64_t kOuter = uint64_t(1) << 32;
  std::vector<TetId> old_sorted(old, old + n_old);
  std::sort(old_sorted.begin(), old_sorted.end());
  std::vector<std::pair<std::array<VertexId, 3>, uint64_t>> sides;
  sides.reserve(4 * (n_old + n_fresh));
  for (size_t k = 0; k < n_old; ++k)
    for (int i = 0; i < 4; ++i) {
      const HalfFace out = adjacent(make_hf(old[k], i));
      if (std::binary_search(old_sorted.begin(), old_sorted.end(), hf_tet(out))) continue;
      const VertexId* w = tet_vertices(old[k]);
      sides.push_back(
          {sorted_triangle(w[kFaceVertex[i][0]], w[kFaceVertex[i][1]], w[kFaceVertex[i][2]]),
           kOuter | out});
    }
  for (size_t j = 0; j < n_fresh; ++j)
    for (int i = 0; i < 4; ++i) {
      const std::array<VertexId, 4>& w = fresh[j];
      sides.push_back(
          {sorted_triangle(w[kFaceVertex[i][0]], w[kFaceVertex[i][1]], w[kFaceVertex[i][2]]),
           4 * j + i});
    }
  std::sort(sides.begin(), sides.end());
  if (sides.size() % 2 != 0) return false;
  for (size_t k = 0; k < sides.size(); k += 2)
    if (sides[k].first != sides[k + 1].first || (sides[k].second & kOuter) ||
        (k + 2 < sides.size() && sides[k + 2].first == sides[k].first))
      return false;
  // Rewire. Fresh tet j takes slot old[j]; the old slots left over go back
  // last first, so that the next alloc_tet calls hand them out in the order
  // of `old`.
  std::vector<TetId> ids(n_fresh);
  for (size_t j = 0; j < n_fresh; ++j) ids[j] = j < n_old ? old[j] : alloc_tet();
  for (size_t k = n_old; k-- > n_fresh;) free_tet(old[k]);
  for (size_t j = 0; j < n_fresh; ++j) {
    tflag[ids[j]] = 0;
    set_tet(ids[j], fresh[j][0], fresh[j][1], fresh[j][2], fresh[j][3]);
  }
  auto fresh_hf = [&](uint64_t side) { return make_hf(ids[side / 4], static_cast<int>(side % 4)); };
  for (size_t k = 0; k < sides.size(); k += 2) {
    const uint64_t other = sides[k + 1].second;
    const HalfFace beyond = other & kOuter ? static_cast<HalfFace>(other & ~kOuter) : fresh_hf(other);
    if (beyond == kNoHalfFace)
      open_face(fresh_hf(sides[k].second));  // the open boundary of a carved mesh
    else
      glue(fresh_hf(sides[k].second), beyond);
  }
  for (size_t j = 0; j < n_fresh; ++j)
    if (fresh[j][3] != kInfinite)
      for (int i = 0; i < 4; ++i) set_vertex_tet(fresh[j][i], ids[j]);
  if (created) *created = ids;
  return true;
}

uint32_t TetMesh::next_epoch() {
  if (epoch == 0xffffffffu) {  // wrapped: forget every old stamp
    std::fill(tstamp.begin(), tstamp.end(), 0u);
    epoch = 0;
  }
  return ++epoch;
}

namespace {

// The first tet around vertex a (a tet of its star) for which found holds,
// breadth-first from vtet[a] across the faces through a (a deterministic
// order), or kNone. found(t, hf) tests tet t, reached through its half-face
// hf (kNoHalfFace for vtet[a], where the walk starts): every tet the walk
// leaves from failed the test, which find_edge uses to test one vertex
// only. Breadth-first order takes tets out of the queue in the order they
// were found, so testing each tet when found returns the same tet as
// testing them on removal, or after the whole walk, and skips the tets
// queued before it: about half of the walk when it succeeds, as it nearly
// always does (segment recovery's first check of every segment with
// find_edge). `queue` ends up holding the tets
// walked, in that order: the whole star (vertex_star) when found() never
// holds.
template <class Found>
TetId first_in_star(TetMesh& m, VertexId a, std::vector<TetId>& queue, Found&& found) {
  const TetId t0 = m.vtet[a];
  if (found(t0, kNoHalfFace)) return t0;
  const uint32_t e = m.next_epoch();
  queue.clear();
  queue.push_back(t0);
  m.stamp(t0, e);
  for (size_t k = 0; k < queue.size(); ++k) {
    const TetId t = queue[k];
    const int ia = m.index_in_tet(t, a);
    const HalfFace* adj = &m.tadj[4 * static_cast<size_t>(t)];
    for (int i = 0; i < 4; ++i) {
      if (i == ia || adj[i] == kNoHalfFace) continue;  // open face
      const TetId n = hf_tet(adj[i]);
      if (m.stamped(n, e)) continue;
      if (found(n, adj[i])) return n;
      m.stamp(n, e);
      queue.push_back(n);
    }
  }
  return kNone;
}

}  // namespace

void TetMesh::vertex_star(VertexId v, std::vector<TetId>& out) {
  out.clear();
  if (v >= num_vertices() || vtet[v] == kNone) return;
  first_in_star(*this, v, out, [](TetId, HalfFace) { return false; });
}

void TetMesh::vertex_neighbors(VertexId v, std::vector<VertexId>& out) {
  std::vector<TetId> star;
  vertex_star(v, star);
  out.clear();
  for (TetId t : star)
    for (int i = 0; i < 4; ++i) {
      const VertexId w = vertex(t, i);
      if (w != v && w != kInfinite) out.push_back(w);
    }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

const char* TetMesh::ring_around_edge(TetId t0, VertexId p, VertexId q, size_t max_len,
                                      std::vector<TetId>& ring,
                                      std::vector<VertexId>& arrive) const {
  ring.clear(), arrive.clear();
  VertexId x = kNone;
  for (int i = 0; i < 4; ++i) {
    const VertexId w = vertex(t0, i);
    if (w != p && w != q) {
      x = w;
      break;
    }
  }
  TetId cur = t0;
  VertexId u = x;
  for (;;) {
    ring.push_back(cur);
    arrive.push_back(u);
    // Leave cur across the face through pq that does not hold u: the one
    // opposite u, whose far tet is entered across the face holding w.
    VertexId w = kNone;
    for (int i = 0; i < 4; ++i) {
      const VertexId z = vertex(cur, i);
      if (z != p && z != q && z != u) w = z;
    }
    const int iu = index_in_tet(cur, u);
    if (w == kNone || iu < 0) return "broken ring of tets around a cavity edge";
    cur = neighbor(cur, iu);
    u = w;
    if (cur == t0) break;
    if (ring.size() > max_len) return "ring of tets around a cavity edge too long";
  }
  if (u != x) return "ring of tets around a cavity edge does not close";
  return nullptr;
}

// A neighbour across a face through a holds b only as the vertex opposite
// that face, since the tet the walk left lacks b: its half-face indexes that
// vertex directly (one load, not a search of four, on the path of segment
// recovery's check of every segment).
TetId TetMesh::find_edge(VertexId a, VertexId b) {
  if (a == kInfinite) std::swap(a, b);
  if (a >= num_vertices() || vtet[a] == kNone || a == b) return kNone;
  return first_in_star(*this, a, scratch, [&](TetId t, HalfFace across) {
    return across == kNoHalfFace ? index_in_tet(t, b) >= 0 : tv[across] == b;
  });
}

HalfFace TetMesh::find_face(VertexId a, VertexId b, VertexId c) {
  if (a == kInfinite) std::swap(a, c);
  if (a >= num_vertices() || vtet[a] == kNone) return kNone;
  const TetId t = first_in_star(*this, a, scratch, [&](TetId x, HalfFace) {
    return index_in_tet(x, b) >= 0 && index_in_tet(x, c) >= 0;
  });
  if (t == kNone) return kNone;
  return make_hf(t, 6 - index_in_tet(t, a) - index_in_tet(t, b) - index_in_tet(t, c));
}

void TetMesh::compact() {
  const size_t slots = num_tet_slots();
  std::vector<TetId> remap(slots, kNone);
  TetId next = 0;
  for (size_t t = 0; t < slots; ++t)
    if (!(tflag[t] & kTetDead)) remap[t] = next++;
  for (size_t t = 0; t < slots; ++t) {
    const TetId nt = remap[t];
    if (nt == kNone) continue;
    for (int i = 0; i < 4; ++i) {
      const HalfFace hf = tadj[4 * t + i];
      tv[4 * static_cast<size_t>(nt) + i] = tv[4 * t + i];
      tadj[4 * static_cast<size_t>(nt) + i] = make_hf(remap[hf_tet(hf)], hf_face(hf));
    }
    tstamp[nt] = tstamp[t];
    tflag[nt] = tflag[t];
  }
  tv.resize(4 * static_cast<size_t>(next));
  tadj.resize(4 * static_cast<size_t>(next));
  tstamp.resize(next);
  tflag.resize(next);
  free_tets.clear();
  for (TetId& t : vtet)
    if (t != kNone) t = remap[t];
  live_tets = next;
}

void TetMesh::real_tets(std::vector<uint32_t>& out) const {
  out.clear();
  const size_t slots = num_tet_slots();
  for (size_t t = 0; t < slots; ++t)
    if (!(tflag[t] & kTetDead) && tv[4 * t + 3] != kInfinite)
      out.insert(out.end(), tv.begin() + 4 * t, tv.begin() + 4 * t + 4);
}

void TetMesh::hull_faces(std::vector<uint32_t>& out) const {
  out.clear();
  const size_t slots = num_tet_slots();
  for (size_t t = 0; t < slots; ++t) {
    if ((tflag[t] & kTetDead) || tv[4 * t + 3] != kInfinite) continue;
    // Face 3 of a ghost is counterclockwise seen from inside the hull;
    // reverse it to face outward.
    out.push_back(tv[4 * t + 0]);
    out.push_back(tv[4 * t + 2]);
    out.push_back(tv[4 * t + 1]);
  }
}

}  // namespace cdt3d
