// Double-double arithmetic (a value as the unevaluated sum hi + lo of two
// doubles, about 106 bits of significand; Dekker 1971, with the error-free
// transformations of expansion.hpp). For constructions that want more than
// double precision and must come out the same in every build: `long double`
// is 80 bits on x86-64 and 128 bits (in software) in WebAssembly, so a point
// built with it can round differently natively and in the browser. Each
// operation here is a fixed sequence of IEEE double operations (no FMA
// contraction, expansion.hpp's requirements), so the results are identical
// wherever it runs. Accuracy: a few units of 2^-104 relative per operation,
// for values far from overflow and underflow.
#pragma once

#include "expansion.hpp"

namespace cdt3d {

struct DoubleDouble {
  double hi = 0, lo = 0;
  DoubleDouble() = default;
  DoubleDouble(double x) : hi(x) {}  // NOLINT: implicit, like a widening conversion
  DoubleDouble(double h, double l) : hi(h), lo(l) {}
  double value() const { return hi + lo; }
};

inline DoubleDouble operator+(const DoubleDouble& a, const DoubleDouble& b) {
  double s, e;
  exact::two_sum(a.hi, b.hi, s, e);
  e += a.lo + b.lo;
  double h, l;
  exact::two_sum(s, e, h, l);  // not fast_two_sum: after cancellation e may outweigh s
  return {h, l};
}

inline DoubleDouble& operator+=(DoubleDouble& a, const DoubleDouble& b) { return a = a + b; }

inline DoubleDouble operator-(const DoubleDouble& a) { return {-a.hi, -a.lo}; }
inline DoubleDouble operator-(const DoubleDouble& a, const DoubleDouble& b) { return a + (-b); }

inline DoubleDouble operator*(const DoubleDouble& a, const DoubleDouble& b) {
  double p, e;
  exact::two_product(a.hi, b.hi, p, e);
  e += a.hi * b.lo + a.lo * b.hi;
  double h, l;
  exact::fast_two_sum(p, e, h, l);
  return {h, l};
}

// One Newton step on the double quotient: q1 = a / b, then the remainder
// a - q1 b (in double-double) divided again.
inline DoubleDouble operator/(const DoubleDouble& a, const DoubleDouble& b) {
  const double q1 = a.hi / b.hi;
  const DoubleDouble r = a - b * DoubleDouble(q1);
  const double q2 = r.hi / b.hi;
  double h, l;
  exact::fast_two_sum(q1, q2, h, l);
  return {h, l};
}

inline bool operator<(const DoubleDouble& a, const DoubleDouble& b) {
  return a.hi < b.hi || (a.hi == b.hi && a.lo < b.lo);
}

}  // namespace cdt3d
