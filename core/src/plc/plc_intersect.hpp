// Exact detection of improper intersections in a PLC before meshing.
//
// Si & Gärtner 2005 §2 require a PLC to be a cell complex: two cells may meet
// only in a union of common cells. For facets this means two facets may meet
// only in shared vertices and shared loop edges (same vertex ids); anything
// else (crossing, touching, a vertex or edge of one lying on the other
// without being shared, coplanar overlap) makes the input unmeshable, and the
// later phases would fail in obscure ways. This check names the offending
// pairs up front.
#pragma once

#include <cdt3d/cdt3d.hpp>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace cdt3d {

/// How two cells of a PLC meet improperly.
enum class IntersectionKind : uint8_t {
  Cross = 1,            ///< interiors cross (the facets pass through each other)
  CoplanarOverlap = 2,  ///< coplanar facets whose interiors overlap
  VertexInFacet = 3,    ///< touching: a vertex or edge of one lies on the other, not shared
  VertexOnSegment = 4,  ///< a vertex lies inside an explicit segment (or a segment on a loop edge)
  SegmentsCross = 5,    ///< an explicit segment crosses a segment (explicit or a facet's loop edge)
};

/// One improper pair. `a` and `b` are references to cells:
///  - r < plc.facets.size(): facet r;
///  - r >= plc.facets.size(): explicit segment r - plc.facets.size()
///    (index into plc.segments).
/// Always a < b, so a facet comes before a segment.
struct Intersection {
  uint32_t a, b;
  IntersectionKind kind;
};

/// Finds the improper intersections among the facets and explicit segments of
/// `plc` (which must have passed check_plc()) with exact predicates only.
/// Replaces the content of `out` by every improper pair once, sorted
/// by (a, b), at most `limit` pairs (the search stops when it has that many,
/// so a limited result is deterministic but not necessarily the smallest
/// pairs). A pair's kind is the smallest kind seen among its triangle pairs.
///
/// Facets are triangulated in their own plane (ear clipping; loops nested in
/// a loop are bridged in as holes, and triangulated on their own unless a
/// facet hole point marks them). An explicit segment lying inside a facet
/// (as TetGen's 2-vertex polygons in a .poly facet) is part of that facet:
/// its endpoints count as vertices of the facet and the segment as one of its
/// edges, so a dangling facet may stand on it. Unreferenced (isolated) points
/// are not checked.
void find_self_intersections(const Plc& plc, std::vector<Intersection>& out,
                             size_t limit = SIZE_MAX);

/// ErrorCode::SelfIntersection naming the first pair (facet / other_facet, or
/// segment in plc_segments() order for a segment), with a message listing the
/// first few pairs and the total count; ok() when `found` is empty.
Status self_intersection_error(const Plc& plc, const std::vector<Intersection>& found);

}  // namespace cdt3d
