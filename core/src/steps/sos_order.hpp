// The vertex order of the symbolic perturbation, chosen for the segments.
//
// Step 1 resolves every co-spherical configuration by the perturbation
// (sos.cpp), ordered by vertex id: among co-spherical points the Delaunay
// tetrahedralization is the placing triangulation in id order, so the edges
// between the first points placed always survive. On CAD and grid models
// many segments (the diagonals of square faces, say) are missing from D0
// only because of that order, and each costs segment recovery (step 2) at
// least one Steiner point. Any order is as valid as any other for the
// theory (the perturbed point set is generic whatever the order), so we
// pick one: a few rounds that put the ends of the segments missing in the
// previous round first, keeping the order with the fewest missing segments
// when it saves at least a tenth of them (a round without progress ends the
// search).
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <array>
#include <cstddef>
#include <functional>
#include <vector>

#include "tet_mesh.hpp"

namespace cdt3d {

struct SosOrderStats {
  size_t rounds = 0;          ///< orders tried (the input order included)
  size_t missing_before = 0;  ///< segments missing from D0 in input order
  size_t missing_after = 0;   ///< ... in the order chosen
  double ms_d0 = 0;           ///< time of the Delaunay tetrahedralization returned in d0
};

/// A vertex order for `plc` (order[k] = the input point that becomes vertex
/// k), or an empty vector when the input order is kept: when D0 needed no
/// perturbation (no co-spherical ties), has no missing segment, or no round
/// saved a tenth of the missing segments. At most `max_rounds` orders are
/// tried; only the input order and the returned one cost a whole Delaunay
/// tetrahedralization, the others retriangulate the co-spherical cells of
/// the first (sos_order.cpp). `d0` gets the Delaunay tetrahedralization of the
/// points in the returned order (or input order), step 1's result, or an
/// empty mesh when step 1 would fail (step 1 then reports why). `segments`,
/// when given, gets plc_segments(plc), which the search computes anyway.
/// `threads`: the whole tetrahedralizations may use a second thread
/// (DelaunayOptions::threads; the same result either way).
/// `ready` (optional): the segments come from elsewhere (the pipeline checks
/// the facets and lists the segments on its second thread meanwhile). The
/// search then builds D0 in input order first, which needs the points alone
/// (they passed check_plc_points), and calls (*ready)(segments) for
/// plc_segments(plc); false from it (the PLC failed its checks) ends the
/// search with an empty order and an empty d0.
using SegmentsWhenReady = std::function<bool(std::vector<std::array<VertexId, 2>>&)>;
std::vector<VertexId> segment_friendly_order(
    const Plc& plc, size_t max_rounds, TetMesh& d0, SosOrderStats* stats = nullptr,
    std::vector<std::array<VertexId, 2>>* segments = nullptr, bool threads = false,
    const SegmentsWhenReady* ready = nullptr);

/// `plc` with its points renumbered: point k of `out` is point order[k] of
/// `plc`; facets, segments, holes and regions follow.
void permute_plc(const Plc& plc, const std::vector<VertexId>& order, Plc& out);

}  // namespace cdt3d
