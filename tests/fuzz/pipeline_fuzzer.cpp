// libFuzzer target for the whole pipeline on tiny inputs. The bytes are
// decoded (see decode()) into a PLC of 4..12 points on the integer grid
// {0,1,2,3}^3 with a few triangles or quadrilaterals and optional explicit
// segments. Inputs that check_plc rejects are skipped. Every other input must
// make tetrahedralize() return (success or a reported error) without
// crashing; a success must pass validate(); an ErrorCode::Internal is a
// library bug; two runs on the same input must give the same mesh. (Flat
// tets are not checked here: on these grid inputs a rounded Steiner point
// can still make one next to a facet whose plane holds other vertices; the
// corpus ctests check that no model of tests/data has one.)
//
// Set CDT3D_FUZZ_ALLOW_INTERNAL=1 to let Internal errors through (while a
// known one is being fixed), CDT3D_FUZZ_VERBOSE=1 to print each outcome, and
// CDT3D_FUZZ_DUMP=path.poly to write the decoded PLC as a TetGen .poly file
// (for `cdt3d mesh path.poly --validate [--keep-hull]`).
#include <cdt3d/cdt3d.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace {

class Bytes {
 public:
  Bytes(const uint8_t* data, size_t size) : data_(data), size_(size) {}
  bool empty() const { return pos_ >= size_; }
  uint8_t next() { return pos_ < size_ ? data_[pos_++] : 0; }

 private:
  const uint8_t* data_;
  size_t size_;
  size_t pos_ = 0;
};

struct Decoded {
  cdt3d::Plc plc;
  cdt3d::Options options;
};

// Layout: [flags] [point count] [one byte per point] [facet count]
// [per facet: header, 3 or 4 vertex bytes] [segment count, 2 bytes each].
//  flags bit 0: keep_convex_hull; bit 1: explicit segments follow the facets;
//  bit 2: a volume hole point at (1.5, 1.5, 1.5).
//  point byte: x = bits 0-1, y = bits 2-3, z = bits 4-5; repeated grid
//  positions are welded (the PLC keeps each point once, as the readers do).
//  facet header: bits 0-1 == 3 gives a quadrilateral, else a triangle;
//  bits 2-4 the marker. Vertex bytes are taken modulo the point count.
Decoded decode(const uint8_t* data, size_t size) {
  Bytes in(data, size);
  Decoded d;
  const uint8_t flags = in.next();
  d.options.keep_convex_hull = (flags & 1) != 0;
  d.options.validate = true;
  const int n = 4 + in.next() % 9;
  int grid_id[64];
  for (int& g : grid_id) g = -1;
  cdt3d::VertexId ids[12];
  for (int i = 0; i < n; ++i) {
    const uint8_t b = in.next();
    const int cell = b & 63;
    if (grid_id[cell] < 0) {
      grid_id[cell] = static_cast<int>(d.plc.points.size());
      d.plc.points.push_back({static_cast<double>(b & 3), static_cast<double>((b >> 2) & 3),
                              static_cast<double>((b >> 4) & 3)});
    }
    ids[i] = static_cast<cdt3d::VertexId>(grid_id[cell]);
  }
  const int facets = in.empty() ? 0 : 1 + in.next() % 8;
  for (int f = 0; f < facets && !in.empty(); ++f) {
    const uint8_t h = in.next();
    const int corners = (h & 3) == 3 ? 4 : 3;
    cdt3d::Facet facet;
    facet.marker = (h >> 2) & 7;
    facet.loops.emplace_back();
    for (int k = 0; k < corners; ++k) facet.loops.back().push_back(ids[in.next() % n]);
    d.plc.facets.push_back(std::move(facet));
  }
  if ((flags & 2) && !in.empty()) {
    const int segments = 1 + in.next() % 3;
    for (int s = 0; s < segments && !in.empty(); ++s) {
      const cdt3d::VertexId a = ids[in.next() % n];
      const cdt3d::VertexId b = ids[in.next() % n];
      d.plc.segments.push_back({a, b});
    }
  }
  if (flags & 4) d.plc.holes.push_back({1.5, 1.5, 1.5});
  return d;
}

std::string describe(const cdt3d::Plc& plc) {
  std::string s = "points:";
  for (const cdt3d::Vec3& p : plc.points) {
    s += " (" + std::to_string(static_cast<int>(p.x)) + "," + std::to_string(static_cast<int>(p.y)) +
         "," + std::to_string(static_cast<int>(p.z)) + ")";
  }
  s += "\nfacets:";
  for (const cdt3d::Facet& f : plc.facets) {
    s += " [";
    for (size_t k = 0; k < f.loops[0].size(); ++k) {
      s += (k ? " " : "") + std::to_string(f.loops[0][k]);
    }
    s += "]";
  }
  s += "\nsegments:";
  for (const auto& e : plc.segments) {
    s += " [" + std::to_string(e[0]) + " " + std::to_string(e[1]) + "]";
  }
  s += "\nholes: " + std::to_string(plc.holes.size());
  return s;
}

// The decoded PLC as a TetGen .poly file (0-based), so that a finding can be
// replayed with the CLI and kept as a regression model.
void dump_poly(const Decoded& d, const char* path) {
  std::FILE* f = std::fopen(path, "w");
  if (!f) return;
  std::fprintf(f, "# fuzz_pipeline input, keep_convex_hull = %d\n%zu 3 0 0\n",
               d.options.keep_convex_hull ? 1 : 0, d.plc.points.size());
  for (size_t i = 0; i < d.plc.points.size(); ++i) {
    const cdt3d::Vec3& p = d.plc.points[i];
    std::fprintf(f, "%zu %.17g %.17g %.17g\n", i, p.x, p.y, p.z);
  }
  std::fprintf(f, "%zu 1\n", d.plc.facets.size() + d.plc.segments.size());
  for (const cdt3d::Facet& facet : d.plc.facets) {
    std::fprintf(f, "1 0 %d\n%zu", facet.marker, facet.loops[0].size());
    for (cdt3d::VertexId v : facet.loops[0]) std::fprintf(f, " %u", v);
    std::fprintf(f, "\n");
  }
  for (const auto& e : d.plc.segments) std::fprintf(f, "1 0 0\n2 %u %u\n", e[0], e[1]);
  std::fprintf(f, "%zu\n", d.plc.holes.size());
  for (size_t i = 0; i < d.plc.holes.size(); ++i) {
    const cdt3d::Vec3& p = d.plc.holes[i];
    std::fprintf(f, "%zu %.17g %.17g %.17g\n", i, p.x, p.y, p.z);
  }
  std::fprintf(f, "0\n");
  std::fclose(f);
}

[[noreturn]] void fuzz_fail(const char* what, const Decoded& d, const cdt3d::Status& s) {
  std::fprintf(stderr, "fuzz_pipeline: %s (keep_convex_hull=%d): %s\n%s\n", what,
               d.options.keep_convex_hull ? 1 : 0, s.error.to_string().c_str(),
               describe(d.plc).c_str());
  std::abort();
}

bool env_flag(const char* name) {
  const char* v = std::getenv(name);
  return v != nullptr && v[0] != '\0' && v[0] != '0';
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size > 64) return 0;  // tiny inputs only; decode() reads at most ~60 bytes
  static const bool allow_internal = env_flag("CDT3D_FUZZ_ALLOW_INTERNAL");
  static const bool verbose = env_flag("CDT3D_FUZZ_VERBOSE");
  const Decoded d = decode(data, size);
  if (!cdt3d::check_plc(d.plc).ok()) return -1;  // not a valid input: keep it out of the corpus
  static const char* dump = std::getenv("CDT3D_FUZZ_DUMP");
  if (dump != nullptr && dump[0] != '\0') dump_poly(d, dump);

  const cdt3d::Result r = cdt3d::tetrahedralize(d.plc, d.options);
  if (verbose) {
    std::fprintf(stderr, "fuzz_pipeline: %s, %zu tets\n",
                 r.status.ok() ? "ok" : r.status.error.to_string().c_str(),
                 r.mesh.tets.size() / 4);
  }
  if (!r.status.ok()) {
    if (r.status.error.code == cdt3d::ErrorCode::Internal && !allow_internal) {
      fuzz_fail("tetrahedralize reports an internal error", d, r.status);
    }
    if (r.status.error.message.empty()) fuzz_fail("error without a message", d, r.status);
  } else {
    if (r.input_points != d.plc.points.size()) fuzz_fail("input_points is wrong", d, r.status);
    const cdt3d::Status v = cdt3d::validate(d.plc, r);
    if (!v.ok()) fuzz_fail("validate rejects the result of tetrahedralize", d, v);
  }

  // Determinism: the same input gives the same output.
  const cdt3d::Result again = cdt3d::tetrahedralize(d.plc, d.options);
  if (again.status.error.code != r.status.error.code || again.mesh.points != r.mesh.points ||
      again.mesh.tets != r.mesh.tets || again.mesh.faces != r.mesh.faces) {
    fuzz_fail("two runs on the same input differ", d, r.status);
  }
  return 0;
}
