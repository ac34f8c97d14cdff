// core/src is grouped by layer (README "Layout", core/CMakeLists.txt): a
// file may include headers of its own layer and of the layers before it,
// never of a later one. This test reads every source file's #include "..."
// lines and checks that order, so a newcomer's include that turns the
// layering around fails here instead of slowly blurring it.
#include <catch2/catch.hpp>

#include <dirent.h>

#include <fstream>
#include <map>
#include <regex>
#include <string>
#include <vector>

namespace {

const std::vector<std::string> kLayers = {"base", "geometry", "mesh", "io", "plc", "report", "steps"};

std::vector<std::string> files_in(const std::string& dir) {
  std::vector<std::string> out;
  if (DIR* d = opendir(dir.c_str())) {
    while (dirent* e = readdir(d)) {
      const std::string name = e->d_name;
      if (name.size() > 4 && (name.substr(name.size() - 4) == ".cpp" || name.substr(name.size() - 4) == ".hpp"))
        out.push_back(name);
    }
    closedir(d);
  }
  return out;
}

}  // namespace

TEST_CASE("core/src: every include goes to the file's own layer or an earlier one", "[layers]") {
  const std::string src = std::string(CDT3D_SOURCE_DIR) + "/core/src/";
  std::map<std::string, size_t> layer_of;  // header file name -> layer index
  size_t files = 0;
  for (size_t l = 0; l < kLayers.size(); ++l)
    for (const std::string& f : files_in(src + kLayers[l])) {
      layer_of[f] = l;
      ++files;
    }
  REQUIRE(files > 40);
  REQUIRE(files_in(src).empty());  // nothing left outside the layers
  const std::regex include_line(R"(^\s*#include\s+"(?:[a-z]+/)?([A-Za-z0-9_]+\.hpp)\")");
  size_t checked = 0;
  for (size_t l = 0; l < kLayers.size(); ++l)
    for (const std::string& f : files_in(src + kLayers[l])) {
      std::ifstream in(src + kLayers[l] + "/" + f);
      std::string line;
      while (std::getline(in, line)) {
        std::smatch m;
        if (!std::regex_search(line, m, include_line)) continue;
        const auto it = layer_of.find(m[1].str());
        if (it == layer_of.end()) continue;  // a header outside core/src
        INFO(kLayers[l] << "/" << f << " includes " << kLayers[it->second] << "/" << m[1].str());
        CHECK(it->second <= l);
        ++checked;
      }
    }
  CHECK(checked > 100);
}
