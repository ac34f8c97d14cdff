// Shared pieces of the PLC readers: a text tokenizer that tracks line numbers,
// number parsing that never throws and never depends on a stream, error
// construction, and PlcBuilder, which welds identical points exactly and remaps
// facet indices once the whole file has been read.
#pragma once

#include <cdt3d/cdt3d.hpp>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace cdt3d {
namespace io {

// ---------------------------------------------------------------------------
// Errors
// ---------------------------------------------------------------------------

/// A failed Status with the given code, message and location.
Status fail(ErrorCode code, std::string message, const std::string& file, int64_t line = -1,
            int64_t record = -1);

/// The whole file at `path` into `bytes`. Errors: IoError (cannot open, or
/// reading failed), OutOfMemory.
Status read_file(const std::string& path, std::vector<uint8_t>& bytes);

/// Largest number of distinct points / file vertex records: VertexId is 32-bit
/// and kNone is reserved.
inline constexpr uint64_t kMaxItems = 0xfffffffeull;
/// Longest group or solid name kept (bytes; longer names are cut).
inline constexpr size_t kMaxNameSize = 200;

// ---------------------------------------------------------------------------
// Numbers
// ---------------------------------------------------------------------------

enum class NumParse {
  Ok,
  Bad,        ///< not a number
  NonFinite,  ///< "nan", "inf", "infinity" (any case, optional sign)
  Overflow,   ///< a finite decimal too large for a double
};

/// Parses a whole token as a double, correctly rounded. Accepts decimal and
/// exponent notation. -0 is returned as +0 so that welding needs no special case.
NumParse parse_double(const char* p, size_t n, double& out);

/// parse_double without the standard library's from_chars: the path of
/// builds that lack it (WebAssembly), the same results.
NumParse parse_decimal(const char* p, size_t n, double& out);

/// m * 10^e10 correctly rounded (to nearest, ties to even), for 0 < m < 2^64
/// and |e10| <= 22; false outside that range. parse_double's path for
/// mantissas of 16 to 19 digits (17-digit "%.17g" output): strtod, its
/// fallback, computes in long double, which WebAssembly emulates in
/// software, slowly.
bool exact_decimal(uint64_t m, int e10, double& out);

/// Parses a whole token as a decimal integer with an optional sign.
/// Overflow when it does not fit in int64.
NumParse parse_int(const char* p, size_t n, int64_t& out);

// ---------------------------------------------------------------------------
// Text tokenizer
// ---------------------------------------------------------------------------

struct Token {
  const char* p = nullptr;
  size_t n = 0;
  int64_t line = 0;  ///< 1-based line of the token

  std::string str() const { return std::string(p, n); }
  bool is(const char* word) const;         ///< exact match
  bool is_nocase(const char* word) const;  ///< ASCII case-insensitive match
};

/// Splits text into whitespace-separated tokens. `comment` (0 for none) starts
/// a comment running to the end of the line, also in the middle of a line.
/// Every call consumes input or reports the end, so no loop over it can hang.
class TextReader {
 public:
  TextReader(const char* data, size_t size, char comment, size_t start = 0, int64_t line = 1);

  /// Next token anywhere (crossing line ends). False at the end of the input.
  /// Inline for the usual token (after spaces, ending at white space): the
  /// readers take millions of them; the rest goes through next_slow().
  bool next(Token& t) {
    size_t i = pos_;
    while (i < size_ && data_[i] == ' ') ++i;
    pos_ = i;
    const size_t start = i;
    while (i < size_ && plain(data_[i])) ++i;
    if (i > start && (i == size_ || data_[i] == ' ' || data_[i] == '\n' || data_[i] == '\t' ||
                      data_[i] == '\r')) {
      t.p = data_ + start;
      t.n = i - start;
      t.line = last_line_ = line_;
      pos_ = i;
      return true;
    }
    return next_slow(t);
  }
  /// Next token on the current line only. False (consuming nothing of the next
  /// line) when the line or the input ends first.
  bool next_on_line(Token& t);
  /// The next token anywhere (as next()) when it is plain decimal digits
  /// (at most 18) followed by white space or the end: its value in v and
  /// true. False otherwise, with the position anywhere: the caller resets
  /// to a mark and reads the record again token by token. Index lists of
  /// triangle soups are most of a mesh file, and a token then a parse
  /// costs several times this one pass per index.
  bool next_uint(uint64_t& v) {
    size_t i = pos_;
    while (i < size_ && data_[i] == ' ') ++i;  // the usual separator
    pos_ = i;
    if (i == size_ || static_cast<unsigned char>(data_[i] - '0') > 9) {
      skip_blank_and_comments(true);  // line ends, tabs, comments
      i = pos_;
    }
    uint64_t x = 0;
    const size_t start = i;
    for (; i < size_ && i - start < 18; ++i) {
      const unsigned d = static_cast<unsigned char>(data_[i] - '0');
      if (d > 9) break;
      x = 10 * x + d;
    }
    pos_ = i;
    if (i == start) return false;
    if (i < size_ && data_[i] != ' ' && data_[i] != '\n' && data_[i] != '\t' && data_[i] != '\r')
      return false;
    last_line_ = line_;
    v = x;
    return true;
  }
  /// Skips the rest of the current line, including its line feed.
  void skip_line();
  /// The tokens left on the line joined by single spaces (and the line
  /// skipped), cut to `max_size` bytes: a name such as an STL solid's.
  std::string rest_of_line(size_t max_size);
  /// True when no token remains anywhere.
  bool at_end();
  /// OBJ: a backslash that is the last non-blank character of a line joins
  /// the next line to it (the backslash is no token). Tokens keep the number
  /// of the physical line they are on, so errors still name that line.
  void set_line_continuation(bool on) { continuation_ = on; }

  /// A saved position, to look ahead and come back.
  struct Mark {
    size_t pos;
    int64_t line;
  };
  Mark mark() const { return Mark{pos_, line_}; }
  void reset(Mark m) {
    pos_ = m.pos;
    line_ = m.line;
  }

  int64_t line() const { return line_; }
  /// Line of the last token read (1 before any): where a truncated file ends.
  int64_t last_line() const { return last_line_; }
  size_t pos() const { return pos_; }
  size_t remaining() const { return size_ - pos_; }

 private:
  /// A character that never ends a token nor starts a comment or a line
  /// continuation (read_token's first loop).
  bool plain(char c) const {
    return static_cast<unsigned char>(c) > ' ' && c != comment_ && c != '\\';
  }
  bool next_slow(Token& t);
  void skip_blank_and_comments(bool cross_lines);
  void read_token(Token& t);
  /// With line continuation on: if a continuation backslash starts at `at`,
  /// the position just past its line feed (or the end); otherwise `at`.
  size_t past_continuation(size_t at) const;

  const char* data_;
  size_t size_;
  size_t pos_;
  int64_t line_;
  int64_t last_line_;
  char comment_;
  bool continuation_ = false;
};

/// A token for messages: in single quotes, cut at 40 characters, with
/// control and non-ASCII bytes shown as '?'.
std::string quote(const Token& t);

/// Reads the next token of a record that may continue on following lines;
/// a Truncated error naming the last line when the input ends.
Status expect_token(TextReader& r, Token& t, const std::string& file, const char* what);

/// What a coordinate belongs to, for messages: kind is "vertex", "hole",
/// "region" or "facet hole"; Error::vertex is set only for "vertex".
struct Subject {
  const char* kind;
  int64_t index;
};

/// Parses a token as a coordinate. Errors: Parse, NonFinite, CoordinateRange
/// (decimal overflow), naming the subject and the token's line.
Status parse_coord(const Token& t, double& out, const std::string& file, Subject who);

/// Next token (possibly on a following line) parsed with parse_coord;
/// Truncated at the end of the input.
Status expect_coord(TextReader& r, double& out, const std::string& file, Subject who);

/// Next token parsed as a non-negative count that must fit in 32 bits
/// (TooLarge otherwise).
Status expect_count(TextReader& r, uint64_t& out, int64_t& line, const std::string& file,
                    const char* what);

/// A token parsed as a count (as expect_count).
Status count_from_token(const Token& t, uint64_t& out, const std::string& file, const char* what);

/// A token parsed as an integer (Parse error otherwise, TooLarge beyond int64).
Status int_from_token(const Token& t, int64_t& out, const std::string& file, const char* what);

/// Next token parsed as an integer (Parse error otherwise).
Status expect_int(TextReader& r, int64_t& out, int64_t& line, const std::string& file,
                  const char* what);

/// The error check_coords reports for a triple that is not coords_ok.
Status coords_error(double x, double y, double z, const std::string& file, int64_t line,
                    int64_t record, Subject who);

/// Finite and within kMaxCoordinate (NaN fails every comparison).
inline bool coords_ok(double x, double y, double z) {
  return std::fabs(x) <= kMaxCoordinate && std::fabs(y) <= kMaxCoordinate &&
         std::fabs(z) <= kMaxCoordinate;
}

/// Checks a coordinate triple: NonFinite or CoordinateRange naming the subject.
/// Inline, so the readers' loops build no Status for a good triple.
inline Status check_coords(double x, double y, double z, const std::string& file, int64_t line,
                           int64_t record, Subject who) {
  if (coords_ok(x, y, z)) return Status::success();
  return coords_error(x, y, z, file, line, record, who);
}

// ---------------------------------------------------------------------------
// Building a Plc
// ---------------------------------------------------------------------------

/// Collects a file's vertex records and facets. Vertices are welded exactly
/// as they arrive (an open-addressing table keyed on the coordinates, used
/// for lookup only; point ids are given in order of first appearance, so the
/// result never depends on the hash). Facets and segments hold *file* vertex
/// indices until finish() checks their range and maps them to point ids.
class PlcBuilder {
 public:
  PlcBuilder(Plc& plc, const std::string& file, int64_t index_base);

  /// Capacity hint: `count` vertex records of which about `distinct` are
  /// different points; never reserves more than `cap` records.
  void reserve_vertices(uint64_t count, uint64_t cap, uint64_t distinct);

  /// Adds one vertex record (coordinates already checked with check_coords).
  /// TooLarge past kMaxItems records.
  /// The records are welded in batches (weld_pending), which readers do not
  /// see: file_vertex_count() counts every record added.
  Status add_vertex(double x, double y, double z, int64_t line, int64_t record);

  uint64_t file_vertex_count() const { return remap_.size() + pending_count_; }
  /// Index base used in messages (0 or 1), when known only after the header.
  void set_index_base(int64_t base) { base_ = base; }

  /// Appends a facet (loops of file indices to fill in) and returns it; its
  /// marker is the one set by start_named_group (0 before any).
  Facet& add_facet(int64_t line, int64_t record);
  /// The facets added from now on form the group of that name (the rest of
  /// the statement's line, e.g. an OBJ "g" or an STL "solid"): they take
  /// the name's marker, a new one (`next_marker`, then counting up) for a
  /// name not seen before. An empty name returns to marker 0.
  void start_named_group(const std::string& name, int next_marker);
  /// Appends an explicit segment between two file vertex indices.
  void add_segment(uint32_t a, uint32_t b, int64_t line, int64_t record);
  /// Records a vertex referenced on its own (a one-corner polygon), for the
  /// range check only.
  void add_isolated(uint32_t a, int64_t line, int64_t record);

  /// Range-checks every index (IndexOutOfRange naming facet and line/record),
  /// maps file indices to point ids and fills the provenance fields.
  Status finish();

 private:
  struct Ref {
    uint32_t a, b;
    int64_t line, record;
  };
  uint32_t weld(const Vec3& p, uint64_t hash);
  uint32_t lookup_or_insert(const Vec3& p, uint64_t hash);
  void grow_table();
  void insert_slot(std::vector<uint64_t>& table, uint32_t id) const;
  void weld_pending();
  Status out_of_range(uint64_t index, int64_t line, int64_t record, int64_t facet) const;

  Plc& plc_;
  const std::string& file_;
  int64_t base_;
  std::vector<uint32_t> remap_;  // file vertex record -> point id
  static constexpr uint64_t kEmptySlot = UINT64_MAX;
  std::vector<uint64_t> table_;  // open addressing: hash tag | point id, or kEmptySlot
  std::vector<Ref> segments_;
  std::vector<Ref> isolated_;
  static constexpr int kRecent = 6;
  uint32_t recent_[kRecent] = {kNone, kNone, kNone, kNone, kNone, kNone};
  int recent_next_ = 0;
  // Records added and not yet welded, and what keeps weld_pending's early
  // loads from being optimised away.
  static constexpr size_t kWeldBatch = 64;
  Vec3 pending_[kWeldBatch];
  size_t pending_count_ = 0;
  uint64_t prefetch_sink_ = 0;
  int marker_ = 0;
  int next_marker_ = -1;  // -1: no named group yet
};

// ---------------------------------------------------------------------------
// TetGen node sections (io/poly.cpp): the points of .node, .poly and .smesh,
// and of the `cdt3d delaunay` command's .node input, which keeps duplicates
// (delaunay_io.cpp) where the PLC reader welds them.
// ---------------------------------------------------------------------------

/// The header "<count> [dimension=3] [#attributes] [markers]" (the last two
/// are skipped: each node's values are). Empty for a file with no token;
/// a count of 0 is Empty in a .node file (node_file) and a Parse error
/// otherwise (TetGen would read the nodes from a separate .node file).
/// `line` gets the header's line.
Status read_node_header(TextReader& r, const std::string& file, bool node_file, uint64_t& count,
                        int64_t& line);

/// Node i, "<id> x y z", the rest of its line skipped: the first node's
/// number (0 or 1) becomes `base`, every other must be base + i. Coordinates
/// are checked (check_coords, subject "vertex i"); `line` gets the id's line.
Status read_node(TextReader& r, const std::string& file, uint64_t i, int64_t& base, double xyz[3],
                 int64_t& line);

// ---------------------------------------------------------------------------
// Format readers (one file each). They fill `out` from scratch and leave the
// final checks (check_plc) to read_plc.
// ---------------------------------------------------------------------------

Status read_stl(const uint8_t* data, size_t size, const std::string& file, Plc& out);
Status read_off(const uint8_t* data, size_t size, const std::string& file, Plc& out);
Status read_obj(const uint8_t* data, size_t size, const std::string& file, Plc& out);
Status read_ply(const uint8_t* data, size_t size, const std::string& file, Plc& out);
/// TetGen .poly (kind Poly), .smesh (Smesh) and .node (Node: points only).
Status read_tetgen(const uint8_t* data, size_t size, const std::string& file, FileFormat kind,
                   Plc& out);

}  // namespace io
}  // namespace cdt3d
