// Step 2 (Si & Gärtner 2005 §5): make every segment of the PLC an edge of the
// Delaunay tetrahedralization by splitting missing segments, by default at
// the projection of §5's reference point (or on a protecting sphere around a
// shared endpoint), with §5's rules 1-3 as the fallback and as the paper
// mode (SplitMode), then removing split points that became redundant. The
// result D1 is still Delaunay (points are inserted by Bowyer–Watson and
// removed by retriangulating their stars) and X1 is recorded here: every
// input segment as a chain of vertices.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "tet_mesh.hpp"

namespace cdt3d {

/// How a Steiner point on a segment was placed.
enum class SplitRule : uint8_t {
  Rule1 = 1,      ///< type-1 segment (§5 rule 1)
  Rule2 = 2,      ///< type-2 segment, sphere around the acute vertex (rule 2)
  Rule3 = 3,      ///< type-2 segment after rule 2 was rejected (rule 3)
  AcuteBoth = 4,  ///< midpoint of a segment whose two ends are acute (§5)
  Protect = 5,    ///< boundary protection point (step 3, §6)
  Projection = 6, ///< projection of the reference point, or midpoint (SplitMode::Projection)
  Shell = 7,      ///< on the sphere around a shared endpoint through the reference point
  Flat = 8,       ///< at or beside the nearest points of two segments within rounding (split_flat_pairs)
};

/// Where step 2 splits a missing subsegment.
enum class SplitMode : uint8_t {
  /// The default (Statistics::split_projection says how): projection of the
  /// reference point, or a protecting sphere around a shared endpoint; rules
  /// 1-3 once a segment has kMaxProjectionSplits points; then redundant split
  /// points are removed.
  Projection,
  /// §5's rules 1-3 only, as published (with DegeneracyMode::Paper).
  Rules,
};

/// What is known about a Steiner vertex that lies on an input segment. Its
/// coordinates are rounded to doubles, so it is not exactly on the segment's
/// line; every later decision about "which segment is this vertex on" uses
/// this record, never coordinates.
struct SegmentVertex {
  VertexId vertex = kNone;
  uint32_t segment = 0;   ///< input segment (index into SegmentSet::input)
  double t = 0;           ///< intended parameter in (0, 1) from input[segment][0]
  VertexId origin = kNone;  ///< O(v): the acute vertex of a type-2 split, else kNone
  SplitRule rule = SplitRule::Rule1;
};

/// The vertices on one input segment, in order from its first endpoint to
/// its second. Most segments are never split or split once or twice, so up
/// to four vertices live in the object itself: one small vector per segment
/// would cost an allocation and a free per segment of every SegmentSet,
/// slow under WebAssembly, whose malloc takes a lock.
class SegmentChain {
 public:
  SegmentChain(VertexId a, VertexId b) : size_(2) { local_[0] = a, local_[1] = b; }
  SegmentChain(const SegmentChain& o) { assign(o.begin(), o.end()); }
  SegmentChain(SegmentChain&& o) noexcept { take(o); }
  SegmentChain& operator=(const SegmentChain& o) {
    if (this != &o) assign(o.begin(), o.end());
    return *this;
  }
  SegmentChain& operator=(SegmentChain&& o) noexcept {
    if (this != &o) release(), take(o);
    return *this;
  }
  ~SegmentChain() { release(); }

  /// Replaces the vertices by [first, last).
  void assign(const VertexId* first, const VertexId* last);
  size_t size() const { return size_; }
  VertexId* begin() { return data(); }
  VertexId* end() { return data() + size_; }
  const VertexId* begin() const { return data(); }
  const VertexId* end() const { return data() + size_; }
  VertexId& operator[](size_t i) { return data()[i]; }
  VertexId operator[](size_t i) const { return data()[i]; }
  VertexId front() const { return data()[0]; }
  VertexId back() const { return data()[size_ - 1]; }
  /// Inserts v before `at` (a position in [begin, end]).
  void insert(const VertexId* at, VertexId v);
  /// Removes the vertex at `at`.
  void erase(const VertexId* at);
  /// The vertices as a vector (tests).
  std::vector<VertexId> to_vector() const { return {begin(), end()}; }

 private:
  static constexpr uint32_t kLocal = 4;
  VertexId* data() { return cap_ > kLocal ? heap_ : local_; }
  const VertexId* data() const { return cap_ > kLocal ? heap_ : local_; }
  void release();
  void take(SegmentChain& o);
  void move_to_heap(uint32_t cap);  // cap >= size_, the vertices kept
  uint32_t size_ = 0, cap_ = kLocal;
  union {
    VertexId local_[kLocal];
    VertexId* heap_;
  };
};

/// The segments of X1: each input segment of plc_segments() order and the
/// vertices now on it, ordered from its first to its second endpoint.
struct SegmentSet {
  std::vector<std::array<VertexId, 2>> input;
  std::vector<SegmentChain> chain;           ///< per input segment, >= 2 vertices
  std::vector<uint8_t> acute;                ///< per PLC point: acute vertex (§5)
  std::vector<VertexId> midpoint;            ///< per input segment: AcuteBoth split, or kNone
  std::vector<SegmentVertex> steiner;        ///< Steiner vertices on segments, in insertion order
  std::vector<uint32_t> steiner_of;          ///< per mesh vertex: index into steiner, or kNone
  /// The plane of each facet (three PLC points that are not collinear; kNone
  /// for a facet without one), and per PLC point p the facets at p:
  /// plane_facets[plane_start[p] .. plane_start[p + 1]). Empty when unknown
  /// and after segment recovery (release_planes). A rounded split point must
  /// stay on its segment's side of them (see insert_on_segment).
  std::vector<std::array<VertexId, 3>> planes;
  std::vector<uint32_t> plane_start;
  std::vector<uint32_t> plane_facets;

  /// Frees the planes once no segment is split by recover_segments any more
  /// (12 bytes per facet and 4 per facet corner: 240 MB on a 10M-triangle
  /// surface, which would otherwise stay through steps 4 and 5).
  void release_planes() {
    std::vector<std::array<VertexId, 3>>().swap(planes);
    std::vector<uint32_t>().swap(plane_start);
    std::vector<uint32_t>().swap(plane_facets);
  }

  /// The record of vertex v if it is a Steiner vertex on a segment, else null.
  const SegmentVertex* on_segment(VertexId v) const {
    return v < steiner_of.size() && steiner_of[v] != kNone ? &steiner[steiner_of[v]] : nullptr;
  }

  /// Parameter of v along input segment s (0 at its first endpoint, 1 at
  /// the second): the recorded intended value for Steiner vertices, never
  /// one computed from their rounded coordinates.
  double param(uint32_t s, VertexId v) const {
    if (v == input[s][0]) return 0;
    if (v == input[s][1]) return 1;
    const SegmentVertex* sv = on_segment(v);
    return sv ? sv->t : 0.5;  // chains hold only endpoints and recorded vertices
  }
  /// Position of v in the chain of segment s, or -1.
  long chain_position(uint32_t s, VertexId v) const;

  /// Number of current subsegments.
  size_t num_subsegments() const;
  /// All current subsegments as (a, b, input segment).
  void subsegments(std::vector<std::array<uint32_t, 3>>& out) const;
};

struct SegmentRecoveryStats {
  size_t segments = 0;         ///< input segments
  size_t acute_vertices = 0;
  size_t missing_initially = 0;  ///< segments missing from D0
  size_t rule1 = 0, rule2 = 0, rule3 = 0, acute_both = 0;
  size_t max_splits = 0;       ///< largest number of points added on one input segment
  size_t rounds = 0;           ///< passes of the outer repeat loop
  size_t flat_moves = 0;       ///< split points moved so as not to make a flat tet
                               ///< or cross a facet plane at their segment's ends
  size_t projection = 0, shell = 0;  ///< SplitMode::Projection's splits
  size_t removed = 0;          ///< split points removed again as redundant
  /// Split points at and beside the nearest points of two segments that
  /// pass within rounding of each other (a numerically flat tet between).
  size_t flat = 0;
  /// Split points left on the segments.
  size_t points() const { return rule1 + rule2 + rule3 + acute_both + projection + shell + flat - removed; }
};

/// Builds the SegmentSet of `plc` (all segments unsplit) and marks acute
/// vertices: a vertex is acute when two of its segments meet at an angle
/// smaller than 90° (exact sign of the dot product).
void init_segments(const Plc& plc, SegmentSet& segs);
/// The same with plc_segments(plc) already computed (`known`, moved from).
void init_segments(const Plc& plc, SegmentSet& segs, std::vector<std::array<VertexId, 2>>&& known);

/// Recovers every segment of `segs` in `mesh`, a Delaunay tetrahedralization
/// whose vertex i is PLC point i (§5, "Delaunay segments recovery"). Inserted
/// vertices get kind kVertexSteiner and a SegmentVertex record.
/// Errors: InvalidPlc when a vertex lies on a segment (the split point would
/// coincide with it), LimitReached when one segment needs too many splits,
/// Cancelled when *cancel or *stop becomes true (the caller's flag and the
/// pipeline's own: the self-intersection test beside it found a pair).
/// Errors name the segment.
Status recover_segments(TetMesh& mesh, SegmentSet& segs, SegmentRecoveryStats* stats = nullptr,
                        const volatile bool* cancel = nullptr,
                        SplitMode mode = SplitMode::Projection,
                        const std::atomic<bool>* stop = nullptr);

/// Subsegments of `segs` that are not edges of `mesh` (a, b, input segment).
/// With `only_at`, only subsegments with both ends v where (*only_at)[v] is
/// nonzero are looked at.
void missing_subsegments(TetMesh& mesh, const SegmentSet& segs,
                         std::vector<std::array<uint32_t, 3>>& out,
                         const std::vector<uint8_t>* only_at = nullptr);

}  // namespace cdt3d
