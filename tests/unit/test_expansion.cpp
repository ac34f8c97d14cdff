// Error-free transforms and expansion arithmetic (expansion.hpp) checked
// against exact rationals (GMP mpq_class).
#include <gmpxx.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "expansion.hpp"

namespace {

using namespace cdt3d;

struct Rng {
  uint64_t s;
  explicit Rng(uint64_t seed) : s(seed) {}
  uint64_t next() {  // splitmix64
    uint64_t z = (s += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  int range(int lo, int hi) { return lo + static_cast<int>(next() % uint64_t(hi - lo + 1)); }
  // Random 53-bit significand (or shorter, to exercise ties and trailing
  // zeros), random sign, times 2^e.
  double value(int e_lo, int e_hi) {
    uint64_t m = (next() >> 11) | (uint64_t(1) << 52);
    const int cut = range(0, 3) == 0 ? range(0, 50) : 0;
    m &= ~((uint64_t(1) << cut) - 1);
    const double x = std::ldexp(static_cast<double>(m), range(e_lo, e_hi) - 52);
    return (next() & 1) ? -x : x;
  }
};

mpq_class Q(double x) { return mpq_class(x); }

mpq_class value_of(int n, const double* e) {
  mpq_class s = 0;
  for (int i = 0; i < n; ++i) s += Q(e[i]);
  return s;
}

int lowest_bit(double x) {
  uint64_t b;
  std::memcpy(&b, &x, 8);
  const int be = static_cast<int>((b >> 52) & 0x7ff);
  const uint64_t f = b & ((uint64_t(1) << 52) - 1);
  if (be == 0) return -1074 + __builtin_ctzll(f);
  return be - 1075 + __builtin_ctzll(f | (uint64_t(1) << 52));
}
int highest_bit(double x) {
  int e;
  std::frexp(x, &e);
  return e - 1;
}

// Zero-free, increasing magnitude, nonoverlapping.
bool well_formed(int n, const double* e) {
  for (int i = 0; i < n; ++i) {
    if (e[i] == 0.0 || !std::isfinite(e[i])) return false;
    if (i > 0 && lowest_bit(e[i]) <= highest_bit(e[i - 1])) return false;
  }
  return true;
}

int significant_bits(double x) {
  if (x == 0.0) return 0;
  return highest_bit(x) - lowest_bit(x) + 1;
}

int sign_q(const mpq_class& q) { return sgn(q.get_num()); }

// Builds a random expansion as the exact sum of k random doubles.
int random_expansion(Rng& r, int k, int e_lo, int e_hi, double* out, mpq_class& exact_value) {
  int n = 0;
  exact_value = 0;
  std::vector<double> tmp(k + 1);
  for (int i = 0; i < k; ++i) {
    const double x = r.value(e_lo, e_hi);
    exact_value += Q(x);
    const int m = exact::sum(n, out, 1, &x, tmp.data());
    for (int j = 0; j < m; ++j) out[j] = tmp[j];
    n = m;
  }
  return n;
}

}  // namespace

TEST_CASE("two_sum, fast_two_sum and two_diff are error-free", "[predicates][expansion]") {
  Rng r(1);
  for (int it = 0; it < 20000; ++it) {
    const int span = it % 4 == 0 ? 1100 : 60;
    const int base = r.range(-900, 900);
    double a = r.value(base, base), b = r.value(std::max(-1074, base - span), base + r.range(0, 3));
    if (it % 7 == 0) b = -a * (1 + std::ldexp(1.0, -r.range(1, 52)));  // cancellation
    double s, e;
    exact::two_sum(a, b, s, e);
    CHECK(s == a + b);
    CHECK(Q(s) + Q(e) == Q(a) + Q(b));
    CHECK((e == 0.0 || significant_bits(s) == 0 ||
           std::fabs(e) <= std::ldexp(1.0, highest_bit(s) - 53)));
    exact::two_diff(a, b, s, e);
    CHECK(Q(s) + Q(e) == Q(a) - Q(b));
    CHECK(exact::diff_tail(a, b, a - b) == e);
    const double big = std::fabs(a) >= std::fabs(b) ? a : b, small = big == a ? b : a;
    exact::fast_two_sum(big, small, s, e);
    CHECK(Q(s) + Q(e) == Q(a) + Q(b));
  }
}

TEST_CASE("Veltkamp split and Dekker two_product are exact", "[predicates][expansion]") {
  Rng r(2);
  for (int it = 0; it < 20000; ++it) {
    // Exponents such that the exact product stays a multiple of 2^-1074 and
    // the split factor cannot overflow (|x| < 2^996).
    const int ea = r.range(-480, 480), eb = r.range(-480, 480);
    const double a = r.value(ea, ea), b = r.value(eb, eb);
    double hi, lo;
    exact::split(a, hi, lo);
    CHECK(hi + lo == a);
    CHECK(Q(hi) + Q(lo) == Q(a));
    CHECK(significant_bits(hi) <= 26);
    CHECK(significant_bits(lo) <= 26);
    double p, e;
    exact::two_product(a, b, p, e);
    CHECK(p == a * b);
    CHECK(Q(p) + Q(e) == Q(a) * Q(b));
    exact::two_square(a, p, e);
    CHECK(Q(p) + Q(e) == Q(a) * Q(a));
  }
  // Extremes of the supported domain: products just above 2^-1074
  // granularity, and factors up to 2^995.
  const double tiny = std::ldexp(1.0 + std::ldexp(1.0, -52), -500);  // lowest bit 2^-552
  const double tiny2 = std::ldexp(3.0, -522);                        // lowest bit 2^-522
  double p, e;
  exact::two_product(tiny, tiny2, p, e);
  CHECK(Q(p) + Q(e) == Q(tiny) * Q(tiny2));
  const double huge = std::ldexp(1.0 + std::ldexp(1.0, -52), 995);
  exact::two_product(huge, 0.75, p, e);
  CHECK(Q(p) + Q(e) == Q(huge) * Q(0.75));
}

TEST_CASE("expansion sum, scale, compress and two_two_diff are exact and well formed",
          "[predicates][expansion]") {
  Rng r(3);
  double e[64], f[64], h[128], g[256];
  for (int it = 0; it < 5000; ++it) {
    mpq_class ve, vf;
    const int lo = r.range(-600, 0), hi = lo + r.range(0, 500);
    const int n = random_expansion(r, r.range(0, 12), lo, hi, e, ve);
    const int m = random_expansion(r, r.range(0, 12), lo, hi, f, vf);
    REQUIRE(well_formed(n, e));
    REQUIRE(well_formed(m, f));
    CHECK(value_of(n, e) == ve);
    const int nh = exact::sum(n, e, m, f, h);
    CHECK(nh <= n + m);
    CHECK(well_formed(nh, h));
    CHECK(value_of(nh, h) == ve + vf);
    CHECK(exact::sign(nh, h) == sign_q(mpq_class(ve + vf)));
    const double b = r.value(-200, 200);
    const int ng = exact::scale(nh, h, b, g);
    CHECK(ng <= 2 * nh);
    CHECK(well_formed(ng, g));
    CHECK(value_of(ng, g) == (ve + vf) * Q(b));
    double c[256];
    const int nc = exact::compress(ng, g, c);
    CHECK(nc <= ng);
    CHECK(well_formed(nc, c));
    CHECK(value_of(nc, c) == (ve + vf) * Q(b));
    if (nc > 0) {  // the top component carries the value to within one ulp of itself
      const mpq_class err = abs(value_of(nc, c) - Q(c[nc - 1]));
      CHECK(err <= Q(std::ldexp(1.0, highest_bit(c[nc - 1]) - 52)));
    }
    // Exact cancellation gives the empty expansion.
    double neg[64];
    for (int i = 0; i < n; ++i) neg[i] = -e[i];
    CHECK(exact::sum(n, e, n, neg, h) == 0);
    const double x = r.value(-300, 300), y = r.value(-300, 300), z = r.value(-300, 300),
                 w = r.value(-300, 300);
    double d[4];
    const int nd = exact::two_two_diff(x, y, z, w, d);
    CHECK(well_formed(nd, d));
    CHECK(value_of(nd, d) == Q(x) * Q(y) - Q(z) * Q(w));
    CHECK(exact::two_two_diff(x, y, y, x, d) == 0);
  }
  // Sign of an expansion whose estimate is wrong: 1 + 2^-60 - 1.
  const double parts[3] = {1.0, std::ldexp(1.0, -60), -1.0};
  double acc[8], tmp[8];
  int n = 0;
  for (double p : parts) {
    const int m = exact::sum(n, acc, 1, &p, tmp);
    for (int i = 0; i < m; ++i) acc[i] = tmp[i];
    n = m;
  }
  CHECK(n == 1);
  CHECK(acc[0] == std::ldexp(1.0, -60));
  CHECK(exact::sign(n, acc) == 1);
}
