// Cavity formation, verification/expansion and retetrahedralization for
// facet recovery (Si & Gärtner 2005 §7). See cavity.hpp for the outline.
#include "cavity.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

#include "delaunay.hpp"
#include "geometry.hpp"
#include "predicates.hpp"

namespace cdt3d {

namespace {

// Per tet slot marks of CavityMesher (mark_): kNone untouched; a cavity id
// (small) for a tet taken in by that cavity's expansion.
constexpr uint32_t kMarkKept = 0xfffffffeu;  // tested, not met by Ω
constexpr uint32_t kMarkHole = 0xfffffffdu;  // met by Ω
constexpr uint32_t kSideKept = 0xffffffffu;  // Rec::side[1]: a kept tet is there
constexpr uint32_t kPending = 0xfffffffcu;   // Rec::side before linking

inline bool is_cavity_mark(uint32_t mark) { return mark < kPending; }

// Gift-wrapping costs about (vertices x front) exact tests per tet: beyond
// this many vertices a cavity is not gift-wrapped (the region fails).
constexpr size_t kMaxGiftWrapVertices = 4096;

// Edges of a tet by vertex positions.
constexpr int kTetEdge[6][2] = {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}};

// (x0, x1, x2) is a cyclic rotation of (y0, y1, y2).
bool same_rotation(const VertexId* x, const VertexId* y) {
  for (int r = 0; r < 3; ++r)
    if (x[0] == y[r] && x[1] == y[(r + 1) % 3] && x[2] == y[(r + 2) % 3]) return true;
  return false;
}

// --- exact 2D tests on coplanar points (projection to a coordinate plane) ---

// A coordinate plane on which the triangle (a, b, c) does not degenerate, and
// the sign that makes the triangle counterclockwise there. Projection drops a
// coordinate, so coplanar points keep their in-plane orientations exactly.
struct Projection {
  int drop = 2;
  int sign = 1;
  int o2(const double* u, const double* v, const double* w) const {
    return sign * pred::orient2d_projected(u, v, w, drop);
  }
};

Projection projection_of(const double* a, const double* b, const double* c) {
  Projection p;
  for (int drop : axes_by_normal(triangle_normal(a, b, c))) {
    const int s = pred::orient2d_projected(a, b, c, drop);
    if (s != 0) {
      p.drop = drop;
      p.sign = s;
      return p;
    }
  }
  p.sign = 0;  // collinear: no projection works
  return p;
}

// u strictly between x and y, all three collinear.
bool strictly_between(const double* x, const double* y, const double* u) {
  int k = 0;
  while (k < 3 && x[k] == y[k]) ++k;
  if (k == 3) return false;
  return (x[k] < u[k] && u[k] < y[k]) || (y[k] < u[k] && u[k] < x[k]);
}

// Relative interiors of segment pq and triangle xyz meet (all coplanar, P
// makes xyz counterclockwise). Separating axis: an edge line of the triangle
// with p and q on its closed outer side, or the line pq with the whole
// triangle on one closed side.
bool segment_meets_triangle_2d(const Projection& P, const double* p, const double* q,
                               const double* x, const double* y, const double* z) {
  const double* t[3] = {x, y, z};
  for (int i = 0; i < 3; ++i) {
    const double *e0 = t[i], *e1 = t[(i + 1) % 3];
    if (P.o2(e0, e1, p) <= 0 && P.o2(e0, e1, q) <= 0) return false;
  }
  const int s1 = P.o2(p, q, x), s2 = P.o2(p, q, y), s3 = P.o2(p, q, z);
  if ((s1 >= 0 && s2 >= 0 && s3 >= 0) || (s1 <= 0 && s2 <= 0 && s3 <= 0)) return false;
  return true;
}

// Relative interiors of coplanar segments pq and xy cross at one point.
bool segments_cross_2d(const Projection& P, const double* p, const double* q, const double* x,
                       const double* y) {
  return P.o2(p, q, x) * P.o2(p, q, y) < 0 && P.o2(x, y, p) * P.o2(x, y, q) < 0;
}

// Segment u1u2 crosses the plane of triangle xyz at a point of its relative
// interior (endpoints strictly on opposite sides): does that point lie in the
// closed triangle? (Inside, on an edge, or at a vertex: every case is an
// improper contact for the callers.)
bool transversal_hits_triangle(const double* u1, const double* u2, const double* x, const double* y,
                               const double* z) {
  const int s1 = pred::orient3d(u1, u2, x, y);
  const int s2 = pred::orient3d(u1, u2, y, z);
  const int s3 = pred::orient3d(u1, u2, z, x);
  const bool pos = s1 > 0 || s2 > 0 || s3 > 0;
  const bool neg = s1 < 0 || s2 < 0 || s3 < 0;
  return !(pos && neg) && (pos || neg);
}

}  // namespace

int orient_ids(const TetMesh& m, VertexId a, VertexId b, VertexId c, VertexId d) {
  return pred::orient3d(m.point(a), m.point(b), m.point(c), m.point(d));
}

// Improper contact of a simplex s (tet or triangle) and a triangle T, from
// the relative interiors of their faces: the intersection of two polytopes is
// the convex hull of its extreme points, and each extreme point lies in the
// relative interiors of a face α of s and a face β of T whose affine hulls
// meet only there, so dim α + dim β <= 3. The contact is improper exactly
// when some such pair with α != β meets. The pairs checked: a vertex of s in
// T or in an edge of T (vertices of T are mesh vertices and cannot lie on
// s); an edge of s through T (transversal, or in T's plane: against T and
// T's edges); an edge of T through a face of s (transversal, or coplanar).
bool improper_intersection(const TetMesh& m, const VertexId* s, int ns, const VertexId* tri) {
  const VertexId a = tri[0], b = tri[1], c = tri[2];
  const double *pa = m.point(a), *pb = m.point(b), *pc = m.point(c);
  bool shared[4] = {false, false, false, false};
  int oT[4] = {0, 0, 0, 0};
  bool pos = false, neg = false, zero = false;
  for (int i = 0; i < ns; ++i) {
    shared[i] = s[i] == a || s[i] == b || s[i] == c;
    if (shared[i]) continue;
    oT[i] = pred::orient3d(pa, pb, pc, m.point(s[i]));
    pos |= oT[i] > 0, neg |= oT[i] < 0, zero |= oT[i] == 0;
  }
  // Every vertex not shared strictly on one side: s meets T's plane only in
  // the common face.
  if (!zero && !(pos && neg)) return false;
  if (ns == 4) {
    // T strictly outside a face plane of the tet (apart from vertices on
    // that face): the contact is at most the common face.
    for (int f = 0; f < 4; ++f) {
      const VertexId x = s[kFaceVertex[f][0]], y = s[kFaceVertex[f][1]], z = s[kFaceVertex[f][2]];
      bool separated = true;
      for (int k = 0; k < 3 && separated; ++k) {
        const VertexId v = tri[k];
        if (v == x || v == y || v == z) continue;
        if (pred::orient3d(m.point(x), m.point(y), m.point(z), m.point(v)) >= 0) separated = false;
      }
      if (separated) return false;
    }
  }
  const Projection PT = projection_of(pa, pb, pc);
  if (PT.sign == 0) return true;  // degenerate triangle: refuse, callers fail loudly
  const double* tp[3] = {pa, pb, pc};
  // Vertices of s on T's plane: inside T or inside an edge of T.
  for (int i = 0; i < ns; ++i) {
    if (shared[i] || oT[i] != 0) continue;
    const double* u = m.point(s[i]);
    const int e0 = PT.o2(pa, pb, u), e1 = PT.o2(pb, pc, u), e2 = PT.o2(pc, pa, u);
    if (e0 > 0 && e1 > 0 && e2 > 0) return true;
    const int es[3] = {e0, e1, e2};
    for (int k = 0; k < 3; ++k)
      if (es[k] == 0 && strictly_between(tp[k], tp[(k + 1) % 3], u)) return true;
  }
  // Edges of s.
  const int nedges = ns == 4 ? 6 : 3;
  for (int e = 0; e < nedges; ++e) {
    const int i = ns == 4 ? kTetEdge[e][0] : e, j = ns == 4 ? kTetEdge[e][1] : (e + 1) % 3;
    if (shared[i] && shared[j]) continue;  // an edge of T as well
    const double *u1 = m.point(s[i]), *u2 = m.point(s[j]);
    if (oT[i] * oT[j] < 0) {
      if (transversal_hits_triangle(u1, u2, pa, pb, pc)) return true;
    } else if (oT[i] == 0 && oT[j] == 0) {
      if (segment_meets_triangle_2d(PT, u1, u2, pa, pb, pc)) return true;
      for (int k = 0; k < 3; ++k) {
        const VertexId t1 = tri[k], t2 = tri[(k + 1) % 3];
        if (t1 == s[i] || t1 == s[j] || t2 == s[i] || t2 == s[j]) continue;
        if (segments_cross_2d(PT, u1, u2, m.point(t1), m.point(t2))) return true;
      }
    }
  }
  // Edges of T against the faces of s.
  const int nfaces = ns == 4 ? 4 : 1;
  for (int f = 0; f < nfaces; ++f) {
    VertexId fv[3];
    for (int k = 0; k < 3; ++k) fv[k] = ns == 4 ? s[kFaceVertex[f][k]] : s[k];
    const double *x = m.point(fv[0]), *y = m.point(fv[1]), *z = m.point(fv[2]);
    int oF[3];
    bool in_face[3];
    for (int k = 0; k < 3; ++k) {
      in_face[k] = tri[k] == fv[0] || tri[k] == fv[1] || tri[k] == fv[2];
      oF[k] = in_face[k] ? 0 : pred::orient3d(x, y, z, m.point(tri[k]));
    }
    Projection PF;
    bool have_pf = false;
    for (int k = 0; k < 3; ++k) {
      const int k2 = (k + 1) % 3;
      if (in_face[k] && in_face[k2]) continue;  // an edge of the face
      const double *t1 = tp[k], *t2 = tp[k2];
      if (oF[k] * oF[k2] < 0) {
        if (transversal_hits_triangle(t1, t2, x, y, z)) return true;
      } else if (oF[k] == 0 && oF[k2] == 0) {
        if (!have_pf) PF = projection_of(x, y, z), have_pf = true;
        if (PF.sign != 0 && segment_meets_triangle_2d(PF, t1, t2, x, y, z)) return true;
      }
    }
  }
  return false;
}

// ---------------------------------------------------------------------------
// CavityMesher
// ---------------------------------------------------------------------------

CavityMesher::CavityMesher(TetMesh& mesh, CavityLimits limits) : m_(mesh), limits_(limits) {}

void CavityMesher::reset_marks() {
  for (TetId t : touched_) mark_[t] = kNone;
  touched_.clear();
}

uint32_t CavityMesher::new_record(const VertexId v[3], uint32_t side_a, uint32_t side_b,
                                  HalfFace kept, int32_t omega) {
  Rec r;
  r.v[0] = v[0], r.v[1] = v[1], r.v[2] = v[2];
  r.side[0] = side_a, r.side[1] = side_b;
  r.kept = kept;
  r.omega = omega;
  const uint32_t id = static_cast<uint32_t>(recs_.size());
  recs_.push_back(r);
  return id;
}

void CavityMesher::kill_record(uint32_t r) {
  recs_[r].alive = false;
  rec_of_.erase(sorted_triangle(recs_[r].v[0], recs_[r].v[1], recs_[r].v[2]));
}

// formcavity step 1: the tets meeting the relative interior of Ω improperly.
bool CavityMesher::test_tet(TetId t, const std::vector<Triangle>& region) {
  mark_[t] = kMarkKept;
  touched_.push_back(t);
  const VertexId* w = m_.tet_vertices(t);
  const int ns = w[3] == kInfinite ? 3 : 4;  // a ghost meets Ω only in its hull face
  double lo[3], hi[3];
  for (int k = 0; k < 3; ++k) lo[k] = hi[k] = m_.point(w[0])[k];
  for (int i = 1; i < ns; ++i)
    for (int k = 0; k < 3; ++k) {
      const double x = m_.point(w[i])[k];
      lo[k] = std::min(lo[k], x), hi[k] = std::max(hi[k], x);
    }
  for (size_t j = 0; j < region.size(); ++j) {
    const std::array<double, 6>& bx = boxes_[j];
    if (bx[0] > hi[0] || bx[3] < lo[0] || bx[1] > hi[1] || bx[4] < lo[1] || bx[2] > hi[2] ||
        bx[5] < lo[2])
      continue;
    if (improper_intersection(m_, w, ns, region[j].data())) {
      mark_[t] = kMarkHole;
      hole_.push_back(t);
      hole_sub_.push_back(static_cast<uint32_t>(j));
      return true;
    }
  }
  return false;
}

// Seeds: the stars of Ω's vertices. Every tet meeting Ω improperly is reached
// from them across faces: follow a path inside Ω from such a tet to a vertex
// of Ω; it can only leave the union of such tets through a kept tet, which
// meets Ω only in vertices and edges of Ω, i.e. at a vertex of Ω, whose star
// was tested.
CavityOutcome CavityMesher::form_hole(const std::vector<Triangle>& region, std::string& why) {
  boxes_.resize(region.size());
  std::vector<VertexId> verts;
  for (size_t j = 0; j < region.size(); ++j) {
    std::array<double, 6>& bx = boxes_[j];
    for (int k = 0; k < 3; ++k) bx[k] = bx[k + 3] = m_.point(region[j][0])[k];
    for (int i = 0; i < 3; ++i) {
      const VertexId v = region[j][i];
      verts.push_back(v);
      for (int k = 0; k < 3; ++k) {
        const double x = m_.point(v)[k];
        bx[k] = std::min(bx[k], x), bx[k + 3] = std::max(bx[k + 3], x);
      }
    }
  }
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  for (VertexId v : verts) {
    if (v >= m_.num_vertices() || m_.vtet[v] == kNone) {
      why = "vertex " + std::to_string(v) + " of the region is not in the mesh";
      return CavityOutcome::Failed;
    }
    m_.vertex_star(v, scratch_);
    for (TetId t : scratch_)
      if (mark_[t] == kNone) test_tet(t, region);
  }
  for (size_t k = 0; k < hole_.size(); ++k) {
    const TetId h = hole_[k];
    for (int i = 0; i < 4; ++i) {
      const TetId n = m_.neighbor(h, i);
      if (mark_[n] == kNone) test_tet(n, region);
    }
    if (hole_.size() > limits_.max_tets) {
      why = "the region meets more than " + std::to_string(limits_.max_tets) + " tets";
      return CavityOutcome::Limit;
    }
  }
  if (hole_.empty()) {
    why = "no tet meets the region";
    return CavityOutcome::Failed;
  }
  return CavityOutcome::Recovered;
}

// formcavity step 2, first half: the faces of the hole and both sides of
// every triangle of Ω become cavity faces.
bool CavityMesher::build_records(const std::vector<Triangle>& region, std::string& why) {
  for (TetId h : hole_) {
    for (int i = 0; i < 4; ++i) {
      const HalfFace out = m_.adjacent(make_hf(h, i));
      if (mark_[hf_tet(out)] == kMarkHole) continue;
      VertexId v[3];
      for (int k = 0; k < 3; ++k) v[k] = m_.vertex(h, kFaceVertex[i][k]);
      const uint32_t r = new_record(v, kPending, kSideKept, out, -1);
      rec_of_[sorted_triangle(v[0], v[1], v[2])] = r;
    }
  }
  omega_rec_.resize(region.size());
  for (size_t j = 0; j < region.size(); ++j) {
    const Triangle& T = region[j];
    const Triangle key = sorted_triangle(T[0], T[1], T[2]);
    if (rec_of_.count(key)) {
      why = "a triangle of the region is already a face of the hole";
      return false;
    }
    omega_rec_[j] = new_record(T.data(), kPending, kPending, kNone, static_cast<int32_t>(j));
    rec_of_[key] = omega_rec_[j];
  }
  return true;
}

namespace {

struct UnionFind {
  std::vector<uint32_t> parent;
  explicit UnionFind(size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), 0u); }
  uint32_t find(uint32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(uint32_t a, uint32_t b) {
    a = find(a), b = find(b);
    if (a != b) parent[std::max(a, b)] = std::min(a, b);
  }
};

// Whether triangle v traverses the edge p -> q (in that direction).
bool has_directed_edge(const VertexId* v, VertexId p, VertexId q) {
  for (int k = 0; k < 3; ++k)
    if (v[k] == p && v[(k + 1) % 3] == q) return true;
  return false;
}

// The vertex of triangle v that is neither p nor q.
VertexId third_vertex(const VertexId* v, VertexId p, VertexId q) {
  VertexId c = kNone;
  for (int k = 0; k < 3; ++k)
    if (v[k] != p && v[k] != q) c = v[k];
  return c;
}

}  // namespace

// link_cavities' state. Node 2r of the union-find is side A of record r,
// node 2r + 1 its side B; the classes are the cavities. The buffers hold the
// edge being linked: its records and the ring of tets around it.
struct CavityMesher::Linking {
  // Where a triangle of Ω lies in a run of hole tets around the edge: pos
  // 2i + 1 inside the i-th tet of the run, 2i + 2 along the face after it;
  // prev_side is the triangle's side (orientation sign) facing the piece
  // before it in the ring's order.
  struct Cut {
    uint32_t pos, rec;
    int prev_side;
  };
  explicit Linking(size_t records) : uf(2 * records) {}

  UnionFind uf;
  std::map<HalfFace, uint32_t> rec_of_kept;    // kept half-face -> its record
  std::vector<std::array<uint32_t, 3>> edges;  // (smaller id, larger id, record), sorted
  std::vector<uint32_t> srecs, orecs;          // at this edge: hole faces, triangles of Ω
  std::vector<TetId> ring;
  std::vector<VertexId> arrive;
  std::vector<Cut> cuts;
  std::vector<uint8_t> placed;  // per orecs entry: cuts made by it
};

// formcavity step 2, second half: which cavity faces bound the same cavity.
// Around an edge of the hole's boundary, the tets form a ring; each run of
// hole tets between two kept tets is one piece of cavity, bounded by the two
// kept faces, unless triangles of Ω containing the edge cut it: they lie in
// the run (in a tet's open wedge, or along a face between two hole tets) and
// split it into pieces, each bounded by consecutive faces. Edges of Ω with no
// kept tet around them (inside the hole, or not mesh edges) join the sides of
// Ω's triangles directly. The connected classes are the cavities.
bool CavityMesher::link_cavities(std::string& why) {
  Linking L(recs_.size());
  list_record_edges(L);
  for (size_t e0 = 0; e0 < L.edges.size();) {
    const VertexId p = L.edges[e0][0], q = L.edges[e0][1];
    L.srecs.clear(), L.orecs.clear();
    for (; e0 < L.edges.size() && L.edges[e0][0] == p && L.edges[e0][1] == q; ++e0) {
      const uint32_t r = L.edges[e0][2];
      (recs_[r].omega < 0 ? L.srecs : L.orecs).push_back(r);
    }
    const bool linked = L.srecs.empty() ? link_omega_edge(L, p, q, why) : link_ring(L, p, q, why);
    if (!linked) return false;
  }
  number_cavities(L);
  return true;
}

// Every edge of every record, sorted so that the records at one edge are
// consecutive; and the record of each kept half-face.
void CavityMesher::list_record_edges(Linking& L) const {
  L.edges.reserve(3 * recs_.size());
  for (uint32_t r = 0; r < recs_.size(); ++r) {
    const Rec& R = recs_[r];
    if (R.omega < 0) L.rec_of_kept[R.kept] = r;
    for (int k = 0; k < 3; ++k) {
      const VertexId x = R.v[k], y = R.v[(k + 1) % 3];
      L.edges.push_back({std::min(x, y), std::max(x, y), r});
    }
  }
  std::sort(L.edges.begin(), L.edges.end());
}

// An edge pq of Ω that no hole face has: the triangles of Ω at pq (one or
// two) close the cavities on their sides among themselves.
bool CavityMesher::link_omega_edge(Linking& L, VertexId p, VertexId q, std::string& why) {
  const std::vector<uint32_t>& o = L.orecs;
  if (o.size() == 1) {
    L.uf.unite(2 * o[0], 2 * o[0] + 1);
  } else if (o.size() == 2) {
    // Same facet, opposite sides of the edge: consistently oriented
    // triangles (the edge traversed in opposite directions) have the same
    // positive side.
    const bool same =
        has_directed_edge(recs_[o[0]].v, p, q) != has_directed_edge(recs_[o[1]].v, p, q);
    L.uf.unite(2 * o[0], 2 * o[1] + (same ? 0 : 1));
    L.uf.unite(2 * o[0] + 1, 2 * o[1] + (same ? 1 : 0));
  } else {
    why = "more than two triangles of the region share an edge";
    return false;
  }
  return true;
}

// An edge pq of the hole's boundary: walks the ring of tets around pq from a
// kept tet and links each run of hole tets in it; every triangle of Ω at pq
// must lie in exactly one run, once.
bool CavityMesher::link_ring(Linking& L, VertexId p, VertexId q, std::string& why) {
  const char* broken =
      m_.ring_around_edge(hf_tet(recs_[L.srecs[0]].kept), p, q, limits_.max_ring, L.ring, L.arrive);
  if (broken) {
    why = broken;
    return false;
  }
  const size_t n = L.ring.size();
  auto hole = [&](size_t i) { return mark_[L.ring[i]] == kMarkHole; };
  L.placed.assign(L.orecs.size(), 0);
  for (size_t s = 1; s < n; ++s) {
    if (!hole(s) || hole(s - 1)) continue;
    size_t e = s;
    while (e + 1 < n && hole(e + 1)) ++e;
    if (!link_run(L, p, q, s, e, why)) return false;
  }
  for (uint8_t count : L.placed)
    if (count != 1) {
      why = "a triangle of the region is not located exactly once around its edge";
      return false;
    }
  return true;
}

// The run ring[s..e] of hole tets between the kept tets ring[s - 1] and
// ring[e + 1]: chains the kept face it enters by, the triangles of Ω that
// cut it (in ring order, each passed from the side facing the piece before
// it to its other side), and the kept face it leaves by.
bool CavityMesher::link_run(Linking& L, VertexId p, VertexId q, size_t s, size_t e,
                            std::string& why) {
  const HalfFace hf_in = make_hf(L.ring[s - 1], m_.index_in_tet(L.ring[s - 1], L.arrive[s - 1]));
  const HalfFace hf_out = m_.adjacent(make_hf(L.ring[e], m_.index_in_tet(L.ring[e], L.arrive[e])));
  auto it_in = L.rec_of_kept.find(hf_in), it_out = L.rec_of_kept.find(hf_out);
  if (it_in == L.rec_of_kept.end() || it_out == L.rec_of_kept.end()) {
    why = "a face of the hole has no record";
    return false;
  }
  L.cuts.clear();
  for (size_t o = 0; o < L.orecs.size(); ++o) locate_in_run(L, p, q, s, e, o);
  std::sort(L.cuts.begin(), L.cuts.end(), [](const Linking::Cut& a, const Linking::Cut& b) {
    return a.pos != b.pos ? a.pos < b.pos : a.rec < b.rec;
  });
  uint32_t prev = 2 * it_in->second;
  for (const Linking::Cut& ct : L.cuts) {
    if (ct.prev_side == 0) {
      why = "a triangle of the region lies in the plane of a ring tet's vertex";
      return false;
    }
    const uint32_t back = ct.prev_side > 0 ? 0 : 1;
    L.uf.unite(prev, 2 * ct.rec + back);
    prev = 2 * ct.rec + (1 - back);
  }
  L.uf.unite(prev, 2 * it_out->second);
  return true;
}

// Where the triangle L.orecs[o] of Ω (edge pq, third vertex c) cuts the run
// ring[s..e]: strictly inside the wedge of a real tet at pq (c strictly
// between the tet's two other vertices around pq), or along the face between
// two consecutive tets (c in that face's plane through pq, on its side).
// Appends a cut for each and counts them in L.placed[o].
void CavityMesher::locate_in_run(Linking& L, VertexId p, VertexId q, size_t s, size_t e, size_t o) {
  const size_t n = L.ring.size();
  auto leave = [&](size_t i) { return L.arrive[(i + 1) % n]; };  // other vertex of ring[i]
  const Rec& R = recs_[L.orecs[o]];
  const VertexId c = third_vertex(R.v, p, q);
  for (size_t i = s; i <= e; ++i) {
    if (!m_.is_ghost(L.ring[i])) {
      const VertexId x = L.arrive[i], y = leave(i);
      const int o1 = orient_ids(m_, p, q, x, c), r1 = orient_ids(m_, p, q, x, y);
      const int o2 = orient_ids(m_, p, q, y, c), r2 = orient_ids(m_, p, q, y, x);
      if (o1 != 0 && o1 == r1 && o2 != 0 && o2 == r2) {
        const int sp = orient_ids(m_, R.v[0], R.v[1], R.v[2], x);
        L.cuts.push_back({uint32_t(2 * (i - s) + 1), L.orecs[o], sp});
        ++L.placed[o];
      }
    }
    if (i == e) continue;
    const VertexId f = L.arrive[i + 1];
    if (f == kInfinite || orient_ids(m_, p, q, f, c) != 0) continue;
    const bool real_i = !m_.is_ghost(L.ring[i]);
    const VertexId x = real_i ? L.arrive[i] : leave(i + 1);
    if (x == kInfinite) continue;
    const int sc = orient_ids(m_, p, q, x, c), sf = orient_ids(m_, p, q, x, f);
    if (sc == 0 || sc != sf) continue;
    const int so = orient_ids(m_, R.v[0], R.v[1], R.v[2], x);
    L.cuts.push_back({uint32_t(2 * (i - s) + 2), L.orecs[o], real_i ? so : -so});
    ++L.placed[o];
  }
}

// Classes -> cavity ids, numbered by first record; a cavity with a face
// through the vertex at infinity is a ghost cavity.
void CavityMesher::number_cavities(Linking& L) {
  const size_t nr = recs_.size();
  std::vector<uint32_t> cav_of_root(2 * nr, kNone);
  uint32_t ncav = 0;
  auto cav_of = [&](uint32_t node) {
    const uint32_t root = L.uf.find(node);
    if (cav_of_root[root] == kNone) cav_of_root[root] = ncav++;
    return cav_of_root[root];
  };
  for (uint32_t r = 0; r < nr; ++r) {
    Rec& R = recs_[r];
    R.side[0] = cav_of(2 * r);
    if (R.omega >= 0) R.side[1] = cav_of(2 * r + 1);
  }
  cavs_.clear();
  cavs_.resize(ncav);
  for (const Rec& R : recs_)
    if (R.v[0] == kInfinite || R.v[1] == kInfinite || R.v[2] == kInfinite)
      cavs_[R.side[0]].ghost = true;
}

// Vertices of hole tets on no cavity face lie inside a cavity: the one on
// their side of a triangle of Ω that meets their tet.
bool CavityMesher::assign_interior_vertices(const std::vector<Triangle>& region, std::string& why) {
  std::vector<VertexId> on;
  for (const Rec& R : recs_) on.insert(on.end(), R.v, R.v + 3);
  std::sort(on.begin(), on.end());
  on.erase(std::unique(on.begin(), on.end()), on.end());
  interior_.clear();
  for (size_t k = 0; k < hole_.size(); ++k) {
    for (int i = 0; i < 4; ++i) {
      const VertexId v = m_.vertex(hole_[k], i);
      if (std::binary_search(on.begin(), on.end(), v)) continue;
      if (v == kInfinite) {
        why = "the vertex at infinity is inside the hole";
        return false;
      }
      const Triangle& T = region[hole_sub_[k]];
      const int s = orient_ids(m_, T[0], T[1], T[2], v);
      if (s == 0) {
        why = "vertex " + std::to_string(v) + " inside the hole lies in the plane of the region";
        return false;
      }
      const Rec& R = recs_[omega_rec_[hole_sub_[k]]];
      interior_.push_back({v, s > 0 ? R.side[0] : R.side[1]});
    }
  }
  std::sort(interior_.begin(), interior_.end());
  interior_.erase(std::unique(interior_.begin(), interior_.end()), interior_.end());
  for (size_t i = 0; i < interior_.size(); ++i) {
    if (i > 0 && interior_[i].first == interior_[i - 1].first) {
      why = "vertex " + std::to_string(interior_[i].first) + " is inside two cavities";
      return false;
    }
    Cav& C = cavs_[interior_[i].second];
    if (C.ghost) {
      why = "a vertex lies inside the cavity beyond the hull";
      return false;
    }
    C.extra.push_back(interior_[i].first);
  }
  return true;
}

// V of cavity k: the vertices of its faces and the ones inside it.
void CavityMesher::collect_vertices(uint32_t k) {
  Cav& C = cavs_[k];
  C.verts = C.extra;
  for (const Rec& R : recs_)
    if (R.alive && (R.side[0] == k || R.side[1] == k)) C.verts.insert(C.verts.end(), R.v, R.v + 3);
  std::sort(C.verts.begin(), C.verts.end());
  C.verts.erase(std::unique(C.verts.begin(), C.verts.end()), C.verts.end());
}

// collect_vertices for a bounded cavity, which cannot hold the vertex at
// infinity (the vertex ids are sorted, so kInfinite would come last).
bool CavityMesher::collect_bounded_vertices(uint32_t k, std::string& why) {
  collect_vertices(k);
  const std::vector<VertexId>& verts = cavs_[k].verts;
  if (verts.empty() || verts.back() == kInfinite) {
    why = "a bounded cavity holds the vertex at infinity";
    return false;
  }
  return true;
}

// Cavity retetrahedralization step 2(1)-(2) for cavity k: D_C of its
// vertices and the records found in it. `missing` gets the records whose
// face is not in D_C (not strongly Delaunay in V under the perturbation).
bool CavityMesher::build_cavity_dt(uint32_t k, std::vector<uint32_t>& missing, std::string& why) {
  Cav& C = cavs_[k];
  if (!collect_bounded_vertices(k, why)) return false;
  const size_t n = C.verts.size();
  std::vector<double> xyz(3 * n);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) xyz[3 * i + c] = m_.point(C.verts[i])[c];
  // Local ids increase with the global ids: the perturbation of the
  // predicates (ordered by id) decides every tie as in the mesh.
  Status st = delaunay_tetrahedralize(C.dt, xyz.data(), n);
  if (!st.ok()) {
    why = "Delaunay tetrahedralization of a cavity failed: " + st.error.message;
    return false;
  }
  const size_t slots = C.dt.num_tet_slots();
  C.rec_at.assign(4 * slots, kNone);
  C.faces = 0;
  auto local = [&](VertexId v) {
    return static_cast<VertexId>(std::lower_bound(C.verts.begin(), C.verts.end(), v) -
                                 C.verts.begin());
  };
  for (uint32_t r = 0; r < recs_.size(); ++r) {
    Rec& R = recs_[r];
    if (!R.alive || (R.side[0] != k && R.side[1] != k)) continue;
    ++C.faces;
    const VertexId l[3] = {local(R.v[0]), local(R.v[1]), local(R.v[2])};
    const HalfFace hf = C.dt.find_face(l[0], l[1], l[2]);
    if (hf == kNone) {
      missing.push_back(r);
      continue;
    }
    const TetId t = hf_tet(hf);
    const int i = hf_face(hf);
    const VertexId listed[3] = {C.dt.vertex(t, kFaceVertex[i][0]),
                                C.dt.vertex(t, kFaceVertex[i][1]),
                                C.dt.vertex(t, kFaceVertex[i][2])};
    const HalfFace a_hf = same_rotation(listed, l) ? hf : C.dt.adjacent(hf);
    const HalfFace b_hf = C.dt.adjacent(a_hf);
    if (R.side[0] == k) R.dt_hf[0] = a_hf;
    if (R.side[1] == k) R.dt_hf[1] = b_hf;
    C.rec_at[a_hf] = C.rec_at[b_hf] = r;  // both sides: the flood stops there either way
  }
  return true;
}

// Cavity retetrahedralization step 2(2): inside/outside of D_C by flood fill
// from both sides of C's faces; a tet reached from both sides, an inside
// ghost tet, or a vertex of C in no inside tet is a failure.
bool CavityMesher::mark_inside(uint32_t k, std::string& why) {
  Cav& C = cavs_[k];
  const TetMesh& dt = C.dt;
  const size_t slots = dt.num_tet_slots();
  C.inside.assign(slots, 0);
  std::vector<TetId> stack_in, stack_out;
  auto internal = [&](uint32_t r) { return recs_[r].side[0] == k && recs_[r].side[1] == k; };
  for (const Rec& R : recs_) {
    if (!R.alive) continue;
    for (int s = 0; s < 2; ++s) {
      if (R.side[s] != k) continue;
      stack_in.push_back(hf_tet(R.dt_hf[s]));
      if (R.side[1 - s] != k) stack_out.push_back(hf_tet(dt.adjacent(R.dt_hf[s])));
    }
  }
  for (TetId t : stack_out) C.inside[t] = 2;
  for (TetId t : stack_in) {
    if (C.inside[t] == 2) {
      why = "a tet of the cavity's Delaunay tetrahedralization is on both sides of its faces";
      return false;
    }
    C.inside[t] = 1;
  }
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<TetId>& stack = pass == 0 ? stack_in : stack_out;
    const uint8_t mine = pass == 0 ? 1 : 2;
    while (!stack.empty()) {
      const TetId t = stack.back();
      stack.pop_back();
      if (pass == 0 && dt.is_ghost(t)) {
        why = "the inside of a cavity reaches the hull of its vertices";
        return false;
      }
      for (int i = 0; i < 4; ++i) {
        const HalfFace hf = make_hf(t, i);
        const uint32_t r = C.rec_at[hf];
        if (r != kNone && !internal(r)) continue;
        const TetId n = hf_tet(dt.adjacent(hf));
        if (C.inside[n] == mine) continue;
        if (C.inside[n] != 0) {
          why = "inside and outside of a cavity meet (its faces do not close it)";
          return false;
        }
        C.inside[n] = mine;
        stack.push_back(n);
      }
    }
  }
  // Every vertex of C must be used by an inside tet (none may be lost).
  std::vector<uint8_t> used(C.verts.size(), 0);
  for (TetId t = 0; t < slots; ++t) {
    if (C.inside[t] != 1) continue;
    for (int i = 0; i < 4; ++i) used[dt.vertex(t, i)] = 1;
  }
  for (size_t i = 0; i < used.size(); ++i)
    if (!used[i]) {
      why = "vertex " + std::to_string(C.verts[i]) + " of a cavity is in no tet of it";
      return false;
    }
  return true;
}

// Expansion (§7 step 1(2)): cavity k takes in the kept tet t; each face of t
// that was a face of k becomes inner, a face that bounded another cavity
// becomes a face between the two, any other face becomes a face of k.
bool CavityMesher::absorb(TetId t, uint32_t k, std::string& why) {
  mark_[t] = k;
  touched_.push_back(t);  // already there (tested); harmless duplicate
  absorbed_.push_back(t);
  Cav& C = cavs_[k];
  for (int i = 0; i < 4; ++i) C.extra.push_back(m_.vertex(t, i));
  for (int i = 0; i < 4; ++i) {
    VertexId v[3];
    for (int j = 0; j < 3; ++j) v[j] = m_.vertex(t, kFaceVertex[i][j]);
    const auto it = rec_of_.find(sorted_triangle(v[0], v[1], v[2]));
    if (it != rec_of_.end()) {
      Rec& R = recs_[it->second];
      if (R.side[1] != kSideKept || hf_tet(R.kept) != t) {
        why = "an expanded tet has a face between two cavities";
        return false;
      }
      if (R.side[0] == k) {
        kill_record(it->second);
      } else {
        R.side[1] = k;  // v is counterclockwise seen from t's side: side B is right
        R.kept = kNone;
        cavs_[R.side[0]].dirty = true;
      }
      continue;
    }
    const HalfFace out = m_.adjacent(make_hf(t, i));
    if (mark_[hf_tet(out)] == kMarkHole || is_cavity_mark(mark_[hf_tet(out)])) {
      why = "a face between an expanded tet and the hole has no record";
      return false;
    }
    const uint32_t r = new_record(v, k, kSideKept, out, -1);
    rec_of_[sorted_triangle(v[0], v[1], v[2])] = r;
  }
  C.dirty = true;
  return true;
}

// Fallback filling of cavity k by constrained gift-wrapping (see cavity.hpp).
// The front holds the faces still open, each listed as the tet that will
// close it must list it (counterclockwise seen from outside that tet). The
// result is stored like a D_C: tets in C.dt (local ids), adjacency among
// them, the cavity's faces in rec_at / dt_hf, and every other face glued to
// one placeholder slot marked outside.
// The faces of cavity k, oriented to face into it, by local vertex ids
// (C.verts): the first front of the gift-wrapping.
bool CavityMesher::open_cavity_faces(uint32_t k, std::map<Triangle, OpenFace>& front,
                                     std::string& why) {
  const Cav& C = cavs_[k];
  auto local = [&](VertexId v) {
    return static_cast<VertexId>(std::lower_bound(C.verts.begin(), C.verts.end(), v) -
                                 C.verts.begin());
  };
  for (uint32_t r = 0; r < recs_.size(); ++r) {
    const Rec& R = recs_[r];
    if (!R.alive || (R.side[0] != k && R.side[1] != k)) continue;
    if (R.side[0] == k && R.side[1] == k) {
      why = "gift-wrapping: a triangle of the region has the same cavity on both sides";
      return false;
    }
    const int side = R.side[0] == k ? 0 : 1;
    OpenFace o;
    o.v[0] = local(R.v[0]);
    o.v[1] = local(side == 0 ? R.v[1] : R.v[2]);
    o.v[2] = local(side == 0 ? R.v[2] : R.v[1]);
    o.rec = r, o.side = side;
    front[sorted_triangle(o.v[0], o.v[1], o.v[2])] = o;
  }
  return true;
}

// Keeps the tets of D_C (still holding this state of C) that are inside C
// and meet no missing face improperly: flood from the present faces without
// entering a tet that meets a missing face. Only the rest is gift-wrapped, so
// C stays Delaunay away from the missing faces. The kept tets go to `tets`,
// and `front` becomes the boundary of what they leave open.
bool CavityMesher::keep_sound_tets(uint32_t k, const std::vector<uint32_t>& missing,
                                   std::vector<std::array<VertexId, 4>>& tets,
                                   std::map<Triangle, OpenFace>& front, std::string& why) {
  Cav& C = cavs_[k];
  // Keep the tets of D_C (still holding this state of C) that are inside
  // C and meet no missing face improperly: flood from the present faces
  // without entering a tet that meets a missing face. Only the rest is
  // gift-wrapped, so C stays Delaunay away from the missing faces.
  const TetMesh& dt = C.dt;
  const size_t slots = dt.num_tet_slots();
  std::vector<uint8_t> mark(slots, 0);  // 1 inside, 2 outside, 3 bad
  for (TetId d = 0; d < slots; ++d) {
    if (dt.is_dead(d)) continue;
    if (dt.is_ghost(d)) {
      mark[d] = 3;
      continue;
    }
    const VertexId tg[4] = {C.verts[dt.vertex(d, 0)], C.verts[dt.vertex(d, 1)],
                            C.verts[dt.vertex(d, 2)], C.verts[dt.vertex(d, 3)]};
    for (uint32_t r : missing)
      if (improper_intersection(m_, tg, 4, recs_[r].v)) {
        mark[d] = 3;
        break;
      }
  }
  std::vector<uint8_t> is_missing(recs_.size(), 0);
  for (uint32_t r : missing) is_missing[r] = 1;
  std::vector<TetId> st_in, st_out;
  for (uint32_t r = 0; r < recs_.size(); ++r) {
    const Rec& R = recs_[r];
    if (!R.alive || is_missing[r] || (R.side[0] != k && R.side[1] != k)) continue;
    const HalfFace hf = R.dt_hf[R.side[0] == k ? 0 : 1];
    const TetId in = hf_tet(hf), out = hf_tet(dt.adjacent(hf));
    if (mark[in] != 3) st_in.push_back(in);
    if (mark[out] != 3) st_out.push_back(out);
  }
  for (int pass = 0; pass < 2; ++pass) {
    std::vector<TetId>& stk = pass == 0 ? st_in : st_out;
    const uint8_t mine = pass == 0 ? 1 : 2;
    for (TetId d : stk) {
      if (mark[d] != 0 && mark[d] != mine) {
        why = "gift-wrapping: a kept tet of D_C is on both sides of the cavity";
        return false;
      }
      mark[d] = mine;
    }
    while (!stk.empty()) {
      const TetId d = stk.back();
      stk.pop_back();
      for (int i = 0; i < 4; ++i) {
        const HalfFace hf = make_hf(d, i);
        if (C.rec_at[hf] != kNone) continue;
        const TetId nb = hf_tet(dt.adjacent(hf));
        if (mark[nb] == 3 || mark[nb] == mine) continue;
        if (mark[nb] != 0) {
          why = "gift-wrapping: inside and outside of D_C meet";
          return false;
        }
        mark[nb] = mine;
        stk.push_back(nb);
      }
    }
  }
  for (TetId d = 0; d < slots; ++d) {
    if (mark[d] != 1) continue;
    tets.push_back({dt.vertex(d, 0), dt.vertex(d, 1), dt.vertex(d, 2), dt.vertex(d, 3)});
    for (int i = 0; i < 4; ++i) {
      const HalfFace hf = make_hf(d, i);
      const VertexId L[3] = {dt.vertex(d, kFaceVertex[i][0]), dt.vertex(d, kFaceVertex[i][1]),
                             dt.vertex(d, kFaceVertex[i][2])};
      const Triangle key = sorted_triangle(L[0], L[1], L[2]);
      if (C.rec_at[hf] != kNone) {
        front.erase(key);  // a face of C, closed by this tet
        continue;
      }
      if (mark[hf_tet(dt.adjacent(hf))] == 1) continue;
      OpenFace o;
      o.v[0] = L[0], o.v[1] = L[2], o.v[2] = L[1];
      o.rec = kNone, o.side = 0;
      front[key] = o;
    }
  }
  return true;
}

// Stores the gift-wrapped tets of cavity k (local vertex ids) as a filled
// D_C: its own TetMesh whose open faces all lead to one placeholder tet
// `outside`, each tied to its record of C. Every vertex of C must be used
// and every open face must be a face of C.
bool CavityMesher::store_wrapped(uint32_t k, const std::vector<std::array<VertexId, 4>>& tets,
                                 const std::map<Triangle, OpenFace>& faces_of_c, std::string& why) {
  Cav& C = cavs_[k];
  const size_t n = C.verts.size();
  TetMesh& dt = C.dt;
  dt.clear();
  std::vector<double> xyz(3 * n);
  for (size_t i = 0; i < n; ++i)
    for (int c = 0; c < 3; ++c) xyz[3 * i + c] = m_.point(C.verts[i])[c];
  dt.coords = xyz;
  dt.vkind.assign(n, kVertexInput);
  dt.vtet.assign(n, kNone);
  for (size_t i = 0; i <= tets.size(); ++i) dt.alloc_tet();
  const TetId outside = static_cast<TetId>(tets.size());
  dt.set_tet(outside, 0, 0, 0, 0);
  C.inside.assign(tets.size() + 1, 1);
  C.inside[outside] = 2;
  C.rec_at.assign(4 * (tets.size() + 1), kNone);
  std::vector<std::pair<Triangle, HalfFace>> hfs;
  for (TetId d = 0; d < tets.size(); ++d) {
    dt.set_tet(d, tets[d][0], tets[d][1], tets[d][2], tets[d][3]);
    for (int i = 0; i < 4; ++i) {
      const VertexId a = tets[d][kFaceVertex[i][0]], b = tets[d][kFaceVertex[i][1]],
                     c = tets[d][kFaceVertex[i][2]];
      hfs.push_back({sorted_triangle(a, b, c), make_hf(d, i)});
    }
  }
  std::sort(hfs.begin(), hfs.end());
  std::vector<uint8_t> used(n, 0);
  for (const auto& t : tets)
    for (VertexId v : t) used[v] = 1;
  for (size_t i = 0; i < n; ++i)
    if (!used[i]) {
      why = "gift-wrapping left vertex " + std::to_string(C.verts[i]) + " of the cavity out";
      return false;
    }
  for (size_t i = 0; i < hfs.size();) {
    if (i + 1 < hfs.size() && hfs[i + 1].first == hfs[i].first) {
      dt.glue(hfs[i].second, hfs[i + 1].second);
      i += 2;
      continue;
    }
    const auto it = faces_of_c.find(hfs[i].first);
    if (it == faces_of_c.end()) {
      why = "gift-wrapping left an open face";
      return false;
    }
    dt.link_one_way(hfs[i].second, make_hf(outside, 0));
    C.rec_at[hfs[i].second] = it->second.rec;
    recs_[it->second.rec].dt_hf[it->second.side] = hfs[i].second;
    ++i;
  }
  C.faces = faces_of_c.size();
  return true;
}

bool CavityMesher::gift_wrap(uint32_t k, const std::vector<uint32_t>* missing, std::string& why) {
  Cav& C = cavs_[k];
  if (!collect_bounded_vertices(k, why)) return false;
  const size_t n = C.verts.size();
  if (n > kMaxGiftWrapVertices) {
    why = "the cavity is too large for gift-wrapping (" + std::to_string(n) + " vertices)";
    return false;
  }
  auto pt = [&](VertexId l) { return m_.point(C.verts[l]); };
  std::map<Triangle, OpenFace> front;
  if (!open_cavity_faces(k, front, why)) return false;
  const std::map<Triangle, OpenFace> faces_of_c = front;
  std::vector<std::array<VertexId, 4>> tets;
  if (missing && !missing->empty() && !keep_sound_tets(k, *missing, tets, front, why)) return false;
  std::vector<VertexId> cand;
  std::vector<uint8_t> tried;
  const size_t max_steps = 8 * n * n + 64;
  for (size_t step = 0; !front.empty(); ++step) {
    if (step > max_steps) {
      why = "gift-wrapping did not close the cavity";
      return false;
    }
    // Faces of Ω first (their tets are the ones the constraint decides),
    // then the other faces of C, then faces made here; by key within each.
    auto pick = front.begin();
    int best_rank = 3;
    for (auto it = front.begin(); it != front.end(); ++it) {
      const uint32_t r = it->second.rec;
      const int rank = r == kNone ? 2 : recs_[r].omega >= 0 ? 0 : 1;
      if (rank < best_rank) best_rank = rank, pick = it;
      if (rank == 0) break;
    }
    const OpenFace f = pick->second;
    const double *p0 = pt(f.v[0]), *p1 = pt(f.v[1]), *p2 = pt(f.v[2]);
    cand.clear();
    for (VertexId w = 0; w < n; ++w) {
      if (w == f.v[0] || w == f.v[1] || w == f.v[2]) continue;
      if (pred::orient3d(p0, p1, p2, pt(w)) > 0) cand.push_back(w);
    }
    tried.assign(cand.size(), 0);
    VertexId chosen = kNone;
    for (size_t round = 0; round < cand.size() && chosen == kNone; ++round) {
      // The untried candidate with the smallest sphere through f (ties by
      // the perturbation, ordered by global id).
      size_t best = kNone;
      for (size_t i = 0; i < cand.size(); ++i) {
        if (tried[i]) continue;
        if (best == kNone) {
          best = i;
          continue;
        }
        const VertexId b = cand[best], u = cand[i];
        if (pred::insphere_sos(p0, p1, p2, pt(b), pt(u), C.verts[f.v[0]], C.verts[f.v[1]],
                               C.verts[f.v[2]], C.verts[b], C.verts[u]) > 0)
          best = i;
      }
      tried[best] = 1;
      const VertexId w = cand[best];
      const VertexId tg[4] = {C.verts[f.v[0]], C.verts[f.v[1]], C.verts[f.v[2]], C.verts[w]};
      bool ok = true;
      // No other vertex of C in the closed tet.
      for (VertexId u = 0; u < n && ok; ++u) {
        if (u == f.v[0] || u == f.v[1] || u == f.v[2] || u == w) continue;
        bool in = true;
        for (int i = 0; i < 4 && in; ++i)
          in = pred::orient3d(m_.point(tg[kFaceVertex[i][0]]), m_.point(tg[kFaceVertex[i][1]]),
                              m_.point(tg[kFaceVertex[i][2]]), pt(u)) >= 0;
        ok = !in;
      }
      // No improper contact with the rest of the front.
      for (auto it = front.begin(); it != front.end() && ok; ++it) {
        if (it == pick) continue;
        const VertexId g[3] = {C.verts[it->second.v[0]], C.verts[it->second.v[1]],
                               C.verts[it->second.v[2]]};
        ok = !improper_intersection(m_, tg, 4, g);
      }
      if (ok) chosen = w;
    }
    if (chosen == kNone) {
      why = "gift-wrapping found no tet on a face of the cavity";
      return false;
    }
    const std::array<VertexId, 4> t = {f.v[0], f.v[1], f.v[2], chosen};
    tets.push_back(t);
    front.erase(pick);
    for (int i = 0; i < 3; ++i) {
      const VertexId L[3] = {t[kFaceVertex[i][0]], t[kFaceVertex[i][1]], t[kFaceVertex[i][2]]};
      const Triangle key = sorted_triangle(L[0], L[1], L[2]);
      auto it = front.find(key);
      if (it != front.end()) {
        if (!same_rotation(it->second.v, L)) {
          why = "gift-wrapping closed a face from the wrong side";
          return false;
        }
        front.erase(it);
        continue;
      }
      OpenFace o;
      o.v[0] = L[0], o.v[1] = L[2], o.v[2] = L[1];
      o.rec = kNone, o.side = 0;
      front[key] = o;
    }
  }
  return store_wrapped(k, tets, faces_of_c, why);
}

// Cavity retetrahedralization step 1 (verify C, expand C if necessary) and
// step 2(1)-(2), for every bounded cavity of the region until all verify in
// the same state (an expansion of one may change the faces of another).
CavityOutcome CavityMesher::verify_and_expand(CavityReport& report, std::string& why) {
  std::vector<uint32_t> missing;
  for (size_t rounds = 0;; ++rounds) {
    uint32_t k = kNone;
    for (uint32_t c = 0; c < cavs_.size(); ++c)
      if (cavs_[c].dirty && !cavs_[c].ghost) {
        k = c;
        break;
      }
    if (k == kNone) return CavityOutcome::Recovered;
    if (rounds >= limits_.max_rounds) {
      why = "cavity verification did not settle within " + std::to_string(limits_.max_rounds) +
            " rounds";
      return CavityOutcome::Limit;
    }
    ++report.rebuilds;
    missing.clear();
    if (!build_cavity_dt(k, missing, why)) return CavityOutcome::Failed;
    if (missing.empty()) {
      if (!mark_inside(k, why)) return CavityOutcome::Failed;
      cavs_[k].dirty = false;
      report.largest_cavity = std::max(report.largest_cavity, cavs_[k].faces);
      continue;
    }
    // Expand across the missing faces that have a kept real tet beyond; when
    // only faces that cannot be expanded are missing, gift-wrap the cavity.
    size_t expanded = 0;
    for (uint32_t r : missing) {
      const Rec& R = recs_[r];
      if (!R.alive || R.side[0] != k || R.side[1] != kSideKept || m_.is_ghost(hf_tet(R.kept)))
        continue;
      if (is_subface_ && is_subface_(sorted_triangle(R.v[0], R.v[1], R.v[2]))) continue;
      if (!absorb(hf_tet(R.kept), k, why)) return CavityOutcome::Failed;
      ++report.expansions;
      ++expanded;
    }
    if (expanded == 0) {
      const Rec& R = recs_[missing.front()];
      const std::string first =
          R.omega >= 0                  ? "a triangle of the region is not Delaunay in its cavity"
          : R.side[1] != kSideKept      ? "a face between two cavities is not Delaunay in a cavity"
          : m_.is_ghost(hf_tet(R.kept)) ? "a hull face of a cavity is not Delaunay in it"
                                        : "a subface on a cavity is not Delaunay in it";
      if (!gift_wrap(k, &missing, why)) {
        why = first + "; " + why;
        return CavityOutcome::Failed;
      }
      ++report.gift_wraps;
      cavs_[k].dirty = false;
      report.largest_cavity = std::max(report.largest_cavity, cavs_[k].faces);
    }
    if (hole_.size() + absorbed_.size() > limits_.max_tets) {
      why = "cavity expansion took in more than " + std::to_string(limits_.max_tets) + " tets";
      return CavityOutcome::Limit;
    }
  }
}

// A cavity holding the vertex at infinity lies beyond a hull plane that Ω
// covers: it is refilled by one ghost tet per finite face, glued along their
// infinite faces to each other or to the kept ghost tets; the hull must stay
// convex there.
bool CavityMesher::plan_ghost_cavity(uint32_t k, std::string& why) {
  Cav& C = cavs_[k];
  C.ghosts.clear();
  for (uint32_t r = 0; r < recs_.size(); ++r) {
    const Rec& R = recs_[r];
    if (!R.alive || (R.side[0] != k && R.side[1] != k)) continue;
    const bool inf = R.v[0] == kInfinite || R.v[1] == kInfinite || R.v[2] == kInfinite;
    if (inf) {
      if (R.side[0] != k || R.side[1] != kSideKept || !m_.is_ghost(hf_tet(R.kept))) {
        why = "an infinite face of the cavity beyond the hull is not next to a ghost tet";
        return false;
      }
      continue;
    }
    if (R.side[0] == k && R.side[1] == k) {
      why = "a triangle of the region has the outside of the hull on both sides";
      return false;
    }
    if (R.side[0] == k)
      C.ghosts.push_back({R.v[0], R.v[1], R.v[2], kInfinite});
    else
      C.ghosts.push_back({R.v[0], R.v[2], R.v[1], kInfinite});
  }
  // Every infinite face of a new ghost: an infinite record of k, or exactly
  // one other new ghost.
  std::vector<std::pair<Triangle, uint32_t>> faces;
  for (uint32_t g = 0; g < C.ghosts.size(); ++g)
    for (int i = 0; i < 3; ++i) {
      const std::array<VertexId, 4>& G = C.ghosts[g];
      faces.push_back(
          {sorted_triangle(G[kFaceVertex[i][0]], G[kFaceVertex[i][1]], G[kFaceVertex[i][2]]),
           4 * g + uint32_t(i)});
    }
  std::sort(faces.begin(), faces.end());
  size_t matched_records = 0;
  for (size_t i = 0; i < faces.size();) {
    size_t j = i;
    while (j < faces.size() && faces[j].first == faces[i].first) ++j;
    const auto it = rec_of_.find(faces[i].first);
    const bool rec = it != rec_of_.end() && recs_[it->second].side[0] == k;
    if ((rec && j - i != 1) || (!rec && j - i != 2)) {
      why = "the new hull faces over the region do not close up";
      return false;
    }
    if (rec) ++matched_records;
    // Convexity across the hull edge of this infinite face.
    for (size_t a = i; a < j; ++a) {
      const std::array<VertexId, 4>& G = C.ghosts[faces[a].second / 4];
      // The hull vertex across the edge: of the kept ghost, or of the other
      // new ghost (the vertex opposite their shared infinite face).
      VertexId other = kNone;
      if (rec) {
        const HalfFace kept = recs_[it->second].kept;
        other = m_.vertex(hf_tet(kept), hf_face(kept));
      } else {
        const uint32_t mate = faces[a == i ? i + 1 : i].second;
        other = C.ghosts[mate / 4][mate % 4];
      }
      if (other != kInfinite && orient_ids(m_, G[0], G[1], G[2], other) > 0) {
        why = "the new hull faces over the region are not convex";
        return false;
      }
    }
    i = j;
  }
  size_t inf_records = 0;
  for (const Rec& R : recs_)
    if (R.alive && R.side[0] == k &&
        (R.v[0] == kInfinite || R.v[1] == kInfinite || R.v[2] == kInfinite))
      ++inf_records;
  if (inf_records != matched_records) {
    why = "a ghost tet next to the region keeps an open face";
    return false;
  }
  return true;
}

// Cavity retetrahedralization step 2(3): replace the hole and the absorbed
// tets by the inside tets of every D_C and the new ghost tets;
// TetMesh::replace_tets glues them to each other and to the kept tets.
bool CavityMesher::commit(std::string& why) {
  removed_faces_.clear();
  auto remove = [&](TetId t) {
    for (int i = 0; i < 4; ++i) {
      VertexId f[3];
      for (int j = 0; j < 3; ++j) f[j] = m_.vertex(t, kFaceVertex[i][j]);
      if (f[0] != kInfinite && f[1] != kInfinite && f[2] != kInfinite)
        removed_faces_.push_back(sorted_triangle(f[0], f[1], f[2]));
    }
  };
  for (TetId t : hole_) remove(t);
  for (TetId t : absorbed_) remove(t);
  std::sort(removed_faces_.begin(), removed_faces_.end());
  removed_faces_.erase(std::unique(removed_faces_.begin(), removed_faces_.end()),
                       removed_faces_.end());

  std::vector<std::array<VertexId, 4>> fresh;
  for (const Cav& C : cavs_) {
    if (C.ghost) {
      fresh.insert(fresh.end(), C.ghosts.begin(), C.ghosts.end());
      continue;
    }
    for (TetId d = 0; d < C.dt.num_tet_slots(); ++d)
      if (C.inside[d] == 1) {
        const VertexId* w = C.dt.tet_vertices(d);
        fresh.push_back({C.verts[w[0]], C.verts[w[1]], C.verts[w[2]], C.verts[w[3]]});
      }
  }
  // Slots: last removed first, the order in which alloc_tet hands them out
  // after the hole and then the absorbed tets are freed one by one (the
  // numbering of the output's tets follows the slots).
  std::vector<TetId> old(absorbed_.rbegin(), absorbed_.rend());
  old.insert(old.end(), hole_.rbegin(), hole_.rend());
  std::vector<TetId> created;
  if (!m_.replace_tets(old.data(), old.size(), fresh.data(), fresh.size(), &created)) {
    why = "the new tets do not fill the cavities face to face";
    return false;
  }
  // vtet: replace_tets set a real new tet where there is one; else a real
  // kept tet next to a cavity face, else any live tet holding the vertex.
  auto valid = [&](VertexId v) {
    const TetId t = m_.vtet[v];
    return t != kNone && t < m_.num_tet_slots() && !m_.is_dead(t) && m_.index_in_tet(t, v) >= 0;
  };
  for (const Rec& R : recs_) {
    if (!R.alive || R.side[1] != kSideKept) continue;
    const TetId t = hf_tet(R.kept);
    for (int j = 0; j < 3; ++j) {
      const VertexId v = R.v[j];
      if (v == kInfinite) continue;
      if (!valid(v) || (m_.is_ghost(m_.vtet[v]) && !m_.is_ghost(t))) m_.set_vertex_tet(v, t);
    }
  }
  for (TetId t : created)
    if (m_.is_ghost(t))
      for (int i = 0; i < 3; ++i)
        if (!valid(m_.vertex(t, i))) m_.set_vertex_tet(m_.vertex(t, i), t);
  return true;
}

CavityOutcome CavityMesher::recover_region(const std::vector<Triangle>& region,
                                           CavityReport& report) {
  report = CavityReport{};
  hole_.clear(), hole_sub_.clear(), absorbed_.clear();
  recs_.clear(), rec_of_.clear(), cavs_.clear(), interior_.clear();
  removed_faces_.clear();
  if (mark_.size() < m_.num_tet_slots())
    mark_.resize(m_.num_tet_slots() + m_.num_tet_slots() / 4, kNone);
  std::string why;
  auto fail = [&](CavityOutcome o) {
    reset_marks();
    report.failure = why;
    return o;
  };
  CavityOutcome o = form_hole(region, why);
  report.hole_tets = hole_.size();
  if (o != CavityOutcome::Recovered) return fail(o);
  if (!build_records(region, why) || !link_cavities(why) || !assign_interior_vertices(region, why))
    return fail(CavityOutcome::Failed);
  o = verify_and_expand(report, why);
  if (o != CavityOutcome::Recovered) return fail(o);
  for (uint32_t k = 0; k < cavs_.size(); ++k)
    if (cavs_[k].ghost && !plan_ghost_cavity(k, why)) return fail(CavityOutcome::Failed);
  // Every live record needs a tet on each cavity side.
  for (const Rec& R : recs_) {
    if (!R.alive) continue;
    for (int s = 0; s < 2; ++s) {
      if (s == 1 && R.side[1] == kSideKept) continue;
      if (!cavs_[R.side[s]].ghost && R.dt_hf[s] == kNone) {
        why = "a cavity face was not identified in its cavity";
        return fail(CavityOutcome::Failed);
      }
    }
  }
  report.cavities = cavs_.size();
  reset_marks();
  if (!commit(why)) return fail(CavityOutcome::Failed);
  return CavityOutcome::Recovered;
}

}  // namespace cdt3d
