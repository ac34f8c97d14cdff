// Input validation of a PLC with exact predicates and no tolerances: finite
// coordinates within kMaxCoordinate, distinct points, indices in range, loops
// of >= 3 distinct vertices that are not all collinear, planar facets, no
// duplicate facets, proper explicit segments. The first problem found is
// reported, naming the facet and its source line or record.
#include <algorithm>
#include <cdt3d/cdt3d.hpp>
#include <cmath>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

#include "blocks.hpp"
#include "group_by_key.hpp"
#include "hash.hpp"
#include "plc_check.hpp"
#include "predicates.hpp"
#include "status.hpp"

namespace cdt3d {
namespace {

bool bad_coord(double c) { return !std::isfinite(c) || std::fabs(c) > kMaxCoordinate; }

// Checks one point, named in messages as "<kind> <index>".
Status check_point(const Plc& plc, const Vec3& p, const char* kind, size_t index, int64_t vertex) {
  const double c[3] = {p.x, p.y, p.z};
  for (int k = 0; k < 3; ++k) {
    if (!bad_coord(c[k])) continue;
    const bool nan = !std::isfinite(c[k]);
    Status s =
        make_error(nan ? ErrorCode::NonFinite : ErrorCode::CoordinateRange,
                   std::string(kind) + " " + std::to_string(index) +
                       (nan ? " has a non-finite " : " has a ") +
                       std::string(1, static_cast<char>('x' + k)) +
                       (nan ? " coordinate." : " coordinate beyond the supported magnitude 1e50."))
            .file(plc.file);
    s.error.vertex = vertex;
    return s;
  }
  return Status::success();
}

// Point v's coordinates as the predicates take them (Vec3 stores x, y, z
// contiguously).
const double* at(const Plc& plc, VertexId v) { return &plc.points[v].x; }

// Whether two of the n items are equal, by an open-addressing hash table:
// hash(i) and equal(i, j) on item indices. One pass, no sort: the checks
// below sort only when this finds a pair, to name the same pair as always.
// A slot keeps the item's index and the top 32 bits of its hash, so that
// equal() (which reads the other item, a cache miss on large inputs) runs
// only on a full hash match.
template <typename Hash, typename Equal>
bool any_equal_pair(size_t n, Hash hash, Equal equal) {
  size_t cap = 16;
  while (cap < 2 * n) cap *= 2;
  constexpr uint64_t kEmpty = UINT64_MAX;  // no item has index 2^32 - 1
  std::vector<uint64_t> slot(cap, kEmpty);
  // In blocks (base/blocks.hpp): a block that finds a pair stops the loop.
  return !for_blocks(n, [&](size_t begin, size_t end) {
    for (uint32_t i = static_cast<uint32_t>(begin); i < end; ++i) {
      const uint64_t h = hash(i);
      const uint64_t tag = h >> 32 << 32;
      for (size_t s = h & (cap - 1);; s = (s + 1) & (cap - 1)) {
        if (slot[s] == kEmpty) {
          slot[s] = tag | i;
          break;
        }
        if ((slot[s] & ~uint64_t(UINT32_MAX)) == tag && equal(static_cast<uint32_t>(slot[s]), i))
          return false;
      }
    }
    return true;
  });
}

// Distinct points: identical coordinates must have been welded. A hash pass
// finds whether any two coincide (-0 and +0 hash alike, as they compare
// equal); only then are copies (coordinates + id) sorted to name the pair.
Status check_distinct_points(const Plc& plc) {
  auto bits = [](double x) {
    x += 0.0;  // -0 -> +0
    uint64_t u;
    std::memcpy(&u, &x, sizeof u);
    return u;
  };
  const auto& P = plc.points;
  const bool any = any_equal_pair(
      P.size(),
      [&](uint32_t i) {
        return hash_mix(bits(P[i].x) ^ hash_mix(bits(P[i].y) ^ hash_mix(bits(P[i].z))));
      },
      [&](uint32_t i, uint32_t j) { return P[i].x == P[j].x && P[i].y == P[j].y && P[i].z == P[j].z; });
  if (!any) return Status::success();
  struct Item {
    double x, y, z;
    VertexId id;
  };
  std::vector<Item> items(plc.points.size());
  for (size_t i = 0; i < items.size(); ++i) {
    const Vec3& p = plc.points[i];
    items[i] = Item{p.x, p.y, p.z, static_cast<VertexId>(i)};
  }
  std::sort(items.begin(), items.end(), [](const Item& a, const Item& b) {
    if (a.x != b.x) return a.x < b.x;
    if (a.y != b.y) return a.y < b.y;
    if (a.z != b.z) return a.z < b.z;
    return a.id < b.id;
  });
  for (size_t i = 1; i < items.size(); ++i) {
    const Item& a = items[i - 1];
    const Item& b = items[i];
    if (a.x == b.x && a.y == b.y && a.z == b.z) {
      Status s = make_error(ErrorCode::InvalidArgument, "Points " + std::to_string(a.id) + " and " +
                                                            std::to_string(b.id) +
                                                            " have identical coordinates.")
                     .file(plc.file);
      s.error.vertex = b.id;
      return s;
    }
  }
  return Status::success();
}

Status check_facet_holes(const Plc& plc, size_t fi) {
  const Facet& f = plc.facets[fi];
  for (size_t h = 0; h < f.holes.size(); ++h) {
    Status s = check_point(plc, f.holes[h], "Facet hole point", h, -1);
    if (!s.ok()) {
      s.error.facet = static_cast<int64_t>(fi);
      s.error.line = f.line;
      s.error.record = f.record;
      return s;
    }
  }
  return Status::success();
}

// Checks one facet's loops: sizes, index range, repeated vertices, zero area,
// planarity. `scratch` is reused between calls.
// Two edges of a facet's loops, in the facet's projection (exact): true when
// they meet anywhere except at a vertex they share. Sharing a vertex, they
// meet elsewhere only when collinear and pointing the same way (overlap).
bool edges_meet(const double* p1, const double* p2, const double* q1, const double* q2, int drop,
                int shared) {
  auto orient = [drop](const double* a, const double* b, const double* c) {
    return pred::orient2d_projected(a, b, c, drop);
  };
  // Coordinate-wise betweenness of c on the segment ab, given collinearity.
  auto within = [](const double* a, const double* b, const double* c) {
    for (int k = 0; k < 3; ++k)
      if (c[k] < std::min(a[k], b[k]) || c[k] > std::max(a[k], b[k])) return false;
    return true;
  };
  if (shared) {
    // p1 == q1 (the caller orders them so): overlap when p2 and q2 lie on
    // one ray from p1.
    if (orient(p1, p2, q2) != 0) return false;
    return within(p1, p2, q2) || within(p1, q2, p2);
  }
  const int o1 = orient(p1, p2, q1), o2 = orient(p1, p2, q2);
  const int o3 = orient(q1, q2, p1), o4 = orient(q1, q2, p2);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  return (o1 == 0 && within(p1, p2, q1)) || (o2 == 0 && within(p1, p2, q2)) ||
         (o3 == 0 && within(q1, q2, p1)) || (o4 == 0 && within(q1, q2, p2));
}

// The loops of a facet must be simple and must not cross or touch each
// other (a polygon facet is a region bounded by simple closed curves). Exact
// orientation tests in the coordinate plane that drops an axis along which
// the facet's normal has a nonzero component. O(edges^2) per facet, with a
// bounding-box test first; triangles need no check.
Status check_simple_loops(const Plc& plc, size_t fi, const double* a, const double* b,
                          const double* c) {
  const Facet& f = plc.facets[fi];
  int drop = 0;
  while (drop < 3 && pred::orient2d_projected(a, b, c, drop) == 0) ++drop;
  if (drop == 3) return Status::success();  // collinear: reported elsewhere
  struct E {
    VertexId u, v;
    const double *pu, *pv;
  };
  std::vector<E> edges;
  for (const auto& L : f.loops)
    for (size_t i = 0; i < L.size(); ++i)
      edges.push_back({L[i], L[(i + 1) % L.size()], at(plc, L[i]), at(plc, L[(i + 1) % L.size()])});
  for (size_t i = 0; i < edges.size(); ++i) {
    for (size_t j = i + 1; j < edges.size(); ++j) {
      const E& x = edges[i];
      const E& y = edges[j];
      bool apart = false;
      for (int k = 0; k < 3 && !apart; ++k)
        apart = std::max(x.pu[k], x.pv[k]) < std::min(y.pu[k], y.pv[k]) ||
                std::max(y.pu[k], y.pv[k]) < std::min(x.pu[k], x.pv[k]);
      // The same edge in two polygons of one facet (TetGen allows a facet
      // made of polygons that share edges).
      if (apart || (x.u == y.v && x.v == y.u) || (x.u == y.u && x.v == y.v)) continue;
      bool meet;
      if (x.u == y.u) meet = edges_meet(x.pu, x.pv, y.pu, y.pv, drop, 1);
      else if (x.u == y.v) meet = edges_meet(x.pu, x.pv, y.pv, y.pu, drop, 1);
      else if (x.v == y.u) meet = edges_meet(x.pv, x.pu, y.pu, y.pv, drop, 1);
      else if (x.v == y.v) meet = edges_meet(x.pv, x.pu, y.pv, y.pu, drop, 1);
      else meet = edges_meet(x.pu, x.pv, y.pu, y.pv, drop, 0);
      if (meet) {
        Status s =
            make_error(ErrorCode::DegenerateFacet,
                       "Facet " + std::to_string(fi) + " is not a simple polygon: its edges (" +
                           std::to_string(x.u) + ", " + std::to_string(x.v) + ") and (" +
                           std::to_string(y.u) + ", " + std::to_string(y.v) + ") meet.")
                .facet_of(plc, fi);
        s.error.vertex = x.u;
        return s;
      }
    }
  }
  return Status::success();
}

Status check_facet(const Plc& plc, size_t fi, std::vector<VertexId>& scratch) {
  const Facet& f = plc.facets[fi];
  const size_t n_points = plc.points.size();
  if (f.loops.empty()) {
    return make_error(ErrorCode::DegenerateFacet,
                      "Facet " + std::to_string(fi) + " has no polygon.")
        .facet_of(plc, fi);
  }
  for (size_t li = 0; li < f.loops.size(); ++li) {
    const auto& loop = f.loops[li];
    auto name = [li, fi]() {
      return "Polygon " + std::to_string(li) + " of facet " + std::to_string(fi);
    };
    for (VertexId v : loop) {
      if (v >= n_points) {
        return make_error(ErrorCode::IndexOutOfRange, name() + " uses vertex " + std::to_string(v) +
                                                          " but there are " +
                                                          std::to_string(n_points) + " points.")
            .facet_of(plc, fi);
      }
    }
    if (loop.size() < 3) {
      return make_error(ErrorCode::DegenerateFacet,
                        name() + " has " + std::to_string(loop.size()) +
                            (loop.size() == 1 ? " vertex" : " vertices") +
                            "; at least 3 are needed.")
          .facet_of(plc, fi);
    }
    VertexId repeated = kNone;
    if (loop.size() == 3) {
      if (loop[0] == loop[1] || loop[0] == loop[2]) {
        repeated = loop[0];
      } else if (loop[1] == loop[2]) {
        repeated = loop[1];
      }
    } else {
      scratch.assign(loop.begin(), loop.end());
      std::sort(scratch.begin(), scratch.end());
      for (size_t i = 1; i < scratch.size() && repeated == kNone; ++i) {
        if (scratch[i] == scratch[i - 1]) repeated = scratch[i];
      }
    }
    if (repeated != kNone) {
      Status s = make_error(ErrorCode::DegenerateFacet,
                            name() + " repeats vertex " + std::to_string(repeated) + ".")
                     .facet_of(plc, fi);
      s.error.vertex = repeated;
      return s;
    }
    // Zero area: every vertex on the line through the first two.
    const double* a = at(plc, loop[0]);
    const double* b = at(plc, loop[1]);
    bool flat = true;
    for (size_t i = 2; i < loop.size() && flat; ++i) {
      const double* c = at(plc, loop[i]);
      if (!pred::collinear3d(a, b, c)) flat = false;
    }
    if (flat) {
      return make_error(ErrorCode::DegenerateFacet,
                        name() + " has zero area: its vertices are collinear.")
          .facet_of(plc, fi);
    }
  }
  // Planarity: a non-collinear triple of the first loop spans the plane; every
  // vertex of every loop must lie in it exactly. A lone triangle is planar.
  const auto& first = f.loops[0];
  if (f.loops.size() == 1 && first.size() == 3) return check_facet_holes(plc, fi);
  const double* a = at(plc, first[0]);
  const double* b = at(plc, first[1]);
  const double* c = a;
  for (size_t i = 2; i < first.size(); ++i) {
    c = at(plc, first[i]);
    if (!pred::collinear3d(a, b, c)) break;
  }
  for (size_t li = 0; li < f.loops.size(); ++li) {
    for (VertexId v : f.loops[li]) {
      const double* d = at(plc, v);
      if (pred::orient3d(a, b, c, d) != 0) {
        Status s = make_error(ErrorCode::NonPlanarFacet,
                              "Facet " + std::to_string(fi) + " is not planar: vertex " +
                                  std::to_string(v) + " lies off the plane of its first polygon.")
                       .facet_of(plc, fi);
        s.error.vertex = v;
        return s;
      }
    }
  }
  Status simple = check_simple_loops(plc, fi, a, b, c);
  if (!simple.ok()) return simple;
  return check_facet_holes(plc, fi);
}

// Whether two of the nf facet keys (keys[start[f]..start[f + 1]), as
// check_duplicates builds them) are equal. Equal keys have the same first
// vertex (keys[start[f] + 2]: the smallest vertex of the facet's first loop
// in key order), so the facets are grouped by it (base/group_by_key.hpp,
// for the memory locality) and each group is compared on its own: pairwise
// when it is small, by sorting (with less, the keys' order) when many
// facets share the vertex (a fan).
template <typename KeyLess>
bool any_equal_key(size_t nf, size_t np, const std::vector<uint32_t>& keys,
                   const std::vector<size_t>& start, KeyLess less) {
  auto first = [&](size_t f) { return keys[start[f] + 2]; };  // every key has >= 5 words
  auto equal = [&](uint32_t x, uint32_t y) {
    return start[x + 1] - start[x] == start[y + 1] - start[y] &&
           std::equal(keys.begin() + static_cast<std::ptrdiff_t>(start[x]),
                      keys.begin() + static_cast<std::ptrdiff_t>(start[x + 1]),
                      keys.begin() + static_cast<std::ptrdiff_t>(start[y]));
  };
  std::vector<uint32_t> order, end;
  group_by_key(
      nf, np, first, [](size_t f) { return static_cast<uint32_t>(f); }, order, end);
  bool found = false;
  size_t b = 0;
  for_blocks(np, [&](size_t v0, size_t v1) {
    for (size_t v = v0; v < v1; ++v) {
      const size_t e = end[v];
      if (e - b <= 8) {
        for (size_t i = b; i < e && !found; ++i)
          for (size_t j = i + 1; j < e && !found; ++j) found = equal(order[i], order[j]);
      } else {
        std::sort(order.begin() + static_cast<std::ptrdiff_t>(b),
                  order.begin() + static_cast<std::ptrdiff_t>(e), less);
        for (size_t i = b + 1; i < e && !found; ++i) found = equal(order[i - 1], order[i]);
      }
      if (found) return false;
      b = e;
    }
    return true;
  });
  return found;
}

// Duplicate facets: the same set of loops, each taken as a vertex set. Every
// facet gets a canonical key (its loops' sorted vertex lists, the loops in
// sorted order); sorting the keys puts duplicates side by side.
Status check_duplicates(const Plc& plc) {
  const size_t nf = plc.facets.size();
  std::vector<uint32_t> keys;
  std::vector<size_t> start(nf + 1, 0);
  std::vector<std::vector<VertexId>> loops;
  for_blocks(nf, [&](size_t begin, size_t end) {
    for (size_t fi = begin; fi < end; ++fi) {
      const Facet& f = plc.facets[fi];
      start[fi] = keys.size();
      keys.push_back(static_cast<uint32_t>(f.loops.size()));
      if (f.loops.size() == 1) {
        const size_t at = keys.size();
        keys.push_back(static_cast<uint32_t>(f.loops[0].size()));
        keys.insert(keys.end(), f.loops[0].begin(), f.loops[0].end());
        std::sort(keys.begin() + static_cast<std::ptrdiff_t>(at) + 1, keys.end());
        continue;
      }
      loops.assign(f.loops.begin(), f.loops.end());
      for (auto& l : loops) std::sort(l.begin(), l.end());
      std::sort(loops.begin(), loops.end(),
                [](const std::vector<VertexId>& x, const std::vector<VertexId>& y) {
                  if (x.size() != y.size()) return x.size() < y.size();
                  return x < y;
                });
      for (const auto& l : loops) {
        keys.push_back(static_cast<uint32_t>(l.size()));
        keys.insert(keys.end(), l.begin(), l.end());
      }
    }
    return true;
  });
  start[nf] = keys.size();
  auto key_less = [&](size_t x, size_t y) {
    return std::lexicographical_compare(keys.begin() + static_cast<std::ptrdiff_t>(start[x]),
                                        keys.begin() + static_cast<std::ptrdiff_t>(start[x + 1]),
                                        keys.begin() + static_cast<std::ptrdiff_t>(start[y]),
                                        keys.begin() + static_cast<std::ptrdiff_t>(start[y + 1]));
  };
  // The first six key words, packed, decide most comparisons (all of them for
  // lone triangles, whose key is 5 words) without touching the key array.
  struct Entry {
    uint64_t w[3];
    uint32_t facet;
  };
  // Most PLCs have no duplicate: grouping the facets by their key's first
  // vertex says so without the sort (which names the pair when there is one).
  const bool any = any_equal_key(nf, plc.points.size(), keys, start, key_less);
  if (!any) return Status::success();
  std::vector<Entry> entries(nf);
  for (size_t fi = 0; fi < nf; ++fi) {
    uint32_t word[6] = {0, 0, 0, 0, 0, 0};
    const size_t len = start[fi + 1] - start[fi];
    for (size_t k = 0; k < 6 && k < len; ++k) word[k] = keys[start[fi] + k] + 1;
    Entry& e = entries[fi];
    for (int k = 0; k < 3; ++k) e.w[k] = (uint64_t{word[2 * k]} << 32) | word[2 * k + 1];
    e.facet = static_cast<uint32_t>(fi);
  }
  auto entry_cmp = [&](const Entry& x, const Entry& y) -> int {
    for (int k = 0; k < 3; ++k) {
      if (x.w[k] != y.w[k]) return x.w[k] < y.w[k] ? -1 : 1;
    }
    if (key_less(x.facet, y.facet)) return -1;
    if (key_less(y.facet, x.facet)) return 1;
    return 0;
  };
  std::sort(entries.begin(), entries.end(), [&](const Entry& x, const Entry& y) {
    const int c = entry_cmp(x, y);
    return c != 0 ? c < 0 : x.facet < y.facet;
  });
  // Among all duplicate pairs, report the one whose later facet comes first
  // in the file: (that facet, the first facet with the same key).
  size_t best_dup = nf, best_first = nf;
  size_t group = 0;  // position where the current run of equal keys starts
  for (size_t i = 1; i < nf; ++i) {
    if (entry_cmp(entries[i - 1], entries[i]) != 0) {
      group = i;
      continue;
    }
    // Same key: entries[i] duplicates entries[group], the run's lowest index.
    if (entries[i].facet < best_dup) {
      best_dup = entries[i].facet;
      best_first = entries[group].facet;
    }
  }
  if (best_dup == nf) return Status::success();
  Status s = make_error(ErrorCode::DuplicateFacet,
                        "Facet " + std::to_string(best_dup) + " repeats facet " +
                            std::to_string(best_first) + " (the same vertices).")
                 .facet_of(plc, best_dup);
  s.error.other_facet = static_cast<int64_t>(best_first);
  return s;
}

}  // namespace

Status check_plc_points(const Plc& plc) {
  Status s;
  for_blocks(plc.points.size(), [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i) {
      s = check_point(plc, plc.points[i], "Point", i, static_cast<int64_t>(i));
      if (!s.ok()) return false;
    }
    return true;
  });
  if (!s.ok()) return s;
  if (plc.points.size() > 0xfffffffeull) {
    return make_error(ErrorCode::TooLarge, "More points than 32-bit ids allow.").file(plc.file);
  }
  return Status::success();
}

namespace {

// check_plc's checks after those of the points.
Status check_plc_after_points(const Plc& plc) {
  Status s;
  std::vector<VertexId> scratch;
  for_blocks(plc.facets.size(), [&](size_t begin, size_t end) {
    for (size_t fi = begin; fi < end; ++fi) {
      s = check_facet(plc, fi, scratch);
      if (!s.ok()) return false;
    }
    return true;
  });
  if (!s.ok()) return s;
  for (size_t i = 0; i < plc.segments.size(); ++i) {
    const auto& seg = plc.segments[i];
    if (seg[0] >= plc.points.size() || seg[1] >= plc.points.size()) {
      return make_error(ErrorCode::IndexOutOfRange,
                        "Segment " + std::to_string(i) + " uses a vertex beyond the " +
                            std::to_string(plc.points.size()) + " points.")
          .file(plc.file);
    }
    if (seg[0] == seg[1]) {
      Status e = make_error(ErrorCode::DegenerateFacet,
                            "Segment " + std::to_string(i) + " has identical endpoints.")
                     .file(plc.file);
      e.error.vertex = seg[0];
      return e;
    }
  }
  for (size_t i = 0; i < plc.holes.size(); ++i) {
    s = check_point(plc, plc.holes[i], "Hole point", i, -1);
    if (!s.ok()) return s;
  }
  for (size_t i = 0; i < plc.regions.size(); ++i) {
    s = check_point(plc, plc.regions[i].point, "Region point", i, -1);
    if (!s.ok()) return s;
    if (!std::isfinite(plc.regions[i].attribute) || !std::isfinite(plc.regions[i].max_volume)) {
      return make_error(ErrorCode::NonFinite,
                        "Region " + std::to_string(i) + " has a non-finite attribute or volume.")
          .file(plc.file);
    }
  }
  return check_duplicates(plc);
}

}  // namespace

Status check_plc(const Plc& plc) {
  Status s = check_plc_points(plc);
  if (!s.ok()) return s;
  s = check_distinct_points(plc);
  if (!s.ok()) return s;
  return check_plc_after_points(plc);
}

Status check_welded_plc(const Plc& plc) {
  Status s = check_plc_points(plc);
  if (!s.ok()) return s;
  return check_plc_after_points(plc);
}

}  // namespace cdt3d
