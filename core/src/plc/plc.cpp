// PLC entry points: format detection by extension, read_plc dispatch (then
// check_plc), reading a file from disk, and the summary used by `cdt3d info`.
#include <algorithm>
#include <cdt3d/cdt3d.hpp>
#include <exception>
#include <new>

#include "blocks.hpp"
#include "group_by_key.hpp"
#include "geometry.hpp"
#include "plc_check.hpp"
#include "status.hpp"
#include "io/read_common.hpp"

namespace cdt3d {

FileFormat format_from_name(const std::string& file_name) {
  const size_t dot = file_name.find_last_of('.');
  const size_t slash = file_name.find_last_of("/\\");
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) {
    return FileFormat::Unknown;
  }
  std::string ext = file_name.substr(dot + 1);
  for (char& c : ext) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  if (ext == "stl") return FileFormat::Stl;
  if (ext == "off") return FileFormat::Off;
  if (ext == "obj") return FileFormat::Obj;
  if (ext == "ply") return FileFormat::Ply;
  if (ext == "poly") return FileFormat::Poly;
  if (ext == "smesh") return FileFormat::Smesh;
  if (ext == "node") return FileFormat::Node;
  return FileFormat::Unknown;
}

namespace {

Status dispatch(const uint8_t* data, size_t size, const std::string& file_name, Plc& out) {
  // A null pointer with a size would be a caller bug; treat it as no data.
  static const uint8_t kNothing = 0;
  if (data == nullptr) {
    data = &kNothing;
    size = 0;
  }
  const FileFormat format = format_from_name(file_name);
  // A UTF-8 byte order mark before a text format is not content. (A binary
  // STL header may hold any bytes: read_stl handles its own case.)
  if (format != FileFormat::Stl && size >= 3 && data[0] == 0xEF && data[1] == 0xBB &&
      data[2] == 0xBF) {
    data += 3;
    size -= 3;
  }
  switch (format) {
    case FileFormat::Stl:
      return io::read_stl(data, size, file_name, out);
    case FileFormat::Off:
      return io::read_off(data, size, file_name, out);
    case FileFormat::Obj:
      return io::read_obj(data, size, file_name, out);
    case FileFormat::Ply:
      return io::read_ply(data, size, file_name, out);
    case FileFormat::Poly:
      return io::read_tetgen(data, size, file_name, FileFormat::Poly, out);
    case FileFormat::Smesh:
      return io::read_tetgen(data, size, file_name, FileFormat::Smesh, out);
    case FileFormat::Node:
      return io::read_tetgen(data, size, file_name, FileFormat::Node, out);
    case FileFormat::Unknown:
      break;
  }
  return io::fail(ErrorCode::UnknownFormat,
                  "Unknown file extension: expected .stl, .off, .obj, .ply, .poly, .smesh or "
                  ".node.",
                  file_name);
}

Status read_and_check(const uint8_t* data, size_t size, const std::string& file_name, Plc& out,
                      bool check) {
  Status s = dispatch(data, size, file_name, out);
  if (s.ok() && out.points.empty()) {
    s = io::fail(ErrorCode::Empty, "The file contains no vertices.", file_name);
  }
  if (s.ok() && check) s = check_welded_plc(out);
  if (!s.ok()) {
    // Never hand back half a PLC.
    out = Plc();
    out.file = file_name;
  }
  return s;
}

}  // namespace

Status read_plc(const uint8_t* data, size_t size, const std::string& file_name, Plc& out,
                bool check) {
#if defined(__cpp_exceptions)
  // Nothing here throws except allocation; turn that into a status.
  try {
    return read_and_check(data, size, file_name, out, check);
  } catch (...) {  // catch (...): see current_exception_code()
    out = Plc();
    Status st;
    st.error = current_exception_error("reading the file", file_name);
    return st;
  }
#else
  return read_and_check(data, size, file_name, out, check);
#endif
}

Status read_plc_file(const std::string& path, Plc& out, bool check) {
  out = Plc();
  out.file = path;
  if (format_from_name(path) == FileFormat::Unknown) {
    // Report the extension before touching the file system.
    return read_plc(nullptr, 0, path, out, check);
  }
  std::vector<uint8_t> bytes;
  Status s = io::read_file(path, bytes);
  if (!s.ok()) return s;
  return read_plc(bytes.data(), bytes.size(), path, out, check);
}

namespace {

// Every edge as (min << 32 | max), sorted, each once.
std::vector<uint64_t> packed_edges(const Plc& plc) {
  std::vector<uint64_t> edges;
  size_t n = plc.segments.size();
  for (const Facet& f : plc.facets) {
    for (const auto& loop : f.loops) n += loop.size();
  }
  edges.reserve(n);
  const size_t np = plc.points.size();
  bool in_range = true;  // false for an unchecked PLC
  auto add = [&edges, &in_range, np](VertexId a, VertexId b) {
    if (a == b) return;
    if (a >= np || b >= np) in_range = false;
    edges.push_back(edge_key(a, b));
  };
  for (const auto& s : plc.segments) add(s[0], s[1]);
  for_blocks(plc.facets.size(), [&](size_t begin, size_t end) {
    for (size_t fi = begin; fi < end; ++fi) {
      for (const auto& loop : plc.facets[fi].loops) {
        const size_t m = loop.size();
        for (size_t i = 0; i < m; ++i) add(loop[i], loop[i + 1 == m ? 0 : i + 1]);
      }
    }
    return true;
  });
  // Grouped by the smaller vertex (base/group_by_key.hpp), each group's
  // larger vertices sorted and made unique: the same order as sorting the
  // packed values, in one counting pass that follows the vertex numbering.
  if (!in_range || edges.size() > UINT32_MAX) {
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    return edges;
  }
  std::vector<uint32_t> other, end;
  group_by_key(
      edges.size(), np, [&edges](size_t i) { return static_cast<size_t>(edges[i] >> 32); },
      [&edges](size_t i) { return static_cast<uint32_t>(edges[i]); }, other, end);
  size_t out = 0, b = 0;
  for_blocks(np, [&](size_t v0, size_t v1) {
    for (size_t a = v0; a < v1; ++a) {
      const auto first = other.begin() + static_cast<std::ptrdiff_t>(b);
      const auto last = other.begin() + static_cast<std::ptrdiff_t>(end[a]);
      std::sort(first, last);
      for (auto it = first; it != last; ++it) {
        if (it == first || *it != *(it - 1)) edges[out++] = (uint64_t(a) << 32) | *it;
      }
      b = end[a];
    }
    return true;
  });
  edges.resize(out);
  return edges;
}

}  // namespace

std::vector<std::array<VertexId, 2>> plc_segments(const Plc& plc) {
  const std::vector<uint64_t> edges = packed_edges(plc);
  std::vector<std::array<VertexId, 2>> segs(edges.size());
  for (size_t i = 0; i < edges.size(); ++i) {
    segs[i] = {static_cast<VertexId>(edges[i] >> 32), static_cast<VertexId>(edges[i])};
  }
  return segs;
}

PlcInfo plc_info(const Plc& plc) {
  PlcInfo info;
  info.file_vertices = plc.file_vertices;
  info.points = plc.points.size();
  info.facets = plc.facets.size();
  info.holes = plc.holes.size();
  info.regions = plc.regions.size();
  std::vector<uint8_t> used(plc.points.size(), 0);
  auto mark = [&used](VertexId v) {
    if (v < used.size()) used[v] = 1;
  };
  for_blocks(plc.facets.size(), [&](size_t begin, size_t end) {
    for (size_t fi = begin; fi < end; ++fi) {
      for (const auto& loop : plc.facets[fi].loops) {
        ++info.loops;
        if (loop.size() >= 3) info.triangles += loop.size() - 2;
        for (VertexId v : loop) mark(v);
      }
    }
    return true;
  });
  for (const auto& s : plc.segments) {
    mark(s[0]);
    mark(s[1]);
  }
  for (uint8_t u : used) info.unreferenced += u ? 0 : 1;
  info.segments = packed_edges(plc).size();
  if (!plc.points.empty()) {
    info.bbox_min = info.bbox_max = plc.points[0];
    for (const Vec3& p : plc.points) {
      info.bbox_min.x = std::min(info.bbox_min.x, p.x);
      info.bbox_min.y = std::min(info.bbox_min.y, p.y);
      info.bbox_min.z = std::min(info.bbox_min.z, p.z);
      info.bbox_max.x = std::max(info.bbox_max.x, p.x);
      info.bbox_max.y = std::max(info.bbox_max.y, p.y);
      info.bbox_max.z = std::max(info.bbox_max.z, p.z);
    }
  }
  return info;
}

}  // namespace cdt3d
