// The improvement pass against slivers (improve.hpp).
#include "improve.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>
#include <vector>

#include "geometry.hpp"
#include "predicates.hpp"

namespace cdt3d {

namespace {

// Largest ring edge removal looks at: rings around sliver edges hold 3 to 7
// tets; the dynamic programme grows with the cube of the size.
constexpr size_t kMaxRing = 10;
// An operation must raise the quality (below) of the tets it replaces by
// this much (about 1e-3 degrees at 5 degrees): every step then makes a
// measurable gain, and the pass ends.
constexpr double kGain = 1e-6;
// A vertex move must gain more (about 0.02 degrees at 10 degrees): moves by
// tiny gains touch their neighbours, which then try again, and on thin
// CAD parts the pass would go on and on.
constexpr double kMoveGain = 3e-4;
// Rounds over the tets below the target; a round that changes nothing ends
// the pass early.
constexpr int kRounds = 4;
// Then, with no tet below the target left, rounds of flips at the worst
// tets of the mesh (polish): at most this many rounds over this many tets.
constexpr int kPolishRounds = 8;
constexpr size_t kPolishTets = 16;
// A new vertex's cavity holds at most this many tets.
constexpr size_t kMaxCavity = 32;
// Heights (in mean edges of the sliver) inward of its centroid where a new
// vertex is tried, the two lowest in two directions: fewer leave slivers
// the pass could have removed.
constexpr double kInsertHeights[] = {0.05, 0.1, 0.2, 0.35, 0.5, 0.7, 1.0};
// Moves tried per target point when smoothing: fractions of the way there.
constexpr double kSteps[] = {1.0, 0.5, 0.25, 0.1};
// Compass search after those moves: first step (in shortest edges at the
// vertex), halvings before it stops, and moves at most.
constexpr double kCompassFirst = 0.1;
constexpr int kCompassHalvings = 3;
constexpr int kCompassMoves = 10;
// flip_ratio_bad's work: at most this many tets tried per tet above the
// ratio guard at its start (the tets its flips make are tried too).
constexpr size_t kRatioFlipWork = 4;
// The radius-edge ratio above which a tet counts as badly shaped (the
// threshold of the quality bench's share and of TetGen's default -q).
constexpr double kRatioGuard = 2.0;
// Flips and new vertices that fix a tet whose smallest angle is at least
// this (degrees) must not add tets above kRatioGuard; below it the angle
// comes first: issue 42 counts tets below 10 degrees, and guarding their
// fixes too left slivers on the scanned models (tests/bench/README.md).
constexpr double kGuardAngle = 10;

using Tet = std::array<VertexId, 4>;

// The normal of face i (kFaceVertex order) of the tet with vertices v and
// 1 / its length; false when it has no length.
CDT3D_FILTER_INLINE bool face_normal(const Vec3 v[4], int i, Vec3& n, double& inv) {
  const Vec3& a = v[kFaceVertex[i][0]];
  n = cross(v[kFaceVertex[i][1]] - a, v[kFaceVertex[i][2]] - a);
  const double len = norm(n);
  if (!(len > 0)) return false;
  inv = 1 / len;
  return true;
}

// 1 - cos of the smallest dihedral angle of a tet from its face normals:
// for a positive tet the normal of face i in kFaceVertex order points out
// of it (no sign test as in dihedral_cosines), and the cosine at the edge
// of faces i and j is -n_i.n_j / |n_i||n_j|. A mirrored tet gets the same.
CDT3D_FILTER_INLINE double quality_from_normals(const Vec3 n[4], const double inv[4]) {
  double cos_min = -1;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) cos_min = std::max(cos_min, -dot(n[i], n[j]) * inv[i] * inv[j]);
  return 1 - std::min(1.0, cos_min);
}

// quality_from_normals of tet (p0, p1, p2, p3) in doubles, or -1 when a
// face has no normal. The improvement pass spends most of its time here.
double angle_quality(const double* p0, const double* p1, const double* p2, const double* p3) {
  const Vec3 v[4] = {to_vec(p0), to_vec(p1), to_vec(p2), to_vec(p3)};
  Vec3 n[4];
  double inv[4];
  for (int i = 0; i < 4; ++i)
    if (!face_normal(v, i, n[i], inv[i])) return -1;
  return quality_from_normals(n, inv);
}

// Whether tet (p0, p1, p2, p3) is positive by the exact orientation test and
// not numerically flat. The floating-point test first: it turns down the
// flat candidates, whose exact orientation would take the slow path, and
// what it lets through is far from flat, so the exact test ends in its filter.
bool usable(const double* p0, const double* p1, const double* p2, const double* p3) {
  return !numerically_flat(p0, p1, p2, p3) && pred::orient3d(p0, p1, p2, p3) > 0;
}

// The quality of tet (p0, p1, p2, p3): 1 - cos of its smallest dihedral
// angle (in [0, 1], growing with the angle; no arc cosine in the inner
// loops), or -1 when it is not positive by the exact orientation test or is
// numerically flat: the measure every operation maximises. Above `floor`
// the value is exact; at or below it, it may be angle_quality's without the
// validity tests: a candidate whose tet is no better than the floor is
// refuted either way, and most candidates are (star_quality).
double quality_of(const double* p0, const double* p1, const double* p2, const double* p3,
                  double floor = -HUGE_VAL) {
  const double q = angle_quality(p0, p1, p2, p3);
  if (!(q > floor) || q < 0) return q;
  return usable(p0, p1, p2, p3) ? q : -1;
}

// What an operation must raise the smallest quality of the tets it replaces
// (old_q) above: old_q + kGain, or twice old_q below kGain (about 0.08
// degrees: a tet across two nearly coplanar facets). An absolute gain there
// turned away every fix of nefertiti's worst tet (0.0047 degrees, its two
// boundary faces on input triangles that meet at 179.96 degrees), whose best
// new vertex reached 0.0126 (TetGen's smallest angle on it: 0.0120). Each
// such step at least doubles it, so the pass still ends.
double gain_bar(double old_q) { return old_q + std::min(kGain, std::max(0.0, old_q)); }

// The quality of a tet whose smallest dihedral angle is `degrees`.
double quality_of_angle(double degrees) { return 1 - std::cos(degrees * 3.14159265358979323846 / 180); }

class Improver {
 public:
  Improver(ConstrainedMesh& cm, double target, const VolumeBounds& bounds,
           const std::vector<char>* needle)
      : needle_(needle),
        bounds_(bounds),
        cm_(cm),
        m_(cm.m),
        target_(quality_of_angle(target)),
        guard_q_(quality_of_angle(kGuardAngle)) {}
  Status run(const volatile bool* cancel, const ImproveProgress& progress, ImproveCounts& counts);

 private:
  double quality(const Tet& t) const;
  double quality(TetId t) const;        // cached per tet slot
  double fresh_quality(TetId t) const;  // computed now
  void forget_quality(TetId t) {
    if (t < qcache_.size()) qcache_[t] = kUnknown;
  }
  bool improve_tet(TetId t);
  void polish();
  void polish_rounds();
  bool exceeds_volume(const std::vector<TetId>& old, const std::vector<Tet>& fresh) const;
  bool polishing_ = false;  // polish() is under way
  bool pinned(TetId t) const;
  void touch(const VertexId* v, size_t n);
  bool unchanged_since_failure(TetId t) const;
  bool remove_edge(TetId t, VertexId a, VertexId b);
  bool flip23(TetId t, int face);
  bool flip23_tets(TetId t, int face, TetId& u);
  bool smooth(VertexId v);
  void compass_search(VertexId v, int keep, Vec3& best, double& best_q);
  static constexpr int kFixed = -2;  // sliding_axis: v does not move
  int sliding_axis(VertexId v, const std::vector<TetId>& star) const;
  bool reduce_ratio_bad(const volatile bool* cancel);
  bool flip_ratio_bad(const volatile bool* cancel);
  bool flip_for_ratio(TetId t);
  bool remove_edge_for_ratio(TetId t, VertexId a, VertexId b);
  bool ring_polygon(TetId t, VertexId a, VertexId b, std::array<VertexId, kMaxRing>& r, int& turn,
                    double& old_q);
  void ring_fresh(const std::array<VertexId, kMaxRing>& r, int turn, VertexId a, VertexId b,
                  const size_t (*pick)[kMaxRing], size_t n);
  bool above_guard(const Tet& t) const;
  bool above_guard(TetId t) const;
  std::vector<TetId> tets_above_guard() const;
  bool move_for_ratio(VertexId v);
  size_t ratio_bad_count(const std::vector<TetId>& star) const;
  double max_ratio(const std::vector<TetId>& tets) const;
  double ratio_of(const Tet& t) const;
  bool adds_ratio_bad(const std::vector<TetId>& old, const std::vector<Tet>& fresh,
                      double old_q) const;
  bool star_cavity(TetId t, const double* p);
  bool sees(HalfFace hf, const double* p) const;
  bool insert_point(TetId t);
  // insert_point's helpers: the best candidate point so far, its cavity
  // and the cavity's boundary faces.
  struct Candidate {
    double q = -1;
    Vec3 at{};
    std::vector<TetId> cavity;
    std::vector<std::array<VertexId, 3>> faces;
  };
  bool cavity_at(TetId t, const double* p, double& old_q);
  double new_quality(const double* p, double look) const;
  long added_ratio_bad(const Vec3& c);
  void fewer_ratio_bad(TetId t, Vec3 at, double edge, Candidate& best);
  bool at_needle(const VertexId* tv) const;
  bool adds_slivers(const Candidate& c) const;
  double worst_fresh_ = 0;  // added_ratio_bad's largest ratio of the new tets
  bool free_vertex(VertexId v, const std::vector<TetId>& star) const;
  double star_quality(double floor);
  bool replace(const std::vector<TetId>& old, const std::vector<Tet>& fresh);

  const std::vector<char>* needle_;  // improve_mesh's `needle`, or null
  const VolumeBounds& bounds_;
  ConstrainedMesh& cm_;
  TetMesh& m_;
  double target_;  // as a quality
  double guard_q_;  // kGuardAngle as a quality
  ImproveCounts counts_;
  std::vector<TetId> queue_;
  // Failure memo: touched_[v] is the operation count when v's star last
  // changed, failed_[t] the count when improve_tet(t) last failed (kNever:
  // not since the slot was filled).
  static constexpr uint32_t kNever = 0xffffffffu;
  uint32_t ops_ = 0;
  std::vector<uint32_t> touched_, failed_;
  // smooth_failed_[v]: the count when smooth(v) last failed. Every tet of
  // v's star asks for the same move; without its star changed it fails again.
  std::vector<uint32_t> smooth_failed_;
  // ratio_failed_[v]: the same for move_for_ratio(v), which a vertex of many
  // tets above the guard is asked for again and again.
  std::vector<uint32_t> ratio_failed_;
  static constexpr double kUnknown = -2;  // below every quality (-1 is "invalid")
  mutable std::vector<double> qcache_;
  // Buffers.
  std::vector<TetId> ring_, star_, created_, cavity_;
  // The tets of star_ (same order) as smooth() moves their vertex v: the
  // face opposite v keeps its normal, computed once per move.
  struct StarTet {
    const double* p[4];  // into the mesh's coordinates: v's follow the move
    int iv;              // v's index
    Vec3 n;              // face iv's normal and 1 / its length (0: none)
    double inv;
  };
  std::vector<StarTet> star_tets_;
  std::vector<double> floors_;  // move_for_ratio's per star tet
  void cache_star(VertexId v);
  std::vector<std::array<VertexId, 3>> faces_;
  std::vector<Tet> fresh_;
};

double Improver::quality(const Tet& t) const {
  return quality_of(cm_.pt(t[0]), cm_.pt(t[1]), cm_.pt(t[2]), cm_.pt(t[3]));
}

double Improver::fresh_quality(TetId t) const {
  const VertexId* v = m_.tet_vertices(t);
  return quality(Tet{v[0], v[1], v[2], v[3]});
}

// The quality of a live tet, remembered until an operation replaces the tet
// (replace) or moves one of its vertices (smooth): the rounds look at the
// same tets again and again.
double Improver::quality(TetId t) const {
  if (qcache_.size() <= t) qcache_.resize(m_.num_tet_slots(), kUnknown);
  if (qcache_[t] == kUnknown) qcache_[t] = fresh_quality(t);
  return qcache_[t];
}

// Replaces the live tets `old` by `fresh` (the same region): constraint tags
// of the region's outer faces are carried over, the fresh tets inherit the
// region attribute and go on the queue.
bool Improver::replace(const std::vector<TetId>& old, const std::vector<Tet>& fresh) {
  if (!cm_.replace_region(old, fresh, created_)) return false;  // across a region border: keep it
  ++ops_;
  for (const Tet& f : fresh) touch(f.data(), 4);
  for (TetId t : created_) {
    if (failed_.size() <= t) failed_.resize(m_.num_tet_slots(), kNever);
    failed_[t] = kNever;
    forget_quality(t);
    queue_.push_back(t);
  }
  return true;
}

// The ring of edge ab of tet t for an edge removal: ring_ (closed, 3 to
// kMaxRing tets, every face through ab unconstrained, ab no subsegment) and
// the polygon r_0..r_n-1 around ab, r_k the vertex ring tets k and k + 1
// share besides a and b. The ring turns one way around ab:
// orient3d(a, b, r_k, r_k+1) has one sign, `turn`, for all k. old_q: the
// smallest quality of the ring's tets.
bool Improver::ring_polygon(TetId t, VertexId a, VertexId b, std::array<VertexId, kMaxRing>& r,
                            int& turn, double& old_q) {
  if (cm_.is_subsegment(a, b)) return false;
  bool closed = false;
  if (!cm_.edge_ring(t, a, b, ring_, &closed) || !closed || ring_.size() < 3 ||
      ring_.size() > kMaxRing)
    return false;
  old_q = HUGE_VAL;
  for (TetId u : ring_) {
    const VertexId* tv = m_.tet_vertices(u);
    for (int i = 0; i < 4; ++i)
      if (tv[i] != a && tv[i] != b && cm_.tag(make_hf(u, i)) != kNoTag) return false;
    old_q = std::min(old_q, quality(u));
  }
  const size_t n = ring_.size();
  for (size_t k = 0; k < n; ++k) {
    const VertexId* x = m_.tet_vertices(ring_[k]);
    const VertexId* y = m_.tet_vertices(ring_[(k + 1) % n]);
    r[k] = kNone;
    for (int i = 0; i < 4; ++i)
      if (x[i] != a && x[i] != b && std::find(y, y + 4, x[i]) != y + 4) r[k] = x[i];
    if (r[k] == kNone) return false;
  }
  turn = pred::orient3d(cm_.pt(a), cm_.pt(b), cm_.pt(r[0]), cm_.pt(r[1]));
  return true;
}

// The two tets that triangle (r_i, r_k, r_j) of ring_polygon's polygon
// makes with a and with b. For ring-ordered i < k < j, b lies on the side
// `turn` of (r_i, r_k, r_j) and a on the other; the tets are written so
// that they are positive exactly then.
void ring_tets(const std::array<VertexId, kMaxRing>& r, int turn, VertexId a, VertexId b, size_t i,
               size_t k, size_t j, Tet& ta, Tet& tb) {
  if (turn > 0)
    tb = {r[i], r[k], r[j], b}, ta = {r[k], r[i], r[j], a};
  else
    tb = {r[k], r[i], r[j], b}, ta = {r[i], r[k], r[j], a};
}

// fresh_ from the triangulation of ring_polygon's polygon r_0..r_n-1 that
// pick[i][j] (the apex k of sub-polygon r_i..r_j) describes.
void Improver::ring_fresh(const std::array<VertexId, kMaxRing>& r, int turn, VertexId a, VertexId b,
                          const size_t (*pick)[kMaxRing], size_t n) {
  fresh_.clear();
  std::vector<std::pair<size_t, size_t>> todo = {{0, n - 1}};
  while (!todo.empty()) {
    const auto [i, j] = todo.back();
    todo.pop_back();
    if (j - i < 2) continue;
    const size_t k = pick[i][j];
    Tet ta, tb;
    ring_tets(r, turn, a, b, i, k, j, ta, tb);
    fresh_.push_back(ta), fresh_.push_back(tb);
    todo.push_back({i, k}), todo.push_back({k, j});
  }
}

// Edge removal of edge ab of tet t: the ring around ab (ring_polygon) gives
// the polygon r_0..r_n-1; each triangle (r_i, r_k, r_j) of a triangulation
// of it makes two tets, one with a and one with b. The best triangulation
// (largest smallest angle) by dynamic programming over sub-polygons
// r_i..r_j.
bool Improver::remove_edge(TetId t, VertexId a, VertexId b) {
  std::array<VertexId, kMaxRing> r{};
  int s = 0;
  double old_q;
  if (!ring_polygon(t, a, b, r, s, old_q)) return false;
  const size_t n = ring_.size();
  const double bar = gain_bar(old_q);
  double best[kMaxRing][kMaxRing];
  size_t pick[kMaxRing][kMaxRing];
  for (size_t len = 1; len < n; ++len)
    for (size_t i = 0; i + len < n; ++i) {
      const size_t j = i + len;
      // Only triangulations better than the ring now are of use: that bound
      // prunes most candidates before their tets are measured.
      best[i][j] = len == 1 ? HUGE_VAL : bar;
      for (size_t k = i + 1; k < j; ++k) {
        const double sub = std::min(best[i][k], best[k][j]);
        if (sub <= best[i][j]) continue;
        Tet ta, tb;
        ring_tets(r, s, a, b, i, k, j, ta, tb);
        double q = std::min(sub, quality(ta));
        if (q <= best[i][j]) continue;
        q = std::min(q, quality(tb));
        if (q > best[i][j]) best[i][j] = q, pick[i][j] = k;
      }
    }
  if (!(best[0][n - 1] > bar)) return false;
  ring_fresh(r, s, a, b, pick, n);
  const std::vector<TetId> old = ring_;
  if (adds_ratio_bad(old, fresh_, old_q) || (polishing_ && exceeds_volume(old, fresh_)) ||
      !replace(old, fresh_))
    return false;
  ++counts_.flips;
  return true;
}

// The three tets of the 2-3 flip across face `face` of t into fresh_ (see
// flip23), and the tet u beyond; false when the face is constrained or has
// no tet beyond.
bool Improver::flip23_tets(TetId t, int face, TetId& u) {
  const HalfFace hf = make_hf(t, face);
  const HalfFace nb = m_.adjacent(hf);
  if (nb == kNoHalfFace || cm_.tag(hf) != kNoTag) return false;
  u = hf_tet(nb);
  const VertexId e = m_.opposite(nb);
  const VertexId* tv = m_.tet_vertices(t);
  fresh_.clear();
  for (int k = 0; k < 3; ++k) {
    Tet n{tv[0], tv[1], tv[2], tv[3]};
    n[kFaceVertex[face][k]] = e;
    fresh_.push_back(n);
  }
  return true;
}

// The 2-3 flip across face `face` of t (not constrained, a tet beyond): the
// two tets become three around the edge joining their apexes. Each new tet
// is t with one vertex of the face replaced by the other apex; all three
// positive means that edge crosses the face inside.
bool Improver::flip23(TetId t, int face) {
  TetId u;
  if (!flip23_tets(t, face, u)) return false;
  const double old_q = std::min(quality(t), quality(u));
  for (const Tet& n : fresh_)
    if (!(quality(n) > gain_bar(old_q))) return false;
  if (adds_ratio_bad({t, u}, fresh_, old_q) || (polishing_ && exceeds_volume({t, u}, fresh_)) ||
      !replace({t, u}, fresh_))
    return false;
  ++counts_.flips;
  return true;
}

// A vertex that may move: a Steiner point inside the volume whose faces are
// all unconstrained and inner (so it lies on no facet and no hull face).
bool Improver::free_vertex(VertexId v, const std::vector<TetId>& star) const {
  if (cm_.where[v] != Where::Volume || star.empty()) return false;
  for (TetId t : star) {
    const int iv = m_.index_in_tet(t, v);
    for (int i = 0; i < 4; ++i) {
      if (i == iv) continue;
      const HalfFace hf = make_hf(t, i);
      if (cm_.tag(hf) != kNoTag || m_.adjacent(hf) == kNoHalfFace) return false;
    }
  }
  return true;
}

// The smallest quality of the tets in star_ as they are now (from
// star_tets_, cache_star); stops early once it is at most `floor` (the
// caller has a better candidate already; as with quality_of, such a value
// may have skipped the validity tests) and moves the tet that stopped it to
// the front: the next candidate is mostly refuted by the same tet. Most of
// the pass's time goes here (about 2 million tets on dragon_decimated).
double Improver::star_quality(double floor) {
  double q = HUGE_VAL;
  for (size_t k = 0; k < star_tets_.size(); ++k) {
    const StarTet& s = star_tets_[k];
    const Vec3 v[4] = {to_vec(s.p[0]), to_vec(s.p[1]), to_vec(s.p[2]), to_vec(s.p[3])};
    Vec3 n[4];
    double inv[4];
    double tq = -1;
    bool normals = s.inv > 0;
    for (int i = 0; i < 4 && normals; ++i)
      if (i == s.iv)
        n[i] = s.n, inv[i] = s.inv;
      else
        normals = face_normal(v, i, n[i], inv[i]);
    if (normals) {
      tq = quality_from_normals(n, inv);  // as quality_of(.., floor) gives it
      if (tq > floor && !usable(s.p[0], s.p[1], s.p[2], s.p[3])) tq = -1;
    }
    q = std::min(q, tq);
    if (q <= floor) {
      std::swap(star_[0], star_[k]);
      std::swap(star_tets_[0], star_tets_[k]);
      break;
    }
  }
  return q;
}

// Fills star_tets_ from star_ before smooth() moves v: the same doubles as
// quality_of would compute, so the moves are the same as without the cache.
void Improver::cache_star(VertexId v) {
  star_tets_.resize(star_.size());
  for (size_t k = 0; k < star_.size(); ++k) {
    StarTet& s = star_tets_[k];
    const VertexId* tv = m_.tet_vertices(star_[k]);
    for (int i = 0; i < 4; ++i) {
      s.p[i] = cm_.pt(tv[i]);
      if (tv[i] == v) s.iv = i;
    }
    const Vec3 p[4] = {to_vec(s.p[0]), to_vec(s.p[1]), to_vec(s.p[2]), to_vec(s.p[3])};
    if (!face_normal(p, s.iv, s.n, s.inv)) s.inv = 0;
  }
}

// p moved by `step` along compass direction d (0-5: +x, -x, +y, -y, +z, -z).
Vec3 compass_step(Vec3 p, int d, double step) {
  (d < 2 ? p.x : d < 4 ? p.y : p.z) += (d & 1) ? -step : step;
  return p;
}

// p with its k-th coordinate taken from q.
Vec3 with_coordinate(Vec3 p, int k, const Vec3& q) {
  (k == 0 ? p.x : k == 1 ? p.y : p.z) = k == 0 ? q.x : k == 1 ? q.y : q.z;
  return p;
}

// Whether tet t's radius-edge ratio is above kRatioGuard (or undefined):
// radius_edge_ratio's test with squared lengths, no square root (a
// heuristic's test, not a topological decision). Smoothing's guard and
// every candidate of the moves against ratio 2 test a whole star.
bool Improver::above_guard(const Tet& t) const {
  const Vec3 p[4] = {to_vec(cm_.pt(t[0])), to_vec(cm_.pt(t[1])), to_vec(cm_.pt(t[2])),
                     to_vec(cm_.pt(t[3]))};
  double shortest2 = HUGE_VAL;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) shortest2 = std::min(shortest2, dot(p[i] - p[j], p[i] - p[j]));
  const Vec3 o = sphere_center(p[0], p[1], p[2], p[3]);
  if (!(shortest2 > 0) || !finite(o)) return true;
  return !(dot(o - p[0], o - p[0]) <= kRatioGuard * kRatioGuard * shortest2);
}

bool Improver::above_guard(TetId t) const {
  const VertexId* tv = m_.tet_vertices(t);
  return above_guard(Tet{tv[0], tv[1], tv[2], tv[3]});
}

// The live tets above kRatioGuard, in slot order.
std::vector<TetId> Improver::tets_above_guard() const {
  std::vector<TetId> out;
  for (TetId t = 0; t < m_.num_tet_slots(); ++t)
    if (!m_.is_dead(t) && above_guard(t)) out.push_back(t);
  return out;
}

// The coordinate a move of vertex v must keep: -1 for a free vertex
// (free_vertex), k for a Steiner point on a facet whose plane is
// perpendicular to axis k (every vertex of the subfaces around v has v's
// k-th coordinate exactly), which may slide in that plane; kFixed
// otherwise. A slide changes v's other coordinates only, so the subfaces
// stay exactly in the facet's plane, and with every tet of the star
// positive they cannot fold: the facet stays covered. On other planes a
// rounded position would leave the plane, so those points stay. Slivers
// between the two faces of a thin plate have all four vertices on facets
// (thin_plate.off: every one of its tets below 10 degrees after the pass
// without slides).
int Improver::sliding_axis(VertexId v, const std::vector<TetId>& star) const {
  if (free_vertex(v, star)) return -1;
  if (cm_.where[v] != Where::Facet || star.empty()) return kFixed;
  uint32_t facet = kNoTag;
  bool same[3] = {true, true, true};
  const double* pv = cm_.pt(v);
  for (TetId t : star) {
    const int iv = m_.index_in_tet(t, v);
    for (int i = 0; i < 4; ++i) {
      if (i == iv) continue;
      const HalfFace hf = make_hf(t, i);
      const uint32_t tag = cm_.tag(hf);
      if (tag == kNoTag) {
        if (m_.adjacent(hf) == kNoHalfFace) return kFixed;
        continue;
      }
      if (is_hull_tag(tag) || (facet != kNoTag && tag != facet)) return kFixed;
      facet = tag;
      for (VertexId w : cm_.face_of(hf))
        for (int k = 0; k < 3; ++k) same[k] = same[k] && cm_.pt(w)[k] == pv[k];
    }
  }
  if (facet == kNoTag) return kFixed;
  for (int k = 0; k < 3; ++k)
    if (same[k]) return k;
  return kFixed;
}

// Moves free vertex v (or slides a facet point in its facet's plane,
// sliding_axis) to the best of a few candidate points (rounded to
// doubles; every tet of its star re-tested exactly), if that raises the
// smallest angle of its star.
bool Improver::smooth(VertexId v) {
  if (v < smooth_failed_.size() && smooth_failed_[v] != kNever && v < touched_.size() &&
      touched_[v] <= smooth_failed_[v])
    return false;
  // sliding_axis's first test, before the star.
  if (cm_.where[v] != Where::Volume && cm_.where[v] != Where::Facet) return false;
  m_.vertex_star(v, star_);
  const int keep = sliding_axis(v, star_);
  if (keep == kFixed) return false;
  const Vec3 home = to_vec(cm_.pt(v));
  // Target points: the centroid of the star's other vertices, and the point
  // above the face opposite v in its worst tet at the height of a regular
  // tet on that face.
  Vec3 centroid{0, 0, 0};
  size_t count = 0, worst_at = 0;
  double old_q = HUGE_VAL;
  for (size_t k = 0; k < star_.size(); ++k) {
    const VertexId* tv = m_.tet_vertices(star_[k]);
    for (int i = 0; i < 4; ++i)
      if (tv[i] != v) centroid = centroid + to_vec(cm_.pt(tv[i])), ++count;
    const double q = quality(star_[k]);
    if (q < old_q) old_q = q, worst_at = k;
  }
  // The worst tet first: a candidate that does not beat the best so far
  // most often fails there, and star_quality stops.
  std::swap(star_[0], star_[worst_at]);
  cache_star(v);
  const TetId worst = star_[0];
  Vec3 targets[2] = {(1.0 / static_cast<double>(count)) * centroid, home};
  {
    const int iv = m_.index_in_tet(worst, v);
    const auto f = cm_.face_of(make_hf(worst, iv));
    const Vec3 pa = to_vec(cm_.pt(f[0])), pb = to_vec(cm_.pt(f[1])), pc = to_vec(cm_.pt(f[2]));
    const Vec3 nrm = cross(pb - pa, pc - pa);  // counterclockwise from outside: points away from v
    const double len = norm(nrm);
    const double edge = (dist(pa, pb) + dist(pb, pc) + dist(pc, pa)) / 3;
    if (len > 0)
      targets[1] = (1.0 / 3) * (pa + pb + pc) - (std::sqrt(2.0 / 3) * edge / len) * nrm;
  }
  if (keep >= 0)  // in the facet's plane
    for (Vec3& target : targets) target = with_coordinate(target, keep, home);
  double* xyz = &m_.coords[3 * static_cast<size_t>(v)];
  Vec3 best = home;
  double best_q = old_q;
  for (const Vec3& target : targets) {
    if (!finite(target) || (target.x == home.x && target.y == home.y && target.z == home.z)) continue;
    for (double step : kSteps) {
      const Vec3 p = home + step * (target - home);
      xyz[0] = p.x, xyz[1] = p.y, xyz[2] = p.z;
      const double q = star_quality(best_q);
      if (q > best_q) best_q = q, best = p;
    }
  }
  // The compass search goes on from there, if it adds no badly shaped tet.
  {
    Vec3 b = best;
    double bq = best_q;
    compass_search(v, keep, b, bq);
    if (bq > best_q) {
      xyz[0] = b.x, xyz[1] = b.y, xyz[2] = b.z;
      const size_t bad = ratio_bad_count(star_);
      xyz[0] = best.x, xyz[1] = best.y, xyz[2] = best.z;
      if (bad <= ratio_bad_count(star_)) best = b, best_q = bq;
    }
  }
  // A slide must not add tets above kRatioGuard either: facet points sit
  // where refinement put them to bound the ratio (on thin_plate.off the
  // slides without this check left 10 tets above ratio 2, TetGen none).
  bool adds_bad = false;
  if (keep >= 0 && best_q > old_q + kMoveGain) {
    xyz[0] = home.x, xyz[1] = home.y, xyz[2] = home.z;
    const size_t before = ratio_bad_count(star_);
    xyz[0] = best.x, xyz[1] = best.y, xyz[2] = best.z;
    adds_bad = ratio_bad_count(star_) > before;
  }
  xyz[0] = best.x, xyz[1] = best.y, xyz[2] = best.z;
  if (!(best_q > old_q + kMoveGain) || adds_bad) {
    xyz[0] = home.x, xyz[1] = home.y, xyz[2] = home.z;
    if (smooth_failed_.size() <= v) smooth_failed_.resize(m_.num_vertices(), kNever);
    smooth_failed_[v] = ops_;
    return false;
  }
  ++ops_;
  for (TetId t : star_) queue_.push_back(t), touch(m_.tet_vertices(t), 4), forget_quality(t);
  ++counts_.smooths;
  return true;
}

// The tets of `star` whose radius-edge ratio is above kRatioGuard. A move
// must not add to them: the smallest angle is what the pass raises, but a
// move towards it can stretch a neighbour's circumsphere, and refinement
// has just bounded the ratios (without the guard the pass undoes part of
// that bound).
size_t Improver::ratio_bad_count(const std::vector<TetId>& star) const {
  size_t n = 0;
  for (TetId t : star) {
    n += above_guard(t);
  }
  return n;
}

double Improver::max_ratio(const std::vector<TetId>& tets) const {
  double worst = 0;
  for (TetId u : tets) {
    const VertexId* v = m_.tet_vertices(u);
    worst = std::max(worst, ratio_of(Tet{v[0], v[1], v[2], v[3]}));
  }
  return worst;
}

double Improver::ratio_of(const Tet& t) const {
  const Vec3 p[4] = {to_vec(cm_.pt(t[0])), to_vec(cm_.pt(t[1])), to_vec(cm_.pt(t[2])),
                     to_vec(cm_.pt(t[3]))};
  return radius_edge_ratio(p);
}

// Whether replacing `old` by `fresh` adds tets above kRatioGuard without
// lowering the largest ratio among them: the guard of smooth() for the
// flips and new vertices. Without it a flip that raises the smallest angle
// of a sliver's neighbourhood can swap a well-shaped tet for one with a
// large circumsphere, and the pass leaves tets above the ratio that
// refinement had removed. A nearly flat tet (its ratio unbounded) may still
// give way to a few above the guard, and so may a tet below kGuardAngle
// (old_q, its quality).
bool Improver::adds_ratio_bad(const std::vector<TetId>& old, const std::vector<Tet>& fresh,
                              double old_q) const {
  if (old_q < guard_q_) return false;
  size_t bad = 0;
  double worst_fresh = 0;
  for (const Tet& t : fresh) {
    const double r = ratio_of(t);
    bad += !(r <= kRatioGuard);
    worst_fresh = std::max(worst_fresh, r);
  }
  if (bad == 0) return false;
  size_t old_bad = 0;
  double worst_old = 0;
  for (TetId u : old) {
    const VertexId* v = m_.tet_vertices(u);
    const double r = ratio_of(Tet{v[0], v[1], v[2], v[3]});
    old_bad += !(r <= kRatioGuard);
    worst_old = std::max(worst_old, r);
  }
  return bad > old_bad && !(worst_fresh < worst_old);
}

// From `best` (quality best_q), steps of free vertex v along the
// axes that raise the smallest quality of star_, halved when none does. The
// targets of smooth() are guesses; a vertex between slivers on both sides
// (often one the pass inserted) needs small steps in a direction neither
// target gives. A candidate is mostly refuted by one tet, so the tet that
// refuted the last one is tried first.
void Improver::compass_search(VertexId v, int keep, Vec3& best, double& best_q) {
  double* xyz = &m_.coords[3 * static_cast<size_t>(v)];
  double reach = HUGE_VAL;  // the shortest edge at v
  for (TetId t : star_) {
    const VertexId* tv = m_.tet_vertices(t);
    for (int i = 0; i < 4; ++i)
      if (tv[i] != v) reach = std::min(reach, dist(best, to_vec(cm_.pt(tv[i]))));
  }
  if (!(reach > 0) || !std::isfinite(reach)) return;
  double step = kCompassFirst * reach;
  for (int moves = 0, halvings = 0; moves < kCompassMoves && halvings < kCompassHalvings;) {
    bool moved = false;
    for (int d = 0; d < 6 && !moved; ++d) {
      if (d / 2 == keep) continue;  // a facet point slides in its plane
      const Vec3 p = compass_step(best, d, step);
      xyz[0] = p.x, xyz[1] = p.y, xyz[2] = p.z;
      const double q = star_quality(best_q);
      if (q > best_q) best_q = q, best = p, moved = true, ++moves;
    }
    if (!moved) step *= 0.5, ++halvings;
  }
}

// The cavity of a new vertex at p, grown from t: the tets whose faces p
// does not see from inside (not positive or numerically flat with p), added
// across such faces until every boundary face is seen, so that the cone of
// the boundary to p is a valid filling. False when a face p does not see is
// constrained, open or a region border, or the cavity grows past kMaxCavity.
// faces_ gets the boundary (counterclockwise from outside: p goes fourth).
bool Improver::star_cavity(TetId t, const double* p) {
  // One pass over the cavity as it grows (each tet's faces looked at once,
  // the cavity marked by kTetInCavity): a face found seen whose tet beyond
  // joins later is inside, and the boundary is collected at the end.
  cavity_.assign(1, t);
  m_.tflag[t] |= kTetInCavity;
  bool ok = true;
  for (size_t k = 0; k < cavity_.size() && ok; ++k)
    for (int i = 0; i < 4 && ok; ++i) {
      const HalfFace hf = make_hf(cavity_[k], i);
      const HalfFace nb = m_.adjacent(hf);
      if (nb != kNoHalfFace && (m_.tflag[hf_tet(nb)] & kTetInCavity)) continue;
      if (sees(hf, p)) continue;
      if (nb == kNoHalfFace || cm_.tag(hf) != kNoTag || cm_.attr[hf_tet(nb)] != cm_.attr[t] ||
          cavity_.size() >= kMaxCavity) {
        ok = false;
        break;
      }
      m_.tflag[hf_tet(nb)] |= kTetInCavity;
      cavity_.push_back(hf_tet(nb));
    }
  faces_.clear();
  for (size_t k = 0; k < cavity_.size() && ok; ++k)
    for (int i = 0; i < 4; ++i) {
      const HalfFace hf = make_hf(cavity_[k], i);
      const HalfFace nb = m_.adjacent(hf);
      if (nb == kNoHalfFace || !(m_.tflag[hf_tet(nb)] & kTetInCavity))
        faces_.push_back(cm_.face_of(hf));
    }
  for (TetId u : cavity_) m_.tflag[u] &= static_cast<uint8_t>(~kTetInCavity);
  return ok;
}

// Whether p sees face hf from inside its tet: a positive, not numerically
// flat tet with it.
bool Improver::sees(HalfFace hf, const double* p) const {
  const auto f = cm_.face_of(hf);
  return pred::orient3d(cm_.pt(f[0]), cm_.pt(f[1]), cm_.pt(f[2]), p) > 0 &&
         !numerically_flat(cm_.pt(f[0]), cm_.pt(f[1]), cm_.pt(f[2]), p);
}

// The star cavity of a new vertex at p from t (star_cavity: cavity_ and
// faces_), and the smallest quality of its tets now in old_q.
bool Improver::cavity_at(TetId t, const double* p, double& old_q) {
  if (!star_cavity(t, p)) return false;
  old_q = HUGE_VAL;
  for (TetId u : cavity_) old_q = std::min(old_q, quality(u));
  return true;
}

// The smallest quality of the tets joining faces_ to p, exact above `look`
// (quality_of): at or under it, the rest of the faces are not looked at.
double Improver::new_quality(const double* p, double look) const {
  double q = HUGE_VAL;
  for (const auto& f : faces_) {
    q = std::min(q, quality_of(cm_.pt(f[0]), cm_.pt(f[1]), cm_.pt(f[2]), p, look));
    if (q <= look) break;
  }
  return q;
}

// For a new vertex at c with the cavity and faces star_cavity() left: how
// many more tets above kRatioGuard its tets hold than the cavity's (its
// largest ratio in worst_fresh_).
long Improver::added_ratio_bad(const Vec3& c) {
  long bad = 0;
  worst_fresh_ = 0;
  for (const auto& f : faces_) {
    const Vec3 tp[4] = {to_vec(cm_.pt(f[0])), to_vec(cm_.pt(f[1])), to_vec(cm_.pt(f[2])), c};
    const double r = radius_edge_ratio(tp);
    bad += !(r <= kRatioGuard);
    worst_fresh_ = std::max(worst_fresh_, r);
  }
  return bad - static_cast<long>(ratio_bad_count(cavity_));
}

// From candidate `best` (at, taken for tet t), compass steps that still
// raise the tets of their cavity (gain_bar) and add fewer tets above
// kRatioGuard; best becomes the last such point.
void Improver::fewer_ratio_bad(TetId t, Vec3 at, double edge, Candidate& best) {
  const double home[3] = {at.x, at.y, at.z};
  if (!star_cavity(t, home)) return;
  long fewest = added_ratio_bad(at);
  double step = 0.5 * kCompassFirst * edge;
  for (int halvings = 0, moves = 0; halvings < kCompassHalvings && moves < 2 * kCompassMoves && fewest > 0;) {
    bool moved = false;
    for (int d = 0; d < 6 && !moved; ++d) {
      const Vec3 c = compass_step(at, d, step);
      const double p[3] = {c.x, c.y, c.z};
      double old_q;
      if (!cavity_at(t, p, old_q)) continue;
      const double bar = gain_bar(old_q);
      const double q = new_quality(p, bar);
      if (!(q > bar)) continue;
      const long added = added_ratio_bad(c);
      if (added < fewest) fewest = added, at = c, moved = true, ++moves, best = {q, c, cavity_, faces_};
    }
    if (!moved) step *= 0.5, ++halvings;
  }
}

// Whether a vertex of tv is on a needle (improve_mesh's `needle`).
bool Improver::at_needle(const VertexId* tv) const {
  if (!needle_) return false;
  for (int i = 0; i < 4; ++i)
    if (tv[i] < needle_->size() && (*needle_)[tv[i]]) return true;
  return false;
}

// Whether candidate c's new tets hold more below kGuardAngle than its
// cavity.
bool Improver::adds_slivers(const Candidate& c) const {
  long below = 0;
  for (TetId u : c.cavity) below -= quality(u) < guard_q_;
  const double p[3] = {c.at.x, c.at.y, c.at.z};
  for (const auto& f : c.faces)
    below += quality_of(cm_.pt(f[0]), cm_.pt(f[1]), cm_.pt(f[2]), p) < guard_q_;
  return below > 0;
}

// The last resort for a sliver no flip or move fixes, typically one on the
// boundary whose two constrained faces lie on nearly coplanar facets (any tet
// holding both is flat, so a vertex inside must see them apart): a new
// vertex at a point inward of t (from its centroid, away from its
// constrained and open faces or from those of t and its neighbours, by a
// fraction of its mean edge), joined to the
// boundary of its star cavity. The candidate whose new tets have the
// largest smallest angle goes in, if that beats the cavity's tets;
// smoothing may move it on later, as it is free.
bool Improver::insert_point(TetId t) {
  const VertexId* tv = m_.tet_vertices(t);
  Vec3 centre{0, 0, 0};
  double edge = 0;
  for (int i = 0; i < 4; ++i) {
    centre = centre + 0.25 * to_vec(cm_.pt(tv[i]));
    for (int j = i + 1; j < 4; ++j) edge += dist(to_vec(cm_.pt(tv[i])), to_vec(cm_.pt(tv[j]))) / 6;
  }
  // Directions inward: away from t's constrained and open faces, and away
  // from those of t and its neighbours (where the boundary bends, a point
  // inward of t's own faces can lie beyond a neighbour's).
  Vec3 own{0, 0, 0}, near{0, 0, 0};
  auto add_faces = [&](TetId u, Vec3& sum) {
    for (int i = 0; i < 4; ++i) {
      const HalfFace hf = make_hf(u, i);
      if (cm_.tag(hf) == kNoTag && m_.adjacent(hf) != kNoHalfFace) continue;
      const auto f = cm_.face_of(hf);
      const Vec3 a = to_vec(cm_.pt(f[0]));
      const Vec3 n = cross(to_vec(cm_.pt(f[1])) - a, to_vec(cm_.pt(f[2])) - a);  // outward
      const double len = norm(n);
      if (len > 0) sum = sum - (1 / len) * n;
    }
  };
  add_faces(t, own);
  near = own;
  for (int i = 0; i < 4; ++i) {
    const HalfFace nb = m_.adjacent(make_hf(t, i));
    if (nb != kNoHalfFace && cm_.tag(make_hf(t, i)) == kNoTag) add_faces(hf_tet(nb), near);
  }
  Vec3 directions[2];
  int nd = 0;
  for (const Vec3& d : {own, near}) {
    const double len = norm(d);
    if (len > 0) directions[nd++] = (1 / len) * d;
  }
  if (nd == 0) return false;  // no boundary face: flips and moves are the tools there
  // The winner's cavity and boundary are kept, not grown again.
  // The best candidate that adds no tet above kRatioGuard (clean), and the
  // best of all; the latter only for a tet below kGuardAngle, as
  // adds_ratio_bad, and only when the clean one stays below it and is worse.
  Candidate clean_best, any_best;
  const bool guarded = quality(t) >= guard_q_;
  // One candidate point c: its star cavity, the smallest quality of the
  // tets it would make, and whether those add tets above kRatioGuard.
  // seen: the best point with a cavity so far, taken or not (the compass
  // search below starts there).
  Vec3 seen_at{};
  double seen_q = -1;
  auto consider = [&](const Vec3& c) {
    const double p[3] = {c.x, c.y, c.z};
    double old_q;
    if (!cavity_at(t, p, old_q)) return;
    // What q must beat to be taken (the test below), or to be seen.
    const double floor =
        std::max(gain_bar(old_q), guarded ? clean_best.q : std::min(clean_best.q, any_best.q));
    const double q = new_quality(p, std::min(floor, seen_q));
    if (q > seen_q) seen_q = q, seen_at = c;
    if (!(q > gain_bar(old_q)) || !(q > clean_best.q || (!guarded && q > any_best.q))) return;
    const long added = added_ratio_bad(c);
    const bool clean = added <= 0 || worst_fresh_ < max_ratio(cavity_);
    if (clean && q > clean_best.q) clean_best = {q, c, cavity_, faces_};
    if (!guarded && q > any_best.q) any_best = {q, c, cavity_, faces_};
  };
  for (int k = 0; k < nd; ++k)
    for (double h : kInsertHeights) consider(centre + (h * edge) * directions[k]);
  // Below kGuardAngle with no candidate taken: the fixed points are
  // guesses along two lines, and a wedge between facets or a sliver beside
  // a new vertex of the pass wants a point off them. A compass search from
  // the best point seen, then from the one it finds a second search that
  // lowers the number of tets above kRatioGuard it adds while it still
  // raises the tet.
  if (!guarded && any_best.q < 0 && seen_q > 0) {
    Vec3 at = seen_at;
    double step = kCompassFirst * edge;
    for (int halvings = 0, moves = 0; halvings < kCompassHalvings + 1 && moves < 2 * kCompassMoves &&
                                      any_best.q < 0;) {
      const double before = seen_q;
      bool moved = false;
      for (int d = 0; d < 6 && !moved; ++d) {
        consider(compass_step(at, d, step));
        if (seen_q > before) at = seen_at, moved = true, ++moves;
      }
      if (!moved) step *= 0.5, ++halvings;
    }
    if (clean_best.q < 0 && any_best.q >= 0) fewer_ratio_bad(t, any_best.at, edge, any_best);
    // At a needle (a vertex of the sliver on a needle's side or corner),
    // the point found must not leave more tets below kGuardAngle than the
    // cavity holds: in a needle's thin triangles a point that raises the
    // sliver often makes two or three slivers only a little better. Tets
    // below 10 degrees, no search at needles / search / search with this
    // test: nefertiti 151 / 217 / 130, dragon_decimated 67 / 25 / 32
    // (tests/bench/README.md).
    if (clean_best.q < 0 && any_best.q >= 0 && at_needle(tv) && adds_slivers(any_best))
      any_best = Candidate{};
  }
  const Candidate& pick =
      clean_best.q >= 0 && (clean_best.q >= any_best.q || clean_best.q >= guard_q_) ? clean_best
                                                                                    : any_best;
  const Vec3 best = pick.at;
  const std::vector<TetId>& best_cavity = pick.cavity;
  const std::vector<std::array<VertexId, 3>>& best_faces = pick.faces;
  if (best_cavity.empty()) return false;
  const double xyz[3] = {best.x, best.y, best.z};
  const VertexId v = cm_.new_vertex(xyz, Where::Volume, -1);
  fresh_.clear();
  for (const auto& f : best_faces) fresh_.push_back({f[0], f[1], f[2], v});
  if (!replace(best_cavity, fresh_)) {
    cm_.drop_last_vertex();  // never on a valid mesh: one region, faces matched
    return false;
  }
  ++counts_.inserts;
  return true;
}

// Tries the operations on tet t until one succeeds: removal of each of its
// edges, the 2-3 flip across each face, a move of each free vertex, a new
// vertex.
bool Improver::improve_tet(TetId t) {
  if (pinned(t) || unchanged_since_failure(t)) return false;
  const VertexId* tv = m_.tet_vertices(t);
  const Tet v{tv[0], tv[1], tv[2], tv[3]};
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      if (remove_edge(t, v[i], v[j])) return true;
  for (int f = 0; f < 4; ++f)
    if (flip23(t, f)) return true;
  for (int i = 0; i < 4; ++i)
    if (smooth(v[i])) return true;
  if (insert_point(t)) return true;
  if (failed_.size() <= t) failed_.resize(m_.num_tet_slots(), kNever);
  failed_[t] = ops_;
  return false;
}

// A tet whose smallest dihedral angle lies at the edge of two constrained
// faces: those two faces fix it (they are subfaces of input facets meeting
// at that angle, or of one facet folded by rounded points), so no flip,
// move or new vertex inside changes it. CAD models with sharp input edges
// have thousands; trying every operation on each would cost more than
// refinement itself, for nothing.
bool Improver::pinned(TetId t) const {
  const VertexId* tv = m_.tet_vertices(t);
  const Vec3 p[4] = {to_vec(cm_.pt(tv[0])), to_vec(cm_.pt(tv[1])), to_vec(cm_.pt(tv[2])),
                     to_vec(cm_.pt(tv[3]))};
  // The dihedral angle at edge (i, j) lies between faces k and l (the faces
  // opposite the other two vertices); find the smallest by its cosine.
  double worst = -2;
  int fk = -1, fl = -1;
  for (int k = 0; k < 4; ++k)
    for (int l = k + 1; l < 4; ++l) {
      int i = 0;
      while (i == k || i == l) ++i;
      const int j = 6 - i - k - l;  // the edge's other end
      const Vec3 e = p[j] - p[i];
      const Vec3 nk = cross(e, p[k] - p[i]), nl = cross(e, p[l] - p[i]);
      const double d = norm(nk) * norm(nl);
      const double c = d > 0 ? dot(nk, nl) / d : 1;  // cosine of the angle at edge ij
      if (c > worst) worst = c, fk = k, fl = l;
    }
  return cm_.tag(make_hf(t, fk)) != kNoTag && cm_.tag(make_hf(t, fl)) != kNoTag;
}

void Improver::touch(const VertexId* v, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    if (touched_.size() <= v[i]) touched_.resize(m_.num_vertices(), 0);
    touched_[v[i]] = ops_;
  }
}

// improve_tet(t) failed and no operation has changed the star of any of its
// vertices since: it would fail again (the tets it looks at are the same,
// but for a new vertex's cavity, which may reach further).
bool Improver::unchanged_since_failure(TetId t) const {
  if (t >= failed_.size() || failed_[t] == kNever) return false;
  const VertexId* tv = m_.tet_vertices(t);
  for (int i = 0; i < 4; ++i)
    if (tv[i] < touched_.size() && touched_[tv[i]] > failed_[t]) return false;
  return true;
}

// Tets above kRatioGuard left by refinement (a split point refused by the
// radius rule) or by the rounds (a fix of a tet below kGuardAngle may add
// them): a move of one of their vertices (free or sliding, as smooth())
// that leaves fewer such tets in its star and makes no new sliver
// (move_for_ratio). The rounds maximise the smallest angle; this is the one
// place that lowers a ratio for its own sake.
// False when cancelled.
bool Improver::reduce_ratio_bad(const volatile bool* cancel) {
  std::vector<TetId> bad = tets_above_guard();
  for (size_t k = 0; k < bad.size(); ++k) {
    if ((k & 1023) == 0 && cancel && *cancel) return false;
    const TetId t = bad[k];
    if (m_.is_dead(t)) continue;
    const VertexId* tv = m_.tet_vertices(t);
    const Tet v{tv[0], tv[1], tv[2], tv[3]};
    if (!above_guard(v)) continue;  // a move for an earlier one fixed it
    for (VertexId w : v)
      if (move_for_ratio(w)) break;
  }
  return true;
}

// Moves v (free, or sliding in its facet's plane) towards the centroid of
// its star's other vertices or by compass steps, to the candidate whose
// star has the fewest tets above kRatioGuard, if that is fewer than now and
// no star tet ends below its floor (below).
bool Improver::move_for_ratio(VertexId v) {
  if (cm_.where[v] != Where::Volume && cm_.where[v] != Where::Facet) return false;
  // Its star unchanged since it last failed (a vertex never touched has
  // the star it had then): it fails again.
  if (v < ratio_failed_.size() && ratio_failed_[v] != kNever &&
      (v < touched_.size() ? touched_[v] : 0) <= ratio_failed_[v])
    return false;
  m_.vertex_star(v, star_);
  const int keep = sliding_axis(v, star_);
  if (keep == kFixed) return false;
  // The tets above kRatioGuard first: a candidate that leaves the first of
  // them so is mostly turned down at once (when it is the only one).
  const auto first_good = std::stable_partition(star_.begin(), star_.end(), [&](TetId t) {
    return above_guard(t);
  });
  const size_t old_bad = static_cast<size_t>(first_good - star_.begin());
  if (old_bad == 0) return false;
  const Vec3 home = to_vec(cm_.pt(v));
  Vec3 centroid{0, 0, 0};
  size_t count = 0;
  double reach = HUGE_VAL;
  for (TetId t : star_) {
    const VertexId* tv = m_.tet_vertices(t);
    for (int i = 0; i < 4; ++i)
      if (tv[i] != v) {
        const Vec3 p = to_vec(cm_.pt(tv[i]));
        centroid = centroid + p, ++count, reach = std::min(reach, dist(home, p));
      }
  }
  // Each star tet's floor: its quality now, or the target or the star's
  // smallest quality, the larger of those two, if lower: no new sliver,
  // and the mesh's smallest angle does not drop.
  double star_q = HUGE_VAL;
  for (TetId t : star_) star_q = std::min(star_q, quality(t));
  floors_.clear();
  for (TetId t : star_) floors_.push_back(std::min(quality(t), std::max(target_, star_q)));
  double* xyz = &m_.coords[3 * static_cast<size_t>(v)];
  Vec3 best = home;
  size_t best_bad = old_bad;
  // A candidate: fewer star tets above kRatioGuard than the best so far
  // (counted first, stopping at that many), then no star tet below its floor
  // or invalid (quality_of's exact tests).
  auto consider = [&](Vec3 p) {
    if (keep >= 0) p = with_coordinate(p, keep, home);
    if (!finite(p)) return;
    xyz[0] = p.x, xyz[1] = p.y, xyz[2] = p.z;
    size_t n_bad = 0;
    for (TetId t : star_) {
      n_bad += above_guard(t);
      if (n_bad >= best_bad) return;
    }
    for (size_t k = 0; k < star_.size(); ++k) {
      const VertexId* tv = m_.tet_vertices(star_[k]);
      if (quality(Tet{tv[0], tv[1], tv[2], tv[3]}) < floors_[k]) return;
    }
    best = p, best_bad = n_bad;
  };
  const Vec3 target = (1.0 / static_cast<double>(count)) * centroid;
  for (double step : kSteps) consider(home + step * (target - home));
  if (std::isfinite(reach) && reach > 0)
    for (double step = kCompassFirst * reach; step > kCompassFirst * reach / 8; step *= 0.5)
      for (int d = 0; d < 6; ++d)
        if (d / 2 != keep) consider(compass_step(home, d, step));
  xyz[0] = best.x, xyz[1] = best.y, xyz[2] = best.z;
  if (best_bad >= old_bad) {
    xyz[0] = home.x, xyz[1] = home.y, xyz[2] = home.z;
    if (ratio_failed_.size() <= v) ratio_failed_.resize(m_.num_vertices(), kNever);
    ratio_failed_[v] = ops_;
    return false;
  }
  ++ops_;  // after the rounds: nothing is queued, the caches are updated
  for (TetId t : star_) touch(m_.tet_vertices(t), 4), forget_quality(t);
  ++counts_.smooths;
  return true;
}

// After the moves against ratio 2 (reduce_ratio_bad), flips against it: at
// each tet above kRatioGuard, a 2-3 flip or an edge removal whose new tets
// hold fewer such tets than the ones they replace, with none below the
// replaced tets' smallest quality or the target, the lower of the two (the
// pass does not undo its own work, and the mesh's smallest angle does not
// drop). The moves leave most such tets where no vertex may move (on
// segments, or between facet points off the axis planes): the flips take
// dragon_decimated's share of tets above ratio 2 from 5.07% to 4.55%,
// decimated_knight's from 2.25% to 1.98% (tests/bench/README.md). The tets
// a flip makes are tried in turn; the work is bounded by kRatioFlipWork per
// tet above the guard.
bool Improver::flip_ratio_bad(const volatile bool* cancel) {
  std::vector<TetId> work = tets_above_guard();
  queue_.clear();
  const size_t budget = kRatioFlipWork * work.size();
  for (size_t k = 0; k < work.size() && k < budget; ++k) {
    if ((k & 1023) == 0 && cancel && *cancel) return false;
    const TetId t = work[k];
    if (m_.is_dead(t)) continue;
    if (!above_guard(t)) continue;
    if (flip_for_ratio(t))  // the tets it made, which replace() queued, are tried too
      work.insert(work.end(), queue_.begin(), queue_.end());
    queue_.clear();
  }
  return true;
}

// One flip of flip_ratio_bad at tet t: the 2-3 flips across its faces, then
// the removals of its edges.
bool Improver::flip_for_ratio(TetId t) {
  const VertexId* tv = m_.tet_vertices(t);
  const Tet v{tv[0], tv[1], tv[2], tv[3]};
  for (int face = 0; face < 4; ++face) {
    TetId u;
    if (!flip23_tets(t, face, u)) continue;
    const double floor = std::min(std::min(quality(t), quality(u)), target_);
    const int old_bad = above_guard(v) + above_guard(u);
    int bad = 0;
    bool ok = true;
    for (size_t k = 0; k < fresh_.size() && ok && bad < old_bad; ++k) {
      bad += above_guard(fresh_[k]);
      const double q = quality(fresh_[k]);
      ok = q >= floor && q > 0;
    }
    if (!ok || bad >= old_bad || exceeds_volume({t, u}, fresh_) || !replace({t, u}, fresh_))
      continue;
    ++counts_.flips;
    return true;
  }
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      if (remove_edge_for_ratio(t, v[i], v[j])) return true;
  return false;
}

// Edge removal (remove_edge) by a triangulation of the ring's polygon with
// the fewest tets above kRatioGuard (dynamic programming as there; the
// counts add up over sub-polygons, so a part that already holds as many as
// the ring is cut off), every new tet at or above the floor of
// flip_ratio_bad.
bool Improver::remove_edge_for_ratio(TetId t, VertexId a, VertexId b) {
  std::array<VertexId, kMaxRing> r{};
  int s = 0;
  double old_q;
  if (!ring_polygon(t, a, b, r, s, old_q)) return false;
  const double floor = std::min(old_q, target_);
  const size_t n = ring_.size();
  const long old_bad = static_cast<long>(ratio_bad_count(ring_));
  long cost[kMaxRing][kMaxRing];
  size_t pick[kMaxRing][kMaxRing];
  for (size_t len = 1; len < n; ++len)
    for (size_t i = 0; i + len < n; ++i) {
      const size_t j = i + len;
      cost[i][j] = len == 1 ? 0 : old_bad;  // old_bad: none found yet
      for (size_t k = i + 1; k < j; ++k) {
        const long sub = cost[i][k] + cost[k][j];
        if (sub >= cost[i][j]) continue;
        Tet ta, tb;
        ring_tets(r, s, a, b, i, k, j, ta, tb);
        const long c = sub + above_guard(ta) + above_guard(tb);
        if (c >= cost[i][j]) continue;
        const double qa = quality(ta);
        if (!(qa >= floor && qa > 0)) continue;
        const double qb = quality(tb);
        if (!(qb >= floor && qb > 0)) continue;
        cost[i][j] = c, pick[i][j] = k;
      }
    }
  if (!(cost[0][n - 1] < old_bad)) return false;
  ring_fresh(r, s, a, b, pick, n);
  const std::vector<TetId> old = ring_;
  if (exceeds_volume(old, fresh_) || !replace(old, fresh_)) return false;
  ++counts_.flips;
  return true;
}

// When no tet is below the target, the smallest angle of the mesh can still
// rise by flips at its worst tets (a small mesh meets any target at once,
// and its smallest angle is what one compares): edge removals and 2-3 flips
// at the kPolishTets worst tets, each done only when it raises the smallest
// angle of the tets it replaces, until a round changes nothing. No vertex
// moves or is added, so refinement's radius-edge bound is kept as the pass
// keeps it.
void Improver::polish() {
  polishing_ = true;
  polish_rounds();
  polishing_ = false;
}

// Whether a tet of `fresh` is larger than the volume bound of the region
// of `old` (VolumeBounds): a polishing flip must not make a tet that
// refinement would split again.
bool Improver::exceeds_volume(const std::vector<TetId>& old, const std::vector<Tet>& fresh) const {
  double limit = bounds_.max_volume > 0 ? bounds_.max_volume : HUGE_VAL;
  const double attr = cm_.attr[old[0]];
  for (const auto& r : bounds_.regions)
    if (r.first == attr) limit = std::min(limit, r.second);
  if (!std::isfinite(limit)) return false;
  for (const Tet& t : fresh) {
    const Vec3 a = to_vec(cm_.pt(t[0]));
    const double v = std::fabs(dot(to_vec(cm_.pt(t[1])) - a,
                                   cross(to_vec(cm_.pt(t[2])) - a, to_vec(cm_.pt(t[3])) - a))) /
                     6;
    if (v > limit) return true;
  }
  return false;
}

void Improver::polish_rounds() {
  std::vector<std::pair<double, TetId>> worst;
  for (int round = 0; round < kPolishRounds; ++round) {
    worst.clear();
    for (TetId t = 0; t < m_.num_tet_slots(); ++t) {
      if (m_.is_dead(t)) continue;
      const double q = quality(t);
      if (q < target_) return;  // the rounds above left it: they tried all
      worst.push_back({q, t});
    }
    const size_t k = std::min(kPolishTets, worst.size());
    std::partial_sort(worst.begin(), worst.begin() + static_cast<long>(k), worst.end());
    bool changed = false;
    for (size_t i = 0; i < k; ++i) {
      const TetId t = worst[i].second;
      if (m_.is_dead(t) || pinned(t)) continue;
      const VertexId* tv = m_.tet_vertices(t);
      const Tet v{tv[0], tv[1], tv[2], tv[3]};
      bool done = false;
      for (int a = 0; a < 4 && !done; ++a)
        for (int b = a + 1; b < 4 && !done; ++b) done = remove_edge(t, v[a], v[b]);
      for (int f = 0; f < 4 && !done; ++f) done = flip23(t, f);
      changed = changed || done;
    }
    if (!changed) return;
  }
}

// Rounds over the tets below the target; progress counts rounds (a round's
// share split by its queue position).
Status Improver::run(const volatile bool* cancel, const ImproveProgress& progress,
                     ImproveCounts& counts) {
  std::vector<TetId> left;  // tets below the target after a round: the next round's queue
  for (TetId t = 0; t < m_.num_tet_slots(); ++t)
    if (!m_.is_dead(t) && quality(t) < target_) left.push_back(t);
  double reported = -1;
  for (int round = 0; round < kRounds && !left.empty(); ++round) {
    queue_.swap(left);
    left.clear();
    const size_t done_before = counts_.flips + counts_.smooths + counts_.inserts;
    // Tets made by an operation join the queue; the budget bounds a round.
    const size_t budget = 20 * queue_.size() + 1000;
    for (size_t head = 0; head < queue_.size() && head < budget; ++head) {
      if ((head & 1023) == 0) {
        // The queue grows as operations add tets, so the fraction may
        // step back: only a larger one is reported.
        const double f = (round + static_cast<double>(head) / static_cast<double>(queue_.size())) / kRounds;
        if (progress.report && f > reported)
          progress.report(progress.user, progress.from + (progress.to - progress.from) * (reported = f));
        if (cancel && *cancel)  // after the report, which may have asked for it
          return make_error(ErrorCode::Cancelled, "Cancelled during the improvement pass.");
      }
      const TetId t = queue_[head];
      if (m_.is_dead(t) || !(quality(t) < target_)) continue;
      if (!improve_tet(t)) left.push_back(t);
    }
    // Tets queued by operations but not reached within the budget.
    for (size_t head = std::min(queue_.size(), budget); head < queue_.size(); ++head)
      left.push_back(queue_[head]);
    std::sort(left.begin(), left.end());
    left.erase(std::unique(left.begin(), left.end()), left.end());
    if (counts_.flips + counts_.smooths + counts_.inserts == done_before) break;
  }
  if (!reduce_ratio_bad(cancel) || !flip_ratio_bad(cancel))
    return make_error(ErrorCode::Cancelled, "Cancelled during the improvement pass.");
  polish();
  counts = counts_;
  return Status::success();
}

}  // namespace

Status improve_mesh(ConstrainedMesh& cm, double target, const volatile bool* cancel,
                    ImproveCounts& counts, const ImproveProgress& progress,
                    const VolumeBounds& bounds, const std::vector<char>* needle) {
  Improver improver(cm, target, bounds, needle);
  return improver.run(cancel, progress, counts);
}

}  // namespace cdt3d
