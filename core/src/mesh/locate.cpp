// Point location by a visibility walk (Devillers, Pion, Teillaud 2002,
// "Walking in a triangulation"), with exact orientation tests and
// deterministic face order. Used by Bowyer–Watson insertion and later steps.
#include <cstring>

#include "delaunay.hpp"

namespace cdt3d {

namespace {

bool same_point(const double* p, const double* q) {
  return p[0] == q[0] && p[1] == q[1] && p[2] == q[2];
}

TetId any_live_tet(const TetMesh& mesh) {
  const size_t slots = mesh.num_tet_slots();
  for (size_t t = 0; t < slots; ++t)
    if (!mesh.is_dead(static_cast<TetId>(t))) return static_cast<TetId>(t);
  return kNone;
}

}  // namespace

Location locate_point(const TetMesh& mesh, const double* p, TetId hint, Rng& rng) {
  Location loc;
  if (hint == kNone || hint >= mesh.num_tet_slots() || mesh.is_dead(hint))
    hint = any_live_tet(mesh);
  if (hint == kNone) return loc;
  TetId t = mesh.is_ghost(hint) ? mesh.neighbor(hint, 3) : hint;
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
      if (pred::orient3d(a, b, c, p) < 0) {  // p strictly beyond face i
        next = n;
        break;
      }
    }
    if (next == kNone) {  // p in the closed tet t
      loc.tet = t;
      loc.kind = LocateKind::InTet;
      for (int i = 0; i < 4; ++i)
        if (same_point(mesh.point(w[i]), p)) {
          loc.kind = LocateKind::OnVertex;
          loc.vertex = w[i];
        }
      return loc;
    }
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

}  // namespace cdt3d
