// Step 1: Delaunay tetrahedralization by incremental Bowyer–Watson insertion
// (Bowyer 1981, Watson 1981) in BRIO + Hilbert order (Amenta, Choi, Rote
// 2003), with ghost tets and SoS-perturbed conflict tests. See delaunay.hpp.
#include "delaunay.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <new>
#include <numeric>

#include "beside.hpp"
#include "geometry.hpp"
#include "status.hpp"

namespace cdt3d {

namespace {

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

// A hint to start loading memory that is needed soon (no-op elsewhere).
template <typename T>
inline void prefetch(const T* p) {
#if defined(__GNUC__) || defined(__clang__)
  __builtin_prefetch(static_cast<const void*>(p));
#else
  (void)p;
#endif
}

bool same_point(const double* p, const double* q) {
  return p[0] == q[0] && p[1] == q[1] && p[2] == q[2];
}

// For a tet whose new vertex sits at position `apex`: the three faces
// through the apex, each with the positions of the boundary edge it contains,
// in the order met going counterclockwise (seen from outside) after the apex.
// Two new tets sharing that edge see it in opposite directions.
struct ApexFace {
  int face, first, second;
};
struct ApexFaceTable {
  ApexFace at[4][3];
};
constexpr ApexFaceTable make_apex_faces() {
  ApexFaceTable t{};
  for (int apex = 0; apex < 4; ++apex) {
    int k = 0;
    for (int m = 0; m < 4; ++m) {
      if (m == apex) continue;
      const int* f = kFaceVertex[m];
      const int j = f[0] == apex ? 0 : f[1] == apex ? 1 : 2;
      t.at[apex][k++] = ApexFace{m, f[(j + 1) % 3], f[(j + 2) % 3]};
    }
  }
  return t;
}
constexpr ApexFaceTable kApexFaces = make_apex_faces();

// Local-id tables up to this many boundary vertices are dense.
constexpr uint32_t kDenseLocals = 96;

}  // namespace

// ---------------------------------------------------------------------------
// PointInserter
// ---------------------------------------------------------------------------

PointInserter::PointInserter(TetMesh& mesh, uint64_t seed)
    : mesh_(mesh), rng_(seed ^ 0x77616c6b77616c6bull) {}

// Conflict of point p (vertex v) with tet t: for a real tet, p strictly
// inside its circumsphere under SoS; for a ghost tet, p strictly beyond its
// hull face, or on the face's plane and inside its circumcircle under SoS
// (the limit of the circumsphere of a tet whose apex goes to infinity).
#if defined(__GNUC__) || defined(__clang__)
__attribute__((always_inline))
#endif
inline bool
PointInserter::in_conflict(TetId t, const double* p, VertexId v) const {
  const VertexId* w = &mesh_.tv[4 * static_cast<size_t>(t)];
  const double* a = mesh_.point(w[0]);
  const double* b = mesh_.point(w[1]);
  const double* c = mesh_.point(w[2]);
  if (w[3] != kInfinite) {
    const double* d = mesh_.point(w[3]);
    const int s = cospherical_      ? 0
                  : small_integers_ ? pred::insphere_small_integers(a, b, c, d, p)
                  : box_.insphere > 0 ? pred::insphere_in_box(a, b, c, d, p, box_)
                                      : pred::insphere(a, b, c, d, p);
    if (s != 0) return s > 0;
    return pred::insphere_tie(a, b, c, d, p, sos(w[0]), sos(w[1]), sos(w[2]), sos(w[3]), sos(v),
                              small_integers_) > 0;
  }
  const int o = small_integers_     ? pred::orient3d_small_integers(a, b, c, p)
                : box_.orient3d > 0 ? pred::orient3d_in_box(a, b, c, p, box_)
                                    : pred::orient3d(a, b, c, p);
  if (o != 0) return o > 0;
  return pred::incircle_coplanar_sos_on_plane(a, b, c, p, sos(w[0]), sos(w[1]), sos(w[2]), sos(v),
                                              small_integers_) > 0;
}

// The static bounds for tests with point p (a point about to be located or
// inserted), or null. A point outside their box ends their use for good:
// they hold only for points inside it, and p may become a vertex.
const pred::BoxBounds* PointInserter::box_at(const double* p) {
  if (!(box_.orient3d > 0)) return nullptr;
  if (box_.contains(p)) return &box_;
  box_ = pred::BoxBounds();
  return nullptr;
}

int conflict_sign(const TetMesh& mesh, TetId t, const double* p) {
  const VertexId* w = mesh.tet_vertices(t);
  const double *a = mesh.point(w[0]), *b = mesh.point(w[1]), *c = mesh.point(w[2]);
  if (w[3] != kInfinite) return pred::insphere(a, b, c, mesh.point(w[3]), p);
  const int o = pred::orient3d(a, b, c, p);
  return o != 0 ? o : pred::incircle_coplanar(a, b, c, p);
}

// The cavity search of grow_cavity without the local ids and the prefetches
// (a probe changes nothing, so it needs neither), plus the vertex beyond
// each boundary face. The located tet is in conflict without a test, as in
// grow_cavity (p lies in its closure and is no vertex of it, or strictly
// beyond its hull face), so its exact test is positive: no tie there.
bool PointInserter::probe(const double* xyz, TetId hint,
                          std::vector<std::array<VertexId, 4>>& faces,
                          const ProbeOptions& options) {
  faces.clear();
  TetMesh& m = mesh_;
  const Location loc = locate_point(m, xyz, hint, options.walk ? *options.walk : rng_, box_at(xyz));
  if (loc.kind != LocateKind::InTet && loc.kind != LocateKind::OutsideHull) return false;
  const VertexId v = static_cast<VertexId>(m.num_vertices());  // the id it would get
  uint8_t* flag = m.tflag.data();
  cavity_.clear();
  cavity_.push_back(loc.tet);
  flag[loc.tet] |= kTetInCavity;
  std::vector<TetId> tested;
  bool tie = false;
  for (size_t k = 0; k < cavity_.size() && !tie; ++k) {
    const TetId t = cavity_[k];
    for (int i = 0; i < 4 && !tie; ++i) {
      const HalfFace hf = m.adjacent(make_hf(t, i));
      const TetId n = hf_tet(hf);
      if (flag[n] & kTetInCavity) continue;
      if (!(flag[n] & kTetTested)) {
        int s;
        if (options.fail_on_tie) {
          s = conflict_sign(m, n, xyz);
          tie = s == 0;
        } else {
          s = in_conflict(n, xyz, v) ? 1 : -1;
        }
        if (s > 0) {
          flag[n] |= kTetInCavity;
          cavity_.push_back(n);
          continue;
        }
        flag[n] |= kTetTested;
        tested.push_back(n);
      }
      const VertexId* w = m.tet_vertices(t);
      faces.push_back(
          {w[kFaceVertex[i][0]], w[kFaceVertex[i][1]], w[kFaceVertex[i][2]], m.opposite(hf)});
    }
  }
  for (TetId t : tested) flag[t] &= uint8_t(~kTetTested);
  for (TetId t : cavity_) flag[t] &= uint8_t(~kTetInCavity);
  cavity_.clear();
  if (tie) faces.clear();
  return !tie;
}

// Whether coning the cavity boundary to p makes a numerically flat real tet.
bool PointInserter::cone_has_flat_tet(const double* p) const {
  for (const BoundaryFace& f : boundary_) {
    if (f.a == kInfinite || f.b == kInfinite || f.c == kInfinite) continue;
    if (numerically_flat(mesh_.point(f.a), mesh_.point(f.b), mesh_.point(f.c), p)) return true;
  }
  return false;
}

// Leaves the mesh as it was before the cavity search (marks and local ids).
void PointInserter::abandon_cavity() {
  for (TetId t : cavity_) mesh_.tflag[t] &= uint8_t(~kTetInCavity);
  for (VertexId x : locals_) vlocal_[x] = 0;
  locals_.clear();
  cavity_.clear();
  boundary_.clear();
}

uint32_t PointInserter::local_id(VertexId x) {
  if (x == kInfinite) return 1;
  uint32_t& l = vlocal_[x];
  if (l == 0) {
    locals_.push_back(x);
    l = static_cast<uint32_t>(locals_.size() + 1);
  }
  return l;
}

// Cavity: breadth-first from the located tet t0 over tets in conflict with
// p (Bowyer-Watson); fills cavity_ and boundary_. Two transient flag bits
// mark "in the cavity" and "tested, not in conflict" (a byte per tet is
// denser in cache than the epoch stamps).
template <bool kShared>
bool PointInserter::grow_cavity_impl(TetId t0, const double* p, VertexId v) {
  TetMesh& m = mesh_;
  uint8_t* flag = m.tflag.data();
  // The located tet is in conflict without a test: p lies in its closure and
  // is not a vertex (strictly inside its circumsphere), or strictly beyond
  // the hull face of a ghost.
  boundary_.clear();
  cavity_.push_back(t0);
  flag[t0] |= kTetInCavity;
  for (size_t k = 0; k < cavity_.size(); ++k) {
    const TetId t = cavity_[k];
    const HalfFace* adj = &m.tadj[4 * static_cast<size_t>(t)];
    // Start the four neighbours' memory loads together.
    for (int i = 0; i < 4; ++i) {
      prefetch(&flag[hf_tet(adj[i])]);
      prefetch(&m.tv[4 * static_cast<size_t>(hf_tet(adj[i]))]);
    }
    for (int i = 0; i < 4; ++i) {
      const HalfFace hf = adj[i];
      const TetId n = hf_tet(hf);
      if constexpr (kShared) {
        if (!lock(n)) {  // the other thread's: leave the point for later
          for (const BoundaryFace& f : boundary_) flag[hf_tet(f.outside)] &= uint8_t(~kTetTested);
          return false;
        }
      }
      const uint8_t f = flag[n];
      if (f & kTetInCavity) continue;
      if (!(f & kTetTested)) {
        if (in_conflict(n, p, v)) {
          flag[n] = f | kTetInCavity;
          cavity_.push_back(n);
          prefetch(&m.tadj[4 * static_cast<size_t>(n)]);
          continue;
        }
        flag[n] = f | kTetTested;
      }
      prefetch(&m.tadj[hf]);  // glued to a new tet below
      const VertexId* w = &m.tv[4 * static_cast<size_t>(t)];
      const VertexId a = w[kFaceVertex[i][0]], b = w[kFaceVertex[i][1]], c = w[kFaceVertex[i][2]];
      boundary_.push_back(BoundaryFace{a, b, c, hf, local_id(a), local_id(b), local_id(c)});
    }
  }
  for (const BoundaryFace& f : boundary_) flag[hf_tet(f.outside)] &= uint8_t(~kTetTested);
  return true;
}

// Replaces the cavity by the cone of its boundary faces to v and glues the
// new tets to each other and to the outside.
Status PointInserter::fill_cavity(VertexId v) {
  TetMesh& m = mesh_;
  uint8_t* flag = m.tflag.data();
  // Cone each boundary face (a, b, c) to v: (a, b, c, v) is positive because
  // v sees the face from inside the cavity. A ghost keeps kInfinite at
  // position 3 by an even permutation.
  // The faces through v are glued to each other by boundary edge: each
  // boundary edge (u, w) lies on exactly two boundary faces, and the two new
  // tets see it in opposite directions. With few boundary vertices a dense
  // table indexed by directed local edge (u, w) finds the partner; large
  // cavities sort edge records instead.
  const size_t nb = boundary_.size(), nc = cavity_.size();
  const uint32_t L = static_cast<uint32_t>(locals_.size() + 2);
  const bool dense = L <= kDenseLocals;
  if (dense && !dense_) dense_.reset(new HalfFace[size_t(kDenseLocals) * kDenseLocals]);
  // Three pending faces per new tet, written by index: push_back of the
  // small struct stalls on store-to-load forwarding (its two 32-bit halves
  // read back as one), on the hottest path of insertion.
  if (dense && pending_.size() < 3 * nb) pending_.resize(3 * nb);
  size_t npending = 0;
  recs_.clear();
  new_tets_.reserve(nb);
  for (size_t j = 0; j < nb; ++j) {
    const BoundaryFace& f = boundary_[j];
    TetId t;
    if (j < nc) {
      t = cavity_[j];
      flag[t] = 0;
    } else {
      t = alloc_slot();
      flag = m.tflag.data();
    }
    VertexId w[4] = {f.a, f.b, f.c, v};
    uint32_t l[4] = {f.la, f.lb, f.lc, 0};
    int apex = 3;
    const int k = f.a == kInfinite ? 0 : f.b == kInfinite ? 1 : f.c == kInfinite ? 2 : -1;
    if (k >= 0) {  // keep kInfinite at position 3 by an even permutation
      const int x = k == 0 ? 1 : 0, y = k == 2 ? 1 : 2;
      std::swap(w[k], w[3]), std::swap(l[k], l[3]);
      std::swap(w[x], w[y]), std::swap(l[x], l[y]);
      apex = k;
    }
    m.set_tet(t, w[0], w[1], w[2], w[3]);
    m.glue(make_hf(t, apex), f.outside);
    for (const ApexFace& af : kApexFaces.at[apex]) {
      const HalfFace hf = make_hf(t, af.face);
      const uint32_t x = l[af.first], y = l[af.second];
      if (dense) {
        dense_[x * L + y] = hf;
        Pending& pe = pending_[npending++];
        pe.hf = hf;
        pe.reverse = y * L + x;
      } else {
        recs_.push_back(EdgeRec{std::min(x, y), std::max(x, y), hf});
      }
    }
    new_tets_.push_back(t);
  }
  for (size_t j = nb; j < nc; ++j) free_slot(cavity_[j]);
  for (VertexId x : locals_) vlocal_[x] = 0;
  locals_.clear();
  if (dense) {
    HalfFace* adj = m.tadj.data();
    for (size_t i = 0; i < npending; ++i) adj[pending_[i].hf] = dense_[pending_[i].reverse];
  } else {
    std::sort(recs_.begin(), recs_.end(), [](const EdgeRec& a, const EdgeRec& b) {
      return a.lo != b.lo ? a.lo < b.lo : a.hi != b.hi ? a.hi < b.hi : a.hf < b.hf;
    });
    for (size_t q = 0; q + 1 < recs_.size(); q += 2) {
      if (recs_[q].lo != recs_[q + 1].lo || recs_[q].hi != recs_[q + 1].hi)
        return make_error(ErrorCode::Internal, "delaunay: cavity boundary is not a closed surface.")
            .vertex(v);
      m.glue(recs_[q].hf, recs_[q + 1].hf);
    }
  }

  return Status::success();
}

void PointInserter::point_vertices_to_new_tets() {
  TetMesh& m = mesh_;
  // Vertex-to-tet map: every vertex of the cavity lies on its boundary and
  // gets a new real tet (near the vertex the old tets it had are replaced by
  // new ones), so vtet always names a real tet (not in shared mode, below).
  if (shared_) {
    point_vertices_shared();
    return;
  }
  for (TetId t : new_tets_) {
    const VertexId* w = &m.tv[4 * static_cast<size_t>(t)];
    if (w[3] == kInfinite) continue;
    m.vtet[w[0]] = t, m.vtet[w[1]] = t, m.vtet[w[2]] = t, m.vtet[w[3]] = t;
    last_tet_ = t;
  }
}

// Shared mode leaves the map alone: a two-thread round only happens in a
// build that numbers its tets canonically afterwards, and canonicalize
// points every vertex anew; until then the map is read only at vertices
// not inserted yet (insert_vertex's check, kNone there) and as a walk
// start that start_tet_shared checks. Both threads would write the
// vertices of the border between their parts, so the stores had to be
// atomic, and under Node every atomic store is an exchange, so even one
// store per vertex and point is a visible cost of step 1. The walk goes on
// from the last new real tet.
void PointInserter::point_vertices_shared() {
  for (auto it = new_tets_.rbegin(); it != new_tets_.rend(); ++it)
    if (mesh_.tv[4 * static_cast<size_t>(*it) + 3] != kInfinite) {
      last_tet_ = *it;
      return;
    }
}

// ---------------------------------------------------------------------------
// Shared mode: two inserters on one mesh (the two-thread bulk build)
// ---------------------------------------------------------------------------

// One thread's part of a shared build. Every tet slot has a lock word: 0,
// or the token of the attempt (one point's insertion) that last took it. A
// token is (attempt number << 2) | the part's id (1 or 2), and each part
// publishes its current one; a word holding the other part's current token
// is held, any other word is free (a finished attempt's tets need no
// unlocking). So an attempt ends with one store, the next token, instead of
// one store per tet it took: under Node every atomic store is an exchange
// (an insertion takes dozens of tets), a plain move natively. Locks are only ever tried,
// never waited for, so the two threads cannot deadlock; a tet is read only
// by its holder. Publication: taking a word is an acquire, and the other
// part's token is read with acquire before a word it wrote is taken, which
// pairs with the release store that ended that attempt (after all its
// writes). 30-bit attempt numbers never wrap within one build. The lock
// words are the tets' visit stamps, which step 1 does not use (a separate
// array was 4 bytes a tet more at the peak), accessed through the
// compiler's atomic builtins (C++17 has no std::atomic_ref).
struct PointInserter::Shared {
  uint32_t* owner = nullptr;
  std::atomic<uint32_t>* token = nullptr;        ///< this part's current token
  const std::atomic<uint32_t>* other = nullptr;  ///< the other part's
  uint32_t me = 0;                               ///< 1 or 2
  uint32_t current = 0;                          ///< == *token, this thread's copy
  TetId begin = 0, next = 0, end = 0;            ///< this part's fresh slots, the next one
  std::vector<TetId> freed;
  int64_t live_delta = 0;
  size_t inserted = 0;
};

TetId PointInserter::alloc_slot() {
  if (!shared_) return mesh_.alloc_tet();
  // A fresh slot from this part's range: the other thread cannot reach it
  // before this attempt's tets are published, so a relaxed store takes it.
  const TetId t = shared_->next++;
  mesh_.tflag[t] = 0;
  __atomic_store_n(&shared_->owner[t], shared_->current, __ATOMIC_RELAXED);
  ++shared_->live_delta;
  return t;
}

void PointInserter::free_slot(TetId t) {
  if (!shared_) {
    mesh_.free_tet(t);
    return;
  }
  // Not reused before the threads join: the other thread may still hold
  // its id (a stale start), and then finds it dead.
  mesh_.tflag[t] = kTetDead;
  shared_->freed.push_back(t);
  --shared_->live_delta;
}

// Takes tet t for this attempt; false when the other part's current
// attempt holds it (or takes it meanwhile).
bool PointInserter::lock(TetId t) {
  uint32_t* o = &shared_->owner[t];
  uint32_t cur = __atomic_load_n(o, __ATOMIC_RELAXED);
  if (cur == shared_->current) return true;
  if ((cur & 3) != 0 && (cur & 3) != shared_->me &&
      cur == shared_->other->load(std::memory_order_acquire))
    return false;
  return __atomic_compare_exchange_n(o, &cur, shared_->current, false, __ATOMIC_ACQUIRE,
                                     __ATOMIC_RELAXED);
}

// Ends this part's attempt: publishes its writes and frees every tet it
// took, by moving on to the next token.
void PointInserter::unlock_all() {
  shared_->current += 4;
  shared_->token->store(shared_->current, std::memory_order_release);
}

// A locked live real tet to start the walk from: the last tet this inserter
// made, else (the other thread took it apart) the newest live one among the
// few last slots of this part's range, which is where this thread works.
bool PointInserter::start_tet_shared(TetId& t) {
  TetMesh& m = mesh_;
  const TetId slots = static_cast<TetId>(m.num_tet_slots());
  auto usable = [&](TetId c) { return c < slots && lock(c) && !m.is_dead(c) && !m.is_ghost(c); };
  if (usable(last_tet_)) {
    t = last_tet_;
    return true;
  }
  constexpr TetId kTries = 64;
  for (TetId c = shared_->next; c > shared_->begin && shared_->next - c < kTries;)
    if (usable(--c)) {
      t = c;
      return true;
    }
  return false;
}

// locate_point's visibility walk, taking each tet before it steps in (the
// tets it passed stay taken until the attempt ends: the walks are a few
// steps long between neighbouring points, and no lock is given back alone).
// False when a tet on the way is held by the other thread.
bool PointInserter::locate_shared(const double* p, TetId& t, LocateKind& kind) {
  TetId start;
  if (!start_tet_shared(start)) return false;
  const Location loc = walk_to_point(
      mesh_, p, start, rng_, [this](TetId, TetId to) { return lock(to); }, box_at(p));
  walk_steps += loc.steps;
  t = loc.tet, kind = loc.kind;
  return kind != LocateKind::Failed;
}

PointInserter::Attempt PointInserter::insert_vertex_shared(VertexId v) {
  TetMesh& m = mesh_;
  new_tets_.clear();
  cavity_.clear();
  if (vlocal_.size() < m.num_vertices()) vlocal_.resize(m.num_vertices(), 0);
  const double* p = m.point(v);
  TetId t0 = kNone;
  LocateKind kind = LocateKind::Failed;
  Attempt result = Attempt::Deferred;
  if (!locate_shared(p, t0, kind) || kind == LocateKind::OnVertex) {
    // Held by the other thread, or a duplicate, which the single-threaded
    // pass decides (it keeps the earlier point): later.
  } else if (!grow_cavity_impl<true>(t0, p, v)) {
    abandon_cavity();
  } else if (boundary_.size() > cavity_.size() &&
             shared_->end - shared_->next < boundary_.size() - cavity_.size()) {
    abandon_cavity();  // out of fresh slots: the rest goes to the single-threaded pass
  } else {
    cavity_tets += cavity_.size();
    if (!fill_cavity(v).ok()) {
      result = Attempt::Failed;
    } else {
      point_vertices_to_new_tets();
      m.vkind[v] = kVertexInput;
      ++shared_->inserted;
      result = Attempt::Inserted;
    }
  }
  unlock_all();
  return result;
}

Status PointInserter::insert_vertex(VertexId v, TetId hint, InsertResult* result) {
  TetMesh& m = mesh_;
  new_tets_.clear();
  cavity_.clear();
  if (v >= m.num_vertices())
    return make_error(ErrorCode::InvalidArgument, "Vertex id out of range.");
  if (m.vtet[v] != kNone)
    return make_error(ErrorCode::InvalidArgument, "Vertex is already in the triangulation.")
        .vertex(v);
  if (m.live_tets == 0)
    return make_error(ErrorCode::InvalidArgument, "The mesh has no tetrahedra to insert into.")
        .vertex(v);

  if (vlocal_.size() < m.num_vertices()) vlocal_.resize(m.num_vertices() + m.num_vertices() / 4, 0);
  const double* p = m.point(v);
  const Location loc = locate_point(m, p, hint, rng_, box_at(p));
  walk_steps += loc.steps;
  if (result) *result = InsertResult{v, false, loc.tet};
  if (loc.kind == LocateKind::Failed)
    return make_error(ErrorCode::Internal, "delaunay: point location made no progress.").vertex(v);
  if (loc.kind == LocateKind::OnVertex) {
    m.vkind[v] = kVertexDuplicate;
    if (result) result->vertex = loc.vertex, result->duplicate = true;
    return Status::success();
  }

  grow_cavity(loc.tet, p, v);
  if (reject_flat_ && cone_has_flat_tet(p)) {
    abandon_cavity();
    if (result) result->rejected = true;
    return Status::success();
  }
  cavity_tets += cavity_.size();
  Status st = fill_cavity(v);
  if (!st.ok()) return st;
  point_vertices_to_new_tets();
  if (m.vkind[v] == kVertexNotInserted || m.vkind[v] == kVertexDuplicate) m.vkind[v] = kVertexInput;
  return Status::success();
}

Status PointInserter::insert_point(const double* xyz, TetId hint, uint8_t kind,
                                   InsertResult* result) {
  for (int k = 0; k < 3; ++k) {
    if (!std::isfinite(xyz[k]))
      return make_error(ErrorCode::NonFinite, "Point has a non-finite coordinate.");
    if (std::fabs(xyz[k]) > kMaxCoordinate)
      return make_error(ErrorCode::CoordinateRange, "Point coordinate exceeds kMaxCoordinate.");
  }
  // Locate first so that a duplicate adds no vertex.
  const Location loc = locate_point(mesh_, xyz, hint, rng_, box_at(xyz));
  if (loc.kind == LocateKind::Failed)
    return make_error(ErrorCode::Internal, "delaunay: point location made no progress.");
  if (loc.kind == LocateKind::OnVertex) {
    new_tets_.clear();
    cavity_.clear();
    walk_steps += loc.steps;
    if (result) *result = InsertResult{loc.vertex, true, loc.tet};
    return Status::success();
  }
  if (mesh_.num_vertices() >= (size_t(1) << 30))
    return make_error(ErrorCode::TooLarge, "Too many vertices.");
  const VertexId v = mesh_.add_vertex(xyz, kind);
  InsertResult local;
  InsertResult& res = result ? *result : local;
  Status s = insert_vertex(v, loc.tet, &res);
  if (s.ok() && res.rejected) {  // v is the last vertex: take it back
    mesh_.coords.resize(3 * static_cast<size_t>(v));
    mesh_.vkind.pop_back();
    mesh_.vtet.pop_back();
    res.vertex = kNone;
    return s;
  }
  if (s.ok()) mesh_.vkind[v] = kind;
  return s;
}

Status insert_point(TetMesh& mesh, const double* xyz, TetId hint, InsertResult* result,
                    std::vector<TetId>* new_tets) {
  PointInserter ins(mesh);
  Status s = ins.insert_point(xyz, hint, kVertexSteiner, result);
  if (new_tets) *new_tets = ins.new_tets();
  return s;
}

// ---------------------------------------------------------------------------
// Whole point sets
// ---------------------------------------------------------------------------

namespace {

// Number of pairwise distinct points among vertices 0..n-1, counted up to 4,
// for the error message when no proper tetrahedron exists.
size_t count_distinct_upto4(const TetMesh& m, size_t n) {
  VertexId seen[4];
  size_t found = 0;
  for (VertexId v = 0; v < n; ++v) {
    bool fresh = true;
    for (size_t k = 0; k < found && fresh; ++k) fresh = !same_point(m.point(seen[k]), m.point(v));
    if (fresh) {
      seen[found++] = v;
      if (found == 4) break;
    }
  }
  return found;
}

// First affinely independent quadruple among vertices 0..n-1 (in id order),
// as a positive tet, with its four ghost tets.
Status make_initial_tet(TetMesh& m, size_t n, VertexId chosen[4]) {
  VertexId i1 = 0, i2 = 0, i3 = 0;
  const double* p0 = m.point(0);
  for (i1 = 1; i1 < n && same_point(m.point(i1), p0); ++i1) {
  }
  if (i1 == n) return make_error(ErrorCode::TooFewPoints, "Fewer than 4 distinct points.");
  const double* p1 = m.point(i1);
  for (i2 = i1 + 1; i2 < n && pred::collinear3d(p0, p1, m.point(i2)); ++i2) {
  }
  if (i2 == n) {
    return count_distinct_upto4(m, n) < 4
               ? make_error(ErrorCode::TooFewPoints, "Fewer than 4 distinct points.")
               : make_error(ErrorCode::Collinear, "All points lie on one line.");
  }
  const double* p2 = m.point(i2);
  int o = 0;
  for (i3 = i2 + 1; i3 < n; ++i3) {
    o = pred::orient3d(p0, p1, p2, m.point(i3));
    if (o != 0) break;
  }
  if (i3 == n) {
    return count_distinct_upto4(m, n) < 4
               ? make_error(ErrorCode::TooFewPoints, "Fewer than 4 distinct points.")
               : make_error(ErrorCode::Coplanar, "All points lie in one plane.");
  }
  VertexId a = 0, b = i1;
  if (o < 0) std::swap(a, b);
  chosen[0] = a, chosen[1] = b, chosen[2] = i2, chosen[3] = i3;

  const TetId t0 = m.alloc_tet();
  m.set_tet(t0, a, b, i2, i3);
  TetId ghost[4];
  for (int i = 0; i < 4; ++i) {
    // Face i of t0 is counterclockwise from outside; the ghost's face 3 is
    // the same face counterclockwise from inside, so reversed.
    const VertexId* w = &m.tv[4 * static_cast<size_t>(t0)];
    const VertexId f0 = w[kFaceVertex[i][0]], f1 = w[kFaceVertex[i][1]], f2 = w[kFaceVertex[i][2]];
    ghost[i] = m.alloc_tet();
    m.set_tet(ghost[i], f0, f2, f1, kInfinite);
    m.glue(make_hf(t0, i), make_hf(ghost[i], 3));
  }
  // Ghost faces 0..2 contain kInfinite and one hull edge: glue the pairs.
  for (int g = 0; g < 4; ++g)
    for (int i = 0; i < 3; ++i)
      for (int h = g + 1; h < 4; ++h)
        for (int j = 0; j < 3; ++j) {
          const VertexId* x = &m.tv[4 * static_cast<size_t>(ghost[g])];
          const VertexId* y = &m.tv[4 * static_cast<size_t>(ghost[h])];
          const VertexId x1 = x[(i + 1) % 3], x2 = x[(i + 2) % 3];
          const VertexId y1 = y[(j + 1) % 3], y2 = y[(j + 2) % 3];
          if ((x1 == y1 && x2 == y2) || (x1 == y2 && x2 == y1))
            m.glue(make_hf(ghost[g], i), make_hf(ghost[h], j));
        }
  for (int k = 0; k < 4; ++k) {
    m.vtet[chosen[k]] = t0;
    m.vkind[chosen[k]] = kVertexInput;
  }
  return Status::success();
}

// Moves coordinates stored in insertion order (a[k] belongs to vertex
// order[k]) to their vertex ids, in place, following the permutation's cycles.
void scatter_coords(std::vector<double>& a, const std::vector<VertexId>& order) {
  const size_t n = order.size();
  std::vector<bool> done(n, false);
  for (size_t s = 0; s < n; ++s) {
    if (done[s]) continue;
    double carry[3] = {a[3 * s], a[3 * s + 1], a[3 * s + 2]};
    size_t k = s;
    do {
      const size_t t = order[k];
      for (int c = 0; c < 3; ++c) std::swap(carry[c], a[3 * t + c]);
      done[t] = true;
      k = t;
    } while (k != s);
  }
}

// The bulk build. For memory locality the triangulation is built in a work
// mesh whose vertex k is vertices[order[k]] in BRIO order (so points inserted
// close in time sit close in memory), perturbing by the caller's ids; then
// the vertex ids are translated back.
// The vertices to triangulate are mesh vertices, each listed once, with
// finite coordinates in the supported range.
Status check_vertices(const TetMesh& m, const std::vector<VertexId>& vertices) {
  const size_t nv = m.num_vertices();
  std::vector<bool> listed(nv, false);
  for (VertexId v : vertices) {
    if (v >= nv) return make_error(ErrorCode::IndexOutOfRange, "Vertex id out of range.").vertex(v);
    if (listed[v]) return make_error(ErrorCode::InvalidArgument, "Vertex listed twice.").vertex(v);
    listed[v] = true;
    const double* p = m.point(v);
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(p[k]))
        return make_error(ErrorCode::NonFinite, "Point has a non-finite coordinate.").vertex(v);
      if (std::fabs(p[k]) > kMaxCoordinate)
        return make_error(ErrorCode::CoordinateRange,
                          "Point coordinate exceeds the supported range.")
            .vertex(v);
    }
  }
  return Status::success();
}

// Moves the work mesh `w` (vertex k is order[k]) into `m`, translating its
// vertex ids back to the caller's; returns the number of ghost tets (hull
// faces), counted on the way.
size_t adopt_work_mesh(TetMesh& m, TetMesh& w, const std::vector<VertexId>& order) {
  const size_t n = order.size();
  size_t ghosts = 0;
  const size_t slots = w.num_tet_slots();
  for (size_t t = 0; t < slots; ++t) {
    VertexId* x = &w.tv[4 * t];
    for (int i = 0; i < 4; ++i)
      if (x[i] < n) x[i] = order[x[i]];
    if (x[3] == kInfinite && !(w.tflag[t] & kTetDead)) ++ghosts;
  }
  m.tv = std::move(w.tv);
  m.tadj = std::move(w.tadj);
  m.tstamp = std::move(w.tstamp);
  m.tflag = std::move(w.tflag);
  m.free_tets = std::move(w.free_tets);
  m.live_tets = w.live_tets;
  m.epoch = w.epoch;
  for (size_t k = 0; k < n; ++k) {
    m.vtet[order[k]] = w.vtet[k];
    m.vkind[order[k]] = w.vkind[k];
  }
  return ghosts;
}

// ---------------------------------------------------------------------------
// Canonical tet numbering
// ---------------------------------------------------------------------------

// The even permutations of the positions (0, 1, 2, 3), grouped by the
// position they bring first: rotated tet position j holds old position
// kEven[r][j]. An even permutation keeps the orientation.
constexpr uint8_t kEven[12][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 0, 3, 2},
                                  {1, 2, 0, 3}, {1, 3, 2, 0}, {2, 0, 1, 3}, {2, 1, 3, 0},
                                  {2, 3, 0, 1}, {3, 0, 2, 1}, {3, 1, 0, 2}, {3, 2, 1, 0}};
struct EvenInverse {
  uint8_t at[12][4];
};
constexpr EvenInverse make_even_inverse() {
  EvenInverse v{};
  for (int r = 0; r < 12; ++r)
    for (int j = 0; j < 4; ++j) v.at[r][kEven[r][j]] = static_cast<uint8_t>(j);
  return v;
}
constexpr EvenInverse kEvenInverse = make_even_inverse();

// The rotation (index into kEven) that lists tet w from its smallest
// vertex, then the smaller of the two choices left; a ghost keeps kInfinite
// last (tet_mesh.hpp), so it only rotates its three hull vertices.
inline uint8_t canonical_rotation(const VertexId* w) {
  if (w[3] == kInfinite) {
    const int i = w[0] < w[1] ? (w[0] < w[2] ? 0 : 2) : (w[1] < w[2] ? 1 : 2);
    return static_cast<uint8_t>(i == 0 ? 0 : i == 1 ? 4 : 6);
  }
  int i0 = 0;
  for (int i = 1; i < 4; ++i)
    if (w[i] < w[i0]) i0 = i;
  int best = 3 * i0;
  for (int r = 3 * i0 + 1; r < 3 * i0 + 3; ++r)
    if (w[kEven[r][1]] < w[kEven[best][1]]) best = r;
  return static_cast<uint8_t>(best);
}

// The largest real vertex id of tet w.
inline VertexId newest_vertex(const VertexId* w) {
  const VertexId a = std::max(w[0], w[1]), b = w[3] == kInfinite ? w[2] : std::max(w[2], w[3]);
  return std::max(a, b);
}

// Moves the tet in slot a to slot b and the one in b to a, with its
// neighbours, flags and tstamp.
inline void swap_tet_slots(TetMesh& w, size_t a, size_t b) {
  for (int j = 0; j < 4; ++j) {
    std::swap(w.tv[4 * a + j], w.tv[4 * b + j]);
    std::swap(w.tadj[4 * a + j], w.tadj[4 * b + j]);
  }
  std::swap(w.tflag[a], w.tflag[b]);
  std::swap(w.tstamp[a], w.tstamp[b]);
}

// Moves every tet to slot tstamp[t] (a permutation of the slots), in place.
// Following the permutation's cycles through the whole array costs a cache
// miss per tet, each waiting for the one before (5 s of 35M tets); so the
// tets first go to their block of 2^16 slots (an American flag sort: each
// block fills from a front that only moves forward, so the few hundred
// fronts stay in cache), then along the cycles inside each block, which
// fits in cache.
void move_tets_to_places(TetMesh& w) {
  constexpr unsigned kBlockBits = 16;
  const size_t slots = w.num_tet_slots();
  const uint32_t* place = w.tstamp.data();
  const size_t blocks = (slots >> kBlockBits) + 1;
  std::vector<size_t> front(blocks), end(blocks);
  for (size_t b = 0; b < blocks; ++b) {
    front[b] = std::min(slots, b << kBlockBits);
    end[b] = std::min(slots, (b + 1) << kBlockBits);
  }
  for (size_t b = 0; b < blocks; ++b) {
    while (front[b] < end[b]) {
      const size_t p = front[b], home = place[p] >> kBlockBits;
      if (home == b)
        ++front[b];
      else
        swap_tet_slots(w, p, front[home]++);
    }
  }
  for (size_t p = 0; p < slots; ++p)
    while (place[p] != p) swap_tet_slots(w, p, place[p]);
}

// Renumbers the live tets of `w` canonically: each listed from its smallest
// vertex (canonical_rotation), all sorted by their newest vertex (the
// largest real id: the insertion that made the tet, so the order stays
// close to the order of creation, and in the Hilbert order of the last
// rounds, which keeps neighbours near in memory), then by their vertex
// lists; no dead slots remain, vtet names the last real tet of each vertex
// in the new order. The perturbed Delaunay tetrahedralization is unique,
// so the mesh is then the same whatever order its points went in, on one
// thread or two (the later steps' results depend on tet numbers: walks
// start at vtet, ties of equal candidates go to the first tet).
// In place: besides the tets it needs a word per vertex, where a sorted
// copy of every tet and its adjacency made it the peak of step 1, at 2.5x
// the memory of the insertions. tstamp holds the new ids meanwhile (first
// indexed by old slot, then by position in the bucket order) and tflag the
// rotations.
void canonicalize(TetMesh& w) {
  const size_t slots = w.num_tet_slots(), nv = w.num_vertices();
  VertexId* tv = w.tv.data();
  HalfFace* adj = w.tadj.data();
  uint8_t* flag = w.tflag.data();
  uint32_t* id = w.tstamp.data();
  // Each live slot to its place in the order by newest vertex, then by slot
  // (a counting sort; once filled, start[v] is the end of bucket v).
  std::vector<uint32_t> start(nv + 1, 0);
  size_t live = 0;
  for (size_t t = 0; t < slots; ++t) {
    if (flag[t] & kTetDead) continue;
    ++start[newest_vertex(tv + 4 * t) + 1];
    ++live;
  }
  for (size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
  // Dead slots go to the end, in slot order, so that the new places are a
  // permutation of all slots.
  for (size_t t = 0, dead = live; t < slots; ++t)
    id[t] = (flag[t] & kTetDead) ? uint32_t(dead++) : start[newest_vertex(tv + 4 * t)]++;
  // Neighbours by their new places first (id is indexed by slot until the
  // tets move), then the tets to those places, id moving along.
  for (size_t t = 0; t < slots; ++t) {
    if (flag[t] & kTetDead) continue;
    for (int j = 0; j < 4; ++j) {
      HalfFace& a = adj[4 * t + j];
      a = make_hf(id[hf_tet(a)], hf_face(a));
    }
  }
  move_tets_to_places(w);
  // Within each bucket (a few tets, now side by side) the order of the
  // rotated vertex lists: id[p] the final id of the tet at p, flag[p] its
  // rotation.
  struct Rotated {
    VertexId v[4];
    uint32_t at;
  };
  std::vector<Rotated> bucket;
  for (size_t v = 0, b = 0; v < nv; b = start[v++]) {
    const size_t e = start[v];
    bucket.clear();
    for (size_t p = b; p < e; ++p) {
      const VertexId* x = tv + 4 * p;
      flag[p] = canonical_rotation(x);
      const uint8_t* r = kEven[flag[p]];
      bucket.push_back(Rotated{{x[r[0]], x[r[1]], x[r[2]], x[r[3]]}, uint32_t(p)});
    }
    std::sort(bucket.begin(), bucket.end(), [](const Rotated& a, const Rotated& c) {
      for (int j = 0; j < 4; ++j)
        if (a.v[j] != c.v[j]) return a.v[j] < c.v[j];
      return false;
    });
    for (size_t k = 0; k < bucket.size(); ++k) id[bucket[k].at] = uint32_t(b + k);
  }
  // Each bucket rotated and reordered through a small copy, its neighbours
  // named by their final ids and faces.
  std::vector<std::array<uint32_t, 8>> moved;
  for (size_t v = 0, b = 0; v < nv; b = start[v++]) {
    const size_t e = start[v];
    moved.resize(e - b);
    for (size_t p = b; p < e; ++p) {
      const uint8_t* r = kEven[flag[p]];
      std::array<uint32_t, 8>& m = moved[id[p] - b];
      for (int j = 0; j < 4; ++j) {
        m[j] = tv[4 * p + r[j]];
        const HalfFace hf = adj[4 * p + r[j]];
        const size_t q = hf_tet(hf);
        m[4 + j] = make_hf(id[q], kEvenInverse.at[flag[q]][hf_face(hf)]);
      }
    }
    for (size_t p = b; p < e; ++p)
      for (int j = 0; j < 4; ++j) tv[4 * p + j] = moved[p - b][j], adj[4 * p + j] = moved[p - b][4 + j];
  }
  w.tv.resize(4 * live);
  w.tadj.resize(4 * live);
  w.tflag.assign(live, 0);
  w.tstamp.assign(live, 0);
  w.free_tets.clear();
  w.live_tets = live;
  w.epoch = 0;
  for (VertexId& x : w.vtet) x = kNone;
  for (size_t i = 0; i < live; ++i) {
    const VertexId* x = &w.tv[4 * i];
    if (x[3] == kInfinite) continue;
    for (int j = 0; j < 4; ++j) w.vtet[x[j]] = TetId(i);
  }
}

// ---------------------------------------------------------------------------
// Two-thread rounds
// ---------------------------------------------------------------------------

// Rounds of fewer points are inserted on one thread.
constexpr size_t kMinTwoThreadRound = 2000;

enum class RoundResult { Done, Failed };

// A real tet near point p to start a walk from (a ghost is swapped for the
// real tet across its hull face).
TetId start_near(TetMesh& w, const double* p, TetId hint, Rng& rng) {
  const Location loc = locate_point(w, p, hint, rng);
  if (loc.tet == kNone) return hint;
  return w.is_ghost(loc.tet) ? w.neighbor(loc.tet, 3) : loc.tet;
}

// Inserts work-mesh vertices b..e-1 (one BRIO round, in Hilbert order) on
// two threads: the first half of the curve by `ins` here, the second half
// by a second inserter beside it, each locking the tets it touches
// (PointInserter::Shared). The halves are far apart except along their
// border, so few points meet a tet of the other thread; those go to
// `later`, in order, for the single-threaded pass (so do duplicates).
RoundResult insert_round_two_threads(TetMesh& w, PointInserter& ins, uint64_t seed, VertexId b,
                                     VertexId e, const VertexId first[4],
                                     std::vector<VertexId>& later, size_t& beside) {
  const VertexId mid = b + (e - b) / 2;
  // Fresh slots: ~6.75 more tets per point (a part that runs out leaves its
  // remaining points to the single-threaded pass). Every slot is written
  // here, so the unused ones cost memory until the tets are compacted: the
  // margin is small.
  const size_t base = w.num_tet_slots();
  const size_t half = size_t(e - mid);
  const size_t per = 7 * half + half / 4 + 1024;
  const size_t slots = base + 2 * per;
  w.tv.resize(4 * slots, kNone);
  w.tadj.resize(4 * slots, kNone);
  w.tstamp.resize(slots, 0);  // the lock words, all free (0) between rounds
  w.tflag.resize(slots, kTetDead);
  // Attempt 1 of each part; a cache line each (each thread writes its own
  // once per point).
  struct alignas(64) Token {
    std::atomic<uint32_t> word;
  };
  Token token_a{{4 | 1}}, token_b{{4 | 2}};
  PointInserter::Shared pa, pb;
  pa.owner = pb.owner = w.tstamp.data();
  pa.me = 1, pb.me = 2;
  pa.current = token_a.word.load(), pb.current = token_b.word.load();
  pa.token = &token_a.word, pa.other = &token_b.word;
  pb.token = &token_b.word, pb.other = &token_a.word;
  pa.begin = pa.next = TetId(base), pa.end = TetId(base + per);
  pb.begin = pb.next = TetId(base + per), pb.end = TetId(slots);

  PointInserter other(w, seed ^ 0x6f74686572ull);
  other.take_settings(ins);
  Rng rng(seed);
  ins.set_hint(start_near(w, w.point(b), ins.last_tet(), rng));
  other.set_hint(start_near(w, w.point(mid), ins.last_tet(), rng));

  auto is_first = [first](VertexId k) {
    return k == first[0] || k == first[1] || k == first[2] || k == first[3];
  };
  std::atomic<bool> stop{false};
  auto work = [&](PointInserter& in, VertexId from, VertexId to, std::vector<VertexId>& out,
                  RoundResult& result) {
    for (VertexId k = from; k < to && !stop.load(std::memory_order_relaxed); ++k) {
      if (is_first(k)) continue;
      const PointInserter::Attempt a = in.insert_vertex_shared(k);
      if (a == PointInserter::Attempt::Deferred) out.push_back(k);
      if (a == PointInserter::Attempt::Failed) {
        result = RoundResult::Failed;
        stop.store(true, std::memory_order_relaxed);
      }
    }
  };
  std::vector<VertexId> later_a, later_b;
  RoundResult ra = RoundResult::Done, rb = RoundResult::Done;
  const pred::Counters* here = &pred::counters();
  pred::Counters beside_counts;
  bool on_other_thread = false;
  ins.share(&pa);
  other.share(&pb);
  run_beside(
      true, [&] { work(ins, b, mid, later_a, ra); },
      [&] {
        // The predicate counters are per thread (a fresh thread's start at
        // 0); the other thread's join this one's (the perturbation-order
        // search reads sos_ties).
        work(other, mid, e, later_b, rb);
        on_other_thread = &pred::counters() != here;
        beside_counts = pred::counters();
      });
  ins.share(nullptr);
  if (on_other_thread) {
    pred::counters() += beside_counts;
    beside += pb.inserted;
  }
  ins.walk_steps += other.walk_steps;
  ins.cavity_tets += other.cavity_tets;

  // The slots back to the mesh: live count, freed and unused ones on the
  // free list (the unused end of the second range cut off).
  w.live_tets = size_t(int64_t(w.live_tets) + pa.live_delta + pb.live_delta);
  w.tv.resize(4 * size_t(pb.next));
  w.tadj.resize(4 * size_t(pb.next));
  w.tstamp.assign(pb.next, 0);
  w.tflag.resize(pb.next);
  for (TetId t = pa.next; t < pa.end; ++t) w.free_tets.push_back(t);
  w.free_tets.insert(w.free_tets.end(), pa.freed.begin(), pa.freed.end());
  w.free_tets.insert(w.free_tets.end(), pb.freed.begin(), pb.freed.end());
  if (ra == RoundResult::Failed || rb == RoundResult::Failed) return RoundResult::Failed;
  later.assign(later_a.begin(), later_a.end());
  later.insert(later.end(), later_b.begin(), later_b.end());
  return RoundResult::Done;
}

Status build(TetMesh& m, const std::vector<VertexId>& vertices, std::vector<VertexId>* to_vertex,
             DelaunayStats* stats, const DelaunayOptions& options) {
  const auto t_start = std::chrono::steady_clock::now();
  const size_t nv = m.num_vertices();
  const size_t n = vertices.size();
  DelaunayStats st;
  st.points = n;
  if (stats) *stats = st;

  m.tv.clear();
  m.tadj.clear();
  m.tstamp.clear();
  m.tflag.clear();
  m.free_tets.clear();
  m.live_tets = 0;
  m.epoch = 0;
  m.vkind.assign(nv, kVertexNotInserted);
  m.vtet.assign(nv, kNone);
  if (to_vertex) to_vertex->assign(vertices.begin(), vertices.end());

  if (n >= (size_t(1) << 30)) return make_error(ErrorCode::TooLarge, "Too many points.");
  Status checked = check_vertices(m, vertices);
  if (!checked.ok()) return checked;
  if (n < 4) return make_error(ErrorCode::TooFewPoints, "Fewer than 4 distinct points.");

  std::vector<VertexId> order;
  std::vector<size_t> rounds = {0, n};
  if (options.spatial_sort) {
    brio_order(m.coords.data(), vertices, options.seed, order, &rounds);
  } else {
    order = vertices;
  }
  st.ms_sort = ms_since(t_start);
  const auto t_insert = std::chrono::steady_clock::now();

  // Work mesh in insertion order. When every vertex is listed, the caller's
  // coordinates are released meanwhile and rebuilt from the work copy.
  TetMesh w;
  w.coords.resize(3 * n);
  for (size_t k = 0; k < n; ++k)
    for (int c = 0; c < 3; ++c) w.coords[3 * k + c] = m.coords[3 * size_t(order[k]) + c];
  const bool all = n == nv;
  if (all) std::vector<double>().swap(m.coords);
  w.vkind.assign(n, kVertexNotInserted);
  w.vtet.assign(n, kNone);
  // About 6.75 tets per point, for uniform points and surface models alike;
  // 10 leaves room for the Steiner points of steps 2-4 too (each makes
  // about 7 tets). A reserve only takes address space until a tet is
  // written there, while each growth copies the arrays into fresh pages.
  w.reserve(0, n * 10 + 1024);

  auto finish = [&](Status s) {
    if (all) {
      scatter_coords(w.coords, order);
      m.coords = std::move(w.coords);
    }
    if (stats) *stats = st;
    return s;
  };

  VertexId first[4];
  Status s = make_initial_tet(w, n, first);
  if (!s.ok()) return finish(s);

  PointInserter ins(w, options.seed);
  ins.set_sos_ids(order.data());
  ins.set_small_integers(pred::small_integer_points(w.coords.data(), n));
  // Every point of this build is known: one static bound for all its
  // conflict tests.
  ins.set_box_bounds(pred::box_bounds(w.coords.data(), n));
  TetId hint = w.vtet[first[0]];
  std::vector<std::pair<VertexId, VertexId>> dups;  // (vertex, merged into), caller ids
  auto is_first = [&first](VertexId k) {
    return k == first[0] || k == first[1] || k == first[2] || k == first[3];
  };
  // Inserted in order, a point can only equal an earlier one (or one of the
  // first four); after a two-thread round it may find a later one inserted
  // first, and the build starts over on one thread to keep the earlier.
  bool out_of_order = false;
  auto insert_one = [&](VertexId k) {
    InsertResult r;
    Status st1 = ins.insert_vertex(k, hint, &r);
    if (!st1.ok()) {
      if (st1.error.vertex >= 0) st1.error.vertex = order[size_t(st1.error.vertex)];
      return st1;
    }
    if (r.duplicate) {
      out_of_order = out_of_order || (r.vertex > k && !is_first(r.vertex));
      dups.emplace_back(order[k], order[r.vertex]);
    } else {
      hint = ins.last_tet();
    }
    return st1;
  };
  const bool two = options.threads && n >= kMinTwoThreadDelaunayPoints && threads_available();
  std::vector<VertexId> later;
  for (size_t r = 0; r + 1 < rounds.size(); ++r) {
    const VertexId b = VertexId(rounds[r]), e = VertexId(rounds[r + 1]);
    if (!two || r == 0 || e - b < kMinTwoThreadRound) {
      for (VertexId k = b; k < e; ++k) {
        if (is_first(k)) continue;
        s = insert_one(k);
        if (!s.ok()) return finish(s);
      }
      continue;
    }
    ins.set_hint(hint);
    later.clear();
    const RoundResult rr =
        insert_round_two_threads(w, ins, options.seed, b, e, first, later, st.points_beside);
    if (rr == RoundResult::Failed)
      return finish(make_error(ErrorCode::Internal, "delaunay: a two-thread insertion failed."));
    hint = ins.last_tet();
    for (VertexId k : later) {
      s = insert_one(k);
      if (!s.ok()) return finish(s);
    }
    if (out_of_order) {
      finish(Status::success());
      DelaunayOptions one = options;
      one.threads = false;
      one.canonical = true;  // as the two-thread build would have numbered it
      return build(m, vertices, to_vertex, stats, one);
    }
  }
  // Large sets are numbered canonically whether or not a second thread
  // helped, so that the result never depends on the threads.
  if (n >= kMinTwoThreadDelaunayPoints && (options.canonical || options.threads)) canonicalize(w);

  const size_t ghosts = adopt_work_mesh(m, w, order);
  if (to_vertex && !dups.empty()) {
    std::sort(dups.begin(), dups.end());
    for (size_t k = 0; k < n; ++k) {
      auto it =
          std::lower_bound(dups.begin(), dups.end(), std::make_pair(vertices[k], VertexId(0)));
      if (it != dups.end() && it->first == vertices[k]) (*to_vertex)[k] = it->second;
    }
  }
  st.ms_insert = ms_since(t_insert);
  st.duplicates = dups.size();
  st.vertices = n - dups.size();
  st.hull_faces = ghosts;
  st.tets = m.live_tets - st.hull_faces;
  st.walk_steps = ins.walk_steps;
  st.cavity_tets = ins.cavity_tets;
  return finish(Status::success());
}

Status build_guarded(TetMesh& m, const std::vector<VertexId>& vertices,
                     std::vector<VertexId>* to_vertex, DelaunayStats* stats,
                     const DelaunayOptions& options) {
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
  try {
    return build(m, vertices, to_vertex, stats, options);
  } catch (...) {  // catch (...): see current_exception_code()
    m.clear();
    Status st;
    st.error = current_exception_error("building the Delaunay tetrahedralization");
    return st;
  }
#else
  return build(m, vertices, to_vertex, stats, options);
#endif
}

}  // namespace

SmallDelaunay::SmallDelaunay() : inserter_(mesh_) {}

Status SmallDelaunay::build(const double* coords, size_t n, bool cospherical) {
  inserter_.set_cospherical(cospherical);
  inserter_.set_small_integers(pred::small_integer_points(coords, n));
  inserter_.set_box_bounds(pred::box_bounds(coords, n));
  mesh_.clear();
  mesh_.coords.assign(coords, coords + 3 * n);
  mesh_.vkind.assign(n, kVertexNotInserted);
  mesh_.vtet.assign(n, kNone);
  VertexId first[4];
  Status s = make_initial_tet(mesh_, n, first);
  if (!s.ok()) return s;
  TetId hint = mesh_.vtet[first[0]];
  for (VertexId k = 0; k < n; ++k) {
    if (k == first[0] || k == first[1] || k == first[2] || k == first[3]) continue;
    InsertResult r;
    s = inserter_.insert_vertex(k, hint, &r);
    if (!s.ok()) return s;
    if (!r.duplicate) hint = inserter_.last_tet();
  }
  return s;
}

Status delaunay_tetrahedralize(TetMesh& mesh, const double* coords, size_t n,
                               std::vector<VertexId>* input_to_vertex, DelaunayStats* stats,
                               const DelaunayOptions& options) {
  mesh.clear();
  if (n >= (size_t(1) << 30)) return make_error(ErrorCode::TooLarge, "Too many points.");
  mesh.coords.assign(coords, coords + 3 * n);
  std::vector<VertexId> all(n);
  std::iota(all.begin(), all.end(), VertexId(0));
  return build_guarded(mesh, all, input_to_vertex, stats, options);
}

Status delaunay_tetrahedralize_vertices(TetMesh& mesh, const std::vector<VertexId>& vertices,
                                        std::vector<VertexId>* to_vertex, DelaunayStats* stats,
                                        const DelaunayOptions& options) {
  return build_guarded(mesh, vertices, to_vertex, stats, options);
}

}  // namespace cdt3d
