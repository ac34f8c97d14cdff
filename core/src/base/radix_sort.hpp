// Least-significant-digit radix sort by an integer key: for the few sorts of
// hundreds of thousands of edge or vertex keys per run, which it does in a
// few linear passes instead of std::sort's n log n comparisons.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "blocks.hpp"

namespace cdt3d {

/// Below this many elements radix_sort_by sorts by comparisons instead.
inline constexpr size_t kSmallSort = 512;

/// Sorts `a` by key(x) (a uint64_t), looking only at bits [lo, hi) of the
/// key, 11 bits per pass; passes where every element has the same digit are
/// skipped. Stable: elements whose keys agree there keep their order, so the
/// result does not depend on the library's sort.
template <typename T, typename KeyFn>
void radix_sort_by(std::vector<T>& a, KeyFn key, int lo, int hi) {
  constexpr int kDigit = 11;
  constexpr size_t kBuckets = size_t(1) << kDigit;
  if (a.size() < 2) return;
  if (a.size() < kSmallSort) {
    // Few elements: each pass would clear and scan its 2^11 counters, more
    // work than the elements themselves (the small tetrahedralizations of
    // facet recovery's cavities sort many short arrays). A stable sort by
    // the same bits, those of the passes [lo, lo + 11k), gives the same
    // order.
    const int top = lo + kDigit * ((hi - lo + kDigit - 1) / kDigit);
    const uint64_t mask = top - lo >= 64 ? ~uint64_t(0) : (uint64_t(1) << (top - lo)) - 1;
    std::stable_sort(a.begin(), a.end(), [&](const T& x, const T& y) {
      return ((key(x) >> lo) & mask) < ((key(y) >> lo) & mask);
    });
    return;
  }
  std::vector<T> tmp(a.size());
  std::vector<size_t> count(kBuckets);
  for (int shift = lo; shift < hi; shift += kDigit) {
    std::fill(count.begin(), count.end(), 0);
    // Both passes over `a` in blocks (blocks.hpp).
    for_blocks(a.size(), [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i) ++count[(key(a[i]) >> shift) & (kBuckets - 1)];
      return true;
    });
    if (std::find(count.begin(), count.end(), a.size()) != count.end()) continue;  // one digit
    size_t sum = 0;
    for (size_t& c : count) {
      const size_t here = c;
      c = sum;
      sum += here;
    }
    for_blocks(a.size(), [&](size_t begin, size_t end) {
      for (size_t i = begin; i < end; ++i)
        tmp[count[(key(a[i]) >> shift) & (kBuckets - 1)]++] = a[i];
      return true;
    });
    a.swap(tmp);
  }
}

/// radix_sort_by on the values themselves.
inline void radix_sort(std::vector<uint64_t>& a, int lo, int hi) {
  radix_sort_by(a, [](uint64_t r) { return r; }, lo, hi);
}

/// Bits needed to write n - 1 (at least 1): the width of an index below n.
inline int index_bits(size_t n) {
  int b = 1;
  while (b < 64 && (uint64_t(1) << b) < n) ++b;
  return b;
}

}  // namespace cdt3d
