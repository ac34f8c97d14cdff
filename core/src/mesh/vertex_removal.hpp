// Removal of a vertex from a Delaunay tetrahedralization (under the symbolic
// perturbation). Step 2 removes Steiner points that turned out redundant
// (segment_recovery.cpp) and step 3's paper mode moves vertices by removal
// and reinsertion (degeneracy.cpp).
#pragma once

#include <array>
#include <vector>

#include "delaunay.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

/// Removes interior vertices. The star of v is refilled with the Delaunay
/// tetrahedralization of its link vertices: the tets of DT(V \ {v}) inside
/// the star are exactly the tets of DT(link) on the inner side of the link
/// faces. The link is triangulated in a scratch mesh whose local ids follow
/// the global ids, so the symbolic perturbation decides every tie as it does
/// in the whole mesh. Hull vertices are not removed. Keeps its buffers
/// between calls.
class VertexRemover {
 public:
  explicit VertexRemover(TetMesh& mesh) : mesh_(mesh) {}

  /// Computes the tets that would replace the star of v (fresh(), global
  /// ids; link() holds the link vertices, sorted). False, with nothing
  /// planned, when v is on the hull or the refill does not fill the star
  /// (which does not happen on a Delaunay mesh).
  bool plan(VertexId v);
  const std::vector<std::array<VertexId, 4>>& fresh() const { return fresh_; }
  const std::vector<VertexId>& link() const { return link_; }

  /// Replaces the star of the planned vertex by fresh(); v leaves the
  /// triangulation (vtet kNone, kind kVertexNotInserted). created (if given)
  /// gets the new tets. Slots: the last star tet first, the order in which
  /// alloc_tet hands them out after the star is freed tet by tet.
  bool commit(std::vector<TetId>* created = nullptr);

  /// plan() and commit().
  bool remove(VertexId v, std::vector<TetId>* created = nullptr) { return plan(v) && commit(created); }

 private:
  struct LinkFace {
    std::array<uint32_t, 3> key;  // sorted local ids
    VertexId a, b, c;             // counterclockwise seen from outside the star
  };
  bool is_link_face(const std::array<uint32_t, 3>& key) const;

  TetMesh& mesh_;
  SmallDelaunay link_dt_;
  VertexId planned_ = kNone;
  std::vector<TetId> star_, inside_, old_;
  std::vector<VertexId> link_;
  std::vector<LinkFace> faces_;
  std::vector<double> xyz_;
  std::vector<std::array<VertexId, 4>> fresh_;
};

}  // namespace cdt3d
