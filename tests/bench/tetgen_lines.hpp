// Shared by the bench tools that read TetGen's .node/.ele/.face output
// (flat_tets.cpp, local_delaunay.cpp): the file's lines, the points of a
// .node file, and error reports.
#pragma once

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

}  // namespace bench
