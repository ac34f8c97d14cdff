// Gmsh MSH 4.1 writer, ASCII or binary, written from the format's
// description in the Gmsh reference manual ("MSH file format").
//
// Layout: every region attribute is one volume (an elementary entity of
// dimension 3) in one volume physical group; every facet marker is one
// surface entity in one surface physical group; entity tag = physical tag,
// so the two numberings never disagree. Simulation codes (dolfinx's gmshio,
// meshio's "gmsh:physical", Gmsh itself when it saves) keep only elements
// that belong to a physical group, so every element gets one, also without
// regions or markers ("domain", "boundary"). Element tags keep the result's
// numbering: tet t is element t + 1, constrained face f element nt + f + 1;
// node i is node i + 1. Tets are written right-handed (kRightHandedTet),
// as Gmsh's reference element is. All nodes sit in one block on the first volume:
// readers rebuild element-to-node links from the tags, not from that block.
//
// Binary files hold the same values in the machine's byte order (the int 1
// after the version line tells readers which): counts and node/element tags
// as 8-byte size_t, entity and physical tags and element types as 4-byte
// int, coordinates as double. $PhysicalNames stays text, as the format says.
#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "write_common.hpp"

namespace cdt3d {
namespace {

using io::n_faces;
using io::n_points;
using io::n_tets;
using io::Out;

// One physical group and its one entity: a tag, a name, the element indices
// (tets or faces) and their bounding box.
struct Group {
  int64_t tag = 0;
  std::string name;
  std::vector<uint32_t> elements;
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
};

// The shortest %g text that reads back to `v` (a group's name shows the
// attribute as the input wrote it: "region 2", not "region 2.0000000000000000").
std::string shortest(double v) {
  char buf[40];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

// A total order on attributes, so that sorting and searching are well
// defined for every double: -0 counts as 0 and all NaNs as one value (the
// readers reject non-finite region attributes; this only keeps the writer
// total).
uint64_t order_key(double a) {
  if (a == 0) a = 0;
  if (std::isnan(a)) a = std::numeric_limits<double>::quiet_NaN();
  uint64_t bits;
  std::memcpy(&bits, &a, sizeof bits);
  return (bits >> 63) ? ~bits : bits | (uint64_t{1} << 63);
}

// Renumbers the groups 1..n when their own tags do not fit Gmsh's int tags.
void fit_tags(std::vector<Group>& groups) {
  for (const Group& g : groups)
    if (g.tag < 1 || g.tag > std::numeric_limits<int32_t>::max()) {
      for (size_t k = 0; k < groups.size(); ++k) groups[k].tag = static_cast<int64_t>(k) + 1;
      return;
    }
}

// Volume groups, one per distinct region attribute in increasing order. The
// tag is the attribute itself when every attribute is a positive integer
// (regions 1 and 2 of a .poly stay 1 and 2), else 1..n in that order.
std::vector<Group> volume_groups(const TetMeshData& m) {
  const size_t nt = n_tets(m);
  std::vector<Group> groups;
  if (!io::has_attributes(m)) {
    groups.push_back({1, "domain", {}});
    for (size_t t = 0; t < nt; ++t) groups[0].elements.push_back(static_cast<uint32_t>(t));
    return groups;
  }
  std::vector<uint64_t> keys(nt);
  for (size_t t = 0; t < nt; ++t) keys[t] = order_key(m.tet_attributes[t]);
  std::vector<uint64_t> distinct = keys;
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  groups.resize(distinct.size());
  bool natural = true;
  for (size_t t = 0; t < nt; ++t) {
    const size_t k = static_cast<size_t>(
        std::lower_bound(distinct.begin(), distinct.end(), keys[t]) - distinct.begin());
    Group& g = groups[k];
    if (g.name.empty()) {
      const double a = m.tet_attributes[t] == 0 ? 0.0 : m.tet_attributes[t];
      g.name = "region " + shortest(a);
      const bool integer = a >= 1 && a <= std::numeric_limits<int32_t>::max() && a == std::floor(a);
      natural = natural && integer;
      g.tag = integer ? static_cast<int64_t>(a) : 0;
    }
    g.elements.push_back(static_cast<uint32_t>(t));
  }
  if (!natural)
    for (size_t k = 0; k < groups.size(); ++k) groups[k].tag = static_cast<int64_t>(k) + 1;
  return groups;
}

// The input's name of a marker (its text made safe inside the quotes of
// $PhysicalNames), else "marker M".
std::string marker_name(const TetMeshData& m, int marker) {
  for (const auto& [known, name] : m.marker_names) {
    if (known != marker || name.empty()) continue;
    std::string safe = name;
    for (char& c : safe)
      if (c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20) c = '_';
    return safe;
  }
  return "marker " + std::to_string(marker);
}

// Surface groups, one per distinct facet marker in increasing order: tag =
// marker when it is positive; markers <= 0 take the tags after the largest
// positive marker, in increasing order (marker 0 of an STL surface becomes
// tag 1 when it is the only one).
std::vector<Group> surface_groups(const TetMeshData& m) {
  const size_t nf = n_faces(m);
  std::vector<Group> groups;
  if (nf == 0) return groups;
  if (!io::has_markers(m)) {
    groups.push_back({1, "boundary", {}});
    for (size_t f = 0; f < nf; ++f) groups[0].elements.push_back(static_cast<uint32_t>(f));
    return groups;
  }
  std::vector<int32_t> distinct(m.face_markers.begin(), m.face_markers.end());
  std::sort(distinct.begin(), distinct.end());
  distinct.erase(std::unique(distinct.begin(), distinct.end()), distinct.end());
  groups.resize(distinct.size());
  int64_t next = std::max<int64_t>(0, distinct.back()) + 1;
  for (size_t k = 0; k < distinct.size(); ++k) {
    groups[k].tag = distinct[k] > 0 ? distinct[k] : next++;
    groups[k].name = marker_name(m, distinct[k]);
  }
  fit_tags(groups);
  for (size_t f = 0; f < nf; ++f) {
    const size_t k = static_cast<size_t>(
        std::lower_bound(distinct.begin(), distinct.end(), m.face_markers[f]) - distinct.begin());
    groups[k].elements.push_back(static_cast<uint32_t>(f));
  }
  return groups;
}

// Extends g's bounding box by point p (the first point sets it).
void extend(Group& g, const double* p, bool& first) {
  for (int c = 0; c < 3; ++c) {
    g.lo[c] = first ? p[c] : std::min(g.lo[c], p[c]);
    g.hi[c] = first ? p[c] : std::max(g.hi[c], p[c]);
  }
  first = false;
}

// The bounding box of g's elements (`arity` point ids each in `ids`).
void bound(Group& g, const TetMeshData& m, const std::vector<uint32_t>& ids, int arity) {
  bool first = true;
  for (uint32_t e : g.elements)
    for (int k = 0; k < arity; ++k)
      extend(g, &m.points[3 * size_t{ids[size_t{e} * arity + k]}], first);
}

// Values in the file's encoding: text separated by spaces, one record per
// line, or binary with nothing between them.
class MshOut {
 public:
  MshOut(bool binary, size_t reserve) : binary_(binary), o_(reserve) {}

  /// A count or a node/element tag (size_t in binary files).
  MshOut& size(uint64_t v) {
    if (binary_)
      o_.bin(v);
    else
      sep().u(v);
    return *this;
  }
  /// An entity or physical tag, a dimension or an element type (int).
  MshOut& tag(int64_t v) {
    if (binary_)
      o_.bin(static_cast<int32_t>(v));
    else
      sep().i(v);
    return *this;
  }
  MshOut& real(double v) {
    if (binary_)
      o_.bin(v);
    else
      sep().d(v);
    return *this;
  }
  /// Ends a record (a line in text files).
  MshOut& eol() {
    if (!binary_) o_.nl();
    first_ = true;
    return *this;
  }
  MshOut& text(const std::string& t) {
    o_.str(t);
    return *this;
  }
  /// Ends a section; binary data is followed by a line break first.
  MshOut& end(const char* section) {
    if (binary_) o_.nl();
    o_.str("$End").str(section).nl();
    return *this;
  }
  std::string take() { return o_.take(); }

 private:
  Out& sep() {
    if (!first_) o_.sp();
    first_ = false;
    return o_;
  }
  bool binary_;
  Out o_;
  bool first_ = true;
};

void write_entities(MshOut& o, const std::vector<Group>& surfaces,
                    const std::vector<Group>& volumes) {
  o.text("$Entities\n");
  o.size(0).size(0).size(surfaces.size()).size(volumes.size()).eol();
  for (const std::vector<Group>* list : {&surfaces, &volumes})
    for (const Group& g : *list) {
      o.tag(g.tag);
      for (double c : g.lo) o.real(c);
      for (double c : g.hi) o.real(c);
      // One physical tag; no bounding entities (the mesh has no geometry).
      o.size(1).tag(g.tag).size(0).eol();
    }
  o.end("Entities");
}

void write_nodes(MshOut& o, const TetMeshData& m, int64_t host_volume) {
  const size_t np = n_points(m);
  o.text("$Nodes\n");
  o.size(np > 0 ? 1 : 0).size(np).size(np > 0 ? 1 : 0).size(np).eol();
  if (np > 0) {
    o.tag(3).tag(host_volume).tag(0).size(np).eol();
    for (size_t p = 0; p < np; ++p) o.size(p + 1).eol();
    for (size_t p = 0; p < np; ++p)
      o.real(m.points[3 * p]).real(m.points[3 * p + 1]).real(m.points[3 * p + 2]).eol();
  }
  o.end("Nodes");
}

// Gmsh element types: 4 is the 4-node tetrahedron, 2 the 3-node triangle.
constexpr int kMshTetrahedron = 4, kMshTriangle = 2;

void write_elements(MshOut& o, const TetMeshData& m, const std::vector<Group>& surfaces,
                    const std::vector<Group>& volumes) {
  const size_t nt = n_tets(m), nf = n_faces(m);
  size_t blocks = 0;
  for (const std::vector<Group>* list : {&volumes, &surfaces})
    for (const Group& g : *list) blocks += g.elements.empty() ? 0 : 1;
  o.text("$Elements\n");
  o.size(blocks).size(nt + nf).size(nt + nf > 0 ? 1 : 0).size(nt + nf).eol();
  for (const Group& g : volumes) {
    if (g.elements.empty()) continue;
    o.tag(3).tag(g.tag).tag(kMshTetrahedron).size(g.elements.size()).eol();
    for (uint32_t t : g.elements) {
      o.size(uint64_t{t} + 1);
      for (int k : io::kRightHandedTet) o.size(uint64_t{m.tets[4 * size_t{t} + k]} + 1);
      o.eol();
    }
  }
  for (const Group& g : surfaces) {
    if (g.elements.empty()) continue;
    o.tag(2).tag(g.tag).tag(kMshTriangle).size(g.elements.size()).eol();
    for (uint32_t f : g.elements) {
      o.size(nt + f + 1);
      for (int k = 0; k < 3; ++k) o.size(uint64_t{m.faces[3 * size_t{f} + k]} + 1);
      o.eol();
    }
  }
  o.end("Elements");
}

}  // namespace

std::string write_msh(const TetMeshData& m, bool binary) {
  std::vector<Group> volumes = volume_groups(m), surfaces = surface_groups(m);
  for (size_t k = 1; k < volumes.size(); ++k) bound(volumes[k], m, m.tets, 4);
  for (Group& g : surfaces) bound(g, m, m.faces, 3);
  // The first volume holds every node: its box is theirs.
  const size_t np = n_points(m), nt = n_tets(m), nf = n_faces(m);
  bool first = true;
  for (size_t p = 0; p < np; ++p) extend(volumes.front(), &m.points[3 * p], first);

  MshOut o(binary,
           512 + np * (binary ? 32 : 64) + nt * (binary ? 40 : 48) + nf * (binary ? 32 : 40));
  o.text("$MeshFormat\n");
  if (binary) {
    o.text("4.1 1 8\n").tag(1);
  } else {
    o.text("4.1 0 8\n");
  }
  o.end("MeshFormat");
  o.text("$PhysicalNames\n" + std::to_string(volumes.size() + surfaces.size()) + "\n");
  for (const std::vector<Group>* list : {&surfaces, &volumes})
    for (const Group& g : *list)
      o.text(std::to_string(list == &volumes ? 3 : 2) + " " + std::to_string(g.tag) + " \"" +
             g.name + "\"\n");
  o.text("$EndPhysicalNames\n");
  write_entities(o, surfaces, volumes);
  write_nodes(o, m, volumes.front().tag);
  write_elements(o, m, surfaces, volumes);
  return o.take();
}

}  // namespace cdt3d
