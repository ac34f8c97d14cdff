// Repair step 5: interpenetrating parts become their union.
//
// After step 4 the facets form an arrangement: no two cross, and every part
// a crossing passed through is cut along it. The cells of space that the
// facets bound each have a winding number: how many times the oriented
// input surfaces wind around them (0 outside everything, 1 inside one
// part, 2 where two parts overlap). The union of the parts is the cells of
// winding number at least 1; a facet with such cells on both sides lies
// inside the union and goes, as does one with winding 0 on both sides.
//
// The winding numbers come from a tetrahedralization of the arrangement
// (the pipeline itself, convex hull kept, every facet its own): outside the
// hull the winding is 0, and crossing a face of a facet changes it by one,
// up when going from the facet's front (where its input facet's normal
// points, right-hand rule) to its back. Every decision is an exact sign:
// which side of a face a tet lies on (orient3d), and whether a face runs
// like its input facet (orient2d in the input facet's projection plane).
//
// The winding numbers exist only when the facets, each oriented like its
// input facet, close up: every edge used as often in each direction. A model
// with inconsistent normals, open pieces or coincident faces of two parts
// (repair keeps one copy) fails that test and keeps every facet, as before
// this step; so does a model whose tetrahedralization fails here (the
// meshing after repair then reports it).
#include <algorithm>
#include <array>
#include <climits>
#include <unordered_map>

#include "geometry.hpp"
#include "hash.hpp"
#include "predicates.hpp"
#include "repair.hpp"

namespace cdt3d {
namespace repair_steps {
namespace {

// An input facet's orientation in the plane that drops axis `drop`: the
// sign of orient2d of the corner at its lexicographically smallest vertex
// (an extreme vertex of the polygon, so a strictly convex corner).
struct Orientation {
  int drop = 2;
  int sign = 0;  // 0: no orientation (degenerate or empty)
};

int corner_sign(const Plc& plc, const std::vector<VertexId>& loop, int drop) {
  size_t low = 0;
  for (size_t i = 1; i < loop.size(); ++i) {
    const Vec3 &u = plc.points[loop[i]], &v = plc.points[loop[low]];
    if (u.x != v.x ? u.x < v.x : u.y != v.y ? u.y < v.y : u.z < v.z) low = i;
  }
  const Vec3& prev = plc.points[loop[(low + loop.size() - 1) % loop.size()]];
  const Vec3& next = plc.points[loop[(low + 1) % loop.size()]];
  return pred::orient2d_projected(&prev.x, &plc.points[loop[low]].x, &next.x, drop);
}

Orientation orientation_of(const Plc& plc, const Facet& f) {
  Orientation o;
  if (f.loops.empty() || f.loops[0].size() < 3) return o;
  const Vec3 n = newell_normal(plc, f.loops[0]);
  const double a[3] = {std::abs(n.x), std::abs(n.y), std::abs(n.z)};
  o.drop = a[0] >= a[1] && a[0] >= a[2] ? 0 : a[1] >= a[2] ? 1 : 2;
  o.sign = corner_sign(plc, f.loops[0], o.drop);
  return o;
}

// The facets, each taken with the orientation of its input facet, form a
// cycle: every directed edge is matched by its reverse as often.
bool facets_close_up(const Work& w, const std::vector<int>& runs_like_input) {
  std::unordered_map<uint64_t, int64_t> balance;
  for (size_t f = 0; f < w.plc.facets.size(); ++f) {
    if (runs_like_input[f] == 0) return false;
    for (const auto& loop : w.plc.facets[f].loops)
      for (size_t i = 0; i < loop.size(); ++i) {
        VertexId a = loop[i], b = loop[(i + 1) % loop.size()];
        if (runs_like_input[f] < 0) std::swap(a, b);
        // a -> b counts +1 on the key (min, max) when a < b, else -1.
        balance[edge_key(a, b)] += a < b ? 1 : -1;
      }
  }
  return std::all_of(balance.begin(), balance.end(), [](const auto& kv) { return kv.second == 0; });
}

struct FaceRecord {
  std::array<VertexId, 3> key;
  uint32_t tet;
  uint8_t face;
  bool operator<(const FaceRecord& o) const { return key != o.key ? key < o.key : tet < o.tet; }
};

struct TripleHash {
  size_t operator()(const std::array<VertexId, 3>& k) const {
    return static_cast<size_t>(hash_mix(edge_key(k[0], k[1]) ^ hash_mix(k[2])));
  }
};

constexpr int kUnset = INT_MIN;

}  // namespace

Status merge_into_union(Work& w, const Plc& input, RepairReport& report) {
  const size_t nf = w.plc.facets.size();
  std::vector<Orientation> input_orientation(input.facets.size());
  for (size_t s = 0; s < input.facets.size(); ++s)
    input_orientation[s] = orientation_of(input, input.facets[s]);
  // Each facet against its input facet: +1 same way round, -1 reversed.
  std::vector<int> runs_like_input(nf, 0);
  for (size_t f = 0; f < nf; ++f) {
    const Orientation& in = input_orientation[w.source[f]];
    const std::vector<std::vector<VertexId>>& loops = w.plc.facets[f].loops;
    if (in.sign == 0 || loops.empty() || loops[0].size() < 3) continue;
    // In the input facet's projection plane: the two lie in one plane (up
    // to the snap rounding of step 4, far below any corner's area).
    const int own = corner_sign(w.plc, loops[0], in.drop);
    if (own != 0) runs_like_input[f] = own == in.sign ? 1 : -1;
  }
  if (!facets_close_up(w, runs_like_input)) {
    report.union_skipped = 1;
    return Status::success();
  }

  Options opt;
  opt.keep_convex_hull = true;
  opt.keep_triangles = true;
  opt.check_intersections = false;  // step 4 left none (checked exactly)
  const Result r = tetrahedralize(w.plc, opt);
  if (!r.status.ok()) {
    report.union_skipped = 1;
    return Status::success();
  }
  const std::vector<double>& xyz = r.mesh.points;
  auto pt = [&](uint32_t v) { return &xyz[3 * size_t(v)]; };
  const size_t nt = r.mesh.tets.size() / 4;

  // Constrained faces: sorted triple -> facet.
  std::unordered_map<std::array<VertexId, 3>, uint32_t, TripleHash> facet_of;
  facet_of.reserve(r.face_facet.size());
  for (size_t i = 0; i < r.face_facet.size(); ++i) {
    if (r.face_facet[i] >= nf) continue;  // a hull face that is no facet
    std::array<VertexId, 3> k = {r.mesh.faces[3 * i], r.mesh.faces[3 * i + 1], r.mesh.faces[3 * i + 2]};
    std::sort(k.begin(), k.end());
    facet_of.emplace(k, r.face_facet[i]);
  }
  // Face adjacency by sorting the four faces of every tet.
  std::vector<FaceRecord> faces;
  faces.reserve(4 * nt);
  for (uint32_t t = 0; t < nt; ++t)
    for (uint8_t i = 0; i < 4; ++i) {
      std::array<VertexId, 3> k;
      for (int j = 0, m = 0; j < 4; ++j)
        if (j != i) k[m++] = r.mesh.tets[4 * size_t(t) + j];
      std::sort(k.begin(), k.end());
      faces.push_back({k, t, i});
    }
  std::sort(faces.begin(), faces.end());

  // Whether the apex of tet t opposite its face i lies in front of facet f.
  auto in_front = [&](uint32_t t, uint8_t i, uint32_t f) -> int {
    const uint32_t* tv = &r.mesh.tets[4 * size_t(t)];
    uint32_t abc[3];
    for (int j = 0, m = 0; j < 4; ++j)
      if (j != i) abc[m++] = tv[j];
    const Orientation& in = input_orientation[w.source[f]];
    // +1 when the face, in the tet's order, runs like the input facet.
    const int along = pred::orient2d_projected(pt(abc[0]), pt(abc[1]), pt(abc[2]), in.drop) * in.sign;
    const int side = pred::orient3d(pt(abc[0]), pt(abc[1]), pt(abc[2]), pt(tv[i]));
    if (along == 0 || side == 0) return -1;  // no decision: give up the union
    return along * side < 0 ? 1 : 0;
  };

  // Flood from the hull (winding 0 outside it).
  std::vector<int> winding(nt, kUnset);
  std::vector<std::array<int, 2>> sides(nf, {kUnset, kUnset});  // winding in front, behind
  std::vector<uint32_t> queue;
  bool consistent = true;
  auto set = [&](uint32_t t, int value) {
    if (winding[t] == kUnset) {
      winding[t] = value;
      queue.push_back(t);
    } else if (winding[t] != value) {
      consistent = false;
    }
  };
  auto note_side = [&](uint32_t f, bool front, int value) {
    int& s = sides[f][front ? 0 : 1];
    if (s == kUnset) s = value;
    else if (s != value) consistent = false;
  };
  // The jump of winding from the tet on face record a's side to the other.
  std::vector<std::pair<size_t, size_t>> pairs;  // records of the two sides (second = npos on the hull)
  for (size_t i = 0; i < faces.size();) {
    size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    pairs.push_back({i, j - i == 2 ? i + 1 : SIZE_MAX});
    if (j - i > 2) consistent = false;  // a face of three tets: a broken result
    i = j;
  }
  // Per tet, its four face pairs, to walk across.
  std::vector<uint32_t> pair_of(4 * nt);
  for (size_t p = 0; p < pairs.size(); ++p) {
    const FaceRecord& a = faces[pairs[p].first];
    pair_of[4 * size_t(a.tet) + a.face] = static_cast<uint32_t>(p);
    if (pairs[p].second != SIZE_MAX) {
      const FaceRecord& b = faces[pairs[p].second];
      pair_of[4 * size_t(b.tet) + b.face] = static_cast<uint32_t>(p);
    }
  }
  auto facet_at = [&](const FaceRecord& rec) -> int64_t {
    const auto it = facet_of.find(rec.key);
    return it == facet_of.end() ? -1 : int64_t(it->second);
  };
  for (size_t p = 0; p < pairs.size() && consistent; ++p) {
    if (pairs[p].second != SIZE_MAX) continue;
    const FaceRecord& a = faces[pairs[p].first];
    const int64_t f = facet_at(a);
    if (f < 0) {
      set(a.tet, 0);
      continue;
    }
    const int front = in_front(a.tet, a.face, uint32_t(f));
    if (front < 0) consistent = false;
    // Outside (winding 0) is the facet's other side.
    const int inside = front ? 0 - 1 : 0 + 1;
    note_side(uint32_t(f), front == 0, 0);
    note_side(uint32_t(f), front == 1, inside);
    set(a.tet, inside);
  }
  for (size_t q = 0; q < queue.size() && consistent; ++q) {
    const uint32_t t = queue[q];
    for (uint8_t i = 0; i < 4; ++i) {
      const auto& pr = pairs[pair_of[4 * size_t(t) + i]];
      if (pr.second == SIZE_MAX) continue;
      const FaceRecord& other = faces[pr.first].tet == t ? faces[pr.second] : faces[pr.first];
      const int64_t f = facet_at(other);
      if (f < 0) {
        set(other.tet, winding[t]);
        continue;
      }
      const int front = in_front(t, i, uint32_t(f));
      if (front < 0) {
        consistent = false;
        break;
      }
      // From the front to the back the winding goes up by one.
      const int value = front ? winding[t] + 1 : winding[t] - 1;
      note_side(uint32_t(f), front == 1, winding[t]);
      note_side(uint32_t(f), front == 0, value);
      set(other.tet, value);
    }
  }
  if (!consistent || std::count(winding.begin(), winding.end(), kUnset) > 0) {
    report.union_skipped = 1;
    return Status::success();
  }
  // A model whose normals all point inwards winds -1 around its inside; one
  // with no winding at all (every cell 0) has no union to speak of.
  const int most = *std::max_element(winding.begin(), winding.end());
  const int least = *std::min_element(winding.begin(), winding.end());
  if (most <= 0 && least >= 0) {
    report.union_skipped = 1;
    return Status::success();
  }
  const bool inverted = most <= 0;
  auto inside = [&](int value) { return inverted ? value <= -1 : value >= 1; };

  std::vector<uint8_t> keep(nf, 1);
  size_t dropped = 0;
  for (size_t f = 0; f < nf; ++f) {
    if (sides[f][0] == kUnset || sides[f][1] == kUnset) continue;  // not in the mesh: keep it
    if (inside(sides[f][0]) != inside(sides[f][1])) continue;
    keep[f] = 0;
    ++dropped;
  }
  if (dropped == 0) return Status::success();
  const std::vector<uint8_t> used_before = used_points(w.plc);
  size_t k = 0;
  for (size_t f = 0; f < nf; ++f) {
    if (!keep[f]) {
      w.mark(w.source[f]);
      continue;
    }
    if (k != f) {
      w.plc.facets[k] = std::move(w.plc.facets[f]);
      w.source[k] = w.source[f];
    }
    ++k;
  }
  w.plc.facets.resize(k);
  w.source.resize(k);
  report.inner_facets = dropped;
  // Points that only dropped facets used go too; isolated points stay.
  const std::vector<uint8_t> used = used_points(w.plc);
  std::vector<VertexId> id(w.plc.points.size(), kNone);
  std::vector<Vec3> kept;
  for (VertexId v = 0; v < w.plc.points.size(); ++v) {
    if (used_before[v] && !used[v]) continue;
    id[v] = static_cast<VertexId>(kept.size());
    kept.push_back(w.plc.points[v]);
  }
  if (kept.size() != w.plc.points.size()) {
    w.plc.points = std::move(kept);
    renumber_vertices(w.plc, id);
  }
  return Status::success();
}

}  // namespace repair_steps
}  // namespace cdt3d
