// Quality refinement of a carved CDT (after the four steps of Si & Gärtner
// 2005): constrained Delaunay refinement in the manner of Shewchuk
// ("Tetrahedral mesh generation by Delaunay refinement", 1998) and Si
// ("TetGen, a Delaunay-based quality tetrahedral mesh generator", 2015).
// Encroached subsegments are split first, then encroached subfaces, then
// the circumcentres of tets whose radius-edge ratio or volume is too large
// are inserted; a circumcentre that would encroach upon a subsegment or a
// subface is rejected and the encroached constraint split instead. Every
// point goes into the CDT by a constrained Bowyer-Watson insertion (the
// cavity never crosses a constrained face it does not split), so the result
// is a CDT of the PLC refined by the new points.
#pragma once

#include <cdt3d/cdt3d.hpp>

namespace cdt3d {

/// Progress of the refinement, a fraction in [0, 1] (may be empty).
struct RefineProgress {
  void (*report)(void* user, double fraction) = nullptr;
  void* user = nullptr;
};

/// Refines `result` (a carved CDT of `plc` in the numbering of `plc`, as
/// tetrahedralize() builds it) in place: new points are appended as Steiner
/// points (SteinerKind and parent filled), tets, faces, edges and tet
/// attributes are rebuilt. Fills the refine_* and improve_* fields of
/// result.stats. Errors: InvalidArgument for bad options, Cancelled.
Status refine_quality(const Plc& plc, const QualityOptions& quality, const volatile bool* cancel,
                      const RefineProgress& progress, Result& result);

/// Options check shared by the pipeline and the front ends.
Status check_quality_options(const QualityOptions& quality);

}  // namespace cdt3d
