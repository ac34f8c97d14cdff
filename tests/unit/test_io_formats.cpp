// Readers, one test case per format: inputs built in memory, counts, welding,
// provenance (line / record) and index remapping checked exactly.
#include <catch2/catch.hpp>
#include <cdt3d/cdt3d.hpp>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "io/read_common.hpp"

using namespace cdt3d;

namespace {

Status read_text(const std::string& text, const std::string& name, Plc& plc) {
  return read_plc(reinterpret_cast<const uint8_t*>(text.data()), text.size(), name, plc);
}

Status read_bytes(const std::vector<uint8_t>& bytes, const std::string& name, Plc& plc) {
  return read_plc(bytes.data(), bytes.size(), name, plc);
}

void put_u32le(std::vector<uint8_t>& b, uint32_t v) {
  for (int k = 0; k < 4; ++k) b.push_back(static_cast<uint8_t>(v >> (8 * k)));
}

void put_f32le(std::vector<uint8_t>& b, float f) {
  uint32_t u;
  std::memcpy(&u, &f, 4);
  put_u32le(b, u);
}

// Binary STL from triangles given as 9 floats each.
std::vector<uint8_t> binary_stl(const std::vector<std::array<float, 9>>& tris, const char* header) {
  std::vector<uint8_t> b(80, ' ');
  std::memcpy(b.data(), header, std::strlen(header));
  put_u32le(b, static_cast<uint32_t>(tris.size()));
  for (const auto& t : tris) {
    for (int k = 0; k < 3; ++k) put_f32le(b, 0.0f);
    for (float f : t) put_f32le(b, f);
    b.push_back(0);
    b.push_back(0);
  }
  return b;
}

const char* kTetOff =
    "OFF\n"
    "4 4 6\n"
    "0 0 0\n"
    "1 0 0\n"
    "0 1 0\n"
    "0 0 1\n"
    "3 0 2 1\n"
    "3 0 1 3\n"
    "3 1 2 3\n"
    "3 0 3 2\n";

// The four triangles of the unit corner tetrahedron as STL corners.
std::vector<std::array<float, 9>> tet_triangles() {
  return {{0, 0, 0, 0, 1, 0, 1, 0, 0},
          {0, 0, 0, 1, 0, 0, 0, 0, 1},
          {1, 0, 0, 0, 1, 0, 0, 0, 1},
          {0, 0, 0, 0, 0, 1, 0, 1, 0}};
}

void check_tet(const Plc& plc) {
  REQUIRE(plc.points.size() == 4);
  REQUIRE(plc.facets.size() == 4);
  const PlcInfo info = plc_info(plc);
  CHECK(info.triangles == 4);
  CHECK(info.segments == 6);
  CHECK(info.unreferenced == 0);
  CHECK(info.bbox_min.x == 0);
  CHECK(info.bbox_max.z == 1);
}

}  // namespace

TEST_CASE("format_from_name picks the format by extension, case-insensitively", "[io]") {
  CHECK(format_from_name("a.stl") == FileFormat::Stl);
  CHECK(format_from_name("dir.v2/A.STL") == FileFormat::Stl);
  CHECK(format_from_name("x.Off") == FileFormat::Off);
  CHECK(format_from_name("x.obj") == FileFormat::Obj);
  CHECK(format_from_name("x.ply") == FileFormat::Ply);
  CHECK(format_from_name("x.poly") == FileFormat::Poly);
  CHECK(format_from_name("x.smesh") == FileFormat::Smesh);
  CHECK(format_from_name("x.node") == FileFormat::Node);
  CHECK(format_from_name("x.stl.gz") == FileFormat::Unknown);
  CHECK(format_from_name("dir.stl/file") == FileFormat::Unknown);
  CHECK(format_from_name("noext") == FileFormat::Unknown);
}

TEST_CASE("OFF: header, comments anywhere, polygons, per-face colours", "[io][off]") {
  Plc plc;
  SECTION("plain tetrahedron") {
    REQUIRE(read_text(kTetOff, "t.off", plc).ok());
    check_tet(plc);
    CHECK(plc.file == "t.off");
    CHECK(plc.file_vertices == 4);
    CHECK(plc.welded_vertices == 0);
    CHECK(plc.facets[0].line == 7);
    CHECK(plc.facets[3].line == 10);
    CHECK(plc.facets[0].record == -1);
    CHECK(plc.facets[0].loops[0] == std::vector<VertexId>{0, 2, 1});
  }
  SECTION("keyword and counts on one line, inline comments, CRLF, colours") {
    const std::string text =
        "# leading comment\r\n"
        "OFF 4 4 0 # counts\r\n"
        "0 0 0 # vertex 0\r\n"
        "1 0 0 255 0 0\r\n"
        "\r\n"
        "0 1 0\r\n"
        "0 0 1\r\n"
        "3 0 2 1 0.5 0.5 0.5 1\r\n"
        "3 0 1 3#no space before the comment\r\n"
        "3 1 2 3\r\n"
        "3 0 3 2\r\n";
    REQUIRE(read_text(text, "t.off", plc).ok());
    check_tet(plc);
    CHECK(plc.facets[0].line == 8);
  }
  SECTION("no keyword, a record continued on the next line") {
    const std::string text =
        "4 4 0\n0 0\n0\n1 0 0\n0 1 0\n0 0 1\n3 0 2\n1\n3 0 1 3\n3 1 2 3\n3 0 3 2\n";
    REQUIRE(read_text(text, "t.off", plc).ok());
    check_tet(plc);
    CHECK(plc.facets[0].loops[0] == std::vector<VertexId>{0, 2, 1});
  }
  SECTION("COFF vertex colours and a quad facet") {
    const std::string text =
        "COFF\n5 2 0\n"
        "0 0 0 1 1 1 1\n1 0 0 1 1 1 1\n1 1 0 1 1 1 1\n0 1 0 1 1 1 1\n0.5 0.5 1 1 1 1 1\n"
        "4 0 1 2 3\n3 0 1 4\n";
    REQUIRE(read_text(text, "q.off", plc).ok());
    REQUIRE(plc.facets.size() == 2);
    CHECK(plc.facets[0].loops.size() == 1);
    CHECK(plc.facets[0].loops[0].size() == 4);
    const PlcInfo info = plc_info(plc);
    CHECK(info.triangles == 3);
    CHECK(info.loops == 2);
    CHECK(info.segments == 6);  // 4 quad edges + 2 more
  }
  SECTION("unreferenced vertices are kept and counted") {
    const std::string text = "OFF\n5 1 0\n0 0 0\n1 0 0\n0 1 0\n7 7 7\n8 8 8\n3 0 1 2\n";
    REQUIRE(read_text(text, "u.off", plc).ok());
    CHECK(plc_info(plc).unreferenced == 2);
  }
  SECTION("4OFF and binary OFF are rejected with a parse error") {
    CHECK(read_text("4OFF\n1 0 0\n0 0 0 0\n", "x.off", plc).error.code == ErrorCode::Parse);
    CHECK(read_text("OFF BINARY\n", "x.off", plc).error.code == ErrorCode::Parse);
  }
}

TEST_CASE("Exact welding: identical coordinates merge, nothing else does", "[io][weld]") {
  Plc plc;
  // Vertex 4 repeats vertex 1 exactly; vertex 5 differs from vertex 2 in the
  // last bit; -0 and +0 are the same point.
  const std::string text =
      "OFF\n7 2 0\n"
      "0 0 0\n"
      "1 0 0\n"
      "0 1 0\n"
      "0 0 1\n"
      "1.0 0e5 -0.0\n"
      "0 1.0000000000000002 0\n"
      "-0 -0 1\n"
      "3 0 1 2\n"
      "3 3 4 5\n";
  REQUIRE(read_text(text, "w.off", plc).ok());
  CHECK(plc.file_vertices == 7);
  CHECK(plc.welded_vertices == 2);
  REQUIRE(plc.points.size() == 5);
  CHECK(plc.facets[1].loops[0] == std::vector<VertexId>{3, 1, 4});
  CHECK(plc.points[4].y == 1.0000000000000002);
  // Point ids follow first appearance: ids equal file indices up to the first weld.
  CHECK(plc.points[3].z == 1);
}

TEST_CASE("Decimal parsing is correctly rounded", "[io][numbers]") {
  Plc plc;
  const std::string text =
      "OFF\n4 1 0\n"
      "0.1 0.30000000000000004 1e-7\n"
      "123456789012345678901234567890 -2.5e-310 1.7976931348623157e308\n"
      "0x1p-3 +4 .5\n"
      "5. 1E2 -0.000001\n"
      "3 0 1 2\n";
  // 1.79e308 exceeds kMaxCoordinate: use a separate check for that.
  Status s = read_text(text, "n.off", plc);
  CHECK(s.error.code == ErrorCode::CoordinateRange);
  CHECK(s.error.vertex == 1);

  const std::string ok =
      "OFF\n4 1 0\n"
      "0.1 0.30000000000000004 1e-7\n"
      "123456789012345678901234567890 -2.5e-310 1e50\n"
      "0x1p-3 +4 .5\n"
      "5. 1E2 -0.000001\n"
      "3 0 1 2\n";
  REQUIRE(read_text(ok, "n.off", plc).ok());
  CHECK(plc.points[0].x == 0.1);
  CHECK(plc.points[0].y == 0.30000000000000004);
  CHECK(plc.points[0].z == 1e-7);
  CHECK(plc.points[1].x == 123456789012345678901234567890.0);
  CHECK(plc.points[1].y == -2.5e-310);
  CHECK(plc.points[1].z == 1e50);
  CHECK(plc.points[2].x == 0.125);
  CHECK(plc.points[2].y == 4);
  CHECK(plc.points[2].z == 0.5);
  CHECK(plc.points[3].x == 5);
  CHECK(plc.points[3].y == 100);
  CHECK(plc.points[3].z == -0.000001);
}

TEST_CASE("STL ASCII: welded corners, several solids, facet lines", "[io][stl]") {
  std::string text = "solid tet\n";
  for (const auto& t : tet_triangles()) {
    text += "  facet normal 0 0 0\n    outer loop\n";
    for (int k = 0; k < 3; ++k) {
      text += "      vertex " + std::to_string(t[3 * k]) + " " + std::to_string(t[3 * k + 1]) +
              " " + std::to_string(t[3 * k + 2]) + "\n";
    }
    text += "    endloop\n  endfacet\n";
  }
  text += "endsolid tet\n";
  Plc plc;
  REQUIRE(read_text(text, "t.stl", plc).ok());
  check_tet(plc);
  CHECK(plc.file_vertices == 12);
  CHECK(plc.welded_vertices == 8);
  CHECK(plc.facets[0].line == 2);
  CHECK(plc.facets[1].line == 9);
  // The solid's name names marker 0 (a Gmsh physical name).
  for (const Facet& f : plc.facets) CHECK(f.marker == 0);
  CHECK(plc.marker_names == std::vector<std::pair<int, std::string>>{{0, "tet"}});

  SECTION("two solids in one file, upper-case keywords, no final endsolid") {
    std::string two = text +
                      "SOLID second  part\nFACET NORMAL 1 2 3\nOUTER LOOP\nVERTEX 5 5 5\nVERTEX 6 5 5\n"
                      "VERTEX 5 6 5\nENDLOOP\nENDFACET\n";
    REQUIRE(read_text(two, "t.stl", plc).ok());
    CHECK(plc.facets.size() == 5);
    CHECK(plc.points.size() == 7);
    // Each solid is a marker of its own, named by its name.
    CHECK(plc.facets[3].marker == 0);
    CHECK(plc.facets[4].marker == 1);
    CHECK(plc.marker_names ==
          std::vector<std::pair<int, std::string>>{{0, "tet"}, {1, "second part"}});
  }
  SECTION("an unnamed solid names nothing") {
    std::string unnamed = text;
    unnamed.replace(0, 9, "solid");
    REQUIRE(read_text(unnamed, "t.stl", plc).ok());
    CHECK(plc.marker_names.empty());
  }
  SECTION("a UTF-8 byte order mark is skipped") {
    REQUIRE(read_text("\xEF\xBB\xBF" + text, "t.stl", plc).ok());
    CHECK(plc.facets[0].line == 2);
    REQUIRE(read_text(std::string("\xEF\xBB\xBF") + kTetOff, "t.off", plc).ok());
    CHECK(plc.facets.size() == 4);
  }
  SECTION("NUL padding after endsolid is ignored") {
    std::string padded = text + std::string(200, '\0');
    REQUIRE(read_text(padded, "t.stl", plc).ok());
    CHECK(plc.facets.size() == 4);
  }
  SECTION("a degenerate normal is ignored") {
    const std::string t1 =
        "solid x\nfacet normal -nan -nan -nan\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
        "vertex 0 1 0\nendloop\nendfacet\nendsolid x\n";
    REQUIRE(read_text(t1, "n.stl", plc).ok());
    CHECK(plc.facets.size() == 1);
  }
  SECTION("a quad loop is a parse error") {
    const std::string q =
        "solid x\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 1 1 0\n"
        "vertex 0 1 0\nendloop\nendfacet\nendsolid x\n";
    const Status s = read_text(q, "q.stl", plc);
    CHECK(s.error.code == ErrorCode::Parse);
    CHECK(s.error.line == 7);
  }
}

TEST_CASE("STL binary: records, welding, a header starting with 'solid'", "[io][stl]") {
  Plc plc;
  SECTION("ordinary header") {
    REQUIRE(read_bytes(binary_stl(tet_triangles(), "binary"), "t.stl", plc).ok());
    check_tet(plc);
    CHECK(plc.file_vertices == 12);
    CHECK(plc.welded_vertices == 8);
    CHECK(plc.facets[2].record == 2);
    CHECK(plc.facets[2].line == -1);
  }
  SECTION("header beginning with 'solid' is still binary when the size matches") {
    REQUIRE(read_bytes(binary_stl(tet_triangles(), "solid looks like ascii"), "t.stl", plc).ok());
    check_tet(plc);
  }
  SECTION("float coordinates convert exactly") {
    std::vector<std::array<float, 9>> tris = {{0.1f, 0, 0, 1, 0, 0, 0, 1, 0}};
    REQUIRE(read_bytes(binary_stl(tris, "f"), "f.stl", plc).ok());
    CHECK(plc.points[0].x == static_cast<double>(0.1f));
  }
}

TEST_CASE("OBJ: v/f lines, corner forms, negative indices, polylines", "[io][obj]") {
  Plc plc;
  SECTION("all corner forms and ignored statements") {
    const std::string text =
        "# tetrahedron\n"
        "mtllib x.mtl\n"
        "o tet\n"
        "v 0 0 0\n"
        "v 1 0 0\n"
        "v 0 1 0\n"
        "v 0 0 1 1.0\n"
        "vt 0 0\n"
        "vn 0 0 1\n"
        "g group\n"
        "usemtl m\n"
        "s off\n"
        "f 1 3 2\n"
        "f 1/1 2/1 4/1\n"
        "f 2//1 3//1 4//1\n"
        "f -4/1/1 -1/1/1 -2/1/1\n";
    REQUIRE(read_text(text, "t.obj", plc).ok());
    check_tet(plc);
    CHECK(plc.facets[3].loops[0] == std::vector<VertexId>{0, 3, 2});
    CHECK(plc.facets[0].line == 13);
    CHECK(plc.facets[3].line == 16);
    // "o tet" is marker 1, then "g group" marker 2 for the faces after it.
    for (const Facet& f : plc.facets) CHECK(f.marker == 2);
    CHECK(plc.marker_names == std::vector<std::pair<int, std::string>>{{1, "tet"}, {2, "group"}});
  }
  SECTION("groups name markers; a group named again takes its marker back") {
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n"
        "f 1 3 2\n"
        "g bottom\nf 1 2 4\n"
        "g side\nf 2 3 4\n"
        "g bottom\nf 1 4 3\n";
    REQUIRE(read_text(text, "g.obj", plc).ok());
    REQUIRE(plc.facets.size() == 4);
    CHECK(plc.facets[0].marker == 0);
    CHECK(plc.facets[1].marker == 1);
    CHECK(plc.facets[2].marker == 2);
    CHECK(plc.facets[3].marker == 1);
    CHECK(plc.marker_names == std::vector<std::pair<int, std::string>>{{1, "bottom"}, {2, "side"}});
  }
  SECTION("faces before later vertices, polygons, l and p statements") {
    const std::string text =
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n"
        "f 1 2 3 4\n"
        "v 0 0 1\n"
        "f -5 -4 -1\n"
        "l 1 3 5\n"
        "p 2\n";
    REQUIRE(read_text(text, "p.obj", plc).ok());
    REQUIRE(plc.facets.size() == 2);
    CHECK(plc.facets[0].loops[0].size() == 4);
    CHECK(plc.facets[1].loops[0] == std::vector<VertexId>{0, 1, 4});
    REQUIRE(plc.segments.size() == 2);
    CHECK(plc.segments[0] == std::array<VertexId, 2>{0, 2});
    CHECK(plc.segments[1] == std::array<VertexId, 2>{2, 4});
    CHECK(plc_info(plc).triangles == 3);
  }
}

TEST_CASE("OBJ: a trailing backslash continues a statement on the next line", "[io][obj]") {
  Plc plc;
  SECTION("face and vertex lines continued, with blanks and CRLF after the backslash") {
    const std::string text =
        "v 0 0 0\nv 1 0 \\\n 0\nv 0 1 0\nv 0 0 1\n"
        "f 1 3 \\\n 2\n"
        "f 1 2\\\r\n4\n"
        "f 2 3 \\  \n\\\n 4\n"
        "vt 0.5 \\\n 0.5\n"
        "f 1 4 3\n";
    REQUIRE(read_text(text, "c.obj", plc).ok());
    check_tet(plc);
    CHECK(plc.facets[0].loops[0] == std::vector<VertexId>{0, 2, 1});
    CHECK(plc.facets[1].loops[0] == std::vector<VertexId>{0, 1, 3});
    // Provenance is the physical line the statement starts on.
    CHECK(plc.facets[0].line == 6);
    CHECK(plc.facets[1].line == 8);
    CHECK(plc.facets[2].line == 10);
    CHECK(plc.facets[3].line == 15);
  }
  SECTION("an error after a continuation names the physical line of the bad token") {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 \\\n2 \\\nx3\n";
    Status s = read_text(text, "c.obj", plc);
    CHECK(s.error.code == ErrorCode::Parse);
    CHECK(s.error.line == 6);
  }
  SECTION("a backslash inside a line is no continuation") {
    const std::string text = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 \\ 2 3\n";
    Status s = read_text(text, "c.obj", plc);
    CHECK(s.error.code == ErrorCode::Parse);
    CHECK(s.error.line == 4);
  }
}

namespace {

// PLY with a vertex element (x y z among other properties) and a face element,
// written in the given binary byte order.
std::vector<uint8_t> binary_ply(bool big_endian) {
  std::string header = std::string("ply\nformat ") +
                       (big_endian ? "binary_big_endian" : "binary_little_endian") +
                       " 1.0\ncomment made in a test\n"
                       "element vertex 4\n"
                       "property uchar flag\n"
                       "property double x\n"
                       "property float y\n"
                       "property list uchar short junk\n"
                       "property int z\n"
                       "element material 2\n"
                       "property list int uint names\n"
                       "property double shine\n"
                       "element face 4\n"
                       "property int id\n"
                       "property list uint8 uint32 vertex_indices\n"
                       "property uchar red\n"
                       "end_header\n";
  std::vector<uint8_t> b(header.begin(), header.end());
  auto put = [&b, big_endian](const void* p, size_t n) {
    const uint8_t* q = static_cast<const uint8_t*>(p);
    for (size_t k = 0; k < n; ++k) b.push_back(q[big_endian ? n - 1 - k : k]);
  };
  const double xs[4] = {0, 1, 0, 0};
  const float ys[4] = {0, 0, 1, 0};
  const int32_t zs[4] = {0, 0, 0, 1};
  for (int v = 0; v < 4; ++v) {
    const uint8_t flag = 7;
    put(&flag, 1);
    put(&xs[v], 8);
    const float y = ys[v];
    put(&y, 4);
    const uint8_t junk_n = static_cast<uint8_t>(v);  // 0..3 shorts
    put(&junk_n, 1);
    for (int j = 0; j < v; ++j) {
      const int16_t s = static_cast<int16_t>(-j);
      put(&s, 2);
    }
    put(&zs[v], 4);
  }
  for (int m = 0; m < 2; ++m) {
    const int32_t n = 3;
    put(&n, 4);
    for (uint32_t k = 0; k < 3; ++k) put(&k, 4);
    const double shine = 0.5;
    put(&shine, 8);
  }
  const uint32_t faces[4][3] = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  for (int f = 0; f < 4; ++f) {
    const int32_t id = f;
    put(&id, 4);
    const uint8_t n = 3;
    put(&n, 1);
    for (uint32_t v : faces[f]) put(&v, 4);
    const uint8_t red = 255;
    put(&red, 1);
  }
  return b;
}

}  // namespace

TEST_CASE("PLY: ascii, binary little and big endian, other elements skipped", "[io][ply]") {
  Plc plc;
  SECTION("ascii with polygons and extra properties") {
    const std::string text =
        "ply\nformat ascii 1.0\ncomment c\n"
        "element vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
        "property uchar red\n"
        "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
        "element face 2\nproperty list uchar int vertex_index\nproperty list uchar float uv\n"
        "end_header\n"
        "0 0 0 1\n1 0 0 1\n1 1 0 1\n0 1 0 1\n0.5 0.5 1 1\n"
        "0 1\n"
        "4 0 1 2 3 2 0.5 0.5\n"
        "3 0 1 4 0\n";
    REQUIRE(read_text(text, "a.ply", plc).ok());
    REQUIRE(plc.facets.size() == 2);
    CHECK(plc.facets[0].loops[0] == std::vector<VertexId>{0, 1, 2, 3});
    CHECK(plc.facets[0].line == 22);
    CHECK(plc.facets[1].line == 23);
    CHECK(plc.points[4].z == 1);
    CHECK(plc_info(plc).triangles == 3);
  }
  SECTION("binary little endian") {
    REQUIRE(read_bytes(binary_ply(false), "b.ply", plc).ok());
    check_tet(plc);
    CHECK(plc.facets[1].record == 1);
    CHECK(plc.facets[1].loops[0] == std::vector<VertexId>{0, 1, 3});
  }
  SECTION("binary big endian") {
    REQUIRE(read_bytes(binary_ply(true), "b.ply", plc).ok());
    check_tet(plc);
    CHECK(plc.facets[3].loops[0] == std::vector<VertexId>{0, 3, 2});
  }
  SECTION("binary truncated inside a face record") {
    std::vector<uint8_t> b = binary_ply(false);
    b.resize(b.size() - 5);
    const Status s = read_bytes(b, "b.ply", plc);
    CHECK(s.error.code == ErrorCode::Truncated);
    CHECK(s.error.record == 3);
  }
}

TEST_CASE("TetGen .poly: facets with several polygons, segments, holes, regions", "[io][poly]") {
  const std::string text =
      "# unit cube [0,2]^3, 1-based\n"
      "10 3 1 1\n"
      "1 0 0 0 5 1\n"
      "2 2 0 0 5 1\n"
      "3 2 2 0 5 1\n"
      "4 0 2 0 5 1\n"
      "5 0 0 2 5 1\n"
      "6 2 0 2 5 1\n"
      "7 2 2 2 5 1\n"
      "8 0 2 2 5 1\n"
      "9 0.5 0.5 0\n"
      "10 1.5 0.5 0\n"
      "6 1\n"
      "2 0 3  # bottom: a quad and a segment inside it\n"
      "4 1 2 3 4\n"
      "2 9 10\n"
      "1 0 1\n"
      "4 5 6 7 8\n"
      "1 0 1\n"
      "4 1 2 6 5\n"
      "1 0 1\n"
      "4 2 3 7 6\n"
      "1 0 1\n"
      "4 3 4 8 7\n"
      "2 1 1\n"
      "4 4 1 5 8\n"
      "1 5\n"
      "1 0 1 1\n"
      "1\n"
      "1 1 1 1\n"
      "2\n"
      "1 0.5 0.5 0.5 10 0.01\n"
      "2 1.5 1.5 1.5 20\n";
  Plc plc;
  const Status s = read_text(text, "c.poly", plc);
  INFO(s.error.to_string());
  REQUIRE(s.ok());
  CHECK(plc.file_vertices == 10);
  REQUIRE(plc.facets.size() == 6);
  CHECK(plc.facets[0].marker == 3);
  CHECK(plc.facets[0].line == 14);
  CHECK(plc.facets[0].loops[0] == std::vector<VertexId>{0, 1, 2, 3});
  REQUIRE(plc.segments.size() == 1);
  CHECK(plc.segments[0] == std::array<VertexId, 2>{8, 9});
  // The last facet has an isolated point polygon and a facet hole point.
  CHECK(plc.facets[5].loops.size() == 1);
  REQUIRE(plc.facets[5].holes.size() == 1);
  CHECK(plc.facets[5].holes[0].y == 1);
  REQUIRE(plc.holes.size() == 1);
  CHECK(plc.holes[0].x == 1);
  REQUIRE(plc.regions.size() == 2);
  CHECK(plc.regions[0].attribute == 10);
  CHECK(plc.regions[0].max_volume == 0.01);
  CHECK(plc.regions[1].attribute == 20);
  CHECK(plc.regions[1].max_volume == -1);
  const PlcInfo info = plc_info(plc);
  CHECK(info.triangles == 12);
  CHECK(info.segments == 13);  // 12 cube edges + the explicit segment
  CHECK(info.unreferenced == 0);
}

TEST_CASE("TetGen .poly without hole and region sections, 0-based", "[io][poly]") {
  const std::string text =
      "4 3 0 0\n0 0 0 0\n1 1 0 0\n2 0 1 0\n3 0 0 1\n"
      "4 0\n1\n3 0 2 1\n1\n3 0 1 3\n1\n3 1 2 3\n1\n3 0 3 2\n";
  Plc plc;
  REQUIRE(read_text(text, "t.poly", plc).ok());
  check_tet(plc);
  CHECK(plc.holes.empty());
  CHECK(plc.regions.empty());
}

TEST_CASE("TetGen .smesh: one polygon per facet line with markers", "[io][smesh]") {
  const std::string text =
      "# tet\n"
      "4 3 0 0\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n"
      "5 1\n"
      "3 1 3 2 7\n"
      "3 1 2 4 8\n"
      "3 2 3 4\n"
      "3 1 4 3 9\n"
      "2 1 2\n"
      "0\n0\n";
  Plc plc;
  const Status s = read_text(text, "t.smesh", plc);
  INFO(s.error.to_string());
  REQUIRE(s.ok());
  check_tet(plc);
  CHECK(plc.facets[0].marker == 7);
  CHECK(plc.facets[2].marker == 0);
  CHECK(plc.facets[3].marker == 9);
  CHECK(plc.facets[3].line == 11);
  REQUIRE(plc.segments.size() == 1);
}

TEST_CASE("TetGen .smesh with node count 0 names the missing .node file", "[io][smesh]") {
  Plc plc;
  const Status s = read_text("0 3 0 0\n1 0\n3 1 2 3\n", "x.smesh", plc);
  CHECK(s.error.code == ErrorCode::Parse);
  CHECK(s.error.line == 1);
  CHECK(s.error.message.find(".node") != std::string::npos);
}

TEST_CASE("TetGen .node: points only", "[io][node]") {
  Plc plc;
  REQUIRE(read_text("3 3 0 1\n0 0 0 0 1\n1 1 0 0 1\n2 1 1 1 0\n", "p.node", plc).ok());
  CHECK(plc.points.size() == 3);
  CHECK(plc.facets.empty());
  CHECK(plc_info(plc).unreferenced == 3);
}

// exact_decimal, parse_double's path for 16- to 19-digit mantissas (the
// WASM build's strtod is slow), against glibc's strtod, which rounds
// correctly: random mantissas and exponents, and exact ties (values halfway
// between two doubles, which must go to the even one).
TEST_CASE("exact_decimal rounds like a correctly rounded strtod", "[io]") {
  uint64_t state = 0x9E3779B97F4A7C15ull;
  auto next = [&state] {
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    return state;
  };
  int checked = 0;
  for (int i = 0; i < 200000; ++i) {
    const int digits = 1 + static_cast<int>(next() % 19);
    uint64_t m = 0;
    for (int k = 0; k < digits; ++k) m = m * 10 + next() % 10;
    if (m == 0) continue;
    const int e10 = static_cast<int>(next() % 45) - 22;
    const std::string text = std::to_string(m) + "e" + std::to_string(e10);
    double got = 0;
    REQUIRE(io::exact_decimal(m, e10, got));
    const double want = std::strtod(text.c_str(), nullptr);
    if (got != want) FAIL_CHECK(text << ": " << got << " != " << want);
    ++checked;
  }
  for (int i = 0; i < 20000; ++i) {
    const uint64_t V = (uint64_t{1} << 52) | (next() >> 12);  // a 53-bit significand
    const int shift = 1 + static_cast<int>(next() % 10);       // halfway: (2V + 1) * 2^(shift - 1)
    const uint64_t tie = (2 * V + 1) << (shift - 1);
    double got = 0;
    REQUIRE(io::exact_decimal(tie, 0, got));
    const double lo = std::ldexp(static_cast<double>(V), shift), hi = std::nextafter(lo, HUGE_VAL);
    CHECK(got == ((V & 1) ? hi : lo));
    CHECK(got == std::strtod(std::to_string(tie).c_str(), nullptr));
  }
  // Ties below a negative power of ten (the reciprocal path, which must hand
  // them to the exact division): (2V + 1) * 5^k / 10^k = (2V + 1) / 2^k.
  for (int i = 0; i < 20000; ++i) {
    const uint64_t V = (uint64_t{1} << 52) | (next() >> 12);
    const int k = 1 + static_cast<int>(next() % 4);
    uint64_t tie = 2 * V + 1;
    for (int j = 0; j < k; ++j) tie *= 5;
    double got = 0;
    REQUIRE(io::exact_decimal(tie, -k, got));
    const double lo = std::ldexp(static_cast<double>(V), 1 - k), hi = std::nextafter(lo, HUGE_VAL);
    CHECK(got == ((V & 1) ? hi : lo));
  }
  CHECK(checked > 150000);
  double out = 0;
  CHECK_FALSE(io::exact_decimal(12345, 23, out));
  CHECK_FALSE(io::exact_decimal(0, 0, out));
}

// parse_decimal, parse_double's path where there is no from_chars (the
// WebAssembly build, which natively only this test runs), against glibc's
// correctly rounded strtod: random decimals with leading and trailing zeros,
// up to 25 digits around the point (digits read eight at a time and one at
// a time), signs and exponents; and tokens that are not numbers.
TEST_CASE("parse_decimal reads like a correctly rounded strtod", "[io]") {
  uint64_t state = 0xD1B54A32D192ED03ull;
  auto next = [&state] {
    state ^= state << 13, state ^= state >> 7, state ^= state << 17;
    return state;
  };
  auto digits = [&](int k) {
    std::string d;
    for (int i = 0; i < k; ++i) d += static_cast<char>('0' + next() % 10);
    return d;
  };
  int checked = 0;
  for (int i = 0; i < 200000; ++i) {
    std::string text;
    if (next() % 4 == 0) text += (next() % 2) ? "-" : "+";
    text += std::string(next() % 3, '0') + digits(static_cast<int>(next() % 12));
    if (next() % 4 != 0) text += "." + std::string(next() % 4, '0') + digits(static_cast<int>(next() % 22));
    if (text.find_first_of("0123456789") == std::string::npos) text += "7";
    if (next() % 3 == 0) text += "e" + std::to_string(static_cast<int>(next() % 61) - 30);
    double got = 0;
    REQUIRE(io::parse_decimal(text.data(), text.size(), got) == io::NumParse::Ok);
    double want = std::strtod(text.c_str(), nullptr);
    if (want == 0) want = 0.0;  // -0 -> +0
    if (got != want || std::signbit(got) != std::signbit(want)) FAIL_CHECK(text << ": " << got << " != " << want);
    ++checked;
  }
  CHECK(checked == 200000);
  double out = 0;
  for (const char* bad : {"1.2.3", "12345678x", "1234567890123x", "0.12345678-", "e5", "-", "1e"})
    CHECK(io::parse_decimal(bad, std::strlen(bad), out) == io::NumParse::Bad);
  CHECK(io::parse_decimal("123456789012345678", 18, out) == io::NumParse::Ok);
  CHECK(out == 123456789012345678.0);
}

// TextReader::next takes the usual token inline and the rest through the
// general path; next_uint reads plain indices. Both must agree with a plain
// definition of the tokens: maximal runs without white space, cut before a
// comment mark, with the line they start on.
TEST_CASE("TextReader tokens and indices match a plain tokenization", "[io]") {
  const std::string text =
      "OFF\r\n  3\t4 0 # comment 5\n\n 1.5 -2e3 +7\f8 9\x01x 10#c\n"
      "\t\t 11 \v 12\r\n0012 123456789012345678 1234567890123456789 \n13";
  struct Want {
    std::string token;
    int64_t line;
  };
  const std::vector<Want> want = {{"OFF", 1},
                                  {"3", 2},
                                  {"4", 2},
                                  {"0", 2},
                                  {"1.5", 4},
                                  {"-2e3", 4},
                                  {"+7", 4},
                                  {"8", 4},
                                  {"9\x01x", 4},
                                  {"10", 4},
                                  {"11", 5},
                                  {"12", 5},
                                  {"0012", 6},
                                  {"123456789012345678", 6},
                                  {"1234567890123456789", 6},
                                  {"13", 7}};
  io::TextReader r(text.data(), text.size(), '#');
  io::Token t;
  for (const Want& w : want) {
    REQUIRE(r.next(t));
    CHECK(t.str() == w.token);
    CHECK(t.line == w.line);
    CHECK(r.last_line() == w.line);
  }
  CHECK_FALSE(r.next(t));

  // next_uint: the same positions for plain indices, false for the others
  // (the caller then reads the record again from a mark).
  io::TextReader u(text.data(), text.size(), '#');
  uint64_t v = 0;
  CHECK_FALSE(u.next_uint(v));  // "OFF"
  u.reset({5, 2});              // just past "OFF\r\n"
  REQUIRE(u.next_uint(v));
  CHECK(v == 3);
  REQUIRE(u.next_uint(v));
  CHECK(v == 4);
  REQUIRE(u.next_uint(v));
  CHECK(v == 0);
  CHECK(u.last_line() == 2);
  CHECK_FALSE(u.next_uint(v));  // "1.5", after a comment and a blank line
  const size_t at = text.find("11");
  u.reset({at, 5});
  REQUIRE(u.next_uint(v));
  CHECK(v == 11);
  REQUIRE(u.next_uint(v));  // past a vertical tab
  CHECK(v == 12);
  CHECK(u.last_line() == 5);
  REQUIRE(u.next_uint(v));  // "0012" on the next line
  CHECK(v == 12);
  CHECK(u.last_line() == 6);
  REQUIRE(u.next_uint(v));
  CHECK(v == 123456789012345678u);
  CHECK_FALSE(u.next_uint(v));  // 19 digits: next() and parse_int decide
  u.reset({text.find("13"), 7});
  REQUIRE(u.next_uint(v));
  CHECK(v == 13);
  CHECK(u.last_line() == 7);
  CHECK_FALSE(u.next_uint(v));  // the end
}
