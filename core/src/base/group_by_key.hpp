// Grouping items by a vertex id with one counting sort.
//
// Finding equal facets or distinct edges by a hash table or a full radix
// sort reads and writes memory at random: on a million-triangle input each
// access is a cache and TLB miss, and WebAssembly (4 KiB pages only) pays a
// page walk for nearly every one. Grouping by a vertex id instead follows
// the vertex numbering, which follows the file's own locality; each group
// is then small and handled on its own.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "blocks.hpp"

namespace cdt3d {

/// Groups the items 0..n-1 by key(i) < range: out gets value(i) for every
/// item, in increasing key and, within a key, increasing i; end[k] is where
/// key k's group ends in `out` (it starts at end[k - 1], or at 0 for k = 0).
/// n must be below 2^32.
template <typename KeyFn, typename ValueFn>
void group_by_key(size_t n, size_t range, KeyFn key, ValueFn value, std::vector<uint32_t>& out,
                  std::vector<uint32_t>& end) {
  end.assign(range, 0);
  for_blocks(n, [&](size_t begin, size_t stop) {
    for (size_t i = begin; i < stop; ++i) ++end[key(i)];
    return true;
  });
  uint32_t sum = 0;
  for (uint32_t& c : end) {
    const uint32_t here = c;
    c = sum;
    sum += here;
  }
  out.resize(n);
  // Each group's cursor starts at its first slot and ends at its end.
  for_blocks(n, [&](size_t begin, size_t stop) {
    for (size_t i = begin; i < stop; ++i) out[end[key(i)]++] = value(i);
    return true;
  });
}

}  // namespace cdt3d
