// Shared by the bench tools that read TetGen's .node/.ele/.face output
// (flat_tets.cpp, local_delaunay.cpp, mesh_quality.cpp): the file's lines,
// the points of a .node file, the tets of a .ele file, error reports, and the
// flat-tet count in doubles.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace bench {

// The non-empty lines of a TetGen file with comments ('#' to the end of the
// line) removed; false when the file cannot be opened.
inline bool read_lines(const char* path, std::vector<std::string>& lines) {
  std::ifstream in(path);
  if (!in) return false;
  std::string line;
  while (std::getline(in, line)) {
    const size_t hash = line.find('#');
    if (hash != std::string::npos) line.resize(hash);
    if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
    lines.push_back(line);
  }
  return true;
}

// Prints "TOOL: PATH: WHAT" on stderr; returns the tools' read-error exit code.
inline int fail(const char* tool, const char* path, const std::string& what) {
  std::fprintf(stderr, "%s: %s: %s\n", tool, path, what.c_str());
  return 1;
}

// Reads a .node file: xyz gets 3 coordinates per point, first the index of
// the first point (0 or 1, as TetGen allows); extra columns are ignored.
// Returns "" or what is wrong.
inline std::string read_nodes(const char* path, std::vector<double>& xyz, long long& first) {
  std::vector<std::string> lines;
  if (!read_lines(path, lines)) return "cannot open";
  if (lines.empty()) return "empty";
  long long n = -1, dim = -1;
  std::istringstream(lines[0]) >> n >> dim;
  if (n < 0 || dim != 3) return "bad header (want '<points> 3 ...')";
  if (static_cast<long long>(lines.size()) - 1 < n) return "fewer points than the header says";
  xyz.assign(3 * static_cast<size_t>(n), 0.0);
  first = 0;
  for (long long i = 0; i < n; ++i) {
    std::istringstream s(lines[1 + i]);
    long long id;
    if (!(s >> id >> xyz[3 * i] >> xyz[3 * i + 1] >> xyz[3 * i + 2]))
      return "bad point line " + std::to_string(i + 1);
    if (i == 0) first = id;
  }
  return "";
}

// Reads a .ele file of a mesh with n points numbered from first: tets gets
// the 4 corner indices of each tet, counted from 0 (second-order nodes and
// attributes are ignored). Returns "" or what is wrong.
inline std::string read_tets(const char* path, long long n, long long first,
                             std::vector<std::array<long long, 4>>& tets) {
  std::vector<std::string> lines;
  if (!read_lines(path, lines)) return "cannot open";
  if (lines.empty()) return "empty";
  long long m = -1, per = -1;
  std::istringstream(lines[0]) >> m >> per;
  if (m < 0 || per < 4) return "bad header (want '<tets> 4|10 ...')";
  if (static_cast<long long>(lines.size()) - 1 < m) return "fewer tets than the header says";
  tets.assign(static_cast<size_t>(m), {});
  for (long long t = 0; t < m; ++t) {
    std::istringstream s(lines[1 + t]);
    long long id;
    auto& v = tets[static_cast<size_t>(t)];
    if (!(s >> id >> v[0] >> v[1] >> v[2] >> v[3])) return "bad tet line " + std::to_string(t + 1);
    for (auto& x : v) {
      x -= first;
      if (x < 0 || x >= n) return "node index out of range in tet " + std::to_string(id);
    }
  }
  return "";
}

// 6 x the signed volume of tet abcd, (a-d).((b-d)x(c-d)), in doubles: positive
// for cdt3d's orientation, negative for TetGen's.
inline double six_volume(const double* a, const double* b, const double* c, const double* d) {
  const double u[3] = {a[0] - d[0], a[1] - d[1], a[2] - d[2]};
  const double v[3] = {b[0] - d[0], b[1] - d[1], b[2] - d[2]};
  const double w[3] = {c[0] - d[0], c[1] - d[1], c[2] - d[2]};
  return u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) +
         u[2] * (v[0] * w[1] - v[1] * w[0]);
}

// The length of the longest of the 6 edges of the tet with corners p[0..3].
inline double longest_edge(const double* const p[4]) {
  double l2 = 0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const double x = p[i][0] - p[j][0], y = p[i][1] - p[j][1], z = p[i][2] - p[j][2];
      l2 = std::max(l2, x * x + y * y + z * z);
    }
  return std::sqrt(l2);
}

// Numerically flat tets with cdt3d's definition (Statistics::flat_tets): 6V in
// doubles from the stored coordinates is not above ratio * (longest edge)^3
// (ratio: cdt3d::kFlatTetRatio). The mesh's orientation is the sign of the
// majority of its tets (TetGen orients them the other way round from cdt3d);
// zero and inverted tets count as flat, and as inverted too.
struct FlatCount {
  size_t flat = 0, inverted = 0;
};
inline FlatCount count_flat(const std::vector<double>& xyz, const std::vector<std::array<long long, 4>>& tets,
                            double ratio) {
  std::vector<double> six_v(tets.size()), scale(tets.size());
  size_t positive = 0, negative = 0;
  for (size_t t = 0; t < tets.size(); ++t) {
    const double* p[4];
    for (int k = 0; k < 4; ++k) p[k] = &xyz[3 * static_cast<size_t>(tets[t][k])];
    six_v[t] = six_volume(p[0], p[1], p[2], p[3]);
    const double l = longest_edge(p);
    scale[t] = ratio * l * l * l;
    if (six_v[t] > 0) ++positive;
    if (six_v[t] < 0) ++negative;
  }
  const double sign = positive >= negative ? 1.0 : -1.0;
  FlatCount c;
  for (size_t t = 0; t < tets.size(); ++t) {
    const double v = sign * six_v[t];
    if (!(v > scale[t])) {
      ++c.flat;
      if (!(v > 0)) ++c.inverted;
    }
  }
  return c;
}

}  // namespace bench
