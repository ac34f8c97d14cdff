// Index-based tetrahedral mesh with half-face adjacency and ghost tets
// (STYLE.md §8). Every algorithm step works on this structure. Adjacency
// (tadj) and the vertex-to-tet map (vtet) are written only by this file's
// methods (glue, link_one_way, set_vertex_tet, replace_tets, compact) and by
// the point inserter (delaunay.cpp, whose cavity filling writes tadj in bulk
// for speed); cavity commits (cavity.cpp), vertex removal (degeneracy.cpp)
// and the flips (flat_flips.cpp) replace tets through replace_tets. A step
// that needs a new mesh operation adds it here. The steps read the mesh
// through the accessors (vertex, tet_vertices, opposite, adjacent, neighbor,
// ring_around_edge), whose preconditions are debug asserts.
//
// Invariants (checked by check_mesh):
//  * Vertex v has coordinates coords[3v..3v+2].
//  * Tet t has vertices tv[4t..4t+3]; face i is the face opposite tv[4t+i].
//  * Orientation: every real tet is positive, orient3d(v0, v1, v2, v3) > 0 in
//    the predicates' convention (Shewchuk: v3 lies below the plane of v0 v1 v2
//    when those are seen counterclockwise from above). Equivalently, face i
//    listed as tv[kFaceVertex[i][0..2]] is counterclockwise seen from outside
//    the tet, and insphere(v0, v1, v2, v3, p) > 0 means p inside.
//  * Ghost tets: the virtual vertex kInfinite closes the hull, so every face
//    has two sides. A ghost tet always stores kInfinite at position 3; its
//    face 3 is a hull face (a, b, c), counterclockwise seen from inside the
//    hull, and a point p is strictly beyond that hull face when
//    orient3d(a, b, c, p) > 0 (kInfinite behaves like a point beyond it).
//  * tadj[4t+i] is the half-face 4t'+j on the other side of face i of t;
//    tadj[tadj[hf]] == hf.
//  * vtet[v] is a live tet incident to v (a real one whenever possible), or
//    kNone for vertices that are not in the triangulation (e.g. duplicates).
//  * Dead tets have kTetDead set and sit on the free list; alloc_tet reuses
//    them first. compact() removes them and renumbers.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <array>
#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace cdt3d {

using TetId = uint32_t;
using HalfFace = uint32_t;  ///< 4 * tet + face index

/// The virtual vertex at infinity of ghost tets. Has no coordinates.
inline constexpr VertexId kInfinite = 0xfffffffeu;

/// tadj value of a face with nothing beyond it: only in meshes of a carved
/// domain without ghost tets (quality refinement, refine.cpp), where the
/// domain boundary is open; every other mesh closes the hull with ghosts.
inline constexpr HalfFace kNoHalfFace = 0xffffffffu;

inline constexpr TetId hf_tet(HalfFace hf) { return hf >> 2; }
inline constexpr int hf_face(HalfFace hf) { return static_cast<int>(hf & 3u); }
inline constexpr HalfFace make_hf(TetId t, int i) { return (t << 2) | static_cast<uint32_t>(i); }

/// kFaceVertex[i]: positions of the vertices of face i (opposite position i),
/// counterclockwise seen from outside the tet. (f0, f1, f2, i) is an even
/// permutation of (0, 1, 2, 3), so orient3d(f0, f1, f2, i) == orient3d(0, 1, 2, 3).
inline constexpr int kFaceVertex[4][3] = {{1, 3, 2}, {0, 2, 3}, {0, 3, 1}, {0, 1, 2}};

/// Per-tet flag bits (tflag). Later phases own the bits they define.
enum TetFlag : uint8_t {
  kTetDead = 1u << 0,
  kTetInside = 1u << 1,   ///< inside the domain (carving)
  kTetOutside = 1u << 2,  ///< outside the domain (carving)
  kTetUser = 1u << 3,     ///< first bit free for the phases (up to 1 << 5)
  // Transient marks of PointInserter; always clear between calls.
  kTetInCavity = 1u << 6,
  kTetTested = 1u << 7,
};

/// Per-vertex kind (vkind).
enum VertexKind : uint8_t {
  kVertexInput = 0,        ///< input point, in the triangulation
  kVertexDuplicate = 1,    ///< same coordinates as an earlier vertex; not inserted
  kVertexNotInserted = 2,  ///< has coordinates but is not (yet) in the triangulation
  kVertexSteiner = 3,      ///< added by a later phase (phases may refine the kind)
};

/// Index-based tetrahedral mesh. Plain data with small helpers; see the
/// invariants at the top of this file.
struct TetMesh {
  std::vector<double> coords;    ///< 3 per vertex
  std::vector<uint8_t> vkind;    ///< per vertex, VertexKind
  std::vector<TetId> vtet;       ///< per vertex: one incident live tet, or kNone
  std::vector<VertexId> tv;      ///< 4 per tet slot
  std::vector<HalfFace> tadj;    ///< 4 per tet slot: mirror half-face
  std::vector<uint32_t> tstamp;  ///< per tet slot: visit stamp (compare to an epoch)
  std::vector<uint8_t> tflag;    ///< per tet slot: TetFlag bits
  std::vector<TetId> free_tets;  ///< dead slots, reused last-in first-out
  uint32_t epoch = 0;            ///< last epoch handed out by next_epoch()
  size_t live_tets = 0;          ///< real + ghost tets alive
  std::vector<TetId> scratch;    ///< reused by find_edge/find_face (no allocation per query)

  // --- sizes -------------------------------------------------------------
  size_t num_vertices() const { return coords.size() / 3; }
  size_t num_tet_slots() const { return tv.size() / 4; }
  /// Counts by scanning (O(slots)).
  size_t num_real_tets() const;
  size_t num_ghost_tets() const;  ///< == number of hull faces

  // --- access ------------------------------------------------------------
  // The preconditions are checked by assert(), compiled in Debug builds only
  // (these accessors sit in the inner loops of every step).
  const double* point(VertexId v) const {
    assert(v < num_vertices());
    return &coords[3 * static_cast<size_t>(v)];
  }
  VertexId vertex(TetId t, int i) const {
    assert(t < num_tet_slots() && i >= 0 && i < 4);
    return tv[4 * static_cast<size_t>(t) + i];
  }
  /// The four vertex ids of tet t, contiguous.
  const VertexId* tet_vertices(TetId t) const {
    assert(t < num_tet_slots());
    return &tv[4 * static_cast<size_t>(t)];
  }
  /// The vertex of hf's tet opposite its face hf.
  VertexId opposite(HalfFace hf) const {
    assert(hf < tv.size());
    return tv[hf];
  }
  HalfFace adjacent(HalfFace hf) const {
    assert(hf < tadj.size());
    return tadj[hf];
  }
  TetId neighbor(TetId t, int i) const {
    assert(t < num_tet_slots() && i >= 0 && i < 4);
    return hf_tet(tadj[4 * static_cast<size_t>(t) + i]);
  }
  bool is_dead(TetId t) const { return (tflag[t] & kTetDead) != 0; }
  bool is_ghost(TetId t) const { return tv[4 * static_cast<size_t>(t) + 3] == kInfinite; }
  /// Position (0..3) of v in t, or -1.
  int index_in_tet(TetId t, VertexId v) const {
    const VertexId* p = &tv[4 * static_cast<size_t>(t)];
    return p[0] == v ? 0 : p[1] == v ? 1 : p[2] == v ? 2 : p[3] == v ? 3 : -1;
  }

  // --- construction ------------------------------------------------------
  void clear();
  /// Reserves room for `vertices` vertices and `tets` tet slots.
  void reserve(size_t vertices, size_t tets);
  /// Appends a vertex (kind kVertexNotInserted until inserted) and returns its id.
  VertexId add_vertex(const double* xyz, uint8_t kind = kVertexNotInserted);
  /// A live tet slot (reused from the free list, else appended). Its vertices
  /// and adjacency are unset; flags cleared. Grows capacity by 1.25x, not 2x,
  /// to keep the peak memory of large meshes low.
  TetId alloc_tet();
  /// Marks t dead and puts it on the free list.
  void free_tet(TetId t);
  void set_tet(TetId t, VertexId a, VertexId b, VertexId c, VertexId d) {
    VertexId* p = &tv[4 * static_cast<size_t>(t)];
    p[0] = a, p[1] = b, p[2] = c, p[3] = d;
  }
  /// Makes a and b mirror half-faces of each other.
  void glue(HalfFace a, HalfFace b) {
    assert(a < tadj.size() && b < tadj.size() && hf_tet(a) != hf_tet(b));
    tadj[a] = b, tadj[b] = a;
  }
  /// Points half-face a at b without the mirror link: only for scratch
  /// meshes whose open faces all lead to one placeholder tet (a cavity's
  /// own triangulation, cavity.cpp); check_mesh rejects it elsewhere.
  void link_one_way(HalfFace a, HalfFace b) {
    assert(a < tadj.size() && b < tadj.size());
    tadj[a] = b;
  }
  /// Marks half-face a as having nothing beyond it (kNoHalfFace): only for
  /// meshes of a carved domain without ghosts (refine.cpp).
  void open_face(HalfFace a) {
    assert(a < tadj.size());
    tadj[a] = kNoHalfFace;
  }
  /// Records t as the incident tet of vertex v (kNone: v left the mesh).
  void set_vertex_tet(VertexId v, TetId t) {
    assert(v < vtet.size());
    assert(t == kNone || (t < num_tet_slots() && !is_dead(t) && index_in_tet(t, v) >= 0));
    vtet[v] = t;
  }
  /// Replaces the live tets `old` (n_old of them) by the tets `fresh`
  /// (n_fresh; real ones positively oriented, ghost ones with kInfinite at
  /// position 3) that fill the same region. Faces are matched by their
  /// vertices: every face on the boundary of `old` must be a face of exactly
  /// one fresh tet, every other fresh face of exactly two. Returns false,
  /// changing nothing, when they do not match (a caller's bug). Otherwise
  /// rewires adjacency; fresh tet j takes slot old[j] (then alloc_tet's),
  /// leftover old slots are freed last first (the next alloc_tet calls get
  /// them in the order of `old`), and fresh tets get tflag 0. Every vertex of
  /// a real fresh tet points at the last one that has it (vtet); the others
  /// are the caller's: a vertex only on fresh ghost tets, or one that left.
  /// A boundary face of `old` that is open (kNoHalfFace) stays open.
  /// created (if given) receives the fresh tets' ids. Step 4's cavity commit
  /// (cavity.cpp), vertex removal (degeneracy.cpp), the flips of step 4's
  /// output (flat_flips.cpp) and of the improvement pass (improve.cpp) are
  /// built on it.
  bool replace_tets(const TetId* old, size_t n_old, const std::array<VertexId, 4>* fresh,
                    size_t n_fresh, std::vector<TetId>* created = nullptr);

  // --- marks -------------------------------------------------------------
  /// A fresh epoch: every tet stamp differs from it until stamped.
  uint32_t next_epoch();
  bool stamped(TetId t, uint32_t e) const { return tstamp[t] == e; }
  void stamp(TetId t, uint32_t e) { tstamp[t] = e; }

  // --- queries for the phases -------------------------------------------
  /// Every live tet incident to vertex v (ghost tets included), in a
  /// deterministic breadth-first order from vtet[v]. Uses the stamps.
  void vertex_star(VertexId v, std::vector<TetId>& out);
  /// Vertices adjacent to v by an edge (kInfinite excluded), sorted ascending.
  void vertex_neighbors(VertexId v, std::vector<VertexId>& out);
  /// A live tet having both a and b as vertices (so ab is a mesh edge), or
  /// kNone. Walks the star of a; b may be kInfinite (hull vertex test).
  TetId find_edge(VertexId a, VertexId b);
  /// A live tet having face {a, b, c} and the position of the fourth vertex
  /// as half-face, or kNone.
  HalfFace find_face(VertexId a, VertexId b, VertexId c);

  /// The tets around edge pq, which tet t0 contains, in the order of a walk
  /// across the faces through pq: ring[k] is entered across its face that
  /// holds arrive[k] (besides p and q); ring[0] = t0, and arrive[0] is the
  /// first vertex of t0 other than p and q. Ghost tets are part of the ring
  /// (arrive may be kInfinite). Returns nullptr, or why the walk failed: the
  /// ring broke (an invariant is violated), grew past max_len tets, or did
  /// not close.
  const char* ring_around_edge(TetId t0, VertexId p, VertexId q, size_t max_len,
                               std::vector<TetId>& ring, std::vector<VertexId>& arrive) const;

  /// Removes dead slots, renumbering tets (order of survivors kept) and
  /// fixing tadj and vtet. Empties the free list.
  void compact();
  /// Real tets as 4 vertex ids each (positive orientation), in slot order.
  void real_tets(std::vector<uint32_t>& out) const;
  /// Hull faces (finite faces of ghost tets), 3 vertex ids each,
  /// counterclockwise seen from outside the hull.
  void hull_faces(std::vector<uint32_t>& out) const;
};

/// Structural and geometric invariants (see the top of this file), with exact
/// predicates: adjacency symmetric and consistent with the vertex lists, every
/// real tet positively oriented, ghost tets well formed, hull faces facing
/// away from the real tets, vtet valid, free list consistent, live_tets right.
/// Returns ErrorCode::Internal with a message naming the first violation.
Status check_mesh(const TetMesh& mesh);

/// Every face between two real tets is locally Delaunay under the symbolic
/// perturbation (insphere_sos < 0 for the opposite vertex), and every edge of
/// the hull between coplanar hull faces is locally Delaunay in that plane
/// (incircle_coplanar_sos). With check_mesh this implies that the real tets
/// form the (SoS-unique) Delaunay tetrahedralization of the vertices.
Status check_delaunay(const TetMesh& mesh);

}  // namespace cdt3d
