// Carving (after Si & Gärtner 2005 §7 has made every subface a face of the
// mesh): the constrained faces split the tets into regions; the regions
// reached from the outside of the hull or from a volume hole point are
// removed, the others get their region attribute.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <array>
#include <cstdint>
#include <vector>

#include "subfaces.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

struct CarveResult {
  std::vector<TetId> tets;          ///< kept real tets, ascending slot order
  std::vector<double> attribute;    ///< per kept tet: region attribute
  std::vector<std::array<VertexId, 3>> faces;  ///< constrained faces, each subface once, as oriented in Subfaces
  std::vector<uint32_t> face_facet;            ///< input facet per face
  size_t regions = 0;               ///< regions of kept tets
};

/// Removes the exterior and the holes of the CDT `mesh` whose faces include
/// every subface, and labels the regions.
///  * Regions: the live tets (ghosts included) connected across faces that
///    are not subfaces, numbered by their smallest tet slot.
///  * The region holding the ghost tets is outside unless keep_convex_hull
///    (then its real tets are kept). A region holding a volume hole point
///    (plc.holes, located with locate_point; points outside the hull or
///    lying on a vertex are ignored) is removed.
///  * A region point (plc.regions) gives its attribute to its region; when
///    several fall in one region, the first listed wins. Kept regions
///    without a region point get automatic attributes k + 1, k + 2, ... in
///    the order of their smallest tet slot, k being the largest region-point
///    attribute rounded down (at least 0); so without region points they are
///    1, 2, ... (like TetGen -AA).
///  * Flags: kept real tets get kTetInside, every other live tet kTetOutside.
///  * Faces: every subface with a kept tet on at least one side, once, in
///    subface order (a subface listed twice keeps its first occurrence).
/// Errors: Internal naming the facet when a subface is not a face of the
/// mesh; InvalidPlc "the surface does not enclose a volume" when no tet is
/// kept, naming the first open boundary edge (a loop edge used by exactly one
/// facet; Error.facet, Error.vertex = its first end) when there is one.
/// `half_faces` (optional): subface_half_faces of an earlier state of the
/// mesh (facet recovery's result), refreshed instead of recomputed.
Status carve(const Plc& plc, TetMesh& mesh, const Subfaces& subfaces, bool keep_convex_hull,
             CarveResult& out, const std::vector<HalfFace>* half_faces = nullptr);

/// Gives the exterior the numerically flat kept tets that lie in a boundary
/// facet: such a tet has two subfaces of one facet as faces, with outside
/// tets across both; the facet is then triangulated with the tet's other two
/// faces (the other diagonal of the same quadrilateral), never across a
/// subsegment. `carved` is carve()'s result; returns the number of subface
/// pairs changed, after which the caller carves again.
size_t move_flat_tets_outside(const TetMesh& mesh, const SegmentSet& segs,
                              const CarveResult& carved, Subfaces& subfaces);

/// With the convex hull kept (like tetgen -c): gives the exterior the
/// numerically flat kept tets that have a face on the hull which is no
/// subface (where hull vertices lie in one plane or a rounded Steiner point
/// lies next to it, no flip removes them), and then those such a removal
/// exposes, in turn. A tet stays when it is the only kept side of a subface
/// or when the boundary would turn reflex at an exposed face by more than a
/// numerically flat amount (the convexity validate() checks). The hull loses
/// slivers of numerically no volume. Updates the flags and `carved` (tets,
/// attributes); returns the number of tets removed. `half_faces` as in
/// carve().
size_t peel_flat_hull_tets(TetMesh& mesh, const Subfaces& subfaces, CarveResult& carved,
                           const std::vector<HalfFace>* half_faces = nullptr);

}  // namespace cdt3d
