// The fields of Statistics are listed once, in kStatisticsFields (stats.hpp).
// The places that name them by hand are checked against that table: the
// native CLI's `mesh --json` (keys and values), the WASM bindings' stats
// object (wasm/bindings.cpp) and the MeshStatistics interface of
// wasm/cdt3d.d.ts.
#include <catch2/catch.hpp>
#include <cdt3d/cdt3d.hpp>
#include <cstdio>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>
#include <string>

#include "cli_run.hpp"
#include "stats.hpp"

using namespace cdt3d;

namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::set<std::string> table_names() {
  std::set<std::string> names;
  for (const StatisticsField& f : kStatisticsFields) names.insert(f.name);
  return names;
}

// Every match of group 1 of `pattern` in `text`.
std::set<std::string> matches(const std::string& text, const std::string& pattern) {
  std::set<std::string> out;
  const std::regex re(pattern);
  for (auto it = std::sregex_iterator(text.begin(), text.end(), re); it != std::sregex_iterator();
       ++it)
    out.insert((*it)[1].str());
  return out;
}

// The text from `start` up to the first "\n}" after it (a C++ function body
// or a TypeScript interface).
std::string block(const std::string& text, const std::string& start) {
  const size_t a = text.find(start);
  if (a == std::string::npos) return {};
  const size_t b = text.find("\n}", a);
  return text.substr(a, b == std::string::npos ? std::string::npos : b - a);
}

}  // namespace

TEST_CASE("kStatisticsFields names every field of Statistics once", "[stats]") {
  size_t bytes = 0;
  std::set<std::string> names;
  for (const StatisticsField& f : kStatisticsFields) {
    INFO(f.name);
    REQUIRE((f.count != nullptr) + (f.real != nullptr) + (f.histogram != nullptr) == 1);
    bytes += f.count  ? sizeof(size_t)
             : f.real ? sizeof(double)
                      : sizeof(Statistics::radius_edge_histogram);
    CHECK(names.insert(f.name).second);
  }
  // Every member of Statistics is 8 bytes wide (size_t, double, an array of
  // size_t), so it has no padding: a field left out of the table shows here.
  CHECK(bytes == sizeof(Statistics));
  // Distinct members: a value written through each pointer reads back
  // unchanged after all were written.
  Statistics s;
  size_t k = 1;
  for (const StatisticsField& f : kStatisticsFields) {
    if (f.count) s.*(f.count) = k;
    if (f.real) s.*(f.real) = static_cast<double>(k);
    if (f.histogram) (s.*(f.histogram))[0] = k;
    ++k;
  }
  k = 1;
  for (const StatisticsField& f : kStatisticsFields) {
    INFO(f.name);
    if (f.count) CHECK(s.*(f.count) == k);
    if (f.real) CHECK(s.*(f.real) == static_cast<double>(k));
    if (f.histogram) CHECK((s.*(f.histogram))[0] == k);
    ++k;
  }
}

TEST_CASE("wasm/cdt3d.d.ts declares exactly the table's statistics", "[stats]") {
  const std::string dts = read_text(std::string(CDT3D_SOURCE_DIR) + "/wasm/cdt3d.d.ts");
  const std::string iface = block(dts, "export interface MeshStatistics {");
  REQUIRE(!iface.empty());
  CHECK(matches(iface, R"((?:^|\n)\s*(\w+)\??\s*:)") == table_names());
}

TEST_CASE("wasm/bindings.cpp sets exactly the table's statistics", "[stats]") {
  const std::string src = read_text(std::string(CDT3D_SOURCE_DIR) + "/wasm/bindings.cpp");
  const std::string body = block(src, "val stats_js(const cdt3d::Statistics& s) {");
  REQUIRE(!body.empty());
  std::set<std::string> keys = matches(body, R"(\bn\("(\w+)\")");
  const std::set<std::string> set_keys = matches(body, R"(o\.set\("(\w+)\")");
  keys.insert(set_keys.begin(), set_keys.end());
  CHECK(keys == table_names());
}

#ifdef CDT3D_CLI_PATH
TEST_CASE("the CLI's mesh --json carries every statistic with its value", "[stats]") {
  // A model that needs Steiner points, so the counts are not all zero.
  const std::string model = std::string(CDT3D_TEST_DATA) + "/chazelle_n3.off";
  const cli_run::Run run = cli_run::run({"mesh", model, "--json"});
  REQUIRE(run.status == 0);
  const std::string& json = run.output;

  Plc plc;
  REQUIRE(read_plc_file(model, plc).ok());
  const Result r = tetrahedralize(plc);
  REQUIRE(r.status.ok());
  CHECK(r.stats.steiner_segment + r.stats.steiner_facet + r.stats.steiner_volume > 0);
  for (const StatisticsField& f : kStatisticsFields) {
    INFO(f.name);
    const std::string value = cli_run::json_value(json, f.name);
    REQUIRE(!value.empty());
    // Counts are deterministic: the CLI prints the value of the field the
    // table names. Times vary between runs; angles are printed rounded.
    if (f.count || f.histogram) CHECK(value == cli_run::expected_json(f, r.stats));
  }
}
#endif
