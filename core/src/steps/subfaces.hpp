// The subfaces of X1/X2 (Si & Gärtner 2005 §2, §7): every facet of the PLC as
// a 2D constrained Delaunay triangulation of its vertices — its loop
// vertices, the Steiner vertices now on its boundary segments, and vertices
// added inside it — respecting its loops and holes.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <array>
#include <cstdint>
#include <vector>

#include "segment_recovery.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

struct Subfaces {
  std::vector<std::array<VertexId, 3>> tri;  ///< mesh vertex ids
  std::vector<uint32_t> facet;               ///< input facet index per subface
};

/// Triangulates every facet of `plc` (facet_triangulate.cpp). Loop edges are
/// replaced by the chains of `segs` (a loop edge (a, b) is input segment s
/// with chain a ... b or b ... a). `interior[f]` (optional, may be shorter
/// than the facet count) lists mesh vertices lying inside facet f (isolated
/// points of a .poly facet, protecting points of step 3). Coordinates come
/// from `mesh`. Decisions use exact orientation tests in the coordinate plane
/// that drops the largest component of the facet normal.
///
/// Points and segments of the PLC lying inside a facet (not on its loops)
/// are found and triangulated in, unless `nothing_embedded` says there are
/// none: then a triangle with unsplit edges is its own triangulation without
/// a search. The caller may say so when the PLC passed the exact
/// self-intersection test (a vertex or edge of one facet inside another is
/// an improper intersection there), has no explicit segments (those may lie
/// inside a facet as part of it) and no point outside the facets' loops.
/// `beside`: the second half of a large PLC's facets on a second thread
/// where there are threads (the same subfaces in the same order either way).
Status triangulate_facets(const Plc& plc, const SegmentSet& segs, const TetMesh& mesh,
                          const std::vector<std::vector<VertexId>>& interior, Subfaces& out,
                          bool nothing_embedded = false, bool beside = false);

/// Per subface, a half-face of `mesh` holding it (either side), or kNone
/// when it is not a face of the mesh (facet_recovery.cpp).
void subface_half_faces(const TetMesh& mesh, const Subfaces& sf, std::vector<HalfFace>& out);

/// subface_half_faces for a mesh that changed since `hf` was right (one
/// entry per subface): an entry whose tet is alive and whose face has the
/// subface's vertices stays, the others are looked up around a vertex
/// (TetMesh::find_face). Cheaper than the pass over all tets when few
/// tets changed; with the wrong size, that pass runs instead.
void refresh_subface_half_faces(TetMesh& mesh, const Subfaces& sf, std::vector<HalfFace>& hf);

}  // namespace cdt3d
