// Writes N uniformly random points in the unit cube as a TetGen .node file
// (numbered from 1), for tests/bench/bench_delaunay.sh.
// usage: gen_points N OUT.node [SEED]
// Deterministic: splitmix64 and 53-bit mantissas, printed with %.17g (exact
// round trip), so every run and platform writes the same bytes.
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

static uint64_t splitmix64(uint64_t& s) {
  uint64_t z = (s += 0x9e3779b97f4a7c15ull);
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr, "usage: gen_points N OUT.node [SEED]\n");
    return 2;
  }
  const uint64_t n = std::strtoull(argv[1], nullptr, 10);
  uint64_t seed = argc > 3 ? std::strtoull(argv[3], nullptr, 10) : 1;
  std::FILE* f = std::fopen(argv[2], "wb");
  if (!f) {
    std::perror(argv[2]);
    return 1;
  }
  std::fprintf(f, "%" PRIu64 " 3 0 0\n", n);
  for (uint64_t i = 1; i <= n; ++i) {
    double c[3];
    for (double& x : c) x = double(splitmix64(seed) >> 11) * 0x1p-53;
    std::fprintf(f, "%" PRIu64 " %.17g %.17g %.17g\n", i, c[0], c[1], c[2]);
  }
  return std::fclose(f) == 0 ? 0 : 1;
}
