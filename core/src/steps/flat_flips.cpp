// Flat-tet removal by flips (flat_flips.hpp).
#include "flat_flips.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "geometry.hpp"
#include "predicates.hpp"

namespace cdt3d {

namespace {

using Tet = std::array<VertexId, 4>;
using FaceKey = std::array<VertexId, 3>;
using EdgeKey = std::array<VertexId, 2>;

// Largest ring of tets around an edge that edge removal tries (2 (k - 2) new
// tets; the fans of a ring of 5 already cover most flat tets met).
constexpr size_t kMaxRing = 5;
// Passes over the flat tets: a flip can make a neighbour flat-free or leave
// another flat tet to a later pass.
constexpr int kMaxPasses = 32;

class FlatFlipper {
 public:
  FlatFlipper(TetMesh& mesh, const Subfaces& sf, const SegmentSet& segs,
              std::vector<uint8_t>* kept)
      : m_(mesh), sf_(sf), segs_(segs), kept_(kept) {}

  void run(FlatFlipStats& st);

 private:
  // A tet to flip away: flat, and kept by carving when that is known.
  bool flat_kept(TetId t) const {
    return !m_.is_dead(t) && (!kept_ || (t < kept_->size() && (*kept_)[t])) && flat(t);
  }
  bool flat(TetId t) const {
    const VertexId* w = m_.tet_vertices(t);
    return w[3] != kInfinite && numerically_flat(m_.point(w[0]), m_.point(w[1]), m_.point(w[2]),
                                                 m_.point(w[3]));
  }
  bool is_subface(VertexId a, VertexId b, VertexId c) const {
    const FaceKey k = sorted_triangle(a, b, c);
    if (k[0] + 1 >= face_start_.size()) return false;
    for (uint32_t i = face_start_[k[0]]; i < face_start_[k[0] + 1]; ++i)
      if (face_rest_[i] == EdgeKey{k[1], k[2]}) return true;
    return false;
  }
  bool is_subsegment(VertexId a, VertexId b) const {
    const EdgeKey k = sorted_edge(a, b);
    if (k[0] + 1 >= edge_start_.size()) return false;
    for (uint32_t i = edge_start_[k[0]]; i < edge_start_[k[0] + 1]; ++i)
      if (edge_rest_[i] == k[1]) return true;
    return false;
  }
  // Orients (a, b, c, d) positively; false when the four are coplanar.
  bool positive(VertexId a, VertexId b, VertexId c, VertexId d, Tet& out) const {
    const int o = pred::orient3d(m_.point(a), m_.point(b), m_.point(c), m_.point(d));
    if (o == 0) return false;
    out = o > 0 ? Tet{a, b, c, d} : Tet{b, a, c, d};
    return true;
  }
  double worst(const std::vector<Tet>& tets) const {
    double r = HUGE_VAL;
    for (const Tet& t : tets)
      r = std::min(r, volume_ratio(m_.point(t[0]), m_.point(t[1]), m_.point(t[2]), m_.point(t[3])));
    return r;
  }
  void consider(const std::vector<TetId>& old, std::vector<Tet>& fresh);
  bool keeps_delaunay(const std::vector<TetId>& old, const std::vector<Tet>& fresh) const;
  void try_face(TetId t, int i);
  void try_edge(TetId t, int i, int j);
  bool fix(TetId t);

  // The constrained faces and edges, each listed at its smallest vertex
  // (CSR by counting: a few entries per vertex, no sort of all of them),
  // built only when a flat tet needs them (most meshes have none).
  void index_constraints() {
    const size_t nv = m_.num_vertices();
    face_start_.assign(nv + 1, 0);
    for (const auto& t : sf_.tri) ++face_start_[std::min({t[0], t[1], t[2]}) + 1];
    for (size_t v = 0; v < nv; ++v) face_start_[v + 1] += face_start_[v];
    face_rest_.resize(face_start_[nv]);
    std::vector<uint32_t> fill(face_start_.begin(), face_start_.end() - 1);
    for (const auto& t : sf_.tri) {
      const FaceKey k = sorted_triangle(t[0], t[1], t[2]);
      face_rest_[fill[k[0]]++] = {k[1], k[2]};
    }
    edge_start_.assign(nv + 1, 0);
    for (const auto& c : segs_.chain)
      for (size_t i = 0; i + 1 < c.size(); ++i) ++edge_start_[std::min(c[i], c[i + 1]) + 1];
    for (size_t v = 0; v < nv; ++v) edge_start_[v + 1] += edge_start_[v];
    edge_rest_.resize(edge_start_[nv]);
    fill.assign(edge_start_.begin(), edge_start_.end() - 1);
    for (const auto& c : segs_.chain)
      for (size_t i = 0; i + 1 < c.size(); ++i) {
        const EdgeKey k = sorted_edge(c[i], c[i + 1]);
        edge_rest_[fill[k[0]]++] = k[1];
      }
  }

  TetMesh& m_;
  const Subfaces& sf_;
  const SegmentSet& segs_;
  std::vector<uint8_t>* kept_;
  std::vector<TetId> created_;
  std::vector<uint32_t> changed_;  // per vertex: clock_ of the last flip that touched it
  uint32_t clock_ = 0;              // flips done so far
  std::vector<uint32_t> face_start_, edge_start_;  // per vertex: its entries (CSR)
  std::vector<EdgeKey> face_rest_;                 // a subface's two larger vertices
  std::vector<VertexId> edge_rest_;                // a subsegment's larger vertex
  // Best candidate of the current flat tet.
  int best_gain_ = 0;
  double best_ratio_ = 0;
  std::vector<TetId> best_old_;
  std::vector<Tet> best_new_;
};

// Keeps the candidate (old tets -> fresh tets) if it leaves fewer flat tets
// than it removes and beats the best so far (fewer flat tets left, then the
// thinner of the two thinnest tets). Counting flat tets, not only requiring
// none, lets a stack of flat tets in one plane go one flip at a time; every
// flip lowers the count, so the passes end.
void FlatFlipper::consider(const std::vector<TetId>& old, std::vector<Tet>& fresh) {
  int before = 0, after = 0;
  for (TetId t : old) before += flat(t);
  for (const Tet& t : fresh)
    after += numerically_flat(m_.point(t[0]), m_.point(t[1]), m_.point(t[2]), m_.point(t[3]));
  const int gain = before - after;
  if (gain <= 0 || !keeps_delaunay(old, fresh)) return;
  const double r = worst(fresh);
  if (gain < best_gain_ || (gain == best_gain_ && !(r > best_ratio_))) return;
  best_gain_ = gain;
  best_ratio_ = r;
  best_old_ = old;
  best_new_.swap(fresh);
}

// Whether every face of the fresh tets that is not a subface is locally
// Delaunay (exact insphere) or has five vertices with a numerically flat
// quadruple (geometry.hpp): the relaxed constrained Delaunay property that
// validate() checks. A flip that would break it elsewhere is not done.
bool FlatFlipper::keeps_delaunay(const std::vector<TetId>& old,
                                 const std::vector<Tet>& fresh) const {
  auto opposite = [&](const FaceKey& k, size_t self) -> VertexId {
    for (size_t j = 0; j < fresh.size(); ++j) {
      if (j == self) continue;
      for (int i = 0; i < 4; ++i) {
        const Tet& w = fresh[j];
        if (sorted_triangle(w[kFaceVertex[i][0]], w[kFaceVertex[i][1]], w[kFaceVertex[i][2]]) == k)
          return w[i];
      }
    }
    for (TetId t : old)
      for (int i = 0; i < 4; ++i) {
        const VertexId* w = m_.tet_vertices(t);
        if (sorted_triangle(w[kFaceVertex[i][0]], w[kFaceVertex[i][1]], w[kFaceVertex[i][2]]) != k)
          continue;
        const HalfFace out = m_.adjacent(make_hf(t, i));
        if (std::find(old.begin(), old.end(), hf_tet(out)) != old.end()) continue;
        return m_.vertex(hf_tet(out), hf_face(out));
      }
    return kNone;
  };
  for (size_t j = 0; j < fresh.size(); ++j) {
    const Tet& w = fresh[j];
    for (int i = 0; i < 4; ++i) {
      const FaceKey k =
          sorted_triangle(w[kFaceVertex[i][0]], w[kFaceVertex[i][1]], w[kFaceVertex[i][2]]);
      if (is_subface(k[0], k[1], k[2])) continue;
      const VertexId e = opposite(k, j);
      if (e == kNone || e == kInfinite) continue;
      const double* p[5] = {m_.point(w[0]), m_.point(w[1]), m_.point(w[2]), m_.point(w[3]),
                            m_.point(e)};
      if (pred::insphere(p[0], p[1], p[2], p[3], p[4]) > 0 && !has_flat_quadruple(p)) return false;
    }
  }
  return true;
}

// 2-3 flip across face i of t: t = (face, d) and its neighbour (face, e)
// become three tets around edge de, valid when de crosses the face.
void FlatFlipper::try_face(TetId t, int i) {
  const HalfFace hf = make_hf(t, i);
  const TetId n = hf_tet(m_.adjacent(hf));
  if (m_.is_ghost(n)) return;
  const VertexId* w = m_.tet_vertices(t);
  const VertexId a = w[kFaceVertex[i][0]], b = w[kFaceVertex[i][1]], c = w[kFaceVertex[i][2]];
  if (is_subface(a, b, c)) return;
  const VertexId d = w[i];
  const VertexId e = m_.vertex(n, hf_face(m_.adjacent(hf)));
  const double *pa = m_.point(a), *pb = m_.point(b), *pc = m_.point(c), *pd = m_.point(d),
               *pe = m_.point(e);
  const int s1 = pred::orient3d(pa, pb, pd, pe), s2 = pred::orient3d(pb, pc, pd, pe),
            s3 = pred::orient3d(pc, pa, pd, pe);
  if (s1 == 0 || s1 != s2 || s2 != s3) return;
  std::vector<Tet> fresh(3);
  positive(a, b, d, e, fresh[0]);
  positive(b, c, d, e, fresh[1]);
  positive(c, a, d, e, fresh[2]);
  consider({t, n}, fresh);
}

// Edge removal around the edge of t between its vertices at positions i, j:
// the ring of k <= kMaxRing tets around it becomes 2 (k - 2) tets, the ring
// polygon triangulated as a fan from one of its vertices and each triangle
// coned to both ends of the edge; valid when every triangle separates them
// with the same orientation (u on the same side of each triangle taken in
// the polygon's order), i.e. every new tet is positively oriented.
void FlatFlipper::try_edge(TetId t, int i, int j) {
  const VertexId u = m_.vertex(t, i), v = m_.vertex(t, j);
  if (is_subsegment(u, v)) return;
  int p = 0;
  while (p == i || p == j) ++p;
  int q = p + 1;
  while (q == i || q == j) ++q;
  std::vector<TetId> ring;
  std::vector<VertexId> poly;
  TetId cur = t;
  VertexId a = m_.vertex(t, p), b = m_.vertex(t, q);
  for (;;) {
    if (m_.is_ghost(cur) || ring.size() >= kMaxRing) return;
    ring.push_back(cur);
    poly.push_back(a);
    if (is_subface(u, v, b)) return;  // the face crossed next is removed
    const TetId nxt = m_.neighbor(cur, m_.index_in_tet(cur, a));
    if (nxt == t) break;
    VertexId c = kNone;
    for (int k = 0; k < 4; ++k) {
      const VertexId x = m_.vertex(nxt, k);
      if (x != u && x != v && x != b) c = x;
    }
    a = b, b = c, cur = nxt;
  }
  const size_t k = poly.size();
  if (k < 3) return;
  for (size_t apex = 0; apex < k; ++apex) {
    std::vector<Tet> fresh;
    bool ok = true;
    int side = 0;  // orientation of (triangle, u), the same for every triangle of the fan
    for (size_t m = 1; m + 1 < k && ok; ++m) {
      const VertexId x = poly[apex], y = poly[(apex + m) % k], z = poly[(apex + m + 1) % k];
      const int ou = pred::orient3d(m_.point(x), m_.point(y), m_.point(z), m_.point(u));
      const int ov = pred::orient3d(m_.point(x), m_.point(y), m_.point(z), m_.point(v));
      if (side == 0) side = ou;
      ok = ou != 0 && ou == side && ov == -ou;
      Tet tu, tv;
      if (ok) ok = positive(x, y, z, u, tu) && positive(x, y, z, v, tv);
      if (ok) fresh.push_back(tu), fresh.push_back(tv);
    }
    if (ok) consider(ring, fresh);
    if (k == 3) break;  // one triangulation only
  }
}

// The best valid flip that removes flat tet t, done; false when none.
bool FlatFlipper::fix(TetId t) {
  best_gain_ = 0;
  best_ratio_ = -HUGE_VAL;
  best_old_.clear();
  best_new_.clear();
  for (int i = 0; i < 4; ++i) try_face(t, i);
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) try_edge(t, i, j);
  if (best_old_.empty()) return false;
  if (!m_.replace_tets(best_old_.data(), best_old_.size(), best_new_.data(), best_new_.size(),
                      &created_))
    return false;
  if (kept_) {
    kept_->resize(m_.num_tet_slots(), 0);
    for (TetId c : created_) (*kept_)[c] = 1;
  }
  ++clock_;
  for (const Tet& w : best_new_)
    for (VertexId v : w) changed_[v] = clock_;
  return true;
}

void FlatFlipper::run(FlatFlipStats& st) {
  std::vector<TetId> todo;
  for (TetId t = 0; t < m_.num_tet_slots(); ++t)
    if (flat_kept(t)) todo.push_back(t);
  st.flat_before = todo.size();
  st.remaining = 0;
  if (todo.empty()) return;
  index_constraints();
  // A failed fix(t) fails again until a flip changes a tet sharing an edge
  // or a face with t, or a tet beyond one of those: all of them have a
  // vertex of t, and a flip's old and new tets have the same vertices. So a
  // tet is tried again only when a flip since its last try touched one of
  // its vertices (the result is that of trying every tet in every pass).
  changed_.assign(m_.num_vertices(), 0);
  clock_ = 0;
  // (tet, 1 + clock_ when last tried, 0 never): a flip after the try stamps
  // its vertices with at least that.
  std::vector<std::pair<TetId, uint32_t>> queue, left;
  for (TetId t : todo) queue.emplace_back(t, 0);
  for (int pass = 0; pass < kMaxPasses && !queue.empty(); ++pass) {
    left.clear();
    const size_t flips = st.flips;
    for (const auto& [t, tried] : queue) {
      if (!flat_kept(t)) continue;  // gone or replaced by an earlier flip
      const VertexId* w = m_.tet_vertices(t);
      const bool touched = changed_[w[0]] >= tried || changed_[w[1]] >= tried ||
                           changed_[w[2]] >= tried || changed_[w[3]] >= tried;
      if (!touched) {
        left.emplace_back(t, tried);
        continue;
      }
      const uint32_t now = clock_ + 1;
      if (fix(t))
        ++st.flips;
      else
        left.emplace_back(t, now);
    }
    queue.swap(left);
    if (st.flips == flips) break;
  }
  for (TetId t = 0; t < m_.num_tet_slots(); ++t)
    if (flat_kept(t)) ++st.remaining;
}

}  // namespace

void remove_flat_tets(TetMesh& mesh, const Subfaces& subfaces, const SegmentSet& segs,
                      FlatFlipStats* stats, std::vector<uint8_t>* kept) {
  FlatFlipStats local;
  FlatFlipStats& st = stats ? *stats : local;
  st = FlatFlipStats();
  FlatFlipper(mesh, subfaces, segs, kept).run(st);
}

}  // namespace cdt3d
