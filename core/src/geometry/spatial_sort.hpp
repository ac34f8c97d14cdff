// Insertion order for incremental Delaunay: biased randomized insertion order
// (BRIO, Amenta–Choi–Rote 2003) with Hilbert order inside each round.
// Deterministic: own PRNG, ties broken by vertex id; same order on every
// platform and standard library.
#pragma once

#include <cdt3d/cdt3d.hpp>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace cdt3d {

/// splitmix64 (Steele, Lea, Flood 2014): small, fast, identical everywhere.
struct Rng {
  uint64_t state;
  explicit Rng(uint64_t seed = 0x243f6a8885a308d3ull) : state(seed) {}
  uint64_t next() {
    uint64_t z = (state += 0x9e3779b97f4a7c15ull);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    return z ^ (z >> 31);
  }
  /// Uniform-enough integer in [0, n) (multiply-shift; n < 2^32).
  uint32_t below(uint32_t n) {
    return static_cast<uint32_t>(((next() >> 32) * static_cast<uint64_t>(n)) >> 32);
  }
};

/// Position of the integer point (x, y, z), each < 2^bits, along the 3D
/// Hilbert curve of order `bits` (bits <= 21): a 3*bits-bit key.
uint64_t hilbert_key(uint32_t x, uint32_t y, uint32_t z, int bits);

/// Sorts vertex ids in place along the Hilbert curve of the bounding cube of
/// the given vertices (ties by id).
void hilbert_sort(const double* coords, VertexId* first, VertexId* last);

/// BRIO order of `vertices`: each vertex draws its round at random (seeded),
/// the last round holding about 3/4 of them, each earlier one a quarter of
/// the next, the first about 1000 (Amenta, Choi, Rote 2003); inside a round
/// the vertices follow one Hilbert curve over the bounding cube of all of
/// them. Stable radix sort: equal keys keep the order of `vertices`.
/// `round_start`, when given, gets the position in `order` where each round
/// starts, plus n at the end.
void brio_order(const double* coords, const std::vector<VertexId>& vertices, uint64_t seed,
                std::vector<VertexId>& order, std::vector<size_t>* round_start = nullptr);

}  // namespace cdt3d
