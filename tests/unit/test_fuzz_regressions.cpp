// Inputs found by the fuzz targets of tests/fuzz (tests/scripts/fuzz.sh),
// kept in tests/data/regress/ and replayed here, so that sanitize.sh runs
// them under ASan + UBSan on every CI run.
//   read-<format>-*.<ext>   a reader input: read_plc must return a Status
//                           (never crash); an error carries a message and
//                           leaves no half-read PLC; a success passes check_plc.
//   pipeline-*.{off,poly}   a tetrahedralize() input: it must not report an
//                           internal error, with or without keep_convex_hull,
//                           and a success must pass validate().
//   *.fuzz                  the raw fuzz input of the model beside it (replay
//                           with .build/fuzz/tests/fuzz/<target> FILE).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cdt3d/cdt3d.hpp>
#include <filesystem>
#include <string>
#include <vector>

using namespace cdt3d;

namespace {

const std::string kRegress = std::string(CDT3D_TEST_DATA) + "/regress";

// Files of tests/data/regress whose names start with `prefix`, sorted.
std::vector<std::string> regress_files(const std::string& prefix) {
  namespace fs = std::filesystem;
  std::vector<std::string> out;
  if (!fs::is_directory(kRegress)) return out;
  for (const auto& e : fs::directory_iterator(kRegress)) {
    const std::string name = e.path().filename().string();
    if (!e.is_regular_file() || name.rfind(prefix, 0) != 0) continue;
    if (e.path().extension() == ".fuzz") continue;
    out.push_back(e.path().string());
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

TEST_CASE("fuzz regressions: reader inputs return a status", "[fuzz][io]") {
  for (const std::string& path : regress_files("read-")) {
    INFO(path);
    Plc plc;
    const Status s = read_plc_file(path, plc);
    if (s.ok()) {
      CHECK(check_plc(plc).ok());
    } else {
      CHECK_FALSE(s.error.message.empty());
      CHECK(plc.points.empty());
      CHECK(plc.facets.empty());
    }
  }
}

// The pipeline findings: each must now mesh and validate, or fail with a
// clear input error (the facet-through-tet input is self-intersecting).
TEST_CASE("fuzz regressions: tetrahedralize reports no internal error", "[fuzz][pipeline]") {
  const std::vector<std::string> files = regress_files("pipeline-");
  CHECK_FALSE(files.empty());
  for (const std::string& path : files) {
    Plc plc;
    const Status read = read_plc_file(path, plc);
    if (!read.ok()) {
      // Rejected on input (e.g. the bowtie facet: not a simple polygon).
      INFO(path << ": " << read.error.to_string());
      CHECK(read.error.code != ErrorCode::Internal);
      CHECK(read.error.facet >= 0);
      continue;
    }
    for (bool keep : {false, true}) {
      INFO(path << (keep ? " keeping the hull" : ""));
      Options options;
      options.keep_convex_hull = keep;
      options.validate = true;
      const Result r = tetrahedralize(plc, options);
      INFO(r.status.error.to_string());
      CHECK(r.status.error.code != ErrorCode::Internal);
      if (r.status.ok()) CHECK(validate(plc, r).ok());
    }
  }
}
