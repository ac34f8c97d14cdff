// STL reader, ASCII and binary. Every STL facet is a triangle with its own
// three corners; corners with identical coordinates are welded exactly.
//
// Binary or ASCII: a file is binary when its size is exactly 84 + 50 * count
// for the triangle count stored at byte 80 (the header may well begin with
// "solid"), or when it does not begin with "solid", or when it begins with
// "solid" but holds control bytes and cannot be parsed as ASCII.
#include <cstring>

#include "blocks.hpp"
#include "io/read_common.hpp"

namespace cdt3d {
namespace io {
namespace {

uint32_t le32(const uint8_t* p) {
  return static_cast<uint32_t>(p[0]) | (static_cast<uint32_t>(p[1]) << 8) |
         (static_cast<uint32_t>(p[2]) << 16) | (static_cast<uint32_t>(p[3]) << 24);
}

double le_float(const uint8_t* p) {
  const uint32_t u = le32(p);
  float f;
  std::memcpy(&f, &u, sizeof f);
  return static_cast<double>(f);
}

bool is_space(uint8_t c) {
  return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\v' || c == '\f';
}

// Control bytes that never occur in an ASCII STL but nearly always in the
// float data of a binary one.
bool has_control_bytes(const uint8_t* data, size_t size, size_t from) {
  for (size_t i = from; i < size; ++i) {
    const uint8_t c = data[i];
    if ((c < 0x20 && !is_space(c)) || c == 0x7f) return true;
  }
  return false;
}

Status read_binary(const uint8_t* data, size_t size, const std::string& file, Plc& out) {
  if (size < 84) {
    return fail(ErrorCode::Truncated,
                "A binary STL starts with an 84-byte header; the file has only " +
                    std::to_string(size) + " bytes.",
                file, -1, 0);
  }
  const uint64_t count = le32(data + 80);
  const uint64_t expected = 84 + 50 * count;
  if (count == 0 && size == 84) {
    return fail(ErrorCode::Empty, "The binary STL holds no triangles.", file);
  }
  if (size < expected) {
    const uint64_t ends_in = (size - 84) / 50;
    return fail(ErrorCode::Truncated,
                "The binary STL header declares " + std::to_string(count) + " triangles (" +
                    std::to_string(expected) + " bytes) but the file has " + std::to_string(size) +
                    " bytes: it ends inside triangle " + std::to_string(ends_in) + ".",
                file, -1, static_cast<int64_t>(ends_in));
  }
  if (size > expected) {
    return fail(ErrorCode::Truncated,
                "The binary STL header declares " + std::to_string(count) + " triangles (" +
                    std::to_string(expected) + " bytes) but the file has " + std::to_string(size) +
                    " bytes: the sizes disagree.",
                file, -1, static_cast<int64_t>(count));
  }
  if (3 * count > kMaxItems) {
    return fail(ErrorCode::TooLarge, "The binary STL has more triangles than 32-bit ids allow.",
                file);
  }
  PlcBuilder b(out, file, 0);
  // A closed triangle surface has about half as many points as triangles.
  b.reserve_vertices(3 * count, 3 * count, count / 2 + 16);
  out.facets.reserve(static_cast<size_t>(count));
  // The records in blocks (blocks.hpp); a failed record leaves its error in
  // `bad` and stops the loop.
  Status bad;
  for_blocks(count, [&](uint64_t begin, uint64_t end) {
    for (uint64_t t = begin; t < end; ++t) {
      const uint8_t* rec = data + 84 + 50 * t + 12;  // skip the normal
      for (int k = 0; k < 3; ++k) {
        const double x = le_float(rec + 12 * k);
        const double y = le_float(rec + 12 * k + 4);
        const double z = le_float(rec + 12 * k + 8);
        const int64_t v = static_cast<int64_t>(3 * t) + k;
        bad = check_coords(x, y, z, file, -1, static_cast<int64_t>(t), Subject{"vertex", v});
        if (!bad.ok()) return false;
        bad = b.add_vertex(x, y, z, -1, static_cast<int64_t>(t));
        if (!bad.ok()) return false;
      }
      Facet& f = b.add_facet(-1, static_cast<int64_t>(t));
      const uint32_t v0 = static_cast<uint32_t>(3 * t);
      f.loops.push_back({v0, v0 + 1, v0 + 2});
    }
    return true;
  });
  if (!bad.ok()) return bad;
  return b.finish();
}

Status expect_word(TextReader& r, const char* word, const std::string& file) {
  Token t;
  Status s = expect_token(r, t, file, (std::string("'") + word + "'").c_str());
  if (!s.ok()) return s;
  if (t.is_nocase(word)) return Status::success();
  return fail(ErrorCode::Parse,
              std::string("Expected '") + word + "' in the ASCII STL, found " + quote(t) + ".",
              file, t.line);
}

Status read_ascii(const uint8_t* data, size_t size, const std::string& file, Plc& out) {
  TextReader r(reinterpret_cast<const char*>(data), size, 0);
  Token t;
  if (!r.next(t)) return fail(ErrorCode::Empty, "The file holds only white space.", file);
  if (!t.is_nocase("solid")) {
    return fail(ErrorCode::Parse, "An ASCII STL must begin with 'solid'.", file, t.line);
  }
  PlcBuilder b(out, file, 0);
  b.start_named_group(r.rest_of_line(kMaxNameSize), 0);
  b.reserve_vertices(size / 64, size / 64, size / 400);
  // The facets in blocks (blocks.hpp): at most one per byte, so the blocks
  // end at the end of the file; a failed facet leaves its error in `bad`
  // and stops the loop.
  Status bad;
  for_blocks(size + 1, [&](size_t begin, size_t end) {
    for (size_t statement = begin; statement < end; ++statement) {
      if (!r.next(t)) return false;
      if (t.is_nocase("endsolid")) {
        r.skip_line();
        // Some exporters pad the file with NUL bytes after the last solid.
        bool padding = true;
        for (size_t i = r.pos(); i < size && padding; ++i)
          padding = data[i] == 0 || is_space(data[i]);
        if (padding || !r.next(t)) return false;
        if (!t.is_nocase("solid")) {
          bad = fail(ErrorCode::Parse, "Expected 'solid' or the end of the file after 'endsolid'.",
                     file, t.line);
          return false;
        }
        // Several solids in one file: read them all, each a marker of its own.
        b.start_named_group(r.rest_of_line(kMaxNameSize), 1);
        continue;
      }
      if (!t.is_nocase("facet")) {
        bad = fail(ErrorCode::Parse,
                   "Expected 'facet' or 'endsolid' in the ASCII STL, found " + quote(t) + ".", file,
                   t.line);
        return false;
      }
      const int64_t facet_line = t.line;
      r.skip_line();  // "normal nx ny nz": ignored (often not even unit length)
      Status s = expect_word(r, "outer", file);
      if (s.ok()) s = expect_word(r, "loop", file);
      if (!s.ok()) {
        bad = std::move(s);
        return false;
      }
      const uint32_t first = static_cast<uint32_t>(b.file_vertex_count());
      for (int k = 0; k < 3; ++k) {
        s = expect_word(r, "vertex", file);
        if (!s.ok()) {
          bad = std::move(s);
          return false;
        }
        const int64_t v = static_cast<int64_t>(b.file_vertex_count());
        double c[3];
        for (double& x : c) {
          s = expect_coord(r, x, file, Subject{"vertex", v});
          if (!s.ok()) {
            bad = std::move(s);
            return false;
          }
        }
        s = check_coords(c[0], c[1], c[2], file, r.last_line(), -1, Subject{"vertex", v});
        if (s.ok()) s = b.add_vertex(c[0], c[1], c[2], r.last_line(), -1);
        if (!s.ok()) {
          bad = std::move(s);
          return false;
        }
      }
      if (!r.next(t)) {
        bad = fail(ErrorCode::Truncated, "The file ends early: expected 'endloop'.", file,
                   r.last_line());
        return false;
      }
      if (t.is_nocase("vertex")) {
        bad = fail(ErrorCode::Parse, "STL facets must be triangles: this loop has a 4th vertex.",
                   file, t.line);
        return false;
      }
      if (!t.is_nocase("endloop")) {
        bad = fail(ErrorCode::Parse, "Expected 'endloop' in the ASCII STL.", file, t.line);
        return false;
      }
      s = expect_word(r, "endfacet", file);
      if (!s.ok()) {
        bad = std::move(s);
        return false;
      }
      Facet& f = b.add_facet(facet_line, -1);
      f.loops.push_back({first, first + 1, first + 2});
    }
    return true;
  });
  if (!bad.ok()) return bad;
  return b.finish();
}

}  // namespace

Status read_stl(const uint8_t* data, size_t size, const std::string& file, Plc& out) {
  if (size == 0) return fail(ErrorCode::Empty, "The file is empty.", file);
  if (size >= 84 && size == 84 + 50 * static_cast<uint64_t>(le32(data + 80))) {
    return read_binary(data, size, file, out);
  }
  size_t i = 0;
  const bool bom = size >= 3 && data[0] == 0xEF && data[1] == 0xBB && data[2] == 0xBF;
  if (bom) i = 3;
  while (i < size && is_space(data[i])) ++i;
  if (i == size) return fail(ErrorCode::Empty, "The file holds only white space.", file);
  const bool solid =
      size - i >= 5 && (data[i] == 's' || data[i] == 'S') &&
      (data[i + 1] == 'o' || data[i + 1] == 'O') && (data[i + 2] == 'l' || data[i + 2] == 'L') &&
      (data[i + 3] == 'i' || data[i + 3] == 'I') && (data[i + 4] == 'd' || data[i + 4] == 'D');
  if (!solid) return read_binary(data, size, file, out);
  Status s = bom ? read_ascii(data + 3, size - 3, file, out) : read_ascii(data, size, file, out);
  const bool ascii_ok = s.ok() && !out.facets.empty();
  if (!ascii_ok && size >= 84 && has_control_bytes(data, size, 84)) {
    // "solid..." header on a binary file whose size disagrees with its count.
    return read_binary(data, size, file, out);
  }
  return s;
}

}  // namespace io
}  // namespace cdt3d
