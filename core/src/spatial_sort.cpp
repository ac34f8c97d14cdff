// BRIO + Hilbert insertion order (see spatial_sort.hpp).
#include "spatial_sort.hpp"

#include <algorithm>
#include <cmath>

namespace cdt3d {

namespace {

constexpr int kMaxHilbertBits = 21;  // 3 * 21 = 63-bit keys
constexpr size_t kFirstRound = 1000;
constexpr size_t kRoundGrowth = 4;

struct Keyed {
  uint64_t key;
  VertexId v;
};

struct KeyedLess {
  bool operator()(const Keyed& a, const Keyed& b) const {
    return a.key != b.key ? a.key < b.key : a.v < b.v;
  }
};

// Grid resolution for n points: about 2^15 cells per point (the cost of a key
// grows with the bits), at most 21 bits per axis.
int hilbert_bits(size_t n) {
  int log2n = 0;
  while (log2n < 40 && (size_t(1) << log2n) < n) ++log2n;
  return std::min(kMaxHilbertBits, std::max(6, (log2n + 2) / 3 + 5));
}

// Maps coordinates of the bounding cube onto the integer grid [0, 2^bits).
struct Quantizer {
  double lo[3] = {0, 0, 0};
  double scale = 0;
  int bits = kMaxHilbertBits;

  void fit(const double* coords, const VertexId* first, const VertexId* last) {
    if (first == last) return;
    bits = hilbert_bits(size_t(last - first));
    double hi[3];
    for (int k = 0; k < 3; ++k) lo[k] = hi[k] = coords[3 * size_t(*first) + k];
    for (const VertexId* p = first; p != last; ++p)
      for (int k = 0; k < 3; ++k) {
        const double c = coords[3 * size_t(*p) + k];
        lo[k] = std::min(lo[k], c);
        hi[k] = std::max(hi[k], c);
      }
    double extent = std::max(hi[0] - lo[0], std::max(hi[1] - lo[1], hi[2] - lo[2]));
    const double cells = double((1u << bits) - 1);
    scale = extent > 0 && std::isfinite(extent) ? cells / extent : 0;
  }

  uint32_t cell(double c, int k) const {
    const double q = (c - lo[k]) * scale;
    const double cells = double((1u << bits) - 1);
    if (!(q > 0)) return 0;  // also NaN
    return q >= cells ? (1u << bits) - 1 : static_cast<uint32_t>(q);
  }

  uint64_t key(const double* coords, VertexId v) const {
    const double* p = coords + 3 * size_t(v);
    return hilbert_key(cell(p[0], 0), cell(p[1], 1), cell(p[2], 2), bits);
  }
};

}  // namespace

// Skilling's transform (AIP Conf. Proc. 707, 2004): turn the axes into the
// "transposed" Hilbert index by undoing the per-level rotations/reflections,
// then Gray-encode; finally interleave the bits, most significant level first.
uint64_t hilbert_key(uint32_t x, uint32_t y, uint32_t z, int bits) {
  uint32_t a[3] = {x, y, z};
  const uint32_t top = 1u << (bits - 1);
  for (uint32_t q = top; q > 1; q >>= 1) {
    const uint32_t low = q - 1;
    for (int i = 0; i < 3; ++i) {
      if (a[i] & q) {
        a[0] ^= low;  // reflect the lower bits
      } else {        // swap the lower bits of axis 0 and axis i
        const uint32_t d = (a[0] ^ a[i]) & low;
        a[0] ^= d;
        a[i] ^= d;
      }
    }
  }
  a[1] ^= a[0];
  a[2] ^= a[1];
  uint32_t flip = 0;
  for (uint32_t q = top; q > 1; q >>= 1)
    if (a[2] & q) flip ^= q - 1;
  for (int i = 0; i < 3; ++i) a[i] ^= flip;

  uint64_t key = 0;
  for (int b = bits - 1; b >= 0; --b)
    for (int i = 0; i < 3; ++i) key = (key << 1) | ((a[i] >> b) & 1u);
  return key;
}

void hilbert_sort(const double* coords, VertexId* first, VertexId* last) {
  Quantizer qz;
  qz.fit(coords, first, last);
  std::vector<Keyed> keyed;
  keyed.reserve(size_t(last - first));
  for (VertexId* p = first; p != last; ++p) keyed.push_back({qz.key(coords, *p), *p});
  std::sort(keyed.begin(), keyed.end(), KeyedLess());
  for (size_t i = 0; i < keyed.size(); ++i) first[i] = keyed[i].v;
}

void brio_order(const double* coords, const std::vector<VertexId>& vertices, uint64_t seed,
                std::vector<VertexId>& order) {
  const size_t n = vertices.size();
  order.clear();
  if (n == 0) return;
  Quantizer qz;
  qz.fit(coords, vertices.data(), vertices.data() + n);
  std::vector<Keyed> keyed(n);
  for (size_t i = 0; i < n; ++i) keyed[i] = {qz.key(coords, vertices[i]), vertices[i]};

  // Fisher–Yates with our own generator (std::shuffle differs between
  // standard libraries).
  Rng rng(seed);
  for (size_t i = n - 1; i > 0; --i) {
    const size_t j = rng.below(static_cast<uint32_t>(i + 1));
    std::swap(keyed[i], keyed[j]);
  }

  // Round boundaries, from the last (largest) round down to the first.
  std::vector<size_t> bounds{n};
  while (bounds.back() > kFirstRound) bounds.push_back(bounds.back() / kRoundGrowth);
  bounds.push_back(0);
  std::reverse(bounds.begin(), bounds.end());
  for (size_t r = 0; r + 1 < bounds.size(); ++r)
    std::sort(keyed.begin() + bounds[r], keyed.begin() + bounds[r + 1], KeyedLess());

  order.resize(n);
  for (size_t i = 0; i < n; ++i) order[i] = keyed[i].v;
}

}  // namespace cdt3d
