// The carved CDT as the two post-processing steps edit it: quality
// refinement (refine.cpp) inserts points into it, the improvement pass
// (improve.cpp) flips its tets and moves its free vertices.
//
// The Result's tets in a TetMesh without ghost tets; a face with no tet
// beyond it is open (kNoHalfFace). Constrained faces carry a tag per
// half-face (facet + 1, or kHullTag for a boundary face that is no facet, in
// keep-hull domains); subsegments live in a hash map edge -> segment; every
// vertex knows where it lies (input point, on a segment, in a facet, in the
// volume) and its parent segment or facet, so that the Result's Steiner
// kinds survive the round trip.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "geometry.hpp"
#include "status.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

enum class Where : uint8_t { Input, Segment, Facet, Volume };

/// Constraint tag of a half-face: none, a facet (facet + 1), or the open
/// boundary of a keep-hull domain.
inline constexpr uint32_t kNoTag = 0;
inline constexpr uint32_t kHullTag = 0xffffffffu;

struct ConstrainedMesh {
  TetMesh m;
  std::vector<uint32_t> hfc;     ///< per half-face: constraint tag
  std::vector<double> attr;      ///< per tet slot: region attribute
  std::vector<Where> where;      ///< per vertex
  std::vector<int64_t> parent;   ///< per vertex: segment or facet, -1
  std::unordered_map<uint64_t, uint32_t> subseg;  ///< subsegment -> input segment
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
  VertexId new_vertex(const double* p, Where w, int64_t parent_id);

  uint32_t tag(HalfFace hf) const { return hfc[hf]; }
  std::array<VertexId, 3> face_of(HalfFace hf) const {
    const VertexId* t = m.tet_vertices(hf_tet(hf));
    const int i = hf_face(hf);
    return {t[kFaceVertex[i][0]], t[kFaceVertex[i][1]], t[kFaceVertex[i][2]]};
  }
  const double* pt(VertexId v) const { return m.point(v); }
  bool is_subsegment(VertexId a, VertexId b) const { return subseg.count(edge_key(a, b)) != 0; }
  /// The projection axis of facet `tag`'s plane (its Newell normal's largest
  /// component), or of triangle v for a hull face.
  int facet_axis(uint32_t tag, const std::array<VertexId, 3>& v) const;
  /// The tets around edge xy, starting at t0 (which has it): rotates across
  /// the faces through xy one way until the ring closes (then `out` is in
  /// ring order and `closed` is set) or meets the domain boundary, then the
  /// other way from t0. False on a broken mesh.
  bool edge_ring(TetId t0, VertexId x, VertexId y, std::vector<TetId>& out,
                 bool* closed = nullptr) const;
};

}  // namespace cdt3d
