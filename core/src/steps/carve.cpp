// Carving: inside/outside marking from the constrained faces, volume holes,
// region attributes, exterior removal (see carve.hpp for the rules).
#include "carve.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "delaunay.hpp"
#include "geometry.hpp"
#include "status.hpp"

namespace cdt3d {
namespace {

// The first loop edge (facet order, loop order) used by exactly one facet.
bool open_edge(const Plc& plc, VertexId& a, VertexId& b, int64_t& facet) {
  struct Use {
    VertexId lo, hi;
    uint32_t facet;
  };
  std::vector<Use> uses;
  for (uint32_t f = 0; f < plc.facets.size(); ++f)
    for (const auto& L : plc.facets[f].loops)
      for (size_t i = 0; i < L.size(); ++i) {
        const VertexId p = L[i], q = L[(i + 1) % L.size()];
        uses.push_back({std::min(p, q), std::max(p, q), f});
      }
  auto less = [](const Use& x, const Use& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.facet < y.facet;
  };
  std::vector<Use> sorted = uses;
  std::sort(sorted.begin(), sorted.end(), less);
  auto facets_on = [&](VertexId lo, VertexId hi) {
    auto it = std::lower_bound(sorted.begin(), sorted.end(), Use{lo, hi, 0}, less);
    size_t n = 0;
    uint32_t last = kNone;
    for (; it != sorted.end() && it->lo == lo && it->hi == hi; ++it)
      if (it->facet != last) ++n, last = it->facet;
    return n;
  };
  for (uint32_t f = 0; f < plc.facets.size(); ++f)
    for (const auto& L : plc.facets[f].loops)
      for (size_t i = 0; i < L.size(); ++i) {
        const VertexId p = L[i], q = L[(i + 1) % L.size()];
        if (facets_on(std::min(p, q), std::max(p, q)) == 1) {
          a = p, b = q, facet = f;
          return true;
        }
      }
  return false;
}

// The tets connected across unconstrained faces (carve.hpp), and what each
// region becomes.
struct Regions {
  std::vector<uint32_t> of;       // per tet slot: its region (kNone: dead slot)
  std::vector<TetId> first;       // per region: its smallest slot
  std::vector<uint8_t> removed;   // per region: exterior or hole
  std::vector<uint8_t> has_real;  // per region: holds a real tet
  std::vector<double> attribute;  // per region
  size_t count() const { return first.size(); }
};

// Constrained half-faces: hf_sub[hf] is the subface on half-face hf (both
// sides), sub_hf[i] the half-face of subface i. A subface listed twice
// counts once, the first time.
// `sub_hf` may come in holding the half-faces of an earlier mesh (one per
// subface): then only the entries that changed are looked up again.
Status constrained_half_faces(TetMesh& mesh, const Subfaces& subfaces,
                              std::vector<uint32_t>& hf_sub, std::vector<HalfFace>& sub_hf) {
  hf_sub.assign(4 * mesh.num_tet_slots(), kNone);
  refresh_subface_half_faces(mesh, subfaces, sub_hf);
  for (size_t i = 0; i < subfaces.tri.size(); ++i) {
    const auto& s = subfaces.tri[i];
    const HalfFace hf = sub_hf[i];
    if (hf == kNone) {
      return make_error(ErrorCode::Internal,
                        "Subface (" + std::to_string(s[0]) + ", " + std::to_string(s[1]) + ", " +
                            std::to_string(s[2]) + ") is not a face of the mesh.")
          .facet(i < subfaces.facet.size() ? subfaces.facet[i] : -1);
    }
    if (hf_sub[hf] != kNone) continue;  // listed twice: the first one counts
    hf_sub[hf] = static_cast<uint32_t>(i);
    hf_sub[mesh.adjacent(hf)] = static_cast<uint32_t>(i);
  }
  return Status::success();
}

// Regions: connected across unconstrained faces, numbered in slot order
// (region r holds R.first[r], and the lowest slot of each region comes
// before that of the next). The ghosts' region is removed unless the hull
// is kept. A union-find over the faces in slot order, whose roots are the
// lowest slots of their sets: it reads the adjacency and the constrained
// faces in memory order, where a depth-first walk missed the cache at
// nearly every tet.
void connect_regions(const TetMesh& mesh, const std::vector<uint32_t>& hf_sub,
                     bool keep_convex_hull, Regions& R) {
  const TetId slots = static_cast<TetId>(mesh.num_tet_slots());
  std::vector<TetId> parent(slots);
  for (TetId t = 0; t < slots; ++t) parent[t] = t;
  auto root = [&parent](TetId x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];  // path halving
    return x;
  };
  for (TetId t = 0; t < slots; ++t) {
    if (mesh.is_dead(t)) continue;
    for (int i = 0; i < 4; ++i) {
      const HalfFace hf = make_hf(t, i);
      if (hf_sub[hf] != kNone) continue;
      const TetId n = hf_tet(mesh.adjacent(hf));
      if (n < t) continue;  // the face was met from n
      const TetId a = root(t), b = root(n);
      if (a < b)
        parent[b] = a;
      else if (b < a)
        parent[a] = b;
    }
  }
  R.of.assign(slots, kNone);
  for (TetId t = 0; t < slots; ++t) {
    if (mesh.is_dead(t)) continue;
    const TetId r = root(t);
    if (r == t) {  // the lowest slot of its region: the next number
      R.of[t] = static_cast<uint32_t>(R.first.size());
      R.first.push_back(t);
    } else {
      R.of[t] = R.of[r];  // r < t is numbered already
    }
  }
  R.removed.assign(R.count(), 0);
  R.has_real.assign(R.count(), 0);
  for (TetId t = 0; t < slots; ++t) {
    if (mesh.is_dead(t)) continue;
    if (mesh.is_ghost(t)) {
      if (!keep_convex_hull) R.removed[R.of[t]] = 1;
    } else {
      R.has_real[R.of[t]] = 1;
    }
  }
}

// Volume holes remove their regions; region points give attributes (the
// first listed wins), the other kept regions get largest + 1, + 2, ...
// Returns the number of kept regions.
size_t apply_holes_and_attributes(const Plc& plc, const TetMesh& mesh, Regions& R) {
  Rng rng(0x63617276652d6c6fULL);
  TetId hint = kNone;
  auto region_of = [&](const Vec3& p) -> uint32_t {
    const double xyz[3] = {p.x, p.y, p.z};
    const Location loc = locate_point(mesh, xyz, hint, rng);
    if (loc.kind != LocateKind::InTet) return kNone;
    hint = loc.tet;
    return R.of[loc.tet];
  };
  for (const Vec3& h : plc.holes) {
    const uint32_t r = region_of(h);
    if (r != kNone) R.removed[r] = 1;
  }
  std::vector<uint8_t> has_attr(R.count(), 0);
  R.attribute.assign(R.count(), 0.0);
  double largest = 0;
  for (const Region& rp : plc.regions) {
    if (std::isfinite(rp.attribute)) largest = std::max(largest, std::floor(rp.attribute));
    const uint32_t r = region_of(rp.point);
    if (r == kNone || has_attr[r]) continue;
    has_attr[r] = 1;
    R.attribute[r] = rp.attribute;
  }
  double next = largest + 1;
  size_t kept = 0;
  for (size_t r = 0; r < R.count(); ++r) {
    if (R.removed[r] || !R.has_real[r]) continue;
    ++kept;
    if (!has_attr[r]) R.attribute[r] = next++, has_attr[r] = 1;
  }
  return kept;
}

// Flags every live tet kTetInside or kTetOutside and lists the kept ones;
// kept[t] marks them by slot.
void keep_tets(TetMesh& mesh, const Regions& R, std::vector<uint8_t>& kept, CarveResult& out) {
  const size_t slots = mesh.num_tet_slots();
  kept.assign(slots, 0);
  for (TetId t = 0; t < slots; ++t) {
    if (mesh.is_dead(t)) continue;
    mesh.tflag[t] &= static_cast<uint8_t>(~(kTetInside | kTetOutside));
    if (!mesh.is_ghost(t) && !R.removed[R.of[t]]) {
      kept[t] = 1;
      mesh.tflag[t] |= kTetInside;
      out.tets.push_back(t);
      out.attribute.push_back(R.attribute[R.of[t]]);
    } else {
      mesh.tflag[t] |= kTetOutside;
    }
  }
}

// No tet kept: the error names an open boundary edge when there is one.
Status nothing_kept_error(const Plc& plc) {
  VertexId a = kNone, b = kNone;
  int64_t facet = -1;
  if (open_edge(plc, a, b, facet)) {
    return make_error(ErrorCode::OpenBoundary,
                      "The surface does not enclose a volume; boundary edge (" + std::to_string(a) +
                          ", " + std::to_string(b) + ") of facet " + std::to_string(facet) +
                          " is open.")
        .facet(facet)
        .vertex(a);
  }
  return make_error(ErrorCode::OpenBoundary,
                    "The surface does not enclose a volume: every tetrahedron is outside "
                    "the surface or in a hole.");
}

}  // namespace

Status carve(const Plc& plc, TetMesh& mesh, const Subfaces& subfaces, bool keep_convex_hull,
             CarveResult& out, const std::vector<HalfFace>* half_faces) {
  out = CarveResult();
  std::vector<uint32_t> hf_sub;
  std::vector<HalfFace> sub_hf;
  if (half_faces) sub_hf = *half_faces;
  Status st = constrained_half_faces(mesh, subfaces, hf_sub, sub_hf);
  if (!st.ok()) return st;
  Regions R;
  connect_regions(mesh, hf_sub, keep_convex_hull, R);
  out.regions = apply_holes_and_attributes(plc, mesh, R);
  std::vector<uint8_t> kept;
  keep_tets(mesh, R, kept, out);
  if (out.tets.empty()) return nothing_kept_error(plc);

  // Constrained faces with a kept tet on at least one side.
  for (size_t i = 0; i < subfaces.tri.size(); ++i) {
    const auto& s = subfaces.tri[i];
    const HalfFace hf = sub_hf[i];
    if (hf_sub[hf] != i) continue;
    if (!kept[hf_tet(hf)] && !kept[hf_tet(mesh.adjacent(hf))]) continue;
    out.faces.push_back(s);
    out.face_facet.push_back(i < subfaces.facet.size() ? subfaces.facet[i] : kNone);
  }
  return Status::success();
}

namespace {

// A tet of `mesh` that is numerically flat (geometry.hpp).
bool flat_tet(const TetMesh& mesh, TetId t) {
  const VertexId* w = mesh.tet_vertices(t);
  return numerically_flat(mesh.point(w[0]), mesh.point(w[1]), mesh.point(w[2]), mesh.point(w[3]));
}

}  // namespace

// A flat tet: two of its faces are subfaces of one facet, so its four
// vertices all lie in that facet, up to the rounding of Steiner points (§5
// rounds them to doubles, so a facet is only nearly planar). Both diagonals
// of the quadrilateral are then faces of the mesh. When the tet is kept but
// the tets across its two subfaces are outside (a boundary facet), the facet
// is triangulated with the tet's two other faces instead: they triangulate
// the same quadrilateral, and the flat tet joins the exterior. Returns the
// number of facets changed; the caller carves again.
size_t move_flat_tets_outside(const TetMesh& mesh, const SegmentSet& segs,
                              const CarveResult& carved, Subfaces& subfaces) {
  // Such a tet is numerically flat (its vertices are a few ulps from one
  // plane); the others need no face lookups.
  std::vector<TetId> flat;
  for (TetId t : carved.tets)
    if (flat_tet(mesh, t)) flat.push_back(t);
  if (flat.empty()) return 0;
  struct Key {
    std::array<VertexId, 3> v;
    uint32_t sub;
    bool operator<(const Key& o) const { return v != o.v ? v < o.v : sub < o.sub; }
  };
  std::vector<Key> keys;
  keys.reserve(subfaces.tri.size());
  for (uint32_t i = 0; i < subfaces.tri.size(); ++i) {
    const auto& t = subfaces.tri[i];
    keys.push_back({sorted_triangle(t[0], t[1], t[2]), i});
  }
  std::sort(keys.begin(), keys.end());
  auto find = [&](const std::array<VertexId, 3>& k) -> uint32_t {
    auto it = std::lower_bound(keys.begin(), keys.end(), Key{k, 0});
    return it != keys.end() && it->v == k ? it->sub : kNone;
  };
  auto kept = [&](TetId t) { return (mesh.tflag[t] & kTetInside) != 0; };
  std::vector<std::array<uint32_t, 3>> sub;
  segs.subsegments(sub);
  std::vector<std::array<VertexId, 2>> subsegs;
  for (const auto& e : sub) subsegs.push_back(sorted_edge(e[0], e[1]));
  std::sort(subsegs.begin(), subsegs.end());
  std::vector<uint8_t> changed(subfaces.tri.size(), 0);
  size_t moved = 0;
  for (TetId t : flat) {
    int face[2], n = 0;
    uint32_t sub[2];
    for (int i = 0; i < 4 && n <= 2; ++i) {
      const uint32_t s =
          find(sorted_triangle(mesh.vertex(t, kFaceVertex[i][0]), mesh.vertex(t, kFaceVertex[i][1]),
                               mesh.vertex(t, kFaceVertex[i][2])));
      if (s == kNone) continue;
      if (n < 2) face[n] = i, sub[n] = s;
      ++n;
    }
    if (n != 2 || subfaces.facet[sub[0]] != subfaces.facet[sub[1]]) continue;
    if (changed[sub[0]] || changed[sub[1]]) continue;
    if (kept(mesh.neighbor(t, face[0])) || kept(mesh.neighbor(t, face[1]))) continue;
    // s1 = (u, v, p) with the shared edge u -> v; s2 runs v -> u to q. The
    // quadrilateral is u -> q -> v -> p; the other diagonal gives (u, q, p)
    // and (q, v, p), oriented like the old pair.
    auto& s1 = subfaces.tri[sub[0]];
    auto& s2 = subfaces.tri[sub[1]];
    int r = 0;
    while (r < 3 && std::find(s2.begin(), s2.end(), s1[(r + 2) % 3]) != s2.end()) ++r;
    if (r == 3) continue;
    const VertexId u = s1[r], v = s1[(r + 1) % 3], p = s1[(r + 2) % 3];
    // Never across a subsegment: the other diagonal would drop it.
    if (std::binary_search(subsegs.begin(), subsegs.end(), sorted_edge(u, v))) continue;
    VertexId q = kNone;
    bool consistent = false;
    for (int k = 0; k < 3; ++k) {
      if (s2[k] != u && s2[k] != v) q = s2[k];
      if (s2[k] == v && s2[(k + 1) % 3] == u) consistent = true;
    }
    if (q == kNone || !consistent) continue;
    s1 = {u, q, p};
    s2 = {q, v, p};
    changed[sub[0]] = changed[sub[1]] = 1;
    ++moved;
  }
  return moved;
}

namespace {

// peel_flat_hull_tets' state: the constrained half-faces
// (constrained_half_faces) and the walks about an edge.
class HullPeeler {
 public:
  HullPeeler(TetMesh& mesh, const std::vector<uint32_t>& hf_sub) : m_(mesh), hf_sub_(hf_sub) {}

  bool kept(HalfFace hf) const {
    return hf != kNoHalfFace && (m_.tflag[hf_tet(hf)] & kTetInside) != 0;
  }

  // Gives t to the exterior if it may go (see peel_flat_hull_tets); true
  // when it went.
  bool try_peel(TetId t) {
    bool hull_face = false;
    for (int i = 0; i < 4; ++i) {
      if (kept(m_.adjacent(make_hf(t, i)))) continue;
      if (constrained(t, i)) return false;  // its subface would lose its last side
      hull_face = true;
    }
    if (!hull_face) return false;
    set_kept(t, false);
    for (int i = 0; i < 4; ++i) {
      const HalfFace hf = m_.adjacent(make_hf(t, i));
      if (kept(hf) && !constrained(hf_tet(hf), hf_face(hf)) && reflex_at(hf)) {
        set_kept(t, true);
        return false;
      }
    }
    return true;
  }

 private:
  void set_kept(TetId t, bool on) {
    m_.tflag[t] &= static_cast<uint8_t>(~(kTetInside | kTetOutside));
    m_.tflag[t] |= on ? kTetInside : kTetOutside;
  }
  bool constrained(TetId t, int i) const { return hf_sub_[make_hf(t, i)] != kNone; }
  // Whether the boundary face hf (of a kept tet, the tet beyond not kept)
  // and an unconstrained boundary face at one of its edges make a reflex
  // angle by more than a numerically flat tet of their four vertices,
  // either face seen against the other's far vertex; every pair at the edge
  // counts, as in validate() (an edge may have more than two boundary faces).
  // True also when the faces about an edge cannot be walked.
  bool reflex_at(HalfFace hf) {
    const TetId u = hf_tet(hf);
    const int i = hf_face(hf);
    const VertexId f[3] = {m_.vertex(u, kFaceVertex[i][0]), m_.vertex(u, kFaceVertex[i][1]),
                           m_.vertex(u, kFaceVertex[i][2])};
    for (int k = 0; k < 3; ++k) {
      const VertexId a = f[k], b = f[(k + 1) % 3], c = f[(k + 2) % 3];
      if (!boundary_faces_about(u, a, b, c)) return true;
      for (HalfFace g : about_) {
        if (g == hf || constrained(hf_tet(g), hf_face(g))) continue;
        const VertexId g_far = third_of(g, a, b);
        if (beyond(hf, g_far) || beyond(g, c)) return true;
      }
    }
    return false;
  }
  // The vertex of half-face hf's face other than a and b.
  VertexId third_of(HalfFace hf, VertexId a, VertexId b) const {
    const TetId t = hf_tet(hf);
    const int i = hf_face(hf);
    for (int k = 0; k < 3; ++k) {
      const VertexId v = m_.vertex(t, kFaceVertex[i][k]);
      if (v != a && v != b) return v;
    }
    return kNone;
  }
  // Whether e lies on the other side of boundary face hf's plane than its
  // kept tet, by more than a numerically flat tet.
  bool beyond(HalfFace hf, VertexId e) const {
    const TetId t = hf_tet(hf);
    const int i = hf_face(hf);
    const double* pa = m_.point(m_.vertex(t, kFaceVertex[i][0]));
    const double* pb = m_.point(m_.vertex(t, kFaceVertex[i][1]));
    const double* pc = m_.point(m_.vertex(t, kFaceVertex[i][2]));
    const int side = pred::orient3d(pa, pb, pc, m_.point(m_.vertex(t, i)));
    const int se = pred::orient3d(pa, pb, pc, m_.point(e));
    return side != 0 && se == -side && std::fabs(volume_ratio(pa, pb, pc, m_.point(e))) > kFlatTetRatio;
  }
  // The boundary faces about edge ab (each as the half-face of its kept
  // tet) into about_, walking once around the edge from tet u, whose face
  // (a, b, c) is the first crossed. False if the walk does not close.
  bool boundary_faces_about(TetId u, VertexId a, VertexId b, VertexId c) {
    about_.clear();
    TetId w = u;
    VertexId prev = c;  // the face of w opposite prev is the next one about ab
    for (int step = 0; step < 4096; ++step) {
      VertexId x = kNone;
      for (int k = 0; k < 4; ++k) {
        const VertexId v = m_.vertex(w, k);
        if (v != a && v != b && v != prev) x = v;
      }
      const int at = m_.index_in_tet(w, prev);
      if (x == kNone || at < 0) return false;
      const HalfFace hf = make_hf(w, at);
      const HalfFace nb = m_.adjacent(hf);
      if (nb == kNoHalfFace) return false;
      const bool kw = (m_.tflag[w] & kTetInside) != 0, kn = kept(nb);
      if (kw && !kn) about_.push_back(hf);
      if (!kw && kn) about_.push_back(nb);
      w = hf_tet(nb), prev = x;
      if (w == u) return true;
    }
    return false;
  }

  std::vector<HalfFace> about_;
  TetMesh& m_;
  const std::vector<uint32_t>& hf_sub_;
};

}  // namespace

size_t peel_flat_hull_tets(TetMesh& mesh, const Subfaces& subfaces, CarveResult& carved,
                           const std::vector<HalfFace>* half_faces) {
  std::vector<TetId> work;
  for (TetId t : carved.tets)
    if (flat_tet(mesh, t)) work.push_back(t);
  if (work.empty()) return 0;
  std::vector<uint32_t> hf_sub;
  std::vector<HalfFace> sub_hf;
  if (half_faces) sub_hf = *half_faces;
  // carve() found every subface a face of this mesh.
  if (!constrained_half_faces(mesh, subfaces, hf_sub, sub_hf).ok()) return 0;
  HullPeeler peeler(mesh, hf_sub);
  // Last in, first out: a removal queues the flat tets it exposes.
  std::reverse(work.begin(), work.end());
  size_t peeled = 0;
  while (!work.empty()) {
    const TetId t = work.back();
    work.pop_back();
    if (!(mesh.tflag[t] & kTetInside) || !peeler.try_peel(t)) continue;
    ++peeled;
    for (int i = 0; i < 4; ++i) {
      const HalfFace hf = mesh.adjacent(make_hf(t, i));
      if (peeler.kept(hf) && flat_tet(mesh, hf_tet(hf))) work.push_back(hf_tet(hf));
    }
  }
  if (peeled == 0) return 0;
  size_t n = 0;
  for (size_t k = 0; k < carved.tets.size(); ++k)
    if (mesh.tflag[carved.tets[k]] & kTetInside)
      carved.tets[n] = carved.tets[k], carved.attribute[n] = carved.attribute[k], ++n;
  carved.tets.resize(n);
  carved.attribute.resize(n);
  return peeled;
}

}  // namespace cdt3d
