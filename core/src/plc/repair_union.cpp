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
// Crossing a facet changes the winding by one, up when going from its front
// (where its input facet's normal points, right-hand rule) to its back. The
// winding numbers come from exact ray casting, one ray per patch of facets
// (windings_by_rays); where no ray of a patch is clear of edges and
// vertices, from a tetrahedralization of the arrangement flooded from its
// hull (windings_by_mesh; the two agree facet for facet on every model
// tried). Every decision is an exact sign.
//
// With RepairOptions::parts_as_regions the winding is kept per part (a
// connected component of the input surface): a cell lies in the set of
// parts that wind around it, and a facet stays wherever the sets on its two
// sides differ, so each set becomes a region bounded by internal facets.
// Without it every facet counts as one part, and the set is just "inside".
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
#include <map>
#include <numeric>
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

Orientation orientation_of(const Plc& plc, const Facet& f) {
  Orientation o;
  if (f.loops.empty() || f.loops[0].size() < 3) return o;
  const Vec3 n = newell_normal(plc, f.loops[0]);
  o.drop = largest_axis(n.x, n.y, n.z);
  o.sign = loop_orientation(plc, f.loops[0], o.drop);
  return o;
}

// Winding numbers per part, sparse: (part, winding) for the parts whose
// winding is not 0, sorted by part.
using Windings = std::vector<std::pair<uint32_t, int>>;

void add_winding(Windings& w, uint32_t part, int delta) {
  auto it = std::lower_bound(w.begin(), w.end(), std::make_pair(part, INT_MIN));
  if (it != w.end() && it->first == part) {
    it->second += delta;
    if (it->second == 0) w.erase(it);
  } else if (delta != 0) {
    w.insert(it, {part, delta});
  }
}

// The distinct winding vectors met, numbered: a cell's windings are named
// by their number, so cells compare by an int. Id 0 is outside everything.
class WindingTable {
 public:
  WindingTable() { id(Windings()); }
  int id(const Windings& w) {
    const auto found = ids_.emplace(w, static_cast<int>(list_.size()));
    if (found.second) list_.push_back(w);
    return found.first->second;
  }
  // The windings of `from` with part's changed by delta (one facet crossed).
  int shifted(int from, uint32_t part, int delta) {
    Windings w = list_[static_cast<size_t>(from)];
    add_winding(w, part, delta);
    return id(w);
  }
  const Windings& at(int i) const { return list_[static_cast<size_t>(i)]; }
  // The winding number of all parts together.
  int total(int i) const {
    int sum = 0;
    for (const auto& pw : at(i)) sum += pw.second;
    return sum;
  }
  size_t size() const { return list_.size(); }

 private:
  std::map<Windings, int> ids_;
  std::vector<Windings> list_;
};

// The part of facet f of the PLC under repair (0 for all without parts).
struct PartOf {
  const Work& w;
  const std::vector<uint32_t>& of_input;  // per input facet; empty: one part
  uint32_t operator()(size_t f) const { return of_input.empty() ? 0 : of_input[w.source[f]]; }
};

// The facets, each taken with the orientation of its input facet, form a
// cycle: every directed edge is matched by its reverse as often.
// With parts, each part's facets must close up by themselves, for each
// part to have winding numbers of its own.
bool facets_close_up(const Work& w, const std::vector<int>& runs_like_input, const PartOf& part) {
  struct PartEdgeHash {
    size_t operator()(const std::pair<uint32_t, uint64_t>& k) const {
      return static_cast<size_t>(hash_mix(k.second ^ hash_mix(k.first)));
    }
  };
  std::unordered_map<std::pair<uint32_t, uint64_t>, int64_t, PartEdgeHash> by_part;
  std::unordered_map<uint64_t, int64_t> balance;
  const bool parts = !part.of_input.empty();
  for (size_t f = 0; f < w.plc.facets.size(); ++f) {
    if (runs_like_input[f] == 0) return false;
    for (const auto& loop : w.plc.facets[f].loops)
      for (size_t i = 0; i < loop.size(); ++i) {
        VertexId a = loop[i], b = loop[(i + 1) % loop.size()];
        if (runs_like_input[f] < 0) std::swap(a, b);
        // a -> b counts +1 on the key (min, max) when a < b, else -1.
        if (parts)
          by_part[{part(f), edge_key(a, b)}] += a < b ? 1 : -1;
        else
          balance[edge_key(a, b)] += a < b ? 1 : -1;
      }
  }
  if (parts)
    return std::all_of(by_part.begin(), by_part.end(), [](const auto& kv) { return kv.second == 0; });
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

// The PLC under repair tetrahedralized with its convex hull, every facet a
// constraint of its own (not merged with coplanar neighbours).
Result tetrahedralize_arrangement(const Plc& plc) {
  Options opt;
  opt.keep_convex_hull = true;
  opt.keep_triangles = true;
  opt.check_intersections = false;  // step 4 left none (checked exactly)
  return tetrahedralize(plc, opt);
}

// The constrained faces of a tetrahedralization of the PLC under repair
// (sorted triple -> facet; hull faces that are no facet left out).
std::unordered_map<std::array<VertexId, 3>, uint32_t, TripleHash> facets_by_face(const Result& r,
                                                                                 size_t nf) {
  std::unordered_map<std::array<VertexId, 3>, uint32_t, TripleHash> facet_of;
  facet_of.reserve(r.face_facet.size());
  for (size_t i = 0; i < r.face_facet.size(); ++i) {
    if (r.face_facet[i] >= nf) continue;
    std::array<VertexId, 3> k = {r.mesh.faces[3 * i], r.mesh.faces[3 * i + 1], r.mesh.faces[3 * i + 2]};
    std::sort(k.begin(), k.end());
    facet_of.emplace(k, r.face_facet[i]);
  }
  return facet_of;
}

// The four faces of every tet, sorted: the two sides of a face are
// neighbours, a hull face is alone.
std::vector<FaceRecord> sorted_tet_faces(const Result& r) {
  const size_t nt = r.mesh.tets.size() / 4;
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
  return faces;
}

// The winding numbers by a tetrahedralization of the arrangement (hull
// kept, every facet its own), flooded from the hull: 0 outside it, up by one
// across a face from the front of its input facet to its back (in the
// facet's part). sides[f] gets the ids in `table` of the windings in front
// of facet f and behind it. False when the tetrahedralization fails or the
// flood contradicts itself.
bool windings_by_mesh(const Work& w, const std::vector<Orientation>& input_orientation,
                      const PartOf& part, WindingTable& table,
                      std::vector<std::array<int, 2>>& sides) {
  const size_t nf = w.plc.facets.size();
  const Result r = tetrahedralize_arrangement(w.plc);
  if (!r.status.ok()) return false;
  const std::vector<double>& xyz = r.mesh.points;
  auto pt = [&](uint32_t v) { return &xyz[3 * size_t(v)]; };
  const size_t nt = r.mesh.tets.size() / 4;

  // Constrained faces: sorted triple -> facet.
  const auto facet_of = facets_by_face(r, nf);
  const std::vector<FaceRecord> faces = sorted_tet_faces(r);

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
  sides.assign(nf, {kUnset, kUnset});
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
    const int inside = table.shifted(0, part(size_t(f)), front ? -1 : 1);
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
      const int value = table.shifted(winding[t], part(size_t(f)), front ? 1 : -1);
      note_side(uint32_t(f), front == 1, winding[t]);
      note_side(uint32_t(f), front == 0, value);
      set(other.tet, value);
    }
  }
  return consistent && std::count(winding.begin(), winding.end(), kUnset) == 0;
}

// The winding numbers by exact ray casting, one ray per patch: a patch is
// a set of facets joined across edges that exactly two facets use (where
// the surface goes on smoothly, so the cells on each side go on too). The
// ray starts at the centroid q of one of its triangles and runs along the
// coordinate axis k closest to that triangle's normal; just ahead of q the
// winding is the sum, over the triangles the ray crosses beyond q, of the
// sign of their input facet's normal along k (crossing a facet from its
// back to its front the winding drops by one, and far away it is 0). The
// centroid is never constructed: orient2d and orient3d are affine in it,
// so each test is the exact sign of a sum of three (predicates.hpp). A ray
// through an edge or a vertex, as exact signs tell, is given up for the
// next triangle of the patch; false when a patch has none left.
struct RayTriangle {
  std::array<VertexId, 3> v;
  uint32_t facet;
  Vec3 lo, hi;  // bounding box, for the conservative prefilter
};

constexpr int kRayAttempts = 8;

bool windings_by_rays(const Work& w, const std::vector<Orientation>& input_orientation,
                      const PartOf& part, WindingTable& table,
                      std::vector<std::array<int, 2>>& sides) {
  const Plc& plc = w.plc;
  const size_t nf = plc.facets.size();
  std::vector<uint32_t> tri, tri_facet;
  if (!triangulate_surface(plc, tri, tri_facet).ok()) return false;
  std::vector<RayTriangle> tris(tri_facet.size());
  double scale = 0;
  for (const Vec3& p : plc.points) scale = std::max({scale, std::abs(p.x), std::abs(p.y), std::abs(p.z)});
  for (size_t t = 0; t < tris.size(); ++t) {
    RayTriangle& r = tris[t];
    r.v = {tri[3 * t], tri[3 * t + 1], tri[3 * t + 2]};
    r.facet = tri_facet[t];
    const Vec3 &a = plc.points[r.v[0]], &b = plc.points[r.v[1]], &c = plc.points[r.v[2]];
    r.lo = {std::min({a.x, b.x, c.x}), std::min({a.y, b.y, c.y}), std::min({a.z, b.z, c.z})};
    r.hi = {std::max({a.x, b.x, c.x}), std::max({a.y, b.y, c.y}), std::max({a.z, b.z, c.z})};
  }
  // Patches: facets joined across edges of exactly two facets.
  std::vector<std::pair<uint64_t, uint32_t>> edges;
  for (uint32_t f = 0; f < nf; ++f)
    for (const auto& loop : plc.facets[f].loops)
      for (size_t i = 0; i < loop.size(); ++i)
        edges.push_back({edge_key(loop[i], loop[(i + 1) % loop.size()]), f});
  std::sort(edges.begin(), edges.end());
  std::vector<uint32_t> root(nf);
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](uint32_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  for (size_t i = 0; i < edges.size();) {
    size_t j = i + 1;
    while (j < edges.size() && edges[j].first == edges[i].first) ++j;
    if (j - i == 2) {
      const uint32_t a = find(edges[i].second), b = find(edges[i + 1].second);
      if (a != b) root[std::max(a, b)] = std::min(a, b);
    }
    i = j;
  }
  std::vector<std::vector<uint32_t>> patch_tris(nf);
  for (uint32_t t = 0; t < tris.size(); ++t) patch_tris[find(tris[t].facet)].push_back(t);

  auto pt = [&](VertexId v) { return &plc.points[v].x; };
  // +1 when triangle t's input facet's normal points along +k, -1 along -k,
  // 0 when its plane contains the axis or no orientation is known.
  auto normal_along = [&](uint32_t t, int k) {
    const RayTriangle& r = tris[t];
    const Orientation& in = input_orientation[w.source[r.facet]];
    const int along_k = pred::orient2d_projected(pt(r.v[0]), pt(r.v[1]), pt(r.v[2]), k);
    const int runs = pred::orient2d_projected(pt(r.v[0]), pt(r.v[1]), pt(r.v[2]), in.drop) * in.sign;
    return along_k * runs;
  };
  // The windings just ahead of the centroid of triangle t along +k; false
  // when the ray meets an edge or a vertex.
  auto cast = [&](uint32_t t, int k, Windings& winding) {
    const RayTriangle& r = tris[t];
    const double* q3[3] = {pt(r.v[0]), pt(r.v[1]), pt(r.v[2])};
    const int i = k == 0 ? 1 : k == 1 ? 2 : 0, j = k == 0 ? 2 : k == 1 ? 0 : 1;
    const Vec3& a = plc.points[r.v[0]];
    const Vec3& b = plc.points[r.v[1]];
    const Vec3& c = plc.points[r.v[2]];
    const double qa[3] = {(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3, (a.z + b.z + c.z) / 3};
    // The rounded centroid is within a few ulps of the exact one: the margin
    // only keeps the prefilter conservative; the exact tests decide.
    const double margin = 1e-9 * scale;
    Windings sum;
    for (uint32_t u = 0; u < tris.size(); ++u) {
      if (u == t) continue;
      const RayTriangle& o = tris[u];
      const double lo[3] = {o.lo.x, o.lo.y, o.lo.z}, hi[3] = {o.hi.x, o.hi.y, o.hi.z};
      if (qa[i] < lo[i] - margin || qa[i] > hi[i] + margin || qa[j] < lo[j] - margin ||
          qa[j] > hi[j] + margin || hi[k] < qa[k] - margin)
        continue;
      const double *x = pt(o.v[0]), *y = pt(o.v[1]), *z = pt(o.v[2]);
      const int s = pred::orient2d_projected(x, y, z, k);
      if (s == 0) continue;  // parallel to the ray: met edge-on only, which its neighbours show
      const int e[3] = {pred::orient2d_centroid_projected(x, y, q3, k),
                        pred::orient2d_centroid_projected(y, z, q3, k),
                        pred::orient2d_centroid_projected(z, x, q3, k)};
      if (e[0] == -s || e[1] == -s || e[2] == -s) continue;  // the ray passes beside it
      if (e[0] == 0 || e[1] == 0 || e[2] == 0) return false;  // through its edge or corner
      const int h = pred::orient3d_centroid(x, y, z, q3);
      if (h == 0) return false;  // q in its plane (no triangle but t contains q)
      if (h != s) continue;      // its plane is behind q
      const int n = normal_along(u, k);
      if (n == 0) return false;
      add_winding(sum, part(o.facet), n);
    }
    winding = std::move(sum);
    return true;
  };

  sides.assign(nf, {kUnset, kUnset});
  for (uint32_t p = 0; p < nf; ++p) {
    if (patch_tris[p].empty()) continue;
    bool done = false;
    for (size_t a = 0; a < patch_tris[p].size() && a < size_t(kRayAttempts) && !done; ++a) {
      // Spread the attempts over the patch.
      const uint32_t t = patch_tris[p][a * patch_tris[p].size() / std::min(patch_tris[p].size(), size_t(kRayAttempts))];
      const RayTriangle& r = tris[t];
      const Vec3 &x = plc.points[r.v[0]], &y = plc.points[r.v[1]], &z = plc.points[r.v[2]];
      const Vec3 n = cross(y - x, z - x);
      const int k = largest_axis(n.x, n.y, n.z);
      const int own = normal_along(t, k);
      Windings windings;
      if (own == 0 || !cast(t, k, windings)) continue;
      // Ahead of q lies the front of t's facet when its normal points along
      // +k; behind it, t's part winds once more.
      const int ahead = table.id(windings);
      const uint32_t p_t = part(r.facet);
      const std::array<int, 2> fb = own > 0
                                        ? std::array<int, 2>{ahead, table.shifted(ahead, p_t, 1)}
                                        : std::array<int, 2>{table.shifted(ahead, p_t, -1), ahead};
      for (uint32_t u : patch_tris[p]) sides[tris[u].facet] = fb;
      done = true;
    }
    if (!done) return false;
  }
  return true;
}

// The region of every winding vector that is on some facet's side: 0
// outside the union, else (without parts) 1, or (with parts) the attribute
// of the set of parts that wind around the cell (RepairReport::region_parts).
std::vector<int32_t> region_labels(const WindingTable& table,
                                   const std::vector<std::array<int, 2>>& sides, bool inverted,
                                   size_t parts, RepairReport& report) {
  auto inside = [inverted](int value) { return inverted ? value <= -1 : value >= 1; };
  std::vector<int32_t> label(table.size(), -1);
  std::vector<std::vector<uint32_t>> set_of(table.size());
  std::map<std::vector<uint32_t>, int32_t> overlaps;  // sorted: numbered in this order
  for (const auto& side : sides)
    for (int id : side) {
      if (id == kUnset || label[size_t(id)] != -1) continue;
      const int total = table.total(id);
      label[size_t(id)] = inside(total) ? 1 : 0;
      if (parts == 0 || !inside(total)) continue;
      for (const auto& pw : table.at(id))
        if (inside(pw.second)) set_of[size_t(id)].push_back(pw.first);
      if (set_of[size_t(id)].size() > 1) overlaps.emplace(set_of[size_t(id)], 0);
    }
  if (parts == 0) return label;
  report.region_parts.assign(parts, {});
  for (size_t p = 0; p < parts; ++p) report.region_parts[p] = {uint32_t(p)};
  for (auto& o : overlaps) {
    o.second = static_cast<int32_t>(report.region_parts.size() + 1);
    report.region_parts.push_back(o.first);
  }
  std::vector<uint8_t> has_cell(parts, 0);
  for (size_t id = 0; id < table.size(); ++id) {
    if (label[id] != 1) continue;
    const std::vector<uint32_t>& set = set_of[id];
    if (set.size() == 1) has_cell[set[0]] = 1;
    label[id] = set.size() == 1 ? int32_t(set[0] + 1) : overlaps.at(set);
  }
  for (size_t p = 0; p < parts; ++p)
    if (!has_cell[p]) report.region_parts[p].clear();
  return label;
}

// Drops the facets not flagged in `keep`, with the points only they used
// (isolated points stay), keeping `regions` and `axis` (when filled) in
// step with the facets.
void drop_facets(Work& w, const std::vector<uint8_t>& keep,
                 std::vector<std::array<int32_t, 2>>& regions, std::vector<uint8_t>& axis) {
  const size_t nf = w.plc.facets.size();
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
      if (!regions.empty()) regions[k] = regions[f], axis[k] = axis[f];
    }
    ++k;
  }
  w.plc.facets.resize(k);
  w.source.resize(k);
  if (!regions.empty()) regions.resize(k), axis.resize(k);
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
}

// Where the facets do not close up (normals that disagree, fins, open
// pieces) there are no winding numbers, but the outside still exists: the
// cells that a tetrahedralization of the arrangement (hull kept) connects
// to the hull without crossing a facet. A facet with the outside on both
// sides (a fin hinged on a seam, a sheet beside the model) bounds no volume,
// and meshing would end on it as an open surface; such facets are dropped
// when they are the lesser part of the surface (by area). Where they are
// most of it (a soup of triangles, an open surface with a few pockets
// closed by crossings) the model is no solid with fins but an open
// surface: every facet stays, for meshing to report the opening or to keep
// as constraints inside the hull; unless `solid` (fill_holes: the caller
// asked for a closed solid), when what bounds no volume goes whatever its
// share. Returns the number dropped.
size_t drop_outside_facets(Work& w, bool solid) {
  const size_t nf = w.plc.facets.size();
  const Result r = tetrahedralize_arrangement(w.plc);
  const size_t nt = r.mesh.tets.size() / 4;
  if (!r.status.ok() || r.mesh.tet_attributes.size() != nt) return 0;
  const auto facet_of = facets_by_face(r, nf);
  const std::vector<FaceRecord> faces = sorted_tet_faces(r);
  // The outside: the regions (connected across faces that are no facet's)
  // of the tets on hull faces that are no facet's.
  std::vector<double> outside;
  for (size_t i = 0; i < faces.size();) {
    size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j - i == 1 && !facet_of.count(faces[i].key)) outside.push_back(r.mesh.tet_attributes[faces[i].tet]);
    i = j;
  }
  std::sort(outside.begin(), outside.end());
  auto is_outside = [&](uint32_t t) {
    return std::binary_search(outside.begin(), outside.end(), r.mesh.tet_attributes[t]);
  };
  // 0: no face of the facet in the mesh (kept), 1: outside on every side, 2: touches the inside.
  std::vector<uint8_t> seen(nf, 0);
  bool any_inside = false;
  for (const FaceRecord& rec : faces) {
    const bool out = is_outside(rec.tet);
    any_inside = any_inside || !out;
    const auto it = facet_of.find(rec.key);
    if (it == facet_of.end()) continue;
    uint8_t& s = seen[it->second];
    s = std::max<uint8_t>(s, out ? 1 : 2);
  }
  if (!any_inside) return 0;
  // A policy between two readings of the model, not a geometric decision:
  // areas in doubles are enough.
  double outside_area = 0, inside_area = 0;
  for (size_t f = 0; f < nf; ++f) {
    if (seen[f] == 0 || w.plc.facets[f].loops.empty()) continue;
    const double a = norm(newell_normal(w.plc, w.plc.facets[f].loops[0]));
    (seen[f] == 1 ? outside_area : inside_area) += a;
  }
  if (!solid && !(outside_area < inside_area)) return 0;
  std::vector<uint8_t> keep(nf, 1);
  size_t dropped = 0;
  for (size_t f = 0; f < nf; ++f)
    if (seen[f] == 1) keep[f] = 0, ++dropped;
  std::vector<std::array<int32_t, 2>> no_regions;
  std::vector<uint8_t> no_axis;
  if (dropped > 0) drop_facets(w, keep, no_regions, no_axis);
  return dropped;
}

}  // namespace

Status merge_into_union(Work& w, const Plc& input, const std::vector<uint32_t>& part_of_input,
                        RepairReport& report, const RepairOptions& options) {
  const bool by_mesh_only = options.debug_union_by_mesh;
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
    const int own = loop_orientation(w.plc, loops[0], in.drop);
    if (own != 0) runs_like_input[f] = own == in.sign ? 1 : -1;
  }
  const PartOf part{w, part_of_input};
  if (!facets_close_up(w, runs_like_input, part)) {
    report.union_skipped = 1;
    report.outside_facets = drop_outside_facets(w, options.fill_holes);
    return Status::success();
  }

  // Per facet: the ids in `table` of the windings in front of it and behind.
  std::vector<std::array<int, 2>> sides;
  // Rays first (fast: one per patch); the tetrahedralization where a patch
  // had no ray clear of edges and vertices.
  WindingTable table;
  const bool by_rays = !by_mesh_only && windings_by_rays(w, input_orientation, part, table, sides);
  if (!by_rays) table = WindingTable();
  if (!by_rays && !windings_by_mesh(w, input_orientation, part, table, sides)) {
    report.union_skipped = 1;
    report.outside_facets = drop_outside_facets(w, options.fill_holes);
    return Status::success();
  }
  // A model whose normals all point inwards winds -1 around its inside; one
  // with no winding at all (every cell 0) has no union to speak of.
  int most = INT_MIN, least = INT_MAX;
  for (const auto& side : sides)
    for (int id : side) {
      if (id == kUnset) continue;
      most = std::max(most, table.total(id)), least = std::min(least, table.total(id));
    }
  if (most <= 0 && least >= 0) {
    report.union_skipped = 1;
    report.outside_facets = drop_outside_facets(w, options.fill_holes);
    return Status::success();
  }
  const bool inverted = most <= 0;
  size_t parts = 0;
  for (uint32_t p : part_of_input)
    if (p != kNone) parts = std::max(parts, size_t(p) + 1);
  const std::vector<int32_t> label = region_labels(table, sides, inverted, parts, report);

  std::vector<uint8_t> keep(nf, 1);
  std::vector<std::array<int32_t, 2>> regions;  // per facet: on its +axis side, on its -axis side
  std::vector<uint8_t> axis;
  if (parts > 0) regions.assign(nf, {-1, -1}), axis.assign(nf, 0);
  size_t dropped = 0;
  for (size_t f = 0; f < nf; ++f) {
    if (sides[f][0] == kUnset || sides[f][1] == kUnset) continue;  // not in the mesh: keep it
    const int32_t front = label[size_t(sides[f][0])], back = label[size_t(sides[f][1])];
    if (parts > 0) {
      // The input facet's normal points to its front; in.sign is the sign
      // of that normal's component along in.drop (loop_orientation).
      const Orientation& in = input_orientation[w.source[f]];
      axis[f] = static_cast<uint8_t>(in.drop);
      regions[f] = in.sign > 0 ? std::array<int32_t, 2>{front, back}
                               : std::array<int32_t, 2>{back, front};
    }
    if (front != back) continue;
    keep[f] = 0;
    ++dropped;
  }
  if (dropped > 0) drop_facets(w, keep, regions, axis);
  report.inner_facets = dropped;
  report.parts = parts;
  report.facet_regions = std::move(regions);
  report.facet_axis = std::move(axis);
  return Status::success();
}

std::vector<uint32_t> connected_parts(const Work& w, size_t input_facets) {
  const size_t nf = w.plc.facets.size();
  std::vector<uint32_t> root(nf);
  std::iota(root.begin(), root.end(), 0);
  auto find = [&](uint32_t x) {
    while (root[x] != x) x = root[x] = root[root[x]];
    return x;
  };
  auto join = [&](uint32_t a, uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) root[std::max(a, b)] = std::min(a, b);
  };
  std::vector<std::pair<uint64_t, uint32_t>> edges;
  for (uint32_t f = 0; f < nf; ++f)
    for (const auto& loop : w.plc.facets[f].loops)
      for (size_t i = 0; i < loop.size(); ++i)
        edges.push_back({edge_key(loop[i], loop[(i + 1) % loop.size()]), f});
  std::sort(edges.begin(), edges.end());
  for (size_t i = 1; i < edges.size(); ++i)
    if (edges[i].first == edges[i - 1].first) join(edges[i - 1].second, edges[i].second);
  // Pieces of one input facet (a loop cut where it came back to a vertex
  // meets itself at a point only) are one part.
  std::vector<uint32_t> first_piece(input_facets, kNone);
  for (uint32_t f = 0; f < nf; ++f) {
    uint32_t& first = first_piece[w.source[f]];
    if (first == kNone) first = f;
    else join(first, f);
  }
  // Numbered in order of their smallest input facet.
  std::vector<uint32_t> number(nf, kNone), part_of_input(input_facets, kNone);
  uint32_t parts = 0;
  for (size_t s = 0; s < input_facets; ++s) {
    if (first_piece[s] == kNone) continue;
    const uint32_t r = find(first_piece[s]);
    if (number[r] == kNone) number[r] = parts++;
    part_of_input[s] = number[r];
  }
  return part_of_input;
}

void label_part_regions(const RepairReport& report, Result& result) {
  TetMeshData& m = result.mesh;
  const size_t nt = m.tets.size() / 4;
  if (report.facet_regions.empty() || !result.status.ok() || nt == 0) return;
  std::unordered_map<std::array<VertexId, 3>, uint32_t, TripleHash> facet_of;
  facet_of.reserve(result.face_facet.size());
  for (size_t i = 0; i < result.face_facet.size() && 3 * i + 2 < m.faces.size(); ++i) {
    if (result.face_facet[i] >= report.facet_regions.size()) continue;
    std::array<VertexId, 3> k = {m.faces[3 * i], m.faces[3 * i + 1], m.faces[3 * i + 2]};
    std::sort(k.begin(), k.end());
    facet_of.emplace(k, result.face_facet[i]);
  }
  // The tets of one region of tetrahedralize() (connected across faces that
  // are no constraints) share an attribute, and lie on one side of every
  // facet they touch: one face per region tells its part set.
  const bool attributed = m.tet_attributes.size() == nt;
  auto old = [&](size_t t) { return attributed ? m.tet_attributes[t] : 0.0; };
  std::map<double, int32_t> to;
  std::vector<double> distinct(attributed ? m.tet_attributes : std::vector<double>{0.0});
  std::sort(distinct.begin(), distinct.end());
  const size_t regions = size_t(std::unique(distinct.begin(), distinct.end()) - distinct.begin());
  auto pt = [&](uint32_t v) { return &m.points[3 * size_t(v)]; };
  for (size_t t = 0; t < nt && to.size() < regions; ++t) {
    if (to.count(old(t))) continue;
    const uint32_t* tv = &m.tets[4 * t];
    for (int i = 0; i < 4; ++i) {
      uint32_t abc[3];
      for (int j = 0, n = 0; j < 4; ++j)
        if (j != i) abc[n++] = tv[j];
      std::array<VertexId, 3> key = {abc[0], abc[1], abc[2]};
      std::sort(key.begin(), key.end());
      const auto it = facet_of.find(key);
      if (it == facet_of.end()) continue;
      const int axis = report.facet_axis[it->second];
      // The sign of the face's normal along the axis (the facet's normal is
      // largest there, so it is not 0), and the apex's side of the face.
      const int along = pred::orient2d_projected(pt(abc[0]), pt(abc[1]), pt(abc[2]), axis);
      const int side = pred::orient3d(pt(abc[0]), pt(abc[1]), pt(abc[2]), pt(tv[i]));
      if (along == 0 || side == 0) continue;
      // orient3d < 0: the apex lies where the face's normal points.
      const int32_t region = report.facet_regions[it->second][along * side < 0 ? 0 : 1];
      if (region < 0) continue;
      to.emplace(old(t), region);
      break;
    }
  }
  m.tet_attributes.resize(nt);
  for (size_t t = 0; t < nt; ++t) {
    const auto it = to.find(old(t));
    m.tet_attributes[t] = it == to.end() ? 0.0 : double(it->second);
  }
}

Status add_part_region_points(Plc& plc, const RepairReport& report) {
  if (report.facet_regions.empty()) return Status::success();
  Result r = tetrahedralize(plc);
  if (!r.status.ok()) return r.status;
  label_part_regions(report, r);
  const TetMeshData& m = r.mesh;
  const size_t nt = m.tets.size() / 4;
  if (m.tet_attributes.size() != nt) return Status::success();
  auto pt = [&](uint32_t v) { return &m.points[3 * size_t(v)]; };
  std::vector<double> placed;
  for (size_t t = 0; t < nt; ++t) {
    const double a = m.tet_attributes[t];
    if (std::find(placed.begin(), placed.end(), a) != placed.end()) continue;
    // The tet's centroid, rounded to doubles: kept only where it is still
    // strictly inside the tet (exact signs), else another tet of the region.
    const uint32_t* tv = &m.tets[4 * t];
    double c[3];
    for (int k = 0; k < 3; ++k) c[k] = (pt(tv[0])[k] + pt(tv[1])[k] + pt(tv[2])[k] + pt(tv[3])[k]) / 4;
    bool inside = true;
    for (int i = 0; i < 4 && inside; ++i) {
      const double* f[3];
      for (int j = 0, n = 0; j < 4; ++j)
        if (j != i) f[n++] = pt(tv[j]);
      const int apex = pred::orient3d(f[0], f[1], f[2], pt(tv[i]));
      inside = apex != 0 && pred::orient3d(f[0], f[1], f[2], c) == apex;
    }
    if (!inside) continue;
    plc.regions.push_back(Region{Vec3{c[0], c[1], c[2]}, a, -1});
    placed.push_back(a);
  }
  return Status::success();
}

}  // namespace repair_steps
}  // namespace cdt3d
