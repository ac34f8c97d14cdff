// Validators for TetMesh (tet_mesh.hpp): structural invariants with exact
// orientation, and local Delaunayhood under the symbolic perturbation.
// O(tets); meant for tests and --validate, not for hot paths.
#include <string>

#include "predicates.hpp"
#include "status.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

namespace {

std::string tet_name(const TetMesh& m, size_t t) {
  std::string s = "tet " + std::to_string(t) + " (";
  for (int i = 0; i < 4; ++i) {
    const VertexId v = m.tv[4 * t + i];
    s += v == kInfinite ? std::string("inf") : std::to_string(v);
    s += i < 3 ? " " : ")";
  }
  return s;
}

// Face i of t as listed counterclockwise from outside t.
void face_of(const TetMesh& m, size_t t, int i, VertexId out[3]) {
  for (int k = 0; k < 3; ++k) out[k] = m.tv[4 * t + kFaceVertex[i][k]];
}

// y is x with the opposite orientation (a cyclic rotation of x reversed).
bool reversed_face(const VertexId x[3], const VertexId y[3]) {
  for (int r = 0; r < 3; ++r)
    if (y[r] == x[0] && y[(r + 1) % 3] == x[2] && y[(r + 2) % 3] == x[1]) return true;
  return false;
}

}  // namespace

Status check_mesh(const TetMesh& m) {
  const size_t nv = m.num_vertices();
  const size_t slots = m.num_tet_slots();
  if (m.coords.size() != 3 * nv || m.vkind.size() != nv || m.vtet.size() != nv)
    return make_error(ErrorCode::Internal, "mesh: per-vertex arrays have different sizes.");
  if (m.tv.size() != 4 * slots || m.tadj.size() != 4 * slots || m.tstamp.size() != slots ||
      m.tflag.size() != slots)
    return make_error(ErrorCode::Internal, "mesh: per-tet arrays have different sizes.");

  size_t live = 0, dead = 0;
  for (size_t t = 0; t < slots; ++t) {
    if (m.tflag[t] & kTetDead) {
      ++dead;
      continue;
    }
    ++live;
    const VertexId* w = &m.tv[4 * t];
    const bool ghost = w[3] == kInfinite;
    for (int i = 0; i < 4; ++i) {
      if (w[i] == kInfinite) {
        if (i != 3)
          return make_error(ErrorCode::Internal, "mesh: " + tet_name(m, t) +
                                                     " has the infinite vertex before position 3.");
      } else if (w[i] >= nv) {
        return make_error(ErrorCode::Internal,
                          "mesh: " + tet_name(m, t) + " has a vertex id out of range.");
      } else if (m.vtet[w[i]] == kNone) {
        return make_error(ErrorCode::Internal,
                          "mesh: " + tet_name(m, t) + " uses a vertex with no incident tet.")
            .vertex(w[i]);
      }
      for (int j = 0; j < i; ++j)
        if (w[i] == w[j])
          return make_error(ErrorCode::Internal, "mesh: " + tet_name(m, t) + " repeats a vertex.");
    }
    for (int i = 0; i < 4; ++i) {
      const HalfFace hf = m.tadj[4 * t + i];
      if (hf == kNone || hf_tet(hf) >= slots)
        return make_error(ErrorCode::Internal, "mesh: " + tet_name(m, t) + " face " +
                                                   std::to_string(i) + " has no neighbour.");
      const size_t n = hf_tet(hf);
      if (m.tflag[n] & kTetDead)
        return make_error(
            ErrorCode::Internal,
            "mesh: " + tet_name(m, t) + " is glued to dead tet " + std::to_string(n) + ".");
      if (m.tadj[hf] != make_hf(static_cast<TetId>(t), i))
        return make_error(ErrorCode::Internal, "mesh: adjacency of " + tet_name(m, t) + " face " +
                                                   std::to_string(i) + " is not symmetric.");
      VertexId x[3], y[3];
      face_of(m, t, i, x);
      face_of(m, n, hf_face(hf), y);
      if (!reversed_face(x, y))
        return make_error(ErrorCode::Internal,
                          "mesh: " + tet_name(m, t) + " and " + tet_name(m, n) +
                              " do not share their face with opposite orientations.");
      const bool n_ghost = m.tv[4 * n + 3] == kInfinite;
      if (ghost && (i == 3) == n_ghost)
        return make_error(ErrorCode::Internal, "mesh: ghost " + tet_name(m, t) +
                                                   " has a wrong neighbour across face " +
                                                   std::to_string(i) + ".");
    }
    if (!ghost) {
      if (pred::orient3d(m.point(w[0]), m.point(w[1]), m.point(w[2]), m.point(w[3])) <= 0)
        return make_error(ErrorCode::Internal,
                          "mesh: " + tet_name(m, t) + " is not positively oriented.");
    } else {
      // Hull convexity at each hull edge: the neighbouring hull face's third
      // vertex is not strictly beyond this hull face.
      if (pred::collinear3d(m.point(w[0]), m.point(w[1]), m.point(w[2])))
        return make_error(ErrorCode::Internal,
                          "mesh: hull face of " + tet_name(m, t) + " is degenerate.");
      for (int i = 0; i < 3; ++i) {
        const HalfFace hf = m.tadj[4 * t + i];
        const VertexId e = m.tv[4 * size_t(hf_tet(hf)) + hf_face(hf)];
        if (pred::orient3d(m.point(w[0]), m.point(w[1]), m.point(w[2]), m.point(e)) > 0)
          return make_error(ErrorCode::Internal,
                            "mesh: hull is not convex at " + tet_name(m, t) + ".");
      }
    }
  }
  if (live != m.live_tets)
    return make_error(ErrorCode::Internal, "mesh: live_tets is " + std::to_string(m.live_tets) +
                                               " but " + std::to_string(live) + " tets are alive.");
  if (dead != m.free_tets.size())
    return make_error(ErrorCode::Internal, "mesh: free list does not hold every dead slot.");
  for (TetId t : m.free_tets)
    if (t >= slots || !(m.tflag[t] & kTetDead))
      return make_error(ErrorCode::Internal, "mesh: free list holds a live slot.");

  for (size_t v = 0; v < nv; ++v) {
    const TetId t = m.vtet[v];
    if (t == kNone) continue;
    if (m.vkind[v] == kVertexDuplicate || m.vkind[v] == kVertexNotInserted)
      return make_error(ErrorCode::Internal,
                        "mesh: vertex " + std::to_string(v) + " is not inserted but has a tet.")
          .vertex(int64_t(v));
    if (t >= slots || (m.tflag[t] & kTetDead) || m.index_in_tet(t, VertexId(v)) < 0)
      return make_error(ErrorCode::Internal, "mesh: vtet of vertex " + std::to_string(v) +
                                                 " is not an incident live tet.")
          .vertex(int64_t(v));
  }
  return Status::success();
}

Status check_delaunay(const TetMesh& m) {
  const size_t slots = m.num_tet_slots();
  for (size_t t = 0; t < slots; ++t) {
    if (m.tflag[t] & kTetDead) continue;
    const VertexId* w = &m.tv[4 * t];
    const bool ghost = w[3] == kInfinite;
    // Each interior face is tested from both sides (cheap, and catches an
    // inconsistent perturbation).
    for (int i = 0; i < (ghost ? 3 : 4); ++i) {
      const HalfFace hf = m.tadj[4 * t + i];
      const size_t n = hf_tet(hf);
      const VertexId e = m.tv[4 * n + hf_face(hf)];
      const bool n_ghost = m.tv[4 * n + 3] == kInfinite;
      if (!ghost && !n_ghost) {
        if (pred::insphere_sos(m.point(w[0]), m.point(w[1]), m.point(w[2]), m.point(w[3]),
                               m.point(e), w[0], w[1], w[2], w[3], e) >= 0)
          return make_error(ErrorCode::Internal,
                            "delaunay: face " + std::to_string(i) + " of " + tet_name(m, t) +
                                " is not locally Delaunay (vertex " + std::to_string(e) + ").");
      }
    }
    if (!ghost) continue;
    // Hull edges: the neighbouring hull face's third vertex e is never beyond
    // (check_mesh); when coplanar it must be outside this face's circle.
    for (int i = 0; i < 3; ++i) {
      const HalfFace hf = m.tadj[4 * t + i];
      const VertexId e = m.tv[4 * size_t(hf_tet(hf)) + hf_face(hf)];
      const double *a = m.point(w[0]), *b = m.point(w[1]), *c = m.point(w[2]);
      if (pred::orient3d(a, b, c, m.point(e)) != 0) continue;
      if (pred::incircle_coplanar_sos_on_plane(a, b, c, m.point(e), w[0], w[1], w[2], e) > 0)
        return make_error(ErrorCode::Internal,
                          "delaunay: hull edge of " + tet_name(m, t) +
                              " is not locally Delaunay in its plane (vertex " + std::to_string(e) +
                              ").");
    }
  }
  return Status::success();
}

}  // namespace cdt3d
