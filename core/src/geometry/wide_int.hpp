// Fixed-width signed integers for the exact stage of the predicates
// (predicates.cpp): N little-endian 64-bit limbs in two's complement.
//
// Why: a determinant of doubles that share a binade range is a determinant
// of integers once every coordinate is divided by the power of two of the
// lowest set bit among them (exact, and it keeps the sign: the forms are
// homogeneous). CAD models with decimal coordinates (0.1, 0.3, ...) are exact
// zeros of insphere again and again, their differences do not round exactly,
// and the expansion arithmetic's raw form is slow there; the same
// determinant over 2-limb integers takes a fraction of its time.
//
// Widths are fixed by the callers from bounds on the operands, so no
// operation ever overflows its result type (each call site states its bound).
#pragma once

#include <cstdint>

namespace cdt3d {
namespace wide {

__extension__ typedef unsigned __int128 u128;  // GCC and Clang, WebAssembly included
__extension__ typedef __int128 i128;

template <int N>
struct Int {
  uint64_t w[N];
};

template <int N>
inline bool negative(const Int<N>& a) {
  return static_cast<int64_t>(a.w[N - 1]) < 0;
}

// A signed 128-bit value as N >= 1 limbs (N == 1: the caller guarantees it
// fits in 64 bits).
template <int N>
inline Int<N> from_i128(i128 v) {
  Int<N> r;
  r.w[0] = static_cast<uint64_t>(v);
  const uint64_t fill = v < 0 ? ~uint64_t(0) : 0;
  if constexpr (N > 1) r.w[1] = static_cast<uint64_t>(static_cast<u128>(v) >> 64);
  for (int i = 2; i < N; ++i) r.w[i] = fill;
  return r;
}

// Sign extension from M to N >= M limbs.
template <int N, int M>
inline Int<N> widen(const Int<M>& a) {
  static_assert(N >= M, "widen only");
  Int<N> r;
  for (int i = 0; i < M; ++i) r.w[i] = a.w[i];
  const uint64_t fill = negative(a) ? ~uint64_t(0) : 0;
  for (int i = M; i < N; ++i) r.w[i] = fill;
  return r;
}

template <int N>
inline Int<N> add(const Int<N>& a, const Int<N>& b) {
  Int<N> r;
  uint64_t carry = 0;
  for (int i = 0; i < N; ++i) {
    const u128 t = static_cast<u128>(a.w[i]) + b.w[i] + carry;
    r.w[i] = static_cast<uint64_t>(t);
    carry = static_cast<uint64_t>(t >> 64);
  }
  return r;
}

template <int N>
inline Int<N> sub(const Int<N>& a, const Int<N>& b) {
  Int<N> r;
  uint64_t borrow = 0;
  for (int i = 0; i < N; ++i) {
    const u128 t = static_cast<u128>(a.w[i]) - b.w[i] - borrow;
    r.w[i] = static_cast<uint64_t>(t);
    borrow = static_cast<uint64_t>(t >> 64) & 1;
  }
  return r;
}

// The exact signed product, A + B limbs: the unsigned product of the two bit
// patterns, less b * 2^(64 A) when a < 0 and a * 2^(64 B) when b < 0
// (modulo 2^(64 (A + B)), where the true product lives).
template <int A, int B>
inline Int<A + B> mul(const Int<A>& a, const Int<B>& b) {
  constexpr int N = A + B;
  Int<N> r;
  for (int i = 0; i < N; ++i) r.w[i] = 0;
  for (int i = 0; i < A; ++i) {
    uint64_t carry = 0;
    for (int j = 0; j < B; ++j) {
      const u128 t = static_cast<u128>(a.w[i]) * b.w[j] + r.w[i + j] + carry;
      r.w[i + j] = static_cast<uint64_t>(t);
      carry = static_cast<uint64_t>(t >> 64);
    }
    r.w[i + B] = carry;
  }
  auto subtract_shifted = [&r](const uint64_t* x, int nx, int shift) {
    uint64_t borrow = 0;
    for (int k = shift; k < N; ++k) {
      const uint64_t xv = k - shift < nx ? x[k - shift] : 0;
      const u128 t = static_cast<u128>(r.w[k]) - xv - borrow;
      r.w[k] = static_cast<uint64_t>(t);
      borrow = static_cast<uint64_t>(t >> 64) & 1;
    }
  };
  if (negative(a)) subtract_shifted(b.w, B, A);
  if (negative(b)) subtract_shifted(a.w, A, B);
  return r;
}

template <int N>
inline int sign(const Int<N>& a) {
  if (negative(a)) return -1;
  for (int i = 0; i < N; ++i)
    if (a.w[i] != 0) return 1;
  return 0;
}

}  // namespace wide
}  // namespace cdt3d
