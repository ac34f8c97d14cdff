// Cavity formation and cavity retetrahedralization for facet recovery
// (Si & Gärtner 2005 §7, "formcavity" and "cavity retetrahedralization").
//
// A missing region Ω (coplanar missing subfaces of one facet) is recovered in
// four stages, all decided with exact predicates:
//  1. Hole: every tet (ghost tets included) that meets Ω other than in a
//     common vertex or edge is found by a breadth-first search seeded with the
//     stars of Ω's vertices.
//  2. Cavities: the faces between the hole and the kept tets, plus both sides
//     of every subface of Ω, are grouped into closed cavities by walking the
//     ring of tets around each of their edges (at an edge of Ω the subface
//     splits the ring's run of hole tets in two).
//  3. Verification and expansion: each cavity C is tetrahedralized by the
//     Delaunay tetrahedralization D_C of its vertices V (a scratch TetMesh
//     whose vertex k is the k-th smallest global id, so the symbolic
//     perturbation decides every tie exactly as in the global mesh). A face of
//     C missing from D_C is not (SoS-)strongly Delaunay in V; C is expanded
//     across it by taking in the kept tet beyond it and toggling that tet's
//     other faces (§7 step 1), then D_C is rebuilt.
//  4. Filling: when every face of every cavity is in its D_C, the tets of D_C
//     on the inner side of C's faces (found by flood fill) replace the hole;
//     a cavity that contains the vertex at infinity (Ω on a hull plane) is
//     refilled with ghost tets. Nothing touches the mesh before stage 4, so a
//     failure leaves the mesh as it was.
// Fallback (documented gap of §7, cf. Diazzi et al. 2023): a face of C that
// cannot be expanded (a subface of Ω, a face shared by the two cavities, a
// hull face, or a subface of any facet, which is never expanded across) may
// be missing from D_C even in exact arithmetic, typically
// because Ω is folded (its Steiner vertices are rounded, so the facet is only
// nearly planar and one cavity is reflex along Ω) or because a vertex of C
// lies on the wrong side of Ω. Such a cavity keeps the tets of D_C that are
// inside it and meet no missing face; the rest is filled by constrained
// gift-wrapping: from a face of the front, the vertex on its inner side with
// the smallest sphere whose tet meets no front face improperly and holds no
// other vertex (exact tests), until the front closes.
// Failures are detected, never papered over: gift-wrapping that finds no
// valid tet (a cavity with no tetrahedralization on its vertices, e.g.
// Schönhardt's prism), an inside/outside conflict, a vertex lost from the
// cavity, inconsistent cavity faces, or a bound of CavityLimits reached.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "tet_mesh.hpp"

namespace cdt3d {

using Triangle = std::array<VertexId, 3>;

/// True when the closed simplex `s` (a tet with 4 finite vertices when
/// ns == 4, a triangle when ns == 3) and the closed triangle `tri` intersect
/// in a point that is not in a face common to both (they may share vertices
/// and an edge). Exact and unperturbed; every degenerate contact is decided:
/// a coplanar overlap or a touching edge counts, a common vertex or edge does
/// not. The vertices of `tri` must be distinct points.
bool improper_intersection(const TetMesh& mesh, const VertexId* s, int ns, const VertexId* tri);

/// Exact orientation of the four points (ids; none is kInfinite).
int orient_ids(const TetMesh& mesh, VertexId a, VertexId b, VertexId c, VertexId d);

/// Limits that keep every loop of a region bounded.
struct CavityLimits {
  size_t max_tets = size_t(1) << 21;  ///< hole + absorbed tets of one region
  size_t max_rounds = 4000;           ///< Delaunay rebuilds of the cavities of one region
  size_t max_ring = 1u << 16;         ///< tets around one edge
};

/// What one call to CavityMesher::recover_region did.
struct CavityReport {
  size_t hole_tets = 0;       ///< tets met by Ω
  size_t cavities = 0;        ///< cavities retetrahedralized (ghost ones included)
  size_t expansions = 0;      ///< tets taken in by expansion
  size_t largest_cavity = 0;  ///< most faces of one cavity
  size_t rebuilds = 0;        ///< Delaunay tetrahedralizations of cavities
  size_t gift_wraps = 0;      ///< cavities filled by the gift-wrapping fallback
  std::string failure;        ///< why the region could not be recovered
};

enum class CavityOutcome {
  Recovered,  ///< every triangle of the region is a face of the mesh
  Failed,     ///< detected failure; the mesh is unchanged
  Limit,      ///< a bound of CavityLimits was reached; the mesh is unchanged
};

/// Recovers missing regions one at a time; keeps its buffers between calls.
class CavityMesher {
 public:
  explicit CavityMesher(TetMesh& mesh, CavityLimits limits = {});

  /// formcavity + cavity retetrahedralization (§7) for the region given as
  /// triangles (global vertex ids, every one missing from the mesh, all of
  /// one facet, edge-connected). On Recovered the mesh is valid and has every
  /// triangle as a face; on Failed or Limit it is untouched.
  CavityOutcome recover_region(const std::vector<Triangle>& region, CavityReport& report);

  /// Tells which faces (sorted vertex ids) are subfaces. A face of a cavity
  /// that is a subface is never expanded across (that would destroy it and
  /// can make two facets take turns destroying each other's subfaces); if it
  /// is missing from D_C the cavity is gift-wrapped instead, which is still
  /// constrained Delaunay there because the subface blocks visibility (§7,
  /// proof of Theorem 5, case 3b).
  void set_subface_test(std::function<bool(const Triangle&)> test) {
    is_subface_ = std::move(test);
  }

  /// After Recovered: the faces (sorted vertex ids, finite only) of the tets
  /// that were removed, so that the caller can re-check subfaces that were
  /// faces of them (Theorem 4: an expansion may destroy recovered subfaces).
  const std::vector<Triangle>& removed_faces() const { return removed_faces_; }

 private:
  /// A face of a cavity (§7: "faces of C"): a face between a cavity and a
  /// kept tet, or between two cavities (a subface of Ω, or a face of a tet
  /// that an expansion took in next to the other cavity).
  struct Rec {
    VertexId v[3];          ///< counterclockwise seen from side B: a tet on side A lists it so
    uint32_t side[2];       ///< cavity on side A; cavity on side B or kSideKept
    HalfFace kept = kNone;  ///< side B's half-face when side[1] == kSideKept
    int32_t omega = -1;     ///< index of the triangle of Ω, or -1
    bool alive = true;
    HalfFace dt_hf[2] = {kNone, kNone};  ///< per cavity side: half-face in that cavity's D_C
  };
  /// A cavity and its Delaunay tetrahedralization D_C (local vertex k is
  /// verts[k]; the ids are increasing so the perturbation agrees with the mesh).
  struct Cav {
    bool ghost = false;           ///< holds the vertex at infinity (Ω on a hull plane)
    bool dirty = true;            ///< faces changed since D_C was built
    std::vector<VertexId> extra;  ///< vertices inside C (not on its faces) and of absorbed tets
    std::vector<VertexId> verts;  ///< V, sorted
    TetMesh dt;
    std::vector<uint8_t> inside;   ///< per D_C slot: 0 unknown, 1 inside C, 2 outside
    std::vector<uint32_t> rec_at;  ///< per D_C half-face: the record lying there, or kNone
    std::vector<std::array<VertexId, 4>> ghosts;  ///< ghost cavity: new ghost tets
    size_t faces = 0;
  };

  CavityOutcome form_hole(const std::vector<Triangle>& region, std::string& why);
  bool test_tet(TetId t, const std::vector<Triangle>& region);
  bool build_records(const std::vector<Triangle>& region, std::string& why);
  // link_cavities and its parts: one edge of the cavity faces at a time.
  struct Linking;
  bool link_cavities(std::string& why);
  void list_record_edges(Linking& L) const;
  bool link_omega_edge(Linking& L, VertexId p, VertexId q, std::string& why);
  bool link_ring(Linking& L, VertexId p, VertexId q, std::string& why);
  bool link_run(Linking& L, VertexId p, VertexId q, size_t s, size_t e, std::string& why);
  void locate_in_run(Linking& L, VertexId p, VertexId q, size_t s, size_t e, size_t o);
  void number_cavities(Linking& L);
  bool assign_interior_vertices(const std::vector<Triangle>& region, std::string& why);
  CavityOutcome verify_and_expand(CavityReport& report, std::string& why);
  bool build_cavity_dt(uint32_t k, std::vector<uint32_t>& missing, std::string& why);
  bool mark_inside(uint32_t k, std::string& why);
  bool collect_bounded_vertices(uint32_t k, std::string& why);
  bool gift_wrap(uint32_t k, const std::vector<uint32_t>* missing, std::string& why);
  // gift_wrap's open faces: a face of cavity k (record rec, seen from
  // `side`) or one made by the wrapping (rec = kNone), by local vertex ids.
  struct OpenFace {
    VertexId v[3];
    uint32_t rec;
    int side;
  };
  bool open_cavity_faces(uint32_t k, std::map<Triangle, OpenFace>& front, std::string& why);
  bool store_wrapped(uint32_t k, const std::vector<std::array<VertexId, 4>>& tets,
                     const std::map<Triangle, OpenFace>& faces_of_c, std::string& why);
  bool keep_sound_tets(uint32_t k, const std::vector<uint32_t>& missing,
                       std::vector<std::array<VertexId, 4>>& tets,
                       std::map<Triangle, OpenFace>& front, std::string& why);
  void collect_vertices(uint32_t k);
  bool absorb(TetId t, uint32_t k, std::string& why);
  bool plan_ghost_cavity(uint32_t k, std::string& why);
  bool commit(std::string& why);
  void reset_marks();
  uint32_t new_record(const VertexId v[3], uint32_t side_a, uint32_t side_b, HalfFace kept,
                      int32_t omega);
  void kill_record(uint32_t r);

  TetMesh& m_;
  CavityLimits limits_;

  // Per tet slot: kNone untouched, else one of the marks in cavity.cpp.
  std::vector<uint32_t> mark_;
  std::vector<TetId> touched_;
  std::vector<TetId> hole_;                   ///< tets met by Ω
  std::vector<uint32_t> hole_sub_;            ///< per hole tet: a triangle of Ω it meets
  std::vector<TetId> absorbed_;               ///< tets taken in by expansions
  std::vector<std::array<double, 6>> boxes_;  ///< bounding boxes of Ω's triangles

  std::vector<Rec> recs_;
  std::vector<uint32_t> omega_rec_;                      ///< per triangle of Ω: its record
  std::vector<std::pair<VertexId, uint32_t>> interior_;  ///< vertex inside a cavity, cavity
  std::map<Triangle, uint32_t> rec_of_;                  ///< sorted vertex triple -> live record
  std::vector<Cav> cavs_;
  std::vector<Triangle> removed_faces_;
  std::vector<TetId> scratch_;
  std::function<bool(const Triangle&)> is_subface_;
};

}  // namespace cdt3d
