// Repair step 1: the clean-up that needs no geometry beyond exact
// collinearity. Identical points are welded (comparing coordinates is
// exact), a polygon that repeats a vertex is cut at the repeat, polygons of
// zero area are dropped, and so are facets that repeat an earlier facet.
#include <algorithm>
#include <numeric>

#include "geometry.hpp"
#include "predicates.hpp"
#include "repair.hpp"

namespace cdt3d {
namespace repair_steps {

std::vector<uint8_t> used_points(const Plc& plc) {
  std::vector<uint8_t> used(plc.points.size(), 0);
  for (const Facet& f : plc.facets)
    for (const auto& l : f.loops)
      for (VertexId v : l) used[v] = 1;
  for (const auto& s : plc.segments) used[s[0]] = used[s[1]] = 1;
  return used;
}

Facet part_of(const Facet& from, std::vector<VertexId> loop) {
  Facet f;
  f.loops.push_back(std::move(loop));
  f.marker = from.marker;
  f.line = from.line;
  f.record = from.record;
  return f;
}

void weld_points(Work& w, RepairReport& report) {
  Plc& plc = w.plc;
  const size_t n = plc.points.size();
  std::vector<VertexId> order(n);
  std::iota(order.begin(), order.end(), 0);
  auto less = [&](VertexId a, VertexId b) {
    const Vec3 &p = plc.points[a], &q = plc.points[b];
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    if (p.z != q.z) return p.z < q.z;
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);
  // Every point goes to the lowest id with its coordinates; the kept points
  // keep their order, so a PLC without repeats comes out unchanged.
  std::vector<VertexId> first(n);
  for (size_t i = 0; i < n; ++i) {
    const bool same = i > 0 && plc.points[order[i]] == plc.points[order[i - 1]];
    first[order[i]] = same ? first[order[i - 1]] : order[i];
  }
  std::vector<VertexId> id(n, kNone);
  std::vector<Vec3> kept;
  for (size_t v = 0; v < n; ++v) {
    if (first[v] != v) continue;
    id[v] = static_cast<VertexId>(kept.size());
    kept.push_back(plc.points[v]);
  }
  report.welded_points = n - kept.size();
  // The input's points are mapped by the first weld; later welds (after
  // step 4 rounds) only merge new points, which no input id names.
  const bool first_weld = w.point_of_input.empty();
  if (first_weld) w.point_of_input = id;
  if (report.welded_points == 0) return;
  for (size_t v = 0; v < n; ++v) id[v] = id[first[v]];
  if (first_weld) w.point_of_input = id;
  plc.points = std::move(kept);
  for (size_t f = 0; f < plc.facets.size(); ++f) {
    bool touched = false;
    for (auto& loop : plc.facets[f].loops)
      for (VertexId& v : loop) {
        touched |= first[v] != v;
        v = id[v];
      }
    if (touched) w.mark(w.source[f]);
  }
  for (auto& s : plc.segments)
    for (VertexId& v : s) v = id[v];
}

namespace {

// Cuts `loop` into loops without repeated vertices: consecutive repeats
// (also across the wrap-around) are dropped, and a loop that comes back to a
// vertex later is cut there into the part before and the part after (a
// figure eight becomes its two lobes). Returns the number of repeats.
size_t cut_repeats(const std::vector<VertexId>& loop, std::vector<std::vector<VertexId>>& out) {
  std::vector<VertexId> l;
  for (VertexId v : loop)
    if (l.empty() || l.back() != v) l.push_back(v);
  while (l.size() > 1 && l.front() == l.back()) l.pop_back();
  size_t repeats = loop.size() - l.size();
  // Walk the loop with a stack; when a vertex comes back, what lies between
  // its two visits is a lobe of its own.
  std::vector<VertexId> stack;
  for (VertexId v : l) {
    const auto it = std::find(stack.begin(), stack.end(), v);
    if (it == stack.end()) {
      stack.push_back(v);
      continue;
    }
    ++repeats;
    out.emplace_back(it, stack.end());
    stack.erase(it + 1, stack.end());
  }
  out.push_back(std::move(stack));
  return repeats;
}

bool zero_area(const Plc& plc, const std::vector<VertexId>& loop) {
  if (loop.size() < 3) return true;
  const double* a = &plc.points[loop[0]].x;
  const double* b = &plc.points[loop[1]].x;
  for (size_t i = 2; i < loop.size(); ++i)
    if (!pred::collinear3d(a, b, &plc.points[loop[i]].x)) return false;
  return true;
}

}  // namespace

void clean_polygons(Work& w, RepairReport& report) {
  Plc& plc = w.plc;
  std::vector<Facet> facets;
  std::vector<uint32_t> source;
  facets.reserve(plc.facets.size());
  source.reserve(plc.facets.size());
  std::vector<std::vector<VertexId>> parts;
  for (size_t f = 0; f < plc.facets.size(); ++f) {
    Facet& facet = plc.facets[f];
    const uint32_t src = w.source[f];
    std::vector<std::vector<VertexId>> loops;
    bool touched = false;
    for (const auto& loop : facet.loops) {
      parts.clear();
      const size_t repeats = cut_repeats(loop, parts);
      report.repeated_vertices += repeats;
      touched |= repeats > 0;
      for (auto& part : parts) {
        if (zero_area(plc, part)) {
          ++report.zero_area_polygons;
          touched = true;
        } else {
          loops.push_back(std::move(part));
        }
      }
    }
    if (touched) w.mark(src);
    if (loops.empty()) {
      ++report.degenerate_facets;
      continue;
    }
    // A single polygon cut into lobes becomes one facet per lobe: the lobes
    // touch at the cut vertex, which one polygon facet may not do.
    if (touched && facet.loops.size() == 1 && loops.size() > 1) {
      for (auto& l : loops) {
        facets.push_back(part_of(facet, std::move(l)));
        source.push_back(src);
      }
      continue;
    }
    facet.loops = std::move(loops);
    facets.push_back(std::move(facet));
    source.push_back(src);
  }
  plc.facets = std::move(facets);
  w.source = std::move(source);
}

namespace {

// A facet's vertex sets, one per polygon, each sorted, the polygons sorted:
// two facets with equal keys cover the same polygons.
std::vector<std::vector<VertexId>> facet_key(const Facet& f) {
  std::vector<std::vector<VertexId>> key(f.loops.begin(), f.loops.end());
  for (auto& l : key) std::sort(l.begin(), l.end());
  std::sort(key.begin(), key.end());
  return key;
}

}  // namespace

void drop_duplicate_facets(Work& w, RepairReport& report) {
  Plc& plc = w.plc;
  const size_t n = plc.facets.size();
  std::vector<std::vector<std::vector<VertexId>>> keys(n);
  for (size_t f = 0; f < n; ++f) keys[f] = facet_key(plc.facets[f]);
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) {
    return keys[a] != keys[b] ? keys[a] < keys[b] : a < b;
  });
  // The first facet of a run of equal keys stays; the others go.
  std::vector<uint8_t> drop(n, 0);
  for (size_t i = 1; i < n; ++i) {
    if (keys[order[i]] != keys[order[i - 1]]) continue;
    drop[order[i]] = 1;
    ++report.duplicate_facets;
    w.mark(w.source[order[i]]);
  }
  if (report.duplicate_facets == 0) return;
  size_t k = 0;
  for (size_t f = 0; f < n; ++f) {
    if (drop[f]) continue;
    if (k != f) plc.facets[k] = std::move(plc.facets[f]);  // no self-move: it would empty it
    w.source[k] = w.source[f];
    ++k;
  }
  plc.facets.resize(k);
  w.source.resize(k);
}

void drop_orphaned_points(Work& w, const Plc& input) {
  Plc& plc = w.plc;
  const std::vector<uint8_t> used = used_points(plc);
  // Only points that a facet used in the input and none uses now go: an
  // isolated input point is part of the PLC and stays.
  std::vector<uint8_t> keep(plc.points.size(), 1);
  size_t dropped = 0;
  for (const Facet& f : input.facets)
    for (const auto& l : f.loops)
      for (VertexId v : l) {
        const VertexId o = w.point_of_input[v];
        if (used[o] || !keep[o]) continue;
        keep[o] = 0;
        ++dropped;
      }
  if (dropped == 0) return;
  std::vector<VertexId> id(plc.points.size(), kNone);
  std::vector<Vec3> kept;
  for (VertexId v = 0; v < plc.points.size(); ++v) {
    if (!keep[v]) continue;
    id[v] = static_cast<VertexId>(kept.size());
    kept.push_back(plc.points[v]);
  }
  plc.points = std::move(kept);
  renumber_vertices(plc, id);
}

// Explicit segments whose ends welded into one point (identical input
// points, or a piece shorter than step 4's grid) are dropped: a segment
// needs two points. With `repeats`, a segment repeating an earlier one (the
// pieces of collinear overlapping segments split at each other's ends) is
// dropped too; the first keeps its input segment. Step 1 leaves repeats: a
// valid PLC may have them, and it must come out unchanged.
void clean_segments(Work& w, bool repeats) {
  Plc& plc = w.plc;
  std::vector<std::pair<VertexId, VertexId>> seen;
  for (const auto& s : plc.segments) seen.push_back({std::min(s[0], s[1]), std::max(s[0], s[1])});
  std::sort(seen.begin(), seen.end());
  std::vector<uint8_t> taken(seen.size(), 0);
  std::vector<std::array<VertexId, 2>> segments;
  std::vector<uint32_t> source;
  for (size_t s = 0; s < plc.segments.size(); ++s) {
    const VertexId a = plc.segments[s][0], b = plc.segments[s][1];
    if (a == b) continue;
    // Copies of one segment all look up the first of their run in `seen`.
    const size_t i = std::lower_bound(seen.begin(), seen.end(), std::make_pair(std::min(a, b), std::max(a, b))) -
                     seen.begin();
    if (repeats && taken[i]) continue;
    taken[i] = 1;
    segments.push_back(plc.segments[s]);
    source.push_back(w.segment_source[s]);
  }
  plc.segments = std::move(segments);
  w.segment_source = std::move(source);
}

}  // namespace repair_steps
}  // namespace cdt3d
