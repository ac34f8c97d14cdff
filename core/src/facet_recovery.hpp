// Step 4 (Si & Gärtner 2005 §7): recover the subfaces of X2 in D2 by cavity
// retetrahedralization, turning D2 into the constrained Delaunay
// tetrahedralization of X2.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <cstdint>
#include <vector>

#include "subfaces.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

struct FacetRecoveryStats {
  size_t subfaces = 0;
  size_t missing_initially = 0;   ///< subfaces not in D2
  size_t regions = 0;             ///< missing regions recovered
  size_t cavities = 0;            ///< cavities retetrahedralized
  size_t expansions = 0;          ///< cavity expansion steps
  size_t largest_cavity = 0;      ///< most faces of one cavity
  size_t fallbacks = 0;           ///< regions recovered by the documented fallback
  size_t steiner_points = 0;      ///< points added by the fallback (if any)
};

/// Makes every subface a face of `mesh`. On success `mesh` is a valid
/// tetrahedralization of the same hull containing every subface (and still
/// every subsegment). A fallback that adds a Steiner point splits the
/// subfaces it lies on (they are updated in place). Errors: Internal naming the facet when a region cannot
/// be recovered, Cancelled when *cancel becomes true.
Status recover_facets(TetMesh& mesh, Subfaces& subfaces, FacetRecoveryStats* stats = nullptr,
                      const volatile bool* cancel = nullptr);

}  // namespace cdt3d
