// Internal pieces of repair() (repair.cpp drives them, one file per step):
// the PLC under repair with the provenance of every facet, and the steps.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "plc_intersect.hpp"

namespace cdt3d {
namespace repair_steps {

/// The PLC under repair. Every step keeps `source` in step with
/// `plc.facets`: source[f] is the input facet that facet f comes from, so
/// errors, colours and markers can still name the input.
struct Work {
  Plc plc;
  std::vector<uint32_t> source;
  /// Like `source` for `plc.segments`: the input segment of each (step 4
  /// splits segments into pieces).
  std::vector<uint32_t> segment_source;
  std::vector<uint8_t> changed;  ///< per input facet: some step changed it
  std::vector<VertexId> point_of_input;  ///< per input point: its point in `plc`

  void mark(uint32_t input_facet) { changed[input_facet] = 1; }
};

/// Per point of `plc`: 1 when a facet loop or an explicit segment uses it.
std::vector<uint8_t> used_points(const Plc& plc);

// Buckets of the points used by facets or segments (and with `isolated`
// the others too), on a uniform grid. The cell of a coordinate is computed
// in doubles, but monotonically, so a box query covers every point whose
// coordinates lie in the box (repair_tjunction.cpp, and the hot pixels of
// repair_crossing.cpp).
class PointGrid {
 public:
  PointGrid(const Plc& plc, bool isolated) {
    const std::vector<uint8_t> used = used_points(plc);
    std::vector<VertexId> pts;
    for (VertexId v = 0; v < used.size(); ++v)
      if (used[v] || isolated) pts.push_back(v);
    if (pts.empty()) return;
    for (int k = 0; k < 3; ++k) lo_[k] = hi_[k] = (&plc.points[pts[0]].x)[k];
    for (VertexId v : pts)
      for (int k = 0; k < 3; ++k) {
        lo_[k] = std::min(lo_[k], (&plc.points[v].x)[k]);
        hi_[k] = std::max(hi_[k], (&plc.points[v].x)[k]);
      }
    n_ = std::max(1, std::min(256, static_cast<int>(std::cbrt(static_cast<double>(pts.size())))));
    for (int k = 0; k < 3; ++k) scale_[k] = hi_[k] > lo_[k] ? n_ / (hi_[k] - lo_[k]) : 0;
    start_.assign(static_cast<size_t>(n_) * n_ * n_ + 1, 0);
    for (VertexId v : pts) ++start_[cell_of(&plc.points[v].x) + 1];
    for (size_t i = 1; i < start_.size(); ++i) start_[i] += start_[i - 1];
    items_.resize(pts.size());
    std::vector<uint32_t> fill(start_.begin(), start_.end() - 1);
    for (VertexId v : pts) items_[fill[cell_of(&plc.points[v].x)]++] = v;
  }

  /// Calls visit(v) for every used point whose cell meets the box [lo, hi].
  template <class F>
  void query(const double* lo, const double* hi, F&& visit) const {
    if (items_.empty()) return;
    int a[3], b[3];
    for (int k = 0; k < 3; ++k) {
      a[k] = index(lo[k], k);
      b[k] = index(hi[k], k);
    }
    for (int x = a[0]; x <= b[0]; ++x)
      for (int y = a[1]; y <= b[1]; ++y)
        for (int z = a[2]; z <= b[2]; ++z) {
          const size_t c = (static_cast<size_t>(x) * n_ + y) * n_ + z;
          for (uint32_t i = start_[c]; i < start_[c + 1]; ++i) visit(items_[i]);
        }
  }

 private:
  int index(double x, int k) const {
    const double t = (x - lo_[k]) * scale_[k];
    if (!(t > 0)) return 0;
    return std::min(n_ - 1, static_cast<int>(t));
  }
  size_t cell_of(const double* p) const {
    return (static_cast<size_t>(index(p[0], 0)) * n_ + index(p[1], 1)) * n_ + index(p[2], 2);
  }

  double lo_[3] = {0, 0, 0}, hi_[3] = {0, 0, 0}, scale_[3] = {0, 0, 0};
  int n_ = 1;
  std::vector<uint32_t> start_;
  std::vector<VertexId> items_;
};

/// A facet made from part of `from`: one loop, the same marker and source
/// line or record, no facet holes (a part is a plain polygon).
Facet part_of(const Facet& from, std::vector<VertexId> loop);

// Step 1 (repair_clean.cpp): identical points welded, repeated polygon
// vertices dropped (a loop that comes back to a vertex is cut there into
// loops of its own), zero-area polygons and facets dropped, duplicate facets
// dropped.
void weld_points(Work& w, RepairReport& report);
void clean_polygons(Work& w, RepairReport& report);
void drop_duplicate_facets(Work& w, RepairReport& report);
/// Explicit segments with both ends welded into one point dropped; with
/// `repeats`, repeated segments kept once (Work::segment_source in step).
void clean_segments(Work& w, bool repeats);
/// Points that facets of `input` used and no facet or segment uses after
/// step 1 are dropped (a point left behind by a dropped zero-area triangle
/// may lie on an edge, which the PLC forbids for a free point).
void drop_orphaned_points(Work& w, const Plc& input);

// Step 3b (repair_holes.cpp, with RepairOptions::fill_holes, after the
// T-junctions): every boundary loop closed by triangles of its vertices, of
// least total area; with `refine`, a non-planar loop's patch then refined
// with new points (report.fill_points) and faired (Liepa 2003).
void fill_holes(Work& w, RepairReport& report, bool refine = true);
/// Some edge is used by one facet alone (and no explicit segment).
bool has_boundary(const Plc& plc);

// Step 2 (repair_nonplanar.cpp): a facet whose vertices are not coplanar is
// split into triangles.
void split_nonplanar_facets(Work& w, RepairReport& report);

// Step 3 (repair_tjunction.cpp): a vertex lying exactly on another facet's
// edge or inside it becomes a vertex of that facet. With `isolated`, also a
// point no facet uses (an isolated point of the input on an edge makes no
// valid PLC; inside the rounds, unused points are constructed points that
// go at the end).
Status split_at_tjunctions(Work& w, RepairReport& report, bool isolated = false);
/// Replaces every facet flagged in `which` by the triangles of its own
/// constrained triangulation (triangulate_surface: its vertices and every
/// PLC point lying in it), one facet each, provenance kept. A facet that
/// cannot be triangulated is left as it is.
Status triangulate_in_place(Work& w, const std::vector<uint8_t>& which);

// Step 4 (repair_crossing.cpp): crossing facets get their intersection
// segments as edges; explicit segments are split where they cross or touch
// facets and each other, and their pieces lying in a facet become its edges. `left` receives the improper pairs (in the numbering of
// w.plc) that remain after the last round; empty when the PLC is clean.
Status resolve_crossings(Work& w, RepairReport& report, std::vector<Intersection>& left);
// Step 5 (repair_union.cpp, after step 4 resolved crossings, and always
// with RepairOptions::parts_as_regions; off with union_of_parts false):
// facets inside the union of the parts (winding number at least 1 on both
// sides) or outside every part are dropped, with the points only they used.
/// With `part_of_input` (per input facet its part, kNone for none; see
/// connected_parts) the facets between cells in different sets of parts
/// stay, and report.region_parts, facet_regions and facet_axis say which
/// region lies on each side; empty: the plain union.
Status merge_into_union(Work& w, const Plc& input, const std::vector<uint32_t>& part_of_input,
                        RepairReport& report, const RepairOptions& options);
/// Per input facet: its part, the connected component of w.plc's facets
/// (joined across shared edges) holding the facets that come from it,
/// numbered in order of their smallest input facet; kNone for an input
/// facet none of w.plc's facets comes from.
std::vector<uint32_t> connected_parts(const Work& w, size_t input_facets);
/// After tetrahedralize() of a PLC repaired with parts as regions: every tet
/// gets the region of report.region_parts it lies in (see
/// map_to_input_facets). Reads result.face_facet before it is mapped.
void label_part_regions(const RepairReport& report, Result& result);
/// For a PLC repaired with parts as regions that is written on its own (a
/// .poly): plc.regions gets one point per region, so that meshing the file
/// labels its tets as label_part_regions does. Costs a tetrahedralization.
Status add_part_region_points(Plc& plc, const RepairReport& report);
/// Step 4's snap grid: a power of two 2^-40 below the binary order of the
/// largest coordinate of the points in use (0 when all are 0).
double snap_grid(const Plc& plc);
/// x rounded to the nearest multiple of `grid` (a grid of 0 leaves it).
Vec3 snapped(Vec3 x, double grid);
/// Every point snapped to step 4's grid (2^-40 below the binary order of the
/// largest coordinate), then steps 1 and 3 again on what moved.
Status snap_to_grid(Work& w);

}  // namespace repair_steps
}  // namespace cdt3d
