// Mesh quality statistics of a result (floating point; reporting only), and
// the one list of the Statistics fields with the names the outside sees.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <array>
#include <cstddef>

namespace cdt3d {

/// A field of Statistics and its camelCase name in the CLI's `mesh --json`,
/// the WASM bindings' `stats` object and wasm/cdt3d.d.ts (MeshStatistics).
/// Exactly one of the member pointers is set.
struct StatisticsField {
  const char* name;
  size_t Statistics::*count;
  double Statistics::*real;
  std::array<size_t, 10> Statistics::*histogram;
};

/// Every field of Statistics, in declaration order. Adding a field to
/// Statistics means adding it here; tests/unit/test_statistics_fields.cpp
/// then fails until the CLI JSON, the bindings and the d.ts carry it too.
inline constexpr StatisticsField kStatisticsFields[] = {
    {"inputPoints", &Statistics::input_points, nullptr, nullptr},
    {"inputFacets", &Statistics::input_facets, nullptr, nullptr},
    {"inputSegments", &Statistics::input_segments, nullptr, nullptr},
    {"points", &Statistics::points, nullptr, nullptr},
    {"tets", &Statistics::tets, nullptr, nullptr},
    {"faces", &Statistics::faces, nullptr, nullptr},
    {"steinerSegment", &Statistics::steiner_segment, nullptr, nullptr},
    {"steinerFacet", &Statistics::steiner_facet, nullptr, nullptr},
    {"steinerVolume", &Statistics::steiner_volume, nullptr, nullptr},
    {"missingSegments", &Statistics::missing_segments, nullptr, nullptr},
    {"rule1", &Statistics::rule1, nullptr, nullptr},
    {"rule2", &Statistics::rule2, nullptr, nullptr},
    {"rule3", &Statistics::rule3, nullptr, nullptr},
    {"acuteBoth", &Statistics::acute_both, nullptr, nullptr},
    {"splitProjection", &Statistics::split_projection, nullptr, nullptr},
    {"splitShell", &Statistics::split_shell, nullptr, nullptr},
    {"splitRemoved", &Statistics::split_removed, nullptr, nullptr},
    {"maxSplits", &Statistics::max_splits, nullptr, nullptr},
    {"perturbations", &Statistics::perturbations, nullptr, nullptr},
    {"breakPoints", &Statistics::break_points, nullptr, nullptr},
    {"protectSegment", &Statistics::protect_segment, nullptr, nullptr},
    {"protectFacet", &Statistics::protect_facet, nullptr, nullptr},
    {"flatEdges", &Statistics::flat_edges, nullptr, nullptr},
    {"mergedFacets", &Statistics::merged_facets, nullptr, nullptr},
    {"missingSubfaces", &Statistics::missing_subfaces, nullptr, nullptr},
    {"regions", &Statistics::regions, nullptr, nullptr},
    {"cavities", &Statistics::cavities, nullptr, nullptr},
    {"largestCavity", &Statistics::largest_cavity, nullptr, nullptr},
    {"fallbacks", &Statistics::fallbacks, nullptr, nullptr},
    {"facetSplits", &Statistics::facet_splits, nullptr, nullptr},
    {"flatFlips", &Statistics::flat_flips, nullptr, nullptr},
    {"flatPeeled", &Statistics::flat_peeled, nullptr, nullptr},
    {"refineSegment", &Statistics::refine_segment, nullptr, nullptr},
    {"refineFacet", &Statistics::refine_facet, nullptr, nullptr},
    {"refineVolume", &Statistics::refine_volume, nullptr, nullptr},
    {"refineSkipped", &Statistics::refine_skipped, nullptr, nullptr},
    {"refineSmallAngle", &Statistics::refine_small_angle, nullptr, nullptr},
    {"refineCapped", &Statistics::refine_capped, nullptr, nullptr},
    {"improveFlips", &Statistics::improve_flips, nullptr, nullptr},
    {"improveSmooths", &Statistics::improve_smooths, nullptr, nullptr},
    {"improvePoints", &Statistics::improve_points, nullptr, nullptr},
    {"msRead", nullptr, &Statistics::ms_read, nullptr},
    {"msDelaunay", nullptr, &Statistics::ms_delaunay, nullptr},
    {"msSegments", nullptr, &Statistics::ms_segments, nullptr},
    {"msDegeneracy", nullptr, &Statistics::ms_degeneracy, nullptr},
    {"msFacets", nullptr, &Statistics::ms_facets, nullptr},
    {"msCarve", nullptr, &Statistics::ms_carve, nullptr},
    {"msRefine", nullptr, &Statistics::ms_refine, nullptr},
    {"msTotal", nullptr, &Statistics::ms_total, nullptr},
    {"minDihedral", nullptr, &Statistics::min_dihedral, nullptr},
    {"maxDihedral", nullptr, &Statistics::max_dihedral, nullptr},
    {"flatTets", &Statistics::flat_tets, nullptr, nullptr},
    {"radiusEdgeHistogram", nullptr, nullptr, &Statistics::radius_edge_histogram},
    {"dihedralHistogram", nullptr, nullptr, &Statistics::dihedral_histogram},
    {"minDihedralBefore", nullptr, &Statistics::min_dihedral_before, nullptr},
    {"radiusEdgeHistogramBefore", nullptr, nullptr, &Statistics::radius_edge_histogram_before},
    {"dihedralHistogramBefore", nullptr, nullptr, &Statistics::dihedral_histogram_before},
};

/// Fills min_dihedral, max_dihedral (degrees), radius_edge_histogram,
/// dihedral_histogram and flat_tets of
/// `stats` from the tets of `mesh`; `beside`: half of a large mesh on a
/// second thread where there are threads (the same numbers either way).
void quality_statistics(const TetMeshData& mesh, Statistics& stats, bool beside = false);

/// Fills points, tets, faces and the Steiner counts by kind of
/// `result.stats` from the result's arrays.
void size_statistics(Result& result);

}  // namespace cdt3d
