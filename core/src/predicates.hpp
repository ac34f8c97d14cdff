// Exact geometric predicates on double coordinates (filter -> exact expansion
// arithmetic), plus symbolic perturbation ordered by vertex index.
// Round-to-nearest only; no FMA contraction (-ffp-contract=off); no fesetround.
#pragma once

#include <cstdint>

namespace cdt3d {
namespace pred {

/// Sign of the determinant | ax-dx ay-dy az-dz ; bx-dx ... ; cx-dx ... |.
/// > 0 when d lies below the plane through a, b, c, with a, b, c appearing
/// counterclockwise seen from above (Shewchuk's convention). Exact.
int orient3d(const double* a, const double* b, const double* c, const double* d);

/// Sign of the 2D orientation of (a, b, c): > 0 counterclockwise. Exact.
int orient2d(const double* a, const double* b, const double* c);

/// Sign of orient2d of the projections of 3D points a, b, c onto the
/// coordinate plane that drops axis `drop` (0 = x, 1 = y, 2 = z); the
/// remaining axes are taken in cyclic order (drop 0: (y,z), 1: (z,x), 2: (x,y)),
/// so for points in a plane with normal n, the sign equals sign(n[drop]) times
/// the in-plane orientation. Exact (projection drops a coordinate, no rounding).
int orient2d_projected(const double* a, const double* b, const double* c, int drop);

/// Sign of the insphere determinant: > 0 when e lies inside the sphere through
/// a, b, c, d, provided orient3d(a, b, c, d) > 0 (the sign flips otherwise).
/// Exact, unperturbed (0 when co-spherical).
int insphere(const double* a, const double* b, const double* c, const double* d,
             const double* e);

/// 2D incircle: > 0 when d inside the circle through a, b, c with
/// orient2d(a,b,c) > 0. Exact.
int incircle(const double* a, const double* b, const double* c, const double* d);

/// In-plane incircle for four coplanar 3D points, without rounding any
/// projection: > 0 when d is inside the circumcircle of a, b, c, independent of
/// the orientation of a, b, c. Precondition: a, b, c not collinear and d in
/// their plane. Exact.
int incircle_coplanar(const double* a, const double* b, const double* c, const double* d);

/// Collinearity of three 3D points, exact.
bool collinear3d(const double* a, const double* b, const double* c);

/// Symbolically perturbed insphere (Simulation of Simplicity on the lifted
/// points, ordered by the vertex ids ia..ie, which must be distinct). Never 0
/// when a,b,c,d is a proper tetrahedron with orient3d(a,b,c,d) > 0:
/// > 0 inside, < 0 outside. Uses insphere() first; the perturbation only
/// decides exact zeros.
int insphere_sos(const double* a, const double* b, const double* c, const double* d,
                 const double* e, uint32_t ia, uint32_t ib, uint32_t ic, uint32_t id,
                 uint32_t ie);

/// Perturbed "in circle of a hull face" test used for ghost tets: for e coplanar
/// with a, b, c (orient3d == 0), decides whether e is in conflict with the
/// ghost tet on the outer side of face (a, b, c), consistently with
/// insphere_sos. > 0 conflict.
int incircle_coplanar_sos(const double* a, const double* b, const double* c,
                          const double* e, uint32_t ia, uint32_t ib, uint32_t ic,
                          uint32_t ie);

/// Counters for filter efficiency (not thread-safe; for statistics only).
struct Counters {
  uint64_t orient3d_calls = 0, orient3d_exact = 0;
  uint64_t insphere_calls = 0, insphere_exact = 0;
};
Counters& counters();

}  // namespace pred
}  // namespace cdt3d
