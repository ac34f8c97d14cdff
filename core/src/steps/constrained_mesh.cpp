// The carved CDT as refinement and the improvement pass edit it
// (constrained_mesh.hpp).
#include "constrained_mesh.hpp"

#include <algorithm>
#include <string>
#include <utility>

#include "predicates.hpp"
#include "stats.hpp"

namespace cdt3d {

namespace {

// Bound on the tets an edge rotation visits before giving up (a broken
// mesh; never reached on a valid one).
constexpr size_t kMaxRing = 1u << 20;

}  // namespace

void EdgeMap::set(uint64_t key, uint32_t value) {
  if (2 * (size_ + 1) > keys_.size()) grow();
  size_t i = slot(key);
  while (keys_[i] != kEmpty && keys_[i] != key) i = (i + 1) & mask_;
  if (keys_[i] == kEmpty) ++size_;
  keys_[i] = key;
  values_[i] = value;
}

void EdgeMap::erase(uint64_t key) {
  if (keys_.empty()) return;
  size_t i = slot(key);
  while (keys_[i] != key) {
    if (keys_[i] == kEmpty) return;
    i = (i + 1) & mask_;
  }
  // Backward shift: move later entries of the probe run into the hole when
  // their home slot does not lie (cyclically) between the hole and them.
  for (size_t j = (i + 1) & mask_; keys_[j] != kEmpty; j = (j + 1) & mask_) {
    const size_t home = slot(keys_[j]);
    if (((j - home) & mask_) >= ((j - i) & mask_)) {
      keys_[i] = keys_[j];
      values_[i] = values_[j];
      i = j;
    }
  }
  keys_[i] = kEmpty;
  --size_;
}

void EdgeMap::grow() {
  std::vector<uint64_t> keys;
  std::vector<uint32_t> values;
  keys.swap(keys_);
  values.swap(values_);
  const size_t capacity = keys.empty() ? 64 : 2 * keys.size();
  keys_.assign(capacity, kEmpty);
  values_.assign(capacity, 0);
  mask_ = capacity - 1;
  shift_ = 64;
  for (size_t c = capacity; c > 1; c >>= 1) --shift_;
  size_ = 0;
  for (size_t i = 0; i < keys.size(); ++i)
    if (keys[i] != kEmpty) set(keys[i], values[i]);
}

TetId ConstrainedMesh::new_tet() {
  const TetId t = m.alloc_tet();
  sync_slots();
  for (int i = 0; i < 4; ++i) hfc[4 * static_cast<size_t>(t) + i] = kNoTag;
  return t;
}

void ConstrainedMesh::sync_slots() {
  if (hfc.size() < 4 * m.num_tet_slots()) {
    hfc.resize(4 * m.num_tet_slots(), kNoTag);
    attr.resize(m.num_tet_slots(), 0);
  }
}

bool ConstrainedMesh::replace_region(const std::vector<TetId>& old,
                                     const std::vector<std::array<VertexId, 4>>& fresh,
                                     std::vector<TetId>& created) {
  const double attribute = attr[old[0]];
  for (TetId t : old)
    if (attr[t] != attribute) return false;
  outer_.clear();
  for (TetId t : old)
    for (int i = 0; i < 4; ++i) {
      const HalfFace hf = make_hf(t, i);
      const HalfFace nb = m.adjacent(hf);
      if (nb != kNoHalfFace && std::find(old.begin(), old.end(), hf_tet(nb)) != old.end()) continue;
      if (tag(hf) != kNoTag) outer_.push_back({sorted_triangle(face_of(hf)), tag(hf)});
    }
  std::sort(outer_.begin(), outer_.end());
  created.clear();
  if (!m.replace_tets(old.data(), old.size(), fresh.data(), fresh.size(), &created)) return false;
  sync_slots();
  for (TetId t : created) {
    attr[t] = attribute;
    for (int i = 0; i < 4; ++i) {
      const HalfFace hf = make_hf(t, i);
      const auto key = sorted_triangle(face_of(hf));
      const auto it = std::lower_bound(outer_.begin(), outer_.end(), std::make_pair(key, uint32_t(0)));
      hfc[hf] = it != outer_.end() && it->first == key ? it->second : kNoTag;
    }
  }
  return true;
}

void ConstrainedMesh::drop_last_vertex() {
  m.coords.resize(m.coords.size() - 3);
  m.vkind.pop_back();
  m.vtet.pop_back();
  where.pop_back();
  parent.pop_back();
}

VertexId ConstrainedMesh::new_vertex(const double* p, Where w, int64_t parent_id) {
  const VertexId v = m.add_vertex(p, kVertexSteiner);
  where.push_back(w);
  parent.push_back(parent_id);
  return v;
}

Status ConstrainedMesh::build(const Plc& plc, const Result& res) {
  const TetMeshData& md = res.mesh;
  const size_t nv = md.points.size() / 3, nt = md.tets.size() / 4;
  facet_drop.assign(plc.facets.size(), -1);
  for (size_t f = 0; f < plc.facets.size(); ++f) {
    const Vec3 n = newell_normal(plc, plc.facets[f].loops[0]);
    facet_drop[f] = static_cast<int8_t>(largest_axis(n.x, n.y, n.z));
  }
  old_points = nv;
  m.reserve(nv, nt);
  for (size_t v = 0; v < nv; ++v) m.add_vertex(&md.points[3 * v], kVertexInput);
  where.assign(nv, Where::Input);
  parent.assign(nv, -1);
  for (size_t i = 0; i < res.steiner_kind.size(); ++i) {
    const size_t v = res.input_points + i;
    if (v >= nv) break;
    const SteinerKind k = res.steiner_kind[i];
    where[v] = k == SteinerKind::Segment ? Where::Segment
                : k == SteinerKind::Facet ? Where::Facet
                                          : Where::Volume;
    parent[v] = res.steiner_parent[i];
  }
  // Tets, then their adjacency by matching sorted face keys.
  std::vector<std::pair<std::array<VertexId, 3>, HalfFace>> keys;
  keys.reserve(4 * nt);
  for (size_t k = 0; k < nt; ++k) {
    const TetId t = new_tet();
    const uint32_t* v = &md.tets[4 * k];
    m.set_tet(t, v[0], v[1], v[2], v[3]);
    attr[t] = md.tet_attributes.size() == nt ? md.tet_attributes[k] : 0;
    for (int i = 0; i < 4; ++i) {
      m.set_vertex_tet(v[i], t);
      const HalfFace hf = make_hf(t, i);
      keys.push_back({sorted_triangle(face_of(hf)), hf});
    }
  }
  std::sort(keys.begin(), keys.end());
  for (size_t i = 0; i < keys.size();) {
    if (i + 1 < keys.size() && keys[i + 1].first == keys[i].first) {
      if (i + 2 < keys.size() && keys[i + 2].first == keys[i].first)
        return make_error(ErrorCode::Internal, "Refinement: a face is shared by three tets.");
      m.glue(keys[i].second, keys[i + 1].second);
      i += 2;
    } else {
      m.open_face(keys[i].second);
      ++i;
    }
  }
  // Constrained faces; open faces that are no facet bound a kept hull.
  facet_side.assign(plc.facets.size(), 0);
  for (size_t i = 0; i < md.faces.size() / 3; ++i) {
    const std::array<VertexId, 3> f = {md.faces[3 * i], md.faces[3 * i + 1], md.faces[3 * i + 2]};
    const uint32_t facet = res.face_facet[i];
    auto it = std::lower_bound(keys.begin(), keys.end(), std::make_pair(sorted_triangle(f), HalfFace(0)));
    for (; it != keys.end() && it->first == sorted_triangle(f); ++it) hfc[it->second] = facet + 1;
    if (facet < facet_side.size() && facet_side[facet] == 0)
      facet_side[facet] = static_cast<int8_t>(
          pred::orient2d_projected(pt(f[0]), pt(f[1]), pt(f[2]), facet_axis(facet + 1, f)));
  }
  tag_hull_planes(keys);
  for (size_t i = 0; i < res.edge_segment.size(); ++i)
    subseg.set(edge_key(res.edges[2 * i], res.edges[2 * i + 1]), res.edge_segment[i]);
  return Status::success();
}

// The open faces that are no facet (a kept hull), tagged per plane: a flood
// fill across their edges between exactly coplanar faces (exact orient3d).
void ConstrainedMesh::tag_hull_planes(
    const std::vector<std::pair<std::array<VertexId, 3>, HalfFace>>& keys) {
  std::vector<HalfFace> hull;
  for (const auto& k : keys)
    if (m.adjacent(k.second) == kNoHalfFace && hfc[k.second] == kNoTag) hull.push_back(k.second);
  if (hull.empty()) return;
  std::vector<std::pair<uint64_t, uint32_t>> edges;  // edge -> index into hull
  for (uint32_t i = 0; i < hull.size(); ++i) {
    const auto f = face_of(hull[i]);
    for (int k = 0; k < 3; ++k) edges.push_back({edge_key(f[k], f[(k + 1) % 3]), i});
  }
  std::sort(edges.begin(), edges.end());
  std::vector<uint32_t> plane(hull.size(), kNoTag);
  std::vector<uint32_t> stack;
  uint32_t planes = 0;
  for (uint32_t seed = 0; seed < hull.size(); ++seed) {
    if (plane[seed] != kNoTag) continue;
    const uint32_t tag = kHullTag + planes++;
    plane[seed] = tag;
    const auto s = face_of(hull[seed]);
    stack.assign(1, seed);
    while (!stack.empty()) {
      const uint32_t i = stack.back();
      stack.pop_back();
      const auto f = face_of(hull[i]);
      for (int k = 0; k < 3; ++k) {
        const uint64_t key = edge_key(f[k], f[(k + 1) % 3]);
        auto it = std::lower_bound(edges.begin(), edges.end(), std::make_pair(key, 0u));
        for (; it != edges.end() && it->first == key; ++it) {
          const uint32_t j = it->second;
          if (plane[j] != kNoTag) continue;
          const auto g = face_of(hull[j]);
          bool coplanar = true;
          for (VertexId v : g) coplanar = coplanar && pred::orient3d(pt(s[0]), pt(s[1]), pt(s[2]), pt(v)) == 0;
          if (!coplanar) continue;
          plane[j] = tag;
          stack.push_back(j);
        }
      }
    }
  }
  for (uint32_t i = 0; i < hull.size(); ++i) hfc[hull[i]] = plane[i];
}

int ConstrainedMesh::facet_axis(uint32_t tag, const std::array<VertexId, 3>& v) const {
  if (!is_hull_tag(tag) && tag != kNoTag && tag - 1 < facet_drop.size() && facet_drop[tag - 1] >= 0)
    return facet_drop[tag - 1];
  return projection_axis(pt(v[0]), pt(v[1]), pt(v[2]));
}

void ConstrainedMesh::write(const Plc& plc, Result& res) const {
  TetMeshData& md = res.mesh;
  const size_t nv = m.num_vertices();
  md.points = m.coords;
  const bool attributes = !md.tet_attributes.empty();
  md.tets.clear();
  md.tet_attributes.clear();
  md.faces.clear();
  md.face_markers.clear();
  res.face_facet.clear();
  for (TetId t = 0; t < m.num_tet_slots(); ++t) {
    if (m.is_dead(t)) continue;
    const VertexId* v = m.tet_vertices(t);
    md.tets.insert(md.tets.end(), v, v + 4);
    if (attributes) md.tet_attributes.push_back(attr[t]);
  }
  for (TetId t = 0; t < m.num_tet_slots(); ++t) {
    if (m.is_dead(t)) continue;
    for (int i = 0; i < 4; ++i) {
      const HalfFace hf = make_hf(t, i);
      const uint32_t g = tag(hf);
      if (g == kNoTag || is_hull_tag(g)) continue;
      const HalfFace nb = m.adjacent(hf);
      if (nb != kNoHalfFace && hf_tet(nb) < t) continue;  // listed from the other side
      std::array<VertexId, 3> f = face_of(hf);
      const uint32_t facet = g - 1;
      // The faces of a facet keep one orientation in its plane (validate()).
      const int side = facet < facet_side.size() ? facet_side[facet] : 0;
      if (side != 0 &&
          pred::orient2d_projected(pt(f[0]), pt(f[1]), pt(f[2]), facet_axis(g, f)) != side)
        std::swap(f[1], f[2]);
      md.faces.insert(md.faces.end(), f.begin(), f.end());
      res.face_facet.push_back(facet);
      md.face_markers.push_back(facet < plc.facets.size() ? plc.facets[facet].marker : 0);
    }
  }
  std::vector<std::array<uint32_t, 3>> edges;
  edges.reserve(subseg.size());
  subseg.for_each([&edges](uint64_t key, uint32_t segment) {
    edges.push_back({segment, static_cast<uint32_t>(key >> 32), static_cast<uint32_t>(key)});
  });
  std::sort(edges.begin(), edges.end());
  res.edges.clear();
  res.edge_segment.clear();
  for (const auto& e : edges) {
    res.edges.push_back(e[1]);
    res.edges.push_back(e[2]);
    res.edge_segment.push_back(e[0]);
  }
  for (size_t v = old_points; v < nv; ++v) {
    const Where w = where[v];
    res.steiner_kind.push_back(w == Where::Segment ? SteinerKind::Segment
                                : w == Where::Facet ? SteinerKind::Facet
                                                    : SteinerKind::Volume);
    res.steiner_parent.push_back(parent[v]);
  }
  size_statistics(res);
}

// The tets around edge xy, starting at t0 (which has it): rotates across the
// faces through xy one way until the ring closes or meets the domain
// boundary, then the other way from t0. False on a broken mesh.
bool ConstrainedMesh::edge_ring(TetId t0, VertexId x, VertexId y, std::vector<TetId>& out,
                                bool* closed) const {
  if (closed) *closed = false;
  out.clear();
  out.push_back(t0);
  const VertexId* v0 = m.tet_vertices(t0);
  VertexId w[2];
  for (int i = 0, k = 0; i < 4; ++i)
    if (v0[i] != x && v0[i] != y) {
      if (k == 2) return false;
      w[k++] = v0[i];
    }
  for (int dir = 0; dir < 2; ++dir) {
    TetId t = t0;
    VertexId came = w[dir];  // we "entered" t across the face opposite this vertex
    for (size_t steps = 0;; ++steps) {
      if (steps > kMaxRing) return false;
      const VertexId* tv = m.tet_vertices(t);
      int exit_pos = -1;
      for (int i = 0; i < 4; ++i)
        if (tv[i] != x && tv[i] != y && tv[i] != came) exit_pos = i;
      if (exit_pos < 0) return false;
      const HalfFace nb = m.adjacent(make_hf(t, exit_pos));
      if (nb == kNoHalfFace) break;
      const TetId u = hf_tet(nb);
      if (u == t0) {  // closed: every tet seen, in ring order
        if (closed) *closed = dir == 0;
        return dir == 0;
      }
      came = m.opposite(nb);
      t = u;
      out.push_back(t);
    }
  }
  return true;
}

}  // namespace cdt3d
