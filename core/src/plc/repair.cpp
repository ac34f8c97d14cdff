// repair(): the steps of repair_*.cpp in order, the report, and the checks
// that tell whether the result is a valid PLC. See cdt3d.hpp for the
// contract; each step's file says how it stays exact.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <string>

#include "plc_intersect.hpp"
#include "repair.hpp"

namespace cdt3d {

bool RepairReport::changed() const {
  return welded_points + repeated_vertices + zero_area_polygons + degenerate_facets +
             duplicate_facets + filled_holes + nonplanar_facets + tjunction_vertices + crossing_pairs +
             crossing_segments + outside_facets >
         0;
}

namespace {

using repair_steps::Work;

Status input_error(const Plc& plc, ErrorCode code, std::string message) {
  Status s;
  s.error.code = code;
  s.error.message = std::move(message);
  s.error.file = plc.file;
  return s;
}

// What no step can repair: coordinates out of range and indices that name
// no point. Named as check_plc names them.
Status check_repairable(const Plc& plc) {
  for (size_t i = 0; i < plc.points.size(); ++i) {
    const Vec3& p = plc.points[i];
    for (double c : {p.x, p.y, p.z}) {
      if (std::isfinite(c) && std::fabs(c) <= kMaxCoordinate) continue;
      Status s = input_error(plc, std::isfinite(c) ? ErrorCode::CoordinateRange : ErrorCode::NonFinite,
                             "Point " + std::to_string(i) +
                                 " has a coordinate that is not finite or beyond 1e50; repair "
                                 "cannot fix coordinates.");
      s.error.vertex = static_cast<int64_t>(i);
      return s;
    }
  }
  for (size_t f = 0; f < plc.facets.size(); ++f)
    for (const auto& loop : plc.facets[f].loops)
      for (VertexId v : loop)
        if (v >= plc.points.size()) {
          Status s = input_error(plc, ErrorCode::IndexOutOfRange,
                                 "Facet " + std::to_string(f) + " uses vertex " + std::to_string(v) +
                                     " but there are " + std::to_string(plc.points.size()) +
                                     " points.");
          s.error.facet = static_cast<int64_t>(f);
          s.error.line = plc.facets[f].line;
          s.error.record = plc.facets[f].record;
          return s;
        }
  for (size_t i = 0; i < plc.segments.size(); ++i)
    if (plc.segments[i][0] >= plc.points.size() || plc.segments[i][1] >= plc.points.size())
      return input_error(plc, ErrorCode::IndexOutOfRange,
                         "Segment " + std::to_string(i) + " uses a vertex beyond the points.");
  return Status::success();
}

// An error about the repaired PLC, told in terms of the input: its facets
// (and their source lines or records) are the input's.
Status in_input_terms(Status st, const Plc& in, const std::vector<uint32_t>& source) {
  auto map = [&](int64_t& f) {
    if (f >= 0 && static_cast<size_t>(f) < source.size()) f = source[static_cast<size_t>(f)];
  };
  map(st.error.facet);
  map(st.error.other_facet);
  if (st.error.facet >= 0 && static_cast<size_t>(st.error.facet) < in.facets.size()) {
    st.error.line = in.facets[static_cast<size_t>(st.error.facet)].line;
    st.error.record = in.facets[static_cast<size_t>(st.error.facet)].record;
  }
  st.error.file = in.file;
  st.error.message = "After repair: " + st.error.message +
                     " (facets are numbered as in the input)";
  return st;
}

// The pairs still intersecting, as pairs of input cells (facets, then
// explicit segments, each named by its source), for self_intersection_error
// on the input.
std::vector<Intersection> input_pairs(const std::vector<Intersection>& left, const Plc& in,
                                      const Plc& out, const std::vector<uint32_t>& source,
                                      const std::vector<uint32_t>& segment_source) {
  const uint32_t nout = static_cast<uint32_t>(out.facets.size());
  const uint32_t nin = static_cast<uint32_t>(in.facets.size());
  auto cell = [&](uint32_t r) { return r < nout ? source[r] : nin + segment_source[r - nout]; };
  std::vector<Intersection> pairs;
  for (const Intersection& x : left) {
    uint32_t a = cell(x.a), b = cell(x.b);
    if (a > b) std::swap(a, b);
    pairs.push_back({a, b, x.kind});
  }
  std::sort(pairs.begin(), pairs.end(), [](const Intersection& x, const Intersection& y) {
    return x.a != y.a ? x.a < y.a : x.b < y.b;
  });
  pairs.erase(std::unique(pairs.begin(), pairs.end(),
                          [](const Intersection& x, const Intersection& y) {
                            return x.a == y.a && x.b == y.b;
                          }),
              pairs.end());
  return pairs;
}

// Facets triangulated at T-junctions can repeat one another where the input
// overlapped: those copies are duplicates like any other.
void tidy_after_tjunctions(repair_steps::Work& w, RepairReport& report) {
  RepairReport again;
  repair_steps::clean_polygons(w, again);
  repair_steps::drop_duplicate_facets(w, again);
  report.duplicate_facets += again.duplicate_facets;
}

// Steps 3b and 4. With `fill`: the points snapped, every hole filled (a
// non-planar hole's patch refined with new points when `refine`), the
// T-junctions split again; then the crossings resolved.
Status fill_and_resolve(repair_steps::Work& w, RepairReport& report, bool fill, bool refine,
                        std::vector<Intersection>& left) {
  Status st;
  if (fill) {
    // Snapped first: a crack narrower than the grid (CAD noise: a wall
    // ending at z = -2.7e-16 beside a face at z = 0) closes by welding
    // instead of taking a patch that would overlap the face.
    st = repair_steps::snap_to_grid(w);
    if (st.ok()) {
      repair_steps::fill_holes(w, report, refine);
      st = repair_steps::split_at_tjunctions(w, report, true);
      tidy_after_tjunctions(w, report);
    }
  }
  if (st.ok()) st = check_plc(w.plc);
  if (st.ok()) st = repair_steps::resolve_crossings(w, report, left);
  return st;
}

}  // namespace

Status repair(const Plc& plc, Plc& out, RepairReport& report, const RepairOptions& options) {
  const auto t0 = std::chrono::steady_clock::now();
  report = RepairReport();
  report.input_points = plc.points.size();
  report.input_facets = plc.facets.size();
  Status st = check_repairable(plc);
  if (st.ok() && options.parts_as_regions && !options.union_of_parts)
    st = input_error(plc, ErrorCode::InvalidArgument,
                     "Parts as regions needs the union of the parts (union_of_parts): the two "
                     "options cannot be combined.");
  if (!st.ok()) {
    out = plc;
    return st;
  }
  Work w;
  w.plc = plc;
  w.source.resize(plc.facets.size());
  std::iota(w.source.begin(), w.source.end(), 0);
  w.changed.assign(plc.facets.size(), 0);
  w.segment_source.resize(plc.segments.size());
  std::iota(w.segment_source.begin(), w.segment_source.end(), 0);

  repair_steps::weld_points(w, report);
  repair_steps::clean_polygons(w, report);
  repair_steps::clean_segments(w, false);
  repair_steps::drop_duplicate_facets(w, report);
  repair_steps::drop_orphaned_points(w, plc);
  // Parts are the input's components once identical points are welded,
  // before any crossing joins them.
  std::vector<uint32_t> part_of_input;
  if (options.parts_as_regions) {
    part_of_input = repair_steps::connected_parts(w, plc.facets.size());
    w.plc.regions.clear();  // the parts name the regions
  }
  repair_steps::split_nonplanar_facets(w, report);
  st = repair_steps::split_at_tjunctions(w, report, true);
  tidy_after_tjunctions(w, report);
  // Holes are filled after the T-junctions are split: a crack along a
  // T-junction is no hole (its edges become shared), and a patch over it
  // would overlap the surface.
  const bool fill = st.ok() && options.fill_holes && repair_steps::has_boundary(w.plc);
  std::vector<Intersection> left;
  repair_steps::Work unfilled;
  RepairReport unfilled_report;
  if (fill) unfilled = w, unfilled_report = report;
  if (st.ok()) st = fill_and_resolve(w, report, fill, true, left);
  // Refining a patch moves it (edge swaps, fairing), and it may then meet
  // the surface where step 4 cannot resolve the crossings (swaps across
  // folds of the patch did, before they were ruled out): then the holes are
  // filled again with the rims' own triangles alone, as without refinement.
  if ((!st.ok() || !left.empty()) && report.fill_points > 0) {
    w = std::move(unfilled), report = unfilled_report, left.clear();
    st = fill_and_resolve(w, report, fill, false, left);
  }
  // Regions are wanted whether or not parts crossed (nested or disjoint
  // parts are labelled too). A surface still open after filling holds a
  // sheet that bounds no volume (a lone triangle, whose rim only its own
  // copy closes), which goes there with what else bounds none.
  if (st.ok() && left.empty() && options.union_of_parts &&
      (report.crossing_pairs > 0 || options.parts_as_regions || (fill && repair_steps::has_boundary(w.plc))))
    st = repair_steps::merge_into_union(w, plc, part_of_input, report, options);
  if (!st.ok()) st = in_input_terms(st, plc, w.source);

  report.facet_source = w.source;
  report.segment_source = w.segment_source;
  for (uint32_t f = 0; f < w.changed.size(); ++f)
    if (w.changed[f]) report.changed_facets.push_back(f);
  report.points = w.plc.points.size();
  report.facets = w.plc.facets.size();
  out = std::move(w.plc);
  if (st.ok() && !left.empty()) {
    const std::vector<Intersection> pairs = input_pairs(left, plc, out, report.facet_source, report.segment_source);
    report.unresolved_pairs = pairs.size();
    st = self_intersection_error(plc, pairs);
    st.error.message = "Repair left intersections: " + st.error.message;
  }
  report.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return st;
}

void map_to_input_facets(const RepairReport& report, Result& result) {
  repair_steps::label_part_regions(report, result);  // reads face_facet before it is mapped
  const auto& src = report.facet_source;
  auto map = [&](auto& f) {
    if (f >= 0 && static_cast<size_t>(f) < src.size()) f = src[static_cast<size_t>(f)];
  };
  for (uint32_t& f : result.face_facet)
    if (f < src.size()) f = src[f];
  result.flat_face_of.clear();  // indexed by repaired facets, which input facets do not name
  for (size_t i = 0; i < result.steiner_kind.size() && i < result.steiner_parent.size(); ++i)
    if (result.steiner_kind[i] == SteinerKind::Facet) map(result.steiner_parent[i]);
  map(result.status.error.facet);
  map(result.status.error.other_facet);
  for (auto& pair : result.intersecting_facets)
    for (uint32_t& f : pair)
      if (f < src.size()) f = src[f];
}

}  // namespace cdt3d
