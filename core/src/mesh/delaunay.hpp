// Step 1 (Si & Gärtner 2005 §4, step (1)): the Delaunay tetrahedralization of
// a point set, by incremental Bowyer–Watson insertion in BRIO + Hilbert order.
// Degenerate (co-spherical, coplanar) configurations are resolved by the
// symbolic perturbation of the predicates (insphere_sos and
// incircle_coplanar_sos, ordered by vertex id), so the result is the unique
// Delaunay tetrahedralization of the perturbed points, whatever the insertion
// order. Later steps reuse PointInserter to add Steiner points.
#pragma once

#include <cdt3d/cdt3d.hpp>
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "predicates.hpp"
#include "spatial_sort.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

inline constexpr uint64_t kDefaultDelaunaySeed = 0x6364743364656c61ull;

/// From this many points the bulk build inserts its later rounds on two
/// threads (DelaunayOptions::threads) and numbers its tets canonically, on
/// one thread too. Below it a second thread saves nothing on a 2-core
/// machine: two threads of insertions fall well short of twice one
/// thread's throughput, and the self-intersection test is better company
/// for step 1 there.
inline constexpr size_t kMinTwoThreadDelaunayPoints = 20000;

struct DelaunayOptions {
  uint64_t seed = kDefaultDelaunaySeed;  ///< BRIO shuffle and walk tie-breaking
  bool spatial_sort = true;              ///< false: insert in the given order (for tests)
  /// Insert the later BRIO rounds on two threads where there are threads
  /// (beside.hpp). The result is the same either way: the perturbed
  /// tetrahedralization is unique and the build numbers its tets canonically.
  bool threads = false;
  /// Number the tets of a set of kMinTwoThreadDelaunayPoints or more
  /// canonically (always with `threads`): then the mesh depends on the
  /// points alone, not on the order of insertion nor on the threads. Costs
  /// a pass of random memory accesses, which the pipeline gets back from the memory locality
  /// of the order (tets by their newest vertex); off only where the order of
  /// the tets does not matter (`cdt3d delaunay --one-thread`).
  bool canonical = true;
};

struct DelaunayStats {
  size_t points = 0;         ///< input points
  size_t duplicates = 0;     ///< points equal to an earlier inserted point
  size_t vertices = 0;       ///< vertices in the triangulation
  size_t tets = 0;           ///< real tets
  size_t hull_faces = 0;     ///< ghost tets
  double ms_sort = 0;        ///< BRIO + Hilbert ordering
  double ms_insert = 0;      ///< initial tet + insertions
  uint64_t walk_steps = 0;   ///< tets visited by point location
  uint64_t cavity_tets = 0;  ///< tets deleted by insertions
  size_t points_beside = 0;  ///< points inserted on the second thread (DelaunayOptions::threads)
};

/// Delaunay tetrahedralization of points coords[3i..3i+2], i < n. Resets
/// `mesh`; vertex i of the mesh is input point i. A point equal to an earlier
/// inserted one is a duplicate: it keeps its vertex slot with kind
/// kVertexDuplicate and vtet kNone, and input_to_vertex (if given, size n)
/// maps it to the vertex it merged into (identity for the others).
/// Errors: TooFewPoints (< 4 distinct points), Collinear, Coplanar,
/// NonFinite / CoordinateRange (bad coordinates; `vertex` names the point),
/// TooLarge (n >= 2^30), Internal (a bug; message says where).
Status delaunay_tetrahedralize(TetMesh& mesh, const double* coords, size_t n,
                               std::vector<VertexId>* input_to_vertex = nullptr,
                               DelaunayStats* stats = nullptr, const DelaunayOptions& options = {});

/// Same, for a subset of the vertices already in mesh.coords (e.g. the
/// vertices of a cavity, step 4): removes all tets, then triangulates only
/// `vertices`, so the perturbation uses the global vertex ids. Vertices not
/// listed get kind kVertexNotInserted. to_vertex[k] is the vertex that
/// vertices[k] ended up as (itself unless duplicate).
Status delaunay_tetrahedralize_vertices(TetMesh& mesh, const std::vector<VertexId>& vertices,
                                        std::vector<VertexId>* to_vertex = nullptr,
                                        DelaunayStats* stats = nullptr,
                                        const DelaunayOptions& options = {});

// ---------------------------------------------------------------------------
// Point location (locate.cpp)
// ---------------------------------------------------------------------------

enum class LocateKind {
  InTet,        ///< tet is a real tet whose closure contains p
  OnVertex,     ///< p equals vertex `vertex` (a vertex of tet)
  OutsideHull,  ///< tet is a ghost tet whose hull face p is strictly beyond
  Failed,       ///< empty mesh or no progress (a bug or a broken mesh)
};

struct Location {
  LocateKind kind = LocateKind::Failed;
  TetId tet = kNone;
  VertexId vertex = kNone;
  uint32_t steps = 0;  ///< tets visited
};

/// Visibility walk from `hint` (any live tet; a ghost hint starts at its real
/// neighbour; a dead or kNone hint starts at an arbitrary live tet): crosses a
/// face whenever p is strictly beyond it, testing the faces in an order
/// rotated by `rng` (deterministic), never going back through the face it
/// entered by. Exact orientation tests. Works on any tetrahedralization of
/// the hull, Delaunay or not. `box`, when given, holds pred::box_bounds of a
/// box around p and every vertex of the mesh (orient3d_in_box).
Location locate_point(const TetMesh& mesh, const double* p, TetId hint, Rng& rng,
                      const pred::BoxBounds* box = nullptr);

/// locate_point's walk from the real tet `t`, asking enter(from, to) before
/// each step (false: the walk stops, kind Failed). The two-thread build
/// locks each tet there before it reads it.
template <class Enter>
Location walk_to_point(const TetMesh& mesh, const double* p, TetId t, Rng& rng, Enter&& enter,
                       const pred::BoxBounds* box = nullptr) {
  Location loc;
  TetId came_from = kNone;
  // A walk in a triangulation visits each tet at most once with probability
  // 1 for a stochastic face order; the cap only guards against broken meshes.
  const uint64_t cap = 64 + 4 * static_cast<uint64_t>(mesh.num_tet_slots());
  const VertexId* tv = mesh.tv.data();
  for (uint64_t step = 0; step < cap; ++step) {
    ++loc.steps;
    const VertexId* w = tv + 4 * static_cast<size_t>(t);
    const uint32_t start = static_cast<uint32_t>(rng.next() >> 62);
    TetId next = kNone;
    for (uint32_t k = 0; k < 4; ++k) {
      const int i = static_cast<int>((start + k) & 3u);
      const TetId n = mesh.neighbor(t, i);
      if (n == came_from) continue;  // p is strictly on our side of that face
      const double* a = mesh.point(w[kFaceVertex[i][0]]);
      const double* b = mesh.point(w[kFaceVertex[i][1]]);
      const double* c = mesh.point(w[kFaceVertex[i][2]]);
      const int o = box ? pred::orient3d_in_box(a, b, c, p, *box) : pred::orient3d(a, b, c, p);
      if (o < 0) {  // p strictly beyond face i
        next = n;
        break;
      }
    }
    if (next == kNone) {  // p in the closed tet t
      loc.tet = t;
      loc.kind = LocateKind::InTet;
      for (int i = 0; i < 4; ++i) {
        const double* q = mesh.point(w[i]);
        if (q[0] == p[0] && q[1] == p[1] && q[2] == p[2]) {
          loc.kind = LocateKind::OnVertex;
          loc.vertex = w[i];
        }
      }
      return loc;
    }
    if (!enter(t, next)) return loc;  // Failed
    if (mesh.is_ghost(next)) {  // left the hull through its face 3
      loc.tet = next;
      loc.kind = LocateKind::OutsideHull;
      return loc;
    }
    came_from = t;
    t = next;
  }
  return loc;  // Failed
}

// ---------------------------------------------------------------------------
// Insertion of one point (Bowyer–Watson), for step 1 and later steps
// ---------------------------------------------------------------------------

struct InsertResult {
  VertexId vertex = kNone;  ///< vertex at the point (the existing one if duplicate)
  bool duplicate = false;   ///< the point coincided with an existing vertex
  TetId located = kNone;    ///< tet found by the walk
  /// With PointInserter::set_reject_flat: the insertion would have created a
  /// numerically flat tet and was not done (the mesh is unchanged; a vertex
  /// appended by insert_point is removed again).
  bool rejected = false;
};

/// How PointInserter::probe() walks and decides ties.
struct ProbeOptions {
  /// The random face order of the walk (nullptr: the inserter's own). A
  /// caller passes its own so that its probes do not change where the
  /// inserter's later walks go.
  Rng* walk = nullptr;
  /// Give up (probe() returns false) at a conflict test that is an exact tie
  /// (conflict_sign() == 0) instead of deciding it by the perturbation: then
  /// the cavity is the same for the exact and the perturbed point.
  bool fail_on_tie = false;
};

/// Inserts points into a Delaunay (under SoS) tetrahedralization: walk to a
/// tet in conflict, grow the cavity of tets whose circumsphere contains the
/// point (breadth-first, marked with the transient tflag bits kTetInCavity /
/// kTetTested), then cone its boundary to the point. New tets reuse the
/// cavity's slots first; their internal adjacency is matched through a small
/// table indexed by the boundary edges' local ids. Reuse one inserter for many
/// points (it keeps its buffers). Precondition: the mesh is a Delaunay
/// tetrahedralization under the perturbation (step 1-3 meshes); on a
/// constrained, non-Delaunay mesh the cavity may not be star-shaped.
/// New tets get tflag 0 (phase bits of the replaced tets are not carried).
class PointInserter {
 public:
  explicit PointInserter(TetMesh& mesh, uint64_t seed = kDefaultDelaunaySeed);

  /// Inserts vertex v, which has coordinates in the mesh but is not in the
  /// triangulation. A duplicate gets kind kVertexDuplicate and vtet kNone.
  Status insert_vertex(VertexId v, TetId hint, InsertResult* result = nullptr);

  /// Appends `xyz` as a new vertex of `kind` and inserts it. A point equal to
  /// an existing vertex adds nothing and reports that vertex as duplicate.
  Status insert_point(const double* xyz, TetId hint, uint8_t kind = kVertexSteiner,
                      InsertResult* result = nullptr);

  /// What inserting `xyz` would do, without doing it: fills `faces` with the
  /// boundary faces of its cavity, each as (a, b, c, beyond): (a, b, c)
  /// counterclockwise seen from outside the cavity (the new tet would be
  /// (a, b, c, point)) and `beyond` the vertex of the tet on the other side;
  /// kInfinite may appear. False when the point equals a vertex, the walk
  /// fails, or (fail_on_tie) a conflict test ties. The point is perturbed as
  /// a new vertex (the largest id); not available with set_sos_ids.
  bool probe(const double* xyz, TetId hint, std::vector<std::array<VertexId, 4>>& faces,
             const ProbeOptions& options = {});

  /// Tets created by the last insertion (real and ghost). Their slots may
  /// include ids from removed_tets(), which were reused.
  const std::vector<TetId>& new_tets() const { return new_tets_; }
  /// Tet slots deleted by the last insertion (before reuse).
  const std::vector<TetId>& removed_tets() const { return cavity_; }
  /// A real tet created by the last insertion: the best hint for the next.
  TetId last_tet() const { return last_tet_; }

  /// Vertex ids to order the symbolic perturbation by, indexed by mesh
  /// vertex id (nullptr: the mesh ids themselves). The bulk build numbers
  /// vertices in insertion order for memory locality and perturbs by the
  /// caller's ids through this table. The table must outlive the inserter.
  void set_sos_ids(const VertexId* ids) { sos_id_ = ids; }

  /// When on, an insertion that would create a numerically flat real tet
  /// (geometry.hpp) is not done and reports InsertResult::rejected. Every tet
  /// an insertion creates has the new vertex, so a caller that tries another
  /// position (segment recovery moves its split point) keeps the mesh free of
  /// flat tets.
  void set_reject_flat(bool on) { reject_flat_ = on; }

  /// Promise that every point inserted from now on lies exactly on the
  /// circumsphere of every real tet (the vertices of one cell of the
  /// Delaunay subdivision, sos_order.cpp): each insphere test is then a tie,
  /// so the conflict test goes straight to the perturbation instead of
  /// evaluating an exact zero first. Wrong answers if the promise is false.
  void set_cospherical(bool on) { cospherical_ = on; }

  /// Promise that every point of the mesh, inserted or to be inserted, passes
  /// pred::small_integer_points (a grid model's vertices, say): the conflict
  /// tests then evaluate their determinants in doubles, exactly, with no
  /// filter and no exact stage (co-spherical grid points made a third of
  /// their Delaunay tetrahedralization's instructions undecided filter
  /// calls). Wrong answers if the promise is false.
  void set_small_integers(bool on) { small_integers_ = on; }
  /// pred::box_bounds of a box around every vertex of the mesh (the points
  /// of one Delaunay tetrahedralization, say; zero bounds for none): its
  /// walks and conflict tests then try those static bounds first
  /// (pred::*_in_box). insert_point, insert_vertex and probe drop them at
  /// the first point outside the box; a vertex that enters the mesh by any
  /// other way must lie inside.
  void set_box_bounds(const pred::BoxBounds& bounds) { box_ = bounds; }
  const pred::BoxBounds& box_bounds() const { return box_; }
  /// The perturbation ids, co-spherical mode, small-integer promise and
  /// static bounds of `other`, for a second inserter on the same points.
  void take_settings(const PointInserter& other) {
    sos_id_ = other.sos_id_, cospherical_ = other.cospherical_;
    small_integers_ = other.small_integers_, box_ = other.box_;
  }

  uint64_t walk_steps = 0;   ///< statistics, cumulative
  uint64_t cavity_tets = 0;  ///< statistics, cumulative

  // The two-thread bulk build (delaunay.cpp) only. With a Shared part set,
  // the inserter takes new tet slots from that part and locks every tet it
  // reads or writes; a point that meets a tet the other thread holds (or
  // anything else unexpected) is left for the single-threaded pass.
  struct Shared;
  enum class Attempt { Inserted, Deferred, Failed };
  void share(Shared* part) { shared_ = part; }
  void set_hint(TetId t) { last_tet_ = t; }
  Attempt insert_vertex_shared(VertexId v);

 private:
  struct BoundaryFace {
    VertexId a, b, c;     ///< counterclockwise seen from outside the cavity
    HalfFace outside;     ///< mirror half-face in the tet beyond
    uint32_t la, lb, lc;  ///< local ids of a, b, c on the cavity boundary
  };
  struct Pending {
    HalfFace hf;       ///< face through the new vertex
    uint32_t reverse;  ///< dense-table index of its edge, reversed
  };
  struct EdgeRec {
    uint32_t lo, hi;
    HalfFace hf;
  };

  bool in_conflict(TetId t, const double* p, VertexId v) const;
  bool cone_has_flat_tet(const double* p) const;
  void abandon_cavity();
  // The steps of insert_vertex: Bowyer-Watson's cavity of p from t0, the
  // cone of its boundary to v, then vtet of the cavity's vertices.
  void grow_cavity(TetId t0, const double* p, VertexId v) { grow_cavity_impl<false>(t0, p, v); }
  // kShared: locks each tet before reading it; false when one is held by
  // the other thread (the cavity is then abandoned, not filled).
  template <bool kShared>
  bool grow_cavity_impl(TetId t0, const double* p, VertexId v);
  TetId alloc_slot();
  void free_slot(TetId t);
  bool lock(TetId t);
  void unlock_all();
  bool start_tet_shared(TetId& t);
  const pred::BoxBounds* box_at(const double* p);
  bool locate_shared(const double* p, TetId& t, LocateKind& kind);
  Status fill_cavity(VertexId v);
  void point_vertices_to_new_tets();
  void point_vertices_shared();
  uint32_t local_id(VertexId x);
  VertexId sos(VertexId v) const { return sos_id_ && v != kInfinite ? sos_id_[v] : v; }

  TetMesh& mesh_;
  const VertexId* sos_id_ = nullptr;
  Shared* shared_ = nullptr;
  bool reject_flat_ = false;
  bool cospherical_ = false;
  bool small_integers_ = false;
  pred::BoxBounds box_;  ///< zero bounds: no box
  Rng rng_;
  TetId last_tet_ = kNone;
  std::vector<TetId> cavity_;
  std::vector<BoundaryFace> boundary_;
  std::vector<TetId> new_tets_;
  std::vector<Pending> pending_;
  // Boundary vertices get small local ids (0 none, 1 kInfinite, then 2..)
  // so that new tets sharing a boundary edge meet in a small dense table.
  std::vector<uint32_t> vlocal_;
  std::vector<VertexId> locals_;
  // Written before read (each directed boundary edge by its own new tet,
  // read by its partner), so left uninitialized: zeroing it would cost more
  // than a small tetrahedralization's whole work.
  std::unique_ptr<HalfFace[]> dense_;
  std::vector<EdgeRec> recs_;
};

/// Delaunay tetrahedralizations of many small point sets in a row (the cells
/// of the perturbation-order search, sos_order.cpp): one work mesh and one
/// inserter serve every call, so a set of a few points costs its insertions,
/// not the allocations of a fresh delaunay_tetrahedralize. Points go in in
/// the given order, perturbed by their index; vertex i is point i, and the
/// result is the same as delaunay_tetrahedralize's with spatial_sort off.
class SmallDelaunay {
 public:
  SmallDelaunay();
  SmallDelaunay(const SmallDelaunay&) = delete;
  SmallDelaunay& operator=(const SmallDelaunay&) = delete;
  /// Tetrahedralizes points coords[3i..3i+2], i < n, replacing the last
  /// result. Errors as delaunay_tetrahedralize's (TooFewPoints, Coplanar...).
  /// `cospherical`: the caller knows the points lie exactly on one sphere
  /// (PointInserter::set_cospherical), which saves the exact zero of every
  /// insphere test.
  Status build(const double* coords, size_t n, bool cospherical = false);
  const TetMesh& mesh() const { return mesh_; }
  /// The last result, for queries that use the stamps (find_face).
  TetMesh& mesh() { return mesh_; }

 private:
  TetMesh mesh_;
  PointInserter inserter_;
};

/// The exact, unperturbed sign of the test by which Bowyer–Watson insertion
/// takes tet t into the cavity of point p: insphere for a real tet; for a
/// ghost tet, orient3d against its hull face (positive beyond it), and in
/// the face's plane the incircle test. Positive: in conflict; 0: a tie, which
/// PointInserter decides by the perturbation.
int conflict_sign(const TetMesh& mesh, TetId t, const double* p);

/// One-shot convenience: inserts `xyz` (as a new vertex of kind
/// kVertexSteiner unless duplicate) starting the walk at `hint`; fills
/// *new_tets with the created tets. For many points keep a PointInserter.
Status insert_point(TetMesh& mesh, const double* xyz, TetId hint, InsertResult* result,
                    std::vector<TetId>* new_tets = nullptr);

// ---------------------------------------------------------------------------
// Reading and writing point files for the CLI (delaunay_io.cpp)
// ---------------------------------------------------------------------------

/// Points of a TetGen .node text: "<n> [dim=3] [#attributes] [#markers]" then
/// n records "<index> <x> <y> <z> [attributes] [marker]"; '#' starts a
/// comment. Indices start at 0 or 1 (*first_index gets the first one) and
/// are consecutive; points are kept in file order, duplicates included.
/// Errors are the PLC readers' (io/read_common.hpp) and carry the 1-based line.
Status parse_node_points(const char* text, size_t size, const std::string& file_name,
                         std::vector<double>& coords, int* first_index = nullptr);
Status read_node_points_file(const std::string& path, std::vector<double>& coords,
                             int* first_index = nullptr);

/// Writes PREFIX.node (every vertex of the mesh, duplicates included, so
/// numbering equals the input order) and PREFIX.ele (real tets), TetGen
/// plain format numbered from 1 like TetGen's default output, each tet in
/// TetGen's orientation ((b - a) x (c - a) . (d - a) > 0, i.e. the last two
/// vertices of TetMesh's order swapped).
Status write_node_ele(const TetMesh& mesh, const std::string& prefix);

}  // namespace cdt3d
