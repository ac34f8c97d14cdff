// Step 4 (Si & Gärtner 2005 §7): recover the subfaces of X2 in D2 by cavity
// retetrahedralization, turning D2 into the constrained Delaunay
// tetrahedralization of X2.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <array>
#include <atomic>
#include <cstdint>
#include <vector>

#include "subfaces.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

/// Statistics of recover_facets (also filled when it fails: what was done).
struct FacetRecoveryStats {
  size_t subfaces = 0;
  size_t missing_initially = 0;   ///< subfaces not in D2 (after subface_flips)
  size_t regions = 0;             ///< missing regions recovered
  size_t cavities = 0;            ///< cavities retetrahedralized (two per region, usually)
  size_t expansions = 0;          ///< tets taken in by cavity expansion (§7 step 1)
  size_t largest_cavity = 0;      ///< most faces of one cavity
  size_t fallbacks = 0;           ///< regions recovered by a fallback (see recover_facets)
  size_t steiner_points = 0;      ///< points added by a fallback (none so far: no such fallback)
  size_t subface_flips = 0;       ///< facet diagonals flipped first (flip_subfaces_toward_mesh)
  /// On failure: a subface that could not be recovered (vertex ids) and its
  /// facet, or kNone. The pipeline inserts a Steiner point inside it and
  /// starts again (Options: never fail on a valid PLC).
  std::array<VertexId, 3> unrecovered = {kNone, kNone, kNone};
  uint32_t unrecovered_facet = kNone;
};

/// The first pass of recover_facets. For an edge of the subfaces that is
/// missing from the mesh and is not a segment (two subfaces of one facet
/// share it), the diagonal of their quadrilateral is flipped when
///  * the four points are exactly co-circular and the symbolic perturbation
///    of the mesh (ordered by vertex id) prefers the other diagonal, or
///  * the quadrilateral is strictly convex and the fourth point lies inside
///    the circle of a subface in the facet's own plane (a triangulation that
///    is Delaunay only in a projection to a coordinate plane), or
///  * the quadrilateral is strictly convex and the mesh already holds the
///    two other triangles (nearly planar facets: rounded Steiner vertices).
/// The subfaces still triangulate the same facet regions. Returns the number
/// of flips; `subfaces` is updated in place.
size_t flip_subfaces_toward_mesh(TetMesh& mesh, Subfaces& subfaces);

/// Makes every subface a face of `mesh`. On success `mesh` is a valid
/// tetrahedralization of the same hull containing every subface (and still
/// every subsegment); subfaces may have been flipped in place (see
/// flip_subfaces_toward_mesh). Missing regions are recovered by cavity
/// retetrahedralization (cavity.hpp); subfaces destroyed meanwhile are queued
/// again. Fallbacks, counted in stats.fallbacks:
///  1. inside a region: a cavity whose subface of Ω (or another face that
///     must not be expanded across) is missing from its Delaunay
///     tetrahedralization keeps the Delaunay tets away from it and fills the
///     rest by constrained gift-wrapping (the cavity.hpp fallback). The mesh
///     stays a valid constrained tetrahedralization; it can miss the
///     constrained Delaunay property by rounding near folds of facets made
///     nearly planar by rounded Steiner vertices;
///  2. a region whose recovery fails is restored (the mesh is only changed
///     by a successful recovery) and retried after the rest of the queue,
///     then subface by subface.
/// Errors name the facet: Internal when a subface still cannot be recovered
/// (no Steiner point fallback is implemented), LimitReached when a bound is
/// reached, Cancelled when *cancel becomes true; InvalidArgument or
/// DegenerateFacet for bad subfaces.
/// `force_failure` (tests): the first missing region counts as
/// unrecoverable without trying, as if both cavity retetrahedralization and
/// gift-wrapping had failed on it.
/// On success `half_faces` (optional) gets subface_half_faces of the mesh
/// before recovery (right for the subfaces that were present then and whose
/// tets no cavity took): input for refresh_subface_half_faces.
/// `beside`: the first pass may use a second thread (beside.hpp); the
/// result is the same either way. `stop` (optional) ends the recovery like
/// *cancel once it becomes true (the pipeline's self-intersection test
/// found a pair).
Status recover_facets(TetMesh& mesh, Subfaces& subfaces, FacetRecoveryStats* stats = nullptr,
                      const volatile bool* cancel = nullptr, bool force_failure = false,
                      std::vector<HalfFace>* half_faces = nullptr, bool beside = false,
                      const std::atomic<bool>* stop = nullptr);

}  // namespace cdt3d
