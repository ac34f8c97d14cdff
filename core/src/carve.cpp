// Carving: inside/outside marking from the constrained faces, volume holes,
// region attributes, exterior removal (see carve.hpp for the rules).
#include "carve.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "delaunay.hpp"
#include "status.hpp"

namespace cdt3d {
namespace {

// The first loop edge (facet order, loop order) used by exactly one facet.
bool open_edge(const Plc& plc, VertexId& a, VertexId& b, int64_t& facet) {
  struct Use {
    VertexId lo, hi;
    uint32_t facet;
  };
  std::vector<Use> uses;
  for (uint32_t f = 0; f < plc.facets.size(); ++f)
    for (const auto& L : plc.facets[f].loops)
      for (size_t i = 0; i < L.size(); ++i) {
        const VertexId p = L[i], q = L[(i + 1) % L.size()];
        uses.push_back({std::min(p, q), std::max(p, q), f});
      }
  auto less = [](const Use& x, const Use& y) {
    return x.lo != y.lo ? x.lo < y.lo : x.hi != y.hi ? x.hi < y.hi : x.facet < y.facet;
  };
  std::vector<Use> sorted = uses;
  std::sort(sorted.begin(), sorted.end(), less);
  auto facets_on = [&](VertexId lo, VertexId hi) {
    auto it = std::lower_bound(sorted.begin(), sorted.end(), Use{lo, hi, 0}, less);
    size_t n = 0;
    uint32_t last = kNone;
    for (; it != sorted.end() && it->lo == lo && it->hi == hi; ++it)
      if (it->facet != last) ++n, last = it->facet;
    return n;
  };
  for (uint32_t f = 0; f < plc.facets.size(); ++f)
    for (const auto& L : plc.facets[f].loops)
      for (size_t i = 0; i < L.size(); ++i) {
        const VertexId p = L[i], q = L[(i + 1) % L.size()];
        if (facets_on(std::min(p, q), std::max(p, q)) == 1) {
          a = p, b = q, facet = f;
          return true;
        }
      }
  return false;
}

}  // namespace

Status carve(const Plc& plc, TetMesh& mesh, const Subfaces& subfaces, bool keep_convex_hull,
             CarveResult& out) {
  out = CarveResult();
  const size_t slots = mesh.num_tet_slots();

  // Constrained half-faces: the subface index on both sides.
  std::vector<uint32_t> hf_sub(4 * slots, kNone);
  std::vector<HalfFace> sub_hf(subfaces.tri.size(), kNone);
  for (size_t i = 0; i < subfaces.tri.size(); ++i) {
    const auto& s = subfaces.tri[i];
    const HalfFace hf = mesh.find_face(s[0], s[1], s[2]);
    sub_hf[i] = hf;
    if (hf == kNone) {
      return make_error(ErrorCode::Internal,
                        "Subface (" + std::to_string(s[0]) + ", " + std::to_string(s[1]) + ", " +
                            std::to_string(s[2]) + ") is not a face of the mesh.")
          .facet(i < subfaces.facet.size() ? subfaces.facet[i] : -1);
    }
    if (hf_sub[hf] != kNone) continue;  // listed twice: the first one counts
    hf_sub[hf] = static_cast<uint32_t>(i);
    hf_sub[mesh.adjacent(hf)] = static_cast<uint32_t>(i);
  }

  // Regions: connected across unconstrained faces, numbered in slot order.
  std::vector<uint32_t> region(slots, kNone);
  std::vector<uint32_t> region_first;  // smallest slot per region
  std::vector<TetId> stack;
  for (TetId t0 = 0; t0 < slots; ++t0) {
    if (mesh.is_dead(t0) || region[t0] != kNone) continue;
    const uint32_t r = static_cast<uint32_t>(region_first.size());
    region_first.push_back(t0);
    region[t0] = r;
    stack.push_back(t0);
    while (!stack.empty()) {
      const TetId t = stack.back();
      stack.pop_back();
      for (int i = 0; i < 4; ++i) {
        const HalfFace hf = make_hf(t, i);
        if (hf_sub[hf] != kNone) continue;
        const TetId n = hf_tet(mesh.adjacent(hf));
        if (region[n] != kNone) continue;
        region[n] = r;
        stack.push_back(n);
      }
    }
  }
  const size_t nregions = region_first.size();
  std::vector<uint8_t> removed(nregions, 0);
  std::vector<uint8_t> has_real(nregions, 0);
  for (TetId t = 0; t < slots; ++t) {
    if (mesh.is_dead(t)) continue;
    if (mesh.is_ghost(t)) {
      if (!keep_convex_hull) removed[region[t]] = 1;
    } else {
      has_real[region[t]] = 1;
    }
  }

  // Volume holes and region points.
  Rng rng(0x63617276652d6c6fULL);
  TetId hint = kNone;
  auto region_of = [&](const Vec3& p) -> uint32_t {
    const double xyz[3] = {p.x, p.y, p.z};
    const Location loc = locate_point(mesh, xyz, hint, rng);
    if (loc.kind != LocateKind::InTet) return kNone;
    hint = loc.tet;
    return region[loc.tet];
  };
  for (const Vec3& h : plc.holes) {
    const uint32_t r = region_of(h);
    if (r != kNone) removed[r] = 1;
  }
  std::vector<uint8_t> has_attr(nregions, 0);
  std::vector<double> attr(nregions, 0.0);
  double largest = 0;
  for (const Region& rp : plc.regions) {
    if (std::isfinite(rp.attribute)) largest = std::max(largest, std::floor(rp.attribute));
    const uint32_t r = region_of(rp.point);
    if (r == kNone || has_attr[r]) continue;
    has_attr[r] = 1;
    attr[r] = rp.attribute;
  }
  double next = largest + 1;
  for (size_t r = 0; r < nregions; ++r) {
    if (removed[r] || !has_real[r]) continue;
    ++out.regions;
    if (!has_attr[r]) attr[r] = next++, has_attr[r] = 1;
  }

  // Kept tets and flags.
  std::vector<uint8_t> kept(slots, 0);
  for (TetId t = 0; t < slots; ++t) {
    if (mesh.is_dead(t)) continue;
    mesh.tflag[t] &= static_cast<uint8_t>(~(kTetInside | kTetOutside));
    if (!mesh.is_ghost(t) && !removed[region[t]]) {
      kept[t] = 1;
      mesh.tflag[t] |= kTetInside;
      out.tets.push_back(t);
      out.attribute.push_back(attr[region[t]]);
    } else {
      mesh.tflag[t] |= kTetOutside;
    }
  }
  if (out.tets.empty()) {
    VertexId a = kNone, b = kNone;
    int64_t facet = -1;
    if (open_edge(plc, a, b, facet)) {
      return make_error(ErrorCode::OpenBoundary,
                        "The surface does not enclose a volume; boundary edge (" +
                            std::to_string(a) + ", " + std::to_string(b) + ") of facet " +
                            std::to_string(facet) + " is open.")
          .facet(facet)
          .vertex(a);
    }
    return make_error(ErrorCode::OpenBoundary,
                      "The surface does not enclose a volume: every tetrahedron is outside "
                      "the surface or in a hole.");
  }

  // Constrained faces with a kept tet on at least one side.
  for (size_t i = 0; i < subfaces.tri.size(); ++i) {
    const auto& s = subfaces.tri[i];
    const HalfFace hf = sub_hf[i];
    if (hf_sub[hf] != i) continue;
    if (!kept[hf_tet(hf)] && !kept[hf_tet(mesh.adjacent(hf))]) continue;
    out.faces.push_back(s);
    out.face_facet.push_back(i < subfaces.facet.size() ? subfaces.facet[i] : kNone);
  }
  return Status::success();
}

}  // namespace cdt3d
