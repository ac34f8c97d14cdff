// Quality refinement of a carved CDT (refine.hpp): constrained Delaunay
// refinement (Shewchuk 1998, Si 2015) on the kept tets alone.
//
// The mesh: the Result's tets without ghosts, constraint tags per half-face
// and subsegments in a hash map (constrained_mesh.hpp).
//
// Insertion (constrained Bowyer-Watson): the cavity of a new point p is
// grown from the tets that contain it (or, for a point on a facet or a
// segment, from the tets beside the subfaces p splits) across faces that
// are not constrained, to tets whose circumsphere contains p (insphere_sos,
// p perturbed as the newest vertex, like every Steiner point of steps 1-4).
// For a point on a facet, the subfaces it splits are found first in the
// facet's plane: the subfaces whose circumcircle contains p, grown across
// edges that are not subsegments (the 2D constrained Bowyer-Watson). The
// cavity boundary must be visible from p (every new tet positive and not
// numerically flat, tested exactly and in doubles); a tet whose face fails
// is dropped from the cavity, and when a seed tet would have to go the
// point is not inserted. So the mesh stays a CDT of the PLC refined by the
// inserted points, and no insertion creates a flat tet.
//
// Termination: a bad tet's circumcentre c is inserted when it encroaches
// upon no subsegment and no subface of its cavity's boundary and lies in the
// domain; otherwise the encroached (or blocking) constraint is split instead,
// but only when the new point lies at least a fixed fraction of the bad
// tet's shortest edge from the vertices nearest to it (the insertion radius
// rule of Shewchuk's proof, without its angle assumptions; kFloorFactor,
// kSplitFloorFactor): insertions then keep a distance to existing vertices
// tied to the mesh they were triggered by. Those two floors can shrink
// along chains of insertions; a third one cannot: a local scale carried
// from the CDT's shortest edges (kScaleFactor, init_scales) keeps all
// points a fixed distance apart, so refinement stops (the point cap,
// max_points, remains as a guard). The radius rule does not hold a split
// point of a segment back from a vertex on a feature that does not meet
// that segment (apart_from_segment): their distance is bounded by the
// input, as in Shewchuk's analysis. Bad tets that would need a closer
// point are left (counted in refine_skipped); they are the ones near small
// input angles and between coplanar facets, which TetGen leaves in part too.
//
// With the improvement pass on (the default), the result need not stay a
// CDT, and split points of subsegments and subfaces go in unconditionally,
// as in Shewchuk's and Si's algorithms: a cavity that is not star-shaped
// from the point is cut down to one that is (shrink_to_star), the subfaces
// it leaves encroached are split right after (split_encroached), and
// Lawson flips restore local Delaunay faces around the new point
// (flip_to_delaunay). Without it, thin facets side by side (the faceted
// wall of a hole, the strips of a fillet) ask for cycles of splits that
// each need the other first, and refinement gives up there. A second sweep
// after flips over the whole mesh retries the bad tets left (run()), and
// every cavity must be a ball (cavity_is_ball), which Bowyer-Watson no
// longer guarantees in a mesh that is not Delaunay everywhere. The sides of
// needles (facet corners below 10 degrees) are then not split at all
// (kNeedleReach), and a circumcentre goes in even where its cone fails the
// Delaunay test at a subface whose split that refused (at_locked_face).
#include "refine.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "constrained_mesh.hpp"
#include "geometry.hpp"
#include "improve.hpp"
#include "predicates.hpp"
#include "radix_sort.hpp"
#include "spatial_sort.hpp"
#include "status.hpp"
#include "tet_mesh.hpp"

namespace cdt3d {

Status check_quality_options(const QualityOptions& q) {
  if (!(q.radius_edge >= 1.0) || !std::isfinite(q.radius_edge))
    return make_error(ErrorCode::InvalidArgument,
                      "The radius-edge bound of quality refinement must be a number >= 1 (got " +
                          std::to_string(q.radius_edge) + ").");
  if (!(q.max_volume == -1 || (q.max_volume > 0 && std::isfinite(q.max_volume))))
    return make_error(ErrorCode::InvalidArgument,
                      "The maximum tet volume must be positive, or -1 for none (got " +
                          std::to_string(q.max_volume) + ").");
  if (!(q.min_dihedral >= 0 && q.min_dihedral <= 70))
    return make_error(ErrorCode::InvalidArgument,
                      "The dihedral angle target must be between 0 and 70 degrees (got " +
                          std::to_string(q.min_dihedral) + ").");
  return Status::success();
}

namespace {


// Split points of subsegments lie exactly on their segment's line when a
// dyadic fraction with this many bits (down to the second) gives one
// (point_exactly_on_segment), as in segment recovery.
constexpr int kLineBits = 24;
constexpr int kLineMinBits = 20;

// The insertion radius rule's factor: a point goes in only if its nearest
// vertex is at least this times the trigger's length (the bad tet's
// shortest edge). 1 is the safe bound of the proof; 0.5 lets refinement
// reach the scale of thin features and still stops on every model of
// tests/data; smaller factors can run away on thin plates.
constexpr double kFloorFactor = 0.5;
// The same rule for the length a subsegment or subface split would make
// (half the subsegment, the subface's circumradius): below 1 refinement
// fixes more bad tets; 0.75 still stops on every model, lower factors can
// run away.
constexpr double kSplitFloorFactor = 0.75;
// The floor of the local scale (init_scales): no point goes in closer than
// kScaleFactor times its local scale to another vertex. The two floors
// above are tied to the tet that asked for the point, and chains of
// insertions near a feature can shrink them without end (scanned models
// then run to the point cap); this one cannot shrink. The scale grows away
// from the CDT's vertices with slope kScaleSlope, not 1 as the local
// feature size does: the vertices sample it too sparsely (in the middle of
// a plate 0.001 thick with vertices 0.1 apart a slope of 1 gives 0.07, far
// above the thickness, and refinement stops early). (0.05, 0.25) leaves the
// classic models as without the floor while bounding the refinement of thin
// plates and large scans (tests/bench/README.md has the runs).
constexpr double kScaleFactor = 0.05;
constexpr double kScaleSlope = 0.25;
// The same floor for the split of a subface an unconditional insertion left
// encroached (split_encroached), which has no radius-rule floor: near small
// input angles those splits cascade, and on decimated scans they tripled
// the tets for a small gain in quality below this (tests/bench/README.md).
constexpr double kEncroachedScaleFactor = 0.2;

// Two facets meeting at an edge at a dihedral angle below this (degrees;
// the small input angle of issue 42) bound a thin wedge (in_thin_wedge).
constexpr double kWedgeAngle = 10;
// Shewchuk's seditious edges ("Delaunay refinement algorithms for triangular
// mesh generation", 2002, section 5): a bad tet whose shortest edge joins
// two segments of one facet corner below kSeditiousAngle degrees, its ends
// at about the same distance from the corner (within kSeditiousSpread of
// the larger), owes its shape to that corner: a point that fixes it lies
// between the two segments closer to the corner, and makes a shorter edge
// across it there, and so on down to the floors. Such a tet is left. On the
// decimated scans these cascades made most of the mesh: dragon_decimated
// 182,509 tets without the rule, 111,571 with it; plate_holes (corners of
// 10.5 degrees in its countersinks) 105,671 and 42,725 (tests/bench/
// README.md). Corners of kTinyCorner to kWedgeAngle degrees are refined as
// before: there the bench excuses the tets at the corner anyway, and
// leaving the seditious ones too left chazelle_n3 (corners of 6-9 degrees)
// with 3.3% of its tets above ratio 2 against TetGen's 1.6%. Below
// kTinyCorner the rule holds again: refining across a corner that thin
// makes slivers all along its sides (dragon_decimated, 122 corners below
// 10 degrees, one of 1.2: smallest dihedral angle 0.0011 degrees without,
// 1.8 with; 111,571 tets and 74,123).
constexpr double kSeditiousAngle = 60;
constexpr double kSeditiousSpread = 0.3;
constexpr double kTinyCorner = 5;
// Needles: with the improvement pass on, the sides of a facet corner below
// kWedgeAngle degrees (its two segments and, on a triangle facet, the third
// side) are not split. A split point there lies inside the corner's
// triangle, where every subface is a needle or a cap and the tets on them
// are slivers that touch no small input angle; and the needle's width
// becomes a feature size that refinement then resolves all around. On
// dragon_decimated (151 corners below 10 degrees) that made 74,123 tets,
// 92 of them below 10 degrees and not at a small angle, in 0.44 s; with the
// sides kept, 33,991 tets, 64 and 0.21 s (nefertiti: 999 -> 167 such tets;
// tests/bench/README.md). The bad tets a kept side leaves go to the pass.
// A needle whose longer side reaches beyond kNeedleReach of the model's
// bounding-box diagonal is a feature of the model, not of its
// triangulation, and is refined as before (chazelle_n3's notches: kept
// whole, 695 tets and 4.5% of them above ratio 2 against 3,666 and 0.44%).
constexpr double kNeedleReach = 0.25;
// With the improvement pass on, a circumcentre whose cone fails the
// Delaunay test at a constrained face at least this many of the face's
// circumradii from its circumcentre goes in (far_fault).
constexpr double kFarFault = 6;

// Facets of more vertices than this are not looked at for wedges
// (small_dihedral_pairs).
constexpr size_t kWedgeFacetSize = 64;

// The guard on added points beyond 100 per point of the CDT: a plate of
// 242 points whose thickness is a thousandth of its width needs about 400k
// points at that scale on its faces to meet the bound (TetGen adds 1M).
constexpr size_t kBasePointCap = 1000000;

// The share of the Refine phase's progress that refinement reports when the
// improvement pass follows (which reports the rest).
constexpr double kRefineShare = 0.8;

// A split point that would leave a constrained face of its cavity non-
// Delaunay splits that face first, and so on to this depth.
constexpr int kMaxSplitDepth = 6;

// flip_to_delaunay's mark of a tet whose four faces it found locally
// Delaunay (the first tet flag after kTetUser, which run() uses).
constexpr uint8_t kTetFlipClean = kTetUser << 1;

// Bound on the tets a walk or an edge rotation visits before giving up (a
// broken mesh; never reached on a valid one).
constexpr size_t kMaxWalk = 1u << 20;

// Floating-point geometry: it places points and ranks tets; no topological
// decision rests on it (those use the exact predicates).
struct TetShape {
  double center[3];
  double radius;    // circumradius
  double shortest;  // shortest edge
  int ends[2];      // its ends, as indices 0-3 of the tet's vertices
  double volume;
};

TetShape tet_shape(const double* p0, const double* p1, const double* p2, const double* p3) {
  TetShape s;
  const Vec3 a = to_vec(p0);
  s.volume = std::fabs(dot(to_vec(p1) - a, cross(to_vec(p2) - a, to_vec(p3) - a))) / 6;
  const Vec3 o = sphere_center(a, to_vec(p1), to_vec(p2), to_vec(p3));
  s.center[0] = o.x, s.center[1] = o.y, s.center[2] = o.z;
  s.radius = finite(o) ? dist(o, a) : HUGE_VAL;
  const double* p[4] = {p0, p1, p2, p3};
  // One square root: it is monotonic and correctly rounded, so the root of
  // the smallest square is the smallest root (every tet popped is tested).
  double shortest2 = HUGE_VAL;
  s.ends[0] = 0, s.ends[1] = 1;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) {
      const Vec3 d = to_vec(p[i]) - to_vec(p[j]);
      if (dot(d, d) < shortest2) shortest2 = dot(d, d), s.ends[0] = i, s.ends[1] = j;
    }
  s.shortest = std::sqrt(shortest2);
  return s;
}

// Two facets meeting at an edge (a, b) at a dihedral angle below kWedgeAngle,
// each with its vertex farthest from the edge's line.
struct WedgePair {
  uint32_t f[2];
  Vec3 a, b, far[2];
  double sin_angle;
  double reach;  // how far the wedge reaches off the edge: the nearer far vertex
};

// The pairs of facets of plc that meet at an edge at a dihedral angle below
// kWedgeAngle, measured as the quality bench does (tests/bench/
// mesh_quality.cpp): the angle between the two facets' directions away
// from the edge, each its vertex farthest from the edge's line made
// perpendicular to it. A threshold on the input, so doubles do. Facets of
// more than kWedgeFacetSize vertices are left out: the farthest vertex
// costs a scan of the facet per edge (they are refined as before).
std::vector<WedgePair> small_dihedral_pairs(const Plc& plc) {
  struct EdgeFacet {
    uint64_t key;  // edge (a, b), a < b, as a * points + b
    uint32_t facet;
  };
  const uint64_t n = plc.points.size();
  std::vector<EdgeFacet> edges;
  for (uint32_t f = 0; f < plc.facets.size(); ++f) {
    size_t size = 0;
    for (const auto& loop : plc.facets[f].loops) size += loop.size();
    if (size > kWedgeFacetSize) continue;
    for (const auto& loop : plc.facets[f].loops)
      for (size_t i = 0; i < loop.size(); ++i) {
        const uint64_t a = loop[i], b = loop[(i + 1) % loop.size()];
        if (a != b) edges.push_back({std::min(a, b) * n + std::max(a, b), f});
      }
  }
  radix_sort_by(edges, [](const EdgeFacet& e) { return e.key; }, 0, 2 * index_bits(n));
  const double cos_limit = std::cos(kWedgeAngle * 3.14159265358979323846 / 180);
  std::vector<WedgePair> out;
  std::vector<Vec3> away, far;
  for (size_t lo = 0, hi = 0; lo < edges.size(); lo = hi) {
    while (hi < edges.size() && edges[hi].key == edges[lo].key) ++hi;
    if (hi - lo < 2) continue;
    const Vec3 a = plc.points[edges[lo].key / n], b = plc.points[edges[lo].key % n];
    const Vec3 e = b - a;
    const double ee = dot(e, e);
    if (!(ee > 0)) continue;
    away.assign(hi - lo, Vec3{0, 0, 0});
    far.assign(hi - lo, a);
    for (size_t k = 0; k < hi - lo; ++k)
      for (const auto& loop : plc.facets[edges[lo + k].facet].loops)
        for (uint32_t v : loop) {
          const Vec3 d = plc.points[v] - a;
          const Vec3 perp = d - (dot(d, e) / ee) * e;
          if (dot(perp, perp) > dot(away[k], away[k])) away[k] = perp, far[k] = plc.points[v];
        }
    for (size_t i = 0; i < hi - lo; ++i)
      for (size_t j = i + 1; j < hi - lo; ++j) {
        const double d = norm(away[i]) * norm(away[j]);
        if (d > 0 && dot(away[i], away[j]) > cos_limit * d)
          out.push_back({{edges[lo + i].facet, edges[lo + j].facet}, a, b, {far[i], far[j]},
                         norm(cross(away[i], away[j])) / d, std::min(norm(away[i]), norm(away[j]))});
      }
  }
  return out;
}

// The pairs of small_dihedral_pairs with the domain between the two facets
// (a thin wedge of it; a notch, the outside between them as on chazelle_n3,
// is none). The domain's side of facet f: the side of its plane, by exact
// orientation, of the tets of cm that have a face on f; the wedge holds the
// domain when the other facet's far vertex lies on that side.
std::vector<WedgePair> domain_wedges(const Plc& plc, const ConstrainedMesh& cm) {
  std::vector<WedgePair> pairs = small_dihedral_pairs(plc);
  if (pairs.empty()) return pairs;
  // pairs_of[f]: (pair, which side of it) for each pair f is in.
  std::unordered_map<uint32_t, std::vector<std::pair<size_t, int>>> pairs_of;
  for (size_t k = 0; k < pairs.size(); ++k)
    for (int s = 0; s < 2; ++s) pairs_of[pairs[k].f[s]].push_back({k, s});
  // sides[2k + s]: bit 1 (positive) and 2 (negative) for the domain's sides
  // of facet f[s] of pair k, relative to the plane (a, b, far[s]).
  std::vector<uint8_t> sides(2 * pairs.size(), 0);
  const TetMesh& m = cm.m;
  for (TetId t = 0; t < m.num_tet_slots(); ++t) {
    if (m.is_dead(t)) continue;
    for (int i = 0; i < 4; ++i) {
      const uint32_t tag = cm.tag(make_hf(t, i));
      if (tag == kNoTag || is_hull_tag(tag)) continue;
      const auto it = pairs_of.find(tag - 1);
      if (it == pairs_of.end()) continue;
      const double* d = cm.pt(m.tet_vertices(t)[i]);
      for (const auto& [k, s] : it->second) {
        const WedgePair& w = pairs[k];
        const int o = pred::orient3d(&w.a.x, &w.b.x, &w.far[s].x, d);
        sides[2 * k + s] |= o > 0 ? 1 : o < 0 ? 2 : 0;
      }
    }
  }
  std::vector<WedgePair> out;
  for (size_t k = 0; k < pairs.size(); ++k) {
    const WedgePair& w = pairs[k];
    bool inside = true;
    for (int s = 0; s < 2 && inside; ++s) {
      const int o = pred::orient3d(&w.a.x, &w.b.x, &w.far[s].x, &w.far[1 - s].x);
      inside = (sides[2 * k + s] & (o > 0 ? 1 : o < 0 ? 2 : 0)) != 0;
    }
    if (inside) out.push_back(w);
  }
  return out;
}

// Circumcentre and circumradius of triangle (a, b, c) in its plane.
bool triangle_circle(const double* pa, const double* pb, const double* pc, Vec3& center, double& r) {
  center = circle_center(to_vec(pa), to_vec(pb), to_vec(pc));
  r = dist(center, to_vec(pa));
  return finite(center) && std::isfinite(r);
}

// p strictly inside the diametral sphere of triangle (a, b, c): the smallest
// sphere through its vertices (Shewchuk's encroachment of a subface).
bool encroaches_triangle(const double* pa, const double* pb, const double* pc, const double* p) {
  Vec3 o;
  double r;
  if (!triangle_circle(pa, pb, pc, o, r)) return false;
  return dist(to_vec(p), o) < r;
}

class Refiner {
 public:
  Refiner(const Plc& plc, const QualityOptions& q, Result& res) : plc_(plc), q_(q), res_(res) {}
  Status run(const volatile bool* cancel, const RefineProgress& progress);

 private:
  struct Subface {
    HalfFace hf;
    uint32_t tag;
    std::array<VertexId, 3> v;
  };
  struct BoundaryFace {
    VertexId a, b, c;   // counterclockwise seen from outside the cavity
    HalfFace outside;   // the half-face beyond, or kNoHalfFace
    HalfFace own;       // the face as a half-face of its cavity tet
    uint32_t tag;
    double attr;
    TetId from;
  };
  enum class Walk { InTet, Blocked, Failed };
  // What a cavity check found: fine, a constraint to split first, or no go.
  enum class Verdict { Ok, SplitSubface, SplitSubsegment, Reject };

  // --- the mesh (constrained_mesh.hpp) ---
  TetId new_tet() { return cm_.new_tet(); }
  VertexId new_vertex(const double* p, Where where, int64_t parent) {
    return cm_.new_vertex(p, where, parent);
  }
  uint32_t tag(HalfFace hf) const { return cm_.tag(hf); }
  std::array<VertexId, 3> face_of(HalfFace hf) const { return cm_.face_of(hf); }
  const double* pt(VertexId v) const { return cm_.pt(v); }
  bool is_subsegment(VertexId a, VertexId b) const { return cm_.is_subsegment(a, b); }
  bool edge_ring(TetId t0, VertexId x, VertexId y, std::vector<TetId>& out) const {
    return cm_.edge_ring(t0, x, y, out);
  }
  int facet_axis(uint32_t tag, const std::array<VertexId, 3>& v) const {
    return cm_.facet_axis(tag, v);
  }

  // --- queries ---
  bool subface_across(const Subface& s, VertexId x, VertexId y, Subface& out);
  void subfaces_at_edge(VertexId a, VertexId b, TetId t0, std::vector<Subface>& out);
  Walk locate(TetId start, const double* p, TetId& found, HalfFace& blocked);
  Walk locate_in_facet(const Subface& start, const double* p, Subface& found, VertexId& sa,
                       VertexId& sb);
  double volume_limit(double attr) const;
  bool is_bad(TetId t, TetShape& shape) const;

  // --- insertion ---
  bool grow_subface_region(const double* p, VertexId pid, VertexId sa, VertexId sb);
  bool grow_cavity(const double* p, VertexId pid, Where where);
  bool removed(HalfFace hf) const {  // removed_ is sorted once the region is known
    return !removed_.empty() && std::binary_search(removed_.begin(), removed_.end(), hf);
  }
  void collect_boundary();
  Verdict check_constraints(const double* p, Where where, VertexId sa, VertexId sb);
  bool cavity_is_star(const double* p);
  bool shrink_to_star(const double* p, size_t seeds);
  bool cavity_is_ball();
  void split_encroached();
  // --- Lawson flips after an insertion that may leave faces not locally Delaunay ---
  void flip_to_delaunay();
  void note_delaunay_face(TetId t, int k, TetId& run, int& run_faces);
  bool not_delaunay(HalfFace hf) const;
  bool flip23(HalfFace hf);
  bool flip32(HalfFace hf);
  bool replace_tets(const std::vector<TetId>& old, const std::vector<std::array<VertexId, 4>>& fresh);
  void region_boundary(VertexId sa, VertexId sb);
  bool region_edges_on_boundary();
  // Whether edge `key` is an edge of the cavity's boundary.
  bool on_boundary(uint64_t key) const { return bnd_edges_.find(key) != nullptr; }
  bool cone_is_delaunay(const double* p);
  // The cone test failed at a subface whose split the needle rule refused
  // (locked_): the point goes in all the same, as an unconditional split
  // point does (the pass is on, the result need not be a CDT). Else each
  // bad tet whose cavity reaches such a subface fails there, after growing
  // its cavity (igea: 10.5 s without the needle rule, 20 s with it, 8 s
  // with this).
  bool at_locked_face() const { return fault_ && locked_.count(sorted_triangle(split_face_.v)) != 0; }
  bool far_fault(const double* p) const;
  bool on_needle(VertexId v) const;
  bool cone_is_delaunay_paired(const double* p);
  bool cone_face_fails(const BoundaryFace& f, VertexId third, const double* p) const;
  bool name_cone_fault(const BoundaryFace& f, const BoundaryFace& g);
  void clear_cavity();
  void glue_cone(const TetId* cone);
  VertexId commit(const double* p, Where where, int64_t parent, VertexId sa, VertexId sb,
                  double scale);
  bool insert(const double* p, Where where, int64_t parent, VertexId sa, VertexId sb,
              double floor, Verdict* verdict);
  double nearest_vertex(const double* p, double& scale, VertexId& nearest) const;
  bool apart_from_segment(VertexId w, int64_t segment) const;
  using SplitKey = std::array<VertexId, 3>;  // a subface, or a subsegment and kNone
  void remember_failure(Verdict verdict);
  bool known_failure(const SplitKey& key, Verdict& verdict);

  // --- the three kinds of split ---
  bool split_subsegment(VertexId a, VertexId b, double lmin, int depth = 0);
  bool split_subface(const Subface& s, double lmin, int depth = 0);
  void init_wedges();
  void init_small_corners();
  bool has_seditious_edge(TetId t, const TetShape& shape) const;
  bool in_thin_wedge(uint32_t tag, const Vec3& c, double r) const;
  bool fix_bad_tet(TetId t, const TetShape& shape);


  const Plc& plc_;
  const QualityOptions& q_;
  Result& res_;
  ConstrainedMesh cm_;
  // Short names for the mesh's parts, used throughout.
  TetMesh& m_ = cm_.m;
  std::vector<uint32_t>& hfc_ = cm_.hfc;
  std::vector<double>& attr_ = cm_.attr;
  std::vector<Where>& where_ = cm_.where;
  EdgeMap& subseg_ = cm_.subseg;
  std::vector<std::pair<double, double>> region_limits_;  // (attribute, max volume)
  Rng rng_{0x7265666e65ull};

  // Insertion buffers.
  std::vector<Subface> region_;    // subfaces the point splits
  std::vector<HalfFace> removed_;  // their half-faces (both sides)
  std::vector<TetId> cav_;
  std::vector<BoundaryFace> bnd_;
  // The edges of bnd_ with the boundary faces through each (collect_boundary).
  // A hash table, not a sort: the boundary of every tried cavity is paired
  // up, so the pairing must be cheap.
  class BoundaryEdges {
   public:
    struct Slot {
      uint64_t key;
      uint32_t stamp;  // the slot is in use when stamp == the table's stamp
      uint32_t count;  // sides seen (boundary faces through the edge)
      uint32_t side[2];  // the first two: 3 * face index in bnd_ + edge index k
    };
    // Empties the table for about n edges.
    void reset(size_t n) {
      size_t size = 16;
      while (size < 2 * n) size *= 2;
      if (size > slots_.size() || ++stamp_ == 0) {
        slots_.assign(std::max(size, slots_.size()), Slot{0, 0, 0, {0, 0}});
        stamp_ = 1;
      }
      mask_ = size - 1;  // the part of the table this cavity needs: a table grown by one
                         // big cavity would spread small ones over many cache lines
      used_.clear();
      crowded_ = false;
    }
    void add(uint64_t key, uint32_t side) {
      const size_t i = probe(key);
      Slot& s = slots_[i];
      if (s.stamp != stamp_) {
        s = Slot{key, stamp_, 0, {0, 0}};
        used_.push_back(static_cast<uint32_t>(i));
      }
      if (s.count < 2) s.side[s.count] = side;
      crowded_ = crowded_ || s.count >= 2;
      ++s.count;
    }
    const Slot* find(uint64_t key) const {
      const Slot& s = slots_[probe(key)];
      return s.stamp == stamp_ ? &s : nullptr;
    }
    // The edges in the order they were first seen.
    const std::vector<uint32_t>& used() const { return used_; }
    const Slot& slot(uint32_t i) const { return slots_[i]; }
    // Some edge lies in more than two boundary faces (a cavity that touches
    // itself along an edge).
    bool crowded() const { return crowded_; }

   private:
    // The slot of `key`, or the free one where it would go.
    size_t probe(uint64_t key) const {
      size_t i = static_cast<size_t>((key * 0x9E3779B97F4A7C15ull) >> 32) & mask_;
      while (slots_[i].stamp == stamp_ && slots_[i].key != key) i = (i + 1) & mask_;
      return i;
    }
    std::vector<Slot> slots_;
    std::vector<uint32_t> used_;
    uint32_t stamp_ = 0;
    size_t mask_ = 0;
    bool crowded_ = false;
  };
  BoundaryEdges bnd_edges_;
  static void add_face_edges(BoundaryEdges& table, const std::array<VertexId, 3>& f) {
    for (int k = 0; k < 3; ++k) table.add(edge_key(f[k], f[(k + 1) % 3]), 0);
  }
  std::vector<TetId> ring_;
  Subface split_face_{};             // what check_constraints asks to split
  VertexId split_a_ = kNone, split_b_ = kNone;
  std::vector<TetId> queue_;       // tets to test (a stack: run())
  // Split points of constraints go in unconditionally (shrink_to_star) when
  // the result need not stay a CDT (the improvement pass follows).
  bool unconditional_splits_ = false;
  std::vector<std::array<VertexId, 3>> encroached_;  // subfaces left encroached (shrink_to_star)
  std::vector<HalfFace> flip_queue_;                  // faces to check (flip_to_delaunay)
  std::vector<TetId> flip_clean_;                     // the tets it marked kTetFlipClean
  std::vector<TetId> created_;                        // replace_tets' new tets
  // shrink_to_star may take tets beyond a seed into the cavity: in the
  // last sweep, for the first try at each bad tet left (run()).
  bool take_in_ = false;
  std::vector<TetId> taken_;                         // shrink_to_star's scratch
  // cavity_is_ball's scratch: the open faces, the edges with them, and
  // its vertices marked (ball_mark_[v] == ball_stamp_).
  std::vector<std::array<VertexId, 3>> ball_faces_;
  BoundaryEdges ball_edges_;
  std::vector<uint32_t> ball_mark_;
  uint32_t ball_stamp_ = 0;
  double scale_factor_ = kScaleFactor;                // the scale floor's factor now
  struct SideRec {
    uint64_t key;
    uint32_t face;
    VertexId third;
  };
  std::vector<SideRec> sides_;
  bool fault_ = false;  // cone_is_delaunay() named a constrained face
  std::vector<std::pair<uint64_t, uint32_t>> rim_;  // region_boundary(): (edge, tag)
  // Failed splits of subsegments and subfaces (remember_failure): the
  // verdict, the constraint it named, the cavity's vertices, and when
  // (commits_ then). attempt_ is the split under way (kNoAttempt: a
  // circumcentre).
  struct Failure {
    uint32_t time = 0;
    Verdict verdict = Verdict::Reject;
    Subface fault{};
    VertexId split_a = kNone, split_b = kNone;
    std::vector<VertexId> vertices;
  };
  struct SplitKeyHash {
    size_t operator()(const SplitKey& k) const {
      return std::hash<uint64_t>()(edge_key(k[0], k[1]) * 0x9e3779b97f4a7c15ull ^ k[2]);
    }
  };
  std::unordered_map<SplitKey, Failure, SplitKeyHash> failures_;
  static constexpr SplitKey kNoAttempt{kNone, kNone, kNone};
  SplitKey attempt_ = kNoAttempt;
  std::vector<uint32_t> touched_;  // per vertex: the commit that last changed its star
  uint32_t commits_ = 0;
  std::vector<double> scale_;  // per vertex: its local scale (init_scales)
  std::vector<std::array<VertexId, 2>> segments_;  // the PLC's segments (plc_segments order)
  // Thin wedges of the domain (domain_wedges) and, per facet, the indices
  // of those it bounds (empty for most).
  std::vector<WedgePair> wedges_;
  std::unordered_map<uint32_t, std::vector<uint32_t>> wedges_of_;
  // Facet corners of an angle below kTinyCorner or in [kWedgeAngle,
  // kSeditiousAngle) degrees, by the pair of segments (indices in
  // segments_) that are their sides.
  std::unordered_set<uint64_t> small_corners_;
  // Per segment (indices in segments_): a side of a needle (kNeedleReach),
  // not split while unconditional_splits_; needle_refused_ is set when a
  // split was refused so, and locked_ holds the subfaces whose split failed
  // for it (fix_bad_tet), which a circumcentre's cone may then fail.
  std::vector<char> needle_side_;
  std::vector<char> needle_end_;  // per input point: an end of a needle side
  bool needle_refused_ = false;
  std::unordered_set<SplitKey, SplitKeyHash> locked_;
  void init_scales();
};

// ---------------------------------------------------------------------------
// Set-up and output
// ---------------------------------------------------------------------------

// ---------------------------------------------------------------------------
// Queries
// ---------------------------------------------------------------------------

// The subface of s's facet on the other side of its edge xy (not a
// subsegment: exactly two subfaces of the facet share it).
bool Refiner::subface_across(const Subface& s, VertexId x, VertexId y, Subface& out) {
  if (!edge_ring(hf_tet(s.hf), x, y, ring_)) return false;
  VertexId z = kNone;
  for (VertexId u : s.v)
    if (u != x && u != y) z = u;
  for (TetId t : ring_) {
    const VertexId* tv = m_.tet_vertices(t);
    for (int i = 0; i < 4; ++i) {
      if (tv[i] == x || tv[i] == y) continue;
      const HalfFace hf = make_hf(t, i);
      if (tag(hf) != s.tag) continue;
      const auto f = face_of(hf);
      if (std::find(f.begin(), f.end(), z) != f.end()) continue;
      out = {hf, s.tag, f};
      return true;
    }
  }
  return false;
}

// Every constrained face through edge ab, each triangle once.
void Refiner::subfaces_at_edge(VertexId a, VertexId b, TetId t0, std::vector<Subface>& out) {
  out.clear();
  if (!edge_ring(t0, a, b, ring_)) return;
  for (TetId t : ring_) {
    const VertexId* tv = m_.tet_vertices(t);
    for (int i = 0; i < 4; ++i) {
      if (tv[i] == a || tv[i] == b) continue;
      const HalfFace hf = make_hf(t, i);
      if (tag(hf) == kNoTag) continue;
      const auto f = sorted_triangle(face_of(hf));
      bool seen = false;
      for (const Subface& s : out) seen = seen || sorted_triangle(s.v) == f;
      if (!seen) out.push_back({hf, tag(hf), face_of(hf)});
    }
  }
}

// Visibility walk from `start` towards p across faces p is strictly beyond;
// stops at a constrained or open face p is beyond (Blocked, `blocked` set).
Refiner::Walk Refiner::locate(TetId start, const double* p, TetId& found, HalfFace& blocked) {
  TetId t = start;
  HalfFace entered = kNoHalfFace;
  for (size_t steps = 0; steps < kMaxWalk; ++steps) {
    const int k0 = static_cast<int>(rng_.next() & 3u);
    bool moved = false;
    for (int j = 0; j < 4 && !moved; ++j) {
      const int i = (k0 + j) & 3;
      const HalfFace hf = make_hf(t, i);
      if (hf == entered) continue;
      const auto f = face_of(hf);
      if (pred::orient3d(pt(f[0]), pt(f[1]), pt(f[2]), p) >= 0) continue;
      const HalfFace nb = m_.adjacent(hf);
      if (tag(hf) != kNoTag || nb == kNoHalfFace) {
        blocked = hf;
        return Walk::Blocked;
      }
      entered = nb;
      t = hf_tet(nb);
      moved = true;
    }
    if (!moved) {
      found = t;
      return Walk::InTet;
    }
  }
  return Walk::Failed;
}

// The 2D walk in a facet from subface `start` towards p (projected by the
// facet's axis): crosses edges p is strictly beyond; stops at a subsegment
// (Blocked, its ends in sa, sb).
Refiner::Walk Refiner::locate_in_facet(const Subface& start, const double* p, Subface& found,
                                       VertexId& sa, VertexId& sb) {
  Subface s = start;
  const int drop = facet_axis(s.tag, s.v);
  VertexId from_x = kNone, from_y = kNone;
  for (size_t steps = 0; steps < kMaxWalk; ++steps) {
    const int side = pred::orient2d_projected(pt(s.v[0]), pt(s.v[1]), pt(s.v[2]), drop);
    if (side == 0) return Walk::Failed;
    bool moved = false;
    for (int k = 0; k < 3 && !moved; ++k) {
      const VertexId x = s.v[k], y = s.v[(k + 1) % 3];
      if ((x == from_x && y == from_y) || (x == from_y && y == from_x)) continue;
      if (pred::orient2d_projected(pt(x), pt(y), p, drop) * side >= 0) continue;
      if (is_subsegment(x, y)) {
        sa = x, sb = y;
        return Walk::Blocked;
      }
      Subface next;
      if (!subface_across(s, x, y, next)) return Walk::Failed;
      s = next;
      from_x = x, from_y = y;
      moved = true;
    }
    if (!moved) {
      found = s;
      return Walk::InTet;
    }
  }
  return Walk::Failed;
}

double Refiner::volume_limit(double attr) const {
  double limit = q_.max_volume > 0 ? q_.max_volume : HUGE_VAL;
  for (const auto& r : region_limits_)
    if (r.first == attr) limit = std::min(limit, r.second);
  return limit;
}

bool Refiner::is_bad(TetId t, TetShape& shape) const {
  const VertexId* v = m_.tet_vertices(t);
  shape = tet_shape(pt(v[0]), pt(v[1]), pt(v[2]), pt(v[3]));
  if (!(shape.shortest > 0) || !std::isfinite(shape.radius)) return false;
  return shape.radius > q_.radius_edge * shape.shortest || shape.volume > volume_limit(attr_[t]);
}

// ---------------------------------------------------------------------------
// Insertion
// ---------------------------------------------------------------------------

// The subfaces a point on a facet (or on segment sa-sb) splits: from the
// seeds in region_, the subfaces of the same facet across edges that are no
// subsegment whose circumcircle contains p (exact, in the facet's
// projection; a tie goes by the perturbed insphere of a tet beside it).
bool Refiner::grow_subface_region(const double* p, VertexId pid, VertexId sa, VertexId sb) {
  for (size_t i = 0; i < region_.size(); ++i) {
    const Subface s = region_[i];
    for (int k = 0; k < 3; ++k) {
      const VertexId x = s.v[k], y = s.v[(k + 1) % 3];
      if ((x == sa && y == sb) || (x == sb && y == sa) || is_subsegment(x, y)) continue;
      Subface n;
      if (!subface_across(s, x, y, n)) {
        if (is_hull_tag(s.tag)) continue;  // an edge between two planes of the hull
        return false;
      }
      const auto key = sorted_triangle(n.v);
      bool seen = false;
      for (const Subface& r : region_) seen = seen || sorted_triangle(r.v) == key;
      if (seen) continue;
      const int drop = facet_axis(n.tag, n.v);
      double a2[2], b2[2], c2[2], p2[2];
      const int u = (drop + 1) % 3, w = (drop + 2) % 3;
      const double* pa = pt(n.v[0]);
      const double* pb = pt(n.v[1]);
      const double* pc = pt(n.v[2]);
      a2[0] = pa[u], a2[1] = pa[w], b2[0] = pb[u], b2[1] = pb[w];
      c2[0] = pc[u], c2[1] = pc[w], p2[0] = p[u], p2[1] = p[w];
      const int o = pred::orient2d(a2, b2, c2);
      int in = o * pred::incircle(a2, b2, c2, p2);
      if (o == 0) in = -1;
      if (in == 0) {
        const VertexId* tv = m_.tet_vertices(hf_tet(n.hf));
        in = pred::insphere_sos(pt(tv[0]), pt(tv[1]), pt(tv[2]), pt(tv[3]), p, tv[0], tv[1], tv[2],
                                tv[3], pid);
      }
      if (in > 0) region_.push_back(n);
    }
  }
  for (const Subface& s : region_) {
    removed_.push_back(s.hf);
    const HalfFace nb = m_.adjacent(s.hf);
    if (nb != kNoHalfFace) removed_.push_back(nb);
  }
  std::sort(removed_.begin(), removed_.end());
  return true;
}

// Bowyer-Watson growth from the seeds in cav_ (already marked) across faces
// that are not constrained (or are removed subfaces) to tets in conflict.
// A circumcentre (Volume, or a point on a hull face of a keep-hull domain)
// that encroaches upon a constrained face the cavity meets, other than the
// subfaces it splits, is not inserted (Shewchuk's first rule): the growth
// stops there, with that face in split_face_, and returns false.
bool Refiner::grow_cavity(const double* p, VertexId pid, Where where) {
  for (size_t i = 0; i < cav_.size(); ++i) {
    const TetId t = cav_[i];
    for (int f = 0; f < 4; ++f) {
      const HalfFace hf = make_hf(t, f);
      const HalfFace nb = m_.adjacent(hf);
      if (where == Where::Volume && tag(hf) != kNoTag && !removed(hf)) {
        const auto v = face_of(hf);
        if (encroaches_triangle(pt(v[0]), pt(v[1]), pt(v[2]), p)) {
          split_face_ = {hf, tag(hf), v};
          return false;
        }
      }
      if (nb == kNoHalfFace) continue;
      const TetId u = hf_tet(nb);
      if (m_.tflag[u] & kTetInCavity) continue;
      const bool split = tag(hf) != kNoTag && removed(hf);
      if (tag(hf) != kNoTag && !split) continue;
      const VertexId* tv = m_.tet_vertices(u);
      const bool conflict = split || pred::insphere_sos(pt(tv[0]), pt(tv[1]), pt(tv[2]),
                                                              pt(tv[3]), p, tv[0], tv[1], tv[2],
                                                              tv[3], pid) > 0;
      if (!conflict) continue;
      m_.tflag[u] |= kTetInCavity;
      cav_.push_back(u);
    }
  }
  return true;
}

void Refiner::collect_boundary() {
  bnd_.clear();
  bnd_edges_.reset(4 * cav_.size() + 8);
  for (TetId t : cav_) {
    for (int f = 0; f < 4; ++f) {
      const HalfFace hf = make_hf(t, f);
      const HalfFace nb = m_.adjacent(hf);
      if (nb != kNoHalfFace && (m_.tflag[hf_tet(nb)] & kTetInCavity)) continue;
      if (nb == kNoHalfFace && removed(hf)) continue;  // a split boundary subface
      const auto v = face_of(hf);
      bnd_.push_back({v[0], v[1], v[2], nb, hf, tag(hf), attr_[t], t});
      const uint32_t i = static_cast<uint32_t>(bnd_.size() - 1);
      for (int k = 0; k < 3; ++k) bnd_edges_.add(edge_key(v[k], v[(k + 1) % 3]), 3 * i + k);
    }
  }
}

// Shewchuk's rejection rules: a circumcentre (Volume) is not inserted when it
// encroaches upon a subface of its cavity's boundary (grow_cavity stops at
// the first) or upon a subsegment among the cavity's edges; a facet point
// not when it encroaches upon such a subsegment. Any subsegment among the
// cavity's edges must survive (be an edge of the boundary), else the point
// is rejected.
Refiner::Verdict Refiner::check_constraints(const double* p, Where where, VertexId sa,
                                            VertexId sb) {
  for (TetId t : cav_) {
    const VertexId* tv = m_.tet_vertices(t);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const VertexId a = tv[i], b = tv[j];
        if ((a == sa && b == sb) || (a == sb && b == sa) || !is_subsegment(a, b)) continue;
        if (where != Where::Segment && pred::dot_sign(pt(a), p, pt(b)) < 0) {
          split_a_ = a, split_b_ = b;
          return Verdict::SplitSubsegment;
        }
        if (!on_boundary(edge_key(a, b)))
          return Verdict::Reject;
      }
  }
  return Verdict::Ok;
}

// The cavity is star-shaped from p: every boundary face gives a positive,
// not numerically flat tet with p (exact orientation, then the doubles of
// the output). A cavity that is not is not shrunk: the tets left out would
// still hold p in their circumsphere, next to the new tets, and the mesh
// would no longer be constrained Delaunay. The point is not inserted. The
// usual culprit is a constrained face p lies beyond or in the plane of: a
// coplanar neighbouring facet whose subface's circumcircle holds p (no CDT
// has a tet on that subface then), or a concave edge; that face is named
// for splitting (fault_).
bool Refiner::cavity_is_star(const double* p) {
  fault_ = false;
  for (const BoundaryFace& f : bnd_)
    if (pred::orient3d(pt(f.a), pt(f.b), pt(f.c), p) <= 0 ||
        numerically_flat(pt(f.a), pt(f.b), pt(f.c), p)) {
      if (f.tag != kNoTag) {
        split_face_ = {f.own, f.tag, {f.a, f.b, f.c}};
        fault_ = true;
      }
      return false;
    }
  return true;
}

// A split point of a subsegment or subface whose cavity is not star-shaped
// from it: the tets behind a face it does not see leave the cavity (the
// seeds, which the split destroys, cannot), until the rest is. A constrained
// face it does not see is encroached (p lies in its circumsphere's tet
// and beyond or in its plane); it is kept in encroached_ and split right
// after this insertion, which removes the tets left beside it. This is how
// Shewchuk's and Si's algorithms insert split points unconditionally: a
// cycle of subsegments that each encroach the other's neighbouring
// subfaces (thin facets side by side, as on the faceted wall of a hole)
// has no split that keeps a CDT at every step.
bool Refiner::shrink_to_star(const double* p, size_t seeds) {
  std::vector<TetId>& taken = taken_;
  for (int round = 0; round < 64; ++round) {
    bool changed = false;
    taken.clear();
    for (const BoundaryFace& f : bnd_) {
      if (pred::orient3d(pt(f.a), pt(f.b), pt(f.c), p) > 0 &&
          !numerically_flat(pt(f.a), pt(f.b), pt(f.c), p))
        continue;
      if (!(m_.tflag[f.from] & kTetInCavity)) continue;  // already cut this round
      if (std::find(cav_.begin(), cav_.begin() + static_cast<long>(seeds), f.from) !=
          cav_.begin() + static_cast<long>(seeds)) {
        // A tet that must go (a seed, or one taken in for a seed) with a
        // face p does not see: in the last sweep the tet beyond joins the
        // cavity (it holds p in no circumsphere where flips could not make
        // that face locally Delaunay) and must go too; cavity_is_ball()
        // then checks the result.
        if (!take_in_ || f.tag != kNoTag || f.outside == kNoHalfFace) return false;
        const TetId u = hf_tet(f.outside);
        if (m_.tflag[u] & kTetInCavity) continue;  // taken in this round
        m_.tflag[u] |= kTetInCavity;
        taken.push_back(u);
        changed = true;
        continue;
      }
      if (f.tag != kNoTag) encroached_.push_back({f.a, f.b, f.c});
      m_.tflag[f.from] &= static_cast<uint8_t>(~kTetInCavity);
      changed = true;
    }
    if (!changed) return true;
    // (A tet cut and taken in in the same round is kept once, as taken in.)
    cav_.erase(std::remove_if(cav_.begin() + static_cast<long>(seeds), cav_.end(),
                              [&](TetId t) {
                                return !(m_.tflag[t] & kTetInCavity) ||
                                       std::find(taken.begin(), taken.end(), t) != taken.end();
                              }),
               cav_.end());
    cav_.insert(cav_.begin() + static_cast<long>(seeds), taken.begin(), taken.end());
    seeds += taken.size();
    collect_boundary();
  }
  return false;
}

// Whether the cavity is a ball whose vertices and constrained faces all lie
// on its boundary. Bowyer-Watson's cavity in a Delaunay mesh always is; once
// unconditional splits have left faces that are not locally Delaunay (flips
// can get stuck) or shrink_to_star has cut tets out or taken tets in, it may
// touch itself along an edge or at a vertex, or close around a vertex, and
// the cone from p then overlaps itself (a face of three tets) or drops the
// vertex. With every boundary face seen from p (cavity_is_star), the cone of
// a ball's boundary fills the ball exactly once: the boundary's winding
// number is 1 inside and 0 outside. (Checking only the cavities that
// shrink_to_star changed or that have an edge in more than two boundary
// faces let an invalid mesh through on plate_holes_binary.stl.)
bool Refiner::cavity_is_ball() {
  // The cavity's faces towards the rest of the mesh (bnd_, whose edges
  // collect_boundary() counted in bnd_edges_) and the open faces it splits
  // (a point on the domain's boundary): together a sphere. Each edge must
  // lie in exactly two of them; counted in hash tables, not by sorting, as
  // every insertion with the pass on checks its cavity.
  std::vector<std::array<VertexId, 3>>& open = ball_faces_;
  open.clear();
  for (TetId t : cav_)
    for (int i = 0; i < 4; ++i) {
      const HalfFace hf = make_hf(t, i);
      if (m_.adjacent(hf) == kNoHalfFace && removed(hf)) open.push_back(face_of(hf));
    }
  const BoundaryEdges* edges = &bnd_edges_;
  if (!open.empty()) {  // bnd_edges_ lacks the open faces' edges: a second table holds all
    ball_edges_.reset(3 * (bnd_.size() + open.size()));
    for (const BoundaryFace& f : bnd_) add_face_edges(ball_edges_, {f.a, f.b, f.c});
    for (const auto& f : open) add_face_edges(ball_edges_, f);
    edges = &ball_edges_;
  }
  if (edges->crowded()) return false;
  for (uint32_t u : edges->used())
    if (edges->slot(u).count != 2) return false;
  // The vertices of those faces, each marked once.
  if (++ball_stamp_ == 0) ball_mark_.assign(ball_mark_.size(), 0), ball_stamp_ = 1;
  if (ball_mark_.size() < m_.num_vertices()) ball_mark_.resize(m_.num_vertices(), 0);
  size_t vertices = 0;
  auto mark = [&](VertexId v) {
    if (ball_mark_[v] != ball_stamp_) ball_mark_[v] = ball_stamp_, ++vertices;
  };
  for (const BoundaryFace& f : bnd_) mark(f.a), mark(f.b), mark(f.c);
  for (const auto& f : open) mark(f[0]), mark(f[1]), mark(f[2]);
  // Euler's formula of a sphere: V - E + F = 2.
  if (vertices + bnd_.size() + open.size() != edges->used().size() + 2) return false;
  for (TetId t : cav_) {
    const VertexId* tv = m_.tet_vertices(t);
    for (int i = 0; i < 4; ++i) {
      if (ball_mark_[tv[i]] != ball_stamp_) return false;
      const HalfFace hf = make_hf(t, i);
      const HalfFace nb = m_.adjacent(hf);
      if (tag(hf) != kNoTag && !removed(hf) && nb != kNoHalfFace &&
          (m_.tflag[hf_tet(nb)] & kTetInCavity))
        return false;
    }
  }
  return true;
}

// ---------------------------------------------------------------------------
// Lawson flips
// ---------------------------------------------------------------------------

// Face hf is not constrained, has a tet beyond, and that tet's far vertex
// lies strictly inside the circumsphere of hf's tet (exact, unperturbed, as
// validate() checks).
bool Refiner::not_delaunay(HalfFace hf) const {
  if (tag(hf) != kNoTag) return false;
  const HalfFace nb = m_.adjacent(hf);
  if (nb == kNoHalfFace) return false;
  const VertexId* tv = m_.tet_vertices(hf_tet(hf));
  return pred::insphere(pt(tv[0]), pt(tv[1]), pt(tv[2]), pt(tv[3]), pt(m_.opposite(nb))) > 0;
}

// Replaces live tets `old` by `fresh` (the same region, one region
// attribute): constraint tags of the outer faces carry over, the new tets go
// on the refinement queue and their faces on the flip queue.
bool Refiner::replace_tets(const std::vector<TetId>& old,
                           const std::vector<std::array<VertexId, 4>>& fresh) {
  if (!cm_.replace_region(old, fresh, created_)) return false;
  for (TetId t : created_)  // their neighbours' faces now face new tets (flip_to_delaunay)
    for (int i = 0; i < 4; ++i) {
      const HalfFace nb = m_.adjacent(make_hf(t, i));
      if (nb != kNoHalfFace) m_.tflag[hf_tet(nb)] &= static_cast<uint8_t>(~kTetFlipClean);
    }
  ++commits_;
  touched_.resize(m_.num_vertices(), 0);
  for (TetId t : created_) {
    for (int i = 0; i < 4; ++i) {
      touched_[m_.vertex(t, i)] = commits_;
      flip_queue_.push_back(make_hf(t, i));
    }
    queue_.push_back(t);
  }
  return true;
}

// The 2-3 flip of face hf: its two tets become three around the edge
// joining their far vertices, when all three are positive and not flat.
bool Refiner::flip23(HalfFace hf) {
  const TetId t = hf_tet(hf);
  const int face = static_cast<int>(hf & 3u);
  const VertexId e = m_.opposite(m_.adjacent(hf));
  const VertexId* tv = m_.tet_vertices(t);
  std::vector<std::array<VertexId, 4>> fresh;
  for (int k = 0; k < 3; ++k) {
    std::array<VertexId, 4> n{tv[0], tv[1], tv[2], tv[3]};
    n[kFaceVertex[face][k]] = e;
    if (pred::orient3d(pt(n[0]), pt(n[1]), pt(n[2]), pt(n[3])) <= 0 ||
        numerically_flat(pt(n[0]), pt(n[1]), pt(n[2]), pt(n[3])))
      return false;
    fresh.push_back(n);
  }
  return replace_tets({t, hf_tet(m_.adjacent(hf))}, fresh);
}

// The 3-2 flip: an edge xy of face hf with exactly three tets around it
// (the two of hf and a third holding both far vertices d and e), no
// subsegment and no constrained face through it, becomes the face (z d e)
// between two tets, when both are positive and not flat.
bool Refiner::flip32(HalfFace hf) {
  const TetId t = hf_tet(hf);
  const VertexId d = m_.opposite(hf), e = m_.opposite(m_.adjacent(hf));
  const auto f = face_of(hf);
  for (int k = 0; k < 3; ++k) {
    const VertexId x = f[k], y = f[(k + 1) % 3], z = f[(k + 2) % 3];
    if (is_subsegment(x, y)) continue;
    bool closed = false;
    if (!cm_.edge_ring(t, x, y, ring_, &closed) || !closed || ring_.size() != 3) continue;
    bool free = true;
    for (TetId u : ring_) {
      const VertexId* uv = m_.tet_vertices(u);
      for (int i = 0; i < 4; ++i)
        if (uv[i] != x && uv[i] != y && tag(make_hf(u, i)) != kNoTag) free = false;
    }
    if (!free) continue;
    std::array<VertexId, 4> a{z, d, e, x}, b{z, e, d, y};
    if (pred::orient3d(pt(a[0]), pt(a[1]), pt(a[2]), pt(a[3])) < 0) std::swap(a[1], a[2]), std::swap(b[1], b[2]);
    bool ok = true;
    for (const auto& n : {a, b})
      ok = ok && pred::orient3d(pt(n[0]), pt(n[1]), pt(n[2]), pt(n[3])) > 0 &&
           !numerically_flat(pt(n[0]), pt(n[1]), pt(n[2]), pt(n[3]));
    if (ok) return replace_tets(ring_, {a, b});
  }
  return false;
}

// Lawson's flips on the faces in flip_queue_ until each is locally
// Delaunay or cannot be flipped (3D flips can get stuck; what is left is
// counted at the end of refinement). The queue holds each face from both
// sides (its tets' four faces each, pushed k = 0..3 and so popped 3..0); a
// tet whose four faces were all found locally Delaunay is marked
// (kTetFlipClean), and its faces are not tested again from the other side:
// for two positive tets the test from either side is the same lifted
// determinant. A flip unmarks the tets beside the tets it makes (their
// neighbours changed); the marks go at the end.
void Refiner::flip_to_delaunay() {
  TetId run = kNone;  // the tet whose faces were popped last, all locally Delaunay
  int run_faces = 0;
  for (size_t n = 0; !flip_queue_.empty() && n < kMaxWalk; ++n) {
    const HalfFace hf = flip_queue_.back();
    flip_queue_.pop_back();
    const TetId t = hf_tet(hf);
    if (m_.is_dead(t)) {
      run = kNone;
      continue;
    }
    const HalfFace nb = m_.adjacent(hf);
    if ((nb != kNoHalfFace && (m_.tflag[hf_tet(nb)] & kTetFlipClean)) || !not_delaunay(hf)) {
      note_delaunay_face(t, static_cast<int>(hf & 3u), run, run_faces);
      continue;
    }
    run = kNone;
    if (!flip23(hf)) flip32(hf);
  }
  flip_queue_.clear();
  for (TetId t : flip_clean_) m_.tflag[t] &= static_cast<uint8_t>(~kTetFlipClean);
  flip_clean_.clear();
}

// Face k of tet t was found locally Delaunay: after faces 3, 2, 1, 0 of
// one tet in a row (the order flip_to_delaunay pops them in), t is marked.
void Refiner::note_delaunay_face(TetId t, int k, TetId& run, int& run_faces) {
  if (k == 3) {
    run = t, run_faces = 1;
    return;
  }
  if (run != t || k != 3 - run_faces) {
    run = kNone;
    return;
  }
  if (++run_faces == 4) {
    m_.tflag[t] |= kTetFlipClean;
    flip_clean_.push_back(t);
    run = kNone;
  }
}

// The boundary edges of the split subfaces' region, per facet (edges in
// one subface of the region only), but the split subsegment sa-sb: the new
// subfaces are p with each of them.
void Refiner::region_boundary(VertexId sa, VertexId sb) {
  rim_.clear();
  for (const Subface& s : region_)
    for (int k = 0; k < 3; ++k) {
      const VertexId x = s.v[k], y = s.v[(k + 1) % 3];
      if ((x == sa && y == sb) || (x == sb && y == sa)) continue;
      rim_.push_back({edge_key(x, y), s.tag});
    }
  std::sort(rim_.begin(), rim_.end());
  size_t out = 0;
  for (size_t i = 0; i < rim_.size();) {
    size_t j = i;
    while (j < rim_.size() && rim_[j] == rim_[i]) ++j;
    if (j - i == 1) rim_[out++] = rim_[i];
    i = j;
  }
  rim_.resize(out);
}

// Every rim edge must be an edge of the cavity boundary, so that the new
// subface through it and p exists.
bool Refiner::region_edges_on_boundary() {
  for (const auto& e : rim_)
    if (!on_boundary(e.first)) return false;
  return true;
}

// The cone's faces through p between two new tets must be locally Delaunay
// (exact, unperturbed, as validate() checks). Bowyer-Watson guarantees it
// for a cavity of tets in conflict bounded by faces that are not
// constrained; next to a constrained face the cavity stops at, a vertex
// beyond a neighbouring new tet may lie in the new tet's circumsphere (the
// constraint is encroached), and the tets beside split subfaces join the
// cavity without the test (a facet point rounded off its plane may not be
// in conflict with them). Such an insertion is not done; the constrained
// face at fault (if any) is named for splitting.
bool Refiner::cone_is_delaunay(const double* p) {
  fault_ = false;
  if (!bnd_edges_.crowded()) return cone_is_delaunay_paired(p);
  std::vector<SideRec>& sides = sides_;
  sides.clear();
  for (uint32_t i = 0; i < bnd_.size(); ++i) {
    const VertexId v[3] = {bnd_[i].a, bnd_[i].b, bnd_[i].c};
    for (int k = 0; k < 3; ++k) sides.push_back({edge_key(v[k], v[(k + 1) % 3]), i, v[(k + 2) % 3]});
  }
  std::sort(sides.begin(), sides.end(),
            [](const SideRec& x, const SideRec& y) {
              // A total order: std::sort differs between standard libraries
              // on ties, and native and WASM must split the same faces.
              return x.key != y.key ? x.key < y.key : x.face < y.face;
            });
  for (size_t i = 0; i + 1 < sides.size(); ++i) {
    if (sides[i].key != sides[i + 1].key) continue;
    const BoundaryFace& f = bnd_[sides[i].face];
    const BoundaryFace& g = bnd_[sides[i + 1].face];
    if (cone_face_fails(f, sides[i + 1].third, p)) return name_cone_fault(f, g);
  }
  return true;
}

// Whether the cone face between the new tets on boundary faces f and g (g's
// far vertex `third`) is not locally Delaunay. One test decides: both new
// tets are positive (cavity_is_star), and for two positive tets sharing a
// face the insphere test of either with the other's far vertex is the same
// lifted determinant, so the same sign.
bool Refiner::cone_face_fails(const BoundaryFace& f, VertexId third, const double* p) const {
  return pred::insphere(pt(f.a), pt(f.b), pt(f.c), p, pt(third)) > 0;
}

// Names the constrained one of f and g (if any) for splitting; false.
bool Refiner::name_cone_fault(const BoundaryFace& f, const BoundaryFace& g) {
  const BoundaryFace& c = f.tag != kNoTag ? f : g;
  split_face_ = {c.own, c.tag, {c.a, c.b, c.c}};
  fault_ = c.tag != kNoTag;
  return false;
}

// cone_is_delaunay when every boundary edge lies in at most two boundary
// faces: the pairs come from bnd_edges_. The face named is the one the
// sorted sides would name first (the smallest edge key that fails), so the
// result does not depend on the hash table's order.
bool Refiner::cone_is_delaunay_paired(const double* p) {
  const BoundaryEdges::Slot* worst = nullptr;  // the failing edge of smallest key
  for (uint32_t u : bnd_edges_.used()) {
    const BoundaryEdges::Slot& e = bnd_edges_.slot(u);
    if (e.count != 2 || (worst && e.key > worst->key)) continue;
    const BoundaryFace& g = bnd_[e.side[1] / 3];
    const uint32_t k = e.side[1] % 3;
    const VertexId third = k == 0 ? g.c : k == 1 ? g.a : g.b;
    if (cone_face_fails(bnd_[e.side[0] / 3], third, p)) worst = &e;
  }
  return !worst || name_cone_fault(bnd_[worst->side[0] / 3], bnd_[worst->side[1] / 3]);
}

void Refiner::clear_cavity() {
  for (TetId t : cav_) m_.tflag[t] &= static_cast<uint8_t>(~kTetInCavity);
  cav_.clear();
  region_.clear();
  removed_.clear();
}

// The faces through the new vertex of the cone's tets (cone[i] on bnd_[i]),
// glued in pairs by the boundary edge they hold, and the new subfaces (the
// new vertex with each rim edge) tagged. Boundary edge k of face i, (v_k,
// v_k+1) of (a, b, c), is opposite vertex (k + 2) % 3 in its tet (a, b, c,
// new). bnd_edges_ pairs the faces when no edge lies in more than two
// boundary faces (collect_boundary), without sorting; else they are sorted.
void Refiner::glue_cone(const TetId* cone) {
  auto side_hf = [&](uint32_t side) { return make_hf(cone[side / 3], static_cast<int>((side % 3 + 2) % 3)); };
  if (!bnd_edges_.crowded()) {
    for (uint32_t u : bnd_edges_.used()) {
      const BoundaryEdges::Slot& e = bnd_edges_.slot(u);
      if (e.count == 2)
        m_.glue(side_hf(e.side[0]), side_hf(e.side[1]));
      else
        m_.open_face(side_hf(e.side[0]));
    }
    for (const auto& e : rim_) {
      const BoundaryEdges::Slot* s = bnd_edges_.find(e.first);
      if (!s) continue;
      for (uint32_t k = 0; k < s->count; ++k) hfc_[side_hf(s->side[k])] = e.second;
    }
    return;
  }
  struct Pending {
    uint64_t key;
    HalfFace hf;
  };
  std::vector<Pending> pending;
  pending.reserve(3 * bnd_.size());
  for (size_t i = 0; i < bnd_.size(); ++i) {
    const VertexId abc[3] = {bnd_[i].a, bnd_[i].b, bnd_[i].c};
    for (int k = 0; k < 3; ++k)
      pending.push_back({edge_key(abc[(k + 1) % 3], abc[(k + 2) % 3]), make_hf(cone[i], k)});
  }
  std::sort(pending.begin(), pending.end(),
            [](const Pending& x, const Pending& y) { return x.key < y.key; });
  for (size_t i = 0; i < pending.size();) {
    if (i + 1 < pending.size() && pending[i + 1].key == pending[i].key) {
      m_.glue(pending[i].hf, pending[i + 1].hf);
      i += 2;
    } else {
      m_.open_face(pending[i].hf);
      ++i;
    }
  }
  for (const auto& e : rim_) {
    auto it = std::lower_bound(pending.begin(), pending.end(), e.first,
                               [](const Pending& a, uint64_t k2) { return a.key < k2; });
    for (; it != pending.end() && it->key == e.first; ++it) hfc_[it->hf] = e.second;
  }
}

// Replaces the cavity by the cone of its boundary to the new vertex.
VertexId Refiner::commit(const double* p, Where where, int64_t parent, VertexId sa, VertexId sb,
                         double scale) {
  const VertexId v = new_vertex(p, where, parent);
  if (scale_.size() <= v) scale_.resize(v + 1, HUGE_VAL);
  scale_[v] = scale;
  ++commits_;
  touched_.resize(m_.num_vertices(), 0);
  for (const BoundaryFace& f : bnd_) touched_[f.a] = touched_[f.b] = touched_[f.c] = commits_;
  touched_[v] = commits_;
  for (TetId t : cav_) m_.free_tet(t);
  cav_.clear();
  for (const BoundaryFace& f : bnd_) {
    const TetId t = new_tet();
    m_.set_tet(t, f.a, f.b, f.c, v);
    attr_[t] = f.attr;
    const HalfFace base = make_hf(t, 3);
    hfc_[base] = f.tag;
    if (f.outside != kNoHalfFace)
      m_.glue(base, f.outside);
    else
      m_.open_face(base);
    queue_.push_back(t);
  }
  glue_cone(queue_.data() + (queue_.size() - bnd_.size()));
  for (size_t i = queue_.size() - bnd_.size(); i < queue_.size(); ++i) {
    const TetId t = queue_[i];
    for (int k = 0; k < 4; ++k) m_.set_vertex_tet(m_.vertex(t, k), t);
  }
  if (where == Where::Segment) {
    const uint32_t seg = *subseg_.find(edge_key(sa, sb));
    subseg_.erase(edge_key(sa, sb));
    subseg_.set(edge_key(sa, v), seg);
    subseg_.set(edge_key(v, sb), seg);
  }
  region_.clear();
  removed_.clear();
  return v;
}

// The distance from p to the nearest vertex of its cavity's boundary: its
// insertion radius (the cavity holds the vertices nearest to p; `nearest`
// gets the one). `scale`
// gets p's local scale: the smallest scale(w) + kScaleSlope |pw| over those
// vertices w (init_scales).
double Refiner::nearest_vertex(const double* p, double& scale, VertexId& nearest) const {
  double d = HUGE_VAL, s = HUGE_VAL;
  const Vec3 q = to_vec(p);
  nearest = kNone;
  for (const BoundaryFace& f : bnd_)
    for (VertexId v : {f.a, f.b, f.c}) {
      const double dv = dist(q, to_vec(pt(v)));
      if (dv < d) d = dv, nearest = v;
      s = std::min(s, scale_[v] + kScaleSlope * dv);
    }
  scale = s;
  return d;
}

// Whether vertex w lies on a feature of the PLC that does not meet input
// segment `segment`: an input vertex other than its ends, or a point of a
// segment with no end in common with it. A split point's distance to such
// a vertex is bounded below by the distance between the two features, a
// constant of the input (the local feature size of Shewchuk's analysis),
// not by the chain of insertions that led to it, so the radius rule, which
// guards against such chains, need not apply. Thin strips between parallel
// segments (the facets of a fillet or a chamfer) need split points that
// close to the other side.
bool Refiner::apart_from_segment(VertexId w, int64_t segment) const {
  if (w == kNone || segment < 0 || static_cast<size_t>(segment) >= segments_.size()) return false;
  const auto& s = segments_[static_cast<size_t>(segment)];
  if (where_[w] == Where::Input) return w != s[0] && w != s[1] && w < plc_.points.size();
  if (where_[w] != Where::Segment) return false;
  const int64_t other = cm_.parent[w];
  if (other < 0 || static_cast<size_t>(other) >= segments_.size()) return false;
  const auto& o = segments_[static_cast<size_t>(other)];
  return o[0] != s[0] && o[0] != s[1] && o[1] != s[0] && o[1] != s[1];
}

// The local scale of the CDT's vertices: the shortest edge at each (an
// estimate of the local feature size there). A new vertex p gets the
// smallest scale(w) + kScaleSlope |pw| over its cavity's vertices w
// (nearest_vertex), so no scale drops below the smallest of the CDT's:
// insert() refuses a point closer than kScaleFactor times its scale to
// another vertex, so all points stay a fixed distance apart and refinement
// stops (a packing argument) whatever it inserted before.
void Refiner::init_scales() {
  scale_.assign(m_.num_vertices(), HUGE_VAL);
  for (TetId t = 0; t < m_.num_tet_slots(); ++t) {
    if (m_.is_dead(t)) continue;
    const VertexId* v = m_.tet_vertices(t);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        const double l = dist(to_vec(pt(v[i])), to_vec(pt(v[j])));
        scale_[v[i]] = std::min(scale_[v[i]], l);
        scale_[v[j]] = std::min(scale_[v[j]], l);
      }
  }
}

// Inserts p (on segment sa-sb, in the facet of the seed subfaces in
// region_, or in the volume from the seed tet in cav_). False when it was
// not inserted; *verdict then says whether a constraint should be split
// first (split_face_ / split_a_, split_b_).
bool Refiner::insert(const double* p, Where where, int64_t parent, VertexId sa, VertexId sb,
                     double floor, Verdict* verdict) {
  *verdict = Verdict::Reject;
  bool floor_rejected = false;
  double scale = HUGE_VAL;  // p's local scale (nearest_vertex)
  const VertexId pid = static_cast<VertexId>(m_.num_vertices());
  if (!region_.empty() && !grow_subface_region(p, pid, sa, sb)) {
    clear_cavity();
    return false;
  }
  for (HalfFace hf : removed_) {
    const TetId t = hf_tet(hf);
    if (!(m_.tflag[t] & kTetInCavity)) m_.tflag[t] |= kTetInCavity, cav_.push_back(t);
  }
  const size_t seeds = cav_.size();
  const size_t encroached_before = encroached_.size();
  const bool unconditional = unconditional_splits_ && where != Where::Volume;
  if (!grow_cavity(p, pid, where)) {
    *verdict = Verdict::SplitSubface;
    clear_cavity();
    return false;
  }
  collect_boundary();
  *verdict = check_constraints(p, where, sa, sb);
  if (*verdict == Verdict::Ok) {
    region_boundary(sa, sb);
    if (!cavity_is_star(p) &&
        !(unconditional && shrink_to_star(p, seeds) &&
          (*verdict = check_constraints(p, where, sa, sb)) == Verdict::Ok))
      *verdict = fault_ ? Verdict::SplitSubface : Verdict::Reject;
    else if (!region_edges_on_boundary() || (unconditional_splits_ && !cavity_is_ball()))
      *verdict = Verdict::Reject;
    else if (!cone_is_delaunay(p) && !unconditional && !at_locked_face() &&
             !far_fault(p))  // a constrained face is encroached
      *verdict = fault_ ? Verdict::SplitSubface : Verdict::Reject;
    else if (VertexId w = kNone; [&] {
               const double near = nearest_vertex(p, scale, w);
               const bool radius_rule = !(where == Where::Segment && apart_from_segment(w, parent));
               return (radius_rule && near < kFloorFactor * floor) || near < scale_factor_ * scale;
             }())
      *verdict = Verdict::Reject, floor_rejected = true;
    // An unconditional split point whose cone is not Delaunay at a
    // constrained face goes in; that face is split after it.
    if (*verdict == Verdict::Ok && unconditional && fault_) encroached_.push_back(split_face_.v);
  }
  if (*verdict != Verdict::Ok) {
    encroached_.resize(encroached_before);
    if (attempt_ != kNoAttempt && !floor_rejected) remember_failure(*verdict);
    clear_cavity();
    return false;
  }
  const size_t first_new = queue_.size();
  commit(p, where, parent, sa, sb, scale);
  if (unconditional) {  // the cone may hold faces that are not locally Delaunay
    for (size_t i = first_new; i < queue_.size(); ++i)
      for (int k = 0; k < 4; ++k) flip_queue_.push_back(make_hf(queue_[i], k));
    flip_to_delaunay();
  }
  return true;
}

// A split of a subsegment or subface that failed for a reason other than
// the radius rule fails again, with the same verdict, as long as no
// insertion has touched a vertex of its cavity: the cavity's tets and the
// tets beyond its boundary are then the same, and every test but the radius
// rule looks at those alone. Bad tets near one small feature ask for the
// same splits again and again (most insertion attempts can be such
// repeats), so the verdict is kept with the cavity's vertices and the time.
void Refiner::remember_failure(Verdict verdict) {
  Failure& f = failures_[attempt_];
  f.time = commits_;
  f.verdict = verdict;
  f.fault = split_face_;
  f.split_a = split_a_, f.split_b = split_b_;
  f.vertices.clear();
  for (const BoundaryFace& bf : bnd_) f.vertices.insert(f.vertices.end(), {bf.a, bf.b, bf.c});
  for (const Subface& r : region_) f.vertices.insert(f.vertices.end(), r.v.begin(), r.v.end());
}

// The remembered verdict of a split, if it still holds (split_face_,
// split_a_ and split_b_ are set as the failed insertion set them).
bool Refiner::known_failure(const SplitKey& key, Verdict& verdict) {
  const auto it = failures_.find(key);
  if (it == failures_.end()) return false;
  const Failure& f = it->second;
  for (VertexId v : f.vertices)
    if (v < touched_.size() && touched_[v] > f.time) return false;
  verdict = f.verdict;
  split_face_ = f.fault;
  split_a_ = f.split_a, split_b_ = f.split_b;
  return true;
}

// ---------------------------------------------------------------------------
// Splits
// ---------------------------------------------------------------------------

// Splits subsegment ab: at its midpoint, or, when exactly one end is an input
// vertex, on the sphere around it whose radius is the power of two nearest to
// half the length (Shewchuk's concentric shells: segments meeting at a small
// angle are then split at the same distances and stop encroaching on each
// other). Not when the split point would come closer than lmin to a or b.
bool Refiner::split_subsegment(VertexId a, VertexId b, double lmin, int depth) {
  const uint32_t* segment = subseg_.find(edge_key(a, b));
  if (!segment) return false;
  if (!needle_side_.empty() && needle_side_[*segment]) {
    needle_refused_ = true;
    return false;
  }
  const double len = dist(to_vec(pt(a)), to_vec(pt(b)));
  double f = 0.5;
  const bool ia = where_[a] == Where::Input, ib = where_[b] == Where::Input;
  if (ia != ib) {
    const double shell = std::ldexp(1.0, static_cast<int>(std::lround(std::log2(len / 2))));
    double g = shell / len;
    if (g > 0.25 && g < 0.75) f = ia ? g : 1 - g;
    // A shell point too close to an end for the floor below falls back to
    // the midpoint, which may not be: the shell only matters where segments
    // meet at a small angle, and a bad tet left for it costs more.
    if (std::min(f, 1 - f) * len < kSplitFloorFactor * lmin) f = 0.5;
  }
  if (std::min(f, 1 - f) * len < kSplitFloorFactor * lmin) return false;
  const SplitKey key = {std::min(a, b), std::max(a, b), kNone};
  Verdict known;
  if (known_failure(key, known))
    return known == Verdict::SplitSubface && depth < kMaxSplitDepth &&
           split_subface(Subface(split_face_), lmin, depth + 1);
  Vec3 q;
  double tf;
  double xyz[3];
  if (point_exactly_on_segment(pt(a), pt(b), f, kLineBits, kLineMinBits, q, tf)) {
    xyz[0] = q.x, xyz[1] = q.y, xyz[2] = q.z;
  } else {
    // Rounded: near, not on, the segment's line; the chain, not the
    // coordinates, says which subsegments make the segment (as in §5's
    // split points), and the star test keeps every new tet positive.
    for (int k = 0; k < 3; ++k) xyz[k] = pt(a)[k] + f * (pt(b)[k] - pt(a)[k]);
  }
  const TetId t0 = m_.find_edge(a, b);
  if (t0 == kNone) return false;
  subfaces_at_edge(a, b, t0, region_);
  if (!edge_ring(t0, a, b, ring_)) {
    region_.clear();
    return false;
  }
  for (TetId t : ring_) m_.tflag[t] |= kTetInCavity, cav_.push_back(t);
  Verdict verdict;
  attempt_ = key;
  const bool done = insert(xyz, Where::Segment, *segment, a, b, lmin, &verdict);
  attempt_ = kNoAttempt;
  if (!done)
    return verdict == Verdict::SplitSubface && depth < kMaxSplitDepth &&
           split_subface(Subface(split_face_), lmin, depth + 1);
  ++res_.stats.refine_segment;
  return true;
}

// The facet corners the seditious-edge rule looks at, and the sides of
// needles (kNeedleReach). Thresholds on the input, so doubles do; the PLC's
// points are the mesh's first vertices.
void Refiner::init_small_corners() {
  const double cos_low = std::cos(kWedgeAngle * 3.14159265358979323846 / 180);
  const double cos_high = std::cos(kSeditiousAngle * 3.14159265358979323846 / 180);
  const double cos_tiny = std::cos(kTinyCorner * 3.14159265358979323846 / 180);
  std::unordered_map<uint64_t, uint32_t> segment_of;  // edge_key of its ends -> segment
  for (uint32_t k = 0; k < segments_.size(); ++k) segment_of[edge_key(segments_[k][0], segments_[k][1])] = k;
  Vec3 lo = plc_.points.empty() ? Vec3{0, 0, 0} : plc_.points[0], hi = lo;
  for (const Vec3& p : plc_.points)
    lo = {std::min(lo.x, p.x), std::min(lo.y, p.y), std::min(lo.z, p.z)},
    hi = {std::max(hi.x, p.x), std::max(hi.y, p.y), std::max(hi.z, p.z)};
  const double reach = kNeedleReach * dist(lo, hi);
  needle_side_.assign(unconditional_splits_ ? segments_.size() : 0, 0);
  needle_end_.assign(unconditional_splits_ ? plc_.points.size() : 0, 0);
  for (const Facet& f : plc_.facets)
    for (const auto& loop : f.loops)
      for (size_t i = 0; i < loop.size(); ++i) {
        const uint32_t apex = loop[i], a = loop[(i + loop.size() - 1) % loop.size()],
                       b = loop[(i + 1) % loop.size()];
        const Vec3 u = plc_.points[a] - plc_.points[apex], w = plc_.points[b] - plc_.points[apex];
        const double c = dot(u, w), len = norm(u) * norm(w);
        if (a == b || !(c > cos_high * len)) continue;
        const auto sa = segment_of.find(edge_key(apex, a)), sb = segment_of.find(edge_key(apex, b));
        if (!needle_side_.empty() && c > cos_low * len && std::max(norm(u), norm(w)) <= reach) {
          const auto sc = loop.size() == 3 ? segment_of.find(edge_key(a, b)) : segment_of.end();
          for (const auto& it : {sa, sb, sc})
            if (it != segment_of.end()) {
              needle_side_[it->second] = 1;
              needle_end_[segments_[it->second][0]] = needle_end_[segments_[it->second][1]] = 1;
            }
        }
        if (!(c <= cos_low * len || c > cos_tiny * len)) continue;
        if (sa != segment_of.end() && sb != segment_of.end())
          small_corners_.insert(edge_key(sa->second, sb->second));
      }
}

// Whether vertex v is an end or a split point of a needle's side.
bool Refiner::on_needle(VertexId v) const {
  if (v < needle_end_.size()) return needle_end_[v] != 0;
  const int64_t s = cm_.parent[v];
  return where_[v] == Where::Segment && s >= 0 && static_cast<size_t>(s) < needle_side_.size() &&
         needle_side_[static_cast<size_t>(s)];
}

// With the pass on (the result need not be a CDT), a circumcentre p whose
// cone failed the Delaunay test at constrained face F (split_face_) goes in
// when F is small and far from it: p at least kFarFault of F's circumradii
// from F's circumcentre, and no vertex of F on a needle. The cone's tet on F
// is then a needle whose circumsphere takes in a vertex beside F; splitting
// F refines the boundary where no bad tet is, and the attempt has grown a
// cavity of hundreds of tets for it. On spot.obj 2,613 circumcentres failed
// so, at F 4 or more circumradii away in 2,225 of them, with 757 tets in
// their cavities on average: refinement took 0.38 s (TetGen's whole
// run: 0.35 s); with this rule 0.09 s, and fewer tets above ratio 2 (2.04%
// -> 1.80%). At needles the rule is not applied: there it left more slivers
// (dragon_decimated: 32 -> 47 tets below 10 degrees away from small input
// angles; tests/bench/README.md).
bool Refiner::far_fault(const double* p) const {
  if (!unconditional_splits_ || !fault_) return false;
  const auto& v = split_face_.v;
  for (VertexId w : v)
    if (on_needle(w)) return false;
  Vec3 o;
  double r;
  return triangle_circle(pt(v[0]), pt(v[1]), pt(v[2]), o, r) && dist(to_vec(p), o) >= kFarFault * r;
}

// Whether t's shortest edge is seditious (kSeditiousAngle): its ends are
// split points of two segments that are the sides of a small facet corner,
// at about the same distance from its apex.
bool Refiner::has_seditious_edge(TetId t, const TetShape& shape) const {
  if (small_corners_.empty()) return false;
  const VertexId* v = m_.tet_vertices(t);
  const VertexId u = v[shape.ends[0]], w = v[shape.ends[1]];
  if (where_[u] != Where::Segment || where_[w] != Where::Segment) return false;
  const int64_t su = cm_.parent[u], sw = cm_.parent[w];
  if (su == sw || su < 0 || sw < 0 ||
      !small_corners_.count(edge_key(static_cast<uint32_t>(su), static_cast<uint32_t>(sw))))
    return false;
  const std::array<VertexId, 2>& a = segments_[su];
  const std::array<VertexId, 2>& b = segments_[sw];
  const VertexId apex = a[0] == b[0] || a[0] == b[1] ? a[0] : a[1];
  const double du = dist(to_vec(pt(u)), to_vec(pt(apex))), dw = dist(to_vec(pt(w)), to_vec(pt(apex)));
  return std::fabs(du - dw) <= kSeditiousSpread * std::max(du, dw);
}

void Refiner::init_wedges() {
  wedges_ = domain_wedges(plc_, cm_);
  for (uint32_t k = 0; k < wedges_.size(); ++k)
    for (uint32_t f : wedges_[k].f) wedges_of_[f].push_back(k);
}

// Whether a split point c of a subface of facet `tag` (circumradius r)
// lies where a thin wedge the facet bounds is thinner than r: tets across
// the wedge there are slivers whatever point goes in, and such points only
// move them off the wedge's edge (on cheburashka, 1,471 of the 1,605 tets
// below 10 degrees that touched no small input angle lay between two such
// facets; none with refinement off). Farther from the edge, where the
// wedge is thicker, or beyond the narrower facet's reach (a scan's cap of
// 172 degrees folded onto a large triangle bounds a wedge only as far as
// the cap reaches; freezing all of the large one left slivers of 0.003
// degrees on nefertiti), the facet is split as any other.
bool Refiner::in_thin_wedge(uint32_t tag, const Vec3& c, double r) const {
  if (wedges_of_.empty() || tag == kNoTag || is_hull_tag(tag)) return false;
  const auto it = wedges_of_.find(tag - 1);
  if (it == wedges_of_.end()) return false;
  for (uint32_t k : it->second) {
    const WedgePair& w = wedges_[k];
    const Vec3 e = w.b - w.a, d = c - w.a;
    const double t = std::clamp(dot(d, e) / dot(e, e), 0.0, 1.0);
    const double off = norm(d - t * e);
    if (off <= w.reach && off * w.sin_angle < r) return true;
  }
  return false;
}

// Splits subface s at its circumcentre, unless that lies beyond a
// subsegment of the facet or encroaches upon one (then the subsegment is
// split), comes closer than lmin to the subface's vertices or lies in a
// thin wedge (in_thin_wedge).
bool Refiner::split_subface(const Subface& s, double lmin, int depth) {
  Vec3 c;
  double r;
  if (!triangle_circle(pt(s.v[0]), pt(s.v[1]), pt(s.v[2]), c, r) || r < kSplitFloorFactor * lmin) return false;
  if (in_thin_wedge(s.tag, c, r)) return false;
  const double xyz[3] = {c.x, c.y, c.z};
  Subface at;
  VertexId sa = kNone, sb = kNone;
  const Walk w = locate_in_facet(s, xyz, at, sa, sb);
  if (w == Walk::Blocked) return split_subsegment(sa, sb, lmin, depth);
  if (w != Walk::InTet) return false;
  for (VertexId v : at.v)
    if (pt(v)[0] == xyz[0] && pt(v)[1] == xyz[1] && pt(v)[2] == xyz[2]) return false;
  const SplitKey key = sorted_triangle(s.v);
  Verdict verdict;
  if (!known_failure(key, verdict)) {
    region_.assign(1, at);
    const int64_t parent = is_hull_tag(s.tag) ? -1 : static_cast<int64_t>(s.tag - 1);
    const Where where = is_hull_tag(s.tag) ? Where::Volume : Where::Facet;
    attempt_ = key;
    const bool done = insert(xyz, where, parent, kNone, kNone, lmin, &verdict);
    attempt_ = kNoAttempt;
    if (done) {
      ++(where == Where::Facet ? res_.stats.refine_facet : res_.stats.refine_volume);
      return true;
    }
  }
  if (verdict == Verdict::SplitSubsegment) return split_subsegment(split_a_, split_b_, lmin, depth);
  if (verdict == Verdict::SplitSubface && depth < kMaxSplitDepth &&
      sorted_triangle(split_face_.v) != sorted_triangle(s.v))
    return split_subface(Subface(split_face_), lmin, depth + 1);
  return false;
}

// Splits the subfaces an insertion left encroached (shrink_to_star), and
// those their splits leave, until none is left or none can be split. No
// radius-rule floor (lmin 0): a subface left encroached has tets beside it
// that hold the new point in their circumsphere, and only its split removes
// them; the local scale's floor (kEncroachedScaleFactor) keeps points apart.
void Refiner::split_encroached() {
  std::vector<Subface> at;
  for (size_t n = 0; !encroached_.empty() && n < kMaxWalk; ++n) {
    const std::array<VertexId, 3> v = encroached_.back();
    encroached_.pop_back();
    const TetId t0 = m_.find_edge(v[0], v[1]);
    if (t0 == kNone) continue;
    subfaces_at_edge(v[0], v[1], t0, at);
    const auto key = sorted_triangle(v);
    for (const Subface& s : at)
      if (sorted_triangle(s.v) == key) {
        scale_factor_ = kEncroachedScaleFactor;
        split_subface(s, 0);
        scale_factor_ = kScaleFactor;
        break;
      }
  }
}

// A bad tet: its circumcentre goes in when it lies in the domain and
// encroaches upon nothing; else the blocking or encroached constraint is
// split (if the radius rule allows). True when the mesh changed.
bool Refiner::fix_bad_tet(TetId t, const TetShape& shape) {
  const double* c = shape.center;
  if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2])) return false;
  TetId at = kNone;
  HalfFace blocked = kNoHalfFace;
  const Walk w = locate(t, c, at, blocked);
  // The radius rule's length: the shortest edge, or for a tet that is too
  // big but well shaped, half the edge of a regular tet of the largest
  // volume allowed (a bound that does not shrink as refinement goes on).
  double lmin = shape.shortest;
  if (shape.radius <= q_.radius_edge * shape.shortest)
    lmin = std::min(lmin, 0.5 * std::cbrt(6 * std::sqrt(2.0) * volume_limit(attr_[t])));
  if (w == Walk::Blocked) {
    if (tag(blocked) == kNoTag) return false;
    const bool changed = split_subface({blocked, tag(blocked), face_of(blocked)}, lmin);
    split_encroached();
    return changed;
  }
  if (w != Walk::InTet) return false;
  const VertexId* tv = m_.tet_vertices(at);
  for (int i = 0; i < 4; ++i)
    if (pt(tv[i])[0] == c[0] && pt(tv[i])[1] == c[1] && pt(tv[i])[2] == c[2]) return false;
  m_.tflag[at] |= kTetInCavity;
  cav_.assign(1, at);
  Verdict verdict;
  bool changed = false;
  if (insert(c, Where::Volume, -1, kNone, kNone, lmin, &verdict)) {
    ++res_.stats.refine_volume;
    changed = true;
  } else if (verdict == Verdict::SplitSubface) {
    needle_refused_ = false;
    changed = split_subface(split_face_, lmin);
    // split_face_ as the attempt leaves it: the last subface its chain of
    // splits reached (a split's cavity may name another), the one whose
    // split the needle rule refused. Locking the subface named first instead
    // gave the same meshes on seven models but took nefertiti's smallest
    // angle from 0.0126 to 0.0092 degrees (TetGen's: 0.0120).
    if (!changed && needle_refused_) locked_.insert(sorted_triangle(split_face_.v));
  } else if (verdict == Verdict::SplitSubsegment) {
    changed = split_subsegment(split_a_, split_b_, lmin);
  }
  split_encroached();
  return changed;
}

Status Refiner::run(const volatile bool* cancel, const RefineProgress& progress) {
  Status st = cm_.build(plc_, res_);
  if (!st.ok()) return st;
  unconditional_splits_ = q_.min_dihedral > 0;
  segments_ = plc_segments(plc_);
  init_wedges();
  init_small_corners();
  init_scales();
  // Per-region volume bounds (Region::max_volume), by attribute.
  for (const Region& r : plc_.regions)
    if (r.max_volume > 0) region_limits_.push_back({r.attribute, r.max_volume});
  // Default bound on added points: far above what the radius-edge bound
  // needs on the models of tests/data, plus room for the volume bound (about one
  // point per 1/6 of the smallest volume limit, a regular tet's share).
  size_t cap = q_.max_points;
  if (cap == 0) {
    double volume = 0, limit = q_.max_volume > 0 ? q_.max_volume : HUGE_VAL;
    for (const auto& r : region_limits_) limit = std::min(limit, r.second);
    if (std::isfinite(limit))
      for (TetId t = 0; t < m_.num_tet_slots(); ++t) {
        const VertexId* v = m_.tet_vertices(t);
        volume += tet_shape(pt(v[0]), pt(v[1]), pt(v[2]), pt(v[3])).volume;
      }
    const double by_volume = std::isfinite(limit) ? std::min(1e9, 6 * volume / limit) : 0;
    cap = 100 * cm_.old_points + kBasePointCap + static_cast<size_t>(by_volume);
  }

  // Depth first: the CDT's tets in slot order, and after each insertion the
  // tets it made (commit() pushes them on queue_) before the next one, so
  // that refinement works in one place at a time (a breadth-first queue
  // sweeps the whole mesh again and again, in cache misses). A bad tet that
  // survives its fix (a constraint was split instead) waits in `retry`
  // until the tets around have been looked at: retried at once, it leaves
  // more bad tets.
  // With unconditional splits a second sweep follows Lawson flips over the
  // whole mesh. Where the first left faces that are not locally Delaunay, a
  // split point can fail the star test at a tet it must replace (a seed of
  // its cavity), and the bad tet that asked for it was left. In the second
  // sweep the first try at each bad tet left may take the tets beyond such
  // faces into the cavity (shrink_to_star); the tets that insertion makes
  // are refined as before, without it (with it throughout, the decimated
  // scans got 10-25% more tets; tests/bench/README.md).
  std::vector<TetId> tets, retry;
  size_t added = 0;
  double reported = 0;
  const int sweeps = unconditional_splits_ ? 2 : 1;
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    if (sweep > 0) {
      for (TetId t = 0; t < m_.num_tet_slots(); ++t)
        if (!m_.is_dead(t))
          for (int k = 0; k < 4; ++k) flip_queue_.push_back(make_hf(t, k));
      flip_to_delaunay();
      queue_.clear();  // flips queued their tets; the sweep looks at all
    }
    tets.clear();
    for (TetId t = 0; t < m_.num_tet_slots(); ++t)
      if (!m_.is_dead(t)) {
        m_.tflag[t] &= static_cast<uint8_t>(~kTetUser);
        tets.push_back(t);
      }
    size_t next = 0;
    for (size_t step = 0; next < tets.size() || !queue_.empty() || !retry.empty(); ++step) {
      if ((step & 1023) == 0) {
        if (cancel && *cancel)
          return make_error(ErrorCode::Cancelled, "Cancelled during quality refinement.");
        // With the improvement pass, refinement reports up to kRefineShare.
        const double share = q_.min_dihedral > 0 ? kRefineShare : 1.0;
        const double f =
            share * (sweep + static_cast<double>(next) / static_cast<double>(tets.size())) / sweeps;
        if (progress.report && f > reported) progress.report(progress.user, reported = f);
      }
      TetId t;
      if (queue_.empty() && !retry.empty()) {  // in the order they were set aside
        queue_.assign(retry.rbegin(), retry.rend());
        retry.clear();
      }
      if (!queue_.empty()) {
        t = queue_.back();
        queue_.pop_back();
        take_in_ = false;
      } else {
        t = tets[next++];
        take_in_ = sweep > 0;
      }
      if (m_.is_dead(t) || (m_.tflag[t] & kTetUser)) continue;
      TetShape shape;
      if (!is_bad(t, shape)) continue;
      if (has_seditious_edge(t, shape)) {
        m_.tflag[t] |= kTetUser;  // left as it is
        continue;
      }
      if (added >= cap) {
        res_.stats.refine_capped = 1;
        sweep = sweeps;
        break;
      }
      const size_t before = m_.num_vertices();
      if (fix_bad_tet(t, shape)) {
        added += m_.num_vertices() - before;
        if (!m_.is_dead(t)) retry.push_back(t);  // still there: try again later
      } else {
        m_.tflag[t] |= kTetUser;  // left as it is
      }
    }
  }
  take_in_ = false;
  // Bad tets left.
  size_t left = 0, at_corners = 0;
  for (TetId t = 0; t < m_.num_tet_slots(); ++t) {
    TetShape shape;
    if (!m_.is_dead(t) && is_bad(t, shape)) ++left, at_corners += has_seditious_edge(t, shape);
  }
  res_.stats.refine_skipped = left;
  res_.stats.refine_small_angle = at_corners;
  // Unconditional splits may leave faces that are not locally Delaunay where
  // flips got stuck: one more round over the whole mesh, and the result is
  // not called Delaunay if any is left (checked after the improvement pass,
  // which makes it not Delaunay by any change, and then the check is moot).
  if (unconditional_splits_) {
    for (TetId t = 0; t < m_.num_tet_slots(); ++t)
      if (!m_.is_dead(t))
        for (int k = 0; k < 4; ++k) flip_queue_.push_back(make_hf(t, k));
    flip_to_delaunay();
  }

  if (q_.min_dihedral > 0) {
    ImproveCounts counts;
    // The needles' vertices: their sides' ends and split points.
    std::vector<char> needle(needle_side_.empty() ? 0 : m_.num_vertices(), 0);
    for (VertexId v = 0; v < needle.size(); ++v) needle[v] = on_needle(v);
    st = improve_mesh(cm_, q_.min_dihedral, cancel, counts,
                      {progress.report, progress.user, kRefineShare, 1.0},
                      {q_.max_volume, region_limits_}, &needle);
    if (!st.ok()) return st;
    res_.stats.improve_flips = counts.flips;
    res_.stats.improve_smooths = counts.smooths;
    res_.stats.improve_points = counts.inserts;
    if (counts.flips + counts.smooths + counts.inserts > 0) res_.delaunay = false;
  }
  if (unconditional_splits_)
    for (TetId t = 0; t < m_.num_tet_slots() && res_.delaunay; ++t)
      if (!m_.is_dead(t))
        for (int k = 0; k < 4; ++k)
          if (not_delaunay(make_hf(t, k))) res_.delaunay = false;

  cm_.write(plc_, res_);
  return Status::success();
}

}  // namespace

Status refine_quality(const Plc& plc, const QualityOptions& quality, const volatile bool* cancel,
                      const RefineProgress& progress, Result& result) {
  Status st = check_quality_options(quality);
  if (!st.ok()) return st;
  Refiner r(plc, quality, result);
  return r.run(cancel, progress);
}

}  // namespace cdt3d
