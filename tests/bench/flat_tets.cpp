// Counts the numerically flat tetrahedra of a TetGen .node/.ele mesh, with
// cdt3d's definition (Statistics::flat_tets, cdt3d.hpp): 6V computed in
// doubles from the stored coordinates is not above kFlatTetRatio * (longest
// edge)^3. Used by tests/bench/bench_corpus.sh on TetGen's own output
// (`tetgen -pMQ M.poly` writes M.1.node / M.1.ele), so that both programs'
// flat tets are counted the same way.
//
// usage: flat_tets MESH.node MESH.ele
// Build (bench_corpus.sh does this; only the header is used):
//   c++ -O2 -std=c++17 -Icore/include tests/bench/flat_tets.cpp -o .build/bench/bench/flat_tets
//
// Orientation: cdt3d's tets are positively oriented ((a-d).((b-d)x(c-d)) > 0),
// TetGen's the other way round. The mesh's orientation is taken as the sign
// of the majority of its tets; a tet counts as flat when its 6V in that
// orientation is not above the threshold, so zero and inverted tets count as
// flat too.
//
// Output, one line: "<flat> <tets> <inverted>", where inverted counts the
// flat tets whose 6V has the minority sign or is zero.
// Numbering: node indices start at the first index of the .node file (0 or
// 1, as TetGen allows); extra node columns (attributes, markers) and extra
// tet columns (second-order nodes, attributes) are ignored; '#' starts a
// comment.
// Exit codes: 0 counted, 1 read error (message on stderr), 2 usage.
#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tetgen_lines.hpp"

namespace {

using bench::read_lines;
int fail(const char* path, const std::string& what) { return bench::fail("flat_tets", path, what); }

double six_volume(const double* a, const double* b, const double* c, const double* d) {
  const double u[3] = {a[0] - d[0], a[1] - d[1], a[2] - d[2]};
  const double v[3] = {b[0] - d[0], b[1] - d[1], b[2] - d[2]};
  const double w[3] = {c[0] - d[0], c[1] - d[1], c[2] - d[2]};
  return u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) +
         u[2] * (v[0] * w[1] - v[1] * w[0]);
}

double longest_edge(const double* const p[4]) {
  double l2 = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double x = p[i][0] - p[j][0], y = p[i][1] - p[j][1], z = p[i][2] - p[j][2];
      l2 = std::max(l2, x * x + y * y + z * z);
    }
  return std::sqrt(l2);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: flat_tets MESH.node MESH.ele\n");
    return 2;
  }
  const char* node_path = argv[1];
  const char* ele_path = argv[2];

  std::vector<double> xyz;
  long long first = 0;
  if (const std::string bad = bench::read_nodes(node_path, xyz, first); !bad.empty()) return fail(node_path, bad);
  const long long n = static_cast<long long>(xyz.size() / 3);
  std::vector<std::string> lines;

  lines.clear();
  if (!read_lines(ele_path, lines)) return fail(ele_path, "cannot open");
  if (lines.empty()) return fail(ele_path, "empty");
  long long m = -1, per = -1;
  std::istringstream(lines[0]) >> m >> per;
  if (m < 0 || per < 4) return fail(ele_path, "bad header (want '<tets> 4|10 ...')");
  if (static_cast<long long>(lines.size()) - 1 < m) return fail(ele_path, "fewer tets than the header says");

  std::vector<double> six_v(static_cast<size_t>(m)), scale(static_cast<size_t>(m));
  size_t positive = 0, negative = 0;
  for (long long t = 0; t < m; ++t) {
    std::istringstream s(lines[1 + t]);
    long long id, v[4];
    if (!(s >> id >> v[0] >> v[1] >> v[2] >> v[3]))
      return fail(ele_path, "bad tet line " + std::to_string(t + 1));
    const double* p[4];
    for (int k = 0; k < 4; ++k) {
      const long long j = v[k] - first;
      if (j < 0 || j >= n) return fail(ele_path, "node index out of range in tet " + std::to_string(id));
      p[k] = &xyz[3 * static_cast<size_t>(j)];
    }
    six_v[t] = six_volume(p[0], p[1], p[2], p[3]);
    const double l = longest_edge(p);
    scale[t] = cdt3d::kFlatTetRatio * l * l * l;
    if (six_v[t] > 0) ++positive;
    if (six_v[t] < 0) ++negative;
  }
  const double sign = positive >= negative ? 1.0 : -1.0;
  size_t flat = 0, inverted = 0;
  for (long long t = 0; t < m; ++t) {
    const double v = sign * six_v[t];
    if (!(v > scale[t])) {
      ++flat;
      if (!(v > 0)) ++inverted;
    }
  }
  std::printf("%zu %lld %zu\n", flat, m, inverted);
  return 0;
}
