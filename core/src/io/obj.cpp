// Wavefront OBJ reader: geometry only. "v x y z" vertices, "f" polygons whose
// corners are written i, i/t, i//n or i/t/n (1-based; negative = relative to
// the vertices read so far), "l" polylines as explicit segments, "p" points.
// Texture coordinates, normals, groups, smoothing and materials are ignored.
// A trailing backslash continues a statement on the next line; errors name the
// physical line of the offending token.
#include <cstring>
#include <vector>

#include "blocks.hpp"
#include "io/read_common.hpp"

namespace cdt3d {
namespace io {
namespace {

// Length of the vertex part of a corner token ("12", "-1", "3/4/5", "3//5").
size_t vertex_part(const Token& t) {
  size_t len = 0;
  while (len < t.n && t.p[len] != '/') ++len;
  return len;
}

// A 1-based (negative: relative to the vertices read so far) index as a
// 0-based file index; -1 when it names no vertex (0, or before the first)
// or lies beyond kMaxItems.
int64_t resolve_index(int64_t i, uint64_t vertices_so_far) {
  const int64_t resolved = i > 0 ? i - 1 : i < 0 ? static_cast<int64_t>(vertices_so_far) + i : -1;
  return resolved >= 0 && static_cast<uint64_t>(resolved) < kMaxItems ? resolved : -1;
}

// Resolves the vertex part of a corner token to a 0-based file index.
Status corner_index(const Token& t, uint64_t vertices_so_far, const std::string& file,
                    int64_t facet, uint32_t& out) {
  Token head = t;
  head.n = vertex_part(t);
  int64_t i = 0;
  Status s = int_from_token(head, i, file, "vertex index");
  if (!s.ok()) {
    if (s.error.code == ErrorCode::TooLarge) s.error.code = ErrorCode::IndexOutOfRange;
    s.error.facet = facet;
    return s;
  }
  const int64_t resolved = resolve_index(i, vertices_so_far);
  if (resolved < 0) {
    Status e = fail(ErrorCode::IndexOutOfRange,
                    "Vertex index " + std::to_string(i) +
                        " is out of range: " + std::to_string(vertices_so_far) +
                        " vertices are defined at this point (indices start at 1, negative "
                        "ones count back from the last).",
                    file, t.line);
    e.error.facet = facet;
    return e;
  }
  out = static_cast<uint32_t>(resolved);
  return Status::success();
}

// The common statements, read without building a Status per token (the
// checked path's main cost): "v" with three coordinates that parse_double
// reads whole and coords_ok accepts, and corners whose vertex part is a
// plain integer in range. On anything else they return false and the caller
// reads the statement again from the same place with the checked path, which
// reports the error: both paths accept the same statements with the same
// values.
bool fast_coords(TextReader& r, double (&c)[3]) {
  Token t;
  for (double& x : c)
    if (!r.next_on_line(t) || parse_double(t.p, t.n, x) != NumParse::Ok) return false;
  return coords_ok(c[0], c[1], c[2]);
}

bool fast_corners(TextReader& r, uint64_t vertices_so_far, std::vector<uint32_t>& out) {
  out.clear();
  Token t;
  while (r.next_on_line(t)) {
    int64_t i = 0;
    if (parse_int(t.p, vertex_part(t), i) != NumParse::Ok) return false;
    const int64_t resolved = resolve_index(i, vertices_so_far);
    if (resolved < 0) return false;
    out.push_back(static_cast<uint32_t>(resolved));
  }
  return true;
}

// Lines that start with "f " or "f\t" (possibly after blanks).
size_t count_face_lines(const char* p, size_t n) {
  size_t count = 0;
  const char* end = p + n;
  while (p < end) {
    while (p < end && (*p == ' ' || *p == '\t')) ++p;
    if (end - p >= 2 && p[0] == 'f' && (p[1] == ' ' || p[1] == '\t')) ++count;
    const void* nl = std::memchr(p, '\n', static_cast<size_t>(end - p));
    if (!nl) break;
    p = static_cast<const char*>(nl) + 1;
  }
  return count;
}

}  // namespace

Status read_obj(const uint8_t* data, size_t size, const std::string& file, Plc& out) {
  out = Plc();
  out.file = file;
  if (size == 0) return fail(ErrorCode::Empty, "The file is empty.", file);
  TextReader r(reinterpret_cast<const char*>(data), size, '#');
  r.set_line_continuation(true);  // legal OBJ: "f 1 2 \\" goes on on the next line
  PlcBuilder b(out, file, 1);
  b.reserve_vertices(size / 32, size / 32, size / 32);
  // Reserve the facet list from a count of "f" lines, so that it is not
  // moved and page-faulted while it grows (a line continued by a backslash
  // may hide one: reserve is only a hint).
  out.facets.reserve(count_face_lines(reinterpret_cast<const char*>(data), size));
  Token t;
  std::vector<uint32_t> corners;
  // The statements in blocks (blocks.hpp): at most one per byte, so the
  // blocks end at the end of the file; a failed statement leaves its error
  // in `bad` and stops the loop.
  Status bad;
  for_blocks(size + 1, [&](size_t begin, size_t end) {
    for (size_t statement = begin; statement < end; ++statement) {
      if (!r.next(t)) return false;
      if (t.is("v")) {
        const Subject who{"vertex", static_cast<int64_t>(b.file_vertex_count())};
        double c[3];
        const TextReader::Mark args = r.mark();
        if (fast_coords(r, c)) {
          Status s = b.add_vertex(c[0], c[1], c[2], t.line, -1);
          if (!s.ok()) {
            bad = std::move(s);
            return false;
          }
          r.skip_line();
          continue;
        }
        r.reset(args);
        for (double& x : c) {
          Token v;
          if (!r.next_on_line(v)) {
            Status e = fail(ErrorCode::Parse, "A 'v' line needs three coordinates.", file, t.line);
            e.error.vertex = who.index;
            bad = std::move(e);
            return false;
          }
          Status s = parse_coord(v, x, file, who);
          if (!s.ok()) {
            bad = std::move(s);
            return false;
          }
        }
        Status s = check_coords(c[0], c[1], c[2], file, t.line, -1, who);
        if (s.ok()) s = b.add_vertex(c[0], c[1], c[2], t.line, -1);
        if (!s.ok()) {
          bad = std::move(s);
          return false;
        }
      } else if (t.is("f") || t.is("fo")) {
        const int64_t facet = static_cast<int64_t>(out.facets.size());
        const TextReader::Mark args = r.mark();
        if (fast_corners(r, b.file_vertex_count(), corners)) {
          b.add_facet(t.line, -1).loops.emplace_back(corners.begin(), corners.end());
          r.skip_line();
          continue;
        }
        r.reset(args);
        corners.clear();
        Token c;
        while (r.next_on_line(c)) {
          uint32_t v = 0;
          Status s = corner_index(c, b.file_vertex_count(), file, facet, v);
          if (!s.ok()) {
            bad = std::move(s);
            return false;
          }
          corners.push_back(v);
        }
        Facet& f = b.add_facet(t.line, -1);
        f.loops.emplace_back(corners.begin(), corners.end());
      } else if (t.is("l") || t.is("p")) {
        corners.clear();
        Token c;
        while (r.next_on_line(c)) {
          uint32_t v = 0;
          Status s = corner_index(c, b.file_vertex_count(), file, -1, v);
          if (!s.ok()) {
            bad = std::move(s);
            return false;
          }
          corners.push_back(v);
        }
        if (t.is("p") || corners.size() == 1) {
          for (uint32_t v : corners) b.add_isolated(v, t.line, -1);
        } else {
          for (size_t k = 0; k + 1 < corners.size(); ++k) {
            b.add_segment(corners[k], corners[k + 1], t.line, -1);
          }
        }
      } else if (t.is("g") || t.is("o")) {
        // A group or object names the faces after it (a Gmsh physical name).
        b.start_named_group(r.rest_of_line(kMaxNameSize), 1);
        continue;
      }
      // Everything else (vt, vn, vp, s, usemtl, mtllib, ...) is ignored.
      r.skip_line();
    }
    return true;
  });
  if (!bad.ok()) return bad;
  return b.finish();
}

}  // namespace io
}  // namespace cdt3d
