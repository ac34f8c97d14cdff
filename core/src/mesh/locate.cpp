// Point location by a visibility walk (Devillers, Pion, Teillaud 2002,
// "Walking in a triangulation"), with exact orientation tests and
// deterministic face order. Used by Bowyer–Watson insertion and later steps.
#include "delaunay.hpp"

namespace cdt3d {

namespace {

TetId any_live_tet(const TetMesh& mesh) {
  const size_t slots = mesh.num_tet_slots();
  for (size_t t = 0; t < slots; ++t)
    if (!mesh.is_dead(static_cast<TetId>(t))) return static_cast<TetId>(t);
  return kNone;
}

}  // namespace

Location locate_point(const TetMesh& mesh, const double* p, TetId hint, Rng& rng,
                      const pred::BoxBounds* box) {
  if (hint == kNone || hint >= mesh.num_tet_slots() || mesh.is_dead(hint))
    hint = any_live_tet(mesh);
  if (hint == kNone) return Location();
  const TetId t = mesh.is_ghost(hint) ? mesh.neighbor(hint, 3) : hint;
  return walk_to_point(mesh, p, t, rng, [](TetId, TetId) { return true; }, box);
}

}  // namespace cdt3d
