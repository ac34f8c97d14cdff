// Flat-face merging (merge_flat_facets in the public header), with what the
// pipeline needs to know of the merged facets' insides.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <vector>

namespace cdt3d {

/// What lies inside the merged facets besides their loops.
struct FlatFaceInsides {
  /// Per facet of the merged PLC: the input vertices of its input facets
  /// that lie on none of its loops (strictly inside the flat face).
  std::vector<std::vector<VertexId>> vertices;
  /// Edges inside some merged facet that stay segments (a third facet or
  /// an explicit segment uses them).
  size_t segments = 0;
};

/// merge_flat_facets(), and the insides of the merged facets when `insides`
/// is given; then, when no edge is flat, `out` is left empty (the input is
/// its own merge) and merged_into is the identity.
size_t merge_flat_facets(const Plc& plc, Plc& out, std::vector<uint32_t>& merged_into,
                         size_t* flat_edges, FlatFaceInsides* insides);

}  // namespace cdt3d
