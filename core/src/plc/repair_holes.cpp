// Repair step 3b (RepairOptions::fill_holes, after the T-junctions): every boundary loop of an open
// surface is closed by triangles. A boundary edge is a polygon edge that an
// odd number of facets uses (boundary_edges); the loops are traced against the facets' orientation, so
// the patch continues the surface's sides. Each loop is first triangulated
// with the smallest total area (the dynamic programme of Liepa 2003, "Filling
// holes in meshes", with area as the weight; no triangle of three collinear
// points) from the loop's own vertices. A planar loop is triangulated as the
// polygon it is (planar_triangulation) and left so: the mesher meshes a flat
// facet's inside itself, and a point constructed in the plane would be
// rounded off it. A non-planar loop's patch is then refined and faired as in
// Liepa 2003 (sections 3.2 and 3.3): triangles split at their centroids until
// their size matches the edges around the hole, edges swapped towards
// Delaunay, and the new points faired (a membrane, then a thin plate leaning
// on the surface around the rim), so the patch's triangles fit their
// neighbours. Those points are constructed (rounded to doubles, then to step
// 4's snap grid). The T-junction step and step 4 then treat the patch like
// any other facets (a patch that crosses the surface is cut along the
// crossing in step 4).
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "geometry.hpp"
#include "predicates.hpp"
#include "repair.hpp"

namespace cdt3d {
namespace repair_steps {
namespace {

// Loops above this size are closed by clipping the ear of least area, one
// at a time (the dynamic programme is cubic in the loop's size).
constexpr size_t kMaxOptimalLoop = 240;

uint64_t undirected(VertexId a, VertexId b) {
  return (uint64_t{std::min(a, b)} << 32) | std::max(a, b);
}

double area(const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 u = b - a, v = c - a;
  return 0.5 * norm(cross(u, v));
}

// A boundary edge in the direction the patch uses it (against its facet's
// loop), with the facet it borders.
struct FillEdge {
  VertexId from, to;
  uint32_t facet;
  bool closing = false;  ///< three or more facets use it: it only closes a loop (trace_loops)
};

// The boundary edges of the PLC, reversed: one facet uses the edge and no
// explicit segment is along it (a facet standing on a segment is closed
// there, as the self-intersection test treats it). Also, as `closing`
// edges, those an odd number of three or more facets uses: where a part
// touches another along an edge, a hole that runs into that edge is closed
// by it. Each edge once, in the direction most of its facets do not use
// (the surfaces that close up there use it both ways), with a facet that
// uses it the other way.
std::vector<FillEdge> boundary_edges(const Plc& plc) {
  struct Uses {
    uint32_t count = 0;
    int32_t net = 0;  // uses from the lower to the higher id, minus the others
    bool done = false;
  };
  std::unordered_map<uint64_t, Uses> uses;
  for (const Facet& f : plc.facets)
    for (const auto& loop : f.loops)
      for (size_t i = 0; i < loop.size(); ++i) {
        const VertexId a = loop[i], b = loop[(i + 1) % loop.size()];
        Uses& u = uses[undirected(a, b)];
        ++u.count;
        u.net += a < b ? 1 : -1;
      }
  std::vector<uint64_t> segments;
  for (const auto& s : plc.segments) segments.push_back(undirected(s[0], s[1]));
  std::sort(segments.begin(), segments.end());
  std::vector<FillEdge> out;
  for (uint32_t fi = 0; fi < plc.facets.size(); ++fi)
    for (const auto& loop : plc.facets[fi].loops)
      for (size_t i = 0; i < loop.size(); ++i) {
        const VertexId a = loop[i], b = loop[(i + 1) % loop.size()];
        const uint64_t key = undirected(a, b);
        Uses& u = uses[key];
        if (u.count % 2 == 0 || u.done || (u.net > 0) != (a < b)) continue;
        if (std::binary_search(segments.begin(), segments.end(), key)) continue;
        u.done = true;
        out.push_back({b, a, fi, u.count > 1});
      }
  return out;
}

// Closed loops of fill edges. At a vertex where several boundary loops
// touch (a non-manifold vertex) the walk takes any unused edge; a walk that
// comes back to a vertex of its own path cuts the cycle off there, so every
// loop is simple. Edges that close no loop are left.
std::vector<std::vector<FillEdge>> trace_loops(const std::vector<FillEdge>& edges) {
  std::unordered_map<VertexId, std::vector<size_t>> out_of;
  for (size_t e = 0; e < edges.size(); ++e) out_of[edges[e].from].push_back(e);
  std::vector<char> used(edges.size(), 0);
  std::vector<std::vector<FillEdge>> loops;
  // First the loops of edges of one facet; then closing edges may finish
  // the chains left open.
  for (size_t pass = 0; pass < 2; ++pass) {
    for (size_t start = 0; start < edges.size(); ++start) {
      if (used[start] || edges[start].closing) continue;
      std::vector<size_t> path{start};
      std::unordered_map<VertexId, size_t> at;  // vertex -> its index in path (as `from`)
      at[edges[start].from] = 0;
      used[start] = 1;
      while (!path.empty()) {
        const VertexId v = edges[path.back()].to;
        if (auto it = at.find(v); it != at.end()) {
          // A cycle from path[first] to the end.
          const size_t first = it->second;
          std::vector<FillEdge> loop;
          for (size_t k = first; k < path.size(); ++k) {
            loop.push_back(edges[path[k]]);
            at.erase(edges[path[k]].from);
          }
          path.resize(first);
          loops.push_back(std::move(loop));
          if (path.empty()) break;
          continue;
        }
        size_t next = edges.size();
        for (size_t e : out_of[v])
          if (!used[e] && (pass == 1 || !edges[e].closing)) {
            next = e;
            break;
          }
        if (next == edges.size()) {  // open chain: no loop here
          // Its edges may still close with a closing edge in the second pass.
          if (pass == 0)
            for (size_t e : path) used[e] = 0;
          break;
        }
        used[next] = 1;
        at[v] = path.size();
        path.push_back(next);
      }
    }
  }
  return loops;
}

// Triangles of the loop's vertices with the smallest total area, none of
// three collinear points and none with an edge across the loop that is in
// `edges` (an edge of the surface would then have three facets or more:
// two faces of a tetrahedron, whose rim's least-area patch is those two
// faces again); empty when there is no such triangulation.
std::vector<std::array<VertexId, 3>> min_area_triangulation(const Plc& plc,
                                                            const std::vector<VertexId>& v,
                                                            const std::unordered_set<uint64_t>& edges) {
  const size_t n = v.size();
  const double inf = std::numeric_limits<double>::infinity();
  auto across = [&](size_t i, size_t j) {  // a diagonal of the loop that exists
    return j - i >= 2 && !(i == 0 && j == n - 1) && edges.count(undirected(v[i], v[j])) > 0;
  };
  auto weight = [&](size_t i, size_t k, size_t j) {
    const Vec3 &a = plc.points[v[i]], &b = plc.points[v[k]], &c = plc.points[v[j]];
    if (pred::collinear3d(&a.x, &b.x, &c.x) || across(i, k) || across(k, j) || across(i, j)) return inf;
    return area(a, b, c);
  };
  std::vector<double> cost(n * n, 0);
  std::vector<uint32_t> split(n * n, 0);
  for (size_t len = 2; len < n; ++len)
    for (size_t i = 0; i + len < n; ++i) {
      const size_t j = i + len;
      double best = inf;
      uint32_t arg = 0;
      for (size_t k = i + 1; k < j; ++k) {
        const double c = cost[i * n + k] + cost[k * n + j] + weight(i, k, j);
        if (c < best) best = c, arg = static_cast<uint32_t>(k);
      }
      cost[i * n + j] = best;
      split[i * n + j] = arg;
    }
  std::vector<std::array<VertexId, 3>> tris;
  if (!std::isfinite(cost[n - 1])) return tris;
  std::vector<std::pair<size_t, size_t>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j - i < 2) continue;
    const size_t k = split[i * n + j];
    tris.push_back({v[i], v[k], v[j]});
    stack.push_back({i, k});
    stack.push_back({k, j});
  }
  return tris;
}

// Large loops: the ear of least area first, again and again (quadratic);
// as there, no ear whose new edge is in `edges`.
std::vector<std::array<VertexId, 3>> ear_triangulation(const Plc& plc, std::vector<VertexId> v,
                                                       const std::unordered_set<uint64_t>& edges) {
  std::vector<std::array<VertexId, 3>> tris;
  while (v.size() > 3) {
    size_t best = v.size();
    double best_area = std::numeric_limits<double>::infinity();
    for (size_t i = 0; i < v.size(); ++i) {
      const VertexId pa = v[(i + v.size() - 1) % v.size()], pc = v[(i + 1) % v.size()];
      const Vec3& a = plc.points[pa];
      const Vec3& b = plc.points[v[i]];
      const Vec3& c = plc.points[pc];
      if (pred::collinear3d(&a.x, &b.x, &c.x) || edges.count(undirected(pa, pc)) > 0) continue;
      const double s = area(a, b, c);
      if (s < best_area) best_area = s, best = i;
    }
    if (best == v.size()) return {};
    tris.push_back({v[(best + v.size() - 1) % v.size()], v[best], v[(best + 1) % v.size()]});
    v.erase(v.begin() + static_cast<std::ptrdiff_t>(best));
  }
  const Vec3 &a = plc.points[v[0]], &b = plc.points[v[1]], &c = plc.points[v[2]];
  if (pred::collinear3d(&a.x, &b.x, &c.x)) return {};
  tris.push_back({v[0], v[1], v[2]});
  return tris;
}

// The least-area patch of loop v, by the dynamic programme or, for large
// loops, by ears; no edge across the loop that is in `edges`.
std::vector<std::array<VertexId, 3>> least_area_patch(const Plc& plc, const std::vector<VertexId>& v,
                                                      const std::unordered_set<uint64_t>& edges) {
  return v.size() <= kMaxOptimalLoop ? min_area_triangulation(plc, v, edges) : ear_triangulation(plc, v, edges);
}

// A loop whose vertices are exactly coplanar: its constrained triangulation
// as a polygon (triangulate_surface), each triangle turned like the loop.
// A least-area set of triangles of a non-convex planar loop can fold over
// itself; the polygon's own triangulation cannot. Empty when the loop is
// not planar or not a simple polygon in its plane.
std::vector<std::array<VertexId, 3>> planar_triangulation(const Plc& plc,
                                                          const std::vector<VertexId>& v) {
  const double* a = &plc.points[v[0]].x;
  size_t ib = 1, ic = 0;
  for (; ib < v.size() && plc.points[v[ib]] == plc.points[v[0]]; ++ib) {
  }
  if (ib >= v.size()) return {};
  const double* b = &plc.points[v[ib]].x;
  for (size_t i = ib + 1; i < v.size() && ic == 0; ++i)
    if (!pred::collinear3d(a, b, &plc.points[v[i]].x)) ic = i;
  if (ic == 0) return {};
  const double* c = &plc.points[v[ic]].x;
  for (VertexId x : v)
    if (pred::orient3d(a, b, c, &plc.points[x].x) != 0) return {};
  int drop = 0;
  while (drop < 2 && pred::orient2d_projected(a, b, c, drop) == 0) ++drop;
  // The loop's turn: at its lowest vertex (in the projection) it is convex.
  const int ua = (drop + 1) % 3, va = (drop + 2) % 3;
  size_t low = 0;
  for (size_t i = 1; i < v.size(); ++i) {
    const double *p = &plc.points[v[i]].x, *q = &plc.points[v[low]].x;
    if (p[ua] < q[ua] || (p[ua] == q[ua] && p[va] < q[va])) low = i;
  }
  const size_t n = v.size();
  const int turn = pred::orient2d_projected(&plc.points[v[(low + n - 1) % n]].x, &plc.points[v[low]].x,
                                            &plc.points[v[(low + 1) % n]].x, drop);
  if (turn == 0) return {};
  Plc part;
  part.points = plc.points;
  Facet f;
  f.loops.push_back(v);
  part.facets.push_back(f);
  std::vector<uint32_t> tris, tri_facet;
  if (!triangulate_surface(part, tris, tri_facet).ok()) return {};
  std::vector<std::array<VertexId, 3>> out;
  for (size_t k = 0; k + 2 < tris.size(); k += 3) {
    std::array<VertexId, 3> t{tris[k], tris[k + 1], tris[k + 2]};
    if (pred::orient2d_projected(&plc.points[t[0]].x, &plc.points[t[1]].x, &plc.points[t[2]].x, drop) != turn)
      std::swap(t[1], t[2]);
    out.push_back(t);
  }
  return out;
}

// --- Refinement and fairing of a non-planar loop's patch (Liepa 2003) ---

using Tri = std::array<VertexId, 3>;

// Liepa's density factor: a triangle is split while its centroid lies
// further than sigma / sqrt(2) from each of its corners.
constexpr double kDensity = 1.4142135623730951;  // sqrt(2)
// Gauss-Seidel sweeps of each fairing stage at most; they stop sooner once
// no point moves more than kFairSettled of the largest sigma.
constexpr int kFairSweeps = 200;
constexpr double kFairSettled = 1e-6;

uint64_t directed(VertexId a, VertexId b) { return (uint64_t{a} << 32) | b; }

// The scale of the surface around the holes, measured before any patch is
// added: per rim vertex sigma, the mean length of the surface's edges at it
// (Liepa's sigma); and the undirected edges between two rim vertices that
// are taken already (by the surface, later also by a patch), which a patch
// across a loop or a swap must not make again; per rim vertex its neighbours in the surface (the
// fixed ring the thin-plate fairing leans on).
struct RimScale {
  std::unordered_map<VertexId, double> sigma;
  std::unordered_set<uint64_t> taken;
  std::unordered_map<VertexId, std::vector<VertexId>> ring;
};

RimScale rim_scale(const Plc& plc, const std::vector<std::vector<FillEdge>>& loops) {
  std::unordered_map<VertexId, std::pair<double, size_t>> sum;  // length sum, edge count
  for (const auto& loop : loops)
    for (const FillEdge& e : loop) sum[e.from] = {0, 0};
  RimScale rim;
  std::unordered_set<uint64_t> seen;
  for (const Facet& f : plc.facets)
    for (const auto& l : f.loops)
      for (size_t i = 0; i < l.size(); ++i) {
        const VertexId a = l[i], b = l[(i + 1) % l.size()];
        const auto ia = sum.find(a), ib = sum.find(b);
        if ((ia == sum.end() && ib == sum.end()) || !seen.insert(undirected(a, b)).second) continue;
        const double len = dist(plc.points[a], plc.points[b]);
        for (auto it : {ia, ib})
          if (it != sum.end()) it->second.first += len, ++it->second.second;
        if (ia != sum.end()) rim.ring[a].push_back(b);
        if (ib != sum.end()) rim.ring[b].push_back(a);
        if (ia != sum.end() && ib != sum.end()) rim.taken.insert(undirected(a, b));
      }
  for (const auto& [v, s] : sum) rim.sigma[v] = s.second ? s.first / double(s.second) : 0;
  return rim;
}

// Whether the angles at c (in triangle a-b-c) and at d (in b-a-d) sum to
// more than pi: sin(C + D) = sin C cos D + cos C sin D < 0, each sine and
// cosine times the positive product of its edge lengths (the cotangent test
// of Delaunay edges). Sums, products and square roots only: rounded alike
// on every platform, so the native and the WASM builds swap the same edges.
bool angles_exceed_pi(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 u1 = a - c, v1 = b - c, u2 = a - d, v2 = b - d;
  return norm(cross(u1, v1)) * dot(u2, v2) + dot(u1, v1) * norm(cross(u2, v2)) < 0;
}

bool collinear(const Plc& plc, VertexId a, VertexId b, VertexId c) {
  return pred::collinear3d(&plc.points[a].x, &plc.points[b].x, &plc.points[c].x);
}

// One loop's patch: oriented triangles, each directed edge owned by one of
// them; the edges the patch shares with the surface (its rim) are owned once.
// New points are appended to the PLC's points.
class Patch {
 public:
  Patch(Plc& plc, const std::vector<Tri>& tris, const RimScale& rim, double grid)
      : plc_(plc), rim_(rim), grid_(grid), first_new_(static_cast<VertexId>(plc.points.size())) {
    for (const Tri& t : tris) add(t);
    for (const Tri& t : tris)
      for (VertexId v : t) sigma_[v] = rim.sigma.at(v);
  }

  // Liepa's refinement: split every triangle too large for the sigma of its
  // corners at its centroid (relaxing the edges around it), swap all edges
  // towards Delaunay, and again, until nothing is split or the patch has
  // `max_points` new points.
  void refine(size_t max_points) {
    while (new_points() < max_points && split_pass(max_points)) relax_all();
  }

  // Fairing with the rim fixed (Liepa 2003, section 3.3), by Gauss-Seidel
  // sweeps: first the membrane, the umbrella operator U = 0 (each new point
  // to the average of its neighbours); then from there the thin plate,
  // U^2 = 0, whose rim vertices' umbrellas reach into the surface, so the
  // patch leaves the rim with the surface's slope. Each stage is undone when
  // it leaves a triangle of three collinear points or more folded edges.
  void fair() {
    if (new_points() == 0) return;
    const Rings ring = rings();
    keep_if_valid([&] { sweep_until_settled([&](VertexId v) { return mean_of(ring.at(v)); }); });
    keep_if_valid([&] { sweep_until_settled([&](VertexId v) { return thin_plate_step(ring, v); }); });
  }

  size_t new_points() const { return plc_.points.size() - first_new_; }
  const std::vector<Tri>& triangles() const { return tris_; }

 private:
  void add(const Tri& t) { set(static_cast<uint32_t>(tris_.size()), t), tris_.push_back(t); }
  void set(uint32_t i, const Tri& t) {
    if (i < tris_.size()) tris_[i] = t;
    for (int k = 0; k < 3; ++k) owner_[directed(t[k], t[(k + 1) % 3])] = i;
  }
  uint32_t owner(VertexId a, VertexId b) const {
    const auto it = owner_.find(directed(a, b));
    return it == owner_.end() ? kNone : it->second;
  }
  static constexpr uint32_t kNone = std::numeric_limits<uint32_t>::max();

  // One pass over the triangles there are; true when some triangle was split.
  bool split_pass(size_t max_points) {
    bool split = false;
    const size_t n = tris_.size();
    for (size_t t = 0; t < n && new_points() < max_points; ++t)
      if (split_if_large(static_cast<uint32_t>(t))) split = true;
    return split;
  }

  // Liepa's test: split at the centroid c when kDensity |c - v| exceeds both
  // sigma(c) (the mean of the corners' sigma) and sigma(v) for every corner
  // v. Not when a piece would have three collinear points (a needle whose
  // rounded centroid falls on its line).
  bool split_if_large(uint32_t t) {
    const Tri tri = tris_[t];
    const Vec3 &a = plc_.points[tri[0]], &b = plc_.points[tri[1]], &c = plc_.points[tri[2]];
    const Vec3 centre = snapped((1.0 / 3.0) * (a + b + c), grid_);
    const double s = (sigma_[tri[0]] + sigma_[tri[1]] + sigma_[tri[2]]) / 3;
    for (VertexId v : tri) {
      const double d = kDensity * dist(centre, plc_.points[v]);
      if (!(d > s && d > sigma_[v])) return false;
    }
    const VertexId m = static_cast<VertexId>(plc_.points.size());
    plc_.points.push_back(centre);
    for (int k = 0; k < 3; ++k)
      if (collinear(plc_, tri[k], tri[(k + 1) % 3], m)) {
        plc_.points.pop_back();
        return false;
      }
    sigma_[m] = s;
    set(t, {tri[0], tri[1], m});
    add({tri[1], tri[2], m});
    add({tri[2], tri[0], m});
    for (int k = 0; k < 3; ++k) relax(tri[k], tri[(k + 1) % 3]);
    return true;
  }

  // Swaps the patch edge a-b (two patch triangles a-b-c and b-a-d) for c-d
  // when the quad wants it: the angles at c and d sum to more than pi, which
  // for a planar quad is Liepa's test (d inside the circumcircle of a-b-c).
  // In a skew quad the four angles sum to less than 2 pi, so a swapped edge
  // never wants to swap back. The angles decide the patch's shape only;
  // what keeps it a valid surface is exact: no triangle of three collinear
  // points and no edge twice.
  bool relax(VertexId a, VertexId b) {
    const uint32_t t1 = owner(a, b), t2 = owner(b, a);
    if (t1 == kNone || t2 == kNone) return false;  // a rim edge
    const VertexId c = third(tris_[t1], a, b), d = third(tris_[t2], b, a);
    if (c == d || owner(c, d) != kNone || owner(d, c) != kNone || rim_.taken.count(undirected(c, d)))
      return false;
    const Vec3 &pa = plc_.points[a], &pb = plc_.points[b], &pc = plc_.points[c], &pd = plc_.points[d];
    if (!angles_exceed_pi(pa, pb, pc, pd) || !keeps_facing(pa, pb, pc, pd)) return false;
    if (collinear(plc_, a, d, c) || collinear(plc_, b, c, d)) return false;
    owner_.erase(directed(a, b)), owner_.erase(directed(b, a));
    set(t1, {a, d, c});
    set(t2, {b, c, d});
    return true;
  }

  // Whether the swap of a-b for c-d leaves the quad facing the same way:
  // each new triangle's normal at less than a right angle to each old one's.
  // Across a fold of the patch (two triangles facing apart) a swap would
  // move the surface itself, maybe through the surface around the hole.
  static bool keeps_facing(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
    const Vec3 old1 = cross(b - a, c - a), old2 = cross(a - b, d - b);
    const Vec3 new1 = cross(d - a, c - a), new2 = cross(c - b, d - b);
    for (const Vec3& o : {old1, old2})
      for (const Vec3& n : {new1, new2})
        if (!(dot(o, n) > 0)) return false;
    return true;
  }

  static VertexId third(const Tri& t, VertexId a, VertexId b) {
    for (VertexId v : t)
      if (v != a && v != b) return v;
    return a;
  }

  // Every patch edge relaxed until none swaps; the number of swaps is
  // bounded, so rounding in the angles cannot make it cycle.
  void relax_all() {
    size_t budget = 16 * tris_.size() + 64;
    for (bool swapped = true; swapped && budget > 0;) {
      swapped = false;
      for (uint32_t t = 0; t < tris_.size() && budget > 0; ++t)
        for (int k = 0; k < 3; ++k)
          if (relax(tris_[t][k], tris_[t][(k + 1) % 3])) {
            swapped = true, --budget;
            break;  // tris_[t] changed
          }
    }
  }

  using Rings = std::unordered_map<VertexId, std::vector<VertexId>>;

  // Per vertex of the patch, its neighbours: in the patch, and for a rim
  // vertex also in the surface. Every edge at a new point is inside the
  // patch, used in both directions, so the heads of the directed edges out
  // of a vertex name its patch neighbours (a rim vertex's missing one is
  // along the rim, in the surface).
  Rings rings() const {
    Rings ring;
    for (const Tri& t : tris_)
      for (int k = 0; k < 3; ++k) ring[t[k]].push_back(t[(k + 1) % 3]);
    for (auto& [v, r] : ring) {
      if (v >= first_new_) continue;
      const std::vector<VertexId>& outside = rim_.ring.at(v);
      r.insert(r.end(), outside.begin(), outside.end());
      std::sort(r.begin(), r.end());
      r.erase(std::unique(r.begin(), r.end()), r.end());
    }
    return ring;
  }

  Vec3 mean_of(const std::vector<VertexId>& vs) const {
    Vec3 sum{0, 0, 0};
    for (VertexId u : vs) sum = sum + plc_.points[u];
    return (1.0 / double(vs.size())) * sum;
  }

  // Where the thin plate moves new point v: U^2(v) = 0 solved for v alone,
  // U(w) = mean of w's ring - w, U^2(v) = mean of U over v's ring - U(v),
  // whose coefficient of v is 1 + sum over v's ring of 1 / (n_v n_w)
  // (Kobbelt et al. 1998, "Interactive multi-resolution modeling").
  Vec3 thin_plate_step(const Rings& ring, VertexId v) const {
    const std::vector<VertexId>& around = ring.at(v);
    const Vec3 uv = mean_of(around) - plc_.points[v];
    Vec3 mean_u{0, 0, 0};
    double diagonal = 1;
    for (VertexId w : around) {
      const std::vector<VertexId>& of_w = ring.at(w);
      mean_u = mean_u + (mean_of(of_w) - plc_.points[w]);
      diagonal += 1.0 / (double(around.size()) * double(of_w.size()));
    }
    const Vec3 u2 = (1.0 / double(around.size())) * mean_u - uv;
    return plc_.points[v] - (1.0 / diagonal) * u2;
  }

  // Gauss-Seidel: each new point in turn to `target(v)`, until no point
  // moves more than kFairSettled of the largest sigma, or kFairSweeps.
  template <class Target>
  void sweep_until_settled(Target target) {
    double scale = 0;
    for (const auto& [v, s] : sigma_) scale = std::max(scale, s);
    for (int sweep = 0; sweep < kFairSweeps; ++sweep) {
      double moved = 0;
      for (VertexId v = first_new_; v < plc_.points.size(); ++v) {
        const Vec3 to = target(v);
        moved = std::max(moved, dist(to, plc_.points[v]));
        plc_.points[v] = to;
      }
      if (moved <= kFairSettled * scale) break;
    }
  }

  // Runs `move` on the new points, snaps them, and puts them back where
  // they were if a triangle became three collinear points or edges folded.
  template <class Move>
  void keep_if_valid(Move move) {
    const std::vector<Vec3> before(plc_.points.begin() + first_new_, plc_.points.end());
    const size_t folds_before = folded_edges();
    move();
    for (VertexId v = first_new_; v < plc_.points.size(); ++v) plc_.points[v] = snapped(plc_.points[v], grid_);
    if (has_collinear_triangle() || folded_edges() > folds_before)
      std::copy(before.begin(), before.end(), plc_.points.begin() + first_new_);
  }

  bool has_collinear_triangle() const {
    for (const Tri& t : tris_)
      if (collinear(plc_, t[0], t[1], t[2])) return true;
    return false;
  }

  // Patch edges whose two triangles face opposite ways (normals at more
  // than a right angle): a fold.
  size_t folded_edges() const {
    size_t folds = 0;
    for (uint32_t t = 0; t < tris_.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        const VertexId a = tris_[t][k], b = tris_[t][(k + 1) % 3];
        const uint32_t u = owner(b, a);
        if (u == kNone || a > b) continue;
        const Vec3 n1 = normal(tris_[t]), n2 = normal(tris_[u]);
        if (dot(n1, n2) < 0) ++folds;
      }
    return folds;
  }
  Vec3 normal(const Tri& t) const {
    return cross(plc_.points[t[1]] - plc_.points[t[0]], plc_.points[t[2]] - plc_.points[t[0]]);
  }

  Plc& plc_;
  const RimScale& rim_;
  double grid_;
  VertexId first_new_;
  std::vector<Tri> tris_;
  std::unordered_map<uint64_t, uint32_t> owner_;  // directed edge -> its triangle
  std::unordered_map<VertexId, double> sigma_;
};

// The cap on new points of one loop's patch: enough for a round hole of n
// rim edges at the rim's spacing (about n^2 / 11 points), bounded so that
// the refinement ends whatever the sigma.
size_t max_fill_points(size_t n) { return std::min<size_t>(std::max(4 * n, n * n / 4), 20000); }

// The least-area triangles of a non-planar loop refined and faired; the
// new points are appended to plc.points.
std::vector<Tri> refined_patch(Plc& plc, const std::vector<Tri>& tris, const RimScale& rim, double grid,
                               size_t loop_size) {
  Patch patch(plc, tris, rim, grid);
  patch.refine(max_fill_points(loop_size));
  patch.fair();
  return patch.triangles();
}

}  // namespace

bool has_boundary(const Plc& plc) {
  for (const FillEdge& e : boundary_edges(plc))
    if (!e.closing) return true;
  return false;
}

void fill_holes(Work& w, RepairReport& report, bool refine) {
  const std::vector<std::vector<FillEdge>> loops = trace_loops(boundary_edges(w.plc));
  RimScale rim = rim_scale(w.plc, loops);
  // The points were snapped to this grid just before (snap_to_grid); the
  // patch's points lie within the rims' bounding box, so the grid stays.
  const double grid = snap_grid(w.plc);
  for (const std::vector<FillEdge>& loop : loops) {
    std::vector<VertexId> v;
    for (const FillEdge& e : loop) v.push_back(e.from);
    if (v.size() < 3) continue;  // two facets' edges on one line: nothing to fill
    std::vector<Tri> tris = planar_triangulation(w.plc, v);
    if (tris.empty()) {
      // No edge across the loop that the surface or an earlier patch has
      // (rim.taken), unless nothing else closes it.
      tris = least_area_patch(w.plc, v, rim.taken);
      if (tris.empty()) tris = least_area_patch(w.plc, v, {});
      const size_t points = w.plc.points.size();
      if (refine && !tris.empty()) tris = refined_patch(w.plc, tris, rim, grid, v.size());
      report.fill_points += w.plc.points.size() - points;
    }
    if (tris.empty()) {
      ++report.unfilled_holes;
      continue;
    }
    // The patch belongs to the facet along the loop's first edge (marker,
    // source line or record, provenance).
    const uint32_t next_to = loop.front().facet;
    const Facet beside = w.plc.facets[next_to];  // a copy: push_back may move the facets
    for (const Tri& t : tris) {
      w.plc.facets.push_back(part_of(beside, {t[0], t[1], t[2]}));
      w.source.push_back(w.source[next_to]);
      for (int k = 0; k < 3; ++k)  // a later loop through these vertices must not repeat the edge
        rim.taken.insert(undirected(t[k], t[(k + 1) % 3]));
    }
    w.mark(w.source[next_to]);
    ++report.filled_holes;
    report.fill_triangles += tris.size();
  }
}

}  // namespace repair_steps
}  // namespace cdt3d
