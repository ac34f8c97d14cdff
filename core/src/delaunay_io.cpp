// Point input (.node) and tet output (.node/.ele) for `cdt3d delaunay`.
// Kept separate from the PLC readers: the Delaunay step only needs points,
// keeps duplicates (and counts them) and must stream a million points fast.
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#if __has_include(<charconv>)
#include <charconv>
#endif

#include "delaunay.hpp"
#include "status.hpp"

namespace cdt3d {

namespace {

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

enum class Num { Ok, Bad, NonFinite };

// Whole token [p, p+n) as a correctly rounded double.
Num parse_double(const char* p, size_t n, double& out) {
  if (n == 0) return Num::Bad;
  const char* q = p;
  if (*q == '+') ++q;  // from_chars rejects a leading '+'
  // Letters other than the exponent mark nan/inf/hex: not accepted here.
  for (const char* r = q; r != p + n; ++r) {
    const char c = *r;
    if ((c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z')) {
      if (c == 'e' || c == 'E') continue;
      return (c == 'n' || c == 'N' || c == 'i' || c == 'I') ? Num::NonFinite : Num::Bad;
    }
  }
#if defined(__cpp_lib_to_chars) && __cpp_lib_to_chars >= 201611L
  const auto r = std::from_chars(q, p + n, out, std::chars_format::general);
  if (r.ec == std::errc::result_out_of_range) return Num::NonFinite;
  if (r.ec != std::errc() || r.ptr != p + n) return Num::Bad;
#else
  char buf[128];
  const size_t len = size_t(p + n - q);
  if (len >= sizeof buf) return Num::Bad;
  std::memcpy(buf, q, len);
  buf[len] = 0;
  char* end = nullptr;
  errno = 0;
  out = std::strtod(buf, &end);
  if (end != buf + len) return Num::Bad;
  if (errno == ERANGE && std::fabs(out) > 1.0) return Num::NonFinite;
#endif
  if (!std::isfinite(out)) return Num::NonFinite;
  if (out == 0) out = 0;  // -0 -> +0
  return Num::Ok;
}

bool parse_uint(const char* p, size_t n, uint64_t& out) {
  if (n == 0 || n > 18) return false;
  out = 0;
  for (size_t i = 0; i < n; ++i) {
    if (p[i] < '0' || p[i] > '9') return false;
    out = out * 10 + uint64_t(p[i] - '0');
  }
  return true;
}

bool parse_int(const char* p, size_t n, int64_t& out) {
  bool neg = n > 0 && p[0] == '-';
  if (n > 0 && (p[0] == '-' || p[0] == '+')) ++p, --n;
  uint64_t u;
  if (!parse_uint(p, n, u)) return false;
  out = neg ? -int64_t(u) : int64_t(u);
  return true;
}

// Splits the current line into whitespace-separated tokens, stopping at '#'.
struct LineReader {
  LineReader(const char* text, size_t size) : p(text), end(text + size) {}
  const char* p;
  const char* end;
  int64_t line = 0;
  struct Tok {
    const char* p;
    size_t n;
  };
  Tok toks[64];
  size_t ntok = 0;
  bool overflow = false;

  // Next line with at least one token; false at end of input.
  bool next() {
    while (p < end) {
      ++line;
      ntok = 0;
      overflow = false;
      bool comment = false;
      while (p < end && *p != '\n') {
        if (comment) {
          ++p;
          continue;
        }
        if (*p == '#') {
          comment = true;
          ++p;
          continue;
        }
        if (is_space(*p)) {
          ++p;
          continue;
        }
        const char* s = p;
        while (p < end && *p != '\n' && *p != '#' && !is_space(*p)) ++p;
        if (ntok < 64)
          toks[ntok++] = Tok{s, size_t(p - s)};
        else
          overflow = true;
      }
      if (p < end) ++p;  // '\n'
      if (ntok > 0) return true;
    }
    return false;
  }
};

#if defined(__cpp_lib_to_chars) && __cpp_lib_to_chars >= 201611L
// Fast path for the common point line "<index> <x> <y> <z> ...": no
// tokenizing pass, from_chars straight on the text. Returns false (and
// leaves p alone) for anything unusual: blank or comment lines, bad or
// non-finite numbers; the general path then parses the line and reports.
bool fast_point_line(const char*& p, const char* end, int64_t& index, double xyz[3]) {
  const char* q = p;
  while (q < end && (*q == ' ' || *q == '\t')) ++q;
  bool neg = false;
  if (q < end && *q == '-') neg = true, ++q;
  if (q == end || *q < '0' || *q > '9') return false;
  uint64_t u = 0;
  int digits = 0;
  while (q < end && *q >= '0' && *q <= '9' && digits < 18)
    u = u * 10 + uint64_t(*q++ - '0'), ++digits;
  index = neg ? -int64_t(u) : int64_t(u);
  for (int k = 0; k < 3; ++k) {
    if (q == end || (*q != ' ' && *q != '\t')) return false;
    while (q < end && (*q == ' ' || *q == '\t')) ++q;
    if (q < end && *q == '+') ++q;
    const auto r = std::from_chars(q, end, xyz[k], std::chars_format::general);
    if (r.ec != std::errc() || !std::isfinite(xyz[k]) || std::fabs(xyz[k]) > kMaxCoordinate)
      return false;
    if (xyz[k] == 0) xyz[k] = 0;  // -0 -> +0
    q = r.ptr;
  }
  if (q < end && *q != ' ' && *q != '\t' && *q != '\r' && *q != '\n' && *q != '#') return false;
  const void* nl = std::memchr(q, '\n', size_t(end - q));
  p = nl ? static_cast<const char*>(nl) + 1 : end;
  return true;
}
#endif

}  // namespace

Status parse_node_points(const char* text, size_t size, const std::string& file_name,
                         std::vector<double>& coords, int* first_index) {
  coords.clear();
  LineReader rd(text, size);
  if (!rd.next())
    return make_error(ErrorCode::Empty, "The .node file has no header line.").file(file_name);
  uint64_t n = 0, dim = 0;
  int64_t nattr = 0, nmark = 0;
  if (rd.ntok < 2 || !parse_uint(rd.toks[0].p, rd.toks[0].n, n) ||
      !parse_uint(rd.toks[1].p, rd.toks[1].n, dim) ||
      (rd.ntok > 2 && !parse_int(rd.toks[2].p, rd.toks[2].n, nattr)) ||
      (rd.ntok > 3 && !parse_int(rd.toks[3].p, rd.toks[3].n, nmark)))
    return make_error(ErrorCode::Parse,
                      "Bad .node header: expected '<points> 3 <attributes> <markers>'.")
        .file(file_name, rd.line);
  if (dim != 3)
    return make_error(ErrorCode::Parse, "Only 3-dimensional .node files are supported.")
        .file(file_name, rd.line);
  if (nattr < 0 || nmark < 0 || nmark > 1)
    return make_error(ErrorCode::Parse, "Bad attribute or marker count in the .node header.")
        .file(file_name, rd.line);
  if (n >= (uint64_t(1) << 30))
    return make_error(ErrorCode::TooLarge, "Too many points in the .node file.")
        .file(file_name, rd.line);
  if (n == 0)
    return make_error(ErrorCode::Empty, "The .node file lists no points.").file(file_name, rd.line);
  coords.reserve(3 * size_t(n));
  for (uint64_t i = 0; i < n; ++i) {
#if defined(__cpp_lib_to_chars) && __cpp_lib_to_chars >= 201611L
    int64_t fast_index;
    double xyz[3];
    if (fast_point_line(rd.p, rd.end, fast_index, xyz)) {
      ++rd.line;
      if (i == 0 && first_index) *first_index = int(fast_index);
      coords.insert(coords.end(), xyz, xyz + 3);
      continue;
    }
#endif
    if (!rd.next())
      return make_error(ErrorCode::Truncated, "The .node file ends after " + std::to_string(i) +
                                                  " of " + std::to_string(n) + " points.")
          .file(file_name, rd.line);
    if (rd.ntok < 4)
      return make_error(ErrorCode::Parse, "Expected '<index> <x> <y> <z> [attributes] [marker]'.")
          .file(file_name, rd.line);
    int64_t index;
    if (!parse_int(rd.toks[0].p, rd.toks[0].n, index))
      return make_error(ErrorCode::Parse, "Bad point index.").file(file_name, rd.line);
    if (i == 0 && first_index) *first_index = int(index);
    for (int k = 1; k <= 3; ++k) {
      double x;
      const Num r = parse_double(rd.toks[k].p, rd.toks[k].n, x);
      if (r == Num::NonFinite)
        return make_error(ErrorCode::NonFinite, "Non-finite coordinate.").file(file_name, rd.line);
      if (r != Num::Ok)
        return make_error(ErrorCode::Parse,
                          "Bad coordinate '" + std::string(rd.toks[k].p, rd.toks[k].n) + "'.")
            .file(file_name, rd.line);
      if (std::fabs(x) > kMaxCoordinate)
        return make_error(ErrorCode::CoordinateRange, "Coordinate exceeds the supported range.")
            .file(file_name, rd.line);
      coords.push_back(x);
    }
  }
  return Status::success();
}

Status read_node_points_file(const std::string& path, std::vector<double>& coords,
                             int* first_index) {
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return make_error(ErrorCode::IoError, "Cannot open the file.").file(path);
  std::string text;
  if (std::fseek(f, 0, SEEK_END) == 0) {
    const long size = std::ftell(f);
    if (size > 0) text.reserve(size_t(size));
    std::fseek(f, 0, SEEK_SET);
  }
  char buf[1 << 16];
  size_t got;
  while ((got = std::fread(buf, 1, sizeof buf, f)) > 0) text.append(buf, got);
  const bool bad = std::ferror(f) != 0;
  std::fclose(f);
  if (bad) return make_error(ErrorCode::IoError, "Error while reading the file.").file(path);
  return parse_node_points(text.data(), text.size(), path, coords, first_index);
}

namespace {

char* put_uint(char* p, uint64_t v) {
  char tmp[24];
  int n = 0;
  do {
    tmp[n++] = char('0' + v % 10);
    v /= 10;
  } while (v);
  while (n) *p++ = tmp[--n];
  return p;
}

}  // namespace

Status write_node_ele(const TetMesh& mesh, const std::string& prefix) {
  const std::string node_name = prefix + ".node", ele_name = prefix + ".ele";
  std::FILE* f = std::fopen(node_name.c_str(), "wb");
  if (!f) return make_error(ErrorCode::IoError, "Cannot create the output file.").file(node_name);
  std::vector<char> buf(1 << 20);
  size_t used = 0;
  bool ok = true;
  auto flush = [&](std::FILE* out) {
    if (used && std::fwrite(buf.data(), 1, used, out) != used) ok = false;
    used = 0;
  };
  const size_t nv = mesh.num_vertices();
  used += size_t(std::snprintf(buf.data(), buf.size(),
                               "%zu 3 0 0\n# generated by cdt3d; numbering from 1\n", nv));
  for (size_t v = 0; v < nv; ++v) {
    if (used + 128 > buf.size()) flush(f);
    const double* p = mesh.point(VertexId(v));
    used += size_t(
        std::snprintf(buf.data() + used, 128, "%zu %.17g %.17g %.17g\n", v + 1, p[0], p[1], p[2]));
  }
  flush(f);
  if (std::fclose(f) != 0) ok = false;
  if (!ok) return make_error(ErrorCode::IoError, "Error while writing the file.").file(node_name);

  f = std::fopen(ele_name.c_str(), "wb");
  if (!f) return make_error(ErrorCode::IoError, "Cannot create the output file.").file(ele_name);
  const size_t real = mesh.live_tets - mesh.num_ghost_tets();
  used += size_t(std::snprintf(buf.data(), buf.size(),
                               "%zu 4 0\n# generated by cdt3d; numbering from 1\n", real));
  const size_t slots = mesh.num_tet_slots();
  size_t k = 0;
  for (size_t t = 0; t < slots; ++t) {
    if ((mesh.tflag[t] & kTetDead) || mesh.tv[4 * t + 3] == kInfinite) continue;
    if (used + 128 > buf.size()) flush(f);
    char* p = buf.data() + used;
    p = put_uint(p, ++k);
    // TetGen's orientation: (b - a) x (c - a) . (d - a) > 0, the reverse of
    // TetMesh's, so the last two vertices are swapped.
    static constexpr int kTetGenOrder[4] = {0, 1, 3, 2};
    for (int i : kTetGenOrder) {
      *p++ = ' ';
      p = put_uint(p, uint64_t(mesh.tv[4 * t + i]) + 1);
    }
    *p++ = '\n';
    used = size_t(p - buf.data());
  }
  flush(f);
  if (std::fclose(f) != 0) ok = false;
  if (!ok) return make_error(ErrorCode::IoError, "Error while writing the file.").file(ele_name);
  return Status::success();
}

}  // namespace cdt3d
