// TetGen .poly, .smesh and .node readers.
//
// Sections, in order: nodes "<count> <dim=3> <#attributes> <markers 0|1>" then
// "<id> x y z [attributes] [marker]"; facets "<count> <markers 0|1>"; holes
// "<count>" then "<id> x y z"; regions "<count>" then "<id> x y z [attribute]
// [max volume]". The hole and region sections may be missing at the end.
//  .poly facet:  "<#polygons> [#holes] [marker]", the polygons "n v1 .. vn"
//                (n = 2: an explicit segment, n = 1: an isolated point), then
//                the facet's hole points "<id> x y z".
//  .smesh facet: "n v1 .. vn [marker]" (one polygon).
// The first node's number (0 or 1) is the numbering base. A node count of 0
// means "nodes in a separate .node file": we read one file, so it is an error.
// '#' starts a comment. A record may continue on the next line; whatever
// follows the values we need on a record's last line is ignored.
#include <cmath>

#include "io/read_common.hpp"

namespace cdt3d {
namespace io {
namespace {

class TetgenReader {
 public:
  TetgenReader(const uint8_t* data, size_t size, const std::string& file, FileFormat kind, Plc& out)
      : r_(reinterpret_cast<const char*>(data), size, '#'),
        file_(file),
        kind_(kind),
        out_(out),
        b_(out, file, 0) {}

  Status read() {
    Status s = read_nodes();
    if (!s.ok() || kind_ == FileFormat::Node) return s.ok() ? b_.finish() : s;
    s = read_facets();
    if (!s.ok()) return s;
    s = read_points("hole", out_.holes, nullptr);
    if (!s.ok()) return s;
    s = read_points("region", out_.holes, &out_.regions);
    if (!s.ok()) return s;
    return b_.finish();
  }

 private:
  // Optional integer on the rest of the current line.
  Status optional_int(int64_t& out, bool& present, const char* what) {
    Token t;
    present = r_.next_on_line(t);
    if (!present) return Status::success();
    return int_from_token(t, out, file_, what);
  }

  Status read_nodes() {
    int64_t line = 0;
    Status s = read_node_header(r_, file_, kind_ == FileFormat::Node, nodes_, line);
    if (!s.ok()) return s;
    b_.reserve_vertices(nodes_, r_.remaining() / 8 + 1, nodes_);
    for (uint64_t i = 0; i < nodes_; ++i) {
      double c[3];
      s = read_node(r_, file_, i, base_, c, line);
      if (!s.ok()) return s;
      if (i == 0) b_.set_index_base(base_);
      s = b_.add_vertex(c[0], c[1], c[2], line, -1);
      if (!s.ok()) return s;
    }
    return Status::success();
  }

  // Reads "n v1 .. vn" (n already read) into file indices, range-checked.
  Status read_polygon(uint64_t n, int64_t line, std::vector<VertexId>& loop) {
    const int64_t facet = static_cast<int64_t>(out_.facets.size());
    if (n > r_.remaining() / 2 + 1) {
      Status e =
          fail(ErrorCode::Truncated,
               "A polygon declares " + std::to_string(n) + " corners but the file ends before.",
               file_, line);
      e.error.facet = facet;
      return e;
    }
    loop.clear();
    loop.reserve(static_cast<size_t>(n));
    for (uint64_t k = 0; k < n; ++k) {
      int64_t v = 0, vline = 0;
      Status s = expect_int(r_, v, vline, file_, "polygon corner");
      if (!s.ok()) {
        s.error.facet = facet;
        return s;
      }
      const int64_t i = v - base_;
      if (i < 0 || static_cast<uint64_t>(i) >= nodes_) {
        Status e = fail(ErrorCode::IndexOutOfRange,
                        "Node " + std::to_string(v) + " does not exist (nodes are numbered " +
                            std::to_string(base_) + ".." +
                            std::to_string(base_ + static_cast<int64_t>(nodes_) - 1) + ").",
                        file_, vline);
        e.error.facet = facet;
        return e;
      }
      loop.push_back(static_cast<VertexId>(i));
    }
    return Status::success();
  }

  // Files a polygon: a loop of the facet, an explicit segment or a lone point.
  void file_polygon(std::vector<VertexId>& loop, int64_t line, Facet& facet) {
    if (loop.size() == 1) {
      b_.add_isolated(loop[0], line, -1);
    } else if (loop.size() == 2) {
      b_.add_segment(loop[0], loop[1], line, -1);
    } else {
      facet.loops.push_back(loop);  // 0 corners too: check_plc reports it
    }
  }

  Status read_facets() {
    uint64_t n = 0;
    int64_t line = 0;
    Status s = expect_count(r_, n, line, file_, "facet count");
    if (!s.ok()) return s;
    int64_t markers = 0;
    bool present = false;
    s = optional_int(markers, present, "facet marker flag");
    if (!s.ok()) return s;
    r_.skip_line();
    out_.facets.reserve(
        static_cast<size_t>(n < r_.remaining() / 4 + 1 ? n : r_.remaining() / 4 + 1));
    std::vector<VertexId> loop;
    for (uint64_t f = 0; f < n; ++f) {
      Facet facet;
      uint64_t npoly = 1, nholes = 0;
      int64_t facet_line = 0;
      if (kind_ == FileFormat::Poly) {
        s = expect_count(r_, npoly, facet_line, file_, "polygon count");
        if (!s.ok()) return s;
        int64_t h = 0, m = 0;
        s = optional_int(h, present, "facet hole count");
        if (!s.ok()) return s;
        if (present) {
          if (h < 0) return fail(ErrorCode::Parse, "Negative facet hole count.", file_, facet_line);
          nholes = static_cast<uint64_t>(h);
          if (markers) {
            s = optional_int(m, present, "facet marker");
            if (!s.ok()) return s;
            facet.marker = static_cast<int>(m);
          }
        }
        r_.skip_line();
        if (npoly > r_.remaining() / 2 + 1 || nholes > r_.remaining() / 8 + 1) {
          return fail(ErrorCode::Truncated,
                      "Facet " + std::to_string(f) +
                          " declares more polygons or holes than the file holds.",
                      file_, facet_line);
        }
        for (uint64_t p = 0; p < npoly; ++p) {
          uint64_t corners = 0;
          int64_t pline = 0;
          s = expect_count(r_, corners, pline, file_, "polygon corner count");
          if (s.ok()) s = read_polygon(corners, pline, loop);
          if (!s.ok()) return s;
          r_.skip_line();
          file_polygon(loop, pline, facet);
        }
        for (uint64_t h2 = 0; h2 < nholes; ++h2) {
          Vec3 p;
          s = read_point("facet hole", static_cast<int64_t>(h2), p);
          if (!s.ok()) return s;
          r_.skip_line();
          facet.holes.push_back(p);
        }
      } else {
        uint64_t corners = 0;
        s = expect_count(r_, corners, facet_line, file_, "polygon corner count");
        if (s.ok()) s = read_polygon(corners, facet_line, loop);
        if (!s.ok()) return s;
        if (markers) {
          int64_t m = 0;
          s = optional_int(m, present, "facet marker");
          if (!s.ok()) return s;
          facet.marker = static_cast<int>(m);
        }
        r_.skip_line();
        file_polygon(loop, facet_line, facet);
      }
      if (!facet.loops.empty()) {
        Facet& dst = b_.add_facet(facet_line, -1);
        dst.loops = std::move(facet.loops);
        dst.holes = std::move(facet.holes);
        dst.marker = facet.marker;
      }
    }
    return Status::success();
  }

  // "<id> x y z", the id ignored.
  Status read_point(const char* kind, int64_t index, Vec3& p) {
    int64_t id = 0, line = 0;
    Status s = expect_int(r_, id, line, file_, kind);
    if (!s.ok()) return s;
    const Subject who{kind, index};
    double c[3];
    for (double& x : c) {
      s = expect_coord(r_, x, file_, who);
      if (!s.ok()) return s;
    }
    s = check_coords(c[0], c[1], c[2], file_, line, -1, who);
    if (!s.ok()) return s;
    p.x = c[0] == 0 ? 0.0 : c[0];
    p.y = c[1] == 0 ? 0.0 : c[1];
    p.z = c[2] == 0 ? 0.0 : c[2];
    return Status::success();
  }

  // Hole list (regions == nullptr) or region list; absent at the end of the file = empty.
  Status read_points(const char* kind, std::vector<Vec3>& holes, std::vector<Region>* regions) {
    if (r_.at_end()) return Status::success();
    uint64_t n = 0;
    int64_t line = 0;
    Status s = expect_count(r_, n, line, file_, regions ? "region count" : "hole count");
    if (!s.ok()) return s;
    r_.skip_line();
    const uint64_t cap = r_.remaining() / 8 + 1;
    if (regions) {
      regions->reserve(static_cast<size_t>(n < cap ? n : cap));
    } else {
      holes.reserve(static_cast<size_t>(n < cap ? n : cap));
    }
    for (uint64_t i = 0; i < n; ++i) {
      Vec3 p;
      s = read_point(kind, static_cast<int64_t>(i), p);
      if (!s.ok()) return s;
      if (!regions) {
        holes.push_back(p);
        r_.skip_line();
        continue;
      }
      Region reg;
      reg.point = p;
      double* fields[2] = {&reg.attribute, &reg.max_volume};
      for (double* field : fields) {
        Token t;
        if (!r_.next_on_line(t)) break;
        double v = 0;
        const NumParse np = parse_double(t.p, t.n, v);
        if (np != NumParse::Ok) {
          return fail(np == NumParse::Bad ? ErrorCode::Parse : ErrorCode::NonFinite,
                      "Region " + std::to_string(i) + " has an invalid attribute or volume " +
                          quote(t) + ".",
                      file_, t.line);
        }
        *field = v;
      }
      regions->push_back(reg);
      r_.skip_line();
    }
    return Status::success();
  }

  TextReader r_;
  const std::string& file_;
  FileFormat kind_;
  Plc& out_;
  PlcBuilder b_;
  int64_t base_ = 0;
  uint64_t nodes_ = 0;
};

}  // namespace

Status read_node_header(TextReader& r, const std::string& file, bool node_file, uint64_t& count,
                        int64_t& line) {
  if (r.at_end())
    return fail(ErrorCode::Empty, "The file holds only comments and white space.", file);
  Status s = expect_count(r, count, line, file, "node count");
  if (!s.ok()) return s;
  int64_t dim = 3;
  Token t;
  if (r.next_on_line(t)) {
    s = int_from_token(t, dim, file, "dimension");
    if (!s.ok()) return s;
  }
  if (dim != 3) {
    return fail(ErrorCode::Parse,
                "Only 3D node lists are supported (the dimension is " + std::to_string(dim) + ").",
                file, line);
  }
  r.skip_line();  // attribute count and marker flag: the values are skipped per node
  if (count == 0) {
    if (node_file) return fail(ErrorCode::Empty, "The node list is empty.", file, line);
    return fail(ErrorCode::Parse,
                "The node count is 0, which in TetGen means the nodes are in a separate "
                ".node file; cdt3d reads a single file, so list the nodes in this one.",
                file, line);
  }
  return Status::success();
}

// A million-point file has four million tokens: each is parsed here without
// building a Status; only a token that fails is handed to the function that
// says what is wrong with it (it parses it again).
Status read_node(TextReader& r, const std::string& file, uint64_t i, int64_t& base, double xyz[3],
                 int64_t& line) {
  Token t;
  int64_t id = 0;
  if (!r.next(t)) return expect_token(r, t, file, "node number");  // Truncated
  line = t.line;
  if (parse_int(t.p, t.n, id) != NumParse::Ok) return int_from_token(t, id, file, "node number");
  if (i == 0) {
    if (id != 0 && id != 1) {
      return fail(ErrorCode::Parse,
                  "The first node is numbered " + std::to_string(id) +
                      "; TetGen numbering starts at 0 or 1.",
                  file, line);
    }
    base = id;
  } else if (id != base + static_cast<int64_t>(i)) {
    return fail(ErrorCode::Parse,
                "Node numbers must be consecutive: expected " +
                    std::to_string(base + static_cast<int64_t>(i)) + ", found " +
                    std::to_string(id) + ".",
                file, line);
  }
  const Subject who{"vertex", static_cast<int64_t>(i)};
  bool in_range = true;
  for (int k = 0; k < 3; ++k) {
    if (!r.next(t)) return expect_coord(r, xyz[k], file, who);  // Truncated
    if (parse_double(t.p, t.n, xyz[k]) != NumParse::Ok) return parse_coord(t, xyz[k], file, who);
    in_range = in_range && std::fabs(xyz[k]) <= kMaxCoordinate;
  }
  if (!in_range) return check_coords(xyz[0], xyz[1], xyz[2], file, r.last_line(), -1, who);
  r.skip_line();
  return Status::success();
}

Status read_tetgen(const uint8_t* data, size_t size, const std::string& file, FileFormat kind,
                   Plc& out) {
  if (size == 0) {
    out = Plc();
    out.file = file;
    return fail(ErrorCode::Empty, "The file is empty.", file);
  }
  TetgenReader reader(data, size, file, kind, out);
  return reader.read();
}

}  // namespace io
}  // namespace cdt3d
