// The model corpus in tests/data, checked against tests/data/MANIFEST.tsv, and
// a 200k-triangle binary STL generated in memory (its read time is printed,
// never asserted).
#include <catch2/catch.hpp>
#include <cdt3d/cdt3d.hpp>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "corpus.hpp"

using namespace cdt3d;

namespace {

const std::string kData = CDT3D_TEST_DATA;

using corpus::Row;
using corpus::read_manifest;

bool is_number(const std::string& s) {
  return !s.empty() && s.find_first_not_of("0123456789") == std::string::npos;
}

}  // namespace

TEST_CASE("Corpus: every manifest row loads or fails as expected", "[io][corpus]") {
  const std::vector<Row> rows = read_manifest();
  REQUIRE(rows.size() >= 30);
  const std::map<std::string, ErrorCode> expected_error = {
      {"invalid-empty", ErrorCode::Empty},
      {"invalid-truncated", ErrorCode::Truncated},
      {"invalid-nan", ErrorCode::NonFinite},
      {"invalid-duplicate", ErrorCode::DuplicateFacet},
      {"invalid-degenerate", ErrorCode::DegenerateFacet},
      {"invalid-nonplanar", ErrorCode::NonPlanarFacet},
  };
  for (const Row& row : rows) {
    INFO("model " << row.file << " (" << row.expected << ")");
    Plc plc;
    const Status s = read_plc_file(kData + "/" + row.file, plc);
    INFO("status: " << (s.ok() ? std::string("ok") : s.error.to_string()));
    const auto it = expected_error.find(row.expected);
    if (it != expected_error.end()) {
      CHECK(s.error.code == it->second);
      CHECK(plc.points.empty());  // a failed read leaves no partial PLC
      continue;
    }
    // valid, valid-plc, and the defects found later in the pipeline
    // (invalid-open, invalid-selfintersect): the reader accepts them.
    REQUIRE((row.expected == "valid" || row.expected == "valid-plc" ||
             row.expected == "invalid-open" || row.expected == "invalid-selfintersect"));
    REQUIRE(s.ok());
    const PlcInfo info = plc_info(plc);
    if (is_number(row.triangles)) CHECK(info.triangles == std::stoull(row.triangles));
    if (is_number(row.vertices)) {
      if (row.format.rfind("stl", 0) == 0) {
        CHECK(info.points == std::stoull(row.vertices));
      } else {
        CHECK(info.file_vertices == std::stoull(row.vertices));
      }
    }
    CHECK(info.points + plc.welded_vertices == plc.file_vertices);
  }
}

TEST_CASE("Corpus: the manifest lists every model in tests/data", "[io][corpus]") {
  std::set<std::string> listed;
  for (const Row& r : read_manifest()) listed.insert(r.file);
  for (const auto& entry : std::filesystem::directory_iterator(kData)) {
    const std::string name = entry.path().filename().string();
    // Subfolders (regress/: minimized fuzzer finds) have tests of their own.
    if (name == "MANIFEST.tsv" || entry.is_directory()) continue;
    INFO(name);
    CHECK(listed.count(name) == 1);
  }
}

TEST_CASE("Corpus: specific models", "[io][corpus]") {
  Plc plc;
  SECTION("cube_dangling.poly: dangling facet, floating segment, isolated vertex") {
    REQUIRE(read_plc_file(kData + "/cube_dangling.poly", plc).ok());
    CHECK(plc.points.size() == 15);
    CHECK(plc.facets.size() == 7);
    CHECK(plc.segments.size() == 2);
    CHECK(plc_info(plc).unreferenced == 1);  // the isolated vertex
  }
  SECTION("cube_internal_facet.poly: regions") {
    REQUIRE(read_plc_file(kData + "/cube_internal_facet.poly", plc).ok());
    REQUIRE(plc.regions.size() == 2);
    CHECK(plc.regions[1].attribute == 2);
    CHECK(plc.facets[2].marker == 2);
  }
  SECTION("nested_cubes_cavity.poly: hole point") {
    REQUIRE(read_plc_file(kData + "/nested_cubes_cavity.poly", plc).ok());
    REQUIRE(plc.holes.size() == 1);
    CHECK(plc.holes[0].x == 1.5);
  }
  SECTION("cube_comments_colors.off: quads with colours") {
    REQUIRE(read_plc_file(kData + "/cube_comments_colors.off", plc).ok());
    CHECK(plc.facets.size() == 6);
    CHECK(plc.facets[0].loops[0].size() == 4);
  }
  SECTION("truncated_binary.stl names the record where it ends") {
    const Status s = read_plc_file(kData + "/truncated_binary.stl", plc);
    CHECK(s.error.code == ErrorCode::Truncated);
    CHECK(s.error.record == 7);
  }
  SECTION("nan_coords.off names the vertex and its line") {
    const Status s = read_plc_file(kData + "/nan_coords.off", plc);
    CHECK(s.error.code == ErrorCode::NonFinite);
    CHECK(s.error.vertex == 6);
    CHECK(s.error.line == 9);
  }
  SECTION("cube_duplicate_face.off names both facets") {
    const Status s = read_plc_file(kData + "/cube_duplicate_face.off", plc);
    CHECK(s.error.code == ErrorCode::DuplicateFacet);
    CHECK(s.error.facet == 12);
    CHECK(s.error.other_facet == 4);
    CHECK(s.error.line == 23);
  }
  SECTION("cube_degenerate_tris.off: the zero-area triangle comes first") {
    const Status s = read_plc_file(kData + "/cube_degenerate_tris.off", plc);
    CHECK(s.error.code == ErrorCode::DegenerateFacet);
    CHECK(s.error.facet == 12);
    CHECK(s.error.line == 24);
  }
  SECTION("a missing file is an io error") {
    const Status s = read_plc_file(kData + "/no_such_file.off", plc);
    CHECK(s.error.code == ErrorCode::IoError);
  }
}

namespace {

void put_u32(std::vector<uint8_t>& b, uint32_t v) {
  for (int k = 0; k < 4; ++k) b.push_back(static_cast<uint8_t>(v >> (8 * k)));
}

void put_f32(std::vector<uint8_t>& b, float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  put_u32(b, u);
}

}  // namespace

TEST_CASE("A 200k-triangle binary STL loads with exact counts", "[io][stl][large]") {
  // Height field over an n x n grid, two triangles per cell: every inner vertex
  // is shared by six triangles, so welding does real work. All values are
  // exact in float.
  const uint32_t n = 317;  // 2 * 317^2 = 200978 triangles
  const uint32_t tris = 2 * n * n;
  auto corner = [](uint32_t i, uint32_t j) {
    const float z = static_cast<float>((i * 7 + j * 3) % 5) * 0.25f;
    return std::array<float, 3>{static_cast<float>(i) * 0.5f, static_cast<float>(j) * 0.5f, z};
  };
  std::vector<uint8_t> bytes(80, ' ');
  bytes.reserve(84 + 50 * static_cast<size_t>(tris));
  put_u32(bytes, tris);
  auto put_tri = [&](std::array<float, 3> a, std::array<float, 3> b, std::array<float, 3> c) {
    for (int k = 0; k < 3; ++k) put_f32(bytes, 0.0f);
    for (const auto& p : {a, b, c}) {
      for (float f : p) put_f32(bytes, f);
    }
    bytes.push_back(0);
    bytes.push_back(0);
  };
  for (uint32_t i = 0; i < n; ++i) {
    for (uint32_t j = 0; j < n; ++j) {
      put_tri(corner(i, j), corner(i + 1, j), corner(i + 1, j + 1));
      put_tri(corner(i, j), corner(i + 1, j + 1), corner(i, j + 1));
    }
  }
  REQUIRE(bytes.size() == 84 + 50 * static_cast<size_t>(tris));

  Plc plc;
  const auto t0 = std::chrono::steady_clock::now();
  const Status s = read_plc(bytes.data(), bytes.size(), "grid.stl", plc);
  const auto t1 = std::chrono::steady_clock::now();
  INFO(s.error.to_string());
  REQUIRE(s.ok());
  const size_t points = static_cast<size_t>(n + 1) * (n + 1);
  CHECK(plc.points.size() == points);
  CHECK(plc.file_vertices == 3 * static_cast<size_t>(tris));
  CHECK(plc.welded_vertices == 3 * static_cast<size_t>(tris) - points);
  CHECK(plc.facets.size() == tris);
  CHECK(plc.facets.back().record == static_cast<int64_t>(tris) - 1);
  const PlcInfo info = plc_info(plc);
  CHECK(info.triangles == tris);
  // Grid edges: n(n+1) in each direction plus one diagonal per cell.
  CHECK(info.segments == 2 * static_cast<size_t>(n) * (n + 1) + static_cast<size_t>(n) * n);
  CHECK(info.unreferenced == 0);
  CHECK(info.bbox_max.x == 0.5 * n);
  std::printf("[io] 200978-triangle binary STL (%zu bytes): read_plc %.1f ms\n", bytes.size(),
              std::chrono::duration<double, std::milli>(t1 - t0).count());
}
