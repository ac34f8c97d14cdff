// The perturbation order chosen for the segments (sos_order.hpp).
#include "sos_order.hpp"

#include <algorithm>
#include <cstdint>

#include "delaunay.hpp"
#include "geometry.hpp"
#include "predicates.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

namespace {

// Up to this many missing segments the search moves one segment at a time.
constexpr size_t kFewMissing = 16;

// Segments of `plc` (input ids) missing from the Delaunay tetrahedralization
// of its points renumbered by `order`; their ends go to `ends` (two per
// missing segment, in segment order). Sets *ties when the perturbation
// decided anything.
size_t missing_segments(const Plc& plc, const std::vector<std::array<VertexId, 2>>& segs,
                        const std::vector<VertexId>& order, std::vector<VertexId>& ends,
                        bool* ties, TetMesh& mesh) {
  const size_t n = plc.points.size();
  std::vector<double> xyz(3 * n);
  std::vector<VertexId> id_of(n);
  for (size_t k = 0; k < n; ++k) {
    const Vec3& p = plc.points[order[k]];
    xyz[3 * k] = p.x, xyz[3 * k + 1] = p.y, xyz[3 * k + 2] = p.z;
    id_of[order[k]] = static_cast<VertexId>(k);
  }
  const uint64_t ties_before = pred::counters().sos_ties;
  if (!delaunay_tetrahedralize(mesh, xyz.data(), n).ok()) return SIZE_MAX;
  if (ties) {
    *ties = pred::counters().sos_ties != ties_before;
    if (!*ties) return 0;  // no order does better: skip the count
  }
  ends.clear();
  size_t missing = 0;
  for (const auto& e : segs) {
    if (mesh.find_edge(id_of[e[0]], id_of[e[1]]) != kNone) continue;
    ++missing;
    ends.push_back(e[0]), ends.push_back(e[1]);
  }
  return missing;
}

}  // namespace

std::vector<VertexId> segment_friendly_order(const Plc& plc, size_t max_rounds,
                                             TetMesh& d0, SosOrderStats* stats) {
  SosOrderStats local;
  SosOrderStats& st = stats ? *stats : local;
  st = SosOrderStats();
  const size_t n = plc.points.size();
  const auto segs = plc_segments(plc);
  std::vector<VertexId> order(n), best, ends, best_ends;
  TetMesh best_mesh;
  for (size_t k = 0; k < n; ++k) order[k] = static_cast<VertexId>(k);
  bool ties = false;
  size_t fewest = missing_segments(plc, segs, order, ends, &ties, d0);
  st.rounds = 1;
  st.missing_before = st.missing_after = fewest;
  if (fewest == SIZE_MAX) {
    d0 = TetMesh();
    return {};
  }
  if (!ties || fewest == 0) return {};
  // Each round: the ends of the segments just found missing first (by
  // segment, so both ends of one segment are placed together), then the
  // others in their previous order.
  std::vector<uint8_t> front(n);
  size_t best_round = 0;
  TetMesh trial;
  std::vector<VertexId> first;
  bool few = false;
  for (size_t round = 1; round < max_rounds; ++round) {
    // First all ends of the missing segments first, while that pays; then,
    // when few are left, one segment's ends first, taking the missing
    // segments in turn from the best order so far (the batch move tends to
    // trade one co-circular diagonal for another there).
    if (!few && round > best_round + 1) {
      if (fewest > kFewMissing) break;
      few = true, best_round = round - 1;  // the batch moves stopped paying
    }
    if (few && round > best_round + 3) break;
    if (few && round == best_round + 1 && !best.empty()) order = best, ends = best_ends;
    first.clear();
    if (few) {
      const size_t pairs = ends.size() / 2;
      if (pairs == 0) break;
      const size_t k = (round - best_round - 1) % pairs;
      first = {ends[2 * k], ends[2 * k + 1]};
    } else {
      first = ends;
    }
    std::fill(front.begin(), front.end(), 0);
    std::vector<VertexId> next;
    next.reserve(n);
    for (VertexId x : first)
      if (!front[x]) front[x] = 1, next.push_back(x);
    for (VertexId x : order)
      if (!front[x]) next.push_back(x);
    order.swap(next);
    const size_t missing = missing_segments(plc, segs, order, ends, nullptr, trial);
    ++st.rounds;
    if (missing < fewest) {
      fewest = missing, best = order, best_ends = ends, best_round = round;
      std::swap(best_mesh, trial);  // trial's next round starts with mesh.clear()
    }
    if (missing == 0) break;
  }
  // A few segments fewer is noise: segment recovery may then spend more
  // points elsewhere (measured on the CAD models of tests/data).
  if (10 * fewest > 9 * st.missing_before) return {};
  st.missing_after = fewest;
  d0 = std::move(best_mesh);
  return best;
}

void permute_plc(const Plc& plc, const std::vector<VertexId>& order, Plc& out) {
  out = plc;
  std::vector<VertexId> id_of(order.size());
  for (size_t k = 0; k < order.size(); ++k) {
    out.points[k] = plc.points[order[k]];
    id_of[order[k]] = static_cast<VertexId>(k);
  }
  renumber_vertices(out, id_of);
}

}  // namespace cdt3d
