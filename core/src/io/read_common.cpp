// Tokenizer, number parsing and exact welding shared by the PLC readers.
#include "io/read_common.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <new>

#if __has_include(<charconv>)
#include <charconv>
#endif

#include "blocks.hpp"
#include "hash.hpp"

namespace cdt3d {
namespace io {

Status fail(ErrorCode code, std::string message, const std::string& file, int64_t line,
            int64_t record) {
  Status s;
  s.error.code = code;
  s.error.message = std::move(message);
  s.error.file = file;
  s.error.line = line;
  s.error.record = record;
  return s;
}

Status read_file(const std::string& path, std::vector<uint8_t>& bytes) {
  bytes.clear();
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return fail(ErrorCode::IoError, "Cannot open the file.", path);
  bool read_error = false;
#if defined(__cpp_exceptions)
  try {
#endif
    // Read straight into the buffer when the size is known, then in chunks
    // for whatever remains (pipes, files that grew).
    if (std::fseek(f, 0, SEEK_END) == 0) {
      const long end = std::ftell(f);
      if (end > 0 && std::fseek(f, 0, SEEK_SET) == 0) {
        bytes.resize(static_cast<size_t>(end));
        bytes.resize(std::fread(bytes.data(), 1, bytes.size(), f));
      } else {
        std::rewind(f);
      }
    }
    uint8_t chunk[1 << 16];
    for (;;) {
      const size_t got = std::fread(chunk, 1, sizeof chunk, f);
      bytes.insert(bytes.end(), chunk, chunk + got);
      if (got < sizeof chunk) {
        read_error = std::ferror(f) != 0;
        break;
      }
    }
#if defined(__cpp_exceptions)
  } catch (...) {  // std::bad_alloc (catch (...): see current_exception_code())
    std::fclose(f);
    return fail(ErrorCode::OutOfMemory, "Out of memory while reading the file.", path);
  }
#endif
  std::fclose(f);
  if (read_error) return fail(ErrorCode::IoError, "Reading the file failed.", path);
  return Status::success();
}

// ---------------------------------------------------------------------------
// Numbers
// ---------------------------------------------------------------------------

namespace {

bool is_digit(char c) { return c >= '0' && c <= '9'; }

// The eight characters at p as a number when all are digits (false
// otherwise), in a few 64-bit operations instead of eight steps: where
// there is no from_chars (WebAssembly), parsing the digits of 17-digit
// coordinates is most of a text file's read. The first character is the
// lowest byte of the little-endian load.
bool eight_digits(const char* p, uint64_t& out) {
  uint64_t x = 0;
  std::memcpy(&x, p, 8);
  // A byte b below '0' sets its top bit in x - '0'...'0' (the lowest such
  // byte receives no borrow); one above '9' sets it in x + 0x46...46 or, from
  // 0xb0 up, in x - '0'...'0'.
  const uint64_t d = x - 0x3030303030303030ull;
  if ((d | (x + 0x4646464646464646ull)) & 0x8080808080808080ull) return false;
  // Neighbouring digits into pairs (even bytes), pairs into fours (even
  // 16-bit lanes), then the two fours: no lane ever carries into the next.
  uint64_t v = (d * 10 + (d >> 8)) & 0x00ff00ff00ff00ffull;
  v = (v * 100 + (v >> 16)) & 0x0000ffff0000ffffull;
  out = (v & 0xffffffffull) * 10000 + (v >> 32);
  return true;
}

// Powers of ten that are exact in binary64.
constexpr double kPow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                               1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                               1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};

char lower(char c) { return (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c; }

// Everything the fast path does not handle: long mantissas, large exponents,
// hexadecimal, nan/inf. strtod is correctly rounded in glibc and in the musl
// used by emscripten; the token is copied so that it is NUL-terminated.
NumParse parse_double_slow(const char* p, size_t n, double& out) {
  char small[128];
  std::string big;
  char* buf = small;
  if (n + 1 > sizeof(small)) {
    big.assign(p, n);
    buf = &big[0];
  } else {
    std::memcpy(small, p, n);
    small[n] = '\0';
  }
  char* end = nullptr;
  const double v = std::strtod(buf, &end);
  if (end != buf + n || n == 0) return NumParse::Bad;
  if (!std::isfinite(v)) {
    size_t i = (p[0] == '+' || p[0] == '-') ? 1 : 0;
    const char c = i < n ? lower(p[i]) : '\0';
    return (c == 'n' || c == 'i') ? NumParse::NonFinite : NumParse::Overflow;
  }
  out = (v == 0) ? 0.0 : v;
  return NumParse::Ok;
}

__extension__ typedef unsigned __int128 U128;  // GCC and Clang, WebAssembly included

int bit_length(U128 x) {
  const uint64_t hi = static_cast<uint64_t>(x >> 64), lo = static_cast<uint64_t>(x);
  if (hi) return 128 - __builtin_clzll(hi);
  return lo ? 64 - __builtin_clzll(lo) : 0;
}

// Powers of five that are exact in binary64 (5^22 < 2^53).
constexpr uint64_t kPow5[23] = {1ull,
                                5ull,
                                25ull,
                                125ull,
                                625ull,
                                3125ull,
                                15625ull,
                                78125ull,
                                390625ull,
                                1953125ull,
                                9765625ull,
                                48828125ull,
                                244140625ull,
                                1220703125ull,
                                6103515625ull,
                                30517578125ull,
                                152587890625ull,
                                762939453125ull,
                                3814697265625ull,
                                19073486328125ull,
                                95367431640625ull,
                                476837158203125ull,
                                2384185791015625ull};

// floor(2^s / 5^d) with s = 127 + bit_length(5^d), for d = 1..22: a 128-bit
// reciprocal of 5^d normalized to [2^127, 2^128) (5^d is never a power of
// two), by long division one bit at a time (at compile time).
struct Reciprocals5 {
  U128 t[23] = {};
  int s[23] = {};
  constexpr Reciprocals5() {
    for (int d = 1; d <= 22; ++d) {
      const uint64_t D = kPow5[d];
      int len = 0;
      while ((D >> len) != 0) ++len;
      s[d] = 127 + len;
      U128 q = 0;
      uint64_t r = 1;  // the leading 1 of 2^s; 1 < D
      for (int i = 0; i < s[d]; ++i) {
        r <<= 1;
        q <<= 1;
        if (r >= D) {
          r -= D;
          q |= 1;
        }
      }
      t[d] = q;
    }
  }
};
constexpr Reciprocals5 kRecip5{};

// The double nearest to top * 2^shift (top in [2^52, 2^53)), or false when
// that is not a normal double.
bool make_double(uint64_t top, int shift, double& out) {
  const int biased = shift + 52 + 1023;
  if (biased < 1 || biased > 2046) return false;
  const uint64_t bits = (static_cast<uint64_t>(biased) << 52) | (top & ((uint64_t{1} << 52) - 1));
  std::memcpy(&out, &bits, sizeof out);
  return true;
}

// m / 10^d for d in 1..22, by one multiplication with the reciprocal of 5^d
// (no 128-bit division, which WebAssembly does in software). With M = m
// shifted to [2^63, 2^64) and T = kRecip5.t[d], the exact X = M * 2^s / 5^d
// lies in [P, P + M) for P = M * T (192 bits), since 2^s / 5^d is in
// [T, T + 1). So X's top 64 bits H are P's unless the middle word of P is
// all ones (a carry from below may reach H); then this returns false and the
// caller divides exactly. Otherwise X / 2^128 = H + f with 0 < f < 1 (f > 0
// because 2^s / 5^d is never an integer), so below the kept 53 bits the
// rounding sees rest + f: never an exact tie, above half when rest >= half.
bool reciprocal_decimal(uint64_t m, int d, double& out) {
  const int l = __builtin_clzll(m);
  const uint64_t M = m << l;
  const U128 T = kRecip5.t[d];
  const U128 lo = static_cast<U128>(M) * static_cast<uint64_t>(T);
  const U128 hi = static_cast<U128>(M) * static_cast<uint64_t>(T >> 64);
  const U128 mid = hi + (lo >> 64);  // P >> 64, exact (< 2^128)
  const uint64_t H = static_cast<uint64_t>(mid >> 64);
  if (static_cast<uint64_t>(mid) == UINT64_MAX) return false;
  const int drop = (H >> 63) ? 11 : 10;  // H >= 2^62 since M >= 2^63, T >= 2^127
  uint64_t top = H >> drop;
  const uint64_t rest = H & ((uint64_t{1} << drop) - 1);
  int shift = drop + 128 - kRecip5.s[d] - l - d;
  if (rest >= (uint64_t{1} << (drop - 1))) ++top;
  if (top == (uint64_t{1} << 53)) {
    top >>= 1;
    ++shift;
  }
  return make_double(top, shift, out);
}

}  // namespace

// In exact integer arithmetic: the value is n * 2^shift with n an integer
// of at most 128 bits, plus a sticky bit that says whether a nonzero
// remainder below n's last bit was dropped. For e10 >= 0, n = m * 5^e10
// exactly (< 2^64 * 5^22 < 2^116); for e10 = -d < 0, reciprocal_decimal
// answers all but a few cases, and otherwise n is the quotient of m * 2^k by
// 5^d (k puts m's top bit at bit 126, so n has at least 74 bits) and the
// remainder is the sticky bit. n is then rounded to 53 bits, to nearest with
// ties to even; a dropped half with the sticky bit set lies above the tie.
// Every value in range is a normal double (1e-22 <= m * 10^e10 < 2^64 *
// 1e22), so the bits are built directly. Why no floating-point estimate and
// no division where it can be avoided: both took a large share of a
// WebAssembly read (tests/bench/README.md, "The first read in WebAssembly,
// without random access").
bool exact_decimal(uint64_t m, int e10, double& out) {
  if (m == 0 || e10 < -22 || e10 > 22) return false;
  if (e10 < 0 && reciprocal_decimal(m, -e10, out)) return true;
  U128 n = 0;
  int shift = 0;
  bool sticky = false;
  if (e10 >= 0) {
    n = static_cast<U128>(m) * kPow5[e10];
    shift = e10;
  } else {
    const int d = -e10;
    const int k = 127 - bit_length(m);
    const U128 num = static_cast<U128>(m) << k;
    n = num / kPow5[d];
    sticky = num - n * kPow5[d] != 0;
    shift = -k - d;
  }
  const int len = bit_length(n);
  uint64_t top = 0;
  if (len <= 53) {
    top = static_cast<uint64_t>(n) << (53 - len);  // exact (sticky is false here)
    shift -= 53 - len;
  } else {
    const int drop = len - 53;
    top = static_cast<uint64_t>(n >> drop);
    const U128 rest = n & ((static_cast<U128>(1) << drop) - 1);
    const U128 half = static_cast<U128>(1) << (drop - 1);
    if (rest > half || (rest == half && (sticky || (top & 1)))) ++top;
    shift += drop;
    if (top == (uint64_t{1} << 53)) {
      top >>= 1;
      ++shift;
    }
  }
  // top in [2^52, 2^53): the value is top * 2^shift.
  return make_double(top, shift, out);
}

NumParse parse_double(const char* p, size_t n, double& out) {
#if defined(__cpp_lib_to_chars) && __cpp_lib_to_chars >= 201611L
  // Where the standard library has from_chars for doubles (not the libc++
  // of Debian's emscripten), it reads the common case several times faster
  // than the paths below, 17-digit coordinates as %.17g writes them
  // included. A finite decimal that it reads whole is the same correctly
  // rounded double; anything else (a '+', hexadecimal, nan/inf, underflow,
  // overflow) takes the paths below, so the result never depends on the
  // library.
  double v = 0;
  const auto r = std::from_chars(p, p + n, v, std::chars_format::general);
  if (r.ec == std::errc() && r.ptr == p + n && std::isfinite(v)) {
    out = (v == 0) ? 0.0 : v;  // -0 -> +0
    return NumParse::Ok;
  }
#endif
  return parse_decimal(p, n, out);
}

NumParse parse_decimal(const char* p, size_t n, double& out) {
  // Fast path (Clinger): a mantissa below 2^53 and a power of ten up to 1e22
  // are both exact, so one multiplication or division rounds correctly.
  size_t i = 0;
  bool neg = false;
  if (i < n && (p[i] == '+' || p[i] == '-')) {
    neg = p[i] == '-';
    ++i;
  }
  uint64_t m = 0;
  int digits = 0;
  int64_t exp10 = 0;
  bool any = false, exact = true;
  uint64_t eight = 0;
  for (; i < n && is_digit(p[i]); ++i) {
    any = true;
    if (m != 0 && digits <= 11 && n - i >= 8 && eight_digits(p + i, eight)) {
      m = m * 100000000 + eight;
      digits += 8;
      i += 7;
      continue;
    }
    const int d = p[i] - '0';
    if (m == 0 && d == 0) continue;
    if (digits < 19) {
      m = m * 10 + static_cast<uint64_t>(d);
      ++digits;
    } else {
      ++exp10;
      if (d != 0) exact = false;
    }
  }
  if (i < n && p[i] == '.') {
    for (++i; i < n && is_digit(p[i]); ++i) {
      any = true;
      if (m != 0 && digits <= 11 && n - i >= 8 && eight_digits(p + i, eight)) {
        m = m * 100000000 + eight;
        digits += 8;
        exp10 -= 8;
        i += 7;
        continue;
      }
      const int d = p[i] - '0';
      if (m == 0 && d == 0) {
        --exp10;
        continue;
      }
      if (digits < 19) {
        m = m * 10 + static_cast<uint64_t>(d);
        ++digits;
        --exp10;
      } else if (d != 0) {
        exact = false;
      }
    }
  }
  if (!any) return parse_double_slow(p, n, out);
  if (i < n && (p[i] == 'e' || p[i] == 'E')) {
    ++i;
    bool eneg = false;
    if (i < n && (p[i] == '+' || p[i] == '-')) {
      eneg = p[i] == '-';
      ++i;
    }
    if (i >= n || !is_digit(p[i])) return NumParse::Bad;
    int64_t e = 0;
    for (; i < n && is_digit(p[i]); ++i) {
      if (e < 100000) e = e * 10 + (p[i] - '0');
    }
    exp10 += eneg ? -e : e;
  }
  if (i != n) return parse_double_slow(p, n, out);
  if (m == 0) {
    out = 0.0;
    return NumParse::Ok;
  }
  if (exact && m <= (uint64_t{1} << 53) && exp10 >= -22 && exp10 <= 22) {
    double v = static_cast<double>(m);
    v = exp10 < 0 ? v / kPow10[-exp10] : v * kPow10[exp10];
    out = neg ? -v : v;
    return NumParse::Ok;
  }
  double w = 0;
  if (exact && exp10 >= -22 && exp10 <= 22 && exact_decimal(m, static_cast<int>(exp10), w)) {
    out = neg ? -w : w;
    return NumParse::Ok;
  }
  return parse_double_slow(p, n, out);
}

NumParse parse_int(const char* p, size_t n, int64_t& out) {
  size_t i = 0;
  bool neg = false;
  if (i < n && (p[i] == '+' || p[i] == '-')) {
    neg = p[i] == '-';
    ++i;
  }
  if (i >= n) return NumParse::Bad;
  uint64_t v = 0;
  bool overflow = false;
  for (; i < n; ++i) {
    if (!is_digit(p[i])) return NumParse::Bad;
    const uint64_t d = static_cast<uint64_t>(p[i] - '0');
    if (v > 922337203685477580ull) {  // (2^63 - 1) / 10: the next digit could overflow
      overflow = true;
    } else {
      v = v * 10 + d;
    }
  }
  if (overflow || v > 9223372036854775807ull) return NumParse::Overflow;
  out = neg ? -static_cast<int64_t>(v) : static_cast<int64_t>(v);
  return NumParse::Ok;
}

// ---------------------------------------------------------------------------
// Tokens
// ---------------------------------------------------------------------------

bool Token::is(const char* word) const {
  const size_t len = std::strlen(word);
  return len == n && std::memcmp(p, word, n) == 0;
}

bool Token::is_nocase(const char* word) const {
  const size_t len = std::strlen(word);
  if (len != n) return false;
  for (size_t i = 0; i < n; ++i) {
    if (lower(p[i]) != lower(word[i])) return false;
  }
  return true;
}

namespace {
bool is_blank(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
}  // namespace

TextReader::TextReader(const char* data, size_t size, char comment, size_t start, int64_t line)
    : data_(data),
      size_(size),
      pos_(start < size ? start : size),
      line_(line),
      last_line_(line),
      comment_(comment) {}

size_t TextReader::past_continuation(size_t at) const {
  if (!continuation_ || at >= size_ || data_[at] != '\\') return at;
  size_t k = at + 1;
  while (k < size_ && is_blank(data_[k])) ++k;
  if (k < size_ && data_[k] != '\n') return at;  // a backslash inside the line
  return k < size_ ? k + 1 : k;
}

void TextReader::skip_blank_and_comments(bool cross_lines) {
  while (pos_ < size_) {
    const char c = data_[pos_];
    const size_t joined = c == '\\' ? past_continuation(pos_) : pos_;
    if (joined != pos_) {
      // The logical line goes on; count the physical line feed consumed.
      if (data_[joined - 1] == '\n') ++line_;
      pos_ = joined;
    } else if (c == '\n') {
      if (!cross_lines) return;
      ++line_;
      ++pos_;
    } else if (is_blank(c)) {
      ++pos_;
    } else if (comment_ != 0 && c == comment_) {
      const void* nl = std::memchr(data_ + pos_, '\n', size_ - pos_);
      pos_ = nl ? static_cast<size_t>(static_cast<const char*>(nl) - data_) : size_;
    } else {
      return;
    }
  }
}

void TextReader::read_token(Token& t) {
  const size_t start = pos_;
  // A printable character other than the comment mark and a backslash never
  // ends a token: the first loop passes those with a cheap test, the second
  // applies every rule to the rest (a million-point .node file has four
  // million tokens).
  for (; pos_ < size_; ++pos_) {
    const char c = data_[pos_];
    if (static_cast<unsigned char>(c) <= ' ' || c == comment_ || c == '\\') break;
  }
  while (pos_ < size_) {
    const char c = data_[pos_];
    if (c == '\n' || is_blank(c) || (comment_ != 0 && c == comment_)) break;
    if (c == '\\' && past_continuation(pos_) != pos_) break;  // "2\" at a line end: token "2"
    ++pos_;
  }
  t.p = data_ + start;
  t.n = pos_ - start;
  t.line = line_;
  last_line_ = line_;
}

bool TextReader::next_slow(Token& t) {
  skip_blank_and_comments(true);
  if (pos_ >= size_) return false;
  read_token(t);
  return true;
}

bool TextReader::next_on_line(Token& t) {
  skip_blank_and_comments(false);
  if (pos_ >= size_ || data_[pos_] == '\n') return false;
  read_token(t);
  return true;
}

std::string TextReader::rest_of_line(size_t max_size) {
  std::string text;
  Token t;
  while (next_on_line(t)) {
    if (!text.empty()) text += ' ';
    text.append(t.p, t.n);
  }
  skip_line();
  if (text.size() > max_size) text.resize(max_size);
  return text;
}

void TextReader::skip_line() {
  if (continuation_) {
    // A statement we ignore may itself continue on the next physical lines.
    Token t;
    while (next_on_line(t)) {
    }
    if (pos_ < size_) {
      ++pos_;  // the line feed
      ++line_;
    }
    return;
  }
  const void* nl = std::memchr(data_ + pos_, '\n', size_ - pos_);
  if (!nl) {
    pos_ = size_;
    return;
  }
  pos_ = static_cast<size_t>(static_cast<const char*>(nl) - data_) + 1;
  ++line_;
}

bool TextReader::at_end() {
  skip_blank_and_comments(true);
  return pos_ >= size_;
}

Status expect_token(TextReader& r, Token& t, const std::string& file, const char* what) {
  if (r.next(t)) return Status::success();
  return fail(ErrorCode::Truncated, std::string("The file ends early: expected ") + what + ".",
              file, r.last_line());
}

std::string quote(const Token& t) {
  std::string s = t.n > 40 ? std::string(t.p, 40) + "..." : t.str();
  for (char& c : s) {
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) >= 0x7f) c = '?';
  }
  return "'" + s + "'";
}

namespace {

std::string describe(Subject who) {
  return std::string(who.kind) + " " + std::to_string(who.index);
}

Status located(Status s, Subject who) {
  if (std::strcmp(who.kind, "vertex") == 0) s.error.vertex = who.index;
  return s;
}

}  // namespace

Status coords_error(double x, double y, double z, const std::string& file, int64_t line,
                    int64_t record, Subject who) {
  const double c[3] = {x, y, z};
  for (int k = 0; k < 3; ++k) {
    if (std::isfinite(c[k]) && std::fabs(c[k]) <= kMaxCoordinate) continue;
    const std::string axis(1, static_cast<char>('x' + k));
    if (!std::isfinite(c[k])) {
      return located(fail(ErrorCode::NonFinite,
                          "The " + axis + " coordinate of " + describe(who) + " is not finite.",
                          file, line, record),
                     who);
    }
    if (std::fabs(c[k]) > kMaxCoordinate) {
      return located(fail(ErrorCode::CoordinateRange,
                          "The " + axis + " coordinate of " + describe(who) +
                              " exceeds the supported magnitude 1e50.",
                          file, line, record),
                     who);
    }
  }
  return Status::success();
}

Status parse_coord(const Token& t, double& out, const std::string& file, Subject who) {
  switch (parse_double(t.p, t.n, out)) {
    case NumParse::Ok:
      return Status::success();
    case NumParse::NonFinite:
      return located(
          fail(ErrorCode::NonFinite,
               "Non-finite coordinate " + quote(t) + " for " + describe(who) + ".", file, t.line),
          who);
    case NumParse::Overflow:
      return located(fail(ErrorCode::CoordinateRange,
                          "The coordinate " + quote(t) + " of " + describe(who) +
                              " exceeds the supported magnitude 1e50.",
                          file, t.line),
                     who);
    case NumParse::Bad:
      break;
  }
  return located(
      fail(ErrorCode::Parse,
           "Expected a number for a coordinate of " + describe(who) + ", found " + quote(t) + ".",
           file, t.line),
      who);
}

Status expect_coord(TextReader& r, double& out, const std::string& file, Subject who) {
  Token t;
  if (!r.next(t)) {
    return located(fail(ErrorCode::Truncated,
                        "The file ends early: expected a coordinate of " + describe(who) + ".",
                        file, r.last_line()),
                   who);
  }
  return parse_coord(t, out, file, who);
}

Status int_from_token(const Token& t, int64_t& out, const std::string& file, const char* what) {
  switch (parse_int(t.p, t.n, out)) {
    case NumParse::Ok:
      return Status::success();
    case NumParse::Overflow:
      return fail(ErrorCode::TooLarge,
                  std::string("The integer ") + quote(t) + " (" + what + ") is too large.", file,
                  t.line);
    default:
      break;
  }
  return fail(ErrorCode::Parse,
              std::string("Expected an integer (") + what + "), found " + quote(t) + ".", file,
              t.line);
}

Status count_from_token(const Token& t, uint64_t& out, const std::string& file, const char* what) {
  int64_t v = 0;
  Status s = int_from_token(t, v, file, what);
  if (!s.ok()) return s;
  if (v < 0) {
    return fail(ErrorCode::Parse, std::string("The ") + what + " is negative.", file, t.line);
  }
  if (static_cast<uint64_t>(v) > kMaxItems) {
    return fail(ErrorCode::TooLarge,
                std::string("The ") + what + " " + std::to_string(v) +
                    " exceeds the 32-bit limit of 4294967294.",
                file, t.line);
  }
  out = static_cast<uint64_t>(v);
  return Status::success();
}

Status expect_int(TextReader& r, int64_t& out, int64_t& line, const std::string& file,
                  const char* what) {
  Token t;
  Status s = expect_token(r, t, file, what);
  if (!s.ok()) return s;
  line = t.line;
  return int_from_token(t, out, file, what);
}

Status expect_count(TextReader& r, uint64_t& out, int64_t& line, const std::string& file,
                    const char* what) {
  Token t;
  Status s = expect_token(r, t, file, what);
  if (!s.ok()) return s;
  line = t.line;
  return count_from_token(t, out, file, what);
}

// ---------------------------------------------------------------------------
// PlcBuilder
// ---------------------------------------------------------------------------

namespace {

uint64_t bits_of(double d) {
  uint64_t u;
  std::memcpy(&u, &d, sizeof u);
  return u;
}

uint64_t hash_point(const Vec3& p) {
  uint64_t h = hash_mix(bits_of(p.x) + 0x9e3779b97f4a7c15ull);
  h = hash_mix(h ^ bits_of(p.y));
  h = hash_mix(h ^ (bits_of(p.z) * 0x9e3779b97f4a7c15ull));
  return h;
}

}  // namespace

PlcBuilder::PlcBuilder(Plc& plc, const std::string& file, int64_t index_base)
    : plc_(plc), file_(file), base_(index_base) {
  plc_ = Plc();
  plc_.file = file;
  table_.assign(64, kEmptySlot);
}

// A slot holds a point id in its low 32 bits and the top 32 bits of the
// point's hash in its high bits, so that a probe compares coordinates (a
// read of another point, at random on large inputs) only on a full hash
// match. kEmptySlot is never a slot's value: no point has id kNone.
void PlcBuilder::insert_slot(std::vector<uint64_t>& table, uint32_t id) const {
  const uint64_t mask = table.size() - 1;
  const uint64_t hash = hash_point(plc_.points[id]);
  uint64_t h = hash & mask;
  while (table[h] != kEmptySlot) h = (h + 1) & mask;
  table[h] = (hash >> 32 << 32) | id;
}

void PlcBuilder::reserve_vertices(uint64_t count, uint64_t cap, uint64_t distinct) {
  const uint64_t n = count < cap ? count : cap;
  const uint64_t d = distinct < n ? distinct : n;
  remap_.reserve(static_cast<size_t>(n));
  plc_.points.reserve(static_cast<size_t>(d));
  size_t want = 64;
  while (want < 2 * d + 2) want *= 2;
  if (want > table_.size()) {
    table_.assign(want, kEmptySlot);
    for (uint32_t id = 0; id < plc_.points.size(); ++id) insert_slot(table_, id);
  }
}

void PlcBuilder::grow_table() {
  // Rebuilt from the points vector in id order: deterministic.
  std::vector<uint64_t> t(table_.size() * 2, kEmptySlot);
  for (uint32_t id = 0; id < plc_.points.size(); ++id) insert_slot(t, id);
  table_.swap(t);
}

uint32_t PlcBuilder::weld(const Vec3& p, uint64_t hash) {
  // Neighbouring records often repeat a recent point (adjacent STL triangles
  // share corners): check the last few ids before probing. Same result either
  // way, since each distinct point has exactly one id.
  for (uint32_t id : recent_) {
    if (id != kNone && plc_.points[id] == p) return id;
  }
  const uint32_t id = lookup_or_insert(p, hash);
  recent_[recent_next_] = id;
  recent_next_ = (recent_next_ + 1) % kRecent;
  return id;
}

uint32_t PlcBuilder::lookup_or_insert(const Vec3& p, uint64_t hash) {
  if (2 * (plc_.points.size() + 1) > table_.size()) grow_table();
  const uint64_t mask = table_.size() - 1;
  const uint64_t tag = hash >> 32 << 32;
  uint64_t h = hash & mask;
  while (table_[h] != kEmptySlot) {
    const uint64_t slot = table_[h];
    if ((slot >> 32 << 32) == tag && plc_.points[static_cast<uint32_t>(slot)] == p)
      return static_cast<uint32_t>(slot);
    h = (h + 1) & mask;
  }
  const uint32_t id = static_cast<uint32_t>(plc_.points.size());
  table_[h] = tag | id;
  plc_.points.push_back(p);
  return id;
}

namespace {

// -0 and +0 are the same point: store +0 so equality and hashing agree.
Vec3 plus_zero(double x, double y, double z) {
  Vec3 p;
  p.x = x == 0 ? 0.0 : x;
  p.y = y == 0 ? 0.0 : y;
  p.z = z == 0 ? 0.0 : z;
  return p;
}

}  // namespace

Status PlcBuilder::add_vertex(double x, double y, double z, int64_t line, int64_t record) {
  if (file_vertex_count() >= kMaxItems) {
    return fail(ErrorCode::TooLarge, "The file has more than 4294967294 vertices.", file_, line,
                record);
  }
  pending_[pending_count_++] = plus_zero(x, y, z);
  if (pending_count_ == kWeldBatch) weld_pending();
  return Status::success();
}

void PlcBuilder::weld_pending() {
  // Each record's first probe is loaded before any record is welded: the
  // loads are independent, so their cache misses overlap instead of coming
  // one after the other (the table is read at random). Only a prefetch:
  // lookup_or_insert probes again, after the inserts before it.
  const uint64_t mask = table_.size() - 1;
  uint64_t hash[kWeldBatch];
  uint64_t touched = 0;
  for (size_t k = 0; k < pending_count_; ++k) {
    hash[k] = hash_point(pending_[k]);
    touched += table_[hash[k] & mask];
  }
  prefetch_sink_ += touched;
  for (size_t k = 0; k < pending_count_; ++k) remap_.push_back(weld(pending_[k], hash[k]));
  pending_count_ = 0;
}

Facet& PlcBuilder::add_facet(int64_t line, int64_t record) {
  plc_.facets.emplace_back();
  Facet& f = plc_.facets.back();
  f.line = line;
  f.record = record;
  f.marker = marker_;
  return f;
}

void PlcBuilder::start_named_group(const std::string& name, int next_marker) {
  if (name.empty()) {
    marker_ = 0;
    return;
  }
  for (const auto& [marker, known] : plc_.marker_names)
    if (known == name) {
      marker_ = marker;
      return;
    }
  if (next_marker_ < 0) next_marker_ = next_marker;
  marker_ = next_marker_++;
  plc_.marker_names.emplace_back(marker_, name);
}

void PlcBuilder::add_segment(uint32_t a, uint32_t b, int64_t line, int64_t record) {
  segments_.push_back(Ref{a, b, line, record});
}

void PlcBuilder::add_isolated(uint32_t a, int64_t line, int64_t record) {
  isolated_.push_back(Ref{a, a, line, record});
}

Status PlcBuilder::out_of_range(uint64_t index, int64_t line, int64_t record, int64_t facet) const {
  Status s = fail(ErrorCode::IndexOutOfRange,
                  "Vertex index " + std::to_string(static_cast<int64_t>(index) + base_) +
                      " is out of range: the file has " + std::to_string(remap_.size()) +
                      " vertices" + (base_ == 1 ? ", numbered from 1." : ", numbered from 0."),
                  file_, line, record);
  s.error.facet = facet;
  return s;
}

Status PlcBuilder::finish() {
  weld_pending();
  const uint64_t n = remap_.size();
  Status bad;
  for_blocks(plc_.facets.size(), [&](size_t begin, size_t end) {
    for (size_t fi = begin; fi < end; ++fi) {
      Facet& f = plc_.facets[fi];
      for (auto& loop : f.loops) {
        for (VertexId& v : loop) {
          if (v >= n) {
            bad = out_of_range(v, f.line, f.record, static_cast<int64_t>(fi));
            return false;
          }
          v = remap_[v];
        }
      }
    }
    return true;
  });
  if (!bad.ok()) return bad;
  for (const Ref& r : isolated_) {
    if (r.a >= n) return out_of_range(r.a, r.line, r.record, -1);
  }
  plc_.segments.reserve(segments_.size());
  for (const Ref& r : segments_) {
    if (r.a >= n) return out_of_range(r.a, r.line, r.record, -1);
    if (r.b >= n) return out_of_range(r.b, r.line, r.record, -1);
    const uint32_t a = remap_[r.a], b = remap_[r.b];
    if (a == b) {
      Status s = fail(ErrorCode::DegenerateFacet,
                      "Segment " + std::to_string(plc_.segments.size()) +
                          " has identical endpoints (point " + std::to_string(a) + ").",
                      file_, r.line, r.record);
      s.error.vertex = a;
      return s;
    }
    plc_.segments.push_back({a, b});
  }
  plc_.file_vertices = static_cast<size_t>(n);
  plc_.welded_vertices = static_cast<size_t>(n - plc_.points.size());
  std::vector<uint64_t>().swap(table_);
  return Status::success();
}

}  // namespace io
}  // namespace cdt3d
