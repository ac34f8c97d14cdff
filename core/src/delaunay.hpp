// Step 1 (Si & Gärtner 2005 §4, step (1)): the Delaunay tetrahedralization of
// a point set, by incremental Bowyer–Watson insertion in BRIO + Hilbert order.
// Degenerate (co-spherical, coplanar) configurations are resolved by the
// symbolic perturbation of the predicates (insphere_sos and
// incircle_coplanar_sos, ordered by vertex id), so the result is the unique
// Delaunay tetrahedralization of the perturbed points, whatever the insertion
// order. Later steps reuse PointInserter to add Steiner points.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "predicates.hpp"
#include "spatial_sort.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

inline constexpr uint64_t kDefaultDelaunaySeed = 0x6364743364656c61ull;

struct DelaunayOptions {
  uint64_t seed = kDefaultDelaunaySeed;  ///< BRIO shuffle and walk tie-breaking
  bool spatial_sort = true;  ///< false: insert in the given order (for tests)
};

struct DelaunayStats {
  size_t points = 0;      ///< input points
  size_t duplicates = 0;  ///< points equal to an earlier inserted point
  size_t vertices = 0;    ///< vertices in the triangulation
  size_t tets = 0;        ///< real tets
  size_t hull_faces = 0;  ///< ghost tets
  double ms_sort = 0;     ///< BRIO + Hilbert ordering
  double ms_insert = 0;   ///< initial tet + insertions
  uint64_t walk_steps = 0;    ///< tets visited by point location
  uint64_t cavity_tets = 0;   ///< tets deleted by insertions
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
                               DelaunayStats* stats = nullptr,
                               const DelaunayOptions& options = {});

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
/// the hull, Delaunay or not.
Location locate_point(const TetMesh& mesh, const double* p, TetId hint, Rng& rng);

// ---------------------------------------------------------------------------
// Insertion of one point (Bowyer–Watson), for step 1 and later steps
// ---------------------------------------------------------------------------

struct InsertResult {
  VertexId vertex = kNone;  ///< vertex at the point (the existing one if duplicate)
  bool duplicate = false;   ///< the point coincided with an existing vertex
  TetId located = kNone;    ///< tet found by the walk
};

/// Inserts points into a Delaunay (under SoS) tetrahedralization: walk to a
/// tet in conflict, grow the cavity of tets whose circumsphere contains the
/// point (breadth-first with stamps), then cone its boundary to the point.
/// New tets reuse the cavity's slots first; their internal adjacency is
/// matched through a small table indexed by the boundary edges' local ids. Reuse one inserter
/// for many points (it keeps its buffers). The mesh must be a Delaunay
/// tetrahedralization under the perturbation for the result to be one.
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

  uint64_t walk_steps = 0;   ///< statistics, cumulative
  uint64_t cavity_tets = 0;  ///< statistics, cumulative

 private:
  struct BoundaryFace {
    VertexId a, b, c;  ///< counterclockwise seen from outside the cavity
    HalfFace outside;  ///< mirror half-face in the tet beyond
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
  uint32_t local_id(VertexId x);
  VertexId sos(VertexId v) const { return sos_id_ && v != kInfinite ? sos_id_[v] : v; }

  TetMesh& mesh_;
  const VertexId* sos_id_ = nullptr;
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
  std::vector<HalfFace> dense_;
  std::vector<EdgeRec> recs_;
};

/// One-shot convenience: inserts `xyz` (as a new vertex of kind
/// kVertexSteiner unless duplicate) starting the walk at `hint`; fills
/// *new_tets with the created tets. For many points keep a PointInserter.
Status insert_point(TetMesh& mesh, const double* xyz, TetId hint, InsertResult* result,
                    std::vector<TetId>* new_tets = nullptr);

// ---------------------------------------------------------------------------
// Reading and writing point files for the CLI (delaunay_io.cpp)
// ---------------------------------------------------------------------------

/// Points of a TetGen .node text: "<n> <dim=3> <#attributes> <#markers>" then
/// n lines "<index> <x> <y> <z> [attributes] [marker]"; '#' starts a comment.
/// Indices may start at 0 or 1 (*first_index gets the first one); points are
/// kept in file order. Errors carry the 1-based line.
Status parse_node_points(const char* text, size_t size, const std::string& file_name,
                         std::vector<double>& coords, int* first_index = nullptr);
Status read_node_points_file(const std::string& path, std::vector<double>& coords,
                             int* first_index = nullptr);

/// Writes PREFIX.node (every vertex of the mesh, duplicates included, so
/// numbering equals the input order) and PREFIX.ele (real tets), TetGen
/// plain format numbered from 1 like TetGen's default output.
Status write_node_ele(const TetMesh& mesh, const std::string& prefix);

// ---------------------------------------------------------------------------
// Filtered predicates used by the hot loops (inline; exact fallback)
// ---------------------------------------------------------------------------

namespace fast {

/// Static-filter bounds (Shewchuk 1997, "stage A" of orient3d and insphere):
/// |det - computed| <= bound * permanent under round-to-nearest, as long as
/// nothing underflows; tiny permanents go to the exact path.
inline constexpr double kEps = 1.1102230246251565e-16;  // 2^-53
inline constexpr double kOrientBound = (7.0 + 56.0 * kEps) * kEps;
inline constexpr double kInsphereBound = (16.0 + 224.0 * kEps) * kEps;
inline constexpr double kTinyPermanent = 1e-200;

/// Sign of pred::orient3d when the double evaluation is certain, else 0.
inline int orient3d_filter(const double* a, const double* b, const double* c, const double* d) {
  const double adx = a[0] - d[0], bdx = b[0] - d[0], cdx = c[0] - d[0];
  const double ady = a[1] - d[1], bdy = b[1] - d[1], cdy = c[1] - d[1];
  const double adz = a[2] - d[2], bdz = b[2] - d[2], cdz = c[2] - d[2];
  const double bc = bdx * cdy, cb = cdx * bdy;
  const double ca = cdx * ady, ac = adx * cdy;
  const double ab = adx * bdy, ba = bdx * ady;
  const double det = adz * (bc - cb) + bdz * (ca - ac) + cdz * (ab - ba);
  const double perm = (std::fabs(bc) + std::fabs(cb)) * std::fabs(adz) +
                      (std::fabs(ca) + std::fabs(ac)) * std::fabs(bdz) +
                      (std::fabs(ab) + std::fabs(ba)) * std::fabs(cdz);
  const double bound = kOrientBound * perm;
  if (perm > kTinyPermanent) {
    if (det > bound) return 1;
    if (-det > bound) return -1;
  }
  return 0;
}

/// Same sign as pred::orient3d, usually without leaving doubles.
inline int orient3d(const double* a, const double* b, const double* c, const double* d) {
  const int s = orient3d_filter(a, b, c, d);
  return s != 0 ? s : pred::orient3d(a, b, c, d);
}

/// Sign of pred::insphere when the double evaluation is certain, else 0.
inline int insphere_filter(const double* a, const double* b, const double* c, const double* d,
                           const double* e) {
  const double aex = a[0] - e[0], bex = b[0] - e[0], cex = c[0] - e[0], dex = d[0] - e[0];
  const double aey = a[1] - e[1], bey = b[1] - e[1], cey = c[1] - e[1], dey = d[1] - e[1];
  const double aez = a[2] - e[2], bez = b[2] - e[2], cez = c[2] - e[2], dez = d[2] - e[2];
  // 2x2 minors of the xy columns and their absolute-value counterparts.
  const double p_ab = aex * bey, q_ab = bex * aey;
  const double p_bc = bex * cey, q_bc = cex * bey;
  const double p_cd = cex * dey, q_cd = dex * cey;
  const double p_da = dex * aey, q_da = aex * dey;
  const double p_ac = aex * cey, q_ac = cex * aey;
  const double p_bd = bex * dey, q_bd = dex * bey;
  const double ab = p_ab - q_ab, bc = p_bc - q_bc, cd = p_cd - q_cd;
  const double da = p_da - q_da, ac = p_ac - q_ac, bd = p_bd - q_bd;
  // 3x3 minors with the z column.
  const double abc = aez * bc - bez * ac + cez * ab;
  const double bcd = bez * cd - cez * bd + dez * bc;
  const double cda = cez * da + dez * ac + aez * cd;
  const double dab = dez * ab + aez * bd + bez * da;
  const double alift = aex * aex + aey * aey + aez * aez;
  const double blift = bex * bex + bey * bey + bez * bez;
  const double clift = cex * cex + cey * cey + cez * cez;
  const double dlift = dex * dex + dey * dey + dez * dez;
  const double det = (dlift * abc - clift * dab) + (blift * cda - alift * bcd);

  const double az = std::fabs(aez), bz = std::fabs(bez), cz = std::fabs(cez),
               dz = std::fabs(dez);
  const double m_ab = std::fabs(p_ab) + std::fabs(q_ab), m_bc = std::fabs(p_bc) + std::fabs(q_bc);
  const double m_cd = std::fabs(p_cd) + std::fabs(q_cd), m_da = std::fabs(p_da) + std::fabs(q_da);
  const double m_ac = std::fabs(p_ac) + std::fabs(q_ac), m_bd = std::fabs(p_bd) + std::fabs(q_bd);
  const double perm = (m_cd * bz + m_bd * cz + m_bc * dz) * alift +
                      (m_da * cz + m_ac * dz + m_cd * az) * blift +
                      (m_ab * dz + m_bd * az + m_da * bz) * clift +
                      (m_bc * az + m_ac * bz + m_ab * cz) * dlift;
  const double bound = kInsphereBound * perm;
  if (perm > kTinyPermanent) {
    if (det > bound) return 1;
    if (-det > bound) return -1;
  }
  return 0;
}

/// Same sign as pred::insphere_sos (ids distinct; a b c d positive).
inline int insphere_sos(const double* a, const double* b, const double* c, const double* d,
                        const double* e, uint32_t ia, uint32_t ib, uint32_t ic, uint32_t id,
                        uint32_t ie) {
  const int s = insphere_filter(a, b, c, d, e);
  return s != 0 ? s : pred::insphere_sos(a, b, c, d, e, ia, ib, ic, id, ie);
}

}  // namespace fast

}  // namespace cdt3d
