// Bit mixing for the open-addressing hash tables of the readers and checks.
#pragma once

#include <cstdint>

namespace cdt3d {

/// The 64-bit finalizer of MurmurHash3 (Appleby; public domain): every input
/// bit affects every output bit, so keys that differ in a few low bits (near
/// vertex ids, near coordinates) spread over a power-of-two table.
inline uint64_t hash_mix(uint64_t h) {
  h ^= h >> 33;
  h *= 0xff51afd7ed558ccdull;
  h ^= h >> 33;
  h *= 0xc4ceb9fe1a85ec53ull;
  h ^= h >> 33;
  return h;
}

}  // namespace cdt3d
