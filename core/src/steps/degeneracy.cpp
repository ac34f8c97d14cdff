// Step 3: local degeneracy removal (Si & Gärtner 2005 §6).
//
// D1 (Delaunay, all subsegments are edges) may hold local degeneracies: two
// adjacent tets whose five vertices lie on one sphere, exactly, without the
// symbolic perturbation. Each is removed by a break point inside the common
// sphere (in the common plane when four of the points are coplanar), unless
// the break point would encroach upon a subsegment or a subface, in which
// case the boundary is protected first (§6, boundary protection procedure).
// A degeneracy with a perturbable vertex (a Steiner vertex on a segment or
// inside a facet; input vertices never move) is first tried by a
// segment-safe perturbation of it: try_perturb removes the vertex
// (remove_vertex) and inserts it again a little way along its segment or
// facet (move_vertex). The outer loop repeats until D2 has no local
// degeneracy.
#include "degeneracy.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <unordered_map>

#include "delaunay.hpp"
#include "geometry.hpp"
#include "predicates.hpp"
#include "spatial_sort.hpp"
#include "status.hpp"
#include "subfaces.hpp"
#include "vertex_removal.hpp"

namespace cdt3d {

namespace {

// Bounds of the outer loop. A valid PLC needs a few rounds in practice (the
// paper's examples add at most 2x the input vertices); reaching a bound means
// rounding or an invalid input made the loop cycle.
constexpr size_t kMaxRounds = 64;
constexpr int kMaxDraws = 24;             // random positions tried per break point
constexpr double kRelativeJitter = 1e-3;  // perturbation size, relative to the radius

// Points step 3 may add in all (break, protection and re-split segment
// points): kPointsPerVertex per vertex of D1 plus kPointsBase for tiny
// inputs. A valid PLC needs far fewer; more means the loop cycles.
constexpr size_t kPointsPerVertex = 4, kPointsBase = 1000;

// Relative slack on the radius of a protecting ball (diametral ball of a
// subsegment, equatorial ball of a subface) in the floating-point tests and
// in the ball index. It errs towards "encroached" and towards one index cell
// too many: either costs at most a protection point or a test, whereas a
// missed ball would let a break point encroach.
constexpr double kBallSlack = 1e-6;

// A circle or sphere center farther than this many diameters of the
// degeneracy's points from their centroid comes from nearly collinear or
// coplanar points; its rounding error is then too large for it to be a break
// point, and the break point is drawn around the centroid instead.
constexpr double kMaxCenterDistance = 1e3;

// Floating-point constructions (circle_center and sphere_center of
// geometry.hpp) only place points and rank candidates; every topological
// decision uses the exact predicates.

// Four points on one circle in one plane. `q` holds 4 points; the circle is
// taken through a non-collinear triple. Four collinear points: false.
bool coplanar_cocircular(const double* const* q) {
  if (pred::orient3d(q[0], q[1], q[2], q[3]) != 0) return false;
  for (int skip = 3; skip >= 0; --skip) {
    const double* r[3];
    int k = 0;
    for (int i = 0; i < 4; ++i)
      if (i != skip) r[k++] = q[i];
    if (!pred::collinear3d(r[0], r[1], r[2]))
      return pred::incircle_coplanar(r[0], r[1], r[2], q[skip]) == 0;
  }
  return false;
}

// ---------------------------------------------------------------------------
// Detection
// ---------------------------------------------------------------------------

// A local degeneracy found at half-face (t, i): the tets on both sides of the
// face are t and its neighbour across face i. For a hull degeneracy both are
// ghost tets and the face is (a, b, kInfinite). `verts` and `apex` let a later
// check see whether the configuration still exists.
struct Found {
  LocalDegeneracy ids;
  TetId t;
  int face;
  std::array<VertexId, 4> verts;
  VertexId apex;
  int tries = 0;  // protections done for it in this round
};

void collect(const TetMesh& mesh, std::vector<Found>& out) {
  out.clear();
  const size_t slots = mesh.num_tet_slots();
  for (size_t ts = 0; ts < slots; ++ts) {
    const TetId t = static_cast<TetId>(ts);
    if (mesh.is_dead(t)) continue;
    const VertexId* w = mesh.tet_vertices(t);
    const bool ghost = w[3] == kInfinite;
    for (int i = 0; i < (ghost ? 3 : 4); ++i) {
      const HalfFace hf = mesh.adjacent(make_hf(t, i));
      const TetId n = hf_tet(hf);
      if (n < t) continue;  // each pair once
      const VertexId e = mesh.vertex(n, hf_face(hf));
      const bool n_ghost = mesh.is_ghost(n);
      bool degenerate = false;
      if (!ghost && !n_ghost) {
        const double *a = mesh.point(w[0]), *b = mesh.point(w[1]), *c = mesh.point(w[2]),
                     *d = mesh.point(w[3]), *p = mesh.point(e);
        degenerate = pred::insphere(a, b, c, d, p) == 0;
      } else if (ghost && n_ghost) {
        // Two hull faces across a hull edge: coplanar and co-circular.
        const double* q[4] = {mesh.point(w[0]), mesh.point(w[1]), mesh.point(w[2]), mesh.point(e)};
        degenerate = coplanar_cocircular(q);
      }
      if (!degenerate) continue;
      Found f;
      f.ids = {w[0], w[1], w[2], w[3], e};
      std::sort(f.ids.begin(), f.ids.end());
      f.t = t;
      f.face = i;
      f.verts = {w[0], w[1], w[2], w[3]};
      f.apex = e;
      out.push_back(f);
    }
  }
  std::sort(out.begin(), out.end(), [](const Found& x, const Found& y) {
    if (x.ids != y.ids) return x.ids < y.ids;
    if (x.t != y.t) return x.t < y.t;
    return x.face < y.face;
  });
  out.erase(std::unique(out.begin(), out.end(),
                        [](const Found& x, const Found& y) { return x.ids == y.ids; }),
            out.end());
}

// Finds the two tets of f again after the mesh was rebuilt around them (a
// perturbation attempt that was undone gives back the same tetrahedralization
// in other tet slots). False if they no longer exist.
bool relocate(TetMesh& mesh, Found& f) {
  VertexId fv[3];
  int n = 0;
  for (int k = 0; k < 4; ++k)
    if (k != f.face) fv[n++] = f.verts[k];
  const VertexId opposite = f.verts[f.face];
  const HalfFace hf = mesh.find_face(fv[0], fv[1], fv[2]);
  if (hf == kNone) return false;
  for (HalfFace side : {hf, mesh.adjacent(hf)}) {
    const HalfFace other = mesh.adjacent(side);
    const TetId t = hf_tet(side);
    if (mesh.vertex(t, hf_face(side)) != opposite || mesh.opposite(other) != f.apex) continue;
    f.t = t;
    f.face = hf_face(side);
    for (int k = 0; k < 4; ++k) f.verts[k] = mesh.vertex(t, k);
    return true;
  }
  return false;
}

bool still_present(const TetMesh& mesh, const Found& f) {
  if (f.t >= mesh.num_tet_slots() || mesh.is_dead(f.t)) return false;
  for (int k = 0; k < 4; ++k)
    if (mesh.vertex(f.t, k) != f.verts[k]) return false;
  const HalfFace hf = mesh.adjacent(make_hf(f.t, f.face));
  return mesh.opposite(hf) == f.apex;
}

// ---------------------------------------------------------------------------
// Encroachment index: the diametral balls of the subsegments and the
// equatorial balls of the subfaces, by the bounding boxes of the balls in a
// hierarchy of uniform grids (level L has cells of size h * 2^L; a ball goes
// to the finest level where its box spans at most 2 cells per axis, so at
// most 8 cells). A sorted (cell, item) array holds the items of the first
// build, a hash map the items added later (looked up, never iterated).
// Items are never removed; the caller skips the ones that are no longer
// current (see DegeneracyRemoval::encroached_by). Queries return sorted item
// ids, so nothing depends on hash-map order.
// ---------------------------------------------------------------------------

struct Ball {
  VertexId v[3];     // subsegment: v[2] == kNone
  uint32_t owner;    // input segment or facet
  uint32_t version;  // subfaces: the facet's triangulation version
  Vec3 center;
  double radius;
};

class BallIndex {
 public:
  void build(std::vector<Ball>&& balls);
  void add(const Ball& b);
  // Items whose box may contain p (sorted, unique).
  void query(Vec3 p, std::vector<uint32_t>& out) const;
  const Ball& ball(uint32_t i) const { return balls_[i]; }
  bool built() const { return built_; }

 private:
  static constexpr int kLevels = 48;
  static constexpr int64_t kOffset = int64_t(1) << 18;  // cell coordinates in [0, 2^19)
  bool cell_of(Vec3 p, int level, int64_t c[3]) const;
  static uint64_t key(int level, const int64_t c[3]) {
    return (static_cast<uint64_t>(level) << 57) | (static_cast<uint64_t>(c[0]) << 38) |
           (static_cast<uint64_t>(c[1]) << 19) | static_cast<uint64_t>(c[2]);
  }
  // Keys of the cells of item i's box; false when the box is not finite.
  bool keys(uint32_t i, std::vector<uint64_t>& out) const;

  bool built_ = false;
  std::vector<Ball> balls_;
  std::vector<std::pair<uint64_t, uint32_t>> cells_;
  std::unordered_map<uint64_t, std::vector<uint32_t>> overlay_;  // lookup only
  std::vector<uint32_t> big_;  // non-finite balls: candidates of every query
  uint64_t levels_used_ = 0;   // bit L: some item at level L
  Vec3 lo_{0, 0, 0};
  double h_ = 1;
  mutable std::vector<uint64_t> scratch_;
};

bool BallIndex::cell_of(Vec3 p, int level, int64_t c[3]) const {
  const double h = std::ldexp(h_, level);
  const double q[3] = {(p.x - lo_.x) / h, (p.y - lo_.y) / h, (p.z - lo_.z) / h};
  for (int d = 0; d < 3; ++d) {
    const double f = std::floor(q[d]) + static_cast<double>(kOffset);
    if (!(f >= 0 && f < static_cast<double>(2 * kOffset))) return false;
    c[d] = static_cast<int64_t>(f);
  }
  return true;
}

bool BallIndex::keys(uint32_t i, std::vector<uint64_t>& out) const {
  out.clear();
  const Ball& b = balls_[i];
  const double r = b.radius * (1 + kBallSlack) + kTinyLength;
  if (!std::isfinite(r) || !finite(b.center)) return false;
  int level = 0;
  while (level < kLevels - 1 && std::ldexp(h_, level) < 2 * r) ++level;
  for (; level < kLevels; ++level) {
    int64_t c0[3], c1[3];
    if (!cell_of(b.center - Vec3{r, r, r}, level, c0) ||
        !cell_of(b.center + Vec3{r, r, r}, level, c1))
      continue;
    if ((c1[0] - c0[0] + 1) * (c1[1] - c0[1] + 1) * (c1[2] - c0[2] + 1) > 8) continue;
    int64_t c[3];
    for (c[0] = c0[0]; c[0] <= c1[0]; ++c[0])
      for (c[1] = c0[1]; c[1] <= c1[1]; ++c[1])
        for (c[2] = c0[2]; c[2] <= c1[2]; ++c[2]) out.push_back(key(level, c));
    return true;
  }
  return false;
}

void BallIndex::build(std::vector<Ball>&& balls) {
  built_ = true;
  balls_ = std::move(balls);
  cells_.clear();
  overlay_.clear();
  big_.clear();
  levels_used_ = 0;
  // Finest cell size: twice the median radius; coarser levels double it.
  std::vector<double> radii;
  Vec3 lo = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const Ball& b : balls_) {
    if (!std::isfinite(b.radius) || !finite(b.center)) continue;
    radii.push_back(b.radius);
    lo = {std::min(lo.x, b.center.x), std::min(lo.y, b.center.y), std::min(lo.z, b.center.z)};
    hi = {std::max(hi.x, b.center.x), std::max(hi.y, b.center.y), std::max(hi.z, b.center.z)};
  }
  if (!radii.empty()) {
    std::nth_element(radii.begin(), radii.begin() + radii.size() / 2, radii.end());
    const double extent = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    h_ = std::max(2 * radii[radii.size() / 2], extent * 0x1.0p-17);
    if (!(h_ > 0) || !std::isfinite(h_)) h_ = 1;
    lo_ = lo;
  }
  for (uint32_t i = 0; i < balls_.size(); ++i) {
    if (!keys(i, scratch_)) {
      big_.push_back(i);
      continue;
    }
    levels_used_ |= uint64_t(1) << (scratch_[0] >> 57);
    for (uint64_t k : scratch_) cells_.push_back({k, i});
  }
  std::sort(cells_.begin(), cells_.end());
}

void BallIndex::add(const Ball& b) {
  const uint32_t i = static_cast<uint32_t>(balls_.size());
  balls_.push_back(b);
  if (!keys(i, scratch_)) {
    big_.push_back(i);
    return;
  }
  levels_used_ |= uint64_t(1) << (scratch_[0] >> 57);
  for (uint64_t k : scratch_) overlay_[k].push_back(i);
}

void BallIndex::query(Vec3 p, std::vector<uint32_t>& out) const {
  out.assign(big_.begin(), big_.end());
  for (int level = 0; level < kLevels; ++level) {
    if (!(levels_used_ >> level & 1)) continue;
    int64_t c[3];
    if (!cell_of(p, level, c)) continue;
    const uint64_t k = key(level, c);
    auto it = std::lower_bound(cells_.begin(), cells_.end(), std::make_pair(k, uint32_t(0)));
    for (; it != cells_.end() && it->first == k; ++it) out.push_back(it->second);
    auto o = overlay_.find(k);
    if (o != overlay_.end()) out.insert(out.end(), o->second.begin(), o->second.end());
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

Ball segment_ball(const TetMesh& mesh, VertexId a, VertexId b, uint32_t s) {
  const Vec3 pa = to_vec(mesh.point(a)), pb = to_vec(mesh.point(b));
  return {{a, b, kNone}, s, 0, 0.5 * (pa + pb), 0.5 * norm(pb - pa)};
}

Ball subface_ball(const TetMesh& mesh, const std::array<VertexId, 3>& tri, uint32_t f,
                  uint32_t version) {
  const Vec3 a = to_vec(mesh.point(tri[0])), b = to_vec(mesh.point(tri[1])),
             c = to_vec(mesh.point(tri[2]));
  const Vec3 o = circle_center(a, b, c);
  const double r = std::max({norm(a - o), norm(b - o), norm(c - o)});
  return {{tri[0], tri[1], tri[2]}, f, version, o, r};
}

// ---------------------------------------------------------------------------
// The removal
// ---------------------------------------------------------------------------

class DegeneracyRemoval {
 public:
  DegeneracyRemoval(const Plc& plc, TetMesh& mesh, SegmentSet& segs,
                    std::vector<std::vector<VertexId>>& facet_interior,
                    std::vector<VertexId>& volume_points, DegeneracyStats& stats)
      : plc_(plc),
        mesh_(mesh),
        segs_(segs),
        facet_interior_(facet_interior),
        volume_points_(volume_points),
        stats_(stats),
        inserter_(mesh, 0x6465676e72617465ull),
        draw_(0x62726b7074733364ull),
        walk_(0x77616c6b64656731ull) {}

  Status run(const volatile bool* cancel);

 private:
  enum class Outcome { Broken, Protected, Deferred, Skipped };

  Status handle(const Found& f, bool force, Outcome& outcome);
  bool probe(const double* p, TetId hint);
  bool new_pair_degenerate(const double* p, const VertexId q[4]) const;
  bool strictly_breaks(const Found& f, const double* p) const;
  bool nudge_to_break(const Found& f, Vec3 dir, double xyz[3]) const;

  // Segment-safe perturbation (§6).
  Status try_perturb(const Found& f, bool& done);
  bool remove_vertex(VertexId v, std::vector<TetId>& created);
  bool move_vertex(VertexId v, const double* to, bool& undone);
  bool face_degenerate(TetId t, int i) const;
  void subsegments_at(VertexId u, std::vector<std::array<VertexId, 2>>& out);

  void init_topology();
  void mark_dirty(uint32_t f) {
    if (!facet_dirty_[f]) facet_dirty_[f] = 1, dirty_list_.push_back(f);
  }
  Status ensure_index();
  Status refresh_facets();
  bool encroached_by(const double* p, bool segments_only, std::vector<uint32_t>& out);
  bool encroaches(const Ball& b, const double* p) const;
  bool crossed_subsegment(uint32_t facet, Vec3 from, const double* to,
                          std::array<uint32_t, 3>& hit);

  Status protect(const std::vector<uint32_t>& encroached, const Found& f, const Vec3* plane,
                 bool& did_something);
  Status split_subsegment(uint32_t s, VertexId a, VertexId b, TetId hint);
  Status insert_facet_point(uint32_t facet, const double* xyz, TetId hint);
  bool is_subsegment(uint32_t s, VertexId a, VertexId b) const;
  double uniform() { return static_cast<double>(draw_.next() >> 11) * 0x1.0p-52 - 1.0; }
  // Two draws in a fixed order: the operands of `uniform() * a + uniform() * b`
  // are evaluated in an unspecified order (g++ and clang differ), which would
  // make native and WebAssembly runs diverge.
  Vec3 uniform_in_plane(Vec3 a, Vec3 b) {
    const double s = uniform();
    const double t = uniform();
    return s * a + t * b;
  }

  const Plc& plc_;
  TetMesh& mesh_;
  SegmentSet& segs_;
  std::vector<std::vector<VertexId>>& facet_interior_;
  std::vector<VertexId>& volume_points_;
  DegeneracyStats& stats_;
  PointInserter inserter_;
  Rng draw_;  // break point and protection point perturbations
  Rng walk_;  // point location in probe(), apart from the inserter's walks

  // Facets and segments, built on first need (models without degeneracies
  // never pay for them).
  bool topology_ = false;
  std::vector<std::vector<uint32_t>> seg_facets_;   // input segment -> facets having it as a loop edge
  std::vector<std::vector<uint32_t>> facet_segs_;   // facet -> its loop edges' input segments
  std::vector<uint8_t> facet_drop_;                 // per facet: axis dropped for 2D tests
  std::vector<Vec3> facet_normal_;                  // per facet: Newell normal (not unit)
  std::vector<uint32_t> vseg_start_, vseg_;         // input vertex -> input segments (CSR)
  std::vector<uint32_t> facet_of_;                  // per vertex: facet of a Steiner vertex inside it
  std::vector<uint8_t> facet_dirty_;                // triangulation out of date
  std::vector<uint32_t> dirty_list_;                // the facets with facet_dirty_ set
  bool chains_changed_ = false;                     // segment recovery ran since the last scan
  std::vector<uint32_t> facet_version_;             // bumped at each retriangulation
  std::vector<size_t> chain_size_;                  // chain sizes the index knows
  BallIndex index_;
  Plc scratch_plc_;  // the PLC's points with only the facets to retriangulate

  // Perturbation scratch.
  VertexRemover remover_{mesh_};
  std::vector<TetId> created_;
  std::vector<VertexId> nbrs_;
  std::vector<std::array<VertexId, 2>> pairs_;

  // probe() scratch.
  std::vector<std::array<VertexId, 4>> faces_;  // boundary face (3) + vertex beyond
  std::vector<std::array<VertexId, 3>> edges_;  // (lo, hi, third)
  std::vector<uint32_t> cand_;
  size_t point_budget_ = 0;
  size_t added_ = 0;
};

// Five points of two new tets sharing a face at p: p and q[0..3], where at
// most one q is kInfinite (then the pair is two hull faces through p).
bool DegeneracyRemoval::new_pair_degenerate(const double* p, const VertexId q[4]) const {
  const double* f[4];
  int n = 0;
  for (int i = 0; i < 4; ++i)
    if (q[i] != kInfinite) f[n++] = mesh_.point(q[i]);
  if (n == 3) {
    const double* r[4] = {f[0], f[1], f[2], p};
    return coplanar_cocircular(r);
  }
  // Four coplanar old vertices: either they are co-circular, an old
  // degeneracy a later round breaks in their plane, or p would be in their
  // plane and the new tets flat, which probe() rejects by orientation.
  if (pred::orient3d(f[0], f[1], f[2], f[3]) == 0) return false;
  return pred::insphere(f[0], f[1], f[2], f[3], p) == 0;
}

// Dry run of the Bowyer–Watson insertion of p (§6: "it is important that v_b
// should not create a new local degeneracy with other existing vertices. This
// can be checked before inserting the point"). True when p can be inserted
// cleanly: p is not an existing vertex, no tet of the cavity or around it has
// p exactly on its circumsphere (so the perturbed insertion, where a new
// vertex counts as outside on ties, agrees with the exact one), no new tet is
// flat, and no two new tets sharing a face are co-spherical.
bool DegeneracyRemoval::probe(const double* p, TetId hint) {
  ProbeOptions exact;
  exact.walk = &walk_;
  exact.fail_on_tie = true;
  if (!inserter_.probe(p, hint, faces_, exact)) return false;
  // No new tet (a boundary face coned to p) is flat.
  for (const auto& f : faces_)
    if (f[0] != kInfinite && f[1] != kInfinite && f[2] != kInfinite &&
        pred::orient3d(mesh_.point(f[0]), mesh_.point(f[1]), mesh_.point(f[2]), p) == 0)
      return false;
  // Pairs of new tets: the two boundary faces at each boundary edge.
  edges_.clear();
  for (const auto& f : faces_)
    for (int k = 0; k < 3; ++k) {
      const VertexId a = f[k], b = f[(k + 1) % 3], c = f[(k + 2) % 3];
      edges_.push_back({std::min(a, b), std::max(a, b), c});
    }
  if (edges_.size() % 2 != 0) return false;
  std::sort(edges_.begin(), edges_.end());
  for (size_t k = 0; k + 1 < edges_.size(); k += 2) {
    if (edges_[k][0] != edges_[k + 1][0] || edges_[k][1] != edges_[k + 1][1]) return false;
    const VertexId q[4] = {edges_[k][0], edges_[k][1], edges_[k][2], edges_[k + 1][2]};
    if (new_pair_degenerate(p, q)) return false;
  }
  return true;
}

// p lies strictly inside the circumspheres of both tets of the degeneracy
// (both ghost tets of a hull degeneracy), so inserting p destroys both.
bool DegeneracyRemoval::strictly_breaks(const Found& f, const double* p) const {
  const TetId n = hf_tet(mesh_.adjacent(make_hf(f.t, f.face)));
  return conflict_sign(mesh_, f.t, p) > 0 && conflict_sign(mesh_, n, p) > 0;
}

// Moves xyz by a few ulps along +-dir until it strictly breaks f. Used for
// points meant to lie in the plane of four co-circular points: rounding puts
// them a rounding error off that plane, and when the fifth point is itself
// nearly in the plane, both spheres of f meet the plane's neighbourhood only
// in a lens a few ulps thick around the circle's disk. In exact arithmetic a
// point of the disk breaks f; the nudge restores that. The move is at most
// about 2^-30 of the coordinates' magnitude. False if no nudge works.
bool DegeneracyRemoval::nudge_to_break(const Found& f, Vec3 dir, double xyz[3]) const {
  if (strictly_breaks(f, xyz)) return true;
  const double len = norm(dir);
  if (!(len > 0) || !std::isfinite(len)) return false;
  const Vec3 v = to_vec(xyz), u = (1 / len) * dir;
  const double mag = std::max({std::fabs(v.x), std::fabs(v.y), std::fabs(v.z)});
  for (double step = mag * 0x1.0p-53; step <= mag * 0x1.0p-30; step *= 2)
    for (double sgn : {1.0, -1.0}) {
      const Vec3 x = v + (sgn * step) * u;
      const double cand[3] = {x.x, x.y, x.z};
      if (strictly_breaks(f, cand)) {
        xyz[0] = x.x, xyz[1] = x.y, xyz[2] = x.z;
        return true;
      }
    }
  return false;
}

bool DegeneracyRemoval::is_subsegment(uint32_t s, VertexId a, VertexId b) const {
  const long ia = segs_.chain_position(s, a), ib = segs_.chain_position(s, b);
  return ia >= 0 && ib >= 0 && (ia + 1 == ib || ib + 1 == ia);
}

// Which facets have which segments as loop edges (segs.input is sorted), and
// the axis each facet's 2D tests drop (largest component of Newell's normal).
void DegeneracyRemoval::init_topology() {
  topology_ = true;
  const size_t nf = plc_.facets.size();
  seg_facets_.assign(segs_.input.size(), {});
  facet_segs_.assign(nf, {});
  facet_drop_.assign(nf, 2);
  facet_normal_.assign(nf, Vec3{0, 0, 0});
  facet_dirty_.assign(nf, 1);
  dirty_list_.resize(nf);
  for (uint32_t f = 0; f < nf; ++f) dirty_list_[f] = f;
  facet_version_.assign(nf, 0);
  for (uint32_t f = 0; f < nf; ++f) {
    Vec3 n = {0, 0, 0};
    const Vec3 origin = to_vec(mesh_.point(plc_.facets[f].loops[0][0]));
    for (const auto& loop : plc_.facets[f].loops) {
      for (size_t k = 0; k < loop.size(); ++k) {
        const VertexId a = loop[k], b = loop[(k + 1) % loop.size()];
        n = n + cross(to_vec(mesh_.point(a)) - origin, to_vec(mesh_.point(b)) - origin);
        if (loop.size() < 2) continue;
        const std::array<VertexId, 2> key = {std::min(a, b), std::max(a, b)};
        auto it = std::lower_bound(segs_.input.begin(), segs_.input.end(), key);
        if (it == segs_.input.end() || *it != key) continue;
        const uint32_t s = static_cast<uint32_t>(it - segs_.input.begin());
        facet_segs_[f].push_back(s);
        if (seg_facets_[s].empty() || seg_facets_[s].back() != f) seg_facets_[s].push_back(f);
      }
    }
    std::sort(facet_segs_[f].begin(), facet_segs_[f].end());
    facet_segs_[f].erase(std::unique(facet_segs_[f].begin(), facet_segs_[f].end()), facet_segs_[f].end());
    facet_drop_[f] = static_cast<uint8_t>(largest_axis(n.x, n.y, n.z));
    facet_normal_[f] = n;
  }
  const size_t nv = segs_.acute.size();
  vseg_start_.assign(nv + 1, 0);
  for (const auto& e : segs_.input) ++vseg_start_[e[0] + 1], ++vseg_start_[e[1] + 1];
  for (size_t v = 0; v < nv; ++v) vseg_start_[v + 1] += vseg_start_[v];
  vseg_.resize(vseg_start_[nv]);
  std::vector<uint32_t> fill(vseg_start_.begin(), vseg_start_.end() - 1);
  for (uint32_t s = 0; s < segs_.input.size(); ++s)
    for (VertexId e : segs_.input[s]) vseg_[fill[e]++] = s;
  for (uint32_t f = 0; f < facet_interior_.size(); ++f)
    for (VertexId v : facet_interior_[f])
      if (v >= plc_.points.size()) {
        if (facet_of_.size() <= v) facet_of_.resize(v + 1, kNone);
        facet_of_[v] = f;
      }
}

// Subfaces of every dirty facet (all of them the first time), by
// triangulate_facets on a PLC holding only those facets; their equatorial
// balls join the index under the facet's new version.
Status DegeneracyRemoval::refresh_facets() {
  const size_t nf = plc_.facets.size();
  std::vector<uint32_t> dirty;
  dirty.swap(dirty_list_);
  std::sort(dirty.begin(), dirty.end());
  if (dirty.empty() && index_.built()) return {};
  Subfaces sub;
  Status st;
  if (dirty.size() == nf) {
    st = triangulate_facets(plc_, segs_, mesh_, facet_interior_, sub);
  } else {
    if (scratch_plc_.points.size() != plc_.points.size()) scratch_plc_.points = plc_.points;
    scratch_plc_.facets.clear();
    std::vector<std::vector<VertexId>> interior;
    for (uint32_t f : dirty) {
      scratch_plc_.facets.push_back(plc_.facets[f]);
      interior.push_back(facet_interior_[f]);
    }
    st = triangulate_facets(scratch_plc_, segs_, mesh_, interior, sub);
    for (uint32_t& f : sub.facet) f = dirty[f];
  }
  if (!st.ok()) return st;
  for (uint32_t f : dirty) {
    facet_dirty_[f] = 0;
    ++facet_version_[f];
  }
  if (!index_.built()) {
    std::vector<Ball> balls;
    for (uint32_t s = 0; s < segs_.chain.size(); ++s) {
      const auto& c = segs_.chain[s];
      for (size_t i = 0; i + 1 < c.size(); ++i) balls.push_back(segment_ball(mesh_, c[i], c[i + 1], s));
    }
    for (size_t k = 0; k < sub.tri.size(); ++k)
      balls.push_back(subface_ball(mesh_, sub.tri[k], sub.facet[k], facet_version_[sub.facet[k]]));
    index_.build(std::move(balls));
    chain_size_.resize(segs_.chain.size());
    for (size_t s = 0; s < segs_.chain.size(); ++s) chain_size_[s] = segs_.chain[s].size();
  } else {
    for (size_t k = 0; k < sub.tri.size(); ++k)
      index_.add(subface_ball(mesh_, sub.tri[k], sub.facet[k], facet_version_[sub.facet[k]]));
  }
  return {};
}

// Builds the index on first need; later, brings it up to date with the
// chains (segment recovery splits subsegments between rounds) and
// retriangulates the facets changed since the last call.
Status DegeneracyRemoval::ensure_index() {
  if (!topology_) init_topology();
  if (!index_.built()) return refresh_facets();
  if (chains_changed_) {
    chains_changed_ = false;
    for (uint32_t s = 0; s < segs_.chain.size(); ++s) {
      if (segs_.chain[s].size() == chain_size_[s]) continue;
      chain_size_[s] = segs_.chain[s].size();
      const auto& c = segs_.chain[s];
      // Old subsegments stay in the index; encroached_by skips them.
      for (size_t i = 0; i + 1 < c.size(); ++i) index_.add(segment_ball(mesh_, c[i], c[i + 1], s));
      for (uint32_t f : seg_facets_[s]) mark_dirty(f);
    }
  }
  return refresh_facets();
}

// Inside or on the diametral ball of a subsegment (exact), or the equatorial
// ball of a subface. The subface test is in floating point with a relative
// margin that errs towards "encroached": a false positive only adds a
// protection point, and the points that matter (break points in a facet's
// plane, near its center) are far inside the ball.
bool DegeneracyRemoval::encroaches(const Ball& b, const double* p) const {
  if (b.v[2] == kNone) return pred::dot_sign(mesh_.point(b.v[0]), p, mesh_.point(b.v[1])) <= 0;
  if (!std::isfinite(b.radius) || !finite(b.center)) return true;
  const Vec3 d = to_vec(p) - b.center;
  return dot(d, d) <= b.radius * b.radius * (1 + kBallSlack);
}

// The current subsegments (and, unless segments_only, subfaces) that p
// encroaches upon, as index ids. False when p encroaches a subface of a
// facet changed since its triangulation: such a facet is not trusted until
// it is retriangulated (the caller defers the decision to the next pass,
// which retriangulates every changed facet at once). A new subface's ball
// lies in the union of the balls it replaces and of the facet's
// subsegments' balls, so a point that encroaches a new subface also
// encroaches an old one (and is deferred) or a subsegment (always current:
// split subsegments are replaced in the index at once).
bool DegeneracyRemoval::encroached_by(const double* p, bool segments_only,
                                      std::vector<uint32_t>& out) {
  index_.query(to_vec(p), cand_);
  out.clear();
  for (uint32_t k : cand_) {
    const Ball& b = index_.ball(k);
    if (b.v[2] == kNone) {
      if (is_subsegment(b.owner, b.v[0], b.v[1]) && encroaches(b, p)) out.push_back(k);
      continue;
    }
    if (segments_only || b.version != facet_version_[b.owner] || !encroaches(b, p)) continue;
    if (facet_dirty_[b.owner]) return false;
    out.push_back(k);
  }
  return true;
}

// The first subsegment of the facet's loops crossed by the segment from
// `from` to `to` (projected along the facet's dropped axis; touching counts),
// nearest to `from`. Such a crossing means `to` lies outside the facet.
bool DegeneracyRemoval::crossed_subsegment(uint32_t facet, Vec3 from, const double* to,
                                           std::array<uint32_t, 3>& hit) {
  const int drop = facet_drop_[facet];
  const double g[3] = {from.x, from.y, from.z};
  double best = HUGE_VAL;
  for (uint32_t s : facet_segs_[facet]) {
    const auto& c = segs_.chain[s];
    for (size_t i = 0; i + 1 < c.size(); ++i) {
      const double *p = mesh_.point(c[i]), *q = mesh_.point(c[i + 1]);
      const int o1 = pred::orient2d_projected(p, q, g, drop), o2 = pred::orient2d_projected(p, q, to, drop);
      if (o1 * o2 > 0) continue;
      const int o3 = pred::orient2d_projected(g, to, p, drop), o4 = pred::orient2d_projected(g, to, q, drop);
      if (o3 * o4 > 0 || (o1 == 0 && o2 == 0)) continue;
      const double d = norm(0.5 * (to_vec(p) + to_vec(q)) - from);  // ranking only
      if (d < best) {
        best = d;
        hit = {s, c[i], c[i + 1]};
      }
    }
  }
  return best < HUGE_VAL;
}

// Splits subsegment (a, b) of input segment s at its perturbed midpoint (§6,
// boundary protection, step 1), as a Steiner vertex of the segment's chain.
//
// Rounding: the point is the segment's endpoints interpolated at parameter t
// and rounded to doubles, so it is near, not on, the segment's line. That is
// safe for the same reasons as in segment recovery: the SegmentVertex record
// and the chain order, not coordinates, say which vertices are on which
// segment, and the Delaunay insertion is exact on the rounded point.
Status DegeneracyRemoval::split_subsegment(uint32_t s, VertexId a, VertexId b, TetId hint) {
  if (segs_.chain_position(s, a) > segs_.chain_position(s, b)) std::swap(a, b);
  const double ta = segs_.param(s, a), tb = segs_.param(s, b);
  const Vec3 p0 = to_vec(mesh_.point(segs_.input[s][0])),
             p1 = to_vec(mesh_.point(segs_.input[s][1]));
  const Vec3 pa = to_vec(mesh_.point(a)), pb = to_vec(mesh_.point(b));
  auto strictly_between = [&](Vec3 v) {
    return dot(v - pa, pb - pa) > 0 && dot(v - pb, pa - pb) > 0;
  };
  double t = 0;
  Vec3 v = {0, 0, 0};
  bool ok = false;
  for (int attempt = 0; attempt < kMaxDraws && !ok; ++attempt) {
    const double f = 0.5 + 0.5 * kRelativeJitter * uniform();
    t = ta + f * (tb - ta);
    v = p0 + t * (p1 - p0);
    if (!strictly_between(v)) {
      v = pa + f * (pb - pa);
      if (!strictly_between(v)) continue;
    }
    const double xyz[3] = {v.x, v.y, v.z};
    ok = probe(xyz, hint);
  }
  if (!ok) {
    // Every draw was rejected by the dry run (or the subsegment is a few ulps
    // long): use the plain midpoint; a degeneracy it creates is found and
    // broken by the next round.
    t = 0.5 * (ta + tb);
    v = 0.5 * (pa + pb);
    if (!strictly_between(v))
      return make_error(ErrorCode::LimitReached, "degeneracy removal: subsegment (" +
                                                     std::to_string(a) + ", " + std::to_string(b) +
                                                     ") of segment " + std::to_string(s) +
                                                     " is too short to split in double precision")
          .vertex(a)
          .segment(s);
  }
  const double xyz[3] = {v.x, v.y, v.z};
  InsertResult res;
  Status st = inserter_.insert_point(xyz, hint, kVertexSteiner, &res);
  if (!st.ok()) return st;
  if (res.duplicate)
    return make_error(ErrorCode::InvalidPlc, "degeneracy removal: vertex " +
                                                 std::to_string(res.vertex) + " lies on segment " +
                                                 std::to_string(s))
        .vertex(res.vertex)
        .segment(s);
  SegmentChain& chain = segs_.chain[s];
  chain.insert(chain.begin() + segs_.chain_position(s, b), res.vertex);
  if (segs_.steiner_of.size() <= res.vertex) segs_.steiner_of.resize(res.vertex + 1, kNone);
  segs_.steiner_of[res.vertex] = static_cast<uint32_t>(segs_.steiner.size());
  const VertexId s0 = segs_.input[s][0], s1 = segs_.input[s][1];
  const bool acute0 = segs_.acute[s0] != 0, acute1 = segs_.acute[s1] != 0;
  VertexId origin = kNone;
  if (acute0 && acute1) origin = t < 0.5 ? s0 : s1;
  else if (acute0) origin = s0;
  else if (acute1) origin = s1;
  segs_.steiner.push_back({res.vertex, s, t, origin, SplitRule::Protect});
  ++stats_.protect_segment;
  ++added_;
  // The two halves join the index; the facets around the segment change.
  index_.add(segment_ball(mesh_, a, res.vertex, s));
  index_.add(segment_ball(mesh_, res.vertex, b, s));
  chain_size_[s] = chain.size();
  for (uint32_t f : seg_facets_[s]) mark_dirty(f);
  return {};
}

// Inserts a protection point inside facet `facet` (§6, step 2) and records it
// in facet_interior.
Status DegeneracyRemoval::insert_facet_point(uint32_t facet, const double* xyz, TetId hint) {
  InsertResult res;
  Status st = inserter_.insert_point(xyz, hint, kVertexSteiner, &res);
  if (!st.ok()) return st;
  if (res.duplicate) return {};  // measure zero; the degeneracy stays queued
  facet_interior_[facet].push_back(res.vertex);
  if (facet_of_.size() <= res.vertex) facet_of_.resize(res.vertex + 1, kNone);
  facet_of_[res.vertex] = facet;
  mark_dirty(facet);
  ++stats_.protect_facet;
  ++added_;
  return {};
}

// Boundary protection (§6) for the encroached items (index ids):
// subsegments are split at their perturbed midpoints; each subface gets its
// perturbed circumcenter x, unless x encroaches upon subsegments (then those
// are split, §6 step 2) or x lies outside the facet (then the facet's
// boundary subsegment between the subface and x is split: x outside means the
// subface's circle reaches across that subsegment).
Status DegeneracyRemoval::protect(const std::vector<uint32_t>& encroached, const Found& deg,
                                  const Vec3* plane, bool& did_something) {
  const TetId hint = deg.t;
  std::vector<std::array<uint32_t, 3>> splits;  // (segment, a, b)
  std::vector<uint32_t> hits;
  for (uint32_t id : encroached) {
    const Ball b = index_.ball(id);
    if (b.v[2] == kNone) {
      splits.push_back({b.owner, b.v[0], b.v[1]});
      continue;
    }
    const uint32_t f = b.owner;
    if (b.version != facet_version_[f]) continue;  // already split in this call
    const Vec3 a = to_vec(mesh_.point(b.v[0])), bb = to_vec(mesh_.point(b.v[1])),
               c = to_vec(mesh_.point(b.v[2]));
    const Vec3 e1 = bb - a, n = cross(e1, c - a);
    if (!(norm(n) > 0)) continue;
    const Vec3 u = (1 / norm(e1)) * e1, w = (1 / norm(n)) * cross(n, e1);
    const Vec3 centroid = (1.0 / 3) * (a + bb + c);
    const bool circum = finite(b.center) && std::isfinite(b.radius);
    const Vec3 o = circum ? b.center : centroid;
    const double scale =
        kRelativeJitter * (circum ? b.radius : std::min({norm(e1), norm(c - a), norm(c - bb)}));
    for (int attempt = 0; attempt < kMaxDraws; ++attempt) {
      // Rounding: x is computed in the subface's plane and rounded to
      // doubles, so it lies near, not exactly on, the plane; the
      // facet_interior record, not its coordinates, makes it a vertex of the
      // facet for the later steps, and the insertion is exact on the
      // rounded point.
      const Vec3 x = o + scale * uniform_in_plane(u, w);
      double xyz[3] = {x.x, x.y, x.z};
      encroached_by(xyz, true, hits);
      if (!hits.empty()) {
        for (uint32_t k : hits) splits.push_back({index_.ball(k).owner, index_.ball(k).v[0], index_.ball(k).v[1]});
        break;
      }
      std::array<uint32_t, 3> cross_hit;
      if (crossed_subsegment(f, centroid, xyz, cross_hit)) {
        splits.push_back(cross_hit);
        break;
      }
      // In the plane of a co-circular degeneracy (the facet's plane, up to
      // rounding), x should break it as it would in exact arithmetic.
      if (plane) nudge_to_break(deg, *plane, xyz);
      if (!probe(xyz, hint)) continue;
      Status st = insert_facet_point(f, xyz, hint);
      if (!st.ok()) return st;
      did_something = true;
      break;
    }
  }
  std::sort(splits.begin(), splits.end());
  splits.erase(std::unique(splits.begin(), splits.end()), splits.end());
  for (const auto& sp : splits) {
    if (!is_subsegment(sp[0], sp[1], sp[2])) continue;
    Status st = split_subsegment(sp[0], sp[1], sp[2], mesh_.vtet[sp[1]]);
    if (!st.ok()) return st;
    did_something = true;
  }
  return {};
}

// Whether the tets on both sides of face i of t form a local degeneracy (the
// test of collect()).
bool DegeneracyRemoval::face_degenerate(TetId t, int i) const {
  const VertexId* w = mesh_.tet_vertices(t);
  const HalfFace hf = mesh_.adjacent(make_hf(t, i));
  const TetId n = hf_tet(hf);
  const VertexId e = mesh_.vertex(n, hf_face(hf));
  const bool ghost = w[3] == kInfinite, n_ghost = mesh_.is_ghost(n);
  if (!ghost && !n_ghost)
    return pred::insphere(mesh_.point(w[0]), mesh_.point(w[1]), mesh_.point(w[2]), mesh_.point(w[3]),
                          mesh_.point(e)) == 0;
  if (ghost && n_ghost && i < 3) {
    const double* q[4] = {mesh_.point(w[0]), mesh_.point(w[1]), mesh_.point(w[2]), mesh_.point(e)};
    return coplanar_cocircular(q);
  }
  return false;
}

// The subsegments at vertex u, as (u, neighbour) pairs.
void DegeneracyRemoval::subsegments_at(VertexId u, std::vector<std::array<VertexId, 2>>& out) {
  auto add = [&](uint32_t s) {
    const long i = segs_.chain_position(s, u);
    if (i < 0) return;
    const auto& c = segs_.chain[s];
    if (i > 0) out.push_back({u, c[i - 1]});
    if (i + 1 < static_cast<long>(c.size())) out.push_back({u, c[i + 1]});
  };
  if (const SegmentVertex* sv = segs_.on_segment(u)) {
    add(sv->segment);
  } else if (u + 1 < vseg_start_.size()) {
    for (uint32_t k = vseg_start_[u]; k < vseg_start_[u + 1]; ++k) add(vseg_[k]);
  }
}

// Removes interior vertex v from the Delaunay tetrahedralization
// (VertexRemover); false, changing nothing, for a hull vertex.
bool DegeneracyRemoval::remove_vertex(VertexId v, std::vector<TetId>& created) {
  return remover_.remove(v, &created);
}

// Moves Steiner vertex v to `to`: removal, then Bowyer–Watson reinsertion.
// The move is kept only when it is clean: the dry run accepts `to`, no
// local degeneracy appears among the tets the move created, and every
// subsegment at the old or new neighbours of v that was an edge still is
// one (segment-safe, §6). Otherwise v goes back (removal and reinsertion at
// its old place give back the same Delaunay tetrahedralization, which is
// unique under the perturbation). False when v could not be removed (mesh
// unchanged) or the move was undone.
bool DegeneracyRemoval::move_vertex(VertexId v, const double* to, bool& undone) {
  undone = false;
  const double from[3] = {mesh_.point(v)[0], mesh_.point(v)[1], mesh_.point(v)[2]};
  const uint8_t kind = mesh_.vkind[v];
  // Subsegments at v and its neighbours that are edges now.
  mesh_.vertex_neighbors(v, nbrs_);
  pairs_.clear();
  subsegments_at(v, pairs_);
  for (VertexId u : nbrs_) subsegments_at(u, pairs_);
  if (!remove_vertex(v, created_)) return false;
  auto put_back = [&]() {
    std::copy(from, from + 3, &mesh_.coords[3 * size_t(v)]);
    InsertResult res;
    const bool ok = inserter_.insert_vertex(v, created_.empty() ? kNone : created_[0], &res).ok() &&
                    !res.duplicate;
    mesh_.vkind[v] = kind;
    return ok;
  };
  std::vector<std::array<VertexId, 2>> required;
  for (const auto& e : pairs_)
    if (e[0] == v || e[1] == v || mesh_.find_edge(e[0], e[1]) != kNone) required.push_back(e);
  std::copy(to, to + 3, &mesh_.coords[3 * size_t(v)]);
  if (!probe(to, created_.empty() ? kNone : created_[0])) {
    undone = true;
    put_back();
    return false;
  }
  // The new neighbours' subsegments (edges now, v being absent).
  for (const auto& f : faces_)
    for (int k = 0; k < 4; ++k) {
      const VertexId u = f[k];
      if (u == kInfinite || std::binary_search(nbrs_.begin(), nbrs_.end(), u)) continue;
      pairs_.clear();
      subsegments_at(u, pairs_);
      for (const auto& e : pairs_)
        if (e[1] != v && mesh_.find_edge(e[0], e[1]) != kNone) required.push_back(e);
    }
  InsertResult res;
  if (!inserter_.insert_vertex(v, created_[0], &res).ok() || res.duplicate) {
    undone = true;
    put_back();
    return false;
  }
  mesh_.vkind[v] = kind;
  bool clean = true;
  for (const auto& e : required)
    if (mesh_.find_edge(e[0], e[1]) == kNone) clean = false;
  std::vector<TetId> touched = created_;
  touched.insert(touched.end(), inserter_.new_tets().begin(), inserter_.new_tets().end());
  for (TetId t : touched) {
    if (!clean) break;
    if (mesh_.is_dead(t)) continue;
    for (int i = 0; i < 4 && clean; ++i) clean = !face_degenerate(t, i);
  }
  if (clean) return true;
  // Undo: remove v from its new place and put it back. Should the removal
  // fail, v stays moved: the mesh is still Delaunay, the end of the round
  // recovers any lost subsegment and the next round sees any degeneracy.
  if (!remove_vertex(v, created_)) return true;
  undone = true;
  put_back();
  return false;
}

// §6: a degeneracy is removable when one of its vertices is perturbable and
// a segment-safe perturbation of it exists. In cdt3d input vertices never
// move (the output keeps every input point exactly); Steiner vertices on a
// segment move along it (a new parameter strictly between their chain
// neighbours', the point interpolated from the segment's endpoints) and
// Steiner vertices inside a facet move in its plane, staying inside it. A few
// random moves of relative size 1e-3 are tried per vertex, smallest id first.
// Rounding: the moved point is rounded to doubles as every Steiner point is
// (see split_subsegment and insert_facet_point).
Status DegeneracyRemoval::try_perturb(const Found& f, bool& done) {
  done = false;
  constexpr int kMoves = 3;
  for (VertexId v : f.ids) {
    if (v == kInfinite || v < plc_.points.size()) continue;
    const SegmentVertex* sv = segs_.on_segment(v);
    const uint32_t facet = v < facet_of_.size() ? facet_of_[v] : kNone;
    if (!sv && facet == kNone) continue;
    if (!topology_) init_topology();
    for (int attempt = 0; attempt < kMoves; ++attempt) {
      double to[3];
      double t = 0;
      if (sv) {
        const uint32_t s = sv->segment;
        const long i = segs_.chain_position(s, v);
        if (i <= 0 || i + 1 >= static_cast<long>(segs_.chain[s].size())) break;
        const VertexId a = segs_.chain[s][i - 1], b = segs_.chain[s][i + 1];
        const double ta = segs_.param(s, a), tb = segs_.param(s, b);
        const double room = std::min(sv->t - ta, tb - sv->t);
        t = sv->t + kRelativeJitter * room * uniform();
        if (!(t > ta && t < tb)) continue;
        const Vec3 p0 = to_vec(mesh_.point(segs_.input[s][0])),
                   p1 = to_vec(mesh_.point(segs_.input[s][1]));
        const Vec3 x = p0 + t * (p1 - p0), pa = to_vec(mesh_.point(a)), pb = to_vec(mesh_.point(b));
        if (!(dot(x - pa, pb - pa) > 0 && dot(x - pb, pa - pb) > 0)) continue;
        to[0] = x.x, to[1] = x.y, to[2] = x.z;
      } else {
        const Vec3 n = facet_normal_[facet];
        if (!(norm(n) > 0)) break;
        const Vec3 p = to_vec(mesh_.point(v));
        // Distance to the nearest neighbour sets the move's scale.
        mesh_.vertex_neighbors(v, nbrs_);
        double near = HUGE_VAL;
        for (VertexId u : nbrs_) near = std::min(near, norm(to_vec(mesh_.point(u)) - p));
        if (!std::isfinite(near)) break;
        const Vec3 e1 = cross(n, std::fabs(n.x) < std::fabs(n.z) ? Vec3{1, 0, 0} : Vec3{0, 0, 1});
        const Vec3 u1 = (1 / norm(e1)) * e1, u2 = (1 / norm(cross(n, u1))) * cross(n, u1);
        const Vec3 x = p + (kRelativeJitter * near) * uniform_in_plane(u1, u2);
        to[0] = x.x, to[1] = x.y, to[2] = x.z;
        std::array<uint32_t, 3> hit;
        if (!std::isfinite(to[0]) || crossed_subsegment(facet, p, to, hit)) continue;
      }
      bool undone = false;
      if (!move_vertex(v, to, undone)) {
        if (!undone) break;  // v cannot be removed (hull vertex)
        continue;
      }
      if (sv) {
        segs_.steiner[segs_.steiner_of[v]].t = t;
        if (index_.built()) {
          const uint32_t s = sv->segment;
          const long i = segs_.chain_position(s, v);
          index_.add(segment_ball(mesh_, segs_.chain[s][i - 1], v, s));
          index_.add(segment_ball(mesh_, v, segs_.chain[s][i + 1], s));
        }
        for (uint32_t g : seg_facets_[sv->segment]) mark_dirty(g);
      } else {
        mark_dirty(facet);
      }
      ++stats_.perturbations;
      done = true;
      return {};
    }
  }
  return {};
}

// One degeneracy: choose a break point v_b (§6) and insert it, or protect the
// boundary it encroaches upon.
Status DegeneracyRemoval::handle(const Found& f, bool force, Outcome& outcome) {
  outcome = Outcome::Skipped;
  const bool hull = f.ids[4] == kInfinite;
  const int np = hull ? 4 : 5;
  Vec3 pts[5];
  for (int k = 0; k < np; ++k) pts[k] = to_vec(mesh_.point(f.ids[k]));

  // Four coplanar (hence co-circular) points? Then v_b goes in their plane.
  int skip = -1;
  if (hull) {
    skip = 4;
  } else {
    for (int k = 4; k >= 0 && skip < 0; --k) {
      const double* q[4];
      int m = 0;
      for (int j = 0; j < 5; ++j)
        if (j != k) q[m++] = mesh_.point(f.ids[j]);
      if (pred::orient3d(q[0], q[1], q[2], q[3]) == 0) skip = k;
    }
  }
  Vec3 center = {0, 0, 0}, e1 = {0, 0, 0}, e2 = {0, 0, 0}, normal = {0, 0, 0}, centroid = {0, 0, 0};
  double diam = 0;
  for (int k = 0; k < np; ++k)
    for (int j = k + 1; j < np; ++j) diam = std::max(diam, norm(pts[k] - pts[j]));
  if (skip >= 0) {
    Vec3 plane[4];
    int m = 0;
    for (int k = 0; k < np; ++k)
      if (k != skip) plane[m++] = pts[k];
    // The circle through the non-collinear triple with the largest normal.
    double best = -1;
    for (int k = 0; k < 4; ++k) {
      Vec3 tri[3];
      int j3 = 0;
      for (int j = 0; j < 4; ++j)
        if (j != k) tri[j3++] = plane[j];
      const Vec3 n = cross(tri[1] - tri[0], tri[2] - tri[0]);
      if (norm(n) > best) {
        best = norm(n);
        normal = n;
        center = circle_center(tri[0], tri[1], tri[2]);
      }
    }
    for (int k = 0; k < 4; ++k) centroid = centroid + 0.25 * plane[k];
    const Vec3 d = plane[1] - plane[0];
    e1 = (1 / norm(d)) * d;
    e2 = (1 / norm(normal)) * cross(normal, e1);
  } else {
    center = sphere_center(pts[0], pts[1], pts[2], pts[3]);
    if (!finite(center)) center = sphere_center(pts[1], pts[2], pts[3], pts[4]);
    for (int k = 0; k < 5; ++k) centroid = centroid + 0.2 * pts[k];
  }
  const bool center_ok = finite(center) && norm(center - centroid) <= kMaxCenterDistance * diam;
  // The index is brought up to date once per pass (run); here it is only
  // built on first need.
  Status st;
  if (!index_.built()) st = ensure_index();
  if (!st.ok()) return st;

  std::vector<uint32_t> encroached;
  for (int attempt = 0; attempt < kMaxDraws; ++attempt) {
    // The circumcenter first; the centroid (strictly inside the sphere) if
    // the circumcenter is far away or does not work out.
    const bool use_center = center_ok && attempt < kMaxDraws / 2;
    const Vec3 base = use_center ? center : centroid;
    const double radius = use_center ? norm(center - pts[0]) : 0.25 * diam;
    const double scale = kRelativeJitter * radius / (1 << std::min(attempt % 12, 8));
    Vec3 v = skip >= 0 ? base + scale * uniform_in_plane(e1, e2)
                       : base + scale * Vec3{uniform(), uniform(), uniform()};
    // Rounding: v is rounded to doubles. A point meant to be in the plane of
    // four co-circular points is then a rounding error off it; that is fine
    // because every decision below is exact on the rounded point: it must lie
    // strictly inside both spheres (a hull point: strictly beyond the hull
    // plane, or in it inside the circle), and the dry run rejects every new
    // co-spherical set. A point meant for the plane that misses both spheres
    // by its rounding is nudged by a few ulps (nudge_to_break).
    double xyz[3] = {v.x, v.y, v.z};
    if (skip >= 0) nudge_to_break(f, normal, xyz);
    if (!strictly_breaks(f, xyz)) continue;
    // Encroachment (§6): v_b must not lie in the diametral ball of a
    // subsegment nor in the equatorial ball of a subface.
    if (!encroached_by(xyz, force, encroached)) {
      outcome = Outcome::Deferred;
      return {};
    }
    if (!encroached.empty()) {
      bool did = false;
      st = protect(encroached, f, skip >= 0 ? &normal : nullptr, did);
      if (!st.ok()) return st;
      outcome = did ? Outcome::Protected : Outcome::Skipped;
      return {};
    }
    if (!probe(xyz, f.t)) continue;
    InsertResult res;
    st = inserter_.insert_point(xyz, f.t, kVertexSteiner, &res);
    if (!st.ok()) return st;
    if (res.duplicate) return {};
    volume_points_.push_back(res.vertex);
    ++stats_.break_points;
    ++added_;
    outcome = Outcome::Broken;
    return {};
  }
  return {};  // every draw failed: tried again next round
}

Status DegeneracyRemoval::run(const volatile bool* cancel) {
  if (facet_interior_.size() < plc_.facets.size()) facet_interior_.resize(plc_.facets.size());
  point_budget_ = kPointsPerVertex * mesh_.num_vertices() + kPointsBase;
  // A degeneracy whose break point asked for protection is tried again (§6:
  // "push Δ into Q") in the next pass of the same round, up to kRetries
  // times. From the kForceAfter-th try on, subfaces no longer stop its break
  // point (only subsegments do): protection converges when v_b lies in a
  // facet (the facet's protection points then break the degeneracy
  // themselves) or away from it, but not when the facet is nearly, not
  // exactly, coplanar with the degeneracy's circle (CAD data with rounded
  // coordinates): v_b then stays within a rounding-sized distance of the
  // facet and the subfaces near it keep encroaching. A break point near a
  // facet costs flat tets, not correctness: Theorem 2 asks for no local
  // degeneracy and every subsegment present, nothing about subfaces.
  constexpr int kRetries = 16, kForceAfter = 8, kMaxPasses = 2 * kRetries + 8;
  auto cancelled = [&]() { return cancel && *cancel; };
  const Status cancelled_status = make_error(ErrorCode::Cancelled, "degeneracy removal cancelled");

  std::vector<Found> queue, pending, next;
  for (size_t round = 0;; ++round) {
    collect(mesh_, queue);
    if (round == 0) stats_.initial = queue.size();
    if (queue.empty()) return {};
    if (round >= kMaxRounds || added_ > point_budget_) {
      const VertexId v = queue.front().ids[0];
      return make_error(ErrorCode::LimitReached,
                        "degeneracy removal: " + std::to_string(queue.size()) +
                            " local degeneracies remain after " + std::to_string(round) +
                            " rounds and " + std::to_string(added_) +
                            " added points (one at vertex " + std::to_string(v) + ")")
          .vertex(v);
    }
    ++stats_.rounds;
    // Removable degeneracies first: a segment-safe perturbation.
    pending.clear();
    for (Found& f : queue) {
      if (cancelled()) return cancelled_status;
      if (!still_present(mesh_, f)) continue;
      bool moved = false;
      Status st = try_perturb(f, moved);
      if (!st.ok()) return st;
      if (moved || (!still_present(mesh_, f) && !relocate(mesh_, f))) continue;
      pending.push_back(f);
    }
    // The others: break points, or boundary protection and another try.
    // Each pass starts with the index up to date (one retriangulation of
    // every facet changed by the previous pass).
    for (int pass = 0; !pending.empty() && pass < kMaxPasses; ++pass) {
      if (index_.built()) {
        Status st = ensure_index();
        if (!st.ok()) return st;
      }
      next.clear();
      for (Found& f : pending) {
        if (cancelled()) return cancelled_status;
        if (added_ > point_budget_) break;
        if (!still_present(mesh_, f)) continue;
        Outcome outcome;
        Status st = handle(f, f.tries >= kForceAfter, outcome);
        if (!st.ok()) return st;
        if (outcome == Outcome::Deferred) next.push_back(f);
        if (outcome == Outcome::Protected && ++f.tries < kRetries) next.push_back(f);
      }
      pending.swap(next);
    }
    // Break points and protection points may have destroyed subsegments:
    // recover them (§6, protection step 3).
    SegmentRecoveryStats rs;
    Status st = recover_segments(mesh_, segs_, &rs, cancel, SplitMode::Rules);
    if (!st.ok()) return st;
    stats_.resplit += rs.points();
    added_ += rs.points();
    chains_changed_ = true;
  }
}

}  // namespace

void find_local_degeneracies(const TetMesh& mesh, std::vector<LocalDegeneracy>& out) {
  std::vector<Found> found;
  collect(mesh, found);
  out.clear();
  out.reserve(found.size());
  for (const Found& f : found) out.push_back(f.ids);
}

// §6 as published: each round perturbs what it can (a perturbable Steiner
// vertex moved segment-safely), then removes the rest by break points, or by
// the boundary protection a break point asks for (DegeneracyRemoval::run).
Status remove_local_degeneracies(const Plc& plc, TetMesh& mesh, SegmentSet& segs,
                                 std::vector<std::vector<VertexId>>& facet_interior,
                                 std::vector<VertexId>& volume_points, DegeneracyStats* stats,
                                 const volatile bool* cancel) {
  DegeneracyStats local;
  DegeneracyStats& st = stats ? *stats : local;
  st = DegeneracyStats();
  DegeneracyRemoval removal(plc, mesh, segs, facet_interior, volume_points, st);
  return removal.run(cancel);
}

}  // namespace cdt3d
