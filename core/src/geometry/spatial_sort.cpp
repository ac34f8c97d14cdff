// BRIO + Hilbert insertion order (see spatial_sort.hpp).
#include "spatial_sort.hpp"

#include <algorithm>
#include <cmath>

#include "radix_sort.hpp"

namespace cdt3d {

namespace {

constexpr int kMaxHilbertBits = 21;  // 3 * 21 = 63-bit keys
constexpr int kBrioHilbertBits = 9;  // 4 bits of round + 3 * 9 fit in 32 bits
// Size of the first BRIO round, at least. Small, so that sets of a few
// thousand points (most surface models) still get several rounds: in one
// round of pure Hilbert order each point lands next to the boundary of the
// region inserted so far, where the circumspheres are large, and its cavity
// holds more tets than with rounds.
constexpr size_t kFirstRound = 64;

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
  while (log2n < 40 && (uint64_t(1) << log2n) < uint64_t(n)) ++log2n;
  return std::min(kMaxHilbertBits, std::max(6, (log2n + 2) / 3 + 5));
}

// Maps coordinates of the bounding cube onto the integer grid [0, 2^bits).
struct Quantizer {
  double lo[3] = {0, 0, 0};
  double scale = 0;
  int bits = kMaxHilbertBits;

  void fit(const double* coords, const VertexId* first, const VertexId* last, int max_bits) {
    if (first == last) return;
    bits = std::min(max_bits, hilbert_bits(size_t(last - first)));
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

// Skilling's transform (AIP Conf. Proc. 707, 2004): turn the axes into the
// "transposed" Hilbert index by undoing the per-level rotations/reflections,
// then Gray-encode; finally interleave the bits, most significant level first.
}  // namespace

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
  qz.fit(coords, first, last, kMaxHilbertBits);
  std::vector<Keyed> keyed;
  keyed.reserve(size_t(last - first));
  for (VertexId* p = first; p != last; ++p) keyed.push_back({qz.key(coords, *p), *p});
  std::sort(keyed.begin(), keyed.end(), KeyedLess());
  for (size_t i = 0; i < keyed.size(); ++i) first[i] = keyed[i].v;
}

void brio_order(const double* coords, const std::vector<VertexId>& vertices, uint64_t seed,
                std::vector<VertexId>& order, std::vector<size_t>* round_start) {
  const size_t n = vertices.size();
  order.clear();
  if (round_start) round_start->assign(1, 0);
  if (n == 0) {
    if (round_start) round_start->push_back(0);
    return;
  }
  Quantizer qz;
  qz.fit(coords, vertices.data(), vertices.data() + n, kBrioHilbertBits);

  // Rounds as levels: a point falls in level j with probability (3/4) 4^-j
  // (two leading zero bits of a random word per level), level 0 being the
  // last round; levels from `top` up form the first round, of about
  // kFirstRound points. Each record is (round, Hilbert index) in its high
  // 32 bits and the position in `vertices` in its low 32 bits, so ties go
  // by position.
  int top = 0;
  while (top < 15 && (uint64_t(n) >> (2 * (top + 1))) >= kFirstRound) ++top;
  const int hbits = 3 * qz.bits;
  Rng rng(seed);
  std::vector<uint64_t> rec(n);
  for (size_t i = 0; i < n; ++i) {
    uint64_t r = rng.next();
    int level = 0;
    while (level < top && (r >> 62) == 0) r <<= 2, ++level;
    const uint64_t key = (uint64_t(top - level) << hbits) | qz.key(coords, vertices[i]);
    rec[i] = (key << 32) | i;
  }
  radix_sort(rec, 32, 32 + hbits + 4);
  order.resize(n);
  for (size_t i = 0; i < n; ++i) order[i] = vertices[uint32_t(rec[i])];
  if (round_start) {
    for (size_t i = 1; i < n; ++i)
      if ((rec[i] >> (32 + hbits)) != (rec[i - 1] >> (32 + hbits))) round_start->push_back(i);
    round_start->push_back(n);
  }
}

}  // namespace cdt3d
