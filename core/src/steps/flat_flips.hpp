// Removal of numerically flat tets from the output of step 4 by flips.
//
// Why: a Steiner point is rounded to doubles (§5), so four vertices that lie
// in one plane in exact geometry (a facet plane through other input
// vertices, points placed symmetrically on parallel segments) can end up a
// few ulps off it, and the exact Delaunay or constrained Delaunay
// tetrahedralization of the rounded points then holds a tet of almost no
// volume. Such a tet is not usable (cdt3d.hpp, kFlatTetRatio). The exact
// constrained Delaunay property holds only because of those few ulps, so we
// give it up there: the flat tet is replaced by a 2-3 flip across one of its
// faces or by an edge removal (3-2, 4-4, 5-6) around one of its edges,
// whichever leaves the fattest tets, never across a subface and never
// removing a subsegment. validate() accepts the faces such flips leave
// (see its check 9).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "segment_recovery.hpp"
#include "subfaces.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

struct FlatFlipStats {
  size_t flat_before = 0;  ///< numerically flat real tets found
  size_t flips = 0;        ///< flips done
  size_t remaining = 0;    ///< flat real tets left (no valid flip found)
};

/// Flips numerically flat real tets of `mesh` away (see above). Keeps every
/// subface of `subfaces` and every subsegment of `segs` in the mesh.
/// With `kept` (per tet slot: nonzero for the tets carving keeps), only
/// those are flipped and counted, and the tets a flip creates are marked in
/// it: a flip never crosses a subface, so its new tets fill the region of its
/// old ones, and the tets carving removes (on CAD models, most of the flat
/// ones: coplanar vertices of the hull's pockets) need no flips.
void remove_flat_tets(TetMesh& mesh, const Subfaces& subfaces, const SegmentSet& segs,
                      FlatFlipStats* stats = nullptr, std::vector<uint8_t>* kept = nullptr);

}  // namespace cdt3d
