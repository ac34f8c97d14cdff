// PLY reader: ascii, binary_little_endian and binary_big_endian. The "vertex"
// element gives x, y, z (any numeric type, among any other properties); the
// "face" element gives a list property "vertex_indices" (or "vertex_index")
// with any count and index types. Every other element and property is read
// past according to the header, so binary files stay in step.
#include <cmath>
#include <cstring>
#include <memory>

#include "blocks.hpp"
#include "io/read_common.hpp"

namespace cdt3d {
namespace io {
namespace {

enum class PType { I8, U8, I16, U16, I32, U32, F32, F64 };

size_t type_size(PType t) {
  switch (t) {
    case PType::I8:
    case PType::U8:
      return 1;
    case PType::I16:
    case PType::U16:
      return 2;
    case PType::I32:
    case PType::U32:
    case PType::F32:
      return 4;
    case PType::F64:
      return 8;
  }
  return 8;
}

bool is_float(PType t) { return t == PType::F32 || t == PType::F64; }

bool type_from_token(const Token& t, PType& out) {
  struct Name {
    const char* name;
    PType type;
  };
  static const Name kNames[] = {
      {"char", PType::I8},    {"int8", PType::I8},     {"uchar", PType::U8},
      {"uint8", PType::U8},   {"short", PType::I16},   {"int16", PType::I16},
      {"ushort", PType::U16}, {"uint16", PType::U16},  {"int", PType::I32},
      {"int32", PType::I32},  {"uint", PType::U32},    {"uint32", PType::U32},
      {"float", PType::F32},  {"float32", PType::F32}, {"double", PType::F64},
      {"float64", PType::F64}};
  for (const Name& n : kNames) {
    if (t.is(n.name)) {
      out = n.type;
      return true;
    }
  }
  return false;
}

struct Property {
  std::string name;
  PType type = PType::F32;
  bool list = false;
  PType count_type = PType::U8;
};

struct Element {
  std::string name;
  std::string label;  // the name quoted and made printable, for messages
  uint64_t count = 0;
  std::vector<Property> props;
  int64_t line = 0;
};

enum class Format { Ascii, LittleEndian, BigEndian };

// One value as read from the file: as a double (every PLY type converts
// exactly) and, for integral values, as an integer.
struct Value {
  double d = 0;
  int64_t i = 0;
  bool integral = false;
};

class BinaryCursor {
 public:
  BinaryCursor(const uint8_t* data, size_t size, size_t pos, bool big)
      : data_(data), size_(size), pos_(pos), big_(big) {}

  size_t remaining() const { return size_ - pos_; }

  bool skip(uint64_t bytes) {
    if (bytes > remaining()) return false;
    pos_ += static_cast<size_t>(bytes);
    return true;
  }

  bool read(PType t, Value& v) {
    const size_t n = type_size(t);
    if (n > remaining()) return false;
    uint8_t b[8];
    for (size_t k = 0; k < n; ++k) b[k] = data_[pos_ + (big_ ? n - 1 - k : k)];
    pos_ += n;
    // b now holds the value little-endian.
    uint64_t u = 0;
    for (size_t k = 0; k < n; ++k) u |= static_cast<uint64_t>(b[k]) << (8 * k);
    v.integral = true;
    switch (t) {
      case PType::I8:
        v.i = static_cast<int8_t>(u);
        break;
      case PType::U8:
        v.i = static_cast<int64_t>(u);
        break;
      case PType::I16:
        v.i = static_cast<int16_t>(u);
        break;
      case PType::U16:
        v.i = static_cast<int64_t>(u);
        break;
      case PType::I32:
        v.i = static_cast<int32_t>(static_cast<uint32_t>(u));
        break;
      case PType::U32:
        v.i = static_cast<int64_t>(u);
        break;
      case PType::F32: {
        const uint32_t w = static_cast<uint32_t>(u);
        float f;
        std::memcpy(&f, &w, sizeof f);
        set_float(static_cast<double>(f), v);
        return true;
      }
      case PType::F64: {
        double d;
        std::memcpy(&d, &u, sizeof d);
        set_float(d, v);
        return true;
      }
    }
    v.d = static_cast<double>(v.i);
    return true;
  }

  static void set_float(double d, Value& v) {
    v.d = d;
    v.integral = std::isfinite(d) && d == std::floor(d) && std::fabs(d) < 9007199254740992.0;
    v.i = v.integral ? static_cast<int64_t>(d) : 0;
  }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_;
  bool big_;
};

class PlyReader {
 public:
  PlyReader(const uint8_t* data, size_t size, const std::string& file, Plc& out)
      : data_(data), size_(size), file_(file), out_(out), builder_(out, file, 0) {}

  Status read() {
    Status s = read_header();
    if (!s.ok()) return s;
    s = find_roles();
    if (!s.ok()) return s;
    for (size_t e = 0; e < elements_.size(); ++e) {
      s = format_ == Format::Ascii ? read_ascii_element(e) : read_binary_element(e);
      if (!s.ok()) return s;
    }
    return builder_.finish();
  }

 private:
  Status parse_error(const std::string& msg, int64_t line) const {
    return fail(ErrorCode::Parse, msg, file_, line);
  }

  Status read_header() {
    TextReader r(reinterpret_cast<const char*>(data_), size_, 0);
    Token t;
    if (!r.next(t)) return fail(ErrorCode::Empty, "The file holds only white space.", file_);
    if (!t.is("ply")) return parse_error("A PLY file must begin with 'ply'.", t.line);
    r.skip_line();
    bool have_format = false;
    for (;;) {
      if (!r.next(t)) {
        return fail(ErrorCode::Truncated, "The PLY header has no 'end_header' line.", file_,
                    r.last_line());
      }
      if (t.is("end_header")) {
        r.skip_line();
        body_ = r.pos();
        body_line_ = r.line();
        break;
      }
      if (t.is("comment") || t.is("obj_info")) {
        r.skip_line();
        continue;
      }
      Token a;
      if (t.is("format")) {
        if (!r.next_on_line(a)) return parse_error("The 'format' line names no format.", t.line);
        if (a.is("ascii")) {
          format_ = Format::Ascii;
        } else if (a.is("binary_little_endian")) {
          format_ = Format::LittleEndian;
        } else if (a.is("binary_big_endian")) {
          format_ = Format::BigEndian;
        } else {
          return parse_error("Unknown PLY format " + quote(a) + ".", a.line);
        }
        have_format = true;
      } else if (t.is("element")) {
        Token name, count;
        if (!r.next_on_line(name) || !r.next_on_line(count)) {
          return parse_error("An 'element' line needs a name and a count.", t.line);
        }
        Element e;
        e.name = name.str();
        e.label = quote(name);
        e.line = t.line;
        Status s = count_from_token(count, e.count, file_, "element count");
        if (!s.ok()) return s;
        elements_.push_back(std::move(e));
      } else if (t.is("property")) {
        if (elements_.empty())
          return parse_error("A 'property' line before any 'element'.", t.line);
        Property p;
        Token type, name;
        if (!r.next_on_line(type)) return parse_error("A 'property' line needs a type.", t.line);
        if (type.is("list")) {
          Token ct, it;
          if (!r.next_on_line(ct) || !r.next_on_line(it) || !r.next_on_line(name)) {
            return parse_error("A list property needs a count type, an item type and a name.",
                               t.line);
          }
          if (!type_from_token(ct, p.count_type) || is_float(p.count_type)) {
            return parse_error("Bad list count type " + quote(ct) + ".", ct.line);
          }
          if (!type_from_token(it, p.type)) {
            return parse_error("Unknown property type " + quote(it) + ".", it.line);
          }
          p.list = true;
        } else {
          if (!type_from_token(type, p.type)) {
            return parse_error("Unknown property type " + quote(type) + ".", type.line);
          }
          if (!r.next_on_line(name)) return parse_error("A property needs a name.", t.line);
        }
        p.name = name.str();
        elements_.back().props.push_back(std::move(p));
      } else {
        return parse_error("Unknown PLY header keyword " + quote(t) + ".", t.line);
      }
      r.skip_line();
    }
    if (!have_format) return parse_error("The PLY header has no 'format' line.", 1);
    return Status::success();
  }

  Status find_roles() {
    for (size_t e = 0; e < elements_.size(); ++e) {
      const Element& el = elements_[e];
      if (el.name == "vertex" && vertex_elem_ < 0) {
        vertex_elem_ = static_cast<int>(e);
        for (size_t k = 0; k < el.props.size(); ++k) {
          const Property& p = el.props[k];
          for (int a = 0; a < 3; ++a) {
            if (p.name == std::string(1, static_cast<char>('x' + a))) {
              if (p.list)
                return parse_error("The vertex property '" + p.name + "' is a list.", el.line);
              xyz_[a] = static_cast<int>(k);
            }
          }
        }
        for (int a = 0; a < 3; ++a) {
          if (xyz_[a] < 0) {
            return parse_error(std::string("The vertex element has no '") +
                                   static_cast<char>('x' + a) + "' property.",
                               el.line);
          }
        }
      } else if (el.name == "face" && face_elem_ < 0) {
        face_elem_ = static_cast<int>(e);
        for (size_t k = 0; k < el.props.size(); ++k) {
          const Property& p = el.props[k];
          if (p.name == "vertex_indices" || p.name == "vertex_index") {
            if (!p.list) {
              return parse_error("The face property '" + p.name + "' is not a list.", el.line);
            }
            index_prop_ = static_cast<int>(k);
            break;
          }
        }
        if (index_prop_ < 0) {
          return parse_error("The face element has no 'vertex_indices' list property.", el.line);
        }
      }
    }
    if (vertex_elem_ < 0) return parse_error("The PLY header declares no 'vertex' element.", 1);
    return Status::success();
  }

  Status truncated(const Element& el, uint64_t rec, int64_t line) const {
    return fail(ErrorCode::Truncated,
                "The file ends inside record " + std::to_string(rec) + " of element " + el.label +
                    " (the header declares " + std::to_string(el.count) + " records).",
                file_, line, line < 0 ? static_cast<int64_t>(rec) : -1);
  }

  // Stores a decoded face corner; the range is checked by finish().
  Status add_corner(const Value& v, std::vector<VertexId>& loop, int64_t facet, int64_t line,
                    int64_t record) {
    if (!v.integral || v.i < 0 || static_cast<uint64_t>(v.i) >= kMaxItems) {
      Status s = fail(ErrorCode::IndexOutOfRange,
                      "Face " + std::to_string(facet) + " has an invalid vertex index" +
                          (v.integral ? " " + std::to_string(v.i) : std::string()) + ".",
                      file_, line, record);
      s.error.facet = facet;
      return s;
    }
    loop.push_back(static_cast<VertexId>(v.i));
    return Status::success();
  }

  void reserve(size_t e, uint64_t min_record_bytes, uint64_t remaining) {
    const Element& el = elements_[e];
    const uint64_t cap = remaining / (min_record_bytes ? min_record_bytes : 1) + 1;
    const uint64_t n = el.count < cap ? el.count : cap;
    if (static_cast<int>(e) == vertex_elem_) builder_.reserve_vertices(el.count, cap, el.count);
    if (static_cast<int>(e) == face_elem_) out_.facets.reserve(static_cast<size_t>(n));
  }

  Status read_binary_element(size_t e) {
    const Element& el = elements_[e];
    if (!cursor_) {
      cursor_.reset(new BinaryCursor(data_, size_, body_, format_ == Format::BigEndian));
    }
    BinaryCursor& c = *cursor_;
    uint64_t min_bytes = 0;
    for (const Property& p : el.props) min_bytes += type_size(p.list ? p.count_type : p.type);
    if (min_bytes == 0) return Status::success();  // records without properties take no bytes
    reserve(e, min_bytes, c.remaining());
    const bool is_vertex = static_cast<int>(e) == vertex_elem_;
    const bool is_face = static_cast<int>(e) == face_elem_;
    double xyz[3] = {0, 0, 0};
    // The records in blocks (blocks.hpp); a failed record leaves its error
    // in `bad` and stops the loop.
    Status bad;
    for_blocks(el.count, [&](uint64_t begin, uint64_t end) {
      for (uint64_t rec = begin; rec < end; ++rec) {
        const int64_t record = static_cast<int64_t>(rec);
        std::vector<VertexId>* loop = nullptr;
        if (is_face) {
          Facet& f = builder_.add_facet(-1, record);
          f.loops.emplace_back();
          loop = &f.loops.back();
        }
        for (size_t k = 0; k < el.props.size(); ++k) {
          const Property& p = el.props[k];
          Value v;
          if (!p.list) {
            if (!c.read(p.type, v)) {
              bad = truncated(el, rec, -1);
              return false;
            }
            if (is_vertex) {
              for (int a = 0; a < 3; ++a) {
                if (xyz_[a] == static_cast<int>(k)) xyz[a] = v.d;
              }
            }
            continue;
          }
          if (!c.read(p.count_type, v)) {
            bad = truncated(el, rec, -1);
            return false;
          }
          if (v.i < 0) {
            bad = fail(ErrorCode::Parse,
                       "Negative list length in record " + std::to_string(rec) + " of element " +
                           el.label + ".",
                       file_, -1, record);
            return false;
          }
          const uint64_t n = static_cast<uint64_t>(v.i);
          const size_t item = type_size(p.type);
          if (n > c.remaining() / item) {
            bad = truncated(el, rec, -1);
            return false;
          }
          if (is_face && static_cast<int>(k) == index_prop_) {
            loop->reserve(static_cast<size_t>(n));
            for (uint64_t j = 0; j < n; ++j) {
              c.read(p.type, v);
              Status s = add_corner(v, *loop, record, -1, record);
              if (!s.ok()) {
                bad = std::move(s);
                return false;
              }
            }
          } else {
            c.skip(n * item);
          }
        }
        if (is_vertex) {
          const Subject who{"vertex", record};
          Status s = check_coords(xyz[0], xyz[1], xyz[2], file_, -1, record, who);
          if (s.ok()) s = builder_.add_vertex(xyz[0], xyz[1], xyz[2], -1, record);
          if (!s.ok()) {
            bad = std::move(s);
            return false;
          }
        }
      }
      return true;
    });
    if (!bad.ok()) return bad;
    return Status::success();
  }

  Status ascii_value(TextReader& r, PType type, const Element& el, uint64_t rec, Value& v,
                     Token& t) {
    if (!r.next(t)) return truncated(el, rec, r.last_line());
    if (is_float(type)) {
      double d = 0;
      const NumParse p = parse_double(t.p, t.n, d);
      if (p == NumParse::Bad) {
        return parse_error("Expected a number in record " + std::to_string(rec) + " of element " +
                               el.label + ", found " + quote(t) + ".",
                           t.line);
      }
      BinaryCursor::set_float(p == NumParse::Ok ? d : NAN, v);
      return Status::success();
    }
    Status s = int_from_token(t, v.i, file_, "integer property");
    if (!s.ok()) return s;
    v.d = static_cast<double>(v.i);
    v.integral = true;
    return Status::success();
  }

  Status read_ascii_element(size_t e) {
    const Element& el = elements_[e];
    if (el.props.empty()) return Status::success();
    if (!text_) {
      text_.reset(
          new TextReader(reinterpret_cast<const char*>(data_), size_, 0, body_, body_line_));
    }
    TextReader& r = *text_;
    reserve(e, 2 * el.props.size(), r.remaining());
    const bool is_vertex = static_cast<int>(e) == vertex_elem_;
    const bool is_face = static_cast<int>(e) == face_elem_;
    Token t;
    for (uint64_t rec = 0; rec < el.count; ++rec) {
      const int64_t record = static_cast<int64_t>(rec);
      double xyz[3] = {0, 0, 0};
      int64_t first_line = -1;
      for (size_t k = 0; k < el.props.size(); ++k) {
        const Property& p = el.props[k];
        Value v;
        if (!p.list) {
          if (is_vertex && (xyz_[0] == static_cast<int>(k) || xyz_[1] == static_cast<int>(k) ||
                            xyz_[2] == static_cast<int>(k))) {
            if (!r.next(t)) return truncated(el, rec, r.last_line());
            if (first_line < 0) first_line = t.line;
            const int a = xyz_[0] == static_cast<int>(k)   ? 0
                          : xyz_[1] == static_cast<int>(k) ? 1
                                                           : 2;
            Status s = parse_coord(t, xyz[a], file_, Subject{"vertex", record});
            if (!s.ok()) return s;
          } else {
            Status s = ascii_value(r, p.type, el, rec, v, t);
            if (!s.ok()) return s;
            if (first_line < 0) first_line = t.line;
          }
          continue;
        }
        Status s = ascii_value(r, p.count_type, el, rec, v, t);
        if (!s.ok()) return s;
        if (first_line < 0) first_line = t.line;
        if (v.i < 0) {
          return parse_error("Negative list length in record " + std::to_string(rec) +
                                 " of element " + el.label + ".",
                             t.line);
        }
        const uint64_t n = static_cast<uint64_t>(v.i);
        if (n > r.remaining() / 2 + 1) return truncated(el, rec, t.line);
        if (is_face && static_cast<int>(k) == index_prop_) {
          Facet& f = builder_.add_facet(first_line, -1);
          f.loops.emplace_back();
          std::vector<VertexId>& loop = f.loops.back();
          loop.reserve(static_cast<size_t>(n));
          for (uint64_t j = 0; j < n; ++j) {
            s = ascii_value(r, p.type, el, rec, v, t);
            if (s.ok()) s = add_corner(v, loop, record, t.line, -1);
            if (!s.ok()) return s;
          }
        } else {
          for (uint64_t j = 0; j < n; ++j) {
            if (!r.next(t)) return truncated(el, rec, r.last_line());
          }
        }
      }
      if (is_vertex) {
        const Subject who{"vertex", record};
        Status s = check_coords(xyz[0], xyz[1], xyz[2], file_, first_line, -1, who);
        if (s.ok()) s = builder_.add_vertex(xyz[0], xyz[1], xyz[2], first_line, -1);
        if (!s.ok()) return s;
      }
    }
    return Status::success();
  }

  const uint8_t* data_;
  size_t size_;
  const std::string& file_;
  Plc& out_;
  PlcBuilder builder_;
  Format format_ = Format::Ascii;
  std::vector<Element> elements_;
  size_t body_ = 0;
  int64_t body_line_ = 1;
  int vertex_elem_ = -1, face_elem_ = -1, index_prop_ = -1;
  int xyz_[3] = {-1, -1, -1};
  std::unique_ptr<BinaryCursor> cursor_;
  std::unique_ptr<TextReader> text_;
};

}  // namespace

Status read_ply(const uint8_t* data, size_t size, const std::string& file, Plc& out) {
  if (size == 0) {
    out = Plc();
    out.file = file;
    return fail(ErrorCode::Empty, "The file is empty.", file);
  }
  PlyReader reader(data, size, file, out);
  return reader.read();
}

}  // namespace io
}  // namespace cdt3d
