// Simulation of Simplicity (Edelsbrunner & Mücke 1990) for the insphere
// test and for the ghost-tet test on a hull face, ordered by vertex id (never
// by address, so native and wasm32 builds decide the same way).
//
// Derivation. With rows (x, y, z, w = x^2 + y^2 + z^2, 1) for the points
// p_0..p_4 = a..e, insphere(a, b, c, d, e) equals the 5x5 determinant
//     D = det | p_i  w_i  1 |
// (subtract row e from the others, expand along the column of ones, then
// replace w_i - w_e by |p_i - e|^2 with column operations). D is linear in the
// lift column, so lifting each point by its own infinitesimal,
// w_i -> w_i + eps_i, gives
//     D(eps) = D + sum_i eps_i * C_i,   C_i = (-1)^(i+3) * M_i = (-1)^(i+1) * M_i,
// where M_i is the minor without row i and the lift column, i.e. the 4x4
// determinant | p 1 | of the other four points in their order, which is
// orient3d of those four points. With eps_i = eps^(rank of p_i), rank 1 for
// the id raised first (sos_raised_before: the smallest), and D = 0, the sign
// of D(eps) for small eps > 0 is the sign of the first nonzero C_i taken in
// that order:
//     a: -orient3d(b,c,d,e)  b: +orient3d(a,c,d,e)  c: -orient3d(a,b,d,e)
//     d: +orient3d(a,b,c,e)  e: -orient3d(a,b,c,d).
// The last one is nonzero for a proper tetrahedron, so the result is never 0
// then. (Check: raising e's lift moves e out of the sphere, and indeed the e
// term is -orient3d(a,b,c,d) < 0.)
#include <cstdint>

#include "predicates.hpp"

namespace cdt3d {
namespace pred {

int insphere_sos(const double* a, const double* b, const double* c, const double* d,
                 const double* e, uint32_t ia, uint32_t ib, uint32_t ic, uint32_t id, uint32_t ie) {
  const int s = insphere(a, b, c, d, e);
  if (s != 0) return s;
  return insphere_tie(a, b, c, d, e, ia, ib, ic, id, ie);
}

int insphere_tie(const double* a, const double* b, const double* c, const double* d,
                 const double* e, uint32_t ia, uint32_t ib, uint32_t ic, uint32_t id, uint32_t ie,
                 bool small_integers) {
  ++detail::g_counters.sos_ties;
  const double* p[5] = {a, b, c, d, e};
  const uint32_t ids[5] = {ia, ib, ic, id, ie};
  int order[5] = {0, 1, 2, 3, 4};
  for (int i = 1; i < 5; ++i)  // insertion sort, first raised first
    for (int j = i; j > 0 && sos_raised_before(ids[order[j]], ids[order[j - 1]]); --j) {
      const int t = order[j];
      order[j] = order[j - 1];
      order[j - 1] = t;
    }
  for (int r = 0; r < 5; ++r) {
    const int i = order[r];
    const double* q[4];
    for (int j = 0, k = 0; j < 5; ++j)
      if (j != i) q[k++] = p[j];
    const int o = small_integers ? orient3d_small_integers(q[0], q[1], q[2], q[3])
                                 : orient3d(q[0], q[1], q[2], q[3]);
    if (o != 0) return i % 2 == 0 ? -o : o;
  }
  return 0;  // all five points coplanar
}

// Ghost tet (a, b, c, inf), outer side orient3d(a, b, c, .) > 0. Take any
// point q on that side and apply insphere_sos(a, b, c, q, e) with e on the
// plane: the q term, +orient3d(a, b, c, e), is 0 whatever q's id, and for x,
// y, z in the plane orient3d(x, y, z, q) = tau(x, y, z) * orient3d(a, b, c, q)
// * (positive), where tau is +1 when (x, y, z) turn the same way as (a, b, c)
// in the plane, -1 when opposite, 0 when collinear. Swapping q to the last
// place, the terms become
//     a: -orient3d(b,c,q,e) = +orient3d(b,c,e,q) -> tau(e, b, c)
//     b: +orient3d(a,c,q,e) = -orient3d(a,c,e,q) -> tau(a, e, c)
//     c: -orient3d(a,b,q,e) = +orient3d(a,b,e,q) -> tau(a, b, e)
//     e: -orient3d(a,b,c,q)                      -> -1
// i.e. for a vertex of the face, the orientation of the face with that vertex
// replaced by e, relative to the face; for e itself, "outside". tau is exact
// from the projection on a coordinate plane where the face does not degenerate
// (the projected orientations share the factor sign(n[drop])).
int incircle_coplanar_sos(const double* a, const double* b, const double* c, const double* e,
                          uint32_t ia, uint32_t ib, uint32_t ic, uint32_t ie) {
  const int o = orient3d(a, b, c, e);
  if (o != 0) return o;
  return incircle_coplanar_sos_on_plane(a, b, c, e, ia, ib, ic, ie);
}

int incircle_coplanar_sos_on_plane(const double* a, const double* b, const double* c,
                                   const double* e, uint32_t ia, uint32_t ib, uint32_t ic,
                                   uint32_t ie, bool small_integers) {
  const int s = small_integers ? incircle_coplanar_small_integers(a, b, c, e)
                               : incircle_coplanar(a, b, c, e);
  if (s != 0) return s;
  ++detail::g_counters.sos_ties;
  int drop = 0, face = 0;
  for (; drop < 3; ++drop) {
    face = orient2d_projected(a, b, c, drop);
    if (face != 0) break;
  }
  if (face == 0) return 0;  // a, b, c collinear
  const double* p[4] = {a, b, c, e};
  const uint32_t ids[4] = {ia, ib, ic, ie};
  int order[4] = {0, 1, 2, 3};
  for (int i = 1; i < 4; ++i)
    for (int j = i; j > 0 && sos_raised_before(ids[order[j]], ids[order[j - 1]]); --j) {
      const int t = order[j];
      order[j] = order[j - 1];
      order[j - 1] = t;
    }
  for (int r = 0; r < 4; ++r) {
    const int i = order[r];
    if (i == 3) return -1;
    const double* q[3] = {p[0], p[1], p[2]};
    q[i] = e;
    const int t = orient2d_projected(q[0], q[1], q[2], drop) * face;
    if (t != 0) return t;
  }
  return -1;  // not reached: the e term is always nonzero
}

}  // namespace pred
}  // namespace cdt3d
