// The subfaces of X1/X2 (Si & Gärtner 2005 §2, §7): each facet as a 2D
// constrained Delaunay triangulation of its vertices, respecting its loops
// (whose edges are now chains of subsegments) and its holes.
//
// Method, per facet:
//  1. Vertices: the chain vertices of every loop edge, the caller's interior
//     vertices, and the PLC points and segments lying in the facet: points
//     in the facet's bounding box that are exactly coplanar (orient3d on
//     input points) and inside or on one of its loops (exact crossing rule
//     in the projection), and every segment joining two such points or loop
//     vertices that is not a loop edge (e.g. the edge where a dangling or
//     internal facet stands on this one). Their subsegments are constraints
//     but not region boundaries; a candidate lying outside the facet only
//     ends up in removed triangles.
//  2. Projection onto the coordinate plane that drops the axis of the largest
//     component of the facet normal (normal of three non-collinear input
//     vertices). Dropping a coordinate rounds nothing, so orient2d and
//     incircle on the projected points are exact; they agree with
//     pred::orient2d_projected (same cyclic axis order). Steiner vertices are
//     rounded and only nearly coplanar, so no 3D test is used at all.
//  3. The Delaunay triangulation of the projected points: on small facets a
//     lexicographic sweep then Lawson flips, on large ones (kMinVerticesInserted)
//     insertion along a Hilbert curve with ghost triangles outside the hull;
//     then every constraint edge inserted by flipping the edges it crosses (a
//     crossed edge whose quadrilateral is strictly convex is flipped, the
//     others wait in a queue; this always terminates), then, if that flipped
//     anything, Lawson flips of the unconstrained edges until every one is
//     locally Delaunay.
//  4. Cocircular ties: incircle is perturbed like insphere_sos (the lifted
//     coordinate of the vertex with the larger mesh id counts as slightly
//     higher), so the triangulation is unique, independent of any order.
//  5. The facet region: the union of the interiors of its loops minus the
//     areas of its hole points (the public Facet definition, as in TetGen's
//     .poly). Triangles reachable from the outside of the convex hull without
//     crossing a loop edge are outside; so is everything reachable from a
//     triangle holding a hole point without crossing a loop edge. A loop
//     nested inside another loop without a hole point is therefore an
//     internal constraint, not a hole. An even-odd facet (a merged flat
//     face, Facet::even_odd) keeps the triangles an odd number of loop
//     edges away from the outside instead.
//  6. Output orientation: the orientation of the facet's outer loop (the
//     loop holding the lexicographically smallest projected loop vertex,
//     lowest loop index on ties).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "beside.hpp"
#include "geometry.hpp"
#include "predicates.hpp"
#include "spatial_sort.hpp"
#include "status.hpp"
#include "subfaces.hpp"

namespace cdt3d {
namespace {

// From this many facets half of them go to a second thread (triangulate_facets):
// a facet costs a few thousand instructions, so half of these far outweigh
// starting a thread.
constexpr size_t kMinFacetsBeside = 2000;

// From this many vertices a facet is triangulated by point insertion
// (Cdt2::build_delaunay); smaller ones by the sweep and Lawson's flips, which
// cost less there and keep their triangles in the order they always had.
constexpr size_t kMinVerticesInserted = 256;

// Lawson's flips (Cdt2::make_delaunay) reach the constrained Delaunay
// triangulation of n points after O(n^2) flips; more than this bound means
// rounding made them cycle, and the facet is reported instead of looping.
constexpr size_t kFlipsPerPointPair = 4, kFlipsBase = 1000;

// ---------------------------------------------------------------------------
// 2D constrained Delaunay triangulation on local vertex ids 0..n-1
// ---------------------------------------------------------------------------

struct Tri {
  uint32_t v[3];  ///< counterclockwise
  int32_t n[3];   ///< n[i]: triangle across the edge opposite v[i], -1 on the hull
};

inline int next3(int i) { return i == 2 ? 0 : i + 1; }
inline int prev3(int i) { return i == 0 ? 2 : i - 1; }

// One per facet triangulator, reused from facet to facet: its buffers keep
// their capacity, so a facet costs no allocation once the larger ones have
// been seen (with two threads each allocation also takes the allocator's
// lock, for which the two halves of triangulate_facets queued in the
// WebAssembly build).
class Cdt2 {
 public:
  /// xy: 2 coordinates per local vertex; ids: mesh ids (perturbation order);
  /// read at each build(), so the caller refills them between facets.
  Cdt2(const std::vector<double>& xy, const std::vector<VertexId>& ids) : xy_(xy), ids_(ids) {}

  /// Triangulates the points, replacing the previous triangulation. Empty
  /// string on success, else what failed.
  std::string build();
  /// The Delaunay triangulation of the points (perturbed as incircle_sos),
  /// replacing the previous one, by insertion along a Hilbert curve. For
  /// large facets: build()'s sweep makes a fan from each new point to the
  /// collinear column before it (a lattice face is made of such columns),
  /// which make_delaunay() then flips in time quadratic in the column, while
  /// an insertion here touches only the triangles around its point. The
  /// triangulation is unique, so the two ways give the same triangles.
  std::string build_delaunay();
  /// Whether insert_constraint() flipped an edge since the last build
  /// (otherwise a Delaunay triangulation is still one).
  bool flipped() const { return flipped_; }
  /// Inserts the constraint edge (a, b).
  std::string insert_constraint(uint32_t a, uint32_t b);
  /// Lawson flips of unconstrained edges until all are locally Delaunay.
  std::string make_delaunay();

  bool is_constrained(uint32_t a, uint32_t b) const {
    return std::binary_search(constrained_.begin(), constrained_.end(), edge_key(a, b));
  }
  /// Triangle and position of the vertex opposite edge (a, b), or {-1, -1}.
  std::pair<int32_t, int> find_edge(uint32_t a, uint32_t b);

  const std::vector<Tri>& tris() const { return tris_; }
  int orient(uint32_t a, uint32_t b, uint32_t c) const {
    return pred::orient2d(&xy_[2 * a], &xy_[2 * b], &xy_[2 * c]);
  }
  /// Perturbed incircle: > 0 when d is inside the circle of ccw (a, b, c).
  int incircle_sos(uint32_t a, uint32_t b, uint32_t c, uint32_t d) const;

 private:
  void add_constrained(uint32_t a, uint32_t b) {
    const uint64_t k = edge_key(a, b);
    auto it = std::lower_bound(constrained_.begin(), constrained_.end(), k);
    if (it == constrained_.end() || *it != k) constrained_.insert(it, k);
  }
  int32_t new_tri(uint32_t a, uint32_t b, uint32_t c) {
    tris_.push_back(Tri{{a, b, c}, {-1, -1, -1}});
    const int32_t t = static_cast<int32_t>(tris_.size() - 1);
    vtri_[a] = vtri_[b] = vtri_[c] = t;
    return t;
  }
  int index_of(int32_t t, uint32_t v) const {
    const Tri& T = tris_[t];
    return T.v[0] == v ? 0 : T.v[1] == v ? 1 : T.v[2] == v ? 2 : -1;
  }
  int index_of_nbr(int32_t t, int32_t nb) const {
    const Tri& T = tris_[t];
    return T.n[0] == nb ? 0 : T.n[1] == nb ? 1 : T.n[2] == nb ? 2 : -1;
  }
  void link(int32_t t, int i, int32_t u, int j) {
    tris_[t].n[i] = u;
    if (u >= 0) tris_[u].n[j] = t;
  }
  /// Sorts order_ lexicographically and checks the points: none projects
  /// twice and not all are collinear. Sets k: order_[0], order_[1] and
  /// order_[k] are the first three not collinear.
  std::string sweep_order(uint32_t& k);
  /// build_delaunay()'s steps. A ghost triangle has the vertex ghost_ (one past
  /// the last point) in place of its third corner: (a, b, ghost_) stands for
  /// the outside of the hull edge (a, b), whose inside is on its right.
  bool is_ghost(int32_t t) const {
    const Tri& T = tris_[t];
    return T.v[0] == ghost_ || T.v[1] == ghost_ || T.v[2] == ghost_;
  }
  /// p lies in the circumcircle of t, for a ghost t: beyond its hull edge
  /// or on the edge between its ends.
  bool in_conflict(int32_t t, uint32_t p) const;
  /// Triangle holding p (edge index in `edge` when p lies on an edge, else -1)
  /// by a visibility walk from `t`; -1 if the walk does not end.
  int32_t locate(int32_t t, uint32_t p, int& edge);
  void insert_point(int32_t t, int edge, uint32_t p);
  void drop_ghosts();
  /// The neighbour nb of `from` sees `to` there instead (nothing for -1).
  void relink(int32_t nb, int32_t from, int32_t to) {
    if (nb < 0) return;
    Tri& N = tris_[nb];
    for (int k = 0; k < 3; ++k)
      if (N.n[k] == from) {
        N.n[k] = to;
        return;
      }
  }
  /// Triangles incident to v (explicit breadth-first walk over its star).
  void star(uint32_t v, std::vector<int32_t>& out);
  /// Flips the edge opposite v[i] of t (quadrilateral must be strictly convex).
  void flip(int32_t t, int i);
  bool convex_quad(int32_t t, int i) const;
  /// p lies on the ray from a through b (the three are collinear).
  bool on_ray(uint32_t a, uint32_t b, uint32_t p) const {
    const double* A = &xy_[2 * a];
    const double* B = &xy_[2 * b];
    const double* P = &xy_[2 * p];
    for (int k = 0; k < 2; ++k) {
      const int sb = (B[k] > A[k]) - (B[k] < A[k]);
      const int sp = (P[k] > A[k]) - (P[k] < A[k]);
      if (sb != 0) return sb == sp;
    }
    return false;
  }

  const std::vector<double>& xy_;
  const std::vector<VertexId>& ids_;
  std::vector<Tri> tris_;
  std::vector<int32_t> vtri_;
  std::vector<uint64_t> constrained_;
  std::vector<uint32_t> tstamp_;
  uint32_t epoch_ = 0;
  std::vector<int32_t> star_buf_;
  uint32_t ghost_ = 0;
  uint32_t walk_turn_ = 0;  // varies the first edge a walk step tests
  bool flipped_ = false;
  std::vector<std::pair<uint64_t, uint32_t>> hkey_;  // Hilbert key, point
  // Scratch of build() (sweep order, hull links, new fan), make_delaunay()
  // (edges to check) and insert_constraint() (crossed edges, flip queue).
  std::vector<uint32_t> order_, hnext_, hprev_, stack_;
  std::vector<int32_t> hedge_, created_;
  std::vector<std::array<uint32_t, 2>> crossed_, flip_queue_;
};

int Cdt2::incircle_sos(uint32_t a, uint32_t b, uint32_t c, uint32_t d) const {
  const int s = pred::incircle(&xy_[2 * a], &xy_[2 * b], &xy_[2 * c], &xy_[2 * d]);
  if (s != 0) return s;
  // Cocircular: raise the lifted coordinate of each vertex by eps^rank, the
  // largest raise going to the mesh id first in pred::sos_raised_before
  // order, as in 3D. That raise decides. Raising
  // d puts it outside. Raising a triangle vertex tilts the lifted plane up on
  // its side: d is inside iff d lies on that vertex's side of the opposite
  // edge (its barycentric coordinate is positive).
  const VertexId ia = ids_[a], ib = ids_[b], ic = ids_[c], id = ids_[d];
  const VertexId m = pred::sos_first(ia, ib, ic, id);
  if (m == id) return -1;
  int o = 0;
  if (m == ia) o = orient(b, c, d);
  else if (m == ib) o = orient(c, a, d);
  else o = orient(a, b, d);
  return o > 0 ? 1 : -1;
}

std::string Cdt2::sweep_order(uint32_t& k) {
  const uint32_t n = static_cast<uint32_t>(ids_.size());
  if (n < 3) return "fewer than 3 vertices";
  std::vector<uint32_t>& order = order_;
  order.resize(n);
  for (uint32_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [this](uint32_t a, uint32_t b) {
    const double* A = &xy_[2 * a];
    const double* B = &xy_[2 * b];
    if (A[0] != B[0]) return A[0] < B[0];
    if (A[1] != B[1]) return A[1] < B[1];
    return a < b;
  });
  for (uint32_t i = 1; i < n; ++i) {
    if (xy_[2 * order[i]] == xy_[2 * order[i - 1]] &&
        xy_[2 * order[i] + 1] == xy_[2 * order[i - 1] + 1])
      return "vertices " + std::to_string(ids_[order[i - 1]]) + " and " +
             std::to_string(ids_[order[i]]) + " have the same projection";
  }
  k = 2;
  while (k < n && orient(order[0], order[1], order[k]) == 0) ++k;
  if (k == n) return "all vertices are collinear in the projection";
  return std::string();
}

std::string Cdt2::build() {
  const uint32_t n = static_cast<uint32_t>(ids_.size());
  tris_.clear();
  constrained_.clear();
  vtri_.assign(n, -1);
  flipped_ = false;
  uint32_t k = 0;
  const std::string msg = sweep_order(k);
  if (!msg.empty()) return msg;
  const std::vector<uint32_t>& order = order_;

  // Initial fan from order[k] to the collinear run order[0..k-1].
  const uint32_t apex = order[k];
  const bool left = orient(order[0], order[1], apex) > 0;
  int32_t prev = -1;
  for (uint32_t i = 0; i + 1 < k; ++i) {
    const uint32_t p = order[i], q = order[i + 1];
    const int32_t t = left ? new_tri(p, q, apex) : new_tri(q, p, apex);
    // Shared edge with the previous fan triangle: (p, apex).
    if (prev >= 0) {
      const int jt = index_of(t, q);          // edge (p, apex) is opposite q
      const int jp = index_of(prev, order[i - 1]);  // edge (p, apex) opposite order[i-1]
      link(t, jt, prev, jp);
    }
    prev = t;
  }

  // Hull as a circular list (counterclockwise, interior on the left) with the
  // half-edge (3 t + i) of the hull triangle along each hull edge.
  std::vector<uint32_t>& hnext = hnext_;
  std::vector<uint32_t>& hprev = hprev_;
  std::vector<int32_t>& hedge = hedge_;
  hnext.assign(n, 0);
  hprev.assign(n, 0);
  hedge.assign(n, -1);
  for (size_t t = 0; t < tris_.size(); ++t) {
    for (int i = 0; i < 3; ++i) {
      if (tris_[t].n[i] != -1) continue;
      const uint32_t from = tris_[t].v[next3(i)], to = tris_[t].v[prev3(i)];
      hnext[from] = to;
      hprev[to] = from;
      hedge[from] = static_cast<int32_t>(3 * t + i);
    }
  }

  std::vector<int32_t>& created = created_;
  for (uint32_t j = k + 1; j < n; ++j) {
    const uint32_t q = order[j];
    const uint32_t r = order[j - 1];
    auto visible = [&](uint32_t u) { return orient(u, hnext[u], q) < 0; };
    uint32_t s = r, e = r;
    while (visible(e)) {
      e = hnext[e];
      if (e == r) return "sweep: every hull edge is visible";
    }
    while (visible(hprev[s])) {
      s = hprev[s];
      if (s == r) return "sweep: every hull edge is visible";
    }
    if (s == e) {
      // No visible edge next to the previous point: scan the hull.
      uint32_t u = hnext[r];
      while (u != r && !visible(u)) u = hnext[u];
      if (!visible(u)) return "sweep: no visible hull edge";
      s = u;
      while (visible(hprev[s]) && hprev[s] != u) s = hprev[s];
      e = hnext[u];
      while (visible(e) && e != s) e = hnext[e];
    }
    // Cone the visible chain s -> ... -> e to q.
    created.clear();
    for (uint32_t u = s; u != e; u = hnext[u]) {
      const uint32_t w = hnext[u];
      const int32_t t = new_tri(w, u, q);  // edge (w, u) opposite q (index 2)
      const int32_t h = hedge[u];
      link(t, 2, h / 3, h % 3);
      if (!created.empty()) link(t, 0, created.back(), 1);  // edge (u, q)
      created.push_back(t);
    }
    hnext[s] = q, hprev[q] = s, hnext[q] = e, hprev[e] = q;
    hedge[s] = 3 * created.front() + 0;  // edge (s, q) opposite w
    hedge[q] = 3 * created.back() + 1;   // edge (q, e) opposite u
  }
  tstamp_.assign(tris_.size(), 0);
  return std::string();
}

std::string Cdt2::build_delaunay() {
  const uint32_t n = static_cast<uint32_t>(ids_.size());
  tris_.clear();
  constrained_.clear();
  flipped_ = false;
  ghost_ = n;
  // The walk decides which side of an edge a point on it is inserted from,
  // and so the order of the triangles: it depends on this facet alone,
  // whichever facets this triangulator saw before (one thread or two).
  walk_turn_ = 0;
  vtri_.assign(n + 1, -1);
  uint32_t k = 0;
  std::string msg = sweep_order(k);
  if (!msg.empty()) return msg;
  uint32_t a = order_[0], b = order_[1];
  const uint32_t c = order_[k];
  if (orient(a, b, c) < 0) std::swap(a, b);
  // The first triangle and the ghosts of its three edges.
  new_tri(a, b, c);
  new_tri(b, a, ghost_);
  new_tri(c, b, ghost_);
  new_tri(a, c, ghost_);
  for (int32_t t = 0; t < 4; ++t)
    for (int i = 0; i < 3; ++i)
      for (int32_t u = 0; u < 4 && tris_[t].n[i] < 0; ++u) {
        if (u == t) continue;
        const int ib = index_of(u, tris_[t].v[next3(i)]), ic = index_of(u, tris_[t].v[prev3(i)]);
        if (ib >= 0 && ic >= 0) tris_[t].n[i] = u;
      }

  // The other points along a Hilbert curve over their bounding box, so each
  // walk starts next to its point.
  double lo[2] = {xy_[0], xy_[1]}, hi[2] = {xy_[0], xy_[1]};
  for (uint32_t v = 1; v < n; ++v)
    for (int d = 0; d < 2; ++d)
      lo[d] = std::min(lo[d], xy_[2 * v + d]), hi[d] = std::max(hi[d], xy_[2 * v + d]);
  constexpr int kBits = 16;
  const double scale[2] = {hi[0] > lo[0] ? 65535.0 / (hi[0] - lo[0]) : 0.0,
                           hi[1] > lo[1] ? 65535.0 / (hi[1] - lo[1]) : 0.0};
  hkey_.clear();
  for (uint32_t v = 0; v < n; ++v) {
    if (v == a || v == b || v == c) continue;
    const uint32_t x = static_cast<uint32_t>((xy_[2 * v] - lo[0]) * scale[0]);
    const uint32_t y = static_cast<uint32_t>((xy_[2 * v + 1] - lo[1]) * scale[1]);
    hkey_.push_back({hilbert_key(std::min(x, 65535u), std::min(y, 65535u), 0, kBits), v});
  }
  std::sort(hkey_.begin(), hkey_.end());
  int32_t t = 0;
  for (const auto& key : hkey_) {
    const uint32_t p = key.second;
    int edge = -1;
    t = locate(t, p, edge);
    if (t < 0) return "the point location walk does not end";
    insert_point(t, edge, p);
    t = vtri_[p];
  }
  drop_ghosts();
  return std::string();
}

bool Cdt2::in_conflict(int32_t t, uint32_t p) const {
  const Tri& T = tris_[t];
  for (int g = 0; g < 3; ++g) {
    if (T.v[g] != ghost_) continue;
    const uint32_t a = T.v[next3(g)], b = T.v[prev3(g)];
    const int o = orient(a, b, p);
    return o > 0 || (o == 0 && on_ray(a, b, p) && on_ray(b, a, p));
  }
  return incircle_sos(T.v[0], T.v[1], T.v[2], p) > 0;
}

int32_t Cdt2::locate(int32_t t, uint32_t p, int& edge) {
  edge = -1;
  for (size_t steps = 0; steps < 4 * tris_.size() + 8; ++steps) {
    const Tri& T = tris_[t];
    int g = -1;
    for (int i = 0; i < 3; ++i)
      if (T.v[i] == ghost_) g = i;
    if (g >= 0) {
      const uint32_t a = T.v[next3(g)], b = T.v[prev3(g)];
      const int o = orient(a, b, p);
      if (o > 0) return t;
      if (o < 0) {
        t = T.n[g];
        continue;
      }
      // On the line of the hull edge: on it, or beyond one of its ends,
      // where the next ghost along the hull lies.
      const bool past_a = !on_ray(a, b, p), past_b = !on_ray(b, a, p);
      if (!past_a && !past_b) {
        edge = g;
        return t;
      }
      t = past_b ? T.n[next3(g)] : T.n[prev3(g)];
      continue;
    }
    const uint32_t turn = walk_turn_++ % 3;
    int zero = -1, zeros = 0;
    bool moved = false;
    for (uint32_t e = 0; e < 3 && !moved; ++e) {
      const int i = static_cast<int>((turn + e) % 3);
      const int o = orient(T.v[next3(i)], T.v[prev3(i)], p);
      if (o < 0) {
        t = T.n[i];
        moved = true;
      } else if (o == 0) {
        zero = i, ++zeros;
      }
    }
    if (moved) continue;
    if (zeros > 1) return -1;  // p is a vertex: sweep_order rules that out
    edge = zero;
    return t;
  }
  return -1;
}

void Cdt2::insert_point(int32_t t, int edge, uint32_t p) {
  stack_.clear();
  if (edge < 0) {
    // Split t = (v0, v1, v2) into (v0, v1, p), (v1, v2, p), (v2, v0, p).
    const Tri T = tris_[t];
    const int32_t t2 = static_cast<int32_t>(tris_.size()), t3 = t2 + 1;
    tris_[t] = Tri{{T.v[0], T.v[1], p}, {t2, t3, T.n[2]}};
    tris_.push_back(Tri{{T.v[1], T.v[2], p}, {t3, t, T.n[0]}});
    tris_.push_back(Tri{{T.v[2], T.v[0], p}, {t, t2, T.n[1]}});
    relink(T.n[0], t, t2);
    relink(T.n[1], t, t3);
    vtri_[T.v[0]] = t, vtri_[T.v[1]] = t2, vtri_[T.v[2]] = t3, vtri_[p] = t;
    stack_.insert(stack_.end(), {static_cast<uint32_t>(t), static_cast<uint32_t>(t2),
                                 static_cast<uint32_t>(t3)});
  } else {
    // p on the edge (b, c) of t = (a, b, c) (a = v[edge]) and of u = (x, c, b):
    // t -> (a, b, p), t2 = (a, p, c), u -> (x, c, p), u2 = (x, p, b).
    const Tri T = tris_[t];
    const int32_t u = T.n[edge];
    const int j = index_of_nbr(u, t);
    const Tri U = tris_[u];
    const uint32_t a = T.v[edge], b = T.v[next3(edge)], c = T.v[prev3(edge)], x = U.v[j];
    const int32_t t2 = static_cast<int32_t>(tris_.size()), u2 = t2 + 1;
    tris_[t] = Tri{{a, b, p}, {u2, t2, T.n[prev3(edge)]}};
    tris_.push_back(Tri{{a, p, c}, {u, T.n[next3(edge)], t}});
    tris_[u] = Tri{{x, c, p}, {t2, u2, U.n[prev3(j)]}};
    tris_.push_back(Tri{{x, p, b}, {t, U.n[next3(j)], u}});
    relink(T.n[next3(edge)], t, t2);
    relink(U.n[next3(j)], u, u2);
    vtri_[a] = t, vtri_[b] = t, vtri_[c] = t2, vtri_[x] = u, vtri_[p] = t;
    stack_.insert(stack_.end(), {static_cast<uint32_t>(t), static_cast<uint32_t>(t2),
                                 static_cast<uint32_t>(u), static_cast<uint32_t>(u2)});
  }
  // Lawson's flips of the edges opposite p: those whose far triangle has p
  // in its circle, which in a Delaunay triangulation are only these.
  while (!stack_.empty()) {
    const int32_t s = static_cast<int32_t>(stack_.back());
    stack_.pop_back();
    const int i = index_of(s, p);
    const int32_t u = tris_[s].n[i];
    if (!in_conflict(u, p)) continue;
    flip(s, i);  // s = (p, b, x), u = (x, c, p)
    stack_.push_back(static_cast<uint32_t>(s));
    stack_.push_back(static_cast<uint32_t>(u));
  }
}

// Removes the ghost triangles (their neighbours then see the hull, -1) and
// renumbers the others in their order.
void Cdt2::drop_ghosts() {
  std::vector<int32_t>& id = created_;
  id.assign(tris_.size(), -1);
  int32_t m = 0;
  for (size_t t = 0; t < tris_.size(); ++t)
    if (!is_ghost(static_cast<int32_t>(t))) id[t] = m++;
  for (size_t t = 0; t < tris_.size(); ++t) {
    if (id[t] < 0) continue;
    Tri T = tris_[t];
    for (int i = 0; i < 3; ++i) T.n[i] = id[T.n[i]];
    tris_[id[t]] = T;
  }
  tris_.resize(static_cast<size_t>(m));
  vtri_.resize(ghost_);
  for (size_t t = 0; t < tris_.size(); ++t)
    for (uint32_t v : tris_[t].v) vtri_[v] = static_cast<int32_t>(t);
  tstamp_.assign(tris_.size(), 0);
}

void Cdt2::star(uint32_t v, std::vector<int32_t>& out) {
  out.clear();
  if (vtri_[v] < 0) return;
  if (tstamp_.size() < tris_.size()) tstamp_.resize(tris_.size(), 0);
  ++epoch_;
  if (epoch_ == 0) {
    std::fill(tstamp_.begin(), tstamp_.end(), 0);
    epoch_ = 1;
  }
  out.push_back(vtri_[v]);
  tstamp_[vtri_[v]] = epoch_;
  for (size_t h = 0; h < out.size(); ++h) {
    const int32_t t = out[h];
    const int i = index_of(t, v);
    for (int j : {next3(i), prev3(i)}) {
      const int32_t u = tris_[t].n[j];
      if (u >= 0 && tstamp_[u] != epoch_) {
        tstamp_[u] = epoch_;
        out.push_back(u);
      }
    }
  }
}

std::pair<int32_t, int> Cdt2::find_edge(uint32_t a, uint32_t b) {
  star(a, star_buf_);
  for (int32_t t : star_buf_) {
    const int ia = index_of(t, a), ib = index_of(t, b);
    if (ib >= 0) return {t, 3 - ia - ib};
  }
  return {-1, -1};
}

bool Cdt2::convex_quad(int32_t t, int i) const {
  const int32_t u = tris_[t].n[i];
  if (u < 0) return false;
  const uint32_t w = tris_[t].v[i], c1 = tris_[t].v[next3(i)], c2 = tris_[t].v[prev3(i)];
  const uint32_t x = tris_[u].v[index_of_nbr(u, t)];
  return orient(w, x, c1) * orient(w, x, c2) < 0;
}

void Cdt2::flip(int32_t t, int i) {
  // t = (a, b, c) with a = v[i]; u = (x, c, b) across edge (b, c).
  // Afterwards t = (a, b, x) and u = (x, c, a).
  const int32_t u = tris_[t].n[i];
  const int j = index_of_nbr(u, t);
  const uint32_t a = tris_[t].v[i], b = tris_[t].v[next3(i)], c = tris_[t].v[prev3(i)];
  const uint32_t x = tris_[u].v[j];
  const int32_t t_ab = tris_[t].n[prev3(i)];  // across (a, b)
  const int32_t t_ca = tris_[t].n[next3(i)];  // across (c, a)
  // In u = (x, c, b) at positions j, j+1, j+2: (b, x) is opposite c, (x, c) opposite b.
  const int32_t u_bx = tris_[u].n[next3(j)];
  const int32_t u_xc = tris_[u].n[prev3(j)];
  tris_[t] = Tri{{a, b, x}, {u_bx, u, t_ab}};
  tris_[u] = Tri{{x, c, a}, {t_ca, t, u_xc}};
  relink(u_bx, u, t);
  relink(t_ca, t, u);
  vtri_[a] = t, vtri_[b] = t, vtri_[x] = t, vtri_[c] = u;
}

std::string Cdt2::insert_constraint(uint32_t a, uint32_t b) {
  if (a == b) return "a constraint edge has equal ends";
  if (find_edge(a, b).first >= 0) {
    add_constrained(a, b);
    return std::string();
  }
  // Start: the triangle of a's star whose opposite edge the segment crosses.
  uint32_t p = 0, q = 0;
  int32_t t = -1;
  star(a, star_buf_);
  for (int32_t s : star_buf_) {
    const int ia = index_of(s, a);
    const uint32_t sp = tris_[s].v[next3(ia)], sq = tris_[s].v[prev3(ia)];
    const int op = orient(a, b, sp), oq = orient(a, b, sq);
    if (op == 0 && on_ray(a, b, sp))
      return "vertex " + std::to_string(ids_[sp]) + " lies on the constraint edge (" +
             std::to_string(ids_[a]) + ", " + std::to_string(ids_[b]) + ")";
    if (oq == 0 && on_ray(a, b, sq))
      return "vertex " + std::to_string(ids_[sq]) + " lies on the constraint edge (" +
             std::to_string(ids_[a]) + ", " + std::to_string(ids_[b]) + ")";
    if (op < 0 && oq > 0) {
      p = sp, q = sq, t = s;
      break;
    }
  }
  if (t < 0) return "no triangle around a constraint edge's end faces it";
  // Walk along a -> b collecting the crossed edges (p right, q left of ab).
  std::vector<std::array<uint32_t, 2>>& crossed = crossed_;
  crossed.clear();
  for (size_t guard = 0;; ++guard) {
    if (guard > 4 * tris_.size() + 8) return "the walk along a constraint edge does not end";
    if (is_constrained(p, q))
      return "constraint edges (" + std::to_string(ids_[a]) + ", " + std::to_string(ids_[b]) +
             ") and (" + std::to_string(ids_[p]) + ", " + std::to_string(ids_[q]) +
             ") cross in the projection";
    crossed.push_back({p, q});
    const int ip = index_of(t, p), iq = index_of(t, q);
    const int32_t u = tris_[t].n[3 - ip - iq];
    if (u < 0) return "the walk along a constraint edge left the hull";
    const int j = index_of_nbr(u, t);
    const uint32_t r = tris_[u].v[j];
    t = u;
    if (r == b) break;
    const int o = orient(a, b, r);
    if (o == 0)
      return "vertex " + std::to_string(ids_[r]) + " lies on the constraint edge (" +
             std::to_string(ids_[a]) + ", " + std::to_string(ids_[b]) + ")";
    if (o < 0) p = r;
    else q = r;
  }
  // Flip the crossed edges away; non-convex ones wait for their turn.
  std::vector<std::array<uint32_t, 2>>& queue = flip_queue_;
  queue.assign(crossed.begin(), crossed.end());
  size_t head = 0;
  const size_t limit = 64 + 16 * crossed.size() * crossed.size() + 16 * tris_.size();
  for (size_t steps = 0; head < queue.size(); ++steps) {
    if (steps > limit) return "flipping away the edges crossing a constraint does not end";
    const std::array<uint32_t, 2> e = queue[head++];
    const std::pair<int32_t, int> f = find_edge(e[0], e[1]);
    if (f.first < 0) return "a crossed edge vanished";
    if (!convex_quad(f.first, f.second)) {
      queue.push_back(e);
      continue;
    }
    flip(f.first, f.second);
    flipped_ = true;
    // New diagonal: v[2] of t (x) and v[0] (the old apex).
    const Tri& T = tris_[f.first];
    const uint32_t w = T.v[0], x = T.v[2];
    const int ow = orient(a, b, w), ox = orient(a, b, x);
    if (ow * ox < 0) queue.push_back({w, x});
    if (head > 4096 && head * 2 > queue.size()) {
      queue.erase(queue.begin(), queue.begin() + static_cast<std::ptrdiff_t>(head));
      head = 0;
    }
  }
  if (find_edge(a, b).first < 0) return "a constraint edge is still missing after flipping";
  add_constrained(a, b);
  return std::string();
}

std::string Cdt2::make_delaunay() {
  std::vector<uint32_t>& stack = stack_;  // half-edge ids 3 t + i
  stack.clear();
  for (size_t t = tris_.size(); t-- > 0;)
    for (int i = 2; i >= 0; --i) stack.push_back(static_cast<uint32_t>(3 * t + i));
  const size_t n = ids_.size();
  const size_t limit = kFlipsBase + kFlipsPerPointPair * n * n;
  size_t done = 0;
  while (!stack.empty()) {
    const uint32_t h = stack.back();
    stack.pop_back();
    const int32_t t = static_cast<int32_t>(h / 3);
    const int i = static_cast<int>(h % 3);
    const Tri& T = tris_[t];
    const int32_t u = T.n[i];
    if (u < 0) continue;
    const uint32_t b = T.v[next3(i)], c = T.v[prev3(i)];
    if (is_constrained(b, c)) continue;
    const uint32_t x = tris_[u].v[index_of_nbr(u, t)];
    if (incircle_sos(T.v[0], T.v[1], T.v[2], x) <= 0) continue;
    if (!convex_quad(t, i)) return "an illegal edge has a non-convex quadrilateral";
    if (++done > limit) return "Lawson flips do not end";
    flip(t, i);
    // The four outer edges of the quadrilateral: t = (a, b, x), u = (x, c, a).
    stack.push_back(static_cast<uint32_t>(3 * t + 0));
    stack.push_back(static_cast<uint32_t>(3 * t + 2));
    stack.push_back(static_cast<uint32_t>(3 * u + 0));
    stack.push_back(static_cast<uint32_t>(3 * u + 2));
  }
  return std::string();
}

// ---------------------------------------------------------------------------
// Facets
// ---------------------------------------------------------------------------

Status facet_error(size_t f, const std::string& what) {
  return make_error(ErrorCode::Internal, "Facet triangulation failed: " + what + ".")
      .facet(static_cast<int64_t>(f));
}

// Projection dropping axis `drop`, the two others in cyclic order (as
// pred::orient2d_projected).
inline void project(const double* p, int drop, double* out) {
  out[0] = p[(drop + 1) % 3];
  out[1] = p[(drop + 2) % 3];
}

// Uniform grid over the PLC points, to find the points in a facet's
// bounding box. Cell indices are monotone in the coordinates, so a box query
// over the cells of its corners sees every point inside the box (the exact
// test is done by the caller).
class PointGrid {
 public:
  // Without `build` the grid stays empty (every query finds nothing).
  PointGrid(const Plc& plc, bool build) : plc_(plc) {
    const size_t n = plc.points.size();
    if (n == 0 || !build) return;
    lo_ = {plc.points[0].x, plc.points[0].y, plc.points[0].z};
    std::array<double, 3> hi = lo_;
    for (const Vec3& p : plc.points) {
      const double c[3] = {p.x, p.y, p.z};
      for (int k = 0; k < 3; ++k) lo_[k] = std::min(lo_[k], c[k]), hi[k] = std::max(hi[k], c[k]);
    }
    // The points of a surface fill few of the cells, so with as few cells
    // as points the cells a triangle's box meets are crowded. 4n cells (two
    // more halvings per axis than n/2) cut the scan; empty cells cost one
    // compare.
    const double side = std::max(1.0, std::floor(std::cbrt(4.0 * static_cast<double>(n))));
    for (int k = 0; k < 3; ++k) {
      const double ext = hi[k] - lo_[k];
      res_[k] = ext > 0 ? static_cast<uint32_t>(std::min(side, 256.0)) : 1u;
      inv_[k] = ext > 0 ? res_[k] / ext : 0.0;
    }
    const size_t cells = static_cast<size_t>(res_[0]) * res_[1] * res_[2];
    start_.assign(cells + 1, 0);
    std::vector<uint32_t> cell_of(n);
    for (size_t i = 0; i < n; ++i) {
      cell_of[i] = cell(&plc.points[i].x);
      ++start_[cell_of[i] + 1];
    }
    for (size_t c = 0; c < cells; ++c) start_[c + 1] += start_[c];
    items_.resize(n);
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    for (size_t i = 0; i < n; ++i) items_[fill[cell_of[i]]++] = static_cast<uint32_t>(i);
  }

  /// Points p with lo <= p <= hi (componentwise, exact comparisons), ascending ids.
  void query(const double* lo, const double* hi, std::vector<VertexId>& out) const {
    out.clear();
    if (items_.empty()) return;
    uint32_t a[3], b[3];
    for (int k = 0; k < 3; ++k) a[k] = coord(lo[k], k), b[k] = coord(hi[k], k);
    for (uint32_t z = a[2]; z <= b[2]; ++z)
      for (uint32_t y = a[1]; y <= b[1]; ++y)
        for (uint32_t x = a[0]; x <= b[0]; ++x) {
          const size_t c = (static_cast<size_t>(z) * res_[1] + y) * res_[0] + x;
          for (uint32_t j = start_[c]; j < start_[c + 1]; ++j) {
            const Vec3& p = plc_.points[items_[j]];
            if (p.x >= lo[0] && p.x <= hi[0] && p.y >= lo[1] && p.y <= hi[1] && p.z >= lo[2] &&
                p.z <= hi[2])
              out.push_back(items_[j]);
          }
        }
    std::sort(out.begin(), out.end());
  }

 private:
  uint32_t coord(double x, int k) const {
    const double c = std::floor((x - lo_[k]) * inv_[k]);
    if (!(c > 0)) return 0;
    if (c >= res_[k] - 1) return res_[k] - 1;
    return static_cast<uint32_t>(c);
  }
  uint32_t cell(const double* p) const {
    return (coord(p[2], 2) * res_[1] + coord(p[1], 1)) * res_[0] + coord(p[0], 0);
  }

  const Plc& plc_;
  std::array<double, 3> lo_{}, inv_{};
  std::array<uint32_t, 3> res_{{1, 1, 1}};
  std::vector<uint32_t> start_, items_;
};

class FacetTriangulator {
 public:
  FacetTriangulator(const Plc& plc, const SegmentSet& segs, const TetMesh& mesh,
                    bool nothing_embedded)
      : plc_(plc), segs_(segs), mesh_(mesh), nothing_embedded_(nothing_embedded),
        grid_(plc, !nothing_embedded) {
    // Segments incident to each PLC point (CSR).
    const size_t np = plc.points.size();
    seg_start_.assign(np + 1, 0);
    for (const auto& e : segs.input)
      for (VertexId v : e)
        if (v < np) ++seg_start_[v + 1];
    for (size_t v = 0; v < np; ++v) seg_start_[v + 1] += seg_start_[v];
    seg_items_.resize(seg_start_[np]);
    std::vector<uint32_t> fill(seg_start_.begin(), seg_start_.end() - 1);
    for (uint32_t s = 0; s < segs.input.size(); ++s)
      for (VertexId v : segs.input[s])
        if (v < np) seg_items_[fill[v]++] = s;
  }

  Status run(size_t f, const std::vector<VertexId>* interior, Subfaces& out);

 private:
  // The steps of run(), in order.
  Status collect_loops(size_t f);
  Status choose_projection(size_t f, int& drop);
  bool plain_triangle(size_t f, const std::vector<VertexId>* interior, Subfaces& out) const;
  Status collect_vertices(size_t f, const std::vector<VertexId>* interior, int drop);
  Status outer_loop_orientation(size_t f, int& sign) const;
  Status insert_constraints(size_t f, Cdt2& cdt);
  void mark_outside(size_t f, const std::vector<Tri>& T, int drop,
                    std::vector<uint8_t>& out_mark);
  void mark_even(const std::vector<Tri>& T, std::vector<uint8_t>& out_mark);

  // Local id (index in verts_) of mesh vertex v, which must be in verts_.
  uint32_t local(VertexId v) const {
    return static_cast<uint32_t>(std::lower_bound(verts_.begin(), verts_.end(), v) -
                                 verts_.begin());
  }
  bool is_loop_edge(uint32_t p, uint32_t q) const {
    return std::binary_search(loop_keys_.begin(), loop_keys_.end(), edge_key(p, q));
  }
  // The input segment ab (smallest index), or -1: a scan of the few segments
  // at the lower end, not a search of all of them (three per facet).
  int64_t segment_index(VertexId a, VertexId b) const {
    const std::array<VertexId, 2> k = {std::min(a, b), std::max(a, b)};
    if (k[0] + 1 >= seg_start_.size()) return -1;
    for (uint32_t j = seg_start_[k[0]]; j < seg_start_[k[0] + 1]; ++j)
      if (segs_.input[seg_items_[j]] == k) return seg_items_[j];
    return -1;
  }
  // PLC points and segments lying in the plane of facet f inside its
  // bounding box that are not on its loops (candidates: those outside the
  // facet end up in removed triangles).
  void embedded(size_t f, const double* A, const double* B, const double* C, int drop);
  // p (projected) inside or on some loop of facet f (crossing rule, exact).
  bool in_some_loop(size_t f, const double* p, int drop) const;

  const Plc& plc_;
  const SegmentSet& segs_;
  const TetMesh& mesh_;
  const bool nothing_embedded_;  // see triangulate_facets
  PointGrid grid_;
  std::vector<uint32_t> seg_start_, seg_items_;
  std::vector<VertexId> verts_;      // sorted mesh ids of the facet's vertices
  std::vector<double> xy_;
  std::vector<std::array<uint32_t, 2>> constraints_;  // local ids
  std::vector<uint64_t> loop_keys_;  // loop subsegments, sorted local-id keys
  std::vector<VertexId> loop_vertices_, extra_points_, box_;
  std::vector<uint32_t> loop_segs_, extra_segs_;
  Cdt2 cdt_{xy_, verts_};             // after xy_ and verts_, which it reads
  std::vector<uint8_t> out_mark_;     // per triangle of cdt_: outside the facet
  std::vector<int32_t> flood_;        // mark_outside's stack
};

bool FacetTriangulator::in_some_loop(size_t f, const double* p, int drop) const {
  for (const auto& L : plc_.facets[f].loops) {
    bool inside = false;
    for (size_t i = 0; i < L.size(); ++i) {
      double a[2], b[2];
      project(&plc_.points[L[i]].x, drop, a);
      project(&plc_.points[L[(i + 1) % L.size()]].x, drop, b);
      const int o = pred::orient2d(a, b, p);
      if (o == 0 && std::min(a[0], b[0]) <= p[0] && p[0] <= std::max(a[0], b[0]) &&
          std::min(a[1], b[1]) <= p[1] && p[1] <= std::max(a[1], b[1]))
        return true;  // on the loop
      if (a[1] <= p[1] && p[1] < b[1] && o > 0) inside = !inside;
      if (b[1] <= p[1] && p[1] < a[1] && o < 0) inside = !inside;
    }
    if (inside) return true;
  }
  return false;
}

void FacetTriangulator::embedded(size_t f, const double* A, const double* B, const double* C,
                                 int drop) {
  const Facet& facet = plc_.facets[f];
  extra_points_.clear();
  extra_segs_.clear();
  double lo[3], hi[3];
  bool first = true;
  for (const auto& L : facet.loops)
    for (VertexId v : L) {
      const Vec3& p = plc_.points[v];
      const double c[3] = {p.x, p.y, p.z};
      for (int k = 0; k < 3; ++k) {
        lo[k] = first ? c[k] : std::min(lo[k], c[k]);
        hi[k] = first ? c[k] : std::max(hi[k], c[k]);
      }
      first = false;
    }
  grid_.query(lo, hi, box_);
  for (VertexId v : box_) {
    if (std::binary_search(loop_vertices_.begin(), loop_vertices_.end(), v)) continue;
    if (pred::orient3d(A, B, C, &plc_.points[v].x) != 0) continue;
    double p[2];
    project(&plc_.points[v].x, drop, p);
    if (in_some_loop(f, p, drop)) extra_points_.push_back(v);
  }
  // Segments between two vertices of the plane (loop or extra) that are not
  // loop edges of this facet. A triangle without extra points has none: a
  // segment joins two of its vertices only along one of its three edges.
  if (extra_points_.empty() && facet.loops.size() == 1 && facet.loops[0].size() == 3) return;
  auto in_plane = [this](VertexId v) {
    return std::binary_search(loop_vertices_.begin(), loop_vertices_.end(), v) ||
           std::binary_search(extra_points_.begin(), extra_points_.end(), v);
  };
  for (const std::vector<VertexId>* list : {&loop_vertices_, &extra_points_})
    for (VertexId v : *list) {
      if (v >= plc_.points.size()) continue;
      for (uint32_t j = seg_start_[v]; j < seg_start_[v + 1]; ++j) {
        const uint32_t s = seg_items_[j];
        const VertexId w = segs_.input[s][0] == v ? segs_.input[s][1] : segs_.input[s][0];
        if (!in_plane(w)) continue;
        if (std::binary_search(loop_segs_.begin(), loop_segs_.end(), s)) continue;
        extra_segs_.push_back(s);
      }
    }
  std::sort(extra_segs_.begin(), extra_segs_.end());
  extra_segs_.erase(std::unique(extra_segs_.begin(), extra_segs_.end()), extra_segs_.end());
}

// Loop vertices and loop segments of facet f (sorted, each once).
Status FacetTriangulator::collect_loops(size_t f) {
  const Facet& facet = plc_.facets[f];
  loop_vertices_.clear();
  loop_segs_.clear();
  for (const auto& L : facet.loops) {
    for (size_t i = 0; i < L.size(); ++i) {
      const VertexId a = L[i], b = L[(i + 1) % L.size()];
      const int64_t s = segment_index(a, b);
      if (s < 0 || a >= plc_.points.size() || b >= plc_.points.size())
        return facet_error(f, "loop edge (" + std::to_string(a) + ", " + std::to_string(b) +
                                  ") is not a segment");
      loop_segs_.push_back(static_cast<uint32_t>(s));
      loop_vertices_.push_back(a);
    }
  }
  std::sort(loop_vertices_.begin(), loop_vertices_.end());
  loop_vertices_.erase(std::unique(loop_vertices_.begin(), loop_vertices_.end()),
                       loop_vertices_.end());
  std::sort(loop_segs_.begin(), loop_segs_.end());
  loop_segs_.erase(std::unique(loop_segs_.begin(), loop_segs_.end()), loop_segs_.end());
  return Status::success();
}

// The facet's plane from three non-collinear loop vertices and the axis its
// projection drops (step 2 of the file header); then the PLC points and
// segments embedded in the facet (embedded()).
Status FacetTriangulator::choose_projection(size_t f, int& drop) {
  const Facet& facet = plc_.facets[f];
  const VertexId a0 = facet.loops[0][0];
  VertexId b0 = kNone, c0 = kNone;
  for (const auto& L : facet.loops) {
    for (VertexId v : L) {
      if (v == a0) continue;
      if (b0 == kNone) {
        b0 = v;
      } else if (c0 == kNone && v != b0 &&
                 !pred::collinear3d(mesh_.point(a0), mesh_.point(b0), mesh_.point(v))) {
        c0 = v;
      }
    }
  }
  if (c0 == kNone) return facet_error(f, "the loops' vertices are collinear");
  const double* A = mesh_.point(a0);
  const double* B = mesh_.point(b0);
  const double* C = mesh_.point(c0);

  // Drop the largest normal component (exactly nonzero).
  drop = projection_axis(A, B, C);
  if (pred::orient2d_projected(A, B, C, drop) == 0) {
    drop = -1;
    for (int k = 0; k < 3 && drop < 0; ++k)
      if (pred::orient2d_projected(A, B, C, k) != 0) drop = k;
    if (drop < 0) return facet_error(f, "no projection plane");
  }
  if (nothing_embedded_) {
    extra_points_.clear();
    extra_segs_.clear();
  } else {
    embedded(f, A, B, C, drop);
  }
  return Status::success();
}

// Fast path: a triangle whose edges are unsplit and nothing inside is its
// own triangulation. Its three edges are looked up directly, so a PLC with
// nothing embedded in its facets takes it before collect_loops and its
// sorts (the bulk of the work on a triangle mesh). False
// sends the facet down the general path, which also reports bad loops.
bool FacetTriangulator::plain_triangle(size_t f, const std::vector<VertexId>* interior,
                                       Subfaces& out) const {
  const Facet& facet = plc_.facets[f];
  if (facet.loops.size() != 1 || facet.loops[0].size() != 3 ||
      (interior != nullptr && !interior->empty()) || !extra_points_.empty() || !extra_segs_.empty())
    return false;
  const auto& L = facet.loops[0];
  for (int i = 0; i < 3; ++i) {
    const VertexId a = L[i], b = L[(i + 1) % 3];
    if (a >= plc_.points.size() || b >= plc_.points.size()) return false;
    const int64_t s = segment_index(a, b);
    if (s < 0 || segs_.chain[s].size() != 2) return false;
  }
  out.tri.push_back({L[0], L[1], L[2]});
  out.facet.push_back(static_cast<uint32_t>(f));
  return true;
}

// Vertices: chain vertices of the loop edges and of the embedded segments,
// embedded points, interior vertices; and their projections.
Status FacetTriangulator::collect_vertices(size_t f, const std::vector<VertexId>* interior,
                                           int drop) {
  verts_.clear();
  for (uint32_t s : loop_segs_)
    verts_.insert(verts_.end(), segs_.chain[s].begin(), segs_.chain[s].end());
  for (uint32_t s : extra_segs_)
    verts_.insert(verts_.end(), segs_.chain[s].begin(), segs_.chain[s].end());
  verts_.insert(verts_.end(), extra_points_.begin(), extra_points_.end());
  if (interior != nullptr) verts_.insert(verts_.end(), interior->begin(), interior->end());
  std::sort(verts_.begin(), verts_.end());
  verts_.erase(std::unique(verts_.begin(), verts_.end()), verts_.end());
  if (!verts_.empty() && verts_.back() >= mesh_.num_vertices())
    return facet_error(f, "vertex " + std::to_string(verts_.back()) + " is not in the mesh");
  xy_.resize(2 * verts_.size());
  for (size_t i = 0; i < verts_.size(); ++i) project(mesh_.point(verts_[i]), drop, &xy_[2 * i]);
  return Status::success();
}

// Orientation of the outer loop in the projection, at its lexicographically
// smallest vertex (a convex corner): +1 counterclockwise, -1 clockwise.
Status FacetTriangulator::outer_loop_orientation(size_t f, int& sign) const {
  const Facet& facet = plc_.facets[f];
  size_t best_loop = 0, best_pos = 0;
  double bx = 0, by = 0;
  bool have = false;
  for (size_t l = 0; l < facet.loops.size(); ++l) {
    const auto& L = facet.loops[l];
    for (size_t i = 0; i < L.size(); ++i) {
      const uint32_t li = local(L[i]);
      const double x = xy_[2 * li], y = xy_[2 * li + 1];
      if (!have || x < bx || (x == bx && y < by)) {
        have = true, bx = x, by = y, best_loop = l, best_pos = i;
      }
    }
  }
  const auto& L = facet.loops[best_loop];
  const uint32_t lp = local(L[(best_pos + L.size() - 1) % L.size()]);
  const uint32_t lv = local(L[best_pos]);
  const uint32_t ln = local(L[(best_pos + 1) % L.size()]);
  sign = pred::orient2d(&xy_[2 * lp], &xy_[2 * lv], &xy_[2 * ln]);
  if (sign == 0) return facet_error(f, "the outer loop has no orientation in the projection");
  return Status::success();
}

// Constraints: every subsegment of the loop chains and embedded segments;
// the loop ones are also remembered (loop_keys_) for the region marking.
Status FacetTriangulator::insert_constraints(size_t f, Cdt2& cdt) {
  constraints_.clear();
  loop_keys_.clear();
  for (int pass = 0; pass < 2; ++pass)
    for (uint32_t s : pass == 0 ? loop_segs_ : extra_segs_) {
      const auto& c = segs_.chain[s];
      for (size_t k = 0; k + 1 < c.size(); ++k) {
        const uint32_t p = local(c[k]), q = local(c[k + 1]);
        constraints_.push_back({p, q});
        if (pass == 0) loop_keys_.push_back(edge_key(p, q));
      }
    }
  std::sort(loop_keys_.begin(), loop_keys_.end());
  for (const auto& e : constraints_) {
    const std::string msg = cdt.insert_constraint(e[0], e[1]);
    if (!msg.empty()) return facet_error(f, msg);
  }
  return Status::success();
}

// Region: marks what the outside and the hole points reach without crossing
// a loop edge.
void FacetTriangulator::mark_outside(size_t f, const std::vector<Tri>& T, int drop,
                                     std::vector<uint8_t>& out_mark) {
  if (plc_.facets[f].even_odd) return mark_even(T, out_mark);
  out_mark.assign(T.size(), 0);
  std::vector<int32_t>& stack = flood_;
  stack.clear();
  auto flood = [&]() {
    while (!stack.empty()) {
      const int32_t t = stack.back();
      stack.pop_back();
      for (int i = 0; i < 3; ++i) {
        const int32_t nb = T[t].n[i];
        if (nb < 0 || out_mark[nb]) continue;
        if (is_loop_edge(T[t].v[next3(i)], T[t].v[prev3(i)])) continue;
        out_mark[nb] = 1;
        stack.push_back(nb);
      }
    }
  };
  for (size_t t = 0; t < T.size(); ++t) {
    for (int i = 0; i < 3; ++i) {
      if (T[t].n[i] >= 0 || out_mark[t]) continue;
      if (is_loop_edge(T[t].v[next3(i)], T[t].v[prev3(i)])) continue;
      out_mark[t] = 1;
      stack.push_back(static_cast<int32_t>(t));
    }
  }
  flood();
  for (const Vec3& hp : plc_.facets[f].holes) {
    const double p3[3] = {hp.x, hp.y, hp.z};
    double p[2];
    project(p3, drop, p);
    for (size_t t = 0; t < T.size(); ++t) {
      const double* P0 = &xy_[2 * T[t].v[0]];
      const double* P1 = &xy_[2 * T[t].v[1]];
      const double* P2 = &xy_[2 * T[t].v[2]];
      if (pred::orient2d(P0, P1, p) >= 0 && pred::orient2d(P1, P2, p) >= 0 &&
          pred::orient2d(P2, P0, p) >= 0) {
        if (!out_mark[t]) {
          out_mark[t] = 1;
          stack.push_back(static_cast<int32_t>(t));
          flood();
        }
        break;
      }
    }
  }
}

// Region of an even-odd facet (a merged flat face): a triangle is outside
// when an even number of loop edges separate it from the outside of the
// hull. The triangulation is connected, so one flood from the hull gives
// every triangle its parity.
void FacetTriangulator::mark_even(const std::vector<Tri>& T, std::vector<uint8_t>& out_mark) {
  constexpr uint8_t kUnseen = 2;
  out_mark.assign(T.size(), kUnseen);
  std::vector<int32_t>& stack = flood_;
  stack.clear();
  for (size_t t = 0; t < T.size(); ++t)
    for (int i = 0; i < 3 && out_mark[t] == kUnseen; ++i) {
      if (T[t].n[i] >= 0) continue;
      out_mark[t] = is_loop_edge(T[t].v[next3(i)], T[t].v[prev3(i)]) ? 0 : 1;
      stack.push_back(static_cast<int32_t>(t));
    }
  while (!stack.empty()) {
    const int32_t t = stack.back();
    stack.pop_back();
    for (int i = 0; i < 3; ++i) {
      const int32_t nb = T[t].n[i];
      if (nb < 0 || out_mark[nb] != kUnseen) continue;
      const bool cross = is_loop_edge(T[t].v[next3(i)], T[t].v[prev3(i)]);
      out_mark[nb] = cross ? !out_mark[t] : out_mark[t];
      stack.push_back(nb);
    }
  }
}

// Facet f's subfaces, appended to `out` oriented like its outer loop.
Status FacetTriangulator::run(size_t f, const std::vector<VertexId>* interior, Subfaces& out) {
  if (plc_.facets[f].loops.empty()) return facet_error(f, "the facet has no loop");
  // Most facets of a triangle mesh: no loop lists, no search for embedded
  // points, no projection (check_plc rejected collinear loops).
  if (nothing_embedded_ && plain_triangle(f, interior, out)) return Status::success();
  Status st = collect_loops(f);
  if (!st.ok()) return st;
  int drop = 2;
  st = choose_projection(f, drop);
  if (!st.ok()) return st;
  if (plain_triangle(f, interior, out)) return Status::success();
  int sign = 0;
  st = collect_vertices(f, interior, drop);
  if (st.ok()) st = outer_loop_orientation(f, sign);
  if (!st.ok()) return st;

  Cdt2& cdt = cdt_;
  // Delaunay first: subsegments are then usually edges already or cross few.
  std::string msg = "sweep";
  if (verts_.size() >= kMinVerticesInserted) msg = cdt.build_delaunay();
  if (!msg.empty()) {
    msg = cdt.build();
    if (msg.empty()) msg = cdt.make_delaunay();
  }
  if (!msg.empty()) return facet_error(f, msg);
  st = insert_constraints(f, cdt);
  if (!st.ok()) return st;
  if (cdt.flipped()) msg = cdt.make_delaunay();
  if (!msg.empty()) return facet_error(f, msg);

  const std::vector<Tri>& T = cdt.tris();
  std::vector<uint8_t>& out_mark = out_mark_;
  mark_outside(f, T, drop, out_mark);
  size_t kept = 0;
  for (size_t t = 0; t < T.size(); ++t) {
    if (out_mark[t]) continue;
    ++kept;
    const Tri& X = T[t];
    if (sign > 0) out.tri.push_back({verts_[X.v[0]], verts_[X.v[1]], verts_[X.v[2]]});
    else out.tri.push_back({verts_[X.v[0]], verts_[X.v[2]], verts_[X.v[1]]});
    out.facet.push_back(static_cast<uint32_t>(f));
  }
  if (kept == 0) return facet_error(f, "no triangle lies inside the facet");
  return Status::success();
}

}  // namespace

Status triangulate_facets(const Plc& plc, const SegmentSet& segs, const TetMesh& mesh,
                          const std::vector<std::vector<VertexId>>& interior, Subfaces& out,
                          bool nothing_embedded, bool beside) {
  out.tri.clear();
  out.facet.clear();
  // Facets are triangulated independently (the mesh and the PLC are only
  // read): the second half of a large PLC on the other core, its subfaces
  // appended after the first half's, so the result is the same either way.
  // An error is the first in facet order, as without the split.
  const size_t nf = plc.facets.size();
  const size_t mid = beside && nf >= kMinFacetsBeside ? nf / 2 : nf;
  auto triangulate = [&](size_t begin, size_t end, Subfaces& sub, Status& st) {
    if (begin == end) return;  // no triangulator (its indexes) for an empty half
    FacetTriangulator ft(plc, segs, mesh, nothing_embedded);
    for (size_t f = begin; f < end && st.ok(); ++f)
      st = ft.run(f, f < interior.size() ? &interior[f] : nullptr, sub);
  };
  Subfaces second;
  Status st1, st2;
  run_beside(
      mid < nf, [&] { triangulate(0, mid, out, st1); },
      [&] { triangulate(mid, nf, second, st2); });
  if (!st1.ok()) return st1;
  if (!st2.ok()) return st2;
  out.tri.insert(out.tri.end(), second.tri.begin(), second.tri.end());
  out.facet.insert(out.facet.end(), second.facet.begin(), second.facet.end());
  return Status::success();
}

}  // namespace cdt3d
