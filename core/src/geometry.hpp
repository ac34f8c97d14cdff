// Small floating-point geometry shared by the steps (never used for a
// topological decision: those go through predicates.hpp).
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <cmath>

namespace cdt3d {

/// 6V / l_max^3 of tet (a, b, c, d) in doubles: 6V = (a - d) . ((b - d) x
/// (c - d)) evaluated in floating point, l_max its longest edge. Positive for
/// a positively oriented tet (tet_mesh.hpp), up to rounding.
inline double volume_ratio(const double* a, const double* b, const double* c, const double* d) {
  const double u[3] = {a[0] - d[0], a[1] - d[1], a[2] - d[2]};
  const double v[3] = {b[0] - d[0], b[1] - d[1], b[2] - d[2]};
  const double w[3] = {c[0] - d[0], c[1] - d[1], c[2] - d[2]};
  const double det = u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) +
                     u[2] * (v[0] * w[1] - v[1] * w[0]);
  const double* p[4] = {a, b, c, d};
  double l2 = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double x = p[i][0] - p[j][0], y = p[i][1] - p[j][1], z = p[i][2] - p[j][2];
      l2 = std::max(l2, x * x + y * y + z * z);
    }
  const double l = std::sqrt(l2);
  return l > 0 ? det / (l * l * l) : 0;
}

/// Whether tet (a, b, c, d) is numerically flat or inverted in doubles:
/// volume_ratio <= kFlatTetRatio. This is the usability test of the output
/// (cdt3d.hpp), applied to the stored coordinates as a user's code would.
inline bool numerically_flat(const double* a, const double* b, const double* c, const double* d) {
  return !(volume_ratio(a, b, c, d) > kFlatTetRatio);
}

/// Whether some four of the five points are numerically flat. A face between
/// two tets whose five vertices pass this test may fail the exact insphere
/// test: the Delaunay choice there would be a flat tet, which the pipeline
/// flips away (flat_flips.hpp); validate() accepts such faces (its check 8).
inline bool has_flat_quadruple(const double* const p[5]) {
  for (int skip = 0; skip < 5; ++skip) {
    const double* q[4];
    for (int i = 0, k = 0; i < 5; ++i)
      if (i != skip) q[k++] = p[i];
    if (std::fabs(volume_ratio(q[0], q[1], q[2], q[3])) <= kFlatTetRatio) return true;
  }
  return false;
}

}  // namespace cdt3d
