// The model list of a corpus MANIFEST.tsv (tests/data, or the shared corpus),
// shared by the tests that run every model. Columns are found by their header
// names.
#pragma once

#include <cstddef>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace corpus {

struct Row {
  std::string file, format, vertices, triangles, expected;
  bool valid() const { return expected == "valid" || expected == "valid-plc"; }
};

inline const std::string kData = CDT3D_TEST_DATA;

/// The rows of `path` (default: tests/data/MANIFEST.tsv); empty if unreadable.
inline std::vector<Row> read_manifest(const std::string& path = kData + "/MANIFEST.tsv") {
  std::vector<Row> rows;
  std::ifstream in(path);
  std::string line;
  std::map<std::string, size_t> col;
  bool header = true;
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<std::string> c;
    std::stringstream cells(line);
    for (std::string cell; std::getline(cells, cell, '\t');) c.push_back(cell);
    if (header) {
      for (size_t i = 0; i < c.size(); ++i) col[c[i]] = i;
      header = false;
      continue;
    }
    auto at = [&](const char* name) {
      const auto it = col.find(name);
      return it != col.end() && it->second < c.size() ? c[it->second] : std::string();
    };
    rows.push_back({at("file"), at("format"), at("vertices"), at("triangles"), at("expected")});
  }
  return rows;
}

/// The files of tests/data that the manifest calls valid (or valid PLCs).
inline std::vector<std::string> valid_models() {
  std::vector<std::string> out;
  for (const Row& r : read_manifest())
    if (r.valid()) out.push_back(r.file);
  return out;
}

}  // namespace corpus
