// Mesh quality statistics of a result (floating point; reporting only).
#pragma once

#include <cdt3d/cdt3d.hpp>

namespace cdt3d {

/// Fills min_dihedral, max_dihedral (degrees) and radius_edge_histogram of
/// `stats` from the tets of `mesh`.
void quality_statistics(const TetMeshData& mesh, Statistics& stats);

}  // namespace cdt3d
