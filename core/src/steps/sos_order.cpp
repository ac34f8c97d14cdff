// The perturbation order chosen for the segments (sos_order.hpp).
#include "sos_order.hpp"

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <unordered_map>
#include <utility>

#include "delaunay.hpp"
#include "geometry.hpp"
#include "predicates.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

namespace {

// Up to this many missing segments the search moves one segment at a time.
constexpr size_t kFewMissing = 16;

// The points of `plc` renumbered by `order` (vertex k is point order[k]),
// as coordinates for delaunay_tetrahedralize; id_of[p] is point p's vertex.
void points_in_order(const Plc& plc, const std::vector<VertexId>& order, std::vector<double>& xyz,
                     std::vector<VertexId>& id_of) {
  const size_t n = plc.points.size();
  xyz.resize(3 * n);
  id_of.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const Vec3& p = plc.points[order[k]];
    xyz[3 * k] = p.x, xyz[3 * k + 1] = p.y, xyz[3 * k + 2] = p.z;
    id_of[order[k]] = static_cast<VertexId>(k);
  }
}

// The Delaunay tetrahedralization of the points of `plc` renumbered by
// `order` into `mesh` (id_of[p]: point p's vertex); false when it fails.
// Sets *ties when the perturbation decided anything, *ms to its time.
bool build_in_order(const Plc& plc, const std::vector<VertexId>& order,
                    std::vector<VertexId>& id_of, bool* ties, TetMesh& mesh, double* ms,
                    bool threads) {
  std::vector<double> xyz;
  points_in_order(plc, order, xyz, id_of);
  const uint64_t ties_before = pred::counters().sos_ties;
  DelaunayStats ds;
  DelaunayOptions opt;
  opt.threads = threads;
  const bool ok =
      delaunay_tetrahedralize(mesh, xyz.data(), plc.points.size(), nullptr, &ds, opt).ok();
  if (ms) *ms = ds.ms_sort + ds.ms_insert;
  if (ties) *ties = pred::counters().sos_ties != ties_before;
  return ok;
}

// Segments (input ids) that are no edge of `mesh`, whose vertices are the
// input points renumbered by id_of; their ends go to `ends` (two per
// missing segment, in segment order).
size_t count_missing(const std::vector<std::array<VertexId, 2>>& segs,
                     const std::vector<VertexId>& id_of, TetMesh& mesh,
                     std::vector<VertexId>& ends) {
  ends.clear();
  size_t missing = 0;
  for (const auto& e : segs) {
    if (mesh.find_edge(id_of[e[0]], id_of[e[1]]) != kNone) continue;
    ++missing;
    ends.push_back(e[0]), ends.push_back(e[1]);
  }
  return missing;
}

// Segments of `plc` (input ids) missing from the Delaunay tetrahedralization
// of its points renumbered by `order`; their ends go to `ends` (two per
// missing segment, in segment order).
size_t missing_segments(const Plc& plc, const std::vector<std::array<VertexId, 2>>& segs,
                        const std::vector<VertexId>& order, std::vector<VertexId>& ends,
                        TetMesh& mesh, bool threads) {
  std::vector<VertexId> id_of;
  if (!build_in_order(plc, order, id_of, nullptr, mesh, nullptr, threads)) return SIZE_MAX;
  return count_missing(segs, id_of, mesh, ends);
}

uint64_t pair_key(VertexId a, VertexId b) {
  if (a > b) std::swap(a, b);
  return (static_cast<uint64_t>(a) << 32) | b;
}

// d = a - b, and whether that is exact: the rounding error of the
// difference (Knuth's two-sum, exact in floating point) is zero.
bool exact_difference(double a, double b, double& d) {
  d = a - b;
  const double bv = a - d, av = d + bv;
  return (a - av) + (bv - b) == 0;
}

struct ShapeHash {
  size_t operator()(const std::vector<uint64_t>& key) const {
    uint64_t h = key.size();
    for (uint64_t x : key) {
      h ^= x + 0x9e3779b97f4a7c15ull + (h << 6) + (h >> 2);
      h *= 0xbf58476d1ce4e5b9ull;
    }
    return static_cast<size_t>(h ^ (h >> 31));
  }
};

// Which segments a perturbation order keeps, without a Delaunay
// tetrahedralization of all the points per order.
//
// The unperturbed points have a Delaunay subdivision whose cells are the
// convex hulls of the points on each empty sphere. A symbolic perturbation
// of the lifting is infinitesimal, so the perturbed Delaunay
// tetrahedralization refines that subdivision, and inside a cell it is the
// Delaunay tetrahedralization (under the same perturbation) of the cell's
// vertices alone: they are co-spherical, and every other point lies strictly
// outside the cell's sphere (a regular triangulation with infinitesimally
// perturbed heights refines the regular subdivision of the unperturbed
// heights). Only cells with more than four vertices depend on the order.
//
// One tetrahedralization D (any order) gives the cells: two tets of D
// sharing a face lie in one cell exactly when the apex of one is on the
// other's circumsphere (exact insphere 0; the apex of a tet in another cell
// is strictly outside), and the tets of a cell are connected through such
// faces. So a segment uv is an edge for a given order exactly when it is an
// edge of a tet alone in its cell (an edge of the subdivision, kept by every
// order) or an edge of the tetrahedralization of some cell holding u and v.
class CellEdges {
 public:
  // d: the Delaunay tetrahedralization of the points of plc, vertex i being
  // point i.
  CellEdges(const Plc& plc, const std::vector<std::array<VertexId, 2>>& segs, const TetMesh& d)
      : plc_(plc), segs_(segs) {
    find_cells(d);
    mark_fixed_segments(d);
  }

  // missing_segments for `order` (without ties); false when a cell could not
  // be tetrahedralized (the caller then builds the whole tetrahedralization).
  bool missing(const std::vector<VertexId>& order, std::vector<VertexId>& ends, size_t& missing);

 private:
  void find_cells(const TetMesh& d);
  void mark_fixed_segments(const TetMesh& d);
  bool has_edge(uint32_t cell, VertexId u, VertexId v);
  bool triangulate_cell(uint32_t cell);
  bool shape_key(size_t k);

  const Plc& plc_;
  const std::vector<std::array<VertexId, 2>>& segs_;
  std::vector<TetId> cell_of_;                       // per tet slot: its cell (kNone: alone)
  std::vector<uint32_t> cell_start_;                 // cell -> its vertices (CSR, ascending)
  std::vector<VertexId> cell_vertices_;
  std::vector<uint32_t> vertex_start_, vertex_cells_;  // point -> its cells (CSR, ascending)
  std::vector<uint8_t> fixed_;                       // per segment: an edge in every order
  // Per cell: its vertices in the order last triangulated and the edges
  // (pair_key of point ids, sorted) of that triangulation.
  std::vector<std::vector<VertexId>> cell_order_;
  std::vector<std::vector<uint64_t>> cell_edges_;
  std::vector<VertexId> id_of_;  // point -> vertex id in the current order
  std::vector<VertexId> local_;
  std::vector<double> xyz_;
  SmallDelaunay scratch_;
  // Cell tetrahedralizations already built, by shape (shape_key): their
  // edges as pairs of positions in the order. Grid and CAD models repeat a
  // few cell shapes (the cubes of a grid) in a few orders.
  std::unordered_map<std::vector<uint64_t>, std::vector<std::pair<uint32_t, uint32_t>>, ShapeHash>
      by_shape_;
  std::vector<uint64_t> shape_;
  std::vector<std::pair<uint32_t, uint32_t>> local_edges_;
};

// Union-find of the tets over the co-spherical faces (see the class comment).
void CellEdges::find_cells(const TetMesh& d) {
  const size_t slots = d.num_tet_slots();
  std::vector<TetId> parent(slots);
  for (TetId t = 0; t < slots; ++t) parent[t] = t;
  auto root = [&](TetId t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  auto real = [&](TetId t) { return !d.is_dead(t) && !d.is_ghost(t); };
  for (TetId t = 0; t < slots; ++t) {
    if (!real(t)) continue;
    const VertexId* w = d.tet_vertices(t);
    for (int i = 0; i < 4; ++i) {
      const HalfFace m = d.adjacent(make_hf(t, i));
      const TetId n = hf_tet(m);
      if (n < t || !real(n)) continue;  // each face once
      if (pred::insphere(d.point(w[0]), d.point(w[1]), d.point(w[2]), d.point(w[3]),
                         d.point(d.opposite(m))) != 0)
        continue;
      const TetId a = root(t), b = root(n);
      if (a != b) parent[std::max(a, b)] = std::min(a, b);
    }
  }
  // Cells: roots with more than one tet, numbered in slot order.
  std::vector<uint32_t> size(slots, 0);
  for (TetId t = 0; t < slots; ++t)
    if (real(t)) ++size[root(t)];
  std::vector<uint32_t> number(slots, kNone);
  uint32_t cells = 0;
  for (TetId t = 0; t < slots; ++t)
    if (real(t) && parent[t] == t && size[t] > 1) number[t] = cells++;
  cell_of_.assign(slots, kNone);
  std::vector<std::pair<uint32_t, VertexId>> members;  // (cell, point)
  for (TetId t = 0; t < slots; ++t) {
    if (!real(t) || number[root(t)] == kNone) continue;
    cell_of_[t] = number[root(t)];
    for (int i = 0; i < 4; ++i) members.emplace_back(cell_of_[t], d.vertex(t, i));
  }
  std::sort(members.begin(), members.end());
  members.erase(std::unique(members.begin(), members.end()), members.end());
  cell_start_.assign(cells + 1, 0);
  cell_vertices_.clear();
  const size_t n = plc_.points.size();
  vertex_start_.assign(n + 1, 0);
  for (const auto& [c, v] : members) {
    ++cell_start_[c + 1], ++vertex_start_[v + 1];
    cell_vertices_.push_back(v);
  }
  for (uint32_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  for (size_t v = 0; v < n; ++v) vertex_start_[v + 1] += vertex_start_[v];
  vertex_cells_.resize(members.size());
  std::vector<uint32_t> fill(vertex_start_.begin(), vertex_start_.end() - 1);
  // Ascending per point: members are sorted by cell.
  for (const auto& [c, v] : members) vertex_cells_[fill[v]++] = c;
  cell_order_.assign(cells, {});
  cell_edges_.assign(cells, {});
}

// A segment that is an edge of a tet alone in its cell is an edge of the
// subdivision, so of the tetrahedralization in every order. The segments are
// listed at their lower end (a few per point), so each tet edge costs a scan
// of a short list, not a search of all segments.
void CellEdges::mark_fixed_segments(const TetMesh& d) {
  const size_t n = plc_.points.size();
  std::vector<uint32_t> start(n + 1, 0);
  for (const auto& e : segs_) ++start[std::min(e[0], e[1]) + 1];
  for (size_t v = 0; v < n; ++v) start[v + 1] += start[v];
  std::vector<std::pair<VertexId, uint32_t>> at(segs_.size());  // (upper end, segment)
  std::vector<uint32_t> fill(start.begin(), start.end() - 1);
  for (uint32_t k = 0; k < segs_.size(); ++k) {
    const VertexId lo = std::min(segs_[k][0], segs_[k][1]), hi = std::max(segs_[k][0], segs_[k][1]);
    at[fill[lo]++] = {hi, k};
  }
  fixed_.assign(segs_.size(), 0);
  static constexpr int kEdge[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};
  for (TetId t = 0; t < d.num_tet_slots(); ++t) {
    if (d.is_dead(t) || d.is_ghost(t) || cell_of_[t] != kNone) continue;
    const VertexId* w = d.tet_vertices(t);
    for (const auto& e : kEdge) {
      const VertexId lo = std::min(w[e[0]], w[e[1]]), hi = std::max(w[e[0]], w[e[1]]);
      for (uint32_t k = start[lo]; k < start[lo + 1]; ++k)
        if (at[k].first == hi) fixed_[at[k].second] = 1;
    }
  }
}

// The shape of the k points in xyz_: their coordinates minus the first
// point's, in order, when every difference is exact (false otherwise). Two
// cells of one shape have the same tetrahedralization, position for
// position: every predicate the construction decides by is the sign of a
// polynomial in the coordinate differences (with the perturbation, of the
// lifted points' minors, which a translation does not change either), and
// the perturbed Delaunay tetrahedralization is unique.
bool CellEdges::shape_key(size_t k) {
  shape_.resize(3 * (k - 1));
  for (size_t i = 1; i < k; ++i)
    for (int c = 0; c < 3; ++c) {
      double d;
      if (!exact_difference(xyz_[3 * i + c], xyz_[c], d)) return false;
      std::memcpy(&shape_[3 * (i - 1) + c], &d, sizeof d);
    }
  return true;
}

// The edges of the real tets of `m` (vertices 0..k-1) as ascending pairs,
// in ascending order. Each edge lies in several tets: up to kDenseCell
// vertices a k x k table of marks lists them without sorting the
// duplicates (many on co-spherical models).
void cell_edges_of(const TetMesh& m, size_t k, std::vector<std::pair<uint32_t, uint32_t>>& out) {
  constexpr size_t kDenseCell = 256;
  out.clear();
  if (k <= kDenseCell) {
    std::vector<uint8_t> mark(k * k, 0);
    for (TetId t = 0; t < m.num_tet_slots(); ++t) {
      if (m.is_dead(t) || m.is_ghost(t)) continue;
      const VertexId* w = m.tet_vertices(t);
      for (int i = 0; i < 4; ++i)
        for (int j = i + 1; j < 4; ++j) mark[std::min(w[i], w[j]) * k + std::max(w[i], w[j])] = 1;
    }
    for (uint32_t i = 0; i < k; ++i)
      for (uint32_t j = i + 1; j < k; ++j)
        if (mark[i * k + j]) out.emplace_back(i, j);
    return;
  }
  for (TetId t = 0; t < m.num_tet_slots(); ++t) {
    if (m.is_dead(t) || m.is_ghost(t)) continue;
    const VertexId* w = m.tet_vertices(t);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) out.emplace_back(std::min(w[i], w[j]), std::max(w[i], w[j]));
  }
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
}

// Tetrahedralizes the cell's vertices in the current order (their relative
// order is all the perturbation looks at), unless that order is the one
// last triangulated or a cell of the same shape was triangulated before.
bool CellEdges::triangulate_cell(uint32_t cell) {
  local_.assign(cell_vertices_.begin() + cell_start_[cell],
                cell_vertices_.begin() + cell_start_[cell + 1]);
  std::sort(local_.begin(), local_.end(),
            [&](VertexId a, VertexId b) { return id_of_[a] < id_of_[b]; });
  if (local_ == cell_order_[cell]) return true;
  const size_t k = local_.size();
  xyz_.resize(3 * k);
  for (size_t i = 0; i < k; ++i) {
    const Vec3& p = plc_.points[local_[i]];
    xyz_[3 * i] = p.x, xyz_[3 * i + 1] = p.y, xyz_[3 * i + 2] = p.z;
  }
  cell_order_[cell].clear();
  const bool keyed = shape_key(k);
  auto known = keyed ? by_shape_.find(shape_) : by_shape_.end();
  if (known == by_shape_.end()) {
    // The result is the same in any insertion order; a cell has a few
    // points, too few for the spatial sort to pay. The vertices of a cell
    // lie on its sphere (class comment), exactly.
    if (!scratch_.build(xyz_.data(), k, /*cospherical=*/true).ok()) return false;
    cell_edges_of(scratch_.mesh(), k, local_edges_);
    if (keyed) known = by_shape_.emplace(shape_, local_edges_).first;
  }
  const std::vector<std::pair<uint32_t, uint32_t>>& pairs =
      known != by_shape_.end() ? known->second : local_edges_;
  std::vector<uint64_t>& edges = cell_edges_[cell];
  edges.clear();
  for (const auto& [i, j] : pairs) edges.push_back(pair_key(local_[i], local_[j]));
  std::sort(edges.begin(), edges.end());
  cell_order_[cell] = local_;
  return true;
}

bool CellEdges::missing(const std::vector<VertexId>& order, std::vector<VertexId>& ends,
                        size_t& missing) {
  id_of_.resize(order.size());
  for (size_t k = 0; k < order.size(); ++k) id_of_[order[k]] = static_cast<VertexId>(k);
  std::vector<uint8_t> fresh(cell_order_.size(), 0);  // triangulated for this order
  ends.clear();
  missing = 0;
  for (uint32_t s = 0; s < segs_.size(); ++s) {
    if (fixed_[s]) continue;
    const VertexId u = segs_[s][0], v = segs_[s][1];
    const uint64_t key = pair_key(u, v);
    bool found = false;
    // The cells holding both ends: merge of two ascending lists.
    uint32_t i = vertex_start_[u], j = vertex_start_[v];
    while (!found && i < vertex_start_[u + 1] && j < vertex_start_[v + 1]) {
      const uint32_t cu = vertex_cells_[i], cv = vertex_cells_[j];
      if (cu != cv) {
        (cu < cv ? i : j)++;
        continue;
      }
      if (!fresh[cu]) {
        if (!triangulate_cell(cu)) return false;
        fresh[cu] = 1;
      }
      found = std::binary_search(cell_edges_[cu].begin(), cell_edges_[cu].end(), key);
      ++i, ++j;
    }
    if (found) continue;
    ++missing;
    ends.push_back(u), ends.push_back(v);
  }
  return true;
}

// How many of the missing segments (ends: two per segment) some order could
// recover, at most: those whose ends lie on the circumsphere of one tet at
// the first end. An order changes only the tetrahedralizations of the cells
// (CellEdges), so a missing segment comes back only if both ends are
// vertices of one cell, and then every tet of that cell at the first end has
// the cell's sphere, through the second end.
size_t recoverable_segments(TetMesh& d, const std::vector<VertexId>& ends) {
  std::vector<TetId> star;
  size_t count = 0;
  for (size_t k = 0; k + 1 < ends.size(); k += 2) {
    const VertexId u = ends[k], v = ends[k + 1];
    d.vertex_star(u, star);
    for (TetId t : star) {
      if (d.is_ghost(t)) continue;
      const VertexId* w = d.tet_vertices(t);
      if (pred::insphere(d.point(w[0]), d.point(w[1]), d.point(w[2]), d.point(w[3]),
                         d.point(v)) == 0) {
        ++count;
        break;
      }
    }
  }
  return count;
}

}  // namespace

std::vector<VertexId> segment_friendly_order(const Plc& plc, size_t max_rounds,
                                             TetMesh& d0, SosOrderStats* stats,
                                             std::vector<std::array<VertexId, 2>>* segments,
                                             bool threads, const SegmentsWhenReady* ready) {
  SosOrderStats local;
  SosOrderStats& st = stats ? *stats : local;
  st = SosOrderStats();
  const size_t n = plc.points.size();
  std::vector<std::array<VertexId, 2>> own;
  std::vector<std::array<VertexId, 2>>& segs = segments ? *segments : own;
  if (!ready) segs = plc_segments(plc);
  std::vector<VertexId> order(n), best, ends, best_ends, id_of;
  TetMesh trial;  // a whole tetrahedralization, only if a cell's fails
  for (size_t k = 0; k < n; ++k) order[k] = static_cast<VertexId>(k);
  // D0 in input order needs the points alone: with `ready` it is built
  // before the segments arrive.
  bool ties = false;
  const bool built = build_in_order(plc, order, id_of, &ties, d0, &st.ms_d0, threads);
  if (ready && !(*ready)(segs)) {
    d0 = TetMesh();
    return {};
  }
  st.rounds = 1;
  if (!built) {
    st.missing_before = st.missing_after = SIZE_MAX;
    d0 = TetMesh();
    return {};
  }
  if (!ties) return {};  // no order does better: skip the count
  size_t fewest = count_missing(segs, id_of, d0, ends);
  st.missing_before = st.missing_after = fewest;
  if (fewest == 0) return {};
  // The search keeps an order only if it saves a tenth of the missing
  // segments (below); when fewer than that can come back at all, it is not
  // worth the cells.
  if (10 * (fewest - recoverable_segments(d0, ends)) > 9 * fewest) return {};
  // Each round: the ends of the segments just found missing first (by
  // segment, so both ends of one segment are placed together), then the
  // others in their previous order.
  std::vector<uint8_t> front(n);
  size_t best_round = 0;
  CellEdges cells(plc, segs, d0);
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
    size_t missing = 0;
    if (!cells.missing(order, ends, missing))
      missing = missing_segments(plc, segs, order, ends, trial, threads);
    ++st.rounds;
    if (missing < fewest) fewest = missing, best = order, best_ends = ends, best_round = round;
    if (missing == 0) break;
  }
  // A few segments fewer is noise: segment recovery may then spend more
  // points elsewhere.
  if (10 * fewest > 9 * st.missing_before) return {};
  st.missing_after = fewest;
  // D0 in the chosen order: the search counted on the cells alone.
  if (!build_in_order(plc, best, id_of, nullptr, d0, &st.ms_d0, threads)) d0 = TetMesh();
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
