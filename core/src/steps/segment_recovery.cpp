// Step 2: Delaunay segment recovery (Si & Gärtner 2005 §5).
#include "segment_recovery.hpp"

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_set>

#include "delaunay.hpp"
#include "geometry.hpp"
#include "point_index.hpp"
#include "predicates.hpp"
#include "status.hpp"
#include "vertex_removal.hpp"

namespace cdt3d {

namespace {

// A split bound: no input segment of a valid PLC needs anywhere near this many
// points in practice (Theorem 3 bounds subsegment lengths from below by the
// local feature size); reaching it means rounding or invalid input made the
// loop cycle, and we stop with an error instead of looping forever.
constexpr size_t kMaxSplitsPerSegment = 4096;

// SplitMode::Projection splits a segment this many times at most; then rules
// 1-3, whose termination §5 proves, take over on that segment. Far above
// what a segment of the models of tests/data needs.
constexpr size_t kMaxProjectionSplits = 64;
// A shell split point (shell_fraction) at a vertex of more segments than
// this stays where it is; at fewer, other points compete with it
// (split_by_projection). Unmerged CAD fans put dozens of segments at a
// vertex, and there the common spheres matter: without the limit they cost
// far more points. Below 5 plate_holes takes more points; 6 gives the
// fewest points on the unmerged models and costs no model of tests/data
// more.
constexpr uint32_t kShellProbeMaxSegments = 6;
// The projection of the reference point is used when it falls between these
// fractions of the subsegment, else the midpoint: a split point next to an
// end would leave a sliver of a subsegment that the next split shortens
// little. The projection moved to the nearer bound is a candidate too
// (split_by_projection).
constexpr double kProjectionLow = 0.2, kProjectionHigh = 0.8;

// Moves of a split point that would make a numerically flat tet, as
// fractions of its subsegment (insert_on_segment); the last one is final.
constexpr double kFlatShifts[] = {0, 1e-8, -1e-8, 1e-6, -1e-6, 1e-4, -1e-4, 1e-2, -1e-2, 0.1, -0.1, 0};
constexpr size_t kNumFlatShifts = sizeof(kFlatShifts) / sizeof(kFlatShifts[0]);
// Bits of the dyadic fractions tried for a split point exactly on its
// segment's line (exact_point_on_line): at most 24 (a float32 significand, so
// products with float32-grid differences stay exact), at least 20 (the point
// moves by at most 2^-21 of its subsegment, too little to change how many
// splits follow; coarser fractions move points enough to cost more).
constexpr int kExactLineBits = 24;
constexpr int kExactLineMinBits = 20;

// split_flat_pairs' bounds: split points per run, and per segment far
// below kMaxSplitsPerSegment, so that these splits never end recovery with
// an error (a flat tet left is counted, Statistics::flat_tets, not fatal).
constexpr size_t kMaxFlatSplits = 4096;
constexpr size_t kMaxFlatSplitsPerSegment = 512;
// near_crossing_splits: segments at an angle whose sine is below this are
// taken as parallel (no crossing point), and only gaps below this times
// their length count as near-crossings (a flat tet needs one far smaller).
constexpr double kCrossingSine = 1e-3;
constexpr double kCrossingGap = 1e-8;
// ... and only nearest points farther than this times that length from
// every end of both.
constexpr double kCrossingEnd = 1e-3;
// split_free_crossings sweeps at most this many free segments.
constexpr size_t kMaxSweptSegments = 1u << 12;

// Padding of the reference point search's box, relative to the segment's
// length: far above the rounding of the few operations that build it, so
// the search only ever looks at too many vertices, never too few.
constexpr double kSearchPad = 1e-9;

// Radius of the smallest sphere through a, b and p (the circumcircle of the
// triangle), used only to rank encroaching vertices (§5, reference point);
// infinite when p is on the line ab. Floating point is fine here: it picks a
// point, it decides no topology, and IEEE +,-,*,/,sqrt give the same result
// natively and in WASM.
double circumradius(Vec3 a, Vec3 b, Vec3 p) {
  const double la = dist(b, p), lb = dist(a, p), lc = dist(a, b);
  const Vec3 n = cross(b - a, p - a);
  const double twice_area = std::sqrt(dot(n, n));
  if (twice_area == 0) return HUGE_VAL;
  return la * lb * lc / (2 * twice_area);
}

// Rule 1 of §5 as a fraction of e_i e_j from e_i: the split point lies on the
// sphere around the end nearer to the reference point p through p when that
// sphere cuts the segment's first or second half, else at the midpoint.
double rule1_fraction(Vec3 a, Vec3 b, Vec3 p) {
  const double len = dist(a, b), dap = dist(a, p), dbp = dist(b, p);
  if (dap < 0.5 * len) return dap / len;
  if (dbp < 0.5 * len) return (len - dbp) / len;
  return 0.5;
}

Status segment_error(ErrorCode code, const SegmentSet& segs, uint32_t s, const std::string& what) {
  return make_error(code, "segment recovery: segment " + std::to_string(s) + " (vertices " +
                              std::to_string(segs.input[s][0]) + ", " +
                              std::to_string(segs.input[s][1]) + "): " + what)
      .segment(s)
      .vertex(segs.input[s][0]);
}

// InvalidPlc when vertex p, which encroaches upon subsegment (a, b) of
// segment s, lies on its line, i.e. in the interior of the segment (a PLC's
// vertex may not); such a p is always the reference point (its circle
// through a and b is infinite). Exact test: a split point computed near p
// would not coincide with it after rounding, and the segment would seem
// recovered around a vertex it passes through.
Status check_not_on_segment(const TetMesh& mesh, const SegmentSet& segs, uint32_t s, VertexId a,
                            VertexId b, VertexId p) {
  if (p == kNone || !pred::collinear3d(mesh.point(a), mesh.point(b), mesh.point(p))) return {};
  return segment_error(ErrorCode::InvalidPlc, segs, s,
                       "vertex " + std::to_string(p) + " lies on the segment");
}

class SegmentRecovery {
 public:
  SegmentRecovery(TetMesh& mesh, SegmentSet& segs, SegmentRecoveryStats& stats, SplitMode mode)
      : mesh_(mesh),
        segs_(segs),
        stats_(stats),
        mode_(mode),
        inserter_(mesh),
        remover_(mesh),
        first_record_(segs.steiner.size()) {
    // The split points lie on segments between vertices, so within their
    // box but for rounding; the margin of 2^-20 of its widths takes that
    // (the inserter stops using the box at a point outside it).
    inserter_.set_box_bounds(pred::box_bounds(mesh.coords.data(), mesh.num_vertices(), 0x1p-20));
  }

  Status run(const volatile bool* cancel, const std::atomic<bool>* stop);

 private:
  Status split(uint32_t s, VertexId u, VertexId w);
  Status split_by_projection(uint32_t s, VertexId u, VertexId w);
  bool shell_fraction(uint32_t s, VertexId a, VertexId b, VertexId p, double& f) const;
  void remove_redundant_points();
  bool try_remove(VertexId v);
  bool may_become_edge(VertexId u, VertexId w, VertexId v);
  std::vector<TetId> star_;
  struct Con { double ax, ay, b; };
  std::vector<Con> cons_;
  VertexId reference_point(VertexId a, VertexId b);
  void index_vertices();
  double pick_fraction(uint32_t s, VertexId a, VertexId b, VertexId p);
  int split_cost(uint32_t s, VertexId a, VertexId b, const double* q);
  Status insert_on_segment(uint32_t s, VertexId u, VertexId w, Vec3 point, double t,
                           VertexId origin, SplitRule rule);
  bool exact_point_on_line(VertexId u, VertexId w, double f, Vec3& q, double& tf) const;
  bool leaves_side(uint32_t s, const double* q) const;
  void queue_destroyed(VertexId v, std::vector<std::array<uint32_t, 3>>& queue);
  void queue_halves(uint32_t s, VertexId u, VertexId w, std::vector<std::array<uint32_t, 3>>& queue);
  struct CrossingSplit {
    uint32_t segment;
    double t;       // parameter along the segment
    double margin;  // no split when a vertex of the chain is this close (in t)
    Vec3 point;     // where (rounded)
  };
  void flat_pair(TetId t, std::vector<CrossingSplit>& out);
  void near_crossing_splits(uint32_t s, uint32_t r, std::vector<CrossingSplit>& out) const;
  bool first_look(uint32_t s, uint32_t r);
  bool on_facet(uint32_t s) const;
  Status split_free_crossings(std::vector<std::array<uint32_t, 3>>& queue);
  Status split_flat_pairs(std::vector<std::array<uint32_t, 3>>& queue, bool& split_any);
  Status insert_crossing_splits(std::vector<CrossingSplit>& splits,
                                std::vector<std::array<uint32_t, 3>>& queue, bool& split_any);
  Status split_crossing_first(uint32_t s, VertexId u, VertexId w,
                              std::vector<std::array<uint32_t, 3>>& queue, bool& split_any);

  TetMesh& mesh_;
  SegmentSet& segs_;
  SegmentRecoveryStats& stats_;
  SplitMode mode_;
  PointInserter inserter_;
  VertexRemover remover_;
  PointIndex index_;                  // every vertex of the mesh, for reference_point
  std::vector<VertexId> candidates_;  // reference_point's query result
  std::vector<VertexId> ring_;         // vertices of the last insertion's new tets, but v
  // Per vertex: 1 when a tet at it was created since the last scan for
  // missing subsegments (the next scan need only look at their subsegments).
  std::vector<uint8_t> touched_;
  std::vector<uint32_t> ring_mark_;    // per vertex: ring_epoch_ when in ring_
  uint32_t ring_epoch_ = 0;
  std::vector<std::array<VertexId, 3>> ring_faces_;  // the faces of those tets opposite v
  // Per vertex of the ring: its position among the vertices add_ring_face
  // found (ring_local_), and the ring faces at each of them (CSR over those
  // positions, built on the first ring_edge query): a query scans the few
  // faces at one vertex instead of all faces, which on CAD fans number in
  // the hundreds.
  std::vector<uint32_t> ring_local_;
  uint32_t ring_found_ = 0;
  std::vector<uint32_t> ring_face_start_, ring_face_items_;
  bool ring_index_ready_ = false;
  // Starts a new ring (ring_ empty, every vertex out of it).
  void clear_ring() {
    ring_.clear();
    ring_faces_.clear();
    ring_found_ = 0;
    ring_index_ready_ = false;
    if (++ring_epoch_ == 0) std::fill(ring_mark_.begin(), ring_mark_.end(), 0), ring_epoch_ = 1;
    if (ring_mark_.size() < mesh_.num_vertices()) {
      ring_mark_.resize(mesh_.num_vertices(), 0);
      ring_local_.resize(mesh_.num_vertices(), 0);
    }
  }
  // Adds face (a, b, c) (opposite the inserted vertex) and its finite
  // vertices. The face is written one vertex at a time: copying it in from
  // an array just built on the stack stalls on store forwarding (its three
  // 4-byte stores read back by an 8-byte load).
  void add_ring_face(VertexId a, VertexId b, VertexId c) {
    std::array<VertexId, 3>& f = ring_faces_.emplace_back();
    f[0] = a, f[1] = b, f[2] = c;
    ring_index_ready_ = false;
    for (VertexId x : {a, b, c})
      if (x != kInfinite && ring_mark_[x] != ring_epoch_) {
        ring_mark_[x] = ring_epoch_, ring_local_[x] = ring_found_++;
        ring_.push_back(x);
      }
  }
  bool in_ring(VertexId x) const { return x < ring_mark_.size() && ring_mark_[x] == ring_epoch_; }
  void index_ring_faces() {
    ring_face_start_.assign(ring_found_ + 1, 0);
    for (const auto& f : ring_faces_)
      for (VertexId x : f)
        if (x != kInfinite) ++ring_face_start_[ring_local_[x] + 1];
    for (uint32_t i = 0; i < ring_found_; ++i) ring_face_start_[i + 1] += ring_face_start_[i];
    ring_face_items_.resize(ring_face_start_[ring_found_]);
    std::vector<uint32_t>& fill = ring_fill_;
    fill.assign(ring_face_start_.begin(), ring_face_start_.end() - 1);
    for (uint32_t k = 0; k < ring_faces_.size(); ++k)
      for (VertexId x : ring_faces_[k])
        if (x != kInfinite) ring_face_items_[fill[ring_local_[x]]++] = k;
    ring_index_ready_ = true;
  }
  std::vector<uint32_t> ring_fill_;
  // Edge xy (finite vertices) is an edge of a ring face (so it survives the
  // insertion).
  bool ring_edge(VertexId x, VertexId y) {
    if (ring_faces_.empty() || !in_ring(x) || !in_ring(y)) return false;
    if (!ring_index_ready_) index_ring_faces();
    const uint32_t lx = ring_local_[x];
    for (uint32_t k = ring_face_start_[lx]; k < ring_face_start_[lx + 1]; ++k) {
      const auto& f = ring_faces_[ring_face_items_[k]];
      if (f[0] == y || f[1] == y || f[2] == y) return true;
    }
    return false;
  }
  // Per segs_.steiner record from first_record_ on (the ones this run
  // adds): the subsegment it split.
  std::vector<std::array<VertexId, 2>> split_of_;
  size_t first_record_ = 0;
  std::vector<uint32_t> incident_start_, incident_;  // input vertex -> segments (CSR)
  // Chain neighbours, kept up to date by every split and removal, so the
  // scans after an insertion need no search in the chains: per entry of
  // incident_, the neighbour of that input vertex along that segment; per
  // vertex on a segment, the previous and next vertex of its chain.
  std::vector<VertexId> end_nbr_, prev_, next_;
  void index_chain_neighbours();
  // The neighbour of chain vertex x on the side of segment s towards its
  // second endpoint (after) or first endpoint (!after) becomes n.
  void set_chain_neighbour(uint32_t s, VertexId x, bool after, VertexId n);
  // Calls f(w) for each chain neighbour w of vertex u (segment s), in chain
  // order per segment (input vertices: in incident_ order).
  template <typename F>
  void for_chain_neighbours(VertexId u, F&& f) const {
    if (const SegmentVertex* sv = segs_.on_segment(u)) {
      f(sv->segment, prev_[u]);
      f(sv->segment, next_[u]);
    } else if (u + 1 < incident_start_.size()) {
      for (uint32_t k = incident_start_[u]; k < incident_start_[u + 1]; ++k) f(incident_[k], end_nbr_[k]);
    }
  }
  std::vector<std::array<VertexId, 4>> probe_faces_;  // (face, vertex beyond)
  // split_flat_pairs: whether its first (full) scan ran, and the vertices
  // inserted since its last scan (every tet made since has one of them).
  bool flat_scanned_ = false;
  std::unordered_set<uint64_t> done_pairs_;  // pairs of segments flat_pair looked at
  // Per input segment: free (no facet at both of its ends; on_facet), the
  // only ones near_crossing_splits looks at; set by split_free_crossings.
  std::vector<uint8_t> free_;
  size_t num_free_ = 0;
  std::vector<VertexId> since_flat_scan_;
};

// The reference point of missing segment ab (§5): among the vertices that
// encroach upon ab (inside or on its diametral sphere, exact test), the one
// whose smallest circumsphere with a and b is largest; ties go to the smaller
// vertex id, so the answer does not depend on the order of the candidates.
//
// Candidates: the vertices in the bounding box of the diametral ball, from
// the point index (padded, so rounding only adds candidates; the
// encroachment test itself is exact).
VertexId SegmentRecovery::reference_point(VertexId a, VertexId b) {
  const Vec3 pa = to_vec(mesh_.point(a)), pb = to_vec(mesh_.point(b));
  const double len = dist(pa, pb);
  const double pad = kSearchPad * len + kTinyLength;
  double lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    const double mid = 0.5 * (mesh_.point(a)[d] + mesh_.point(b)[d]);
    lo[d] = mid - 0.5 * len - pad;
    hi[d] = mid + 0.5 * len + pad;
  }
  index_.query(lo, hi, candidates_);
  VertexId best = kNone;
  double best_r = -1;
  for (VertexId v : candidates_) {
    if (v == a || v == b) continue;
    // Encroaches: the angle avb is not acute, i.e. (a-v).(b-v) <= 0.
    if (pred::dot_sign(mesh_.point(a), mesh_.point(v), mesh_.point(b)) > 0) continue;
    const double rv = circumradius(pa, pb, to_vec(mesh_.point(v)));
    if (rv > best_r || (rv == best_r && v < best)) best = v, best_r = rv;
  }
  return best;
}

// Puts every vertex of the mesh into the point index; its root box is the
// vertices' bounding box, padded so that split points rounded a few ulps
// off their segments still fall inside.
void SegmentRecovery::index_vertices() {
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (VertexId v = 0; v < mesh_.num_vertices(); ++v) {
    if (mesh_.vtet[v] == kNone) continue;
    for (int d = 0; d < 3; ++d)
      lo[d] = std::min(lo[d], mesh_.point(v)[d]), hi[d] = std::max(hi[d], mesh_.point(v)[d]);
  }
  for (int d = 0; d < 3; ++d) {
    const double pad = 1e-6 * (hi[d] - lo[d]) + 1e-6 * std::max(std::fabs(lo[d]), std::fabs(hi[d]));
    lo[d] -= pad, hi[d] += pad;
  }
  index_.reset(lo, hi);
  for (VertexId v = 0; v < mesh_.num_vertices(); ++v)
    if (mesh_.vtet[v] != kNone) index_.insert(v, mesh_.point(v));
}

// What splitting subsegment (a, b) of segment s at q would cost later, from
// a probe of the insertion (nothing changes): each half that would still be
// missing counts 4 (it needs another split), each other subsegment the
// insertion would destroy counts 1 (it will need one). An existing edge
// between two vertices of the cavity survives exactly when it is an edge of
// the cavity boundary; the halves exist when a and b are on the boundary.
int SegmentRecovery::split_cost(uint32_t s, VertexId a, VertexId b, const double* q) {
  if (!inserter_.probe(q, mesh_.vtet[a], probe_faces_)) return INT32_MAX;
  clear_ring();
  for (const auto& f : probe_faces_) add_ring_face(f[0], f[1], f[2]);
  int cost = 4 * (!in_ring(a) + !in_ring(b));
  for (VertexId x : ring_)
    for_chain_neighbours(x, [&](uint32_t t, VertexId y) {
      if (y == kNone || x > y || !in_ring(y) || (t == s && ((x == a && y == b) || (x == b && y == a))))
        return;
      if (!ring_edge(x, y)) ++cost;
    });
  return cost;
}

// Where to split subsegment (a, b) (a fraction from a) when no acute vertex
// constrains it (rule 1, and the first split of a segment with two acute
// ends): rule 1's point or the projection of the reference point p onto the
// segment (kept within the middle 80%), whichever split_cost prefers (rule
// 1's on a tie). Any point strictly inside splits the subsegment; the choice
// only decides how many more splits follow. (The midpoint or quarter
// points as further candidates lead to more splits on CAD models.)
double SegmentRecovery::pick_fraction(uint32_t s, VertexId a, VertexId b, VertexId p) {
  const Vec3 pa = to_vec(mesh_.point(a)), pb = to_vec(mesh_.point(b)), pp = to_vec(mesh_.point(p));
  const double f1 = rule1_fraction(pa, pb, pp);
  const Vec3 ab = pb - pa;
  const double proj = std::min(0.9, std::max(0.1, dot(pp - pa, ab) / dot(ab, ab)));
  double best = f1;
  int best_cost = INT32_MAX;
  for (double f : {f1, proj}) {
    const double q[3] = {pa.x + f * ab.x, pa.y + f * ab.y, pa.z + f * ab.z};
    const int c = split_cost(s, a, b, q);
    if (c < best_cost) best = f, best_cost = c;
    if (best_cost == 0) break;
  }
  return best;
}

// The split point of subsegment (a, b) of segment s (a fraction from a) on
// the sphere around an endpoint e that s shares with the segment of the
// reference point p, through p: the points that segments leaving e get this
// way lie on common spheres around e, the protecting ball of §5 (Figure 4),
// so they do not encroach upon each other's subsegments at e, whatever the
// angle between the segments. False when p is not a Steiner vertex of such
// a segment or the sphere does not cross the open subsegment.
bool SegmentRecovery::shell_fraction(uint32_t s, VertexId a, VertexId b, VertexId p, double& f) const {
  const SegmentVertex* sp = segs_.on_segment(p);
  if (!sp || sp->segment == s) return false;
  const std::array<VertexId, 2>& other = segs_.input[sp->segment];
  for (int k = 0; k < 2; ++k) {
    const VertexId e = segs_.input[s][k], far = segs_.input[s][1 - k];
    if (other[0] != e && other[1] != e) continue;
    const Vec3 pe = to_vec(mesh_.point(e)), pf = to_vec(mesh_.point(far));
    const double r = dist(pe, to_vec(mesh_.point(p))) / dist(pe, pf);
    const Vec3 v = {pe.x + r * (pf.x - pe.x), pe.y + r * (pf.y - pe.y), pe.z + r * (pf.z - pe.z)};
    const Vec3 pa = to_vec(mesh_.point(a)), ab = to_vec(mesh_.point(b)) - pa;
    const double g = dot(v - pa, ab) / dot(ab, ab);
    if (g > 0 && g < 1) {
      f = g;
      return true;
    }
  }
  return false;
}

// SplitMode::Projection: splits the missing subsegment (u, w) of segment s
// near the vertex that keeps it from being a Delaunay edge. Its reference
// point p is §5's (of the vertices in its diametral ball, the one with the
// largest circle through its ends, roughly the one nearest its line); the
// split point is p's projection onto the subsegment, which puts p outside
// the diametral balls of both halves when p is close to the segment (the
// usual case on CAD models: a vertex of a long thin facet next to the
// segment), or the midpoint when the projection is near an end. When p is a
// split point of a segment sharing an endpoint with s, the point goes on the
// sphere around that endpoint through p instead (shell_fraction). That
// point competes with the projection (moved into the middle part) and the
// midpoint: a probe of each insertion (split_cost) counts the subsegments it
// would leave missing or destroy, the fewest win, the rule's own point on a
// tie. Most split points on CAD parts are not the missing segments' own but
// those of segments that earlier insertions destroyed, several times as
// many; the probe avoids points that start such a cascade. A shell point
// at a vertex of many
// segments does not compete (kShellProbeMaxSegments): there the shared
// spheres keep the segments' points from encroaching on each other (§5,
// Figure 4), which a probe of one insertion does not see. Rounded to
// doubles like every split point (insert_on_segment).
Status SegmentRecovery::split_by_projection(uint32_t s, VertexId u, VertexId w) {
  VertexId a = u, b = w;
  if (segs_.param(s, a) > segs_.param(s, b)) std::swap(a, b);
  const VertexId p = reference_point(a, b);
  if (p == kNone)
    return segment_error(ErrorCode::Internal, segs_, s,
                         "a missing subsegment has no encroaching vertex");
  if (Status st = check_not_on_segment(mesh_, segs_, s, a, b, p); !st.ok()) return st;
  const Vec3 pa = to_vec(mesh_.point(a)), ab = to_vec(mesh_.point(b)) - pa;
  double f = 0.5;
  SplitRule rule = SplitRule::Projection;
  const double g = dot(to_vec(mesh_.point(p)) - pa, ab) / dot(ab, ab);
  if (shell_fraction(s, a, b, p, f)) {
    rule = SplitRule::Shell;
  } else if (g >= kProjectionLow && g <= kProjectionHigh) {
    f = g;
  }
  // The other candidates, in this order (ties keep the first): any point
  // strictly inside splits the subsegment (§5's termination is kept by
  // kMaxProjectionSplits, then rules 1-3), so the choice decides only how
  // many splits follow. These candidates (the projection clamped into
  // the middle part, the midpoint) save Steiner points on the valid models
  // of tests/data and cost none more; the counts of the CAD parts are
  // sensitive to the bounds.
  const double cands[3] = {f, std::min(kProjectionHigh, std::max(kProjectionLow, g)), 0.5};
  bool compete = true;
  if (rule == SplitRule::Shell) {
    const std::array<VertexId, 2>& o = segs_.input[segs_.on_segment(p)->segment];
    for (VertexId e : segs_.input[s])
      if ((o[0] == e || o[1] == e) &&
          incident_start_[e + 1] - incident_start_[e] > kShellProbeMaxSegments)
        compete = false;
  }
  int best_cost = INT32_MAX;
  double best = f;
  for (int k = 0; k < 3 && compete && best_cost > 0; ++k) {
    if ((k >= 1 && cands[k] == cands[0]) || (k == 2 && cands[2] == cands[1])) continue;
    const double q[3] = {pa.x + cands[k] * ab.x, pa.y + cands[k] * ab.y, pa.z + cands[k] * ab.z};
    const int cost = split_cost(s, a, b, q);
    if (cost < best_cost) best_cost = cost, best = cands[k];
  }
  if (best != f) f = best, rule = SplitRule::Projection;
  const Vec3 v = {pa.x + f * ab.x, pa.y + f * ab.y, pa.z + f * ab.z};
  const double ta = segs_.param(s, a), tb = segs_.param(s, b);
  return insert_on_segment(s, a, b, v, ta + f * (tb - ta), kNone, rule);
}

// Splits the missing subsegment (u, w) of input segment s: by projection
// (the default) while s has fewer than kMaxProjectionSplits points, else by
// rule 1, 2 or 3.
Status SegmentRecovery::split(uint32_t s, VertexId u, VertexId w) {
  if (mode_ == SplitMode::Projection && segs_.chain[s].size() - 2 < kMaxProjectionSplits)
    return split_by_projection(s, u, w);
  const VertexId s0 = segs_.input[s][0], s1 = segs_.input[s][1];
  const bool acute0 = segs_.acute[s0] != 0, acute1 = segs_.acute[s1] != 0;

  // §5: a segment with both ends acute becomes two type-2 segments by "a
  // vertex" in between. The paper leaves the vertex free; we place it like
  // rule 1 (on the sphere around the nearer end through the reference point,
  // else the midpoint), which often recovers both halves at once where the
  // midpoint would leave one of them encroached. Rounded to doubles (see
  // insert_on_segment).
  if (acute0 && acute1 && segs_.midpoint[s] == kNone) {
    VertexId ei = u, ej = w;
    if (segs_.param(s, ei) > segs_.param(s, ej)) std::swap(ei, ej);
    const VertexId p = reference_point(ei, ej);
    if (Status st = check_not_on_segment(mesh_, segs_, s, ei, ej, p); !st.ok()) return st;
    const double f = p == kNone ? 0.5 : pick_fraction(s, ei, ej, p);
    const Vec3 a = to_vec(mesh_.point(ei)), b = to_vec(mesh_.point(ej));
    const Vec3 v = {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), a.z + f * (b.z - a.z)};
    const double ti = segs_.param(s, ei), tj = segs_.param(s, ej);
    return insert_on_segment(s, ei, ej, v, ti + f * (tj - ti), kNone, SplitRule::AcuteBoth);
  }

  // Orient the subsegment: e_i is the end nearer to the acute origin e_k.
  VertexId origin = kNone;
  if (acute0 && acute1) {
    // Which side of the split vertex between the two acute ends.
    const double tm = segs_.midpoint[s] != kNone ? segs_.param(s, segs_.midpoint[s]) : 0.5;
    origin = segs_.param(s, u) + segs_.param(s, w) < 2 * tm ? s0 : s1;
  } else if (acute0) {
    origin = s0;
  } else if (acute1) {
    origin = s1;
  }
  VertexId ei = u, ej = w;
  if (segs_.param(s, ei) > segs_.param(s, ej)) std::swap(ei, ej);  // now ei is nearer to s0
  if (origin == s1) std::swap(ei, ej);

  const VertexId p = reference_point(ei, ej);
  if (p == kNone)
    return segment_error(ErrorCode::Internal, segs_, s,
                         "a missing subsegment has no encroaching vertex");
  if (Status st = check_not_on_segment(mesh_, segs_, s, ei, ej, p); !st.ok()) return st;
  const Vec3 a = to_vec(mesh_.point(ei)), b = to_vec(mesh_.point(ej)), pp = to_vec(mesh_.point(p));

  if (origin == kNone) {
    // Rule 1 (type-1): v = e_i e_j ∩ S(c, r).
    const double f = pick_fraction(s, ei, ej, p);
    const Vec3 v = {a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), a.z + f * (b.z - a.z)};
    const double ti = segs_.param(s, ei), tj = segs_.param(s, ej);
    return insert_on_segment(s, ei, ej, v, ti + f * (tj - ti), kNone, SplitRule::Rule1);
  }

  // Rules 2 and 3 (type-2): v on the ray from e_k = O(e_i) through e_j.
  const Vec3 k = to_vec(mesh_.point(origin));
  const double lkj = dist(k, b);
  const double tk = segs_.param(s, origin), tj = segs_.param(s, ej);
  auto point_at = [&](double r) {
    const double f = r / lkj;
    return Vec3{k.x + f * (b.x - k.x), k.y + f * (b.y - k.y), k.z + f * (b.z - k.z)};
  };
  const double r2 = dist(k, pp);
  const Vec3 v2 = point_at(r2);
  if (!(dist(v2, b) < dist(v2, pp))) {
    return insert_on_segment(s, ei, ej, v2, tk + (r2 / lkj) * (tj - tk), origin, SplitRule::Rule2);
  }
  // Rule 3: v' = v2 was rejected.
  const double dki = dist(k, a), div = dist(a, v2), dpv = dist(pp, v2);
  const double r3 = dpv < 0.5 * div ? dki + div - dpv : dki + 0.5 * div;
  return insert_on_segment(s, ei, ej, point_at(r3), tk + (r3 / lkj) * (tj - tk), origin,
                           SplitRule::Rule3);
}

// A point of the open subsegment (u, w) exactly on its line
// (point_exactly_on_segment, geometry.hpp).
bool SegmentRecovery::exact_point_on_line(VertexId u, VertexId w, double f, Vec3& q, double& tf) const {
  return point_exactly_on_segment(mesh_.point(u), mesh_.point(w), f, kExactLineBits,
                                  kExactLineMinBits, q, tf);
}

// Whether the point q, meant for the open segment s, fails to lie strictly
// on the segment's side of the plane of a facet at one of its endpoints e
// (a facet holding e but not the segment: the whole open segment lies
// strictly on one side of its plane, as e is in it). Exact orientations.
// Why: a rounded split point lies up to half an ulp off its segment; where
// two facets at e meet at a dihedral angle so small that, at the point's
// distance from e, the gap between the segment and the other facet's plane
// is below that (thin wedges between near-duplicate parts: 1e-7 rad), the
// point can land on the far side, the subfaces made from it then cross the
// other facet's subfaces, and the discretized PLC has no CDT: no cavity of
// facet recovery (§7) can hold both, and facet Steiner points (which do not
// move segment points) cannot undo it.
bool SegmentRecovery::leaves_side(uint32_t s, const double* q) const {
  if (segs_.plane_start.empty()) return false;
  for (int end = 0; end < 2; ++end) {
    const VertexId e = segs_.input[s][end], far = segs_.input[s][1 - end];
    if (size_t(e) + 1 >= segs_.plane_start.size()) continue;
    for (uint32_t i = segs_.plane_start[e]; i < segs_.plane_start[e + 1]; ++i) {
      const std::array<VertexId, 3>& P = segs_.planes[segs_.plane_facets[i]];
      const double *a = mesh_.point(P[0]), *b = mesh_.point(P[1]), *c = mesh_.point(P[2]);
      const int side = pred::orient3d(a, b, c, mesh_.point(far));
      if (side != 0 && pred::orient3d(a, b, c, q) != side) return true;
    }
  }
  return false;
}

// Inserts the split point of subsegment (u, w) of segment s.
//
// Rounding: the point is computed in floating point and rounded to doubles,
// so it lies near, not on, the segment's line, unless a double exactly on the
// line lies within 2^-21 of the subsegment from it (exact_point_on_line; a
// coarser snap, to the nearest such double at any distance, moves points
// far enough to cost more splits on CAD models). Off the line is
// safe because (1) we keep the intended parameter and the segment in a
// SegmentVertex, and the chain order, not coordinates, says which vertices
// are on which segment; (2) the Delaunay
// insertion uses exact predicates on the rounded point, so D1 is exactly the
// Delaunay tetrahedralization of the vertices as stored; (3) a rounded point
// that fails to land strictly between u and w (possible only for subsegments
// a few ulps long) is replaced by the midpoint, and if that too coincides with
// an end we stop with an error.
Status SegmentRecovery::insert_on_segment(uint32_t s, VertexId u, VertexId w, Vec3 point, double t,
                                          VertexId origin, SplitRule rule) {
  SegmentChain& chain = segs_.chain[s];
  if (chain.size() - 2 >= kMaxSplitsPerSegment)
    return segment_error(ErrorCode::LimitReached, segs_, s,
                         "more than " + std::to_string(kMaxSplitsPerSegment) +
                             " splits; recovery does not terminate");
  const Vec3 a = to_vec(mesh_.point(u)), b = to_vec(mesh_.point(w));
  auto strictly_between = [&](Vec3 v) {
    return dot((v - a), (b - a)) > 0 && dot((v - b), (a - b)) > 0;
  };
  if (!strictly_between(point)) {
    point = {0.5 * (a.x + b.x), 0.5 * (a.y + b.y), 0.5 * (a.z + b.z)};
    t = 0.5 * (segs_.param(s, u) + segs_.param(s, w));
    if (!strictly_between(point))
      return segment_error(ErrorCode::LimitReached, segs_, s,
                           "a subsegment is too short to split in double precision");
  }

  // No numerically flat tets (cdt3d.hpp): the rounded split point can make
  // one with nearly co-planar vertices around it (CAD models: points placed
  // symmetrically on parallel segments). The insertion is then refused and
  // the point moves along the subsegment; the rule's exact position matters
  // for the bound on splits, not for correctness (any vertex strictly inside
  // the subsegment splits it). A rounded point on the wrong side of a facet
  // plane at the segment's ends moves the same way (leaves_side). After all
  // tries it is inserted as planned.
  const double tu = segs_.param(s, u), tw = segs_.param(s, w);
  double f0 = tw != tu ? (t - tu) / (tw - tu) : 0.5;
  // Prefer a point exactly on the segment's line, moved by at most
  // 2^-kExactLineMinBits of the subsegment: it lies exactly in every plane
  // that holds the segment, so it cannot make a flat tet with points of a
  // facet plane (a rounded point a few ulps off that plane does, once other
  // points of the plane are inserted next to it; fuzz findings with the hull
  // kept). Such a point exists when the coordinates are short (integer, CAD
  // and float32 grids); otherwise the rounded point stays.
  // Not for a near-crossing's points (split_flat_pairs): they must stay
  // where the two lines pass nearest, far closer than that move.
  if (rule != SplitRule::Flat) {
    Vec3 q;
    double tf;
    if (exact_point_on_line(u, w, f0, q, tf)) point = q, t = tu + tf * (tw - tu), f0 = tf;
  }
  InsertResult res;
  Status st;
  // split_flat_pairs' points go where planned: at and beside a near-crossing
  // they make flat tets with the other segment until it is split too.
  for (size_t k = rule == SplitRule::Flat ? kNumFlatShifts - 1 : 0; k < kNumFlatShifts; ++k) {
    const double shift = kFlatShifts[k];
    const double f = std::min(0.95, std::max(0.05, f0 + shift));
    Vec3 q = shift == 0 ? point
                        : Vec3{a.x + f * (b.x - a.x), a.y + f * (b.y - a.y), a.z + f * (b.z - a.z)};
    if (shift != 0 && !strictly_between(q)) continue;
    const double xyz[3] = {q.x, q.y, q.z};
    if (k + 1 < kNumFlatShifts && leaves_side(s, xyz)) continue;
    inserter_.set_reject_flat(k + 1 < kNumFlatShifts);
    st = inserter_.insert_point(xyz, mesh_.vtet[u], kVertexSteiner, &res);
    if (!st.ok()) return st;
    if (!res.rejected) {
      if (shift != 0) t = tu + f * (tw - tu), ++stats_.flat_moves;
      break;
    }
  }
  inserter_.set_reject_flat(false);
  if (res.rejected || res.vertex == kNone)
    return segment_error(ErrorCode::Internal, segs_, s, "no position for the split point");
  if (res.duplicate)
    return segment_error(ErrorCode::InvalidPlc, segs_, s,
                         "vertex " + std::to_string(res.vertex) + " lies on the segment");
  index_.insert(res.vertex, mesh_.point(res.vertex));
  if (flat_scanned_) since_flat_scan_.push_back(res.vertex);

  // Keep the chain ordered from the segment's first to its second endpoint.
  const long iu = segs_.chain_position(s, u), iw = segs_.chain_position(s, w);
  const long at = std::max(iu, iw);
  chain.insert(chain.begin() + at, res.vertex);
  if (prev_.size() <= res.vertex) prev_.resize(res.vertex + 1, kNone), next_.resize(res.vertex + 1, kNone);
  prev_[res.vertex] = chain[at - 1], next_[res.vertex] = chain[at + 1];
  set_chain_neighbour(s, chain[at - 1], true, res.vertex);
  set_chain_neighbour(s, chain[at + 1], false, res.vertex);

  if (segs_.steiner_of.size() <= res.vertex) segs_.steiner_of.resize(res.vertex + 1, kNone);
  segs_.steiner_of[res.vertex] = static_cast<uint32_t>(segs_.steiner.size());
  segs_.steiner.push_back({res.vertex, s, t, origin, rule});
  split_of_.push_back({u, w});
  if (rule == SplitRule::AcuteBoth) segs_.midpoint[s] = res.vertex;
  switch (rule) {
    case SplitRule::Rule1: ++stats_.rule1; break;
    case SplitRule::Rule2: ++stats_.rule2; break;
    case SplitRule::Rule3: ++stats_.rule3; break;
    case SplitRule::AcuteBoth: ++stats_.acute_both; break;
    case SplitRule::Projection: ++stats_.projection; break;
    case SplitRule::Shell: ++stats_.shell; break;
    case SplitRule::Flat: ++stats_.flat; break;
    case SplitRule::Protect: break;
  }
  stats_.max_splits = std::max(stats_.max_splits, chain.size() - 2);
  return {};
}

// After inserting v, pushes every subsegment the insertion destroyed. The
// Bowyer–Watson insertion creates only edges at v and deletes only edges
// between vertices of its cavity, all of which are vertices of the new tets;
// an edge between two of them survives if it lies on the cavity boundary (an
// edge of a new tet not at v) or outside the cavity (find_edge decides).
void SegmentRecovery::queue_destroyed(VertexId v, std::vector<std::array<uint32_t, 3>>& queue) {
  const std::vector<TetId>& created = inserter_.new_tets();
  clear_ring();
  for (TetId t : created) {
    const VertexId* w = mesh_.tet_vertices(t);  // the three but v, in order
    if (w[3] == v)                              // a real new tet (fill_cavity puts v last)
      add_ring_face(w[0], w[1], w[2]);
    else if (w[0] == v)
      add_ring_face(w[1], w[2], w[3]);
    else if (w[1] == v)
      add_ring_face(w[0], w[2], w[3]);
    else
      add_ring_face(w[0], w[1], w[3]);
  }
  // In id order: the queue order (and so the result) does not depend on the
  // order of the new tets.
  std::sort(ring_.begin(), ring_.end());
  if (touched_.size() < mesh_.num_vertices()) touched_.resize(mesh_.num_vertices(), 0);
  touched_[v] = 1;
  for (VertexId u : ring_) touched_[u] = 1;
  for (VertexId u : ring_)
    for_chain_neighbours(u, [&](uint32_t s, VertexId w) {
      if (w == kNone || w == v || u > w || !in_ring(w)) return;  // each pair once (u < w)
      if (ring_edge(u, w)) return;
      if (mesh_.find_edge(u, w) == kNone) queue.push_back({u, w, s});
    });
}

// A floating-point filter for try_remove: whether some sphere through u and
// w may hold none of v's neighbours but u and w (the exact test is
// remover_.plan's DT(link)). Centres of spheres through u and w lie in the
// bisector plane of uw; with z the centre's offset from uw's midpoint m in
// that plane, neighbour x is outside the sphere when a.z < b, a = 2 (x - m)
// projected on the plane, b = |x - m|^2 - |uw|^2 / 4. A neighbour with b <= 0
// (in uw's diametral ball) allows only the half of the directions away from
// it; the others bound how far z may go. We look along directions sampled in
// the arc all of them allow. False means no sphere was found: a missed
// removal at worst (rounding, a narrow arc), never a wrong one, because only
// the exact test removes.
bool SegmentRecovery::may_become_edge(VertexId u, VertexId w, VertexId v) {
  constexpr double kPi = 3.14159265358979323846;
  constexpr int kSamples = 24;
  // v's neighbours, in ring_ (no sort needed: the filter's answer does not
  // depend on their order).
  mesh_.vertex_star(v, star_);
  clear_ring();
  for (TetId t : star_)
    for (int i = 0; i < 4; ++i) {
      const VertexId x = mesh_.vertex(t, i);
      if (x != v && x != kInfinite && ring_mark_[x] != ring_epoch_) ring_mark_[x] = ring_epoch_, ring_.push_back(x);
    }
  const Vec3 pu = to_vec(mesh_.point(u)), pw = to_vec(mesh_.point(w));
  const Vec3 m = {0.5 * (pu.x + pw.x), 0.5 * (pu.y + pw.y), 0.5 * (pu.z + pw.z)};
  const Vec3 axis = pw - pu;
  const double h2 = 0.25 * dot(axis, axis);
  // An orthonormal basis (e1, e2) of the bisector plane.
  Vec3 e1 = std::fabs(axis.x) < std::fabs(axis.y) ? cross(axis, Vec3{1, 0, 0}) : cross(axis, Vec3{0, 1, 0});
  e1 = (1 / std::sqrt(dot(e1, e1))) * e1;
  Vec3 e2 = cross(axis, e1);
  e2 = (1 / std::sqrt(dot(e2, e2))) * e2;
  std::vector<Con>& cons = cons_;
  cons.clear();
  double lo = -kPi, hi = kPi;  // allowed arc of directions, as angles
  bool any_inside = false;
  for (VertexId x : ring_) {
    if (x == u || x == w) continue;
    const Vec3 d = to_vec(mesh_.point(x)) - m;
    const Con c = {2 * dot(d, e1), 2 * dot(d, e2), dot(d, d) - h2};
    cons.push_back(c);
    if (c.b > 0) continue;
    if (c.ax == 0 && c.ay == 0) return false;
    // Allowed: directions within 90 degrees of -a. Intersect with [lo, hi].
    const double centre = std::atan2(-c.ay, -c.ax);
    if (!any_inside) {
      lo = centre - kPi / 2, hi = centre + kPi / 2, any_inside = true;
      continue;
    }
    double mid = 0.5 * (lo + hi);
    double off = centre - mid;
    while (off > kPi) off -= 2 * kPi;
    while (off < -kPi) off += 2 * kPi;
    const double c0 = mid + off;
    lo = std::max(lo, c0 - kPi / 2), hi = std::min(hi, c0 + kPi / 2);
    if (!(lo < hi)) return false;
  }
  if (!any_inside) return true;  // the diametral sphere itself
  for (int k = 0; k < kSamples; ++k) {
    const double th = lo + (hi - lo) * (k + 0.5) / kSamples;
    const double dx = std::cos(th), dy = std::sin(th);
    double rmin = 0, rmax = HUGE_VAL;
    for (const Con& c : cons) {
      const double ad = c.ax * dx + c.ay * dy;
      if (c.b <= 0) {
        if (ad >= 0) { rmin = HUGE_VAL; break; }
        rmin = std::max(rmin, c.b / ad);
      } else if (ad > 0) {
        rmax = std::min(rmax, c.b / ad);
      }
    }
    if (rmin < rmax) return true;
  }
  return false;
}

// Removes split point v, between u and w on its segment, when uw is an edge
// of DT(V \ {v}) and none of the tets that would fill v's star is
// numerically flat. uw then becomes the subsegment. Hull vertices stay.
bool SegmentRecovery::try_remove(VertexId v) {
  const SegmentVertex* sv = segs_.on_segment(v);
  const uint32_t s = sv->segment;
  const long i = segs_.chain_position(s, v);
  SegmentChain& chain = segs_.chain[s];
  if (i <= 0 || i + 1 >= static_cast<long>(chain.size())) return false;
  const VertexId u = chain[i - 1], w = chain[i + 1];
  if (!may_become_edge(u, w, v)) return false;
  if (!remover_.plan(v)) return false;
  bool has_uw = false;
  for (const auto& t : remover_.fresh()) {
    const bool hu = t[0] == u || t[1] == u || t[2] == u || t[3] == u;
    const bool hw = t[0] == w || t[1] == w || t[2] == w || t[3] == w;
    has_uw = has_uw || (hu && hw);
    if (t[3] != kInfinite &&
        numerically_flat(mesh_.point(t[0]), mesh_.point(t[1]), mesh_.point(t[2]), mesh_.point(t[3])))
      return false;
  }
  if (!has_uw || !remover_.commit()) return false;
  chain.erase(chain.begin() + i);
  set_chain_neighbour(s, u, true, w);
  set_chain_neighbour(s, w, false, u);
  return true;
}

// The last part of step 2 (SplitMode::Projection): a split point v between
// u and w can go when uw is an edge of DT(V \ {v}), because the result still
// has every subsegment as a Delaunay edge: removing a vertex empties spheres,
// it never fills one, so every other subsegment stays an edge. A later
// split often makes an earlier one redundant (its reference point is now
// shielded by closer points). Greedy, in insertion order; a removal changes
// only the stars of its link vertices, so only the split points among them
// are tried again. The first pass tries only split points whose neighbours
// on the segment are no longer the ends of the subsegment they split: a
// point between the same two ends is still needed, because the vertices
// have only grown since, and more vertices never make a missing edge
// Delaunay.
void SegmentRecovery::remove_redundant_points() {
  std::vector<VertexId> work;
  std::vector<uint8_t> queued(mesh_.num_vertices(), 0), gone(mesh_.num_vertices(), 0);
  for (size_t k = first_record_; k < segs_.steiner.size(); ++k) {
    const SegmentVertex& sv = segs_.steiner[k];
    if (sv.rule != SplitRule::Projection && sv.rule != SplitRule::Shell) continue;
    const SegmentChain& chain = segs_.chain[sv.segment];
    const long i = segs_.chain_position(sv.segment, sv.vertex);
    const VertexId u = chain[i - 1], w = chain[i + 1];
    const std::array<VertexId, 2>& was = split_of_[k - first_record_];
    if ((u == was[0] && w == was[1]) || (u == was[1] && w == was[0])) continue;
    work.push_back(sv.vertex), queued[sv.vertex] = 1;
  }
  std::vector<VertexId> link;
  for (size_t k = 0; k < work.size(); ++k) {
    const VertexId v = work[k];
    queued[v] = 0;
    if (!try_remove(v)) continue;
    gone[v] = 1;
    ++stats_.removed;
    link = remover_.link();
    for (VertexId x : link) {
      const SegmentVertex* sx = segs_.on_segment(x);
      if (!sx || queued[x] || (sx->rule != SplitRule::Projection && sx->rule != SplitRule::Shell)) continue;
      queued[x] = 1;
      work.push_back(x);
    }
  }
  if (stats_.removed == 0) return;
  // Drop the records of the removed points (kept in insertion order).
  size_t n = 0;
  for (const SegmentVertex& sv : segs_.steiner)
    if (!gone[sv.vertex]) segs_.steiner[n++] = sv;
  segs_.steiner.resize(n);
  std::fill(segs_.steiner_of.begin(), segs_.steiner_of.end(), kNone);
  for (uint32_t k = 0; k < n; ++k) segs_.steiner_of[segs_.steiner[k].vertex] = k;
}

void SegmentRecovery::index_chain_neighbours() {
  end_nbr_.assign(incident_.size(), kNone);
  prev_.assign(mesh_.num_vertices(), kNone);
  next_.assign(mesh_.num_vertices(), kNone);
  for (uint32_t s = 0; s < segs_.chain.size(); ++s) {
    const SegmentChain& c = segs_.chain[s];
    set_chain_neighbour(s, c.front(), true, c[1]);
    set_chain_neighbour(s, c.back(), false, c[c.size() - 2]);
    for (size_t i = 1; i + 1 < c.size(); ++i) prev_[c[i]] = c[i - 1], next_[c[i]] = c[i + 1];
  }
}

void SegmentRecovery::set_chain_neighbour(uint32_t s, VertexId x, bool after, VertexId n) {
  if (x == segs_.input[s][0] || x == segs_.input[s][1]) {
    for (uint32_t k = incident_start_[x]; k < incident_start_[x + 1]; ++k)
      if (incident_[k] == s) end_nbr_[k] = n;
    return;
  }
  if (prev_.size() <= x) prev_.resize(x + 1, kNone), next_.resize(x + 1, kNone);
  (after ? next_ : prev_)[x] = n;
}

Status SegmentRecovery::run(const volatile bool* cancel, const std::atomic<bool>* stop) {
  // Segments incident to each input vertex (CSR), for queue_destroyed.
  const size_t nv = segs_.acute.size();
  incident_start_.assign(nv + 1, 0);
  for (const auto& e : segs_.input) ++incident_start_[e[0] + 1], ++incident_start_[e[1] + 1];
  for (size_t v = 0; v < nv; ++v) incident_start_[v + 1] += incident_start_[v];
  incident_.resize(incident_start_[nv]);
  index_vertices();
  std::vector<uint32_t> fill(incident_start_.begin(), incident_start_.end() - 1);
  for (uint32_t s = 0; s < segs_.input.size(); ++s)
    for (VertexId e : segs_.input[s]) incident_[fill[e]++] = s;
  index_chain_neighbours();

  // The repeat loop of the pseudo-code. Missing subsegments stay missing
  // until split (insertions add edges only at the new vertex), and every
  // subsegment an insertion destroys is queued again by queue_destroyed, so
  // the second scan normally finds nothing; it is the loop's exit test.
  // Scans after the first look only at subsegments with both ends touched.
  // One that was an edge stays one unless a cavity removed it, and then
  // both its ends are vertices of the cavity's new tets. One that was
  // missing was queued, so it is split or no longer a subsegment. One made
  // by a split has the new (touched) vertex at one end; its other end is
  // either a vertex of the new tets (touched) or not, and then the new
  // subsegment is no edge and was queued. So the exit scan need not pass
  // over every subsegment again.
  std::vector<std::array<uint32_t, 3>> queue;
  if (Status st = split_free_crossings(queue); !st.ok()) return st;
  for (;;) {
    missing_subsegments(mesh_, segs_, queue, stats_.rounds == 0 ? nullptr : &touched_);
    touched_.assign(touched_.size(), 0);
    if (stats_.rounds == 0) stats_.missing_initially = queue.size();
    bool flat_split = false;
    if (queue.empty()) {
      if (Status st = split_flat_pairs(queue, flat_split); !st.ok()) return st;
    }
    if (queue.empty() && !flat_split) {
      if (mode_ == SplitMode::Projection) remove_redundant_points();
      return {};
    }
    ++stats_.rounds;
    for (size_t k = 0; k < queue.size(); ++k) {
      if ((cancel && *cancel) || (stop && stop->load(std::memory_order_relaxed))) {
        return make_error(ErrorCode::Cancelled, "segment recovery cancelled");
      }
      const auto [u, w, s] = queue[k];
      const long iu = segs_.chain_position(s, u), iw = segs_.chain_position(s, w);
      if (iu < 0 || iw < 0 || (iu + 1 != iw && iw + 1 != iu)) continue;  // already split
      bool crossed = false;
      if (Status st = split_crossing_first(s, u, w, queue, crossed); !st.ok()) return st;
      if (crossed) {
        const long ju = segs_.chain_position(s, u), jw = segs_.chain_position(s, w);
        if ((ju + 1 != jw && jw + 1 != ju) || mesh_.find_edge(u, w) != kNone) continue;
      }
      Status st = split(s, u, w);
      if (!st.ok()) return st;
      queue_halves(s, u, w, queue);
    }
  }
}

// After the split of subsegment (u, w) of segment s: queues every
// subsegment the insertion destroyed, and each half that is no edge (v's
// neighbours are exactly the vertices of the new tets).
void SegmentRecovery::queue_halves(uint32_t s, VertexId u, VertexId w,
                                   std::vector<std::array<uint32_t, 3>>& queue) {
  const VertexId v = segs_.steiner.back().vertex;
  queue_destroyed(v, queue);
  for (VertexId x : {u, w})
    if (!in_ring(x)) queue.push_back({std::min(x, v), std::max(x, v), s});
}

// When tet t is numerically flat and two of its vertices lie on different
// free segments s and r whose lines pass nearest to each other inside both, at
// a distance far below their length, the split points that cure it (below)
// go into `out`, once per pair of segments (done_pairs_).
void SegmentRecovery::flat_pair(TetId t, std::vector<CrossingSplit>& out) {
  const VertexId* v = mesh_.tet_vertices(t);
  if (v[3] == kInfinite ||
      !numerically_flat(mesh_.point(v[0]), mesh_.point(v[1]), mesh_.point(v[2]), mesh_.point(v[3])))
    return;
  std::array<uint32_t, 16> on{};
  int n_on = 0;
  for (int i = 0; i < 4; ++i)  // the segments of the subsegments at each vertex
    for_chain_neighbours(v[i], [&](uint32_t s, VertexId) {
      if (!free_[s]) return;
      for (int k = 0; k < n_on; ++k)
        if (on[k] == s) return;
      if (n_on < static_cast<int>(on.size())) on[n_on++] = s;
    });
  for (int i = 0; i < n_on; ++i)
    for (int j = i + 1; j < n_on; ++j) {
      const uint32_t s = std::min(on[i], on[j]), r = std::max(on[i], on[j]);
      if (s != r && first_look(s, r)) near_crossing_splits(s, r, out);
    }
}

// Split points where input segments s and r pass within a tiny distance of
// each other (nearly crossing, not touching: a valid PLC). Every
// tetrahedralization that holds both near the crossing has tets of almost no
// volume unless both have vertices at their lines' nearest points (the
// short edge between those two is then an edge of its own) and the next
// vertices at a spacing h on either side: tets of the two crossing points
// and two neighbours have 6V / l_max^3 about gap / h, those of a crossing
// point, a neighbour and far vertices (at about the segments' length L)
// about (h / L)^2; h = (gap L^2)^(1/3) makes both (gap / L)^(2/3), far above
// kFlatTetRatio for any gap above rounding. Rounded geometry: it only
// places points (the chains say which subsegments make a segment).
void SegmentRecovery::near_crossing_splits(uint32_t s, uint32_t r, std::vector<CrossingSplit>& out) const {
  // Free segments only: where facets hold them, the points would make
  // their subfaces nearly as small as the gap, and facet recovery then
  // fails there (repair's arrangements of crossing parts) and retries.
  if (!free_[s] || !free_[r]) return;
  const Vec3 pa = to_vec(mesh_.point(segs_.input[s][0])), pb = to_vec(mesh_.point(segs_.input[s][1]));
  const Vec3 pc = to_vec(mesh_.point(segs_.input[r][0])), pd = to_vec(mesh_.point(segs_.input[r][1]));
  const Vec3 u = pb - pa, w = pd - pc;
  const double lab = std::sqrt(dot(u, u)), lcd = std::sqrt(dot(w, w));
  const Vec3 n = cross(u, w);
  const double nn = std::sqrt(dot(n, n));
  if (!(nn > kCrossingSine * lab * lcd)) return;  // nearly parallel
  const double gap = std::fabs(dot(pc - pa, n)) / nn;
  const double len = std::max(lab, lcd);
  if (!(gap > 0 && gap < kCrossingGap * len)) return;  // 0: the lines meet (at an end)
  const Vec3 e = pc - pa;
  const double fa = dot(cross(e, w), n) / (nn * nn), fc = dot(cross(e, u), n) / (nn * nn);
  const double h = std::cbrt(gap * len * len);
  // Far inside both (an end of either near the other line is a vertex
  // near a segment, not a crossing).
  const double m = std::max(2 * h, kCrossingEnd * len);
  if (!(fa * lab > m && (1 - fa) * lab > m && fc * lcd > m && (1 - fc) * lcd > m)) return;
  // Each segment's chain about the crossing after the splits: the vertices
  // before and after it and the three new points (rounded to doubles from
  // the input segment's ends). Where recovery has already clustered split
  // points about the crossing (within 1.5 h), they stay (removing them
  // fails while they are needed): no change there.
  struct Side {
    uint32_t seg;
    double l, f;
    Vec3 p0, dir;
    std::array<Vec3, 5> chain;
    std::array<double, 3> t;
  };
  std::array<Side, 2> sides = {Side{s, lab, fa, pa, u, {}, {}}, Side{r, lcd, fc, pc, w, {}, {}}};
  for (Side& sd : sides) {
    const double lo = sd.f - h / sd.l, hi = sd.f + h / sd.l;
    sd.t = {lo, sd.f, hi};
    VertexId before = segs_.input[sd.seg][0], after = segs_.input[sd.seg][1];
    for (VertexId x : segs_.chain[sd.seg]) {
      const double tx = segs_.param(sd.seg, x);
      if (std::fabs(tx - sd.f) * sd.l < 1.5 * h) return;
      if (tx < lo && tx > segs_.param(sd.seg, before)) before = x;
      if (tx > hi && tx < segs_.param(sd.seg, after)) after = x;
    }
    sd.chain[0] = to_vec(mesh_.point(before));
    for (int k = 0; k < 3; ++k) sd.chain[k + 1] = sd.p0 + sd.t[k] * sd.dir;
    sd.chain[4] = to_vec(mesh_.point(after));
  }
  // Rounding must not make the two chains meet: two segments in space meet
  // only if their four ends lie in one plane, so every piece of one (the
  // subsegment before the splits too, should a bound stop them halfway)
  // and every piece of the other must be in general position (exact
  // orient3d). Nor may a point cross the plane of a facet at its
  // segment's ends (leaves_side). Otherwise (gaps of a few ulps) nothing
  // changes here.
  auto piece = [](const Side& sd, int i, int k) {
    return i < 4 ? sd.chain[static_cast<size_t>(i + k)] : sd.chain[k == 0 ? 0 : 4];
  };
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) {
      const Vec3 a0 = piece(sides[0], i, 0), a1 = piece(sides[0], i, 1);
      const Vec3 b0 = piece(sides[1], j, 0), b1 = piece(sides[1], j, 1);
      if (pred::orient3d(&a0.x, &a1.x, &b0.x, &b1.x) == 0) return;
    }
  for (const Side& sd : sides)
    for (int k = 1; k <= 3; ++k)
      if (leaves_side(sd.seg, &sd.chain[static_cast<size_t>(k)].x)) return;
  for (const Side& sd : sides)
    for (int k = 0; k < 3; ++k) out.push_back({sd.seg, sd.t[k], 0.25 * h / sd.l, sd.chain[k + 1]});
}

// Whether segment s lies on a facet: a facet is at both of its ends
// (SegmentSet::plane_facets; false when those are not known).
bool SegmentRecovery::on_facet(uint32_t s) const {
  if (segs_.plane_start.empty()) return false;
  const VertexId a = segs_.input[s][0], b = segs_.input[s][1];
  for (uint32_t i = segs_.plane_start[a]; i < segs_.plane_start[a + 1]; ++i)
    for (uint32_t j = segs_.plane_start[b]; j < segs_.plane_start[b + 1]; ++j)
      if (segs_.plane_facets[i] == segs_.plane_facets[j]) return true;
  return false;
}

// Whether the pair of segments s and r is looked at for the first time
// (done_pairs_).
bool SegmentRecovery::first_look(uint32_t s, uint32_t r) {
  const uint64_t key = (static_cast<uint64_t>(std::min(s, r)) << 32) | std::max(s, r);
  return done_pairs_.insert(key).second;
}

// Before recovery: marks the free segments (free_), then splits every pair
// of them that pass within rounding of each other (near_crossing_splits),
// found by a sweep over their boxes along x, so that recovery never
// clusters split points about them (the hooks below catch the rest).
// Skipped beyond kMaxSweptSegments free segments (the sweep is quadratic
// where boxes overlap).
Status SegmentRecovery::split_free_crossings(std::vector<std::array<uint32_t, 3>>& queue) {
  struct Box {
    double lo[3], hi[3];
    uint32_t s;
  };
  free_.assign(segs_.input.size(), 0);
  num_free_ = 0;
  for (uint32_t s = 0; s < segs_.input.size(); ++s)
    if (!on_facet(s)) free_[s] = 1, ++num_free_;
  if (num_free_ == 0 || num_free_ > kMaxSweptSegments) return {};
  std::vector<Box> boxes;
  for (uint32_t s = 0; s < segs_.input.size(); ++s) {
    if (!free_[s]) continue;
    const double* a = mesh_.point(segs_.input[s][0]);
    const double* b = mesh_.point(segs_.input[s][1]);
    Box box;
    box.s = s;
    double len2 = 0;
    for (int k = 0; k < 3; ++k) len2 += (b[k] - a[k]) * (b[k] - a[k]);
    const double pad = kCrossingGap * std::sqrt(len2);
    for (int k = 0; k < 3; ++k)
      box.lo[k] = std::min(a[k], b[k]) - pad, box.hi[k] = std::max(a[k], b[k]) + pad;
    boxes.push_back(box);
  }
  std::sort(boxes.begin(), boxes.end(), [](const Box& x, const Box& y) { return x.lo[0] < y.lo[0]; });
  std::vector<CrossingSplit> splits;
  for (size_t i = 0; i < boxes.size(); ++i)
    for (size_t j = i + 1; j < boxes.size() && boxes[j].lo[0] <= boxes[i].hi[0]; ++j) {
      if (boxes[j].lo[1] > boxes[i].hi[1] || boxes[i].lo[1] > boxes[j].hi[1] ||
          boxes[j].lo[2] > boxes[i].hi[2] || boxes[i].lo[2] > boxes[j].hi[2])
        continue;
      const uint32_t s = std::min(boxes[i].s, boxes[j].s), r = std::max(boxes[i].s, boxes[j].s);
      if (first_look(s, r)) near_crossing_splits(s, r, splits);
    }
  bool any = false;
  return insert_crossing_splits(splits, queue, any);
}

// Before missing subsegment uw of segment s is split: when its encroaching
// vertex lies on a segment r that passes within rounding of s
// (near_crossing_splits), both are split at the near-crossing first, so
// that recovery does not cluster split points about it (both subsegments
// across it must be Delaunay edges, which takes a spacing of about
// sqrt(gap) there, and such a cluster makes flat needles with far
// vertices). Each pair of segments is looked at once.
Status SegmentRecovery::split_crossing_first(uint32_t s, VertexId u, VertexId w,
                                             std::vector<std::array<uint32_t, 3>>& queue,
                                             bool& split_any) {
  split_any = false;
  if (!free_[s]) return {};  // the only ones looked at; most models have none
  VertexId a = u, b = w;
  if (segs_.param(s, a) > segs_.param(s, b)) std::swap(a, b);
  const VertexId p = reference_point(a, b);
  if (p == kNone) return {};
  std::vector<CrossingSplit> splits;
  for_chain_neighbours(p, [&](uint32_t r, VertexId) {
    if (r != s && first_look(s, r)) near_crossing_splits(std::min(s, r), std::max(s, r), splits);
  });
  if (splits.empty()) return {};
  return insert_crossing_splits(splits, queue, split_any);
}

// No numerically flat tets (cdt3d.hpp): two segments that pass within
// rounding of each other without meeting (a valid PLC) are both edges of
// the Delaunay tetrahedralization of their ends, and the tet of those four
// vertices is flat; no flip removes it without removing one of them. Every
// tetrahedralization that holds both subsegments across the near-crossing
// has such a tet, so both are split at their lines' nearest points (the
// short edge between those two points is then an edge of its own) and at
// a spacing h on either side (flat_pair), without the flat-tet moves of
// insert_on_segment: in between the new points make flat tets with the
// other segment until it is split too. The first scan looks at every tet,
// later ones only at tets of vertices inserted since. Bounded
// (kMaxFlatSplits): a flat tet left is counted, not an error.
Status SegmentRecovery::split_flat_pairs(std::vector<std::array<uint32_t, 3>>& queue,
                                         bool& split_any) {
  split_any = false;
  if (num_free_ < 2) return {};  // no pair to look at: no scan of the tets
  std::vector<CrossingSplit> splits;
  if (!flat_scanned_) {
    flat_scanned_ = true;
    for (TetId t = 0; t < mesh_.num_tet_slots(); ++t)
      if (!mesh_.is_dead(t)) flat_pair(t, splits);
  } else {
    std::vector<TetId> star;
    for (VertexId x : since_flat_scan_) {
      if (x >= mesh_.num_vertices()) continue;
      mesh_.vertex_star(x, star);
      for (TetId t : star) flat_pair(t, splits);
    }
  }
  since_flat_scan_.clear();
  return insert_crossing_splits(splits, queue, split_any);
}

// Inserts the split points of near_crossing_splits (sorted along each
// segment, each into the subsegment that holds it, none next to a vertex of
// the chain) and queues what they leave missing.
Status SegmentRecovery::insert_crossing_splits(std::vector<CrossingSplit>& splits,
                                               std::vector<std::array<uint32_t, 3>>& queue,
                                               bool& split_any) {
  std::sort(splits.begin(), splits.end(), [](const CrossingSplit& x, const CrossingSplit& y) {
    return x.segment != y.segment ? x.segment < y.segment : x.t < y.t;
  });
  for (size_t k = 0; k < splits.size(); ++k) {
    const uint32_t s = splits[k].segment;
    const double t = splits[k].t;
    if (k > 0 && splits[k - 1].segment == s && splits[k - 1].t == t) continue;
    if (stats_.flat >= kMaxFlatSplits) break;
    const SegmentChain& chain = segs_.chain[s];
    if (chain.size() - 2 >= kMaxFlatSplitsPerSegment) continue;
    // The subsegment holding t.
    size_t i = 1;
    while (i + 1 < chain.size() && segs_.param(s, chain[i]) <= t) ++i;
    const VertexId u = chain[i - 1], w = chain[i];
    const double tu = segs_.param(s, u), tw = segs_.param(s, w);
    if (!(t - tu > splits[k].margin && tw - t > splits[k].margin)) continue;
    if (Status st = insert_on_segment(s, u, w, splits[k].point, t, kNone, SplitRule::Flat); !st.ok())
      return st;
    queue_halves(s, u, w, queue);
    split_any = true;
  }
  return {};
}


}  // namespace

void SegmentChain::release() {
  if (cap_ > kLocal) delete[] heap_;
  cap_ = kLocal, size_ = 0;
}

void SegmentChain::take(SegmentChain& o) {
  size_ = o.size_, cap_ = o.cap_;
  if (cap_ > kLocal)
    heap_ = o.heap_;
  else
    std::copy(o.local_, o.local_ + o.size_, local_);
  o.size_ = 0, o.cap_ = kLocal;
}

void SegmentChain::move_to_heap(uint32_t cap) {
  VertexId* fresh = new VertexId[cap];
  std::copy(begin(), end(), fresh);
  const uint32_t n = size_;
  release();
  heap_ = fresh, cap_ = cap, size_ = n;
}

void SegmentChain::assign(const VertexId* first, const VertexId* last) {
  const uint32_t n = static_cast<uint32_t>(last - first);
  if (n > cap_) {
    size_ = 0;  // nothing of the old vertices to keep
    move_to_heap(n);
  }
  std::copy(first, last, data());  // first..last is never our own storage here
  size_ = n;
}

void SegmentChain::insert(const VertexId* at, VertexId v) {
  const size_t i = static_cast<size_t>(at - begin());
  if (size_ == cap_) move_to_heap(2 * cap_);
  VertexId* d = data();
  std::copy_backward(d + i, d + size_, d + size_ + 1);
  d[i] = v;
  ++size_;
}

void SegmentChain::erase(const VertexId* at) {
  VertexId* d = data();
  const size_t i = static_cast<size_t>(at - d);
  std::copy(d + i + 1, d + size_, d + i);
  --size_;
}

// Position of v in the chain of segment s, or -1. The endpoints are the
// chain's ends, and a Steiner vertex lies in the chain of its own segment
// only, which answers the many queries for vertices of other segments at
// once. Chains are ordered by parameter, so a binary search finds the spot;
// equal parameters (possible only after rounding on extremely short
// subsegments) fall back to a scan.
long SegmentSet::chain_position(uint32_t s, VertexId v) const {
  const SegmentChain& c = chain[s];
  if (v == input[s][0]) return 0;
  if (v == input[s][1]) return static_cast<long>(c.size()) - 1;
  if (const SegmentVertex* sv = on_segment(v))
    if (sv->segment != s) return -1;
  const double t = param(s, v);
  size_t lo = 0, hi = c.size();
  while (lo < hi) {
    const size_t m = (lo + hi) / 2;
    if (param(s, c[m]) < t)
      lo = m + 1;
    else
      hi = m;
  }
  for (size_t i = lo; i < c.size() && param(s, c[i]) == t; ++i)
    if (c[i] == v) return static_cast<long>(i);
  auto it = std::find(c.begin(), c.end(), v);
  return it == c.end() ? -1 : static_cast<long>(it - c.begin());
}

size_t SegmentSet::num_subsegments() const {
  size_t n = 0;
  for (const auto& c : chain) n += c.size() - 1;
  return n;
}

void SegmentSet::subsegments(std::vector<std::array<uint32_t, 3>>& out) const {
  out.clear();
  for (uint32_t s = 0; s < chain.size(); ++s)
    for (size_t i = 0; i + 1 < chain[s].size(); ++i) out.push_back({chain[s][i], chain[s][i + 1], s});
}

void init_segments(const Plc& plc, SegmentSet& segs) {
  init_segments(plc, segs, plc_segments(plc));
}

void init_segments(const Plc& plc, SegmentSet& segs, std::vector<std::array<VertexId, 2>>&& known) {
  segs = SegmentSet();
  segs.input = std::move(known);
  segs.chain.reserve(segs.input.size());
  for (const auto& e : segs.input) segs.chain.emplace_back(e[0], e[1]);
  segs.midpoint.assign(segs.input.size(), kNone);

  // The planes of the facets at each point (leaves_side), as three of the
  // facet's points that are not collinear (a facet is planar).
  {
    const size_t np = plc.points.size();
    segs.planes.assign(plc.facets.size(), {kNone, kNone, kNone});
    segs.plane_start.assign(np + 1, 0);
    for (size_t f = 0; f < plc.facets.size(); ++f) {
      const Facet& F = plc.facets[f];
      if (F.loops.empty() || F.loops[0].size() < 3) continue;
      const std::vector<VertexId>& L = F.loops[0];
      const double *a = &plc.points[L[0]].x, *b = &plc.points[L[1]].x;
      for (size_t i = 2; i < L.size(); ++i)
        if (!pred::collinear3d(a, b, &plc.points[L[i]].x)) {
          segs.planes[f] = {L[0], L[1], L[i]};
          break;
        }
      if (segs.planes[f][0] == kNone) continue;
      for (const auto& loop : F.loops)
        for (VertexId v : loop) ++segs.plane_start[v + 1];
    }
    for (size_t v = 0; v < np; ++v) segs.plane_start[v + 1] += segs.plane_start[v];
    segs.plane_facets.resize(segs.plane_start[np]);
    std::vector<uint32_t> at(segs.plane_start.begin(), segs.plane_start.end() - 1);
    for (size_t f = 0; f < plc.facets.size(); ++f) {
      if (segs.planes[f][0] == kNone) continue;
      for (const auto& loop : plc.facets[f].loops)
        for (VertexId v : loop) segs.plane_facets[at[v]++] = static_cast<uint32_t>(f);
    }
  }

  // Acute vertices (§5): two incident segments at an angle below 90°, i.e. a
  // positive dot product of their directions (exact sign).
  // The segments' other ends at each point (CSR: one allocation).
  const size_t np = plc.points.size();
  std::vector<uint32_t> start(np + 1, 0);
  for (const auto& e : segs.input) ++start[e[0] + 1], ++start[e[1] + 1];
  for (size_t v = 0; v < np; ++v) start[v + 1] += start[v];
  std::vector<VertexId> ends(start[np]);
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for (const auto& e : segs.input) ends[fill[e[0]]++] = e[1], ends[fill[e[1]]++] = e[0];
  segs.acute.assign(np, 0);
  for (VertexId v = 0; v < np; ++v) {
    const double* pv = &plc.points[v].x;
    const VertexId* n = ends.data() + start[v];
    const size_t count = start[v + 1] - start[v];
    for (size_t i = 0; i < count && !segs.acute[v]; ++i)
      for (size_t j = i + 1; j < count; ++j)
        if (pred::dot_sign(&plc.points[n[i]].x, pv, &plc.points[n[j]].x) > 0) {
          segs.acute[v] = 1;
          break;
        }
  }
}

void missing_subsegments(TetMesh& mesh, const SegmentSet& segs,
                         std::vector<std::array<uint32_t, 3>>& out,
                         const std::vector<uint8_t>* only_at) {
  out.clear();
  auto skip = [only_at](VertexId a, VertexId b) {
    if (!only_at) return false;
    return !(a < only_at->size() && (*only_at)[a] && b < only_at->size() && (*only_at)[b]);
  };
  for (uint32_t s = 0; s < segs.chain.size(); ++s) {
    const auto& c = segs.chain[s];
    for (size_t i = 0; i + 1 < c.size(); ++i)
      if (!skip(c[i], c[i + 1]) && mesh.find_edge(c[i], c[i + 1]) == kNone)
        out.push_back({c[i], c[i + 1], s});
  }
}

Status recover_segments(TetMesh& mesh, SegmentSet& segs, SegmentRecoveryStats* stats,
                        const volatile bool* cancel, SplitMode mode,
                        const std::atomic<bool>* stop) {
  SegmentRecoveryStats local;
  SegmentRecoveryStats& st = stats ? *stats : local;
  st = SegmentRecoveryStats();
  st.segments = segs.input.size();
  for (uint8_t a : segs.acute) st.acute_vertices += a;
  SegmentRecovery rec(mesh, segs, st, mode);
  return rec.run(cancel, stop);
}

}  // namespace cdt3d
