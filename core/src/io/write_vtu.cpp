// VTK XML unstructured grid (.vtu) writer, written from the description of
// VTK's XML file formats: one piece of tetrahedra, every array in one raw
// appended block (`<AppendedData encoding="raw">`), each array's bytes
// preceded by their byte count as UInt64 (header_type="UInt64"); an array's
// offset attribute counts bytes from the first byte after the '_' that opens
// the block. Raw binary rather than base64 keeps the file a third smaller
// and needs no encoder; ParaView, VTK and meshio read both.
//
// Arrays: Points Float64 x3; Cells connectivity and offsets Int64, types
// UInt8 (10 = VTK_TETRA), each tet right-handed as VTK's reference tet is
// (kRightHandedTet); PointData "steiner_kind" UInt8 (0 input point, then
// SteinerKind: 1 segment, 2 facet, 3 volume); CellData "region" Float64 (the
// region attribute, only when the result has them, like write_vtk) and
// "min_dihedral" Float64 (smallest dihedral angle of the tet, degrees). Only
// tets are cells: one cell type keeps every cell array meaningful for every
// cell.
#include <cdt3d/cdt3d.hpp>

#include <cstdint>
#include <string>
#include <vector>

#include "geometry.hpp"
#include "write_common.hpp"

namespace cdt3d {
namespace {

using io::n_points;
using io::n_tets;
using io::Out;

constexpr uint8_t kVtkTetra = 10;

// Collects the appended arrays and the XML elements that point at them.
class Appended {
 public:
  explicit Appended(size_t reserve) : data_(reserve) {}

  /// Adds an array's bytes (with their UInt64 byte count first) and returns
  /// its <DataArray> element.
  template <typename T, typename Fill>
  std::string array(const char* type, const char* name, int components, size_t count, Fill fill) {
    std::string xml = std::string("<DataArray type=\"") + type + "\"";
    if (name) xml += std::string(" Name=\"") + name + "\"";
    if (components > 1) xml += " NumberOfComponents=\"" + std::to_string(components) + "\"";
    xml += " format=\"appended\" offset=\"" + std::to_string(data_.size()) + "\"/>\n";
    data_.bin(static_cast<uint64_t>(count * sizeof(T)));
    for (size_t i = 0; i < count; ++i) data_.bin(static_cast<T>(fill(i)));
    return xml;
  }
  std::string take() { return data_.take(); }

 private:
  Out data_;
};

}  // namespace

std::string write_vtu(const Result& r) {
  const TetMeshData& m = r.mesh;
  const size_t np = n_points(m), nt = n_tets(m);
  Appended a(64 + np * 25 + nt * 57);

  // The data go in the reverse order of their <DataArray> elements. meshio 5
  // reads raw appended data by rewriting each element's offset in turn and
  // looking the next one up by value; in file order a rewritten offset can
  // equal a later raw one and the lookup takes the wrong element (a one-tet
  // mesh's connectivity got the types' bytes). In reverse order the element
  // looked up always comes before the rewritten ones. VTK reads either.
  const std::string types =
      a.array<uint8_t>("UInt8", "types", 1, nt, [](size_t) { return kVtkTetra; });
  const std::string offsets =
      a.array<int64_t>("Int64", "offsets", 1, nt, [](size_t t) { return 4 * (t + 1); });
  auto corner = [&](size_t i) { return m.tets[i - i % 4 + io::kRightHandedTet[i % 4]]; };
  const std::string connectivity = a.array<int64_t>("Int64", "connectivity", 1, 4 * nt, corner);
  const std::string points =
      a.array<double>("Float64", "Points", 3, 3 * np, [&](size_t i) { return m.points[i]; });
  const std::string dihedral = a.array<double>("Float64", "min_dihedral", 1, nt, [&](size_t t) {
    Vec3 p[4];
    for (int k = 0; k < 4; ++k) p[k] = to_vec(&m.points[3 * size_t{m.tets[4 * t + k]}]);
    double lo, hi;
    dihedral_range(p, lo, hi);
    return lo;
  });
  std::string region;
  if (io::has_attributes(m))
    region =
        a.array<double>("Float64", "region", 1, nt, [&](size_t t) { return m.tet_attributes[t]; });
  const std::string steiner = a.array<uint8_t>("UInt8", "steiner_kind", 1, np, [&](size_t p) {
    if (p < r.input_points) return uint8_t{0};
    const size_t s = p - r.input_points;
    return s < r.steiner_kind.size() ? static_cast<uint8_t>(r.steiner_kind[s])
                                     : static_cast<uint8_t>(SteinerKind::Volume);
  });
  const std::string data = a.take();

  Out o(1024 + data.size());
  o.str("<?xml version=\"1.0\"?>\n");
  o.str("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"")
      .str(io::little_endian() ? "LittleEndian" : "BigEndian")
      .str("\" header_type=\"UInt64\">\n");
  o.str("<UnstructuredGrid>\n");
  o.str("<Piece NumberOfPoints=\"").u(np).str("\" NumberOfCells=\"").u(nt).str("\">\n");
  o.str("<PointData Scalars=\"steiner_kind\">\n").str(steiner).str("</PointData>\n");
  o.str(io::has_attributes(m) ? "<CellData Scalars=\"region\">\n"
                              : "<CellData Scalars=\"min_dihedral\">\n")
      .str(region)
      .str(dihedral)
      .str("</CellData>\n");
  o.str("<Points>\n").str(points).str("</Points>\n");
  o.str("<Cells>\n").str(connectivity).str(offsets).str(types).str("</Cells>\n");
  o.str("</Piece>\n</UnstructuredGrid>\n");
  o.str("<AppendedData encoding=\"raw\">\n_").str(data).str("\n</AppendedData>\n</VTKFile>\n");
  return o.take();
}

}  // namespace cdt3d
