// Shared pieces of the mesh writers: a byte builder that prints numbers
// through std::to_chars (no format parsing, no locale) and appends binary
// values for the binary formats (MSH binary, VTU appended data), and the
// element counts of a TetMeshData.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <charconv>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <type_traits>

namespace cdt3d {
namespace io {

class Out {
 public:
  explicit Out(size_t reserve) { s_.reserve(reserve); }

  Out& str(const char* t) {
    s_ += t;
    return *this;
  }
  Out& str(const std::string& t) {
    s_ += t;
    return *this;
  }
  // Numbers through std::to_chars, which skips printf's format parsing and
  // locale (a mesh is millions of numbers).
  Out& u(uint64_t v) {
    char buf[24];
    s_.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
    return *this;
  }
  Out& i(int64_t v) {
    char buf[24];
    s_.append(buf, std::to_chars(buf, buf + sizeof buf, v).ptr);
    return *this;
  }
  Out& d(double v) {
    char buf[32];
#if defined(__cpp_lib_to_chars) && __cpp_lib_to_chars >= 201611L
    // The same text as %.17g: the standard defines to_chars with a format
    // and a precision as printf with the matching conversion.
    s_.append(buf, std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general, 17).ptr);
#else
    // Standard libraries without floating-point to_chars (Emscripten's).
    const int n = std::snprintf(buf, sizeof buf, "%.17g", v);
    s_.append(buf, static_cast<size_t>(n));
#endif
    return *this;
  }
  Out& sp() {
    s_ += ' ';
    return *this;
  }
  Out& nl() {
    s_ += '\n';
    return *this;
  }
  /// The bytes of `v` in the machine's byte order (binary formats say which).
  template <typename T>
  Out& bin(T v) {
    static_assert(std::is_arithmetic<T>::value, "binary values are numbers");
    char buf[sizeof(T)];
    std::memcpy(buf, &v, sizeof(T));
    s_.append(buf, sizeof(T));
    return *this;
  }
  size_t size() const { return s_.size(); }
  std::string take() { return std::move(s_); }

 private:
  std::string s_;
};

/// True on little-endian machines (x86-64, WebAssembly): the binary formats
/// write the machine's order and name it in their header.
inline bool little_endian() {
  const uint16_t one = 1;
  unsigned char first = 0;
  std::memcpy(&first, &one, 1);
  return first == 1;
}

/// Vertex order for Gmsh and VTK. cdt3d's tets are positive for orient3d
/// (Shewchuk's sign: the fourth vertex below the first three, seen turning
/// counterclockwise), which is negative for the reference tetrahedron of Gmsh
/// and VTK (the fourth vertex on the side of the right-hand normal); one swap
/// makes their volumes positive (`gmsh -check` warns otherwise).
constexpr int kRightHandedTet[4] = {0, 2, 1, 3};

inline size_t n_points(const TetMeshData& m) { return m.points.size() / 3; }
inline size_t n_tets(const TetMeshData& m) { return m.tets.size() / 4; }
inline size_t n_faces(const TetMeshData& m) { return m.faces.size() / 3; }
inline bool has_attributes(const TetMeshData& m) {
  return n_tets(m) > 0 && m.tet_attributes.size() == n_tets(m);
}
inline bool has_markers(const TetMeshData& m) {
  return n_faces(m) > 0 && m.face_markers.size() == n_faces(m);
}

}  // namespace io
}  // namespace cdt3d
