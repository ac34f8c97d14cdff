// Removal of a vertex from a Delaunay tetrahedralization (vertex_removal.hpp).
#include "vertex_removal.hpp"

#include <algorithm>

#include "predicates.hpp"

namespace cdt3d {

bool VertexRemover::is_link_face(const std::array<uint32_t, 3>& key) const {
  auto it = std::lower_bound(faces_.begin(), faces_.end(), key,
                             [](const LinkFace& x, const std::array<uint32_t, 3>& k) { return x.key < k; });
  return it != faces_.end() && it->key == key;
}

bool VertexRemover::plan(VertexId v) {
  planned_ = kNone;
  fresh_.clear();
  mesh_.vertex_star(v, star_);
  if (star_.empty()) return false;
  faces_.clear();
  link_.clear();
  for (TetId t : star_) {
    if (mesh_.is_ghost(t)) return false;
    const int iv = mesh_.index_in_tet(t, v);
    const VertexId* w = mesh_.tet_vertices(t);
    faces_.push_back({{0, 0, 0}, w[kFaceVertex[iv][0]], w[kFaceVertex[iv][1]], w[kFaceVertex[iv][2]]});
    for (int j = 0; j < 4; ++j)
      if (j != iv) link_.push_back(w[j]);
  }
  std::sort(link_.begin(), link_.end());
  link_.erase(std::unique(link_.begin(), link_.end()), link_.end());
  auto local = [&](VertexId g) {
    return static_cast<uint32_t>(std::lower_bound(link_.begin(), link_.end(), g) - link_.begin());
  };
  xyz_.clear();
  for (VertexId u : link_) xyz_.insert(xyz_.end(), mesh_.point(u), mesh_.point(u) + 3);
  // Points go in in id order and are perturbed by their index, which is
  // their rank among the global ids: the same perturbation as the mesh's.
  if (!link_dt_.build(xyz_.data(), link_.size()).ok()) return false;
  TetMesh& tmp = link_dt_.mesh();
  for (LinkFace& f : faces_) {
    f.key = {local(f.a), local(f.b), local(f.c)};
    std::sort(f.key.begin(), f.key.end());
  }
  std::sort(faces_.begin(), faces_.end(), [](const LinkFace& x, const LinkFace& y) { return x.key < y.key; });
  for (size_t k = 0; k + 1 < faces_.size(); ++k)
    if (faces_[k].key == faces_[k + 1].key) return false;
  // Seeds: the tet of DT(link) on the inner side of each link face (the side
  // of v: orient3d(a, b, c, x) > 0 for a face counterclockwise from outside).
  inside_.clear();
  for (const LinkFace& f : faces_) {
    const HalfFace hf = tmp.find_face(f.key[0], f.key[1], f.key[2]);
    if (hf == kNone) return false;
    TetId t = kNone;
    for (HalfFace side : {hf, tmp.adjacent(hf)}) {
      const VertexId d = tmp.opposite(side);
      if (d != kInfinite &&
          pred::orient3d(mesh_.point(f.a), mesh_.point(f.b), mesh_.point(f.c), mesh_.point(link_[d])) > 0)
        t = hf_tet(side);
    }
    if (t == kNone) return false;
    inside_.push_back(t);
  }
  // (find_face uses the stamps too: mark only now.)
  std::sort(inside_.begin(), inside_.end());
  inside_.erase(std::unique(inside_.begin(), inside_.end()), inside_.end());
  const uint32_t epoch = tmp.next_epoch();
  for (TetId t : inside_) tmp.stamp(t, epoch);
  // Flood fill without crossing link faces.
  for (size_t k = 0; k < inside_.size(); ++k) {
    const TetId t = inside_[k];
    for (int i = 0; i < 4; ++i) {
      std::array<uint32_t, 3> key = {tmp.vertex(t, kFaceVertex[i][0]), tmp.vertex(t, kFaceVertex[i][1]),
                                     tmp.vertex(t, kFaceVertex[i][2])};
      std::sort(key.begin(), key.end());
      if (is_link_face(key)) continue;
      const TetId n = tmp.neighbor(t, i);
      if (tmp.is_ghost(n)) return false;
      if (!tmp.stamped(n, epoch)) {
        tmp.stamp(n, epoch);
        inside_.push_back(n);
      }
    }
  }
  for (TetId t : inside_) {
    const VertexId* w = tmp.tet_vertices(t);
    fresh_.push_back({link_[w[0]], link_[w[1]], link_[w[2]], link_[w[3]]});
  }
  planned_ = v;
  return true;
}

bool VertexRemover::commit(std::vector<TetId>* created) {
  if (created) created->clear();
  if (planned_ == kNone) return false;
  const VertexId v = planned_;
  planned_ = kNone;
  // replace_tets checks that the fresh tets meet every link face once.
  old_.assign(star_.rbegin(), star_.rend());
  if (!mesh_.replace_tets(old_.data(), old_.size(), fresh_.data(), fresh_.size(), created)) return false;
  mesh_.set_vertex_tet(v, kNone);
  mesh_.vkind[v] = kVertexNotInserted;
  return true;
}

}  // namespace cdt3d
