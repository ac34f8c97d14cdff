// Step 3 (Si & Gärtner 2005 §6): remove the local degeneracies of D1 — five
// co-spherical vertices of two adjacent tets, including four coplanar
// co-circular ones — by segment-safe perturbation of Steiner vertices or by
// break points with boundary protection, so that D2 is the unique Delaunay
// tetrahedralization of X2 and contains all segments (Theorem 2).
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <array>
#include <cstdint>
#include <vector>

#include "segment_recovery.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

struct DegeneracyStats {
  size_t initial = 0;          ///< local degeneracies found in D1
  size_t perturbations = 0;    ///< removed by moving a perturbable vertex
  size_t break_points = 0;     ///< volume break points inserted
  size_t protect_segment = 0;  ///< boundary protection points on segments
  size_t protect_facet = 0;    ///< boundary protection points on subfaces
  size_t rounds = 0;           ///< passes of the outer repeat loop
  size_t resplit = 0;          ///< segment points added by re-running segment recovery (§6, step 3)
};

/// A local degeneracy: the vertices of two adjacent real tets (sorted), all
/// on one sphere by the exact, unperturbed insphere test.
using LocalDegeneracy = std::array<VertexId, 5>;

/// Every local degeneracy of `mesh`, each once, in a deterministic order.
void find_local_degeneracies(const TetMesh& mesh, std::vector<LocalDegeneracy>& out);

/// D1 -> D2 (§6, "Local Degeneracy Removal"). Updates `segs` (protection
/// points on segments become Steiner vertices of their segment chains,
/// recovered segments again by recover_segments), appends to
/// facet_interior[f] the points inserted inside facet f (size it to the
/// facet count), and to volume_points the break points (which may end
/// outside the domain; carving removes them with the exterior).
/// Errors: LimitReached naming the degeneracy's vertex when the outer loop
/// does not terminate within its bound, Cancelled.
Status remove_local_degeneracies(const Plc& plc, TetMesh& mesh, SegmentSet& segs,
                                 std::vector<std::vector<VertexId>>& facet_interior,
                                 std::vector<VertexId>& volume_points,
                                 DegeneracyStats* stats = nullptr,
                                 const volatile bool* cancel = nullptr);

}  // namespace cdt3d
