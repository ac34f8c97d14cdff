// OFF reader (Object File Format): optional "OFF" keyword (also COFF, NOFF,
// STOFF... whose extra per-vertex values are ignored), the counts
// "vertices faces [edges]", the vertex lines, then one line per face
// "n i1 ... in [colour]". Polygons become one-loop facets. '#' starts a comment
// anywhere on a line. A record may continue on the next line; whatever
// follows the values we need on a record's last line is ignored.
#include <vector>

#include "blocks.hpp"
#include "io/read_common.hpp"

namespace cdt3d {
namespace io {
namespace {

// Recognises [ST][C][N][4][n]OFF. Sets dims_error for 4OFF / nOFF.
bool is_off_keyword(const Token& t, bool& dims_error) {
  dims_error = false;
  if (t.n < 3) return false;
  const char* end = t.p + t.n - 3;
  if (!(end[0] == 'O' && end[1] == 'F' && end[2] == 'F') &&
      !(end[0] == 'o' && end[1] == 'f' && end[2] == 'f')) {
    return false;
  }
  for (const char* c = t.p; c < end; ++c) {
    switch (*c) {
      case 'S':
      case 'T':
      case 'C':
      case 'N':
        break;
      case '4':
      case 'n':
        dims_error = true;
        break;
      default:
        return false;
    }
  }
  return true;
}

// The common records, read without building a Status per token (the
// checked path's main cost): a vertex whose three coordinates
// parse_double reads whole and coords_ok accepts, and a face "n i1 .. in"
// with 1 <= n and every index in 0..nv-1. On anything else they return
// false and the caller reads the record again from its start with the
// checked path, which reports the error: both paths accept the same records
// with the same values.
bool fast_vertex(TextReader& r, double (&c)[3]) {
  Token t;
  for (double& x : c)
    if (!r.next(t) || parse_double(t.p, t.n, x) != NumParse::Ok) return false;
  return coords_ok(c[0], c[1], c[2]);
}

bool fast_face(TextReader& r, uint64_t nv, std::vector<VertexId>& loop, int64_t& face_line) {
  uint64_t n = 0;
  if (!r.next_uint(n) || n < 1 || n > r.remaining() / 2 + 1) return false;
  face_line = r.last_line();
  loop.clear();
  for (uint64_t k = 0; k < n; ++k) {
    uint64_t v = 0;
    if (!r.next_uint(v) || v >= nv) return false;
    loop.push_back(static_cast<VertexId>(v));
  }
  return true;
}

}  // namespace

Status read_off(const uint8_t* data, size_t size, const std::string& file, Plc& out) {
  out = Plc();
  out.file = file;
  if (size == 0) return fail(ErrorCode::Empty, "The file is empty.", file);
  TextReader r(reinterpret_cast<const char*>(data), size, '#');
  Token t;
  if (!r.next(t))
    return fail(ErrorCode::Empty, "The file holds only comments and white space.", file);

  bool dims_error = false;
  uint64_t nv = 0, nf = 0;
  int64_t line = t.line;
  if (is_off_keyword(t, dims_error)) {
    if (dims_error) {
      return fail(ErrorCode::Parse, "Only 3D OFF files are supported (found " + quote(t) + ").",
                  file, t.line);
    }
    const TextReader::Mark after_keyword = r.mark();
    Token b;
    if (r.next_on_line(b) && b.is_nocase("BINARY")) {
      return fail(ErrorCode::Parse, "Binary OFF files are not supported.", file, b.line);
    }
    r.reset(after_keyword);  // the counts follow, on this line or a later one
    Status s = expect_count(r, nv, line, file, "vertex count");
    if (!s.ok()) return s;
  } else {
    Status s = count_from_token(t, nv, file, "vertex count");
    if (!s.ok()) {
      if (s.error.code == ErrorCode::Parse) {
        s.error.message = "An OFF file must begin with 'OFF' or the vertex count.";
      }
      return s;
    }
  }
  Status s = expect_count(r, nf, line, file, "face count");
  if (!s.ok()) return s;
  r.skip_line();  // the optional edge count

  PlcBuilder b(out, file, 0);
  // Each vertex line needs at least 6 bytes ("0 0 0\n"): never reserve more
  // than the file can hold.
  b.reserve_vertices(nv, r.remaining() / 6 + 1, nv);
  // The records in blocks (base/blocks.hpp); a failed record leaves its
  // error in s and stops the loop.
  for_blocks(nv, [&](uint64_t begin, uint64_t end) {
    for (uint64_t i = begin; i < end; ++i) {
      const Subject who{"vertex", static_cast<int64_t>(i)};
      double c[3];
      const TextReader::Mark record = r.mark();
      if (!fast_vertex(r, c)) {
        r.reset(record);
        for (double& x : c) {
          s = expect_coord(r, x, file, who);
          if (!s.ok()) return false;
        }
        s = check_coords(c[0], c[1], c[2], file, r.last_line(), -1, who);
        if (!s.ok()) return false;
      }
      s = b.add_vertex(c[0], c[1], c[2], r.last_line(), -1);
      if (!s.ok()) return false;
      r.skip_line();
    }
    return true;
  });
  if (!s.ok()) return s;

  out.facets.reserve(static_cast<size_t>(nf < r.remaining() / 8 + 1 ? nf : r.remaining() / 8 + 1));
  std::vector<VertexId> quick;
  for_blocks(nf, [&](uint64_t begin, uint64_t end) {
    for (uint64_t f = begin; f < end; ++f) {
      const TextReader::Mark record = r.mark();
      int64_t face_line = 0;
      if (fast_face(r, nv, quick, face_line)) {
        b.add_facet(face_line, -1).loops.emplace_back(quick.begin(), quick.end());
        r.skip_line();  // optional face colour
        continue;
      }
      r.reset(record);
      uint64_t n = 0;
      s = expect_count(r, n, face_line, file, "face vertex count");
      if (!s.ok()) return false;
      if (n > r.remaining() / 2 + 1) {
        Status e = fail(ErrorCode::Truncated,
                        "Face " + std::to_string(f) + " declares " + std::to_string(n) +
                            " vertices but the file ends before.",
                        file, face_line);
        e.error.facet = static_cast<int64_t>(f);
        s = std::move(e);
        return false;
      }
      Facet& facet = b.add_facet(face_line, -1);
      facet.loops.emplace_back();
      std::vector<VertexId>& loop = facet.loops.back();
      loop.reserve(static_cast<size_t>(n));
      for (uint64_t k = 0; k < n; ++k) {
        int64_t v = 0, vline = 0;
        s = expect_int(r, v, vline, file, "face vertex index");
        if (!s.ok()) {
          s.error.facet = static_cast<int64_t>(f);
          return false;
        }
        if (v < 0 || static_cast<uint64_t>(v) >= nv) {
          Status e = fail(ErrorCode::IndexOutOfRange,
                          "Face " + std::to_string(f) + " uses vertex index " + std::to_string(v) +
                              ", outside 0.." + std::to_string(static_cast<int64_t>(nv) - 1) + ".",
                          file, vline);
          e.error.facet = static_cast<int64_t>(f);
          s = std::move(e);
          return false;
        }
        loop.push_back(static_cast<VertexId>(v));
      }
      r.skip_line();  // optional face colour
    }
    return true;
  });
  if (!s.ok()) return s;
  return b.finish();
}

}  // namespace io
}  // namespace cdt3d
