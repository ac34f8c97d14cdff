// The carved CDT as the two post-processing steps edit it: quality
// refinement (refine.cpp) inserts points into it, the improvement pass
// (improve.cpp) flips its tets and moves its free vertices.
//
// The Result's tets in a TetMesh without ghost tets; a face with no tet
// beyond it is open (kNoHalfFace). Constrained faces carry a tag per
// half-face (facet + 1, or a hull tag for a boundary face that is no facet,
// in keep-hull domains: one per plane of the hull); subsegments live in a
// hash map edge -> segment; every vertex knows where it lies (input point,
// on a segment, in a facet, in the volume) and its parent segment or facet,
// so that the Result's Steiner kinds survive the round trip.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <array>
#include <cstdint>
#include <vector>

#include "geometry.hpp"
#include "status.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

enum class Where : uint8_t { Input, Segment, Facet, Volume };

/// Constraint tag of a half-face: none, a facet (facet + 1), or the open
/// boundary of a keep-hull domain: kHullTag + k for its k-th plane (the
/// open faces of one plane, exactly coplanar and connected across edges).
/// A split of a hull face grows only within its plane: across a hull edge
/// between two planes lies a face a point of this one is not on.
inline constexpr uint32_t kNoTag = 0;
inline constexpr uint32_t kHullTag = 0x80000000u;
inline bool is_hull_tag(uint32_t tag) { return tag >= kHullTag; }

/// Map from edge keys (edge_key) to input segments: open addressing with
/// linear probing, a power-of-two table at most half full, backward-shift
/// erase. Subsegment lookups are the most frequent map queries of
/// refinement; std::unordered_map spends a division and a pointer chase on
/// each.
class EdgeMap {
 public:
  /// The segment of edge `key`, or nullptr.
  const uint32_t* find(uint64_t key) const {
    if (keys_.empty()) return nullptr;
    for (size_t i = slot(key);; i = (i + 1) & mask_) {
      if (keys_[i] == key) return &values_[i];
      if (keys_[i] == kEmpty) return nullptr;
    }
  }
  bool contains(uint64_t key) const { return find(key) != nullptr; }
  void set(uint64_t key, uint32_t value);
  void erase(uint64_t key);
  size_t size() const { return size_; }
  /// Calls f(key, segment) for every entry, in table order.
  template <class F>
  void for_each(F f) const {
    for (size_t i = 0; i < keys_.size(); ++i)
      if (keys_[i] != kEmpty) f(keys_[i], values_[i]);
  }

 private:
  static constexpr uint64_t kEmpty = ~uint64_t(0);  // no edge_key: ids stay below 2^32 - 1
  size_t slot(uint64_t key) const {
    return static_cast<size_t>((key * 0x9e3779b97f4a7c15ull) >> shift_) & mask_;
  }
  void grow();
  std::vector<uint64_t> keys_;
  std::vector<uint32_t> values_;
  size_t size_ = 0, mask_ = 0;
  int shift_ = 64;
};

struct ConstrainedMesh {
  TetMesh m;
  std::vector<uint32_t> hfc;     ///< per half-face: constraint tag
  std::vector<double> attr;      ///< per tet slot: region attribute
  std::vector<Where> where;      ///< per vertex
  std::vector<int64_t> parent;   ///< per vertex: segment or facet, -1
  EdgeMap subseg;                                 ///< subsegment -> input segment
  std::vector<int8_t> facet_drop;                 ///< per facet: projection axis
  std::vector<int8_t> facet_side;                 ///< per facet: orientation of its output faces
  size_t old_points = 0;                          ///< points of the Result it was built from

  /// Builds the mesh from a carved Result of `plc`. Internal error when a
  /// face is shared by three tets (a broken Result).
  Status build(const Plc& plc, const Result& res);
  /// Writes tets, constrained faces, subsegments and the new points' Steiner
  /// kinds back into `res` and updates its size and Steiner counts.
  void write(const Plc& plc, Result& res) const;

  /// A live tet slot with the per-slot arrays grown to match, tags cleared.
  TetId new_tet();
  /// Grows the per-slot arrays after TetMesh calls that allocate by
  /// themselves (replace_tets); new slots get kNoTag.
  void sync_slots();
  /// Replaces the live tets `old`, all of one region, by `fresh`, which
  /// fill the same region: the tags of its outer faces carry over, the fresh
  /// tets (in `created`) inherit the region attribute. False, with nothing
  /// changed, across a region border or when the TetMesh refuses.
  bool replace_region(const std::vector<TetId>& old,
                      const std::vector<std::array<VertexId, 4>>& fresh,
                      std::vector<TetId>& created);
  VertexId new_vertex(const double* p, Where w, int64_t parent_id);
  /// Takes back the last new_vertex() while no tet uses it yet.
  void drop_last_vertex();

  uint32_t tag(HalfFace hf) const { return hfc[hf]; }
  std::array<VertexId, 3> face_of(HalfFace hf) const {
    const VertexId* t = m.tet_vertices(hf_tet(hf));
    const int i = hf_face(hf);
    return {t[kFaceVertex[i][0]], t[kFaceVertex[i][1]], t[kFaceVertex[i][2]]};
  }
  const double* pt(VertexId v) const { return m.point(v); }
  /// Only input points and points on segments end subsegments: the test of
  /// where[] spares most hash lookups.
  bool is_subsegment(VertexId a, VertexId b) const {
    return where[a] <= Where::Segment && where[b] <= Where::Segment &&
           subseg.contains(edge_key(a, b));
  }
  /// The projection axis of facet `tag`'s plane (its Newell normal's largest
  /// component), or of triangle v for a hull face.
  int facet_axis(uint32_t tag, const std::array<VertexId, 3>& v) const;
  /// The tets around edge xy, starting at t0 (which has it): rotates across
  /// the faces through xy one way until the ring closes (then `out` is in
  /// ring order and `closed` is set) or meets the domain boundary, then the
  /// other way from t0. False on a broken mesh.
  bool edge_ring(TetId t0, VertexId x, VertexId y, std::vector<TetId>& out,
                 bool* closed = nullptr) const;

 private:
  std::vector<std::pair<std::array<VertexId, 3>, uint32_t>> outer_;  // replace_region's scratch
  void tag_hull_planes(const std::vector<std::pair<std::array<VertexId, 3>, HalfFace>>& keys);
};

}  // namespace cdt3d
