// Closed triangle surfaces of a given size for tests/bench/bench_scale.sh.
//
// usage: gen_surface KIND TRIANGLES OUT.{off,ply}
//   KIND torus: a bumpy torus, a smooth surface (every triangle in its own
//               plane), ~TRIANGLES triangles on an (nu x nv) grid;
//   KIND steps: a step pyramid on a lattice (CAD-like: a few hundred large
//               flat faces meeting at sharp edges, each split into unit
//               squares), ~TRIANGLES triangles.
// .off writes text (read by tetgen too), .ply binary little-endian (smaller,
// for the WASM heap). Deterministic: the same bytes on every machine.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <unordered_map>
#include <vector>

namespace {

struct Surface {
  std::vector<double> xyz;
  std::vector<uint32_t> tri;
};

// Torus around the z axis, tube radius modulated by a product of sines small
// enough that the tube never meets itself.
Surface bumpy_torus(size_t triangles) {
  const double kPi = 3.14159265358979323846;
  const size_t cells = triangles / 2;
  size_t nv = static_cast<size_t>(std::llround(std::sqrt(cells / 2.6)));
  if (nv < 3) nv = 3;
  size_t nu = cells / nv;
  if (nu < 3) nu = 3;
  Surface s;
  s.xyz.reserve(3 * nu * nv);
  for (size_t i = 0; i < nu; ++i) {
    const double u = 2 * kPi * double(i) / double(nu);
    for (size_t j = 0; j < nv; ++j) {
      const double v = 2 * kPi * double(j) / double(nv);
      const double r = 0.3 * (1 + 0.15 * std::sin(7 * u) * std::sin(5 * v));
      const double d = 1 + r * std::cos(v);
      s.xyz.push_back(d * std::cos(u));
      s.xyz.push_back(d * std::sin(u));
      s.xyz.push_back(r * std::sin(v));
    }
  }
  s.tri.reserve(6 * nu * nv);
  auto id = [&](size_t i, size_t j) { return uint32_t((i % nu) * nv + (j % nv)); };
  for (size_t i = 0; i < nu; ++i)
    for (size_t j = 0; j < nv; ++j) {
      const uint32_t a = id(i, j), b = id(i + 1, j), c = id(i + 1, j + 1), d = id(i, j + 1);
      s.tri.insert(s.tri.end(), {a, b, c, a, c, d});
    }
  return s;
}

// Step pyramid: column (i, j) of an n x n lattice has height
// 1 + (n/2 - chebyshev distance to the centre) / step; the levels are nested
// squares, so the voxel surface is a manifold. Every face is a unit square
// of the lattice (two triangles), scaled by 1/1000.
Surface step_pyramid(size_t triangles) {
  size_t n = static_cast<size_t>(std::sqrt(double(triangles) / 4.0));
  if (n < 4) n = 4;
  const long c = long(n) / 2;
  const long step = std::max<long>(1, long(n) / 64);  // ~32 levels
  std::vector<int> h(n * n);
  for (size_t i = 0; i < n; ++i)
    for (size_t j = 0; j < n; ++j) {
      const long di = std::labs(long(i) - c), dj = std::labs(long(j) - c);
      h[i * n + j] = int(1 + (c - std::max(di, dj)) / step);
    }
  auto height = [&](long i, long j) {
    return i < 0 || j < 0 || i >= long(n) || j >= long(n) ? 0 : h[size_t(i) * n + size_t(j)];
  };
  Surface s;
  std::unordered_map<uint64_t, uint32_t> ids;
  ids.reserve(3 * n * n);
  auto vertex = [&](long x, long y, long z) {
    const uint64_t key = (uint64_t(x) << 42) | (uint64_t(y) << 21) | uint64_t(z);
    auto [it, fresh] = ids.emplace(key, uint32_t(s.xyz.size() / 3));
    if (fresh) s.xyz.insert(s.xyz.end(), {double(x) / 1000, double(y) / 1000, double(z) / 1000});
    return it->second;
  };
  // A unit square given counterclockwise seen from outside.
  auto quad = [&](uint32_t a, uint32_t b, uint32_t c2, uint32_t d) {
    s.tri.insert(s.tri.end(), {a, b, c2, a, c2, d});
  };
  for (long i = 0; i < long(n); ++i)
    for (long j = 0; j < long(n); ++j) {
      const long z = height(i, j);
      quad(vertex(i, j, z), vertex(i + 1, j, z), vertex(i + 1, j + 1, z), vertex(i, j + 1, z));
      quad(vertex(i, j, 0), vertex(i, j + 1, 0), vertex(i + 1, j + 1, 0), vertex(i + 1, j, 0));
      // Walls towards +x and +y (and, at the lattice's low border, -x, -y).
      for (long k = height(i + 1, j); k < z; ++k)
        quad(vertex(i + 1, j, k), vertex(i + 1, j + 1, k), vertex(i + 1, j + 1, k + 1),
             vertex(i + 1, j, k + 1));
      for (long k = z; k < height(i + 1, j); ++k)
        quad(vertex(i + 1, j, k), vertex(i + 1, j, k + 1), vertex(i + 1, j + 1, k + 1),
             vertex(i + 1, j + 1, k));
      for (long k = height(i, j + 1); k < z; ++k)
        quad(vertex(i, j + 1, k), vertex(i, j + 1, k + 1), vertex(i + 1, j + 1, k + 1),
             vertex(i + 1, j + 1, k));
      for (long k = z; k < height(i, j + 1); ++k)
        quad(vertex(i, j + 1, k), vertex(i + 1, j + 1, k), vertex(i + 1, j + 1, k + 1),
             vertex(i, j + 1, k + 1));
      if (i == 0)
        for (long k = 0; k < z; ++k)
          quad(vertex(0, j, k), vertex(0, j, k + 1), vertex(0, j + 1, k + 1), vertex(0, j + 1, k));
      if (j == 0)
        for (long k = 0; k < z; ++k)
          quad(vertex(i, 0, k), vertex(i + 1, 0, k), vertex(i + 1, 0, k + 1), vertex(i, 0, k + 1));
    }
  return s;
}

bool write_off(const Surface& s, const char* path) {
  FILE* f = std::fopen(path, "wb");
  if (!f) return false;
  std::fprintf(f, "OFF\n%zu %zu 0\n", s.xyz.size() / 3, s.tri.size() / 3);
  for (size_t k = 0; k < s.xyz.size(); k += 3)
    std::fprintf(f, "%.17g %.17g %.17g\n", s.xyz[k], s.xyz[k + 1], s.xyz[k + 2]);
  for (size_t k = 0; k < s.tri.size(); k += 3)
    std::fprintf(f, "3 %u %u %u\n", s.tri[k], s.tri[k + 1], s.tri[k + 2]);
  return std::fclose(f) == 0;
}

bool write_ply(const Surface& s, const char* path) {
  FILE* f = std::fopen(path, "wb");
  if (!f) return false;
  std::fprintf(f,
               "ply\nformat binary_little_endian 1.0\nelement vertex %zu\nproperty double x\n"
               "property double y\nproperty double z\nelement face %zu\n"
               "property list uchar uint vertex_indices\nend_header\n",
               s.xyz.size() / 3, s.tri.size() / 3);
  std::fwrite(s.xyz.data(), sizeof(double), s.xyz.size(), f);  // x86-64 and wasm: little-endian
  std::vector<unsigned char> rec(13);
  rec[0] = 3;
  for (size_t k = 0; k < s.tri.size(); k += 3) {
    std::memcpy(&rec[1], &s.tri[k], 12);
    std::fwrite(rec.data(), 1, 13, f);
  }
  return std::fclose(f) == 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: gen_surface torus|steps TRIANGLES OUT.{off,ply}\n");
    return 2;
  }
  const std::string kind = argv[1], out = argv[3];
  const size_t triangles = std::strtoull(argv[2], nullptr, 10);
  Surface s;
  if (kind == "torus") {
    s = bumpy_torus(triangles);
  } else if (kind == "steps") {
    s = step_pyramid(triangles);
  } else {
    std::fprintf(stderr, "gen_surface: unknown kind %s\n", kind.c_str());
    return 2;
  }
  const bool ply = out.size() > 4 && out.compare(out.size() - 4, 4, ".ply") == 0;
  if (!(ply ? write_ply(s, out.c_str()) : write_off(s, out.c_str()))) {
    std::fprintf(stderr, "gen_surface: cannot write %s\n", out.c_str());
    return 1;
  }
  std::printf("%zu %zu\n", s.xyz.size() / 3, s.tri.size() / 3);
  return 0;
}
