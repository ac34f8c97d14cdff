// Error-free transformations and floating-point expansion arithmetic
// (Knuth's two-sum, Dekker's fast two-sum, Veltkamp's split and Dekker's
// two-product; expansion sums and scaling with zero elimination after
// Shewchuk 1997, "Adaptive precision floating-point arithmetic and fast robust
// geometric predicates", §2).
//
// Requirements: IEEE-754 binary64 evaluated in double precision, rounding to
// nearest with ties to even (the only mode WebAssembly has), no FMA
// contraction (-ffp-contract=off), no -ffast-math. std::fma is deliberately
// not used: it is a slow library call in WebAssembly.
//
// An expansion is an array of doubles x[0..n) whose exact sum is the value it
// represents, ordered by increasing magnitude and nonoverlapping (the lowest
// set bit of each component lies above the highest set bit of the previous
// one); every function here also drops zero components, so the last component
// carries the sign and n == 0 means the value 0. Output buffers must not alias
// the inputs; their required capacity is stated at each function.
//
// Range: two_sum/fast_two_sum/two_diff are exact for all finite inputs whose
// result does not overflow (sums of doubles never lose bits to underflow).
// split/two_product are exact when |a|, |b| < 2^996 (the split multiplies by
// 2^27 + 1) and the exact product a*b is a multiple of 2^-1074 (no bit falls
// below the smallest subnormal). The predicates guarantee both by scaling
// their inputs by a power of two first (predicates.cpp).
#pragma once

#include <cmath>

// GCC cannot see that a buffer filled by one call holds the `n` components the
// next call reads (n == 0 returns before any read) and reports false
// "may be used uninitialized" warnings at the inlined reads.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif

namespace cdt3d {
namespace exact {

/// s + e == a + b exactly, s = fl(a + b). Branch-free (Knuth).
inline void two_sum(double a, double b, double& s, double& e) {
  s = a + b;
  const double b_in_s = s - a;       // the share of b that reached s
  const double a_in_s = s - b_in_s;  // the share of a that reached s
  e = (a - a_in_s) + (b - b_in_s);
}

/// s + e == a + b exactly, s = fl(a + b); requires |a| >= |b| or a == 0
/// (Dekker). Three operations instead of six.
inline void fast_two_sum(double a, double b, double& s, double& e) {
  s = a + b;
  e = b - (s - a);
}

/// d + e == a - b exactly, d = fl(a - b).
inline void two_diff(double a, double b, double& d, double& e) {
  d = a - b;
  const double b_in_d = a - d;
  const double a_in_d = d + b_in_d;
  e = (a - a_in_d) + (b_in_d - b);
}

/// Tail of a - b given d = fl(a - b): (a - b) - d, exactly.
inline double diff_tail(double a, double b, double d) {
  const double b_in_d = a - d;
  const double a_in_d = d + b_in_d;
  return (a - a_in_d) + (b_in_d - b);
}

/// hi + lo == a with hi and lo fitting in 26 bits of significand each, so that
/// products of parts are exact (Veltkamp; the constant is 2^27 + 1).
inline void split(double a, double& hi, double& lo) {
  const double c = 134217729.0 * a;
  const double big = c - a;
  hi = c - big;
  lo = a - hi;
}

/// p + e == a * b exactly, p = fl(a * b), with b already split as bhi + blo.
inline void two_product_presplit(double a, double b, double bhi, double blo, double& p, double& e) {
  p = a * b;
  double ahi, alo;
  split(a, ahi, alo);
  // Peel the four partial products of (ahi + alo)(bhi + blo) off p, largest
  // first; each subtraction is exact (Dekker 1971).
  const double r1 = p - ahi * bhi;
  const double r2 = r1 - alo * bhi;
  const double r3 = r2 - ahi * blo;
  e = alo * blo - r3;
}

/// p + e == a * b exactly, p = fl(a * b) (Dekker's two-product, Veltkamp split).
inline void two_product(double a, double b, double& p, double& e) {
  double bhi, blo;
  split(b, bhi, blo);
  two_product_presplit(a, b, bhi, blo, p, e);
}

/// p + e == a * a exactly.
inline void two_square(double a, double& p, double& e) {
  p = a * a;
  double ahi, alo;
  split(a, ahi, alo);
  const double r1 = p - ahi * ahi;
  const double r3 = r1 - (ahi + ahi) * alo;  // 2*ahi*alo: doubling is exact
  e = alo * alo - r3;
}

/// h = e + f. Capacity of h: n + m. Returns the length of h.
/// Merges the components of e and f by increasing magnitude, then carries a
/// running sum through them, emitting each nonzero roundoff as a component
/// (Shewchuk's fast expansion sum; valid for nonoverlapping inputs under
/// round-to-nearest-even, which every function here produces).
inline int sum(int n, const double* e, int m, const double* f, double* h) {
  if (n == 0) {
    for (int j = 0; j < m; ++j) h[j] = f[j];
    return m;
  }
  if (m == 0) {
    for (int i = 0; i < n; ++i) h[i] = e[i];
    return n;
  }
  int i = 0, j = 0, k = 0;
  double q, g, s, t;
  if (std::fabs(e[0]) <= std::fabs(f[0])) {
    q = e[0];
    i = 1;
  } else {
    q = f[0];
    j = 1;
  }
  if (j == m || (i < n && std::fabs(e[i]) <= std::fabs(f[j]))) {
    g = e[i++];
  } else {
    g = f[j++];
  }
  // The second merged component is at least as large as the first.
  fast_two_sum(g, q, s, t);
  q = s;
  if (t != 0.0) h[k++] = t;
  while (i < n && j < m) {
    g = std::fabs(e[i]) <= std::fabs(f[j]) ? e[i++] : f[j++];
    two_sum(q, g, s, t);
    q = s;
    if (t != 0.0) h[k++] = t;
  }
  for (; i < n; ++i) {
    two_sum(q, e[i], s, t);
    q = s;
    if (t != 0.0) h[k++] = t;
  }
  for (; j < m; ++j) {
    two_sum(q, f[j], s, t);
    q = s;
    if (t != 0.0) h[k++] = t;
  }
  if (q != 0.0) h[k++] = q;
  return k;
}

/// h = e * b. Capacity of h: 2n. Returns the length of h.
/// Each component product is split into head and tail; tails and the running
/// sum are accumulated with two-sums, largest part kept as the carry.
inline int scale(int n, const double* e, double b, double* h) {
  if (n == 0 || b == 0.0) return 0;
  double bhi, blo;
  split(b, bhi, blo);
  double q, t;
  two_product_presplit(e[0], b, bhi, blo, q, t);
  int k = 0;
  if (t != 0.0) h[k++] = t;
  for (int i = 1; i < n; ++i) {
    double p, pt, s;
    two_product_presplit(e[i], b, bhi, blo, p, pt);
    two_sum(q, pt, s, t);
    if (t != 0.0) h[k++] = t;
    fast_two_sum(p, s, q, t);
    if (t != 0.0) h[k++] = t;
  }
  if (q != 0.0) h[k++] = q;
  return k;
}

/// h = a * b - c * d exactly. Capacity of h: 4. Returns the length of h.
inline int two_two_diff(double a, double b, double c, double d, double* h) {
  double x[2], y[2];
  two_product(a, b, x[1], x[0]);
  two_product(c, d, y[1], y[0]);
  y[0] = -y[0];
  y[1] = -y[1];
  const int nx = x[1] == 0.0 ? 0 : (x[0] == 0.0 ? 1 : 2);
  const int ny = y[1] == 0.0 ? 0 : (y[0] == 0.0 ? 1 : 2);
  return sum(nx, nx == 1 ? x + 1 : x, ny, ny == 1 ? y + 1 : y, h);
}

/// h = e with fewer components: the same value as a nonoverlapping
/// expansion whose components are, in practice, about as few as the value's
/// bit span allows (Shewchuk's compression). Capacity of h: n. Returns the
/// length of h. Renormalizes top-down (carrying the sum of the larger
/// components and keeping a component only when it leaves a remainder), then
/// bottom-up the same way.
inline int compress(int n, const double* e, double* h) {
  if (n == 0) return 0;
  // Top-down pass into h[bottom..n): h[n-1] is the largest part.
  int bottom = n - 1;
  double q = e[n - 1];
  for (int i = n - 2; i >= 0; --i) {
    double s, t;
    fast_two_sum(q, e[i], s, t);
    if (t != 0.0) {
      h[bottom--] = s;
      q = t;
    } else {
      q = s;
    }
  }
  h[bottom] = q;
  // Bottom-up pass: each part absorbs what lies below it, emitting the
  // roundoffs as the new small components from index 0 upwards.
  int top = 0;
  for (int i = bottom + 1; i < n; ++i) {
    double s, t;
    fast_two_sum(h[i], q, s, t);
    if (t != 0.0) h[top++] = t;
    q = s;
  }
  if (q != 0.0) h[top++] = q;
  return top;
}

/// Negates e in place.
inline void negate(int n, double* e) {
  for (int i = 0; i < n; ++i) e[i] = -e[i];
}

/// Sign of a zero-eliminated expansion: the sign of its largest component.
inline int sign(int n, const double* e) {
  if (n == 0) return 0;
  return e[n - 1] > 0.0 ? 1 : -1;
}

/// Approximate value (the components summed in increasing order).
inline double estimate(int n, const double* e) {
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += e[i];
  return s;
}

}  // namespace exact
}  // namespace cdt3d

#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif
