// Shared by the bench tools that read TetGen's .node/.ele/.face output
// (flat_tets.cpp, local_delaunay.cpp): the file's lines and error reports.
#pragma once

#include <cstdio>
#include <fstream>
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

}  // namespace bench
