// Exact stages of the predicates (the filters are inline in predicates.hpp),
// the 2D incircle, and the projected / coplanar helpers.
//
// Exact stage, for every predicate:
//  1. Scale the points by a power of two 2^s (exact; the sign of each
//     determinant is unchanged since it is homogeneous in the coordinates)
//     so that the largest |coordinate| is below 2^T_hi and every coordinate
//     is a multiple of 2^T_lo. T_lo makes every product of `degree`
//     coordinates a multiple of 2^-1074, so no Dekker product ever loses a
//     bit to underflow; T_hi keeps every partial sum below 2^996, so the
//     Veltkamp split never overflows. Inside the documented range, s = 0.
//  2. If the coordinates span at most 125 bits (from the lowest set bit of
//     any of them to the top of the largest: every model whose coordinates
//     share a few binades, CAD's decimal ones included), divide them by the
//     power of two of that lowest bit: they are integers below 2^125, and
//     the difference form of the determinant is evaluated in fixed-width
//     two's complement integers of one or two 64-bit limbs per difference
//     (wide_int.hpp), without a memo (far cheaper than step 4's raw form,
//     on one limb most of all).
//  3. Else, if every coordinate difference against the last point is exact in
//     double (two-diff tail 0), evaluate the difference form of the
//     determinant on those doubles: short expansions.
//  4. Otherwise evaluate the raw homogeneous form (the determinant with a
//     column of ones, and the lifted column |p|^2 for in-circle/sphere),
//     whose entries are the coordinates themselves: longer expansions
//     (the slowest stage, for insphere on full 53-bit significands most of
//     all).
// Only products of an expansion by a double are used, so every length has a
// fixed bound and the buffers live on the stack (about 170 KB at most, in
// insphere_exact; the wasm build has a 5 MB stack). Intermediate expansions
// are compressed, which keeps them to a few components in practice.
#include "predicates.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "expansion.hpp"
#include "wide_int.hpp"

namespace cdt3d {
namespace pred {

namespace detail {
thread_local Counters g_counters;
}  // namespace detail

namespace {

using detail::g_counters;

// Scaling targets (see step 1 above); T_lo = -floor(1074 / degree), T_hi from
// the largest sum of absolute monomials of each form (predicates.hpp has the
// resulting hi - lo limits).
struct ScaleLimits {
  int t_lo, t_hi;
};
constexpr ScaleLimits kOrient2dScale{-537, 490};  // 6 (2M)^2 < 2^996
constexpr ScaleLimits kOrient3dScale{-358, 320};  // 24 (2M)^3 < 2^996
constexpr ScaleLimits kIncircleScale{-268, 240};  // 192 (2M)^4 < 2^996
constexpr ScaleLimits kInsphereScale{-214, 190};  // 2304 (2M)^5 < 2^996

// Exponent of the lowest set bit of a nonzero finite double.
int lowest_bit_exponent(double x) {
  uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  const uint64_t frac = bits & ((uint64_t(1) << 52) - 1);
  if (biased == 0) return -1074 + __builtin_ctzll(frac);  // subnormal
  return biased - 1075 + __builtin_ctzll(frac | (uint64_t(1) << 52));
}

// frexp's exponent of a nonzero double: the e with 2^(e-1) <= |x| < 2^e,
// read from the bits (cheaper than a call of frexp, on the load step of
// every exact stage). 0 for inf and NaN, as glibc's frexp sets it.
int binary_exponent(double x) {
  uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  if (biased == 0x7ff) return 0;
  if (biased == 0) return (63 - __builtin_clzll(bits & ((uint64_t(1) << 52) - 1))) - 1073;
  return biased - 1022;
}

// Copies n points of `dim` coordinates into q, scaled by the power of two that
// brings them into [2^T_lo granularity, 2^T_hi magnitude] (no scaling when
// already there). Counts an out-of-range evaluation when no power of two fits;
// it then avoids overflow and may lose the lowest bits.
void load_scaled(const double* const* p, int n, int dim, ScaleLimits lim, double (*q)[3]) {
  int e_hi = INT32_MIN, e_lo = INT32_MAX;
  for (int i = 0; i < n; ++i) {
    for (int k = 0; k < dim; ++k) {
      const double x = p[i][k];
      q[i][k] = x;
      if (x == 0.0) continue;
      const int e = binary_exponent(x);  // |x| < 2^e
      if (e > e_hi) e_hi = e;
      const int l = lowest_bit_exponent(x);
      if (l < e_lo) e_lo = l;
    }
  }
  if (e_hi == INT32_MIN) return;  // all zero
  const int s_min = lim.t_lo - e_lo, s_max = lim.t_hi - e_hi;
  int s = 0;
  if (s_min > s_max) {
    ++g_counters.out_of_range;
    s = s_max;
  } else if (s_min > 0) {
    s = s_min;
  } else if (s_max < 0) {
    s = s_max;
  }
  if (s == 0) return;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < dim; ++k) q[i][k] = std::ldexp(q[i][k], s);
}

// Copies n points of `dim` coordinates into q unchanged (for the integer
// forms, which take any power-of-two scale).
void load_raw(const double* const* p, int n, int dim, double (*q)[3]) {
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < dim; ++k) q[i][k] = p[i][k];
}

// Differences q[i] - q[last] for i < last, rounded; returns whether all of
// them are exact.
bool differences(const double (*q)[3], int last, int dim, double (*d)[3]) {
  bool exact_all = true;
  for (int i = 0; i < last; ++i) {
    for (int k = 0; k < dim; ++k) {
      d[i][k] = q[i][k] - q[last][k];
      if (exact::diff_tail(q[i][k], q[last][k], d[i][k]) != 0.0) exact_all = false;
    }
  }
  return exact_all;
}

// |x| = mant 2^expo with mant odd (mant 0 for +-0), and |x| < 2^top; false
// for subnormals, infinities and NaN.
bool split_double(double x, uint64_t& mant, int& expo, int& top) {
  uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  const int biased = static_cast<int>((bits >> 52) & 0x7ff);
  const uint64_t frac = bits & ((uint64_t(1) << 52) - 1);
  mant = 0, expo = 0, top = 0;
  if (biased == 0 && frac == 0) return true;  // +-0
  if (biased == 0 || biased == 0x7ff) return false;
  const uint64_t m = frac | (uint64_t(1) << 52);
  const int tz = __builtin_ctzll(m);
  mant = m >> tz;
  expo = biased - 1075 + tz;
  top = biased - 1075 + 53;
  return true;
}

// d = x[i] - x[last] for 64-bit integer points; the limbs (1 or 2) that
// hold every difference below 2^62 or 2^126.
int int64_differences(const int64_t (*x)[3], int n, int dim, wide::i128 (*d)[3]) {
  const int last = n - 1;
  uint64_t all = 0;
  for (int i = 0; i < last; ++i)
    for (int k = 0; k < dim; ++k) {
      const int64_t v = x[i][k] - x[last][k];
      d[i][k] = v;
      all |= static_cast<uint64_t>(v < 0 ? -v : v);
    }
  return all < (uint64_t(1) << 62) ? 1 : 2;
}

// Integer differences (wide_int.hpp): every coordinate of the n points of q
// divided by 2^L, for the lowest set bit 2^L among them (exact), minus the
// last point's. Returns the number of limbs (1 or 2) that holds every
// difference below 2^62 or 2^126 in magnitude (the headroom the integer forms
// below count on), or 0 when the coordinates span more than 125 bits or one
// is subnormal, infinite or NaN: the expansion forms take those.
int integer_differences(const double (*q)[3], int n, int dim, wide::i128 (*d)[3]) {
  // The span first: the lowest set bit and the top of the largest
  // coordinate (exact, from the bits).
  uint64_t mant[5][3];
  int expo[5][3];
  int lo = INT32_MAX, hi = INT32_MIN;
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < dim; ++k) {
      int top;
      if (!split_double(q[i][k], mant[i][k], expo[i][k], top)) return 0;
      if (mant[i][k] == 0) continue;
      lo = std::min(lo, expo[i][k]);
      hi = std::max(hi, top);
    }
  int64_t x[5][3];
  if (hi != INT32_MIN && hi - lo <= 62 && lo >= -1022 && lo <= 1022) {
    // One limb, the common case: x 2^-lo is an integer below 2^62 with at
    // most 53 significant bits, so the product by the power of two (a
    // normal double for -1022 <= lo <= 1022) is exact (no rounding, no
    // overflow or underflow) and so is the conversion to int64_t.
    uint64_t scale_bits = static_cast<uint64_t>(1023 - lo) << 52;
    double scale;
    std::memcpy(&scale, &scale_bits, sizeof scale);
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < dim; ++k) x[i][k] = static_cast<int64_t>(q[i][k] * scale);
    return int64_differences(x, n, dim, d);
  }
  // Otherwise by shifts of the significands (two limbs, or a scale beyond
  // the doubles' exponent range).
  if (hi == INT32_MIN) lo = hi = 0;  // all zero
  if (hi - lo > 125) return 0;
  if (hi - lo <= 62) {
    // |X| < 2^62: the differences fit in 64 bits.
    for (int i = 0; i < n; ++i)
      for (int k = 0; k < dim; ++k) {
        // (A zero has mant 0 and no exponent: no shift.)
        const int64_t v = mant[i][k] ? static_cast<int64_t>(mant[i][k] << (expo[i][k] - lo)) : 0;
        x[i][k] = q[i][k] < 0 ? -v : v;
      }
    return int64_differences(x, n, dim, d);
  }
  const int last = n - 1;
  wide::i128 xw[5][3];
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < dim; ++k) {
      const wide::i128 v =
          mant[i][k] ? static_cast<wide::i128>(mant[i][k]) << (expo[i][k] - lo) : 0;
      xw[i][k] = q[i][k] < 0 ? -v : v;
    }
  wide::u128 all = 0;
  for (int i = 0; i < last; ++i)
    for (int k = 0; k < dim; ++k) {
      d[i][k] = xw[i][k] - xw[last][k];
      all |= static_cast<wide::u128>(d[i][k] < 0 ? -d[i][k] : d[i][k]);
    }
  return all < (static_cast<wide::u128>(1) << 62) ? 1 : 2;
}

// Rows of D-limb integers: entries below 2^(64D - 2) in magnitude.
template <int D>
struct IntRows {
  wide::Int<D> r[4][3];
  IntRows(const wide::i128 (*d)[3], int rows, int dim) {
    for (int i = 0; i < rows; ++i)
      for (int k = 0; k < dim; ++k) r[i][k] = wide::from_i128<D>(d[i][k]);
  }
};

// [PQ] = Px Qy - Py Qx: below 2 (2^(64D-2))^2 = 2^(128D-3).
template <int D>
wide::Int<2 * D> int_minor2(const wide::Int<D>* p, const wide::Int<D>* q) {
  return wide::sub(wide::mul(p[0], q[1]), wide::mul(p[1], q[0]));
}

// det | P ; Q ; R | as det3 below: below 3 2^(64D-2) 2^(128D-3) < 2^(192D-3).
template <int D>
wide::Int<3 * D> int_det3(const wide::Int<D>* p, const wide::Int<D>* q, const wide::Int<D>* r) {
  const auto a = wide::mul(p[2], int_minor2<D>(q, r));
  const auto b = wide::mul(q[2], int_minor2<D>(p, r));
  const auto c = wide::mul(r[2], int_minor2<D>(p, q));
  return wide::add(wide::sub(a, b), c);
}

// |P|^2 over dim coordinates: below 3 2^(128D-4) < 2^(128D-2).
template <int D>
wide::Int<2 * D> int_lift(const wide::Int<D>* p, int dim) {
  wide::Int<2 * D> l = wide::mul(p[0], p[0]);
  for (int k = 1; k < dim; ++k) l = wide::add(l, wide::mul(p[k], p[k]));
  return l;
}

// orient3d's difference form on integer rows: sign of det3.
template <int D>
int int_orient3d(const wide::i128 (*d)[3]) {
  const IntRows<D> m(d, 3, 3);
  return wide::sign(int_det3<D>(m.r[0], m.r[1], m.r[2]));
}

// insphere's difference form on integer rows (as insphere_rows):
// -|A|^2 [BCD] + |B|^2 [ACD] - |C|^2 [ABD] + |D|^2 [ABC], each term below
// 2^(128D-2) 2^(192D-3), the sum below 2^(320D-3): fits 5D limbs.
template <int D>
int int_insphere(const wide::i128 (*d)[3]) {
  static constexpr int kOthers[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  const IntRows<D> m(d, 4, 3);
  wide::Int<5 * D> det = wide::from_i128<5 * D>(0);
  for (int i = 0; i < 4; ++i) {
    const auto minor = int_det3<D>(m.r[kOthers[i][0]], m.r[kOthers[i][1]], m.r[kOthers[i][2]]);
    const auto term = wide::mul(int_lift<D>(m.r[i], 3), minor);
    det = i % 2 == 0 ? wide::sub(det, term) : wide::add(det, term);
  }
  return wide::sign(det);
}

// The one-limb forms again, written for the machine's 64 x 64 -> 128-bit
// multiply: the generic limb loops above take many more instructions per
// exact insphere, and co-spherical CAD points send many calls to this
// stage. Entries below 2^62 (integer_differences).
//
// A signed value below 2^189 in magnitude as hi 2^64 + lo, lo unsigned:
// what a 3x3 minor of such entries needs (< 2^189, as int_det3<1>).
struct I192 {
  wide::i128 hi;
  uint64_t lo;
};

// a += x for |x| < 2^127: x = (x >> 64) 2^64 + (uint64_t)x, >> arithmetic.
inline void add_into(I192& a, wide::i128 x) {
  const uint64_t xl = static_cast<uint64_t>(x);
  const uint64_t s = a.lo + xl;
  a.hi += (x >> 64) + static_cast<wide::i128>(s < xl);
  a.lo = s;
}

// a += f m for |f| < 2^62 and |m| < 2^125: m = mh 2^64 + ml with |mh| < 2^61,
// so f mh < 2^123 and f ml < 2^126, both exact in i128.
inline void add_product(I192& a, int64_t f, wide::i128 m) {
  const int64_t mh = static_cast<int64_t>(m >> 64);
  const uint64_t ml = static_cast<uint64_t>(m);
  a.hi += static_cast<wide::i128>(f) * mh;
  add_into(a, static_cast<wide::i128>(f) * static_cast<wide::i128>(ml));
}

// [PQ] = Px Qy - Py Qx, below 2^125: exact in i128.
inline wide::i128 minor2_1(const int64_t* p, const int64_t* q) {
  return static_cast<wide::i128>(p[0]) * q[1] - static_cast<wide::i128>(p[1]) * q[0];
}

// det | P ; Q ; R | = Pz [QR] - Qz [PR] + Rz [PQ], below 3 2^62 2^125 < 2^189.
inline I192 det3_1(const int64_t* p, const int64_t* q, const int64_t* r) {
  I192 a{0, 0};
  add_product(a, p[2], minor2_1(q, r));
  add_product(a, -q[2], minor2_1(p, r));
  add_product(a, r[2], minor2_1(p, q));
  return a;
}

// The insphere sum (below 2^317, as int_insphere<1>) as sum col[k] 2^(64 k):
// each 128-bit product adds its low half to one column and its high half to
// the next, and the carries are propagated once, in sign(). A column takes
// at most 12 halves below 2^64 in magnitude: no overflow.
struct I320 {
  wide::i128 col[5] = {0, 0, 0, 0, 0};
  template <int K>
  void add_unsigned(wide::u128 v) {
    col[K] += static_cast<uint64_t>(v);
    col[K + 1] += static_cast<uint64_t>(v >> 64);
  }
  template <int K>
  void add_signed(wide::i128 v) {
    col[K] += static_cast<uint64_t>(v);
    col[K + 1] += v >> 64;  // arithmetic: v = (v >> 64) 2^64 + (uint64_t)v
  }
  int sign() const {
    // Normalize to five unsigned limbs and a final carry c: the value is
    // c 2^320 + limbs, and |value| < 2^317 leaves c = 0 (value >= 0) or -1.
    wide::i128 carry = 0;
    uint64_t any = 0;
    for (int k = 0; k < 5; ++k) {
      const wide::i128 t = col[k] + carry;
      any |= static_cast<uint64_t>(t);
      carry = t >> 64;
    }
    return carry < 0 ? -1 : any != 0;
  }
};

// s += l d for a lift l < 2^126 (l1 2^64 + l0) and |d| < 2^189 (d = (h1 2^64
// + h0) 2^64 + lo, h1 signed): six 64 x 64 products, each exact in 128 bits
// (|l0 h1|, |l1 h1| < 2^126 since |h1| < 2^62).
inline void add_lift_times(I320& s, wide::u128 l, const I192& d) {
  const uint64_t l0 = static_cast<uint64_t>(l), l1 = static_cast<uint64_t>(l >> 64);
  const uint64_t h0 = static_cast<uint64_t>(d.hi);
  const int64_t h1 = static_cast<int64_t>(d.hi >> 64);
  s.add_unsigned<0>(static_cast<wide::u128>(l0) * d.lo);
  s.add_unsigned<1>(static_cast<wide::u128>(l1) * d.lo);
  s.add_unsigned<1>(static_cast<wide::u128>(l0) * h0);
  s.add_unsigned<2>(static_cast<wide::u128>(l1) * h0);
  s.add_signed<2>(static_cast<wide::i128>(h1) * static_cast<wide::i128>(l0));
  s.add_signed<3>(static_cast<wide::i128>(h1) * static_cast<wide::i128>(l1));
}

inline I192 negated(const I192& a) {
  return I192{-a.hi - static_cast<wide::i128>(a.lo != 0), ~a.lo + 1};
}

// |P|^2 below 3 2^124 < 2^126.
inline wide::u128 lift_1(const int64_t* p) {
  wide::u128 l = 0;
  for (int k = 0; k < 3; ++k) l += static_cast<wide::u128>(static_cast<wide::i128>(p[k]) * p[k]);
  return l;
}

int int_orient3d_1(const wide::i128 (*d)[3]) {
  int64_t r[3][3];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 3; ++k) r[i][k] = static_cast<int64_t>(d[i][k]);
  const I192 det = det3_1(r[0], r[1], r[2]);
  return det.hi < 0 ? -1 : (det.hi != 0 || det.lo != 0);
}

// As int_insphere<1>: -|A|^2 [BCD] + |B|^2 [ACD] - |C|^2 [ABD] + |D|^2 [ABC].
int int_insphere_1(const wide::i128 (*d)[3]) {
  int64_t r[4][3];
  for (int i = 0; i < 4; ++i)
    for (int k = 0; k < 3; ++k) r[i][k] = static_cast<int64_t>(d[i][k]);
  static constexpr int kOthers[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  I320 sum;
  for (int i = 0; i < 4; ++i) {
    const I192 minor = det3_1(r[kOthers[i][0]], r[kOthers[i][1]], r[kOthers[i][2]]);
    add_lift_times(sum, lift_1(r[i]), i % 2 == 0 ? negated(minor) : minor);
  }
  return sum.sign();
}

// As int_incircle<1>: la [BC] + lb [CA] + lc [AB], 2D lifts below 2^125 and
// minors below 2^125, each term below 2^250.
int int_incircle_1(const wide::i128 (*d)[3]) {
  int64_t r[3][2];
  for (int i = 0; i < 3; ++i)
    for (int k = 0; k < 2; ++k) r[i][k] = static_cast<int64_t>(d[i][k]);
  I320 sum;
  for (int i = 0; i < 3; ++i) {
    const wide::i128 minor = minor2_1(r[(i + 1) % 3], r[(i + 2) % 3]);
    const wide::u128 lift = static_cast<wide::u128>(static_cast<wide::i128>(r[i][0]) * r[i][0]) +
                            static_cast<wide::u128>(static_cast<wide::i128>(r[i][1]) * r[i][1]);
    add_lift_times(sum, lift, I192{minor >> 64, static_cast<uint64_t>(minor)});
  }
  return sum.sign();
}

// incircle's difference form on integer rows (as incircle_rows):
// la [BC] + lb [CA] + lc [AB], each term below 2^(128D-3) 2^(128D-3), the sum
// below 2^(256D-4): fits 4D limbs.
template <int D>
int int_incircle(const wide::i128 (*d)[3]) {
  const IntRows<D> m(d, 3, 2);
  wide::Int<4 * D> det = wide::from_i128<4 * D>(0);
  for (int i = 0; i < 3; ++i) {
    const auto minor = int_minor2<D>(m.r[(i + 1) % 3], m.r[(i + 2) % 3]);
    det = wide::add(det, wide::mul(int_lift<D>(m.r[i], 2), minor));
  }
  return wide::sign(det);
}

// det | P ; Q ; R | of three 3-vectors of doubles, expanded along z over the
// xy 2x2 minors: Pz (QxRy - QyRx) - Qz (PxRy - PyRx) + Rz (PxQy - PyQx).
// Output capacity 24.
int det3(const double* p, const double* q, const double* r, double* out) {
  double qr[4], pr[4], pq[4], t[4], t1[8], t2[8], t3[8], u[16];
  const int nqr = exact::compress(exact::two_two_diff(q[0], r[1], q[1], r[0], t), t, qr);
  const int npr = exact::compress(exact::two_two_diff(p[0], r[1], p[1], r[0], t), t, pr);
  const int npq = exact::compress(exact::two_two_diff(p[0], q[1], p[1], q[0], t), t, pq);
  const int n1 = exact::scale(nqr, qr, p[2], t1);
  const int n2 = exact::scale(npr, pr, -q[2], t2);
  const int n3 = exact::scale(npq, pq, r[2], t3);
  const int nu = exact::sum(n1, t1, n2, t2, u);
  return exact::sum(nu, u, n3, t3, out);
}

// The xy minors of every pair and the xyz minors of every triple of up to
// five raw points, shared by the raw orient3d of each four of them:
// [ijk] = z_i [jk] - z_j [ik] + z_k [ij], [ij] = x_i y_j - y_i x_j.
struct RawMinors {
  int pair[5][5];
  int triple[5][5][5];
  int n2[10], n3[10];
  double m2[10][4];
  double m3[10][24];
};

void raw_minors(const double (*q)[3], int n, RawMinors& r) {
  int np = 0;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      double t[4];
      r.pair[i][j] = np;
      r.n2[np] =
          exact::compress(exact::two_two_diff(q[i][0], q[j][1], q[i][1], q[j][0], t), t, r.m2[np]);
      ++np;
    }
  int nt = 0;
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j)
      for (int k = j + 1; k < n; ++k) {
        const int jk = r.pair[j][k], ik = r.pair[i][k], ij = r.pair[i][j];
        double t1[8], t2[8], t3[8], u[16], v[24];
        const int n1 = exact::scale(r.n2[jk], r.m2[jk], q[i][2], t1);
        const int n2 = exact::scale(r.n2[ik], r.m2[ik], -q[j][2], t2);
        const int n3 = exact::scale(r.n2[ij], r.m2[ij], q[k][2], t3);
        const int nu = exact::sum(n1, t1, n2, t2, u);
        r.triple[i][j][k] = nt;
        r.n3[nt] = exact::compress(exact::sum(nu, u, n3, t3, v), v, r.m3[nt]);
        ++nt;
      }
}

// det | p 1 ; q 1 ; r 1 ; s 1 | (raw orient3d) for point indices p < q < r
// < s, expanded along the column of ones: -[qrs] + [prs] - [pqs] + [pqr].
// Output capacity 96.
int raw_orient3d(const RawMinors& m, int p, int q, int r, int s, double* out) {
  double neg[2][24], u[48], v[48];
  const int a = m.triple[q][r][s], b = m.triple[p][r][s];
  const int c = m.triple[p][q][s], d = m.triple[p][q][r];
  for (int i = 0; i < m.n3[a]; ++i) neg[0][i] = -m.m3[a][i];
  for (int i = 0; i < m.n3[c]; ++i) neg[1][i] = -m.m3[c][i];
  const int nu = exact::sum(m.n3[a], neg[0], m.n3[b], m.m3[b], u);
  const int nv = exact::sum(m.n3[c], neg[1], m.n3[d], m.m3[d], v);
  return exact::sum(nu, u, nv, v, out);
}

// out = sign * (p_0^2 + ... + p_{dim-1}^2) * m. The lift is formed exactly
// (at most 2 dim components, compressed: usually 2 or 3), then m is scaled by
// each of its components and the products summed. Capacity of out: 4 dim N.
template <int N>
int times_lift(int n, const double* m, const double* p, int dim, bool negative, double* out) {
  double sq[3][2], l4[4], l6[6], lift[6];
  for (int k = 0; k < dim; ++k) exact::two_square(p[k], sq[k][1], sq[k][0]);
  int nl = exact::sum(2, sq[0], 2, sq[1], l4);
  const double* raw_lift = l4;
  if (dim == 3) {
    nl = exact::sum(nl, l4, 2, sq[2], l6);
    raw_lift = l6;
  }
  nl = exact::compress(nl, raw_lift, lift);
  if (negative) exact::negate(nl, lift);
  double t[2 * N], acc[2][12 * N];
  int nacc = 0, cur = 0;
  for (int j = 0; j < nl; ++j) {
    const int nt = exact::scale(n, m, lift[j], t);
    double* dst = j + 1 == nl ? out : acc[1 - cur];
    nacc = exact::sum(nacc, acc[cur], nt, t, dst);
    cur = 1 - cur;
  }
  return nacc;
}

// 2D: det | p 1 ; q 1 ; r 1 | over the xy minors: [qr] - [pr] + [pq].
// Output capacity 12.
int raw_orient2d(const double* p, const double* q, const double* r, double* out) {
  double qr[4], pr[4], pq[4], u[8];
  const int nqr = exact::two_two_diff(q[0], r[1], q[1], r[0], qr);
  const int npr = exact::two_two_diff(p[0], r[1], p[1], r[0], pr);
  const int npq = exact::two_two_diff(p[0], q[1], p[1], q[0], pq);
  exact::negate(npr, pr);
  const int nu = exact::sum(nqr, qr, npr, pr, u);
  return exact::sum(nu, u, npq, pq, out);
}

// Memos of exact results (insphere_exact, incircle_exact): direct-mapped
// tables keyed by the points' rows in sorted order; a hit compares all rows,
// so a collision only costs a recomputation.
template <int N, int D>
struct Memo {
  double rows[N][D];
  int8_t sign;
  bool used;
};
// One table per thread (tetrahedralize() may run on several threads at once,
// and runs its self-intersection test beside steps 1-2), allocated by the
// thread's first memoized call: calloc leaves the pages no slot touches
// unmapped, like the zero-initialized static arrays this replaces. Without
// memory the call is computed without the memo.
template <int N, int D, size_t Slots>
class MemoTable {
 public:
  MemoTable() = default;
  MemoTable(const MemoTable&) = delete;
  MemoTable& operator=(const MemoTable&) = delete;
  ~MemoTable() { std::free(slots_); }
  Memo<N, D>* get() {
    if (!slots_) slots_ = static_cast<Memo<N, D>*>(std::calloc(Slots, sizeof(Memo<N, D>)));
    return slots_;
  }

 private:
  Memo<N, D>* slots_ = nullptr;
};
// 16384 slots (2 MiB): a balance between the share of calls that hit and
// the memory (and first-touch page faults) of a thread's table. Only
// coordinates spanning more than 125 bits reach it; the integer stage
// decides the others.
thread_local MemoTable<5, 3, 16384> t_insphere_memo;
// The 2D facet triangulations test each edge from both sides, the same four
// points in another order (half the exact calls there).
thread_local MemoTable<4, 2, 4096> t_incircle_memo;

// Sorts the N rows of q lexicographically; returns the parity of the
// permutation (+1 even, -1 odd).
template <int N, int D>
int sort_rows(double (*q)[D]) {
  int parity = 1;
  for (int i = 1; i < N; ++i)
    for (int j = i;
         j > 0 && std::lexicographical_compare(q[j], q[j] + D, q[j - 1], q[j - 1] + D); --j) {
      std::swap_ranges(q[j], q[j] + D, q[j - 1]);
      parity = -parity;
    }
  return parity;
}

template <int N, int D>
size_t memo_slot(const double (*q)[D], size_t slots) {
  uint64_t h = 1469598103934665603ull;
  for (int i = 0; i < N; ++i)
    for (int k = 0; k < D; ++k) {
      uint64_t bits;
      std::memcpy(&bits, &q[i][k], sizeof bits);
      h = (h ^ bits) * 1099511628211ull;
      h ^= h >> 29;
    }
  return static_cast<size_t>(h % slots);
}

// The memoized sign of the determinant of the N rows of q (sorted in place),
// `compute` evaluating it on the sorted rows.
template <int N, int D, size_t Slots, typename Compute>
int memoized_sign(double (*q)[D], MemoTable<N, D, Slots>& memos, Compute compute) {
  const int parity = sort_rows<N, D>(q);
  Memo<N, D>* table = memos.get();
  if (!table) return parity * compute(q);
  Memo<N, D>& memo = table[memo_slot<N, D>(q, Slots)];
  if (memo.used && std::memcmp(memo.rows, q, sizeof memo.rows) == 0) return parity * memo.sign;
  const int sign = compute(q);
  std::memcpy(memo.rows, q, sizeof memo.rows);
  memo.sign = static_cast<int8_t>(sign);
  memo.used = true;
  return parity * sign;
}

// insphere of the five (scaled) rows of q, exact: the difference form when
// the differences are exact, else the raw form.
int insphere_rows(const double (*q)[3]) {
  double diff[4][3];
  if (differences(q, 4, 3, diff)) {
    // Rows A..D = a..d - e: det | A |A|^2 ; ... | expanded along the lift
    // column: -|A|^2 [BCD] + |B|^2 [ACD] - |C|^2 [ABD] + |D|^2 [ABC].
    static constexpr int kOthers[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
    double m3[24], m[24], terms[4][288], u[576], v[576], det[1152];
    int nt[4];
    for (int i = 0; i < 4; ++i) {
      const int nm = exact::compress(
          det3(diff[kOthers[i][0]], diff[kOthers[i][1]], diff[kOthers[i][2]], m3), m3, m);
      nt[i] = times_lift<24>(nm, m, diff[i], 3, i % 2 == 0, terms[i]);
    }
    const int nu = exact::sum(nt[0], terms[0], nt[1], terms[1], u);
    const int nv = exact::sum(nt[2], terms[2], nt[3], terms[3], v);
    return exact::sign(exact::sum(nu, u, nv, v, det), det);
  }
  // Raw form: det | p |p|^2 1 | over the five points, expanded along the lift
  // column: sum_i (-1)^(i+1) |p_i|^2 orient3d(the other four, in order)
  // (0-based i). It equals the difference form (subtract the last row, then
  // the column operations |p|^2 - |e|^2 -> |p - e|^2).
  static constexpr int kOthers[5][4] = {
      {1, 2, 3, 4}, {0, 2, 3, 4}, {0, 1, 3, 4}, {0, 1, 2, 4}, {0, 1, 2, 3}};
  RawMinors m;
  raw_minors(q, 5, m);
  double o[96], oc[96], term[1152], acc[2][5760];
  int nacc = 0;
  for (int i = 0; i < 5; ++i) {
    const int* k = kOthers[i];
    const int no = exact::compress(raw_orient3d(m, k[0], k[1], k[2], k[3], o), o, oc);
    const int nterm = times_lift<96>(no, oc, q[i], 3, i % 2 == 0, term);
    nacc = exact::sum(nacc, acc[0], nterm, term, acc[1]);
    nacc = exact::compress(nacc, acc[1], acc[0]);
  }
  return exact::sign(nacc, acc[0]);
}

}  // namespace

namespace detail {

// The row of a column of coordinate differences that is its only nonzero
// entry, or -1 (none, or more than one). A computed difference is 0 exactly
// when the coordinates are equal (see orient3d), so the test is exact.
int single_nonzero_row(const double* col, int rows) {
  int row = -1;
  for (int r = 0; r < rows; ++r)
    if (col[r] != 0) {
      if (row >= 0) return -1;
      row = r;
    }
  return row;
}

// Points that share an axis-parallel plane with the reference point but one
// (CAD and thin-plate models: a tet with three vertices on a face of the
// part and one off it, tested against a point of that face): expanding the
// determinant along that column leaves one entry times a 2D determinant of
// the other rows in the two remaining coordinates, which the exact 2D
// predicates evaluate far more cheaply than the 3D exact stage. Entry (i, k)
// of an n x n determinant carries the cofactor sign (-1)^(i + k); dropping
// coordinate k keeps the other two in order (and, for insphere, the lift,
// whose k term is 0 on those rows), so the minor is orient2d / incircle of
// the projected points in the given order.
inline void projected(const double* p, int k, double* out) {
  out[0] = p[k == 0 ? 1 : 0];
  out[1] = p[k == 2 ? 1 : 2];
}

// The expansion for N rows (points p[0..N-1] minus ref, columns cols[k]):
// the sign, or 2 when no column has a single nonzero row. minor2d takes the
// N projected points (the other rows', then ref's).
template <int N, typename Minor2d>
int sign_by_single_column(const double* const* p, const double* ref, const double (*cols)[N],
                          Minor2d minor2d) {
  for (int k = 0; k < 3; ++k) {
    const int i = single_nonzero_row(cols[k], N);
    if (i < 0) continue;
    double q[N][2];
    for (int r = 0, n = 0; r < N; ++r)
      if (r != i) projected(p[r], k, q[n++]);
    projected(ref, k, q[N - 1]);
    return ((i + k) % 2 == 0 ? 1 : -1) * sign_of(cols[k][i]) * minor2d(q);
  }
  return 2;
}

int orient3d_undecided(const double* a, const double* b, const double* c, const double* d) {
  const Orient3dTerms t = orient3d_terms(a, b, c, d);
  // Small integer coordinates (grid and many CAD models, where the filter
  // fails on every exactly coplanar quadruple): the evaluation of the filter
  // is exact (kOrient3dSmallInteger), so its sign is the answer.
  if (t.sx + t.sy + t.sz <= kOrient3dSmallInteger && integers({a, b, c, d})) return sign_of(t.det);
  // Four points in one axis-parallel plane (CAD models; nearly all the exact
  // zeros there): a column of the matrix is zero, so the determinant is. A
  // computed difference is 0 exactly when the two coordinates are equal (x - y
  // rounds to 0 only for x == y, subnormals included), so the test is exact.
  if (zero_column(t.adx, t.bdx, t.cdx, 0) | zero_column(t.ady, t.bdy, t.cdy, 0) |
      zero_column(t.adz, t.bdz, t.cdz, 0))
    return 0;
  const double* p[3] = {a, b, c};
  const double cols[3][3] = {{t.adx, t.bdx, t.cdx}, {t.ady, t.bdy, t.cdy}, {t.adz, t.bdz, t.cdz}};
  const int s = sign_by_single_column<3>(p, d, cols, [](const double (*q)[2]) {
    return orient2d(q[0], q[1], q[2]);
  });
  if (s != 2) return s;
  return orient3d_exact(a, b, c, d);
}

int insphere_undecided(const double* a, const double* b, const double* c, const double* d,
                       const double* e) {
  const InsphereTerms t = insphere_terms(a, b, c, d, e);
  // As in orient3d: exact for small integer coordinates (co-spherical grid
  // points reach this line on every tie).
  if (t.sx + t.sy + t.sz <= kInsphereSmallInteger && integers({a, b, c, d, e}))
    return sign_of(t.det);
  // Five points in one axis-parallel plane: a zero column again (see orient3d).
  if (zero_column(t.aex, t.bex, t.cex, t.dex) | zero_column(t.aey, t.bey, t.cey, t.dey) |
      zero_column(t.aez, t.bez, t.cez, t.dez))
    return 0;
  const double* p[4] = {a, b, c, d};
  const double cols[3][4] = {{t.aex, t.bex, t.cex, t.dex},
                             {t.aey, t.bey, t.cey, t.dey},
                             {t.aez, t.bez, t.cez, t.dez}};
  const int s = sign_by_single_column<4>(p, e, cols, [](const double (*q)[2]) {
    return incircle(q[0], q[1], q[2], q[3]);
  });
  if (s != 2) return s;
  if (insphere_in_range(t)) {
    const double rows[4][3] = {
        {t.aex, t.aey, t.aez}, {t.bex, t.bey, t.bez}, {t.cex, t.cey, t.cez}, {t.dex, t.dey, t.dez}};
    const double lifts[4] = {t.la, t.lb, t.lc, t.ld};
    const double perm = insphere_permanent(rows, lifts);
    if ((std::fabs(t.det) > kInspherePermanentEps * perm) & (perm >= kInspherePermanentLo))
      return sign_of(t.det);
  }
  return insphere_exact(a, b, c, d, e);
}

int orient3d_exact(const double* a, const double* b, const double* c, const double* d) {
  ++g_counters.orient3d_exact;
  const double* p[4] = {a, b, c, d};
  double q[4][3], diff[3][3];
  // The integer form first, on the coordinates as they are: a power-of-two
  // scale does not change its sign, so it needs no load_scaled.
  load_raw(p, 4, 3, q);
  wide::i128 xd[3][3];
  if (const int limbs = integer_differences(q, 4, 3, xd))
    return limbs == 1 ? int_orient3d_1(xd) : int_orient3d<2>(xd);
  load_scaled(p, 4, 3, kOrient3dScale, q);
  if (differences(q, 3, 3, diff)) {
    double det[24];
    return exact::sign(det3(diff[0], diff[1], diff[2], det), det);
  }
  RawMinors m;
  raw_minors(q, 4, m);
  double det[96];
  return exact::sign(raw_orient3d(m, 0, 1, 2, 3, det), det);
}

double insphere_permanent(const double (&r)[4][3], const double (&lift)[4]) {
  const double aex = r[0][0], aey = r[0][1], aez = std::fabs(r[0][2]);
  const double bex = r[1][0], bey = r[1][1], bez = std::fabs(r[1][2]);
  const double cex = r[2][0], cey = r[2][1], cez = std::fabs(r[2][2]);
  const double dex = r[3][0], dey = r[3][1], dez = std::fabs(r[3][2]);
  const double ab = std::fabs(aex * bey) + std::fabs(bex * aey);
  const double bc = std::fabs(bex * cey) + std::fabs(cex * bey);
  const double cd = std::fabs(cex * dey) + std::fabs(dex * cey);
  const double da = std::fabs(dex * aey) + std::fabs(aex * dey);
  const double ac = std::fabs(aex * cey) + std::fabs(cex * aey);
  const double bd = std::fabs(bex * dey) + std::fabs(dex * bey);
  const double abc = aez * bc + bez * ac + cez * ab;
  const double bcd = bez * cd + cez * bd + dez * bc;
  const double cda = cez * da + dez * ac + aez * cd;
  const double dab = dez * ab + aez * bd + bez * da;
  return (lift[3] * abc + lift[2] * dab) + (lift[1] * cda + lift[0] * bcd);
}

int insphere_exact(const double* a, const double* b, const double* c, const double* d,
                   const double* e) {
  ++g_counters.insphere_exact;
  const double* p[5] = {a, b, c, d, e};
  double q[5][3];
  // Coordinates within 125 bits of each other: the integer form, cheaper
  // than a memo lookup (whose 2 MiB table also costs page faults on first
  // touch). On the coordinates as they are: a power-of-two scale does not
  // change its sign, so load_scaled's pass over the points is skipped.
  load_raw(p, 5, 3, q);
  wide::i128 xd[4][3];
  if (const int limbs = integer_differences(q, 5, 3, xd))
    return limbs == 1 ? int_insphere_1(xd) : int_insphere<2>(xd);
  load_scaled(p, 5, 3, kInsphereScale, q);
  // The expansion forms cost microseconds on 53-bit coordinates, and the
  // same five points come back: the search for the perturbation order
  // (sos_order.cpp) builds the Delaunay tetrahedralization of one point set
  // several times. Memoized on the rows in sorted order (the determinant
  // changes sign with the permutation).
  return memoized_sign(q, t_insphere_memo, [](const double (*rows)[3]) { return insphere_rows(rows); });
}

int orient2d_exact(double ax, double ay, double bx, double by, double cx, double cy) {
  ++g_counters.orient2d_exact;
  const double xy[3][2] = {{ax, ay}, {bx, by}, {cx, cy}};
  const double* p[3] = {xy[0], xy[1], xy[2]};
  double q[3][3], diff[2][3];
  load_scaled(p, 3, 2, kOrient2dScale, q);
  if (differences(q, 2, 2, diff)) {
    double det[4];
    return exact::sign(exact::two_two_diff(diff[0][0], diff[1][1], diff[0][1], diff[1][0], det),
                       det);
  }
  double det[12];
  return exact::sign(raw_orient2d(q[0], q[1], q[2], det), det);
}

}  // namespace detail

namespace {

// incircle filter constants (same scheme as predicates.hpp):
//   det = (la*bc + lb*ca) + lc*ab, rows A..C = a..c - d, l = Ax^2 + Ay^2,
//   minors 2 roundings, lifts 2, product 1, two sums: k = 7, g = 4;
//   S <= 2 Mx My (la + lb + lc); (1+u)^11 - 1 < 11.0000001u;
//   22u(1 + 8u) = 2.44249e-15 < 2.45e-15 (margin 0.068u). Column sums as in
//   predicates.hpp: every M >= 2^-230 (s >= 2^-228) keeps the bound normal
//   and the underflow error (<= 2^-1069 (Mmax^2 + 1)) below the margin;
//   s_x + s_y <= 2^240 rules out overflow.
constexpr double kIncircleEps = 2.45e-15;
constexpr double kIncircleLo = 0x1p-228, kIncircleHi = 0x1p+240;
// Second stage with the computed permanent P (as insphere's, predicates.hpp):
//   ((1+u)^11 - 1)(1-u)^-7 < 11.1u, fl(C P) one more (1 - u): C = 1.34e-15
//   (12.07u). Underflow: under the first stage's limits the error is below
//   2^-1069 (2^480 + 1) < 2^-588; P >= 2^-500 keeps the margin 0.9u P above it.
constexpr double kIncirclePermanentEps = 1.34e-15;
constexpr double kIncirclePermanentLo = 0x1p-500;

// P of incircle's second stage: its expression tree on absolute values.
double incircle_permanent(double adx, double ady, double bdx, double bdy, double cdx, double cdy) {
  const double bc = std::fabs(bdx * cdy) + std::fabs(bdy * cdx);
  const double ca = std::fabs(cdx * ady) + std::fabs(cdy * adx);
  const double ab = std::fabs(adx * bdy) + std::fabs(ady * bdx);
  const double la = adx * adx + ady * ady;
  const double lb = bdx * bdx + bdy * bdy;
  const double lc = cdx * cdx + cdy * cdy;
  return (la * bc + lb * ca) + lc * ab;
}

// incircle of the four rows of r (x, y), exact.
int incircle_rows(const double (*r)[2]) {
  const double* p[4] = {r[0], r[1], r[2], r[3]};
  double q[4][3], diff[3][3];
  load_scaled(p, 4, 2, kIncircleScale, q);
  if (differences(q, 3, 2, diff)) {
    // la [BC] + lb [CA] + lc [AB], [PQ] = Px Qy - Py Qx.
    double m[4], terms[3][32], u[64], det[96];
    int nt[3];
    for (int i = 0; i < 3; ++i) {
      const double* s = diff[(i + 1) % 3];
      const double* t = diff[(i + 2) % 3];
      const int nm = exact::two_two_diff(s[0], t[1], s[1], t[0], m);
      nt[i] = times_lift<4>(nm, m, diff[i], 2, false, terms[i]);
    }
    const int nu = exact::sum(nt[0], terms[0], nt[1], terms[1], u);
    return exact::sign(exact::sum(nu, u, nt[2], terms[2], det), det);
  }
  // Raw form: sum_i (-1)^i |p_i|^2 orient2d(the other three) (0-based i).
  static constexpr int kOthers[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  double o[12], oc[12], term[96], acc[2][384];
  int nacc = 0;
  for (int i = 0; i < 4; ++i) {
    const int* k = kOthers[i];
    const int no = exact::compress(raw_orient2d(q[k[0]], q[k[1]], q[k[2]], o), o, oc);
    const int nterm = times_lift<12>(no, oc, q[i], 2, i % 2 == 1, term);
    nacc = exact::sum(nacc, acc[0], nterm, term, acc[1]);
    nacc = exact::compress(nacc, acc[1], acc[0]);
  }
  return exact::sign(nacc, acc[0]);
}

int incircle_exact(const double* a, const double* b, const double* c, const double* d) {
  ++g_counters.incircle_exact;
  // The integer form first, without the memo (as insphere_exact).
  const double xy[4][3] = {{a[0], a[1], 0}, {b[0], b[1], 0}, {c[0], c[1], 0}, {d[0], d[1], 0}};
  wide::i128 xd[3][3];
  if (const int limbs = integer_differences(xy, 4, 2, xd))
    return limbs == 1 ? int_incircle_1(xd) : int_incircle<2>(xd);
  double r[4][2] = {{a[0], a[1]}, {b[0], b[1]}, {c[0], c[1]}, {d[0], d[1]}};
  return memoized_sign(r, t_incircle_memo, [](const double (*rows)[2]) { return incircle_rows(rows); });
}

}  // namespace

int incircle(const double* a, const double* b, const double* c, const double* d) {
  detail::count_call(g_counters.incircle_calls);
  const double adx = a[0] - d[0], ady = a[1] - d[1];
  const double bdx = b[0] - d[0], bdy = b[1] - d[1];
  const double cdx = c[0] - d[0], cdy = c[1] - d[1];
  const double bc = bdx * cdy - bdy * cdx;
  const double ca = cdx * ady - cdy * adx;
  const double ab = adx * bdy - ady * bdx;
  const double la = adx * adx + ady * ady;
  const double lb = bdx * bdx + bdy * bdy;
  const double lc = cdx * cdx + cdy * cdy;
  const double det = (la * bc + lb * ca) + lc * ab;
  const double sx = (std::fabs(adx) + std::fabs(bdx)) + std::fabs(cdx);
  const double sy = (std::fabs(ady) + std::fabs(bdy)) + std::fabs(cdy);
  const double bound = kIncircleEps * sx * sy * ((la + lb) + lc);
  const bool decided = (std::fabs(det) > bound) & (sx >= kIncircleLo) & (sy >= kIncircleLo) &
                       (sx + sy <= kIncircleHi);
  if (decided) return detail::sign_of(det);
  // Four points on one axis-parallel line: a zero column (see orient3d).
  if (detail::zero_column(adx, bdx, cdx, 0) | detail::zero_column(ady, bdy, cdy, 0)) return 0;
  if ((sx >= kIncircleLo) & (sy >= kIncircleLo) & (sx + sy <= kIncircleHi)) {
    const double perm = incircle_permanent(adx, ady, bdx, bdy, cdx, cdy);
    if ((std::fabs(det) > kIncirclePermanentEps * perm) & (perm >= kIncirclePermanentLo))
      return detail::sign_of(det);
  }
  return incircle_exact(a, b, c, d);
}

BoxBounds box_bounds(const double* coords, size_t n, double widen) {
  if (n == 0) return {};
  BoxBounds b;
  double w[3];
  for (int k = 0; k < 3; ++k) {
    double lo = coords[k], hi = coords[k];
    for (size_t i = 0; i < n; ++i) {
      const double x = coords[3 * i + k];
      if (std::isnan(x)) return {};
      lo = std::min(lo, x), hi = std::max(hi, x);
    }
    const double margin = widen * (hi - lo);
    b.lo[k] = lo - margin, b.hi[k] = hi + margin;
    // The width of the box as stored: what contains() tests is what the
    // bounds cover (infinities fail the range test below).
    w[k] = b.hi[k] - b.lo[k];
    if (!(w[k] >= detail::kBoxWidthLo && w[k] <= detail::kBoxWidthHi)) return {};
  }
  b.orient3d = detail::kOrient3dBoxEps * (w[0] * w[1] * w[2]);
  b.insphere = detail::kInsphereBoxEps * (w[0] * w[1] * w[2]) *
               ((w[0] * w[0] + w[1] * w[1]) + w[2] * w[2]);
  return b;
}

int detail::orient3d_out_of_line(const double* a, const double* b, const double* c,
                                 const double* d) {
  return orient3d(a, b, c, d);
}

int detail::insphere_out_of_line(const double* a, const double* b, const double* c,
                                 const double* d, const double* e) {
  return insphere(a, b, c, d, e);
}

bool small_integer_points(const double* coords, size_t n) {
  if (n == 0) return false;
  for (int k = 0; k < 3; ++k) {
    double lo = coords[k], hi = coords[k];
    for (size_t i = 0; i < n; ++i) {
      const double x = coords[3 * i + k];
      if (!detail::small_integer(x)) return false;
      lo = std::min(lo, x), hi = std::max(hi, x);
    }
    if (hi - lo > kSmallIntegerSpread) return false;
  }
  return true;
}

int orient2d_projected(const double* a, const double* b, const double* c, int drop) {
  const int i = drop == 0 ? 1 : drop == 1 ? 2 : 0;
  const int j = drop == 0 ? 2 : drop == 1 ? 0 : 1;
  return detail::orient2d_xy(a[i], a[j], b[i], b[j], c[i], c[j]);
}

int orient2d_centroid_projected(const double* a, const double* b, const double* const c[3], int drop) {
  const int i = drop == 0 ? 1 : drop == 1 ? 2 : 0;
  const int j = drop == 0 ? 2 : drop == 1 ? 0 : 1;
  double xy[5][2] = {{a[i], a[j]}, {b[i], b[j]}};
  for (int k = 0; k < 3; ++k) xy[2 + k][0] = c[k][i], xy[2 + k][1] = c[k][j];
  const double* p[5] = {xy[0], xy[1], xy[2], xy[3], xy[4]};
  // One power-of-two scale for all five points keeps every product exact; a
  // sum of three determinants stays far from overflow within orient2d's range.
  double q[5][3];
  load_scaled(p, 5, 2, kOrient2dScale, q);
  double det[12], acc[36], tmp[36];
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const int m = raw_orient2d(q[0], q[1], q[2 + k], det);
    const int total = exact::sum(n, acc, m, det, tmp);
    std::copy(tmp, tmp + total, acc);
    n = total;
  }
  return exact::sign(n, acc);
}

int orient3d_centroid(const double* a, const double* b, const double* c, const double* const p[3]) {
  const double* pts[6] = {a, b, c, p[0], p[1], p[2]};
  // One power-of-two scale for all six points, as in orient3d_exact.
  double q[6][3];
  load_scaled(pts, 6, 3, kOrient3dScale, q);
  double det[96], acc[288], tmp[288];
  int n = 0;
  for (int k = 0; k < 3; ++k) {
    const double four[4][3] = {{q[0][0], q[0][1], q[0][2]},
                               {q[1][0], q[1][1], q[1][2]},
                               {q[2][0], q[2][1], q[2][2]},
                               {q[3 + k][0], q[3 + k][1], q[3 + k][2]}};
    RawMinors m;
    raw_minors(four, 4, m);
    const int nd = raw_orient3d(m, 0, 1, 2, 3, det);
    const int total = exact::sum(n, acc, nd, det, tmp);
    std::copy(tmp, tmp + total, acc);
    n = total;
  }
  return exact::sign(n, acc);
}

bool collinear3d(const double* a, const double* b, const double* c) {
  // The cross product (b - a) x (c - a) has the three projected orientations
  // as its components.
  return orient2d_projected(a, b, c, 2) == 0 && orient2d_projected(a, b, c, 0) == 0 &&
         orient2d_projected(a, b, c, 1) == 0;
}

int dot_sign(const double* a, const double* v, const double* b) { return dot_sign(a, v, b, v); }

int dot_sign(const double* a, const double* v, const double* b, const double* w) {
  double approx = 0, magnitude = 0;
  for (int d = 0; d < 3; ++d) {
    const double x = (a[d] - v[d]) * (b[d] - w[d]);
    approx += x;
    magnitude += std::fabs(x);
  }
  // Each difference, product and sum rounds once: the error is below
  // 8 ulp-units of the magnitude sum.
  const double bound = 8 * 1.1102230246251565e-16 * magnitude;
  if (approx > bound) return 1;
  if (-approx > bound) return -1;
  double acc[24], tmp[24];
  int n = 0;
  for (int d = 0; d < 3; ++d) {
    double x[2], y[2];  // exact differences as expansions (small component first)
    exact::two_diff(a[d], v[d], x[1], x[0]);
    exact::two_diff(b[d], w[d], y[1], y[0]);
    const int nx = x[1] == 0 ? 0 : (x[0] == 0 ? 1 : 2);
    const double* xs = nx == 1 ? x + 1 : x;
    double p0[4], p1[4], prod[8];
    int np = 0;
    if (nx > 0) {
      const int n0 = exact::scale(nx, xs, y[0], p0);
      const int n1 = exact::scale(nx, xs, y[1], p1);
      np = exact::sum(n0, p0, n1, p1, prod);
    }
    const int m = exact::sum(n, acc, np, prod, tmp);
    std::copy(tmp, tmp + m, acc);
    n = m;
  }
  return exact::sign(n, acc);
}


int incircle_coplanar_small_integers(const double* a, const double* b, const double* c,
                                     const double* d) {
  for (int k = 0; k < 3; ++k) {
    if (a[k] != b[k] || a[k] != c[k] || a[k] != d[k]) continue;
    const int x = k == 0 ? 1 : 0, y = k == 2 ? 1 : 2;  // the other two axes
    const double acx = a[x] - c[x], acy = a[y] - c[y], bcx = b[x] - c[x], bcy = b[y] - c[y];
    const int o = detail::sign_of(acx * bcy - acy * bcx);
    if (o == 0) return 0;
    detail::count_call(g_counters.incircle_calls);
    const double adx = a[x] - d[x], ady = a[y] - d[y];
    const double bdx = b[x] - d[x], bdy = b[y] - d[y];
    const double cdx = c[x] - d[x], cdy = c[y] - d[y];
    const double det = (adx * adx + ady * ady) * (bdx * cdy - bdy * cdx) +
                       (bdx * bdx + bdy * bdy) * (cdx * ady - cdy * adx) +
                       (cdx * cdx + cdy * cdy) * (adx * bdy - ady * bdx);
    return o * detail::sign_of(det);
  }
  return incircle_coplanar(a, b, c, d);
}

int incircle_coplanar(const double* a, const double* b, const double* c, const double* d) {
  // Four points in one axis-parallel plane (the hull faces of CAD models,
  // tested by every ghost tet in conflict search): dropping that coordinate
  // is exact, so the 2D predicates decide, oriented by the projected face.
  for (int k = 0; k < 3; ++k) {
    if (a[k] != b[k] || a[k] != c[k] || a[k] != d[k]) continue;
    double pa[2], pb[2], pc[2], pd[2];
    detail::projected(a, k, pa), detail::projected(b, k, pb);
    detail::projected(c, k, pc), detail::projected(d, k, pd);
    const int o = orient2d(pa, pb, pc);
    return o == 0 ? 0 : o * incircle(pa, pb, pc, pd);
  }
  // Rounded normal, only to pick a well-conditioned axis first.
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double n[3] = {std::fabs(u[1] * v[2] - u[2] * v[1]), std::fabs(u[2] * v[0] - u[0] * v[2]),
                       std::fabs(u[0] * v[1] - u[1] * v[0])};
  int order[3] = {0, 1, 2};
  for (int x = 0; x < 2; ++x)
    for (int y = 0; y + 1 < 3 - x; ++y)
      if (n[order[y]] < n[order[y + 1]]) {
        const int t = order[y];
        order[y] = order[y + 1];
        order[y + 1] = t;
      }
  double span = 0.0;
  for (int k = 0; k < 3; ++k) span = std::fmax(span, std::fmax(std::fabs(u[k]), std::fabs(v[k])));
  if (span == 0.0) return 0;
  for (int r = 0; r < 3; ++r) {
    // f = a moved along axis k: off the plane exactly when the normal's k-th
    // component is nonzero, whatever f[k] rounds to, as long as f[k] != a[k].
    const int k = order[r];
    double f[3] = {a[0], a[1], a[2]};
    f[k] = a[k] + span;
    if (f[k] == a[k]) f[k] = a[k] + (span > std::fabs(a[k]) ? span : std::fabs(a[k]));
    const int o = orient3d(a, b, c, f);
    // The sphere through a, b, c, f cuts the plane in the circumcircle of
    // a, b, c, so d (in the plane) is inside the circle iff inside the sphere.
    if (o != 0) return o * insphere(a, b, c, f, d);
  }
  return 0;  // a, b, c collinear
}

}  // namespace pred
}  // namespace cdt3d
