// The improvement pass after quality refinement (QualityOptions::
// min_dihedral): local changes that raise the smallest dihedral angle of the
// tets, like TetGen's -O, within the same exact predicates.
//
// Delaunay refinement bounds the radius-edge ratio, which does not rule out
// slivers: four nearly coplanar points with a good radius-edge ratio, on the
// boundary (two subfaces of nearly coplanar facets) and inside. They go by
// three operations, each done only when it raises the smallest dihedral
// angle of the tets it touches:
//  * edge removal: the ring of tets around an edge that is no subsegment and
//    lies in no facet is replaced by the best triangulation of the ring's
//    polygon joined to the edge's ends (dynamic programming over the
//    polygon's triangulations; the 3-2 and 4-4 flips are its smallest cases;
//    Shewchuk, "Two discrete optimization algorithms for the topological
//    improvement of tetrahedral meshes", 2002);
//  * the 2-3 flip across a face that is not constrained;
//  * smoothing: a free vertex (a Steiner point inside the volume, on no
//    constrained face) moves towards the centre of its star, or away from
//    the face opposite it in its worst tet; a Steiner point on a facet whose
//    plane is perpendicular to an axis slides in that plane (its subfaces
//    stay exactly in the facet), which slivers across thin plates need;
//  * as the last resort, a new vertex inside the union of the tet and its
//    neighbours across unconstrained faces (a Steiner point in the volume);
//    for a tet below 10 degrees that none of the fixed candidate points
//    raises, a compass search from the best of them, then one that adds
//    fewer tets above radius-edge ratio 2 (at needles, where the tets are
//    slivers of the input's making, only a point that leaves no more tets
//    below 10 degrees than it replaces).
// When no tet is left below the target, edge removals and 2-3 flips at the
// worst tets of the mesh go on raising its smallest angle (a small mesh
// meets the target at once).
// Fixes of tets at or above 10 degrees must not add tets above radius-edge
// ratio 2 (refinement's work) unless they lower the largest ratio there.
// After the rounds, vertices of the tets left above ratio 2 move (freely or
// sliding) where fewer such tets are left around them, making no new
// sliver; then 2-3 flips and edge removals at the tets still above it
// replace tets by fewer such ones, none below the target or the smallest
// angle they replace.
// A new tet must be positive by the exact orientation test and not
// numerically flat; constrained faces and subsegments are never removed, so
// the mesh stays a constrained tetrahedralization of the PLC (every facet
// and segment still covered), but no longer a Delaunay one.
#pragma once

#include <cstddef>
#include <utility>
#include <vector>

#include "constrained_mesh.hpp"
#include "status.hpp"

namespace cdt3d {

struct ImproveCounts {
  size_t flips = 0;    ///< edge removals and 2-3 flips done
  size_t smooths = 0;  ///< vertex moves done
  size_t inserts = 0;  ///< vertices added (Where::Volume)
};

/// Progress of the pass, reported as from + (to - from) * (its fraction).
struct ImproveProgress {
  void (*report)(void* user, double fraction) = nullptr;
  void* user = nullptr;
  double from = 0, to = 1;
};

/// Volume bounds of refinement the pass's final flips keep (a tet of
/// region attribute a stays within the smallest of max_volume and the
/// limits of a in regions; -1 and no entry: none).
struct VolumeBounds {
  double max_volume = -1;
  std::vector<std::pair<double, double>> regions;  ///< (attribute, max volume)
};

/// Raises the smallest dihedral angle of cm's tets towards `target`
/// degrees. `needle` (optional): per vertex, 1 on a side or at the apex of
/// a needle (refine.cpp), where a new vertex found by search must not add
/// tets below 10 degrees. Errors: Cancelled when *cancel becomes true.
Status improve_mesh(ConstrainedMesh& cm, double target, const volatile bool* cancel,
                    ImproveCounts& counts, const ImproveProgress& progress = {},
                    const VolumeBounds& bounds = {}, const std::vector<char>* needle = nullptr);

}  // namespace cdt3d
