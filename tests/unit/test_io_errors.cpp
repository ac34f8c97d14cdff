// Reader errors: one test case per error kind, each naming file and line (or
// record), plus hostile inputs (absurd counts, every truncation, random byte
// damage) that must fail cleanly: no crash, no hang, no huge allocation.
#include <catch2/catch.hpp>
#include <cdt3d/cdt3d.hpp>
#include <cstring>
#include <limits>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "status.hpp"

using namespace cdt3d;

namespace {

Status read_text(const std::string& text, const std::string& name) {
  Plc plc;
  return read_plc(reinterpret_cast<const uint8_t*>(text.data()), text.size(), name, plc);
}

Status read_bytes(const std::vector<uint8_t>& bytes, const std::string& name) {
  Plc plc;
  return read_plc(bytes.data(), bytes.size(), name, plc);
}

void put_u32(std::vector<uint8_t>& b, uint32_t v) {
  for (int k = 0; k < 4; ++k) b.push_back(static_cast<uint8_t>(v >> (8 * k)));
}

void put_f32(std::vector<uint8_t>& b, float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  put_u32(b, u);
}

std::vector<uint8_t> stl_binary(uint32_t declared, const std::vector<float>& coords) {
  std::vector<uint8_t> b(80, 'x');
  put_u32(b, declared);
  for (size_t t = 0; t + 9 <= coords.size(); t += 9) {
    for (int k = 0; k < 3; ++k) put_f32(b, 0);
    for (int k = 0; k < 9; ++k) put_f32(b, coords[t + k]);
    b.push_back(0);
    b.push_back(0);
  }
  return b;
}

const std::vector<float> kTri = {0, 0, 0, 1, 0, 0, 0, 1, 0};

const char* kTetOff =
    "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";

void expect(const Status& s, ErrorCode code, int64_t line) {
  INFO(s.error.to_string());
  CHECK(s.error.code == code);
  CHECK(s.error.line == line);
  CHECK(!s.error.message.empty());
}

}  // namespace

TEST_CASE("Error: empty input", "[io][errors]") {
  for (const char* name : {"a.stl", "a.off", "a.obj", "a.ply", "a.poly", "a.smesh", "a.node"}) {
    INFO(name);
    CHECK(read_text("", name).error.code == ErrorCode::Empty);
    CHECK(read_text(" \n\t\r\n", name).error.code == ErrorCode::Empty);
  }
  CHECK(read_text("# only a comment\n", "a.off").error.code == ErrorCode::Empty);
  CHECK(read_text("# only a comment\n", "a.obj").error.code == ErrorCode::Empty);
  CHECK(read_text("solid x\nendsolid x\n", "a.stl").error.code == ErrorCode::Empty);
  CHECK(read_bytes(stl_binary(0, {}), "a.stl").error.code == ErrorCode::Empty);
  CHECK(read_text("OFF\n0 0 0\n", "a.off").error.code == ErrorCode::Empty);
  const Status s = read_text("", "dir/a.off");
  CHECK(s.error.file == "dir/a.off");
}

TEST_CASE("Error: truncated input names the line or record", "[io][errors]") {
  SECTION("OFF ends inside the vertex list") {
    expect(read_text("OFF\n4 1 0\n0 0 0\n1 0 0\n", "t.off"), ErrorCode::Truncated, 4);
  }
  SECTION("OFF ends inside a face") {
    expect(read_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1", "t.off"), ErrorCode::Truncated, 6);
  }
  SECTION("binary STL shorter than its count: the record where it ends") {
    std::vector<uint8_t> b = stl_binary(3, {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 0, 0, 0, 1, 0});
    const Status s = read_bytes(b, "t.stl");
    CHECK(s.error.code == ErrorCode::Truncated);
    CHECK(s.error.record == 2);
    b.resize(b.size() - 20);
    CHECK(read_bytes(b, "t.stl").error.record == 1);
  }
  SECTION("binary STL longer than its count") {
    std::vector<uint8_t> b = stl_binary(1, kTri);
    b.push_back(0);
    CHECK(read_bytes(b, "t.stl").error.code == ErrorCode::Truncated);
  }
  SECTION("binary STL with a 'solid' header and a wrong size") {
    std::vector<uint8_t> b = stl_binary(2, kTri);
    std::memcpy(b.data(), "solid name", 10);
    const Status s = read_bytes(b, "t.stl");
    CHECK(s.error.code == ErrorCode::Truncated);
    CHECK(s.error.record == 1);
  }
  SECTION("binary STL shorter than its header") {
    const Status s = read_text("abc", "t.stl");
    CHECK(s.error.code == ErrorCode::Truncated);
    CHECK(s.error.record == 0);
  }
  SECTION("ASCII STL ends inside a facet") {
    expect(
        read_text("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n", "t.stl"),
        ErrorCode::Truncated, 5);
  }
  SECTION("PLY header without end_header") {
    expect(read_text("ply\nformat ascii 1.0\nelement vertex 1\n", "t.ply"), ErrorCode::Truncated,
           3);
  }
  SECTION("binary PLY ends inside the vertex element") {
    std::string h =
        "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
        "property float y\nproperty float z\nend_header\n";
    std::vector<uint8_t> b(h.begin(), h.end());
    for (int k = 0; k < 7; ++k) put_f32(b, 1.0f);
    const Status s = read_bytes(b, "t.ply");
    CHECK(s.error.code == ErrorCode::Truncated);
    CHECK(s.error.record == 2);
  }
  SECTION("ASCII PLY ends inside the face element") {
    const std::string t =
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
        "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1\n";
    expect(read_text(t, "t.ply"), ErrorCode::Truncated, 14);
  }
  SECTION(".poly ends inside the facet list") {
    expect(read_text("3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n2 0\n1\n3 1 2 3\n", "t.poly"),
           ErrorCode::Truncated, 7);
  }
}

TEST_CASE("Error: malformed numbers and syntax are parse errors", "[io][errors]") {
  expect(read_text("OFF\n3 1 0\n0 0 0\n1 0.0.0 0\n0 1 0\n3 0 1 2\n", "p.off"), ErrorCode::Parse, 4);
  expect(read_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 x 2\n", "p.off"), ErrorCode::Parse, 6);
  expect(read_text("OFF\nthree 1 0\n", "p.off"), ErrorCode::Parse, 2);
  expect(read_text("OFF\n-3 1 0\n", "p.off"), ErrorCode::Parse, 2);
  expect(read_text("v 1 2\nf 1 2 3\n", "p.obj"), ErrorCode::Parse, 1);
  expect(read_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 a/3\n", "p.obj"), ErrorCode::Parse, 4);
  expect(read_text("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 zero\n", "p.stl"),
         ErrorCode::Parse, 4);
  expect(read_text("solid x\nfacet normal 0 0 1\ninner loop\n", "p.stl"), ErrorCode::Parse, 3);
  expect(read_text("plyx\n", "p.ply"), ErrorCode::Parse, 1);
  expect(read_text("ply\nformat binary_middle_endian 1.0\n", "p.ply"), ErrorCode::Parse, 2);
  expect(read_text("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\n"
                   "end_header\n0 0\n",
                   "p.ply"),
         ErrorCode::Parse, 3);
  expect(read_text("ply\nformat ascii 1.0\nelement vertex 1\nproperty quad x\n", "p.ply"),
         ErrorCode::Parse, 4);
  expect(read_text("2 2 0 0\n1 0 0\n2 1 0\n", "p.poly"), ErrorCode::Parse, 1);
  expect(read_text("1 3 0 0\n5 0 0 0\n", "p.poly"), ErrorCode::Parse, 2);
  expect(read_text("2 3 0 0\n1 0 0 0\n3 1 0 0\n", "p.poly"), ErrorCode::Parse, 3);
}

TEST_CASE("Error: NaN and infinite coordinates name the vertex and line", "[io][errors]") {
  Status s = read_text("OFF\n3 1 0\n0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n", "n.off");
  expect(s, ErrorCode::NonFinite, 4);
  CHECK(s.error.vertex == 1);
  s = read_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 -Infinity 0\n3 0 1 2\n", "n.off");
  expect(s, ErrorCode::NonFinite, 5);
  CHECK(s.error.vertex == 2);
  s = read_text("v 0 0 0\nv inf 0 0\n", "n.obj");
  expect(s, ErrorCode::NonFinite, 2);
  CHECK(s.error.vertex == 1);
  s = read_text("solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 NaN\n", "n.stl");
  expect(s, ErrorCode::NonFinite, 5);
  CHECK(s.error.vertex == 1);
  s = read_text("3 3 0 0\n0 0 0 0\n1 nan 0 0\n", "n.node");
  expect(s, ErrorCode::NonFinite, 3);
  CHECK(s.error.vertex == 1);

  std::vector<float> c = kTri;
  c[7] = std::numeric_limits<float>::quiet_NaN();
  s = read_bytes(stl_binary(1, c), "n.stl");
  CHECK(s.error.code == ErrorCode::NonFinite);
  CHECK(s.error.record == 0);
  CHECK(s.error.vertex == 2);

  std::string h =
      "ply\nformat binary_big_endian 1.0\nelement vertex 2\nproperty double x\n"
      "property double y\nproperty double z\nend_header\n";
  std::vector<uint8_t> b(h.begin(), h.end());
  const double vals[6] = {0, 0, 0, 0, std::numeric_limits<double>::infinity(), 0};
  for (double v : vals) {
    uint64_t u;
    std::memcpy(&u, &v, 8);
    for (int k = 7; k >= 0; --k) b.push_back(static_cast<uint8_t>(u >> (8 * k)));
  }
  s = read_bytes(b, "n.ply");
  CHECK(s.error.code == ErrorCode::NonFinite);
  CHECK(s.error.record == 1);
  CHECK(s.error.vertex == 1);
}

TEST_CASE("Error: coordinates beyond kMaxCoordinate", "[io][errors]") {
  Status s = read_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1.000001e50 0\n3 0 1 2\n", "r.off");
  expect(s, ErrorCode::CoordinateRange, 5);
  CHECK(s.error.vertex == 2);
  s = read_text("OFF\n3 1 0\n0 0 0\n-1e400 0 0\n0 1 0\n3 0 1 2\n", "r.off");
  expect(s, ErrorCode::CoordinateRange, 4);
  CHECK(read_text("OFF\n3 1 0\n0 0 0\n-1e50 0 0\n0 1 0\n3 0 1 2\n", "r.off").ok());
  std::vector<float> c = kTri;
  c[0] = 3e38f;  // fits in a float, not in kMaxCoordinate? 3e38 < 1e50: accepted
  CHECK(read_bytes(stl_binary(1, c), "r.stl").ok());
}

TEST_CASE("Error: vertex index out of range names facet and line", "[io][errors]") {
  Status s = read_text("OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 1 3\n", "i.off");
  expect(s, ErrorCode::IndexOutOfRange, 7);
  CHECK(s.error.facet == 1);
  s = read_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 -1 2\n", "i.off");
  expect(s, ErrorCode::IndexOutOfRange, 6);
  s = read_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 0\n", "i.obj");
  expect(s, ErrorCode::IndexOutOfRange, 5);
  CHECK(s.error.facet == 1);
  s = read_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf -4 -2 -1\n", "i.obj");
  expect(s, ErrorCode::IndexOutOfRange, 4);
  s = read_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n",
                "i.obj");  // forward reference never defined
  expect(s, ErrorCode::IndexOutOfRange, 4);
  CHECK(s.error.facet == 0);
  s = read_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 99999999999999999999\n", "i.obj");
  expect(s, ErrorCode::IndexOutOfRange, 4);
  s = read_text(
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 3\n",
      "i.ply");
  expect(s, ErrorCode::IndexOutOfRange, 13);
  CHECK(s.error.facet == 0);
  s = read_text("3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n1 0\n1\n3 1 2 4\n", "i.poly");
  expect(s, ErrorCode::IndexOutOfRange, 7);
  CHECK(s.error.facet == 0);
  s = read_text("3 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n1 0\n3 0 1 3\n", "i.smesh");
  expect(s, ErrorCode::IndexOutOfRange, 6);
}

TEST_CASE("Error: unknown extension", "[io][errors]") {
  CHECK(read_text(kTetOff, "model.txt").error.code == ErrorCode::UnknownFormat);
  CHECK(read_text(kTetOff, "model").error.code == ErrorCode::UnknownFormat);
  Plc plc;
  CHECK(read_plc_file("/nonexistent/model.xyz", plc).error.code == ErrorCode::UnknownFormat);
}

TEST_CASE("Error: counts beyond 32 bits are too large", "[io][errors]") {
  expect(read_text("OFF\n5000000000 1 0\n", "l.off"), ErrorCode::TooLarge, 2);
  expect(read_text("OFF\n3 4294967296 0\n", "l.off"), ErrorCode::TooLarge, 2);
  expect(read_text("ply\nformat ascii 1.0\nelement vertex 8589934592\n", "l.ply"),
         ErrorCode::TooLarge, 3);
  expect(read_text("99999999999 3 0 0\n", "l.poly"), ErrorCode::TooLarge, 1);
}

TEST_CASE("Error: degenerate facets", "[io][errors]") {
  SECTION("two vertices") {
    Status s = read_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n2 0 1\n", "d.off");
    expect(s, ErrorCode::DegenerateFacet, 6);
    CHECK(s.error.facet == 0);
  }
  SECTION("repeated vertex") {
    Status s = read_text("OFF\n4 2 0\n0 0 0\n1 0 0\n0 1 0\n1 1 0\n3 0 1 2\n4 0 1 3 1\n", "d.off");
    expect(s, ErrorCode::DegenerateFacet, 8);
    CHECK(s.error.facet == 1);
    CHECK(s.error.vertex == 1);
  }
  SECTION("corners welded into a repeated vertex") {
    Status s = read_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0.0 0.0 0.0\n3 0 1 2\n", "d.off");
    expect(s, ErrorCode::DegenerateFacet, 6);
  }
  SECTION("zero area (collinear)") {
    Status s = read_text("OFF\n4 1 0\n0 0 0\n1 1 1\n3 3 3\n2 2 2\n4 0 1 3 2\n", "d.off");
    expect(s, ErrorCode::DegenerateFacet, 7);
  }
  SECTION("zero area in binary STL names the record") {
    const Status s = read_bytes(stl_binary(1, {0, 0, 0, 1, 1, 1, 2, 2, 2}), "d.stl");
    CHECK(s.error.code == ErrorCode::DegenerateFacet);
    CHECK(s.error.record == 0);
    CHECK(s.error.facet == 0);
  }
  SECTION("explicit segment with identical endpoints after welding") {
    Status s = read_text("3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 0 0\n1 0\n1\n2 1 3\n", "d.poly");
    expect(s, ErrorCode::DegenerateFacet, 7);
  }
}

TEST_CASE("Error: non-planar facets", "[io][errors]") {
  Status s = read_text("OFF\n4 1 0\n0 0 0\n1 0 0\n1 1 0\n0 1 1e-300\n4 0 1 2 3\n", "np.off");
  expect(s, ErrorCode::NonPlanarFacet, 7);
  CHECK(s.error.facet == 0);
  CHECK(s.error.vertex == 3);
  // Two loops of one facet in parallel planes.
  s = read_text(
      "6 3 0 0\n1 0 0 0\n2 4 0 0\n3 0 4 0\n4 1 1 1\n5 2 1 1\n6 1 2 1\n"
      "1 0\n2\n3 1 2 3\n3 4 5 6\n",
      "np.poly");
  expect(s, ErrorCode::NonPlanarFacet, 9);
  // Exactly coplanar but far from axis-aligned: accepted.
  CHECK(read_text("OFF\n4 1 0\n0 0 0\n1 2 3\n2 3 5\n3 5 8\n4 0 1 3 2\n", "p.off").ok());
}

TEST_CASE("Error: duplicate facets name both", "[io][errors]") {
  SECTION("reversed orientation") {
    Status s = read_text(std::string(kTetOff) + "", "d.off");
    REQUIRE(s.ok());
    s = read_text("OFF\n4 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n3 2 1 0\n", "d.off");
    expect(s, ErrorCode::DuplicateFacet, 9);
    CHECK(s.error.facet == 2);
    CHECK(s.error.other_facet == 0);
  }
  SECTION("same quad from another start vertex") {
    Status s = read_text("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n4 2 3 0 1\n", "d.off");
    expect(s, ErrorCode::DuplicateFacet, 8);
  }
  SECTION("a triangle and a quad sharing three vertices are different facets") {
    CHECK(read_text("OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n3 0 1 2\n", "d.off").ok());
  }
  SECTION("multi-loop facets with their loops in another order") {
    const std::string t =
        "8 3 0 0\n1 0 0 0\n2 4 0 0\n3 4 4 0\n4 0 4 0\n5 1 1 0\n6 2 1 0\n7 2 2 0\n8 1 2 0\n"
        "2 0\n2 1\n4 1 2 3 4\n4 5 6 7 8\n0 0 0 0\n2 1\n4 8 7 6 5\n4 4 3 2 1\n0 1.5 1.5 0\n";
    Status s = read_text(t, "d.poly");
    expect(s, ErrorCode::DuplicateFacet, 15);
    CHECK(s.error.facet == 1);
    CHECK(s.error.other_facet == 0);
  }
}

TEST_CASE("Hostile headers never allocate what the file cannot hold", "[io][errors][hostile]") {
  CHECK(read_text("OFF\n4294967294 4294967294 0\n0 0 0\n", "h.off").error.code ==
        ErrorCode::Truncated);
  CHECK(read_text("OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n4294967294 0 1 2\n", "h.off").error.code ==
        ErrorCode::Truncated);
  CHECK(read_text("4294967294 3 0 0\n1 0 0 0\n", "h.poly").error.code == ErrorCode::Truncated);
  CHECK(read_text("3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4294967294 0\n1\n", "h.poly").error.code ==
        ErrorCode::Truncated);
  CHECK(
      read_text("3 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n1 0\n4294967294 0 0\n", "h.poly").error.code ==
      ErrorCode::Truncated);
  // Binary PLY: huge element counts and list lengths against a tiny body.
  std::string h =
      "ply\nformat binary_little_endian 1.0\nelement vertex 4294967294\nproperty float x\n"
      "property float y\nproperty float z\nend_header\n";
  std::vector<uint8_t> b(h.begin(), h.end());
  for (int k = 0; k < 3; ++k) put_f32(b, 0);
  CHECK(read_bytes(b, "h.ply").error.code == ErrorCode::Truncated);
  h = "ply\nformat binary_little_endian 1.0\nelement vertex 1\nproperty float x\n"
      "property float y\nproperty float z\nelement face 1\nproperty list uint int vertex_indices\n"
      "end_header\n";
  b.assign(h.begin(), h.end());
  for (int k = 0; k < 3; ++k) put_f32(b, 0);
  put_u32(b, 4000000000u);
  put_u32(b, 0);
  CHECK(read_bytes(b, "h.ply").error.code == ErrorCode::Truncated);
  // Elements without properties cost nothing however many there are.
  h = "ply\nformat binary_little_endian 1.0\nelement nothing 4294967294\nelement vertex 1\n"
      "property float x\nproperty float y\nproperty float z\nend_header\n";
  b.assign(h.begin(), h.end());
  for (int k = 0; k < 3; ++k) put_f32(b, 0);
  CHECK(read_bytes(b, "h.ply").ok());
  // Binary STL with the largest count: the size check comes first.
  CHECK(read_bytes(stl_binary(0xffffffffu, kTri), "h.stl").error.code == ErrorCode::Truncated);
}

namespace {

// Small deterministic generator (the same sequence on every platform).
struct Lcg {
  uint64_t s;
  uint32_t next() {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<uint32_t>(s >> 33);
  }
};

void check_clean_failure(const std::vector<uint8_t>& bytes, const std::string& name) {
  Plc plc;
  const Status s = read_plc(bytes.data(), bytes.size(), name, plc);
  if (s.ok()) {
    CHECK(check_plc(plc).ok());
    return;
  }
  INFO(name << ": " << s.error.to_string());
  CHECK(!s.error.message.empty());
  CHECK(s.error.file == name);
  CHECK(plc.points.empty());
  if (s.error.code != ErrorCode::Empty) CHECK((s.error.line >= 1 || s.error.record >= 0));
}

std::vector<std::pair<std::string, std::vector<uint8_t>>> samples() {
  std::vector<std::pair<std::string, std::vector<uint8_t>>> out;
  auto text = [&out](const char* name, const std::string& t) {
    out.emplace_back(name, std::vector<uint8_t>(t.begin(), t.end()));
  };
  text("s.off", kTetOff);
  text(
      "s.obj",
      "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1/1 2/1 4/1\nf 2//1 3//1 4//1\nf -4 -1 -2\n");
  text("s.stl",
       "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
       "endloop\nendfacet\nendsolid s\n");
  text("s.ply",
       "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\n"
       "property float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n"
       "0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n");
  text("s.poly",
       "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n4 1\n1 0 1\n3 1 3 2\n2 0 2\n3 1 2 4\n1 4\n"
       "2 1\n3 2 3 4\n2 2 3\n1 0.3 0.3 0.4\n1 0 0\n3 1 4 3\n1\n1 5 5 5\n1\n1 0.1 0.1 0.1 1 0.5\n");
  text("s.smesh",
       "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n4 1\n3 1 3 2 1\n3 1 2 4\n3 2 3 4\n3 1 4 "
       "3\n0\n0\n");
  out.emplace_back("b.stl", stl_binary(2, {0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1}));
  std::string h =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n";
  std::vector<uint8_t> b(h.begin(), h.end());
  for (float f : kTri) put_f32(b, f);
  b.push_back(3);
  for (uint32_t v = 0; v < 3; ++v) put_u32(b, v);
  out.emplace_back("b.ply", b);
  return out;
}

}  // namespace

TEST_CASE("Every truncation of a valid file fails cleanly or still reads",
          "[io][errors][hostile]") {
  for (const auto& sample : samples()) {
    Plc plc;
    INFO(sample.first);
    REQUIRE(read_plc(sample.second.data(), sample.second.size(), sample.first, plc).ok());
    for (size_t n = 0; n < sample.second.size(); ++n) {
      std::vector<uint8_t> cut(sample.second.begin(),
                               sample.second.begin() + static_cast<std::ptrdiff_t>(n));
      check_clean_failure(cut, sample.first);
    }
  }
}

TEST_CASE("Random byte damage never crashes a reader", "[io][errors][hostile]") {
  Lcg rng{12345};
  const uint8_t specials[] = {0, '\n', ' ', '#', '-', '9', '/', 0xff, 0x80, '.', 'e'};
  for (const auto& sample : samples()) {
    for (int round = 0; round < 300; ++round) {
      std::vector<uint8_t> bytes = sample.second;
      const int edits = 1 + static_cast<int>(rng.next() % 4);
      for (int e = 0; e < edits; ++e) {
        const size_t at = rng.next() % bytes.size();
        switch (rng.next() % 4) {
          case 0:
            bytes[at] = static_cast<uint8_t>(rng.next());
            break;
          case 1:
            bytes[at] = specials[rng.next() % sizeof specials];
            break;
          case 2:
            bytes.erase(bytes.begin() + static_cast<std::ptrdiff_t>(at));
            break;
          default:
            bytes.insert(bytes.begin() + static_cast<std::ptrdiff_t>(at),
                         specials[rng.next() % sizeof specials]);
            break;
        }
        if (bytes.empty()) bytes.push_back('0');
      }
      check_clean_failure(bytes, sample.first);
    }
  }
}

// The handlers catch everything and ask current_exception_code(), because
// the threaded WebAssembly build matches no typed catch clause (status.hpp).
TEST_CASE("Error: an exception caught by catch (...) maps to out-of-memory or internal",
          "[errors]") {
  clear_allocation_failure();
  auto code_of = [](auto&& thrower) {
    try {
      thrower();
    } catch (...) {
      return std::make_pair(current_exception_code(), current_exception_text());
    }
    return std::make_pair(ErrorCode::Ok, std::string());
  };
  CHECK(code_of([] { throw std::bad_alloc(); }).first == ErrorCode::OutOfMemory);
  const auto other = code_of([] { throw std::runtime_error("boom"); });
  CHECK(other.first == ErrorCode::Internal);
  CHECK(other.second == "boom");
  CHECK(code_of([] { throw 7; }).second.empty());
  // Where the type cannot be seen, a failed allocation noted by the
  // new-handler decides.
  note_allocation_failure();
  CHECK(code_of([] { throw 7; }).first == ErrorCode::OutOfMemory);
  clear_allocation_failure();
  CHECK(code_of([] { throw 7; }).first == ErrorCode::Internal);
  // The one error every handler builds from it.
  auto error_of = [](auto&& thrower) {
    try {
      thrower();
    } catch (...) {
      return current_exception_error("meshing", "m.off");
    }
    return Error();
  };
  const Error oom = error_of([] { throw std::bad_alloc(); });
  CHECK(oom.code == ErrorCode::OutOfMemory);
  CHECK(oom.message == "Out of memory while meshing.");
  CHECK(oom.file == "m.off");
  const Error boom = error_of([] { throw std::runtime_error("boom"); });
  CHECK(boom.code == ErrorCode::Internal);
  CHECK(boom.message == "Unexpected failure while meshing: boom");
  CHECK(error_of([] { throw 7; }).message == "Unexpected failure while meshing.");
}

// The readers' record loops and check_plc's loops run in blocks of
// kBlockItems (base/blocks.hpp): an error in a later block must name its own
// record, line, vertex and facet, as one in the first block does.
TEST_CASE("Error: a bad record past the first blocks names itself", "[io][errors]") {
  const int n = 3 * 4096 + 17;  // vertices in a fan strip; bad ones near the end
  const int bad = n - 5;
  auto coords = [](int i) {
    return std::to_string(i % 2) + " " + std::to_string(i / 2) + " " + std::to_string(i % 3);
  };
  std::string off = "OFF\n" + std::to_string(n) + " " + std::to_string(n - 2) + " 0\n";
  std::string obj;
  for (int i = 0; i < n; ++i) {
    off += (i == bad ? std::string("1 nan 0") : coords(i)) + "\n";
    obj += "v " + (i == bad ? std::string("1 nan 0") : coords(i)) + "\n";
  }
  Status s = read_text(off, "b.off");
  expect(s, ErrorCode::NonFinite, 3 + bad);
  CHECK(s.error.vertex == bad);
  s = read_text(obj, "b.obj");
  expect(s, ErrorCode::NonFinite, 1 + bad);
  CHECK(s.error.vertex == bad);

  // Faces: the one before the last uses a vertex beyond the count.
  std::string faces;
  for (int i = 0; i + 2 < n; ++i) {
    const int last = i == n - 4 ? n : i + 2;
    faces += "3 " + std::to_string(i) + " " + std::to_string(i + 1) + " " +
             std::to_string(last) + "\n";
  }
  std::string good = "OFF\n" + std::to_string(n) + " " + std::to_string(n - 2) + " 0\n";
  for (int i = 0; i < n; ++i) good += coords(i) + "\n";
  s = read_text(good + faces, "f.off");
  expect(s, ErrorCode::IndexOutOfRange, 3 + n + (n - 4));
  CHECK(s.error.facet == n - 4);

  // Binary STL and PLY records.
  std::vector<float> tris;
  for (int t = 0; t < n; ++t) {
    const float z = static_cast<float>(t);
    const float tri[9] = {0, 0, z, 1, 0, z, 0, 1, z};
    tris.insert(tris.end(), tri, tri + 9);
  }
  tris[9 * bad + 4] = std::numeric_limits<float>::quiet_NaN();
  s = read_bytes(stl_binary(static_cast<uint32_t>(n), tris), "b.stl");
  CHECK(s.error.code == ErrorCode::NonFinite);
  CHECK(s.error.record == bad);
  CHECK(s.error.vertex == 3 * bad + 1);

  std::string h = "ply\nformat binary_little_endian 1.0\nelement vertex " + std::to_string(n) +
                  "\nproperty float x\nproperty float y\nproperty float z\nend_header\n";
  std::vector<uint8_t> ply(h.begin(), h.end());
  for (int i = 0; i < n; ++i) {
    put_f32(ply, static_cast<float>(i));
    put_f32(ply, i == bad ? std::numeric_limits<float>::infinity() : 0.0f);
    put_f32(ply, 0);
  }
  s = read_bytes(ply, "b.ply");
  CHECK(s.error.code == ErrorCode::NonFinite);
  CHECK(s.error.record == bad);
}

TEST_CASE("Error: check_plc names a bad facet past the first blocks", "[io][errors]") {
  // A strip of n - 2 triangles over n points on two lines, all valid but for
  // one facet near the end.
  const int n = 2 * 4096 + 101;
  Plc plc;
  for (int i = 0; i < n; ++i) {
    plc.points.push_back({static_cast<double>(i / 2), static_cast<double>(i % 2), 0});
  }
  for (int i = 0; i + 2 < n; ++i) {
    Facet f;
    f.loops.push_back({static_cast<VertexId>(i), static_cast<VertexId>(i + 1),
                       static_cast<VertexId>(i + 2)});
    plc.facets.push_back(f);
  }
  REQUIRE(check_plc(plc).ok());
  const int bad = n - 7;
  Plc repeated = plc;
  repeated.facets[bad].loops[0][2] = repeated.facets[bad].loops[0][0];
  Status s = check_plc(repeated);
  CHECK(s.error.code == ErrorCode::DegenerateFacet);
  CHECK(s.error.facet == bad);
  Plc duplicated = plc;
  duplicated.facets.push_back(plc.facets[bad]);
  s = check_plc(duplicated);
  CHECK(s.error.code == ErrorCode::DuplicateFacet);
  CHECK(s.error.facet == n - 2);
  CHECK(s.error.other_facet == bad);
  Plc welded = plc;
  welded.points[n - 3] = welded.points[n - 9];
  s = check_plc(welded);
  CHECK(s.error.code == ErrorCode::InvalidArgument);
  CHECK(s.error.vertex == n - 3);
}
