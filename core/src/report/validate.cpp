// cdt3d::validate: checks a Result against its PLC. Exact predicates for every
// combinatorial and geometric decision; floating-point sums with tolerances
// only for the area and volume comparisons, which are checks, never decisions.
//
// Checks, in the order run() makes them (the first violation is returned as
// ErrorCode::Internal):
//  1. Sizes and indices; the first input_points points are the PLC's points
//     (sizes).
//  2. Every tet is positively oriented: orient3d(v0, v1, v2, v3) > 0, the
//     convention of tet_mesh.hpp (v3 below the plane of v0 v1 v2 seen
//     counterclockwise from above; insphere(v0..v3, p) > 0 means p inside).
//  3. Every triangle is a face of at most two tets, which lie on opposite
//     sides of it (2 and 3: tets_and_faces).
//  4. Constrained faces: listed once, each a face of a tet. A face of exactly
//     one tet (the boundary of the kept domain) must be constrained, unless
//     the result kept the convex hull (detected: some boundary face is not
//     constrained); then the boundary must be locally convex at every edge
//     (a closed, connected, locally convex surface bounds a convex set)
//     (constrained_faces).
//  5. Segments: the ends and the Segment Steiner points of each segment,
//     sorted along it, are consecutive mesh edges. Checked for segments whose
//     vertices all belong to kept tets, and a missing piece is an error only
//     when its midpoint lies in a kept tet (the others lie outside the
//     domain) (segments; it builds the chains check 6 uses).
//  6. Facets: the faces of facet f use only vertices of f (its input vertices
//     and the PLC points and segments lying in it, found by triangulating the
//     input facet without Steiner points; Steiner points on those segments;
//     Facet Steiner points of f), are consistently oriented, and the edges of
//     the patch used once are subsegments of f's segments, every loop
//     subsegment being an edge of the patch. When every such patch boundary
//     edge is on a loop, the area must equal the facet's area; when the patch
//     ends on a segment inside the facet (the facet leaves the domain there),
//     the area may only be smaller. A facet without faces must lie outside
//     the kept tets (a point of it is strictly inside none) (facets).
//  7. No unconstrained face lies in a facet: its projection overlaps no
//     triangle of the facet, up to the slivers rounded Steiner points make
//     beside a subsegment (unconstrained_in_facets).
//  8. Volume: for closed results (no hull kept, every facet with faces either
//     entirely on the boundary with the domain on one side, or entirely
//     inside, single-loop facets), the tets' volume equals the volume the
//     boundary facets enclose (divergence theorem on the input loops)
//     (volume).
//  9. Constrained Delaunay: every face shared by two tets that is not
//     constrained is locally Delaunay: insphere of the opposite vertex <= 0
//     (exact, unperturbed; co-spherical allowed), unless four of its five
//     points are numerically flat (a flat tet flipped away, flat_flips.hpp)
//     (delaunay). Skipped when Result::delaunay is false (the improvement
//     pass of quality refinement, improve.hpp, trades it for angles).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <iterator>
#include <string>
#include <vector>

#include "geometry.hpp"
#include "predicates.hpp"
#include "status.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {
namespace {

using Tri3 = std::array<uint32_t, 3>;

// Area check (6): the faces' area sums and the input facet's differ by
// rounding in the sums (relative kAreaSumTolerance) and by Steiner points
// rounded to doubles, each at most a few ulps (kRoundingUlps ulps of the
// coordinate scale) off the facet, along the patch's perimeter.
constexpr double kAreaSumTolerance = 1e-9;
constexpr double kRoundingUlps = 64;
constexpr double kUlp = 2.2e-16;  // DBL_EPSILON (2.22e-16), to two digits
// Volume check (8): the tets' volume and the one the facets enclose are both
// sums of signed terms; they may differ by this much relative to the sum of
// the terms' magnitudes.
constexpr double kVolumeSumTolerance = 1e-8;

// A violated property: an internal error, since a valid run cannot produce
// one. The caller names the element with the builder's setters.
ErrorBuilder fail(const std::string& message) {
  return make_error(ErrorCode::Internal, "Validation: " + message);
}

std::string tri_name(const Tri3& t) {
  return "(" + std::to_string(t[0]) + ", " + std::to_string(t[1]) + ", " + std::to_string(t[2]) +
         ")";
}

struct FaceRec {
  Tri3 key;      // sorted vertex ids
  uint32_t tet;  // tet index in the result
  int face;      // position of the opposite vertex
};

class Validator {
 public:
  // face_facet and steiner_parent: the result's, or those of a result that
  // names input facets translated to the merged PLC's (validate()).
  Validator(const Plc& plc, const Result& r, const std::vector<uint32_t>& face_facet,
            const std::vector<int64_t>& steiner_parent)
      : plc_(plc), r_(r), m_(r.mesh), face_facet_(face_facet), steiner_parent_(steiner_parent) {}
  Status run();

 private:
  const double* pt(uint32_t v) const { return &m_.points[3 * static_cast<size_t>(v)]; }
  Tri3 tet_face(uint32_t t, int i) const {
    const uint32_t* w = &m_.tets[4 * static_cast<size_t>(t)];
    return {w[kFaceVertex[i][0]], w[kFaceVertex[i][1]], w[kFaceVertex[i][2]]};
  }
  double tri_area(const Tri3& t) const;
  bool is_edge(uint32_t a, uint32_t b) const {
    return std::binary_search(edges_.begin(), edges_.end(), edge_key(a, b));
  }
  int64_t segment_index(uint32_t a, uint32_t b) const {
    const std::array<VertexId, 2> k = {std::min(a, b), std::max(a, b)};
    auto it = std::lower_bound(segments_.begin(), segments_.end(), k);
    return it != segments_.end() && *it == k ? it - segments_.begin() : -1;
  }

  Status sizes();
  Status tets_and_faces();
  Status constrained_faces();
  Status facets();
  // The parts of facets(): facet f's input vertices and segments, its loop
  // and allowed edges, the faces' check, and the test of faceless facets.
  double facet_input(size_t f, const std::vector<uint32_t>& tris,
                     const std::vector<size_t>& input_tris);
  void facet_edges(size_t f, std::vector<uint64_t>& allowed_edges,
                   std::vector<uint64_t>& loop_edges) const;
  bool vertex_in_facet(uint32_t v, size_t f) const;
  Status facet_faces(size_t f, const std::vector<size_t>& faces, double area_in,
                     const std::vector<uint64_t>& allowed_edges,
                     const std::vector<uint64_t>& loop_edges);
  struct Probe {
    double p[3] = {0, 0, 0};
    uint32_t facet = 0;
  };
  Status probes_outside(std::vector<Probe>& probes) const;
  Status unconstrained_in_facets();
  // The parts of unconstrained_in_facets() (check 7).
  struct Membership {
    std::vector<std::vector<uint32_t>> seg_facets;    // per segment: facets it lies in
    std::vector<std::vector<uint32_t>> input_facets;  // per input point: its facets
    std::vector<std::vector<uint32_t>> segs_at;       // per input point: segments it ends
    std::vector<std::vector<size_t>> faces_of_facet;  // per facet: its constrained faces
    std::vector<std::array<uint32_t, 2>> subsegs;     // sorted (lower, higher)
    std::vector<uint32_t> one[3];                     // facets_of()'s buffers
  };
  void build_membership();
  const std::vector<uint32_t>& facets_of(uint32_t v, int slot);
  bool flat_in_facet(size_t i, uint32_t f);
  bool along_one_line(const Tri3& k) const;
  void project(uint32_t v, int drop, double out[2]) const;
  bool beyond_subsegment(const Tri3& k, uint32_t f, int drop) const;
  bool overlaps_facet(const Tri3& k, uint32_t f, int drop) const;
  bool overlaps_subfaces(const Tri3& k, uint32_t f, int drop) const;
  Status segments();
  Status volume();
  Status delaunay();
  bool flipped_for_flat_tet(const uint32_t* w, uint32_t e) const;
  bool in_some_tet(uint32_t a, uint32_t b) const;

  const Plc& plc_;
  const Result& r_;
  const TetMeshData& m_;
  const std::vector<uint32_t>& face_facet_;
  const std::vector<int64_t>& steiner_parent_;
  size_t np_ = 0, nt_ = 0, nf_ = 0;
  double scale_ = 0;  // largest |coordinate|
  std::vector<FaceRec> faces_;                // every tet face, sorted by key
  std::vector<uint64_t> edges_;               // every tet edge, sorted
  std::vector<uint8_t> in_tet_;               // per point: vertex of a tet
  std::vector<Tri3> constrained_;             // sorted keys of the constrained faces
  std::vector<uint32_t> boundary_;            // indices into faces_ of faces with one tet
  bool hull_kept_ = false;
  std::vector<std::array<VertexId, 2>> segments_;      // plc_segments order
  std::vector<std::vector<uint32_t>> chains_;          // per segment, sorted along it
  std::vector<uint32_t> face_tet_;                     // per constrained face: a tet index (face side)
  std::vector<uint8_t> face_two_;                      // per constrained face: two tets
  bool facets_closed_ = true;                          // volume check applies
  // Per input facet: its input vertices, the segments lying in it, its
  // triangulation without Steiner points, the axis its projection drops.
  std::vector<std::vector<uint32_t>> fverts_, fsegs_;
  std::vector<std::vector<Tri3>> ftris_;
  std::vector<int> fdrop_;
  Membership ms_;
};

double Validator::tri_area(const Tri3& t) const {
  const double* a = pt(t[0]);
  const double* b = pt(t[1]);
  const double* c = pt(t[2]);
  const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double x = u[1] * w[2] - u[2] * w[1], y = u[2] * w[0] - u[0] * w[2],
               z = u[0] * w[1] - u[1] * w[0];
  return 0.5 * std::sqrt(x * x + y * y + z * z);
}

Status Validator::sizes() {
  if (m_.points.size() % 3 != 0) return fail("the point array's size is not a multiple of 3.");
  if (m_.tets.size() % 4 != 0) return fail("the tet array's size is not a multiple of 4.");
  if (m_.faces.size() % 3 != 0) return fail("the face array's size is not a multiple of 3.");
  np_ = m_.points.size() / 3, nt_ = m_.tets.size() / 4, nf_ = m_.faces.size() / 3;
  if (r_.input_points != plc_.points.size() || np_ < r_.input_points)
    return fail("the result does not start with the PLC's points.");
  for (size_t i = 0; i < r_.input_points; ++i) {
    const Vec3& p = plc_.points[i];
    if (pt(static_cast<uint32_t>(i))[0] != p.x || pt(static_cast<uint32_t>(i))[1] != p.y ||
        pt(static_cast<uint32_t>(i))[2] != p.z)
      return fail("point " + std::to_string(i) + " differs from the PLC's point.")
          .vertex(static_cast<int64_t>(i));
  }
  const size_t ns = np_ - r_.input_points;
  if (r_.steiner_kind.size() != ns || steiner_parent_.size() != ns)
    return fail("steiner_kind and steiner_parent need one entry per Steiner point.");
  for (size_t i = 0; i < ns; ++i) {
    const SteinerKind k = r_.steiner_kind[i];
    const int64_t p = steiner_parent_[i];
    const int64_t v = static_cast<int64_t>(r_.input_points + i);
    if (k != SteinerKind::Segment && k != SteinerKind::Facet && k != SteinerKind::Volume)
      return fail("Steiner point " + std::to_string(v) + " has an unknown kind.").vertex(v);
    if (k == SteinerKind::Volume && p != -1)
      return fail("volume Steiner point " + std::to_string(v) + " has a parent.").vertex(v);
    if (k == SteinerKind::Facet && (p < 0 || static_cast<size_t>(p) >= plc_.facets.size()))
      return fail("facet Steiner point " + std::to_string(v) + " has no valid parent facet.")
          .vertex(v);
  }
  if (face_facet_.size() != nf_) return fail("face_facet needs one entry per face.");
  if (!m_.face_markers.empty() && m_.face_markers.size() != nf_)
    return fail("face_markers needs one entry per face.");
  if (!m_.tet_attributes.empty() && m_.tet_attributes.size() != nt_)
    return fail("tet_attributes needs one entry per tet.");
  for (uint32_t v : m_.tets)
    if (v >= np_) return fail("a tet uses point " + std::to_string(v) + ", which does not exist.");
  for (size_t i = 0; i < nf_; ++i) {
    for (int k = 0; k < 3; ++k)
      if (m_.faces[3 * i + k] >= np_)
        return fail("face " + std::to_string(i) + " uses a point that does not exist.");
    if (face_facet_[i] >= plc_.facets.size())
      return fail("face " + std::to_string(i) + " names facet " +
                  std::to_string(face_facet_[i]) + ", which does not exist.");
    if (!m_.face_markers.empty() && m_.face_markers[i] != plc_.facets[face_facet_[i]].marker)
      return fail("face " + std::to_string(i) + " has a marker other than its facet's.")
          .facet(face_facet_[i]);
  }
  for (double x : m_.points) scale_ = std::max(scale_, std::fabs(x));
  return Status::success();
}

Status Validator::tets_and_faces() {
  in_tet_.assign(np_, 0);
  faces_.clear();
  faces_.reserve(4 * nt_);
  edges_.clear();
  edges_.reserve(6 * nt_);
  for (uint32_t t = 0; t < nt_; ++t) {
    const uint32_t* w = &m_.tets[4 * static_cast<size_t>(t)];
    if (pred::orient3d(pt(w[0]), pt(w[1]), pt(w[2]), pt(w[3])) <= 0)
      return fail("tet " + std::to_string(t) + " (" + std::to_string(w[0]) + ", " +
                  std::to_string(w[1]) + ", " + std::to_string(w[2]) + ", " + std::to_string(w[3]) +
                  ") is not positively oriented.")
          .vertex(w[0]);
    for (int i = 0; i < 4; ++i) {
      in_tet_[w[i]] = 1;
      faces_.push_back({sorted_triangle(tet_face(t, i)), t, i});
      for (int j = i + 1; j < 4; ++j) edges_.push_back(edge_key(w[i], w[j]));
    }
  }
  std::sort(faces_.begin(), faces_.end(), [](const FaceRec& a, const FaceRec& b) {
    return a.key != b.key ? a.key < b.key : a.tet < b.tet;
  });
  std::sort(edges_.begin(), edges_.end());
  edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
  boundary_.clear();
  for (size_t i = 0; i < faces_.size();) {
    size_t j = i;
    while (j < faces_.size() && faces_[j].key == faces_[i].key) ++j;
    if (j - i > 2)
      return fail("face " + tri_name(faces_[i].key) + " belongs to " + std::to_string(j - i) +
                  " tets.")
          .vertex(faces_[i].key[0]);
    if (j - i == 2) {
      const FaceRec& a = faces_[i];
      const FaceRec& b = faces_[i + 1];
      const Tri3 f = tet_face(a.tet, a.face);
      const uint32_t d = m_.tets[4 * static_cast<size_t>(b.tet) + b.face];
      if (pred::orient3d(pt(f[0]), pt(f[1]), pt(f[2]), pt(d)) >= 0)
        return fail("tets " + std::to_string(a.tet) + " and " + std::to_string(b.tet) +
                    " overlap at face " + tri_name(a.key) + ".")
            .vertex(a.key[0]);
    } else {
      boundary_.push_back(static_cast<uint32_t>(i));
    }
    i = j;
  }
  return Status::success();
}

Status Validator::constrained_faces() {
  constrained_.resize(nf_);
  for (size_t i = 0; i < nf_; ++i)
    constrained_[i] = sorted_triangle({m_.faces[3 * i], m_.faces[3 * i + 1], m_.faces[3 * i + 2]});
  std::vector<Tri3> keys = constrained_;
  std::sort(keys.begin(), keys.end());
  for (size_t i = 0; i + 1 < keys.size(); ++i)
    if (keys[i] == keys[i + 1])
      return fail("constrained face " + tri_name(keys[i]) + " is listed twice.").vertex(keys[i][0]);
  face_tet_.assign(nf_, 0);
  face_two_.assign(nf_, 0);
  auto lower = [this](const Tri3& k) {
    return std::lower_bound(faces_.begin(), faces_.end(), k,
                            [](const FaceRec& a, const Tri3& b) { return a.key < b; });
  };
  for (size_t i = 0; i < nf_; ++i) {
    auto it = lower(constrained_[i]);
    if (it == faces_.end() || it->key != constrained_[i])
      return fail("constrained face " + tri_name(constrained_[i]) + " is not a face of a tet.")
          .facet(face_facet_[i])
          .vertex(constrained_[i][0]);
    face_tet_[i] = static_cast<uint32_t>(it - faces_.begin());
    face_two_[i] = (it + 1) != faces_.end() && (it + 1)->key == it->key;
  }
  // Boundary faces: constrained, or (hull kept) locally convex among themselves.
  std::vector<uint32_t> unconstrained;
  for (uint32_t b : boundary_)
    if (!std::binary_search(keys.begin(), keys.end(), faces_[b].key)) unconstrained.push_back(b);
  hull_kept_ = !unconstrained.empty();
  if (!hull_kept_) return Status::success();
  struct EdgeUse {
    uint64_t key;
    uint32_t face;  // index into boundary_
  };
  // Two unconstrained boundary faces are faces of the convex hull, so the
  // boundary is convex where they meet. (Where a constrained face meets the
  // hull it may be reflex: a hole point can empty a region that touches the
  // hull.)
  std::vector<EdgeUse> uses;
  for (uint32_t i = 0; i < boundary_.size(); ++i) {
    const Tri3& k = faces_[boundary_[i]].key;
    if (std::binary_search(keys.begin(), keys.end(), k)) continue;
    uses.push_back({edge_key(k[0], k[1]), i});
    uses.push_back({edge_key(k[1], k[2]), i});
    uses.push_back({edge_key(k[0], k[2]), i});
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& a, const EdgeUse& b) {
    return a.key != b.key ? a.key < b.key : a.face < b.face;
  });
  for (size_t i = 0; i < uses.size();) {
    size_t j = i;
    while (j < uses.size() && uses[j].key == uses[i].key) ++j;
    for (size_t x = i; x < j; ++x) {
      const FaceRec& F = faces_[boundary_[uses[x].face]];
      const Tri3 f = tet_face(F.tet, F.face);  // counterclockwise from outside
      for (size_t y = i; y < j; ++y) {
        if (y == x) continue;
        const Tri3& g = faces_[boundary_[uses[y].face]].key;
        uint32_t e = g[0];
        for (uint32_t v : g)
          if (v != (uses[i].key >> 32) && v != static_cast<uint32_t>(uses[i].key)) e = v;
        // Reflex only by the rounding of a Steiner point (§5) when the two
        // faces are numerically flat (geometry.hpp): no error.
        if (pred::orient3d(pt(f[0]), pt(f[1]), pt(f[2]), pt(e)) < 0 &&
            std::fabs(volume_ratio(pt(f[0]), pt(f[1]), pt(f[2]), pt(e))) > kFlatTetRatio)
          return fail("the boundary of the kept tets is not convex at face " + tri_name(F.key) +
                      " (with the convex hull kept, as some boundary face is not constrained).")
              .vertex(F.key[0]);
      }
    }
    i = j;
  }
  return Status::success();
}

// Whether the midpoint of (a, b), rounded to doubles, lies in a tet or on its
// boundary (exact orientations; a scan, only on the failure path).
bool Validator::in_some_tet(uint32_t a, uint32_t b) const {
  const double* p = pt(a);
  const double* q = pt(b);
  const double m[3] = {0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.5 * (p[2] + q[2])};
  for (size_t t = 0; t < nt_; ++t) {
    const uint32_t* w = &m_.tets[4 * t];
    bool in = true;
    for (int i = 0; i < 4 && in; ++i) {
      const double* f[3];
      for (int j = 0; j < 3; ++j) f[j] = pt(w[kFaceVertex[i][j]]);
      in = pred::orient3d(f[0], f[1], f[2], m) >= 0;
    }
    if (in) return true;
  }
  return false;
}

Status Validator::segments() {
  segments_ = plc_segments(plc_);
  chains_.assign(segments_.size(), {});
  for (size_t s = 0; s < segments_.size(); ++s) chains_[s] = {segments_[s][0], segments_[s][1]};
  for (size_t i = 0; i < r_.steiner_kind.size(); ++i) {
    if (r_.steiner_kind[i] != SteinerKind::Segment) continue;
    const int64_t p = steiner_parent_[i];
    const uint32_t v = static_cast<uint32_t>(r_.input_points + i);
    if (p < 0 || static_cast<size_t>(p) >= segments_.size())
      return fail("segment Steiner point " + std::to_string(v) + " has no valid parent segment.")
          .vertex(v);
    chains_[static_cast<size_t>(p)].push_back(v);
  }
  for (size_t s = 0; s < segments_.size(); ++s) {
    std::vector<uint32_t>& c = chains_[s];
    const double* a = pt(c[0]);
    const double* b = pt(c[1]);
    const uint32_t last = c[1];
    c.erase(c.begin() + 1);
    // Ordered along ab exactly: points a few ulps apart (two segments that
    // pass within rounding of each other get split points that close to
    // the other's) are ordered wrongly by a dot product in doubles.
    std::sort(c.begin() + 1, c.end(), [&](uint32_t x, uint32_t y) {
      const int s = pred::dot_sign(pt(x), pt(y), b, a);
      return s != 0 ? s < 0 : x < y;
    });
    c.push_back(last);
    bool inside = true;
    for (uint32_t v : c) inside = inside && in_tet_[v];
    if (!inside) continue;  // the segment lies outside the kept tets
    // A missing piece whose midpoint is in no tet lies outside the kept tets
    // too, between removed regions (a hole that touches the convex hull).
    for (size_t k = 0; k + 1 < c.size(); ++k)
      if (!is_edge(c[k], c[k + 1]) && in_some_tet(c[k], c[k + 1]))
        return fail("segment (" + std::to_string(c.front()) + ", " + std::to_string(c.back()) +
                    ") is not a chain of mesh edges: (" + std::to_string(c[k]) + ", " +
                    std::to_string(c[k + 1]) + ") is missing.")
            .vertex(c[k])
            .segment(static_cast<int64_t>(s));
  }
  return Status::success();
}

// Facet f's input vertices, the segments lying in it and its input
// triangles (fverts_, fsegs_, ftris_), the axis its projection drops (the
// largest component of Newell's normal of its first loop); returns its area.
double Validator::facet_input(size_t f, const std::vector<uint32_t>& tris,
                              const std::vector<size_t>& input_tris) {
  std::vector<uint32_t>& verts = fverts_[f];
  std::vector<uint32_t>& segs_in = fsegs_[f];
  double area_in = 0;
  for (size_t i : input_tris) {
    const Tri3 t = {tris[3 * i], tris[3 * i + 1], tris[3 * i + 2]};
    ftris_[f].push_back(t);
    area_in += tri_area(t);
    for (int k = 0; k < 3; ++k) {
      verts.push_back(t[k]);
      const int64_t s = segment_index(t[k], t[(k + 1) % 3]);
      if (s >= 0) segs_in.push_back(static_cast<uint32_t>(s));
    }
  }
  std::sort(verts.begin(), verts.end());
  verts.erase(std::unique(verts.begin(), verts.end()), verts.end());
  std::sort(segs_in.begin(), segs_in.end());
  segs_in.erase(std::unique(segs_in.begin(), segs_in.end()), segs_in.end());
  const Vec3 n = newell_normal(plc_, plc_.facets[f].loops[0]);
  fdrop_[f] = largest_axis(n.x, n.y, n.z);
  return area_in;
}

// The subsegments of the segments lying in facet f (the edges where its
// patch may end) and those of its loops, as sorted edge keys.
void Validator::facet_edges(size_t f, std::vector<uint64_t>& allowed_edges,
                            std::vector<uint64_t>& loop_edges) const {
  allowed_edges.clear();
  for (uint32_t s : fsegs_[f])
    for (size_t k = 0; k + 1 < chains_[s].size(); ++k)
      allowed_edges.push_back(edge_key(chains_[s][k], chains_[s][k + 1]));
  std::sort(allowed_edges.begin(), allowed_edges.end());
  loop_edges.clear();
  for (const auto& L : plc_.facets[f].loops)
    for (size_t i = 0; i < L.size(); ++i) {
      const int64_t s = segment_index(L[i], L[(i + 1) % L.size()]);
      if (s < 0) continue;
      for (size_t k = 0; k + 1 < chains_[s].size(); ++k)
        loop_edges.push_back(edge_key(chains_[s][k], chains_[s][k + 1]));
    }
  std::sort(loop_edges.begin(), loop_edges.end());
  loop_edges.erase(std::unique(loop_edges.begin(), loop_edges.end()), loop_edges.end());
}

// Output vertex v may be a vertex of a face of facet f: an input vertex of
// f, a Steiner point on one of its segments, or a Facet Steiner point of f.
bool Validator::vertex_in_facet(uint32_t v, size_t f) const {
  if (v < r_.input_points) return std::binary_search(fverts_[f].begin(), fverts_[f].end(), v);
  const size_t i = v - r_.input_points;
  const int64_t p = steiner_parent_[i];
  switch (r_.steiner_kind[i]) {
    case SteinerKind::Facet:
      return p == static_cast<int64_t>(f);
    case SteinerKind::Segment:
      return std::binary_search(fsegs_[f].begin(), fsegs_[f].end(), static_cast<uint32_t>(p));
    default:
      return false;
  }
}

// Check 6 on the faces of facet f: their vertices, orientation in the
// facet's plane, the patch's boundary edges, its area.
Status Validator::facet_faces(size_t f, const std::vector<size_t>& faces, double area_in,
                              const std::vector<uint64_t>& allowed_edges,
                              const std::vector<uint64_t>& loop_edges) {
  const int64_t F = static_cast<int64_t>(f);
  const int drop = fdrop_[f];
  int side = 0;
  double area_out = 0, perimeter = 0;
  std::vector<uint64_t> fedges;
  for (size_t i : faces) {
    const Tri3 t = {m_.faces[3 * i], m_.faces[3 * i + 1], m_.faces[3 * i + 2]};
    for (uint32_t v : t)
      if (!vertex_in_facet(v, f))
        return fail("face " + tri_name(t) + " of facet " + std::to_string(f) + " uses vertex " +
                    std::to_string(v) + ", which does not belong to the facet.")
            .facet(F)
            .vertex(v);
    const int o = pred::orient2d_projected(pt(t[0]), pt(t[1]), pt(t[2]), drop);
    if (o == 0)
      return fail("face " + tri_name(t) + " of facet " + std::to_string(f) +
                  " is degenerate in the facet's plane.")
          .facet(F)
          .vertex(t[0]);
    if (side == 0) side = o;
    if (o != side)
      return fail("the faces of facet " + std::to_string(f) +
                  " overlap or are not consistently oriented (face " + tri_name(t) + ").")
          .facet(F)
          .vertex(t[0]);
    area_out += tri_area(t);
    for (int k = 0; k < 3; ++k) {
      fedges.push_back(edge_key(t[k], t[(k + 1) % 3]));
      const double* a = pt(t[k]);
      const double* b = pt(t[(k + 1) % 3]);
      perimeter += std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                             (a[2] - b[2]) * (a[2] - b[2]));
    }
  }
  std::sort(fedges.begin(), fedges.end());
  bool partial = false;
  for (size_t i = 0; i < fedges.size();) {
    size_t j = i;
    while (j < fedges.size() && fedges[j] == fedges[i]) ++j;
    const uint32_t a = static_cast<uint32_t>(fedges[i] >> 32), b = static_cast<uint32_t>(fedges[i]);
    if (j - i > 2)
      return fail("edge (" + std::to_string(a) + ", " + std::to_string(b) + ") is in " +
                  std::to_string(j - i) + " faces of facet " + std::to_string(f) + ".")
          .facet(F)
          .vertex(a);
    if (j - i == 1) {
      if (!std::binary_search(allowed_edges.begin(), allowed_edges.end(), fedges[i]))
        return fail("the faces of facet " + std::to_string(f) + " end at edge (" +
                    std::to_string(a) + ", " + std::to_string(b) +
                    "), which is on none of its segments.")
            .facet(F)
            .vertex(a);
      if (!std::binary_search(loop_edges.begin(), loop_edges.end(), fedges[i])) partial = true;
    }
    i = j;
  }
  for (uint64_t e : loop_edges)
    if (!partial && !std::binary_search(fedges.begin(), fedges.end(), e))
      return fail("loop subsegment (" + std::to_string(e >> 32) + ", " +
                  std::to_string(static_cast<uint32_t>(e)) + ") of facet " + std::to_string(f) +
                  " is no edge of its faces.")
          .facet(F)
          .vertex(static_cast<int64_t>(e >> 32));
  const double tol = kAreaSumTolerance * area_in + kRoundingUlps * kUlp * scale_ * perimeter;
  if (partial ? area_out > area_in + tol : std::fabs(area_out - area_in) > tol)
    return fail("the faces of facet " + std::to_string(f) + " cover an area of " +
                std::to_string(area_out) + " instead of " + std::to_string(area_in) + ".")
        .facet(F);
  if (partial || plc_.facets[f].loops.size() != 1) facets_closed_ = false;
  return Status::success();
}

// The facets without faces must lie outside the kept tets: their probe
// points (sorted here by x) are strictly inside no tet; each tet tests those
// in its bounding box.
Status Validator::probes_outside(std::vector<Probe>& probes) const {
  std::sort(probes.begin(), probes.end(), [](const Probe& a, const Probe& b) {
    return a.p[0] != b.p[0] ? a.p[0] < b.p[0] : a.facet < b.facet;
  });
  for (uint32_t t = 0; t < nt_ && !probes.empty(); ++t) {
    const uint32_t* w = &m_.tets[4 * static_cast<size_t>(t)];
    double lo[3], hi[3];
    for (int x = 0; x < 3; ++x) {
      lo[x] = hi[x] = pt(w[0])[x];
      for (int k = 1; k < 4; ++k)
        lo[x] = std::min(lo[x], pt(w[k])[x]), hi[x] = std::max(hi[x], pt(w[k])[x]);
    }
    auto it = std::lower_bound(probes.begin(), probes.end(), lo[0],
                               [](const Probe& a, double x) { return a.p[0] < x; });
    for (; it != probes.end() && it->p[0] <= hi[0]; ++it) {
      if (it->p[1] < lo[1] || it->p[1] > hi[1] || it->p[2] < lo[2] || it->p[2] > hi[2]) continue;
      bool strictly = true;
      for (int i = 0; i < 4 && strictly; ++i) {
        const Tri3 g = tet_face(t, i);
        strictly = pred::orient3d(pt(g[0]), pt(g[1]), pt(g[2]), it->p) > 0;
      }
      if (strictly)
        return fail("facet " + std::to_string(it->facet) +
                    " has no constrained faces but passes through tet " + std::to_string(t) + ".")
            .facet(it->facet);
    }
  }
  return Status::success();
}

// Check 6 (file header).
Status Validator::facets() {
  // The input facets triangulated without Steiner points: their vertices
  // (loop vertices, PLC points and segments lying in them) and areas.
  std::vector<uint32_t> tris, tri_facet;
  Status st = triangulate_surface(plc_, tris, tri_facet);
  if (!st.ok()) {
    st.error.code = ErrorCode::Internal;
    st.error.message = "Validation: the input facet cannot be triangulated: " + st.error.message;
    return st;
  }
  const size_t nfacets = plc_.facets.size();
  std::vector<std::vector<size_t>> sub_of(nfacets), faces_of(nfacets);
  for (size_t i = 0; i < tri_facet.size(); ++i) sub_of[tri_facet[i]].push_back(i);
  for (size_t i = 0; i < nf_; ++i) faces_of[face_facet_[i]].push_back(i);

  std::vector<Probe> probes;
  fverts_.assign(nfacets, {});
  fsegs_.assign(nfacets, {});
  ftris_.assign(nfacets, {});
  fdrop_.assign(nfacets, 2);
  std::vector<uint64_t> allowed_edges, loop_edges;
  for (size_t f = 0; f < nfacets; ++f) {
    const double area_in = facet_input(f, tris, sub_of[f]);
    facet_edges(f, allowed_edges, loop_edges);
    if (faces_of[f].empty()) {
      // Must lie outside the kept tets: the centroid of its largest input
      // triangle is strictly inside no tet (probes_outside).
      size_t best = 0;
      double best_area = -1;
      for (size_t i : sub_of[f]) {
        const double a = tri_area({tris[3 * i], tris[3 * i + 1], tris[3 * i + 2]});
        if (a > best_area) best_area = a, best = i;
      }
      if (best_area < 0) continue;
      Probe q;
      q.facet = static_cast<uint32_t>(f);
      for (int k = 0; k < 3; ++k) {
        const Vec3& v = plc_.points[tris[3 * best + k]];
        q.p[0] += v.x / 3, q.p[1] += v.y / 3, q.p[2] += v.z / 3;
      }
      probes.push_back(q);
      continue;
    }
    st = facet_faces(f, faces_of[f], area_in, allowed_edges, loop_edges);
    if (!st.ok()) return st;
  }
  return probes_outside(probes);
}

// Check 7's tables: which facets each vertex belongs to, which segments
// each input point ends, the constrained faces per facet, the subsegments.
void Validator::build_membership() {
  const size_t nfacets = plc_.facets.size();
  Membership& ms = ms_;
  ms.seg_facets.assign(segments_.size(), {});
  for (uint32_t f = 0; f < nfacets; ++f)
    for (uint32_t s : fsegs_[f]) ms.seg_facets[s].push_back(f);
  ms.input_facets.assign(r_.input_points, {});
  for (uint32_t f = 0; f < nfacets; ++f)
    for (uint32_t v : fverts_[f]) ms.input_facets[v].push_back(f);
  ms.segs_at.assign(r_.input_points, {});
  for (uint32_t s = 0; s < segments_.size(); ++s)
    for (VertexId v : segments_[s])
      if (v < r_.input_points) ms.segs_at[v].push_back(s);
  ms.faces_of_facet.assign(nfacets, {});
  for (size_t j = 0; j < nf_; ++j) ms.faces_of_facet[face_facet_[j]].push_back(j);
  ms.subsegs.clear();
  for (size_t j = 0; j + 1 < r_.edges.size(); j += 2)
    ms.subsegs.push_back({std::min(r_.edges[j], r_.edges[j + 1]), std::max(r_.edges[j], r_.edges[j + 1])});
  std::sort(ms.subsegs.begin(), ms.subsegs.end());
}

// The facets vertex v belongs to (sorted): an input point's facets, a
// segment Steiner point's segment's facets, a facet Steiner point's facet.
// `slot` picks one of three buffers, so three results can be held at once.
const std::vector<uint32_t>& Validator::facets_of(uint32_t v, int slot) {
  if (v < r_.input_points) return ms_.input_facets[v];
  const size_t i = v - r_.input_points;
  ms_.one[slot].clear();
  const int64_t p = steiner_parent_[i];
  if (r_.steiner_kind[i] == SteinerKind::Segment) return ms_.seg_facets[static_cast<size_t>(p)];
  if (r_.steiner_kind[i] == SteinerKind::Facet) ms_.one[slot].push_back(static_cast<uint32_t>(p));
  return ms_.one[slot];
}

// A tet whose four vertices all belong to facet f is flat up to the
// rounding of Steiner points (§5: they are rounded to doubles): the facet
// is only nearly planar there, and both diagonals of the quadrilateral are
// faces, one pair constrained, the other not. Such a face is no error;
// neither is a face of a numerically flat tet (one the flips of
// flat_flips.hpp could not remove, e.g. between several facets whose
// planes meet along a segment): it is in f's plane only by rounding.
bool Validator::flat_in_facet(size_t i, uint32_t f) {
  for (size_t j = i; j < faces_.size() && faces_[j].key == faces_[i].key; ++j) {
    const uint32_t* w = &m_.tets[4 * static_cast<size_t>(faces_[j].tet)];
    const std::vector<uint32_t>& fv = facets_of(w[faces_[j].face], 0);
    if (std::binary_search(fv.begin(), fv.end(), f)) return true;
    if (numerically_flat(pt(w[0]), pt(w[1]), pt(w[2]), pt(w[3]))) return true;
  }
  return false;
}

// Three vertices on one line of segments (input points and Steiner points
// of segments whose ends are all exactly collinear, e.g. the consecutive
// collinear edges along a merged flat face) make a face that is flat along
// that line, up to the rounding of Steiner points: it lies in no facet's
// interior.
bool Validator::along_one_line(const Tri3& k) const {
  std::array<uint32_t, 6> ends;  // input points spanning the line
  size_t n = 0;
  for (uint32_t v : k) {
    if (v < r_.input_points) {
      ends[n++] = v;
      continue;
    }
    const size_t i = v - r_.input_points;
    if (r_.steiner_kind[i] != SteinerKind::Segment) return false;
    const int64_t s = steiner_parent_[i];
    if (s < 0 || s >= static_cast<int64_t>(segments_.size())) return false;
    ends[n++] = segments_[s][0];
    ends[n++] = segments_[s][1];
  }
  const double* a = &plc_.points[ends[0]].x;
  size_t j = 1;
  while (j < n && ends[j] == ends[0]) ++j;
  if (j == n) return true;
  const double* b = &plc_.points[ends[j]].x;
  for (size_t x = j + 1; x < n; ++x)
    if (ends[x] != ends[0] && ends[x] != ends[j] && !pred::collinear3d(a, b, &plc_.points[ends[x]].x))
      return false;
  return true;
}

void Validator::project(uint32_t v, int drop, double out[2]) const {
  const double* p = pt(v);
  out[0] = p[(drop + 1) % 3], out[1] = p[(drop + 2) % 3];
}

// Whether an edge line of triangle u (counterclockwise, projected) has all
// of triangle w on its outer side or on it: then their interiors are disjoint.
bool separated(const double (*u)[2], const double (*w)[2]) {
  for (int e = 0; e < 3; ++e) {
    bool all = true;
    for (int x = 0; x < 3 && all; ++x) all = pred::orient2d(u[e], u[(e + 1) % 3], w[x]) <= 0;
    if (all) return true;
  }
  return false;
}

// Rounded Steiner points (§5) put a subsegment a few ulps off its segment's
// line, so a face on the far side of a subsegment of f can overlap f in a
// sliver: that is no error when face k shares a subsegment (x, y) with a
// constrained face of f whose third vertex is on the other side of xy, and
// overlaps no constrained face of f.
bool Validator::beyond_subsegment(const Tri3& k, uint32_t f, int drop) const {
  bool across = false;
  for (int e = 0; e < 3 && !across; ++e) {
    const uint32_t x = k[e], y = k[(e + 1) % 3], z = k[(e + 2) % 3];
    if (!std::binary_search(ms_.subsegs.begin(), ms_.subsegs.end(),
                            std::array<uint32_t, 2>{std::min(x, y), std::max(x, y)}))
      continue;
    for (size_t j : ms_.faces_of_facet[f]) {
      const uint32_t* c = &m_.faces[3 * j];
      int at = -1;
      for (int q = 0; q < 3; ++q)
        if (c[q] != x && c[q] != y) at = q;
      if (at < 0 || (c[(at + 1) % 3] != x && c[(at + 2) % 3] != x) ||
          (c[(at + 1) % 3] != y && c[(at + 2) % 3] != y))
        continue;
      double px[2], py[2], pz[2], pw[2];
      project(x, drop, px), project(y, drop, py), project(z, drop, pz), project(c[at], drop, pw);
      if (pred::orient2d(px, py, pz) * pred::orient2d(px, py, pw) < 0) across = true;
    }
  }
  if (!across) return false;
  double g[3][2];
  for (int x = 0; x < 3; ++x) project(k[x], drop, g[x]);
  if (pred::orient2d(g[0], g[1], g[2]) < 0) std::swap(g[1], g[2]);
  for (size_t j : ms_.faces_of_facet[f]) {
    double h[3][2];
    for (int x = 0; x < 3; ++x) project(m_.faces[3 * j + x], drop, h[x]);
    if (pred::orient2d(h[0], h[1], h[2]) < 0) std::swap(h[1], h[2]);
    if (!separated(g, h) && !separated(h, g)) return false;
  }
  return true;
}

// Whether face k (all of whose vertices belong to facet f) overlaps the
// interior of a triangle of f's input triangulation, in f's projection.
bool Validator::overlaps_facet(const Tri3& k, uint32_t f, int drop) const {
  double g[3][2];
  for (int x = 0; x < 3; ++x) project(k[x], drop, g[x]);
  if (pred::orient2d(g[0], g[1], g[2]) < 0) std::swap(g[1], g[2]);
  if (pred::orient2d(g[0], g[1], g[2]) == 0) return false;
  for (const Tri3& t : ftris_[f]) {
    double h[3][2];
    for (int x = 0; x < 3; ++x) {
      const Vec3& p = plc_.points[t[x]];
      const double c[3] = {p.x, p.y, p.z};
      h[x][0] = c[(drop + 1) % 3], h[x][1] = c[(drop + 2) % 3];
    }
    if (pred::orient2d(h[0], h[1], h[2]) < 0) std::swap(h[1], h[2]);
    if (!separated(g, h) && !separated(h, g)) return true;
  }
  return false;
}

// The same against f's constrained faces (their rounded Steiner points
// included). A face beside f's rounded subsegments can overlap f's input
// triangles by the rounding alone (e.g. a hull face along a merged facet's
// nearly straight boundary); where it overlaps none of f's faces it is not
// in f as meshed, and check 6 has shown those faces cover f.
bool Validator::overlaps_subfaces(const Tri3& k, uint32_t f, int drop) const {
  if (ms_.faces_of_facet[f].empty()) return true;  // check 6 did not cover f
  double g[3][2];
  for (int x = 0; x < 3; ++x) project(k[x], drop, g[x]);
  if (pred::orient2d(g[0], g[1], g[2]) < 0) std::swap(g[1], g[2]);
  if (pred::orient2d(g[0], g[1], g[2]) == 0) return false;
  for (size_t j : ms_.faces_of_facet[f]) {
    double h[3][2];
    for (int x = 0; x < 3; ++x) project(m_.faces[3 * j + x], drop, h[x]);
    if (pred::orient2d(h[0], h[1], h[2]) < 0) std::swap(h[1], h[2]);
    if (pred::orient2d(h[0], h[1], h[2]) == 0) continue;
    if (!separated(g, h) && !separated(h, g)) return true;
  }
  return false;
}

// Check 7: a face that is not constrained must not lie in a facet. For
// every unconstrained face of the mesh whose three vertices all belong to
// facet f, its projection must not overlap the interior of
// any triangle of f (exact orient2d in f's projection; two triangles'
// interiors are disjoint iff an edge line of one separates them), but for
// the rounding cases above (flat_in_facet, along_one_line,
// beyond_subsegment, overlaps_subfaces).
Status Validator::unconstrained_in_facets() {
  build_membership();
  std::vector<Tri3> keys = constrained_;
  std::sort(keys.begin(), keys.end());
  std::vector<uint32_t> ab, abc;
  for (size_t i = 0; i < faces_.size(); ++i) {
    if (i > 0 && faces_[i].key == faces_[i - 1].key) continue;
    const Tri3& k = faces_[i].key;
    if (std::binary_search(keys.begin(), keys.end(), k)) continue;
    const std::vector<uint32_t>& fa = facets_of(k[0], 0);
    if (fa.empty()) continue;
    const std::vector<uint32_t>& fb = facets_of(k[1], 1);
    ab.clear();
    std::set_intersection(fa.begin(), fa.end(), fb.begin(), fb.end(), std::back_inserter(ab));
    if (ab.empty()) continue;
    const std::vector<uint32_t>& fc = facets_of(k[2], 2);
    abc.clear();
    std::set_intersection(ab.begin(), ab.end(), fc.begin(), fc.end(), std::back_inserter(abc));
    for (uint32_t f : abc) {
      const int drop = fdrop_[f];
      if (overlaps_facet(k, f, drop) && !flat_in_facet(i, f) && !along_one_line(k) &&
          !beyond_subsegment(k, f, drop) && overlaps_subfaces(k, f, drop))
        return fail("face " + tri_name(k) + " lies in facet " + std::to_string(f) +
                    " but is not constrained.")
            .facet(f)
            .vertex(k[0]);
    }
  }
  return Status::success();
}

Status Validator::volume() {
  if (hull_kept_ || !facets_closed_) return Status::success();
  // Centre the coordinates for accuracy.
  double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (size_t v = 0; v < np_; ++v)
    for (int k = 0; k < 3; ++k) {
      lo[k] = v == 0 ? pt(0)[k] : std::min(lo[k], pt(static_cast<uint32_t>(v))[k]);
      hi[k] = v == 0 ? pt(0)[k] : std::max(hi[k], pt(static_cast<uint32_t>(v))[k]);
    }
  const double c[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  auto det = [&c](const double* a, const double* b, const double* d) {
    const double u[3] = {a[0] - c[0], a[1] - c[1], a[2] - c[2]};
    const double v[3] = {b[0] - c[0], b[1] - c[1], b[2] - c[2]};
    const double w[3] = {d[0] - c[0], d[1] - c[1], d[2] - c[2]};
    return u[0] * (v[1] * w[2] - v[2] * w[1]) + u[1] * (v[2] * w[0] - v[0] * w[2]) +
           u[2] * (v[0] * w[1] - v[1] * w[0]);
  };
  double vt = 0, vabs = 0;
  for (uint32_t t = 0; t < nt_; ++t) {
    const uint32_t* w = &m_.tets[4 * static_cast<size_t>(t)];
    // Positive tets: orient3d > 0, i.e. det(v0 - v3, v1 - v3, v2 - v3) > 0,
    // which is the sum of the four centred triple products below.
    const double* p0 = pt(w[0]);
    const double* p1 = pt(w[1]);
    const double* p2 = pt(w[2]);
    const double* p3 = pt(w[3]);
    const double x = (det(p0, p1, p2) - det(p0, p1, p3) + det(p0, p2, p3) - det(p1, p2, p3)) / 6;
    vt += x;
    vabs += std::fabs(x);
  }
  // Per facet: all faces on the boundary with the domain on one side, or all
  // interior; the boundary ones contribute their loop, oriented outwards.
  std::vector<int> out_sign(plc_.facets.size(), 0);
  std::vector<uint8_t> interior(plc_.facets.size(), 0), any(plc_.facets.size(), 0);
  for (size_t i = 0; i < nf_; ++i) {
    const size_t f = face_facet_[i];
    any[f] = 1;
    if (face_two_[i]) {
      if (out_sign[f] != 0) return Status::success();  // mixed: not checked
      interior[f] = 1;
      continue;
    }
    if (interior[f]) return Status::success();
    const FaceRec& R = faces_[face_tet_[i]];
    const Tri3 g = tet_face(R.tet, R.face);  // counterclockwise from outside the domain
    const auto& L = plc_.facets[f].loops[0];
    // Outward normal of g against the loop's Newell normal.
    const Vec3 nv = newell_normal(plc_, L);
    const double n[3] = {nv.x, nv.y, nv.z};
    const double* a = pt(g[0]);
    const double* b = pt(g[1]);
    const double* d = pt(g[2]);
    const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
    const double gn[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                          u[0] * w[1] - u[1] * w[0]};
    const double dot = gn[0] * n[0] + gn[1] * n[1] + gn[2] * n[2];
    const int s = dot > 0 ? 1 : dot < 0 ? -1 : 0;
    if (s == 0) return Status::success();
    if (out_sign[f] != 0 && out_sign[f] != s) return Status::success();  // both sides: skip
    out_sign[f] = s;
  }
  double vf = 0;
  for (size_t f = 0; f < plc_.facets.size(); ++f) {
    if (out_sign[f] == 0) continue;
    const auto& L = plc_.facets[f].loops[0];
    for (size_t k = 1; k + 1 < L.size(); ++k)
      vf += out_sign[f] * det(&plc_.points[L[0]].x, &plc_.points[L[k]].x,
                              &plc_.points[L[k + 1]].x) / 6;
  }
  if (std::fabs(vt - vf) > kVolumeSumTolerance * vabs + kTinyLength)
    return fail("the tets' volume " + std::to_string(vt) + " differs from the volume " +
                std::to_string(vf) + " enclosed by the facets.");
  return Status::success();
}

// A face between tets (w) and (face, e) may fail the insphere test where the
// Delaunay choice for these five points would be a numerically flat tet,
// which the pipeline flips away (flat_flips.hpp): some four of the five
// points are numerically flat (geometry.hpp).
bool Validator::flipped_for_flat_tet(const uint32_t* w, uint32_t e) const {
  const double* p[5] = {pt(w[0]), pt(w[1]), pt(w[2]), pt(w[3]), pt(e)};
  return has_flat_quadruple(p);
}

Status Validator::delaunay() {
  std::vector<Tri3> keys = constrained_;
  std::sort(keys.begin(), keys.end());
  for (size_t i = 0; i + 1 < faces_.size(); ++i) {
    if (faces_[i].key != faces_[i + 1].key) continue;
    if (std::binary_search(keys.begin(), keys.end(), faces_[i].key)) continue;
    const FaceRec& a = faces_[i];
    const FaceRec& b = faces_[i + 1];
    const uint32_t* w = &m_.tets[4 * static_cast<size_t>(a.tet)];
    const uint32_t e = m_.tets[4 * static_cast<size_t>(b.tet) + b.face];
    if (pred::insphere(pt(w[0]), pt(w[1]), pt(w[2]), pt(w[3]), pt(e)) > 0 &&
        !flipped_for_flat_tet(w, e))
      return fail("face " + tri_name(a.key) +
                  " is not constrained and not locally Delaunay: "
                  "vertex " +
                  std::to_string(e) + " is inside the circumsphere of tet " +
                  std::to_string(a.tet) + ".")
          .vertex(e);
  }
  return Status::success();
}

// The checks of the file header, numbered as there.
Status Validator::run() {
  Status st = sizes();
  if (st.ok()) st = tets_and_faces();
  if (st.ok()) st = constrained_faces();
  if (st.ok()) st = segments();
  if (st.ok()) st = facets();
  if (st.ok()) st = unconstrained_in_facets();
  if (st.ok()) st = volume();
  if (st.ok() && r_.delaunay) st = delaunay();  // not after the improvement pass
  return st;
}

}  // namespace

// A result of merged flat faces (Result::flat_faces_merged) names input
// facets and segments; it is checked against the merged PLC, with faces and
// Steiner parents translated to it, and errors translated back.
Status validate(const Plc& plc, const Result& result) {
  if (!result.flat_faces_merged)
    return Validator(plc, result, result.face_facet, result.steiner_parent).run();
  Plc merged;
  std::vector<uint32_t> into;
  merge_flat_facets(plc, merged, into);
  std::vector<uint32_t> rep(merged.facets.size(), kNone);
  for (uint32_t f = 0; f < into.size(); ++f)
    if (rep[into[f]] == kNone) rep[into[f]] = f;
  auto to_merged = [&](int64_t f) -> int64_t {
    return f >= 0 && f < static_cast<int64_t>(into.size()) ? into[f] : f;
  };
  std::vector<uint32_t> face_facet(result.face_facet);
  for (uint32_t& f : face_facet) f = static_cast<uint32_t>(to_merged(f));
  const auto theirs = plc_segments(plc), mine = plc_segments(merged);
  std::vector<int64_t> parent(result.steiner_parent);
  for (size_t i = 0; i < parent.size() && i < result.steiner_kind.size(); ++i) {
    int64_t& p = parent[i];
    if (result.steiner_kind[i] == SteinerKind::Facet) p = to_merged(p);
    if (result.steiner_kind[i] != SteinerKind::Segment || p < 0 ||
        p >= static_cast<int64_t>(theirs.size()))
      continue;
    auto it = std::lower_bound(mine.begin(), mine.end(), theirs[p]);
    p = it != mine.end() && *it == theirs[p] ? it - mine.begin() : -1;
  }
  Status st = Validator(merged, result, face_facet, parent).run();
  Error& e = st.error;
  for (int64_t* f : {&e.facet, &e.other_facet})
    if (*f >= 0 && *f < static_cast<int64_t>(rep.size())) *f = rep[*f];
  if (e.segment >= 0 && e.segment < static_cast<int64_t>(mine.size())) {
    auto it = std::lower_bound(theirs.begin(), theirs.end(), mine[e.segment]);
    e.segment = it - theirs.begin();
  }
  return st;
}

}  // namespace cdt3d
