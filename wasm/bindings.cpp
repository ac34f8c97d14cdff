// Embind bindings of the cdt3d core: conversion only, no geometry.
//
// Every raw function returns a plain JS object and never throws or aborts on
// bad input: {ok: true, ...fields} on success, {ok: false, error: {...}} on
// failure, the same shape as the native CLI's --json output. api.js turns the
// failures into Cdt3dError. The raw names start with '_' and are not part of
// the public API.
#include <emscripten/bind.h>
#include <emscripten/heap.h>
#include <emscripten/val.h>
#include <malloc.h>

#include <cdt3d/cdt3d.hpp>

#include "plc_check.hpp"  // check_welded_plc (core/src)
#include "refine.hpp"  // check_quality_options (core/src)
#include "repair.hpp"  // add_part_region_points (core/src)
#include "status.hpp"  // current_exception_code (core/src)

#include <array>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <new>
#include <vector>
#include <cstdlib>
#include <memory>
#include <set>
#include <string>

#ifndef CDT3D_VERSION
#error "CDT3D_VERSION must be defined by the build (wasm/CMakeLists.txt)"
#endif

namespace {

using emscripten::val;

val number(int64_t v) { return val(static_cast<double>(v)); }
val number(size_t v) { return val(static_cast<double>(v)); }

val vec3(const cdt3d::Vec3& p) {
  val a = val::array();
  a.call<void>("push", p.x, p.y, p.z);
  return a;
}

// What meshing needs of the heap at its peak, per input point: ~1.45 KB on
// the bumpy torus of tests/bench/bench_scale.sh (the tets, the PLC, the
// result copied out; the CAD-like models need less), with a margin. A
// model that cannot fit is refused before the work, not minutes into it.
constexpr double kHeapBytesPerPoint = 1800;
// With `validate`: the validator's sorted faces and edges of every tet come
// on top of the mesh (the pipeline's working mesh is freed first). Measured
// heap: the 3M-triangle torus, 1.50M points, 2.17 GB without validation;
// 3.15M triangles, 1.58M points, 3.28 GB with it (2.08 KB per point), and
// 3.99 GB before the working mesh was freed.
constexpr double kHeapBytesPerPointValidated = 2300;

double heap_bytes_per_point(bool validate) {
  return validate ? kHeapBytesPerPointValidated : kHeapBytesPerPoint;
}

// The 4 GiB heap (-sMAXIMUM_MEMORY) and the model sizes it holds, for the
// error of a model that does not fit (too large up front, or out of memory).
std::string heap_limit_text() {
  const double heap = static_cast<double>(emscripten_get_heap_max());
  const double points = heap / kHeapBytesPerPoint;
  const double checked = heap / kHeapBytesPerPointValidated;
  char text[320];
  std::snprintf(text, sizeof text,
                "The WebAssembly heap is limited to %.1f GiB (wasm32); it holds models of up to "
                "about %.1f million points (%.1f million triangles of a closed surface), or %.1f "
                "million points (%.1f million triangles) with validation. Mesh larger models "
                "with the native cdt3d.",
                heap / (1024.0 * 1024 * 1024), points / 1e6, 2 * points / 1e6, checked / 1e6,
                2 * checked / 1e6);
  return text;
}

// {ok: false, error: {code, message, file, line, record, facet, vertex, otherFacet}};
// an out-of-memory error also says what the heap holds.
val failure(const cdt3d::Error& e) {
  val err = val::object();
  err.set("code", val(std::string(cdt3d::error_code_name(e.code))));
  err.set("message", val(e.code == cdt3d::ErrorCode::OutOfMemory
                             ? e.message + " " + heap_limit_text()
                             : e.message));
  err.set("file", val(e.file));
  err.set("line", number(e.line));
  err.set("record", number(e.record));
  err.set("facet", number(e.facet));
  err.set("vertex", number(e.vertex));
  err.set("otherFacet", number(e.other_facet));
  err.set("segment", number(e.segment));
  val out = val::object();
  out.set("ok", val(false));
  out.set("error", err);
  return out;
}

val failure(cdt3d::ErrorCode code, std::string message, std::string file) {
  cdt3d::Error e;
  e.code = code;
  e.message = std::move(message);
  e.file = std::move(file);
  return failure(e);
}

// Summary of a PLC with the field names of `cdt3d info --json`.
val plc_summary(const cdt3d::Plc& plc) {
  const cdt3d::PlcInfo info = cdt3d::plc_info(plc);
  val out = val::object();
  out.set("ok", val(true));
  out.set("file", val(plc.file));
  out.set("fileVertices", number(info.file_vertices));
  out.set("points", number(info.points));
  out.set("welded", number(plc.welded_vertices));
  out.set("unreferenced", number(info.unreferenced));
  out.set("facets", number(info.facets));
  out.set("triangles", number(info.triangles));
  out.set("loops", number(info.loops));
  out.set("segments", number(info.segments));
  out.set("holes", number(info.holes));
  out.set("regions", number(info.regions));
  out.set("bboxMin", vec3(info.bbox_min));
  out.set("bboxMax", vec3(info.bbox_max));
  return out;
}

struct FreeDeleter {
  void operator()(uint8_t* p) const { std::free(p); }
};

// Copies a JS Uint8Array into the WASM heap. malloc (not a vector) so that an
// input too large for the heap is an "out-of-memory" status, not an abort.
// Returns false when the allocation fails.
bool copy_bytes(const val& bytes, size_t size, std::unique_ptr<uint8_t, FreeDeleter>& out) {
  out.reset(static_cast<uint8_t*>(std::malloc(size > 0 ? size : 1)));
  if (!out) return false;
  // The view is created after the allocation, so memory growth cannot detach it.
  if (size > 0) val(emscripten::typed_memory_view(size, out.get())).call<void>("set", bytes);
  return true;
}

// read_plc, with the file's copy freed before check_plc: the checks' arrays
// then reuse its pages instead of growing the heap into fresh ones, which
// a fresh instance faults in one 4 KiB page at a time.
cdt3d::Status read_then_check(std::unique_ptr<uint8_t, FreeDeleter>& data, size_t size,
                              const std::string& name, cdt3d::Plc& plc, bool check) {
  cdt3d::Status st = cdt3d::read_plc(data.get(), size, name, plc, false);
  data.reset();
  try {
    if (st.ok() && check) st = cdt3d::check_welded_plc(plc);
  } catch (...) {  // catch (...): see current_exception_code()
    st.error = cdt3d::current_exception_error("checking the file", name);
  }
  if (!st.ok()) {
    // Never hand back half a PLC (as read_plc).
    plc = cdt3d::Plc();
    plc.file = name;
  }
  return st;
}

// readPlc(bytes: Uint8Array, fileName: string) -> summary or error object.
val read_plc_js(val bytes, val file_name) {
  if (!file_name.isString()) {
    return failure(cdt3d::ErrorCode::InvalidArgument,
                   "The file name must be a string (it picks the format by extension).", "");
  }
  std::string name = file_name.as<std::string>();
  if (name.empty()) {
    return failure(cdt3d::ErrorCode::InvalidArgument,
                   "The file name is empty (it picks the format by extension).", "");
  }
  if (!bytes.instanceof(val::global("Uint8Array"))) {
    return failure(cdt3d::ErrorCode::InvalidArgument,
                   "The file contents must be a Uint8Array, an ArrayBuffer or a Buffer.", name);
  }
  const double length = bytes["length"].as<double>();
  if (!(length >= 0) || length > static_cast<double>(SIZE_MAX)) {
    return failure(cdt3d::ErrorCode::TooLarge, "The file is too large for a 32-bit heap.", name);
  }
  const size_t size = static_cast<size_t>(length);
  std::unique_ptr<uint8_t, FreeDeleter> data;
  if (!copy_bytes(bytes, size, data)) {
    return failure(cdt3d::ErrorCode::OutOfMemory,
                   "Not enough WebAssembly memory to hold the file (" + std::to_string(size) +
                       " bytes).",
                   name);
  }
  cdt3d::Plc plc;
  const cdt3d::Status status = read_then_check(data, size, name, plc, true);
  if (!status.ok()) return failure(status.error);
  return plc_summary(plc);
}

// ---------------------------------------------------------------------------
// Meshing. api.js normalizes every accepted input to one object: either
// {fileName, bytes} (a file's contents) or flat typed arrays
// {points: Float64Array, loopCounts: Uint32Array (loops per facet),
//  loopSizes: Uint32Array (vertices per loop), loopVertices: Uint32Array,
//  holeCounts: Uint32Array (hole points per facet), holePoints: Float64Array,
//  markers: Int32Array, segments: Uint32Array, holes: Float64Array,
//  regions: Float64Array (x, y, z, attribute, maxVolume per region)}.
// ---------------------------------------------------------------------------

// Copies a JS typed array of the matching element type into `out`.
template <class T>
void from_js(const val& array, std::vector<T>& out) {
  out.clear();
  if (array.isUndefined() || array.isNull()) return;
  const size_t n = array["length"].as<size_t>();
  out.resize(n);
  if (n > 0) val(emscripten::typed_memory_view(n, out.data())).call<void>("set", array);
}

// A JS typed array holding a copy of `v` (never a view into the heap, which
// memory growth would detach).
template <class T>
val to_js(const T* data, size_t n) {
  return val(emscripten::typed_memory_view(n, data)).call<val>("slice");
}
template <class T>
val to_js(const std::vector<T>& v) {
  return to_js(v.data(), v.size());
}

// Marker names as a JS array of {marker, name}.
val names_js(const std::vector<std::pair<int, std::string>>& names) {
  val a = val::array();
  for (const auto& [marker, name] : names) {
    val o = val::object();
    o.set("marker", val(marker));
    o.set("name", val(name));
    a.call<void>("push", o);
  }
  return a;
}

// Marker names back from such an array (absent: none).
void names_from_js(const val& a, std::vector<std::pair<int, std::string>>& out) {
  out.clear();
  if (a.isUndefined() || a.isNull()) return;
  const size_t n = a["length"].as<size_t>();
  for (size_t i = 0; i < n; ++i)
    out.emplace_back(a[i]["marker"].as<int>(), a[i]["name"].as<std::string>());
}

cdt3d::Status invalid(const std::string& message) {
  cdt3d::Status st;
  st.error.code = cdt3d::ErrorCode::InvalidArgument;
  st.error.message = message;
  return st;
}

// Builds a Plc from the flat arrays (or parses the file) of a normalized input.
cdt3d::Status plc_from_js(const val& input, cdt3d::Plc& plc, double* ms_read = nullptr,
                          bool check = true) {
  const auto t0 = std::chrono::steady_clock::now();
  if (!input["bytes"].isUndefined()) {
    const std::string name = input["fileName"].as<std::string>();
    const val bytes = input["bytes"];
    const size_t size = bytes["length"].as<size_t>();
    std::unique_ptr<uint8_t, FreeDeleter> data;
    if (!copy_bytes(bytes, size, data)) {
      cdt3d::Status st;
      st.error = {cdt3d::ErrorCode::OutOfMemory,
                  "Not enough WebAssembly memory to hold the file (" + std::to_string(size) +
                      " bytes).",
                  name};
      return st;
    }
    cdt3d::Status st = read_then_check(data, size, name, plc, check);
    if (ms_read) *ms_read = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
    return st;
  }
  std::vector<double> points, hole_points, holes, regions;
  std::vector<uint32_t> loop_counts, loop_sizes, loop_vertices, hole_counts, segments;
  std::vector<int32_t> markers;
  from_js(input["points"], points);
  from_js(input["loopCounts"], loop_counts);
  from_js(input["loopSizes"], loop_sizes);
  from_js(input["loopVertices"], loop_vertices);
  from_js(input["holeCounts"], hole_counts);
  from_js(input["holePoints"], hole_points);
  from_js(input["markers"], markers);
  from_js(input["segments"], segments);
  from_js(input["holes"], holes);
  from_js(input["regions"], regions);
  names_from_js(input["markerNames"], plc.marker_names);
  if (points.size() % 3 || segments.size() % 2 || holes.size() % 3 || regions.size() % 5 ||
      hole_points.size() % 3)
    return invalid("points, holes and facet hole points need 3 numbers each, segments 2, regions 5.");
  plc.file = input["fileName"].isString() ? input["fileName"].as<std::string>() : "";
  plc.points.resize(points.size() / 3);
  for (size_t i = 0; i < plc.points.size(); ++i)
    plc.points[i] = {points[3 * i], points[3 * i + 1], points[3 * i + 2]};
  plc.file_vertices = plc.points.size();
  plc.facets.resize(loop_counts.size());
  size_t loop = 0, vertex = 0, hole = 0;
  for (size_t f = 0; f < loop_counts.size(); ++f) {
    cdt3d::Facet& F = plc.facets[f];
    F.record = static_cast<int64_t>(f);
    if (f < markers.size()) F.marker = markers[f];
    for (uint32_t k = 0; k < loop_counts[f]; ++k, ++loop) {
      if (loop >= loop_sizes.size()) return invalid("loopCounts asks for more loops than loopSizes has.");
      const uint32_t n = loop_sizes[loop];
      if (vertex + n > loop_vertices.size())
        return invalid("loopSizes asks for more vertices than loopVertices has.");
      F.loops.emplace_back(loop_vertices.begin() + vertex, loop_vertices.begin() + vertex + n);
      vertex += n;
    }
    const uint32_t nh = f < hole_counts.size() ? hole_counts[f] : 0;
    for (uint32_t k = 0; k < nh; ++k, ++hole) {
      if (3 * hole + 2 >= hole_points.size())
        return invalid("holeCounts asks for more facet hole points than holePoints has.");
      F.holes.push_back({hole_points[3 * hole], hole_points[3 * hole + 1], hole_points[3 * hole + 2]});
    }
  }
  if (loop != loop_sizes.size() || vertex != loop_vertices.size())
    return invalid("loopCounts, loopSizes and loopVertices disagree in length.");
  for (size_t i = 0; i + 1 < segments.size(); i += 2) plc.segments.push_back({segments[i], segments[i + 1]});
  for (size_t i = 0; i + 2 < holes.size(); i += 3) plc.holes.push_back({holes[i], holes[i + 1], holes[i + 2]});
  for (size_t i = 0; i + 4 < regions.size(); i += 5) {
    cdt3d::Region r;
    r.point = {regions[i], regions[i + 1], regions[i + 2]};
    r.attribute = regions[i + 3];
    r.max_volume = regions[i + 4];
    plc.regions.push_back(r);
  }
  return check ? cdt3d::check_plc(plc) : cdt3d::Status::success();
}

val histogram_js(const std::array<size_t, 10>& counts) {
  val h = val::array();
  for (size_t c : counts) h.call<void>("push", static_cast<double>(c));
  return h;
}

val stats_js(const cdt3d::Statistics& s) {
  val o = val::object();
  auto n = [&o](const char* k, double v) { o.set(k, val(v)); };
  n("inputPoints", s.input_points), n("inputFacets", s.input_facets);
  n("inputSegments", s.input_segments), n("points", s.points), n("tets", s.tets);
  n("faces", s.faces), n("steinerSegment", s.steiner_segment), n("steinerFacet", s.steiner_facet);
  n("steinerVolume", s.steiner_volume), n("rule1", s.rule1), n("rule2", s.rule2);
  n("rule3", s.rule3), n("missingSegments", s.missing_segments), n("acuteBoth", s.acute_both);
  n("splitProjection", s.split_projection), n("splitShell", s.split_shell);
  n("splitRemoved", s.split_removed);
  n("maxSplits", s.max_splits), n("perturbations", s.perturbations);
  n("breakPoints", s.break_points), n("protectSegment", s.protect_segment);
  n("protectFacet", s.protect_facet), n("flatEdges", s.flat_edges);
  n("mergedFacets", s.merged_facets);
  n("missingSubfaces", s.missing_subfaces), n("regions", s.regions), n("cavities", s.cavities);
  n("largestCavity", s.largest_cavity), n("fallbacks", s.fallbacks);
  n("facetSplits", s.facet_splits), n("refineSegment", s.refine_segment);
  n("refineFacet", s.refine_facet), n("refineVolume", s.refine_volume);
  n("refineSkipped", s.refine_skipped), n("refineSmallAngle", s.refine_small_angle);
  n("refineCapped", s.refine_capped);
  n("improveFlips", s.improve_flips), n("improveSmooths", s.improve_smooths);
  n("improvePoints", s.improve_points);
  n("msRead", s.ms_read), n("msDelaunay", s.ms_delaunay), n("msSegments", s.ms_segments);
  n("msDegeneracy", s.ms_degeneracy), n("msFacets", s.ms_facets), n("msCarve", s.ms_carve);
  n("msRefine", s.ms_refine), n("msTotal", s.ms_total), n("flatFlips", s.flat_flips);
  n("flatPeeled", s.flat_peeled);
  n("flatTets", s.flat_tets), n("minDihedral", s.min_dihedral), n("maxDihedral", s.max_dihedral);
  n("minDihedralBefore", s.min_dihedral_before);
  o.set("radiusEdgeHistogram", histogram_js(s.radius_edge_histogram));
  o.set("dihedralHistogram", histogram_js(s.dihedral_histogram));
  o.set("radiusEdgeHistogramBefore", histogram_js(s.radius_edge_histogram_before));
  o.set("dihedralHistogramBefore", histogram_js(s.dihedral_histogram_before));
  return o;
}

// options.quality as api.js passes it: null (no refinement) or
// {radiusEdge, maxVolume, minDihedral, maxPoints}, all numbers. Each value is
// checked alone by the core's rules, so that the error names its option.
cdt3d::Status quality_from_js(const val& q, cdt3d::QualityOptions& out) {
  if (q.isNull() || q.isUndefined()) return cdt3d::Status::success();
  out.enabled = true;
  const char* keys[3] = {"radiusEdge", "maxVolume", "minDihedral"};
  double cdt3d::QualityOptions::*fields[3] = {&cdt3d::QualityOptions::radius_edge,
                                               &cdt3d::QualityOptions::max_volume,
                                               &cdt3d::QualityOptions::min_dihedral};
  for (int i = 0; i < 3; ++i) {
    cdt3d::QualityOptions one;
    one.*fields[i] = out.*fields[i] = q[keys[i]].as<double>();
    cdt3d::Status st = cdt3d::check_quality_options(one);
    if (!st.ok()) {
      st.error.message = "tetrahedralize: option quality." + std::string(keys[i]) + ": " + st.error.message;
      return st;
    }
  }
  out.max_points = static_cast<size_t>(q["maxPoints"].as<double>());
  return cdt3d::Status::success();
}

// Progress and cancellation: the JS callback gets (phase, fraction) and
// returns true to cancel (api.js checks the AbortSignal there).
struct ProgressBridge {
  val callback = val::undefined();
  volatile bool cancel = false;
  static void report(void* user, cdt3d::Phase phase, double fraction) {
    auto* self = static_cast<ProgressBridge*>(user);
    if (self->callback.isUndefined()) return;
    if (self->callback(std::string(cdt3d::phase_name(phase)), fraction).as<bool>()) self->cancel = true;
  }
};

val result_js(const cdt3d::Result& r) {
  val o = val::object();
  o.set("ok", val(true));
  o.set("points", to_js(r.mesh.points));
  o.set("tets", to_js(r.mesh.tets));
  o.set("faces", to_js(r.mesh.faces));
  o.set("faceFacets", to_js(r.face_facet));
  o.set("faceMarkers", to_js(r.mesh.face_markers));
  o.set("markerNames", names_js(r.mesh.marker_names));
  o.set("tetAttributes", to_js(r.mesh.tet_attributes));
  o.set("edges", to_js(r.edges));
  o.set("edgeSegments", to_js(r.edge_segment));
  o.set("inputPoints", val(static_cast<double>(r.input_points)));
  std::vector<uint8_t> kinds(r.steiner_kind.size());
  std::vector<int32_t> parents(r.steiner_parent.size());
  for (size_t i = 0; i < kinds.size(); ++i) kinds[i] = static_cast<uint8_t>(r.steiner_kind[i]);
  for (size_t i = 0; i < parents.size(); ++i) parents[i] = static_cast<int32_t>(r.steiner_parent[i]);
  o.set("steinerKinds", to_js(kinds));
  o.set("steinerParents", to_js(parents));
  o.set("delaunay", val(r.delaunay));
  o.set("flatFacesMerged", val(r.flat_faces_merged));
  o.set("flatFaceOf", to_js(r.flat_face_of));
  o.set("stats", stats_js(r.stats));
  return o;
}

val repair_report_js(const cdt3d::RepairReport& r) {
  val o = val::object();
  auto n = [&o](const char* k, double v) { o.set(k, val(v)); };
  o.set("changed", val(r.changed()));
  n("inputPoints", r.input_points), n("points", r.points);
  n("inputFacets", r.input_facets), n("facets", r.facets);
  n("weldedPoints", r.welded_points), n("repeatedVertices", r.repeated_vertices);
  n("zeroAreaPolygons", r.zero_area_polygons), n("degenerateFacets", r.degenerate_facets);
  n("duplicateFacets", r.duplicate_facets), n("nonplanarFacets", r.nonplanar_facets);
  n("filledHoles", r.filled_holes), n("fillTriangles", r.fill_triangles);
  n("fillPoints", r.fill_points), n("unfilledHoles", r.unfilled_holes);
  n("tjunctionVertices", r.tjunction_vertices), n("tjunctionFacets", r.tjunction_facets);
  n("crossingPairs", r.crossing_pairs), n("crossingFacets", r.crossing_facets);
  n("intersectionPoints", r.intersection_points), n("rounds", r.rounds);
  n("unresolvedPairs", r.unresolved_pairs), n("innerFacets", r.inner_facets);
  n("crossingSegments", r.crossing_segments), n("segmentSplits", r.segment_splits);
  o.set("unionSkipped", val(r.union_skipped != 0));
  n("outsideFacets", r.outside_facets);
  n("ms", r.ms);
  {
    // With parts as regions: entry a - 1 lists the parts of region attribute a.
    n("parts", static_cast<double>(r.parts));
    val list = val::array();
    for (size_t a = 0; a < r.region_parts.size(); ++a) {
      val parts = val::array();  // plain numbers, as in the CLI's JSON
      for (size_t i = 0; i < r.region_parts[a].size(); ++i) parts.set(i, val(r.region_parts[a][i]));
      list.set(a, parts);
    }
    o.set("regionParts", list);
  }
  o.set("changedFacets", to_js(r.changed_facets));
  return o;
}

// repair(input) -> {ok, report, facetSources, segmentSources, the repaired PLC as flat arrays
// (the shape plc_from_js reads), poly: its TetGen .poly text} or an error.
// The input is read without check_plc(): what it rejects is what repair fixes.
val repair_js(val input, bool fill_holes, bool union_of_parts, bool parts_as_regions) {
  cdt3d::Plc plc, fixed;
  cdt3d::Status st = plc_from_js(input, plc, nullptr, false);
  if (!st.ok()) return failure(st.error);
  cdt3d::RepairReport report;
  cdt3d::RepairOptions repair_options;
  repair_options.fill_holes = fill_holes;
  repair_options.union_of_parts = union_of_parts;
  repair_options.parts_as_regions = parts_as_regions;
  st = cdt3d::repair(plc, fixed, report, repair_options);
  // Handed back on its own: a region point per region says which is which
  // (as `cdt3d repair --parts-as-regions -o` writes them).
  if (st.ok() && parts_as_regions) st = cdt3d::repair_steps::add_part_region_points(fixed, report);
  if (!st.ok()) return failure(st.error);
  std::vector<double> xyz, hole_points, holes, regions;
  std::vector<uint32_t> counts, sizes, verts, hole_counts, segments;
  std::vector<int32_t> markers;
  for (const auto& p : fixed.points) xyz.insert(xyz.end(), {p.x, p.y, p.z});
  for (const auto& f : fixed.facets) {
    counts.push_back(static_cast<uint32_t>(f.loops.size()));
    for (const auto& l : f.loops) {
      sizes.push_back(static_cast<uint32_t>(l.size()));
      verts.insert(verts.end(), l.begin(), l.end());
    }
    hole_counts.push_back(static_cast<uint32_t>(f.holes.size()));
    for (const auto& h : f.holes) hole_points.insert(hole_points.end(), {h.x, h.y, h.z});
    markers.push_back(f.marker);
  }
  for (const auto& sg : fixed.segments) segments.insert(segments.end(), {sg[0], sg[1]});
  for (const auto& h : fixed.holes) holes.insert(holes.end(), {h.x, h.y, h.z});
  for (const auto& r : fixed.regions)
    regions.insert(regions.end(), {r.point.x, r.point.y, r.point.z, r.attribute, r.max_volume});
  val out = val::object();
  out.set("ok", val(true));
  out.set("report", repair_report_js(report));
  out.set("facetSources", to_js(report.facet_source));
  out.set("segmentSources", to_js(report.segment_source));
  out.set("points", to_js(xyz));
  out.set("loopCounts", to_js(counts));
  out.set("loopSizes", to_js(sizes));
  out.set("loopVertices", to_js(verts));
  out.set("holeCounts", to_js(hole_counts));
  out.set("holePoints", to_js(hole_points));
  out.set("markers", to_js(markers));
  out.set("markerNames", names_js(fixed.marker_names));
  out.set("segments", to_js(segments));
  out.set("holes", to_js(holes));
  out.set("regions", to_js(regions));
  out.set("poly", val(cdt3d::write_poly(fixed)));
  return out;
}

// The too-large error of a model that cannot fit the heap, or undefined.
val too_large(const cdt3d::Plc& plc, bool validate) {
  const double need = heap_bytes_per_point(validate) * static_cast<double>(plc.points.size());
  if (need <= static_cast<double>(emscripten_get_heap_max())) return val::undefined();
  size_t triangles = 0;
  for (const auto& f : plc.facets) triangles += f.loops.empty() ? 0 : f.loops[0].size() - 2;
  char text[192];
  std::snprintf(text, sizeof text,
                "This model has %zu points and %zu triangles: meshing it%s needs about %.1f GiB. ",
                plc.points.size(), triangles, validate ? " and validating the mesh" : "",
                need / (1024.0 * 1024 * 1024));
  return failure(cdt3d::ErrorCode::TooLarge, text + heap_limit_text(), plc.file);
}

val tetrahedralize_js(val input, val options, val on_progress) {
  cdt3d::Options opt;
  // Options first: a bad one is the caller's error whatever the input.
  cdt3d::Status st = quality_from_js(options["quality"], opt.quality);
  if (!st.ok()) return failure(st.error);
  cdt3d::Plc plc;
  double ms_read = 0;
  // The input checks (check_plc) are tetrahedralize()'s first step, or
  // repair's business with repair (as `mesh --repair`): reading does not
  // run them too.
  const bool fix = options["repair"].as<bool>();
  st = plc_from_js(input, plc, &ms_read, false);
  if (!st.ok()) return failure(st.error);
  if (val refused = too_large(plc, options["validate"].as<bool>()); !refused.isUndefined())
    return refused;
  cdt3d::RepairReport report;
  if (fix) {
    cdt3d::Plc fixed;
    cdt3d::RepairOptions repair_options;
    repair_options.fill_holes = options["fillHoles"].as<bool>();
    repair_options.union_of_parts = options["unionOfParts"].as<bool>();
    repair_options.parts_as_regions = options["partsAsRegions"].as<bool>();
    st = cdt3d::repair(plc, fixed, report, repair_options);
    if (!st.ok()) return failure(st.error);
    plc = std::move(fixed);
    ms_read += report.ms;
  }
  opt.keep_convex_hull = options["keepConvexHull"].as<bool>();
  opt.validate = options["validate"].as<bool>();
  opt.check_intersections = options["checkIntersections"].as<bool>();
  opt.keep_triangles = options["keepTriangles"].as<bool>();
  const std::string degeneracy = options["degeneracy"].as<std::string>();
  if (degeneracy == "paper")
    opt.degeneracy = cdt3d::DegeneracyMode::Paper;
  else if (degeneracy == "symbolic")
    opt.degeneracy = cdt3d::DegeneracyMode::Symbolic;
  else
    return failure(invalid("Unknown degeneracy mode (symbolic, paper).").error);
  opt.verbosity = options["verbosity"].as<int>();
  if (!cdt3d::phase_from_name(options["stopAfter"].as<std::string>(), opt.stop_after))
    return failure(invalid("Unknown phase for stopAfter.").error);
  ProgressBridge bridge;
  bridge.callback = on_progress;
  opt.progress = &ProgressBridge::report;
  opt.progress_user = &bridge;
  opt.cancel = &bridge.cancel;
  cdt3d::Result r = cdt3d::tetrahedralize(plc, opt);  // validates the repaired PLC
  if (fix) cdt3d::map_to_input_facets(report, r);
  if (!r.status.ok()) {
    val out = failure(r.status.error);
    if (!r.intersecting_facets.empty()) {
      std::vector<uint32_t> flat;
      for (const auto& p : r.intersecting_facets) flat.push_back(p[0]), flat.push_back(p[1]);
      out["error"].set("facets", to_js(flat));
    }
    return out;
  }
  r.stats.ms_read += ms_read;
  r.stats.ms_total += ms_read;
  val out = result_js(r);
  if (fix) out.set("repair", repair_report_js(report));
  return out;
}

// A Result rebuilt from the arrays of result_js (for validate and write).
void result_from_js(const val& res, cdt3d::Result& r) {
  from_js(res["points"], r.mesh.points);
  from_js(res["tets"], r.mesh.tets);
  from_js(res["faces"], r.mesh.faces);
  from_js(res["faceFacets"], r.face_facet);
  from_js(res["faceMarkers"], r.mesh.face_markers);
  names_from_js(res["markerNames"], r.mesh.marker_names);
  from_js(res["tetAttributes"], r.mesh.tet_attributes);
  r.input_points = res["inputPoints"].as<size_t>();
  std::vector<uint8_t> kinds;
  std::vector<int32_t> parents;
  from_js(res["steinerKinds"], kinds);
  from_js(res["steinerParents"], parents);
  for (uint8_t k : kinds) r.steiner_kind.push_back(static_cast<cdt3d::SteinerKind>(k));
  for (int32_t p : parents) r.steiner_parent.push_back(p);
  // Results from before the improvement pass existed have no flag: Delaunay.
  const val delaunay = res["delaunay"];
  r.delaunay = delaunay.isUndefined() || delaunay.as<bool>();
  // Results from before flat faces were merged have no flag: triangles kept.
  const val merged = res["flatFacesMerged"];
  r.flat_faces_merged = !merged.isUndefined() && merged.as<bool>();
}

val validate_js(val input, val result) {
  cdt3d::Plc plc;
  cdt3d::Status st = plc_from_js(input, plc);
  if (!st.ok()) return failure(st.error);
  cdt3d::Result r;
  result_from_js(result, r);
  st = cdt3d::validate(plc, r);
  if (!st.ok()) return failure(st.error);
  val out = val::object();
  out.set("ok", val(true));
  return out;
}

val write_js(std::string format, val result) {
  cdt3d::Result r;
  result_from_js(result, r);
  std::string text;
  // The binary formats come back as bytes (a string would be UTF-8 decoded).
  bool bytes = true;
  if (format == "msh") text = cdt3d::write_msh(r.mesh, false);
  else if (format == "msh-binary") text = cdt3d::write_msh(r.mesh, true);
  else if (format == "vtu") text = cdt3d::write_vtu(r);
  else bytes = false;
  if (format == "node") text = cdt3d::write_node(r.mesh);
  else if (format == "ele") text = cdt3d::write_ele(r.mesh);
  else if (format == "face") text = cdt3d::write_face(r.mesh);
  else if (format == "vtk") text = cdt3d::write_vtk(r.mesh);
  else if (format == "mesh") text = cdt3d::write_medit(r.mesh);
  else if (!bytes)
    return failure(invalid("Unknown format '" + format +
                           "' (node, ele, face, vtk, mesh, msh, msh-binary, vtu).").error);
  val out = val::object();
  out.set("ok", val(true));
  if (bytes)
    out.set("bytes", to_js(reinterpret_cast<const uint8_t*>(text.data()), text.size()));
  else
    out.set("text", val(text));
  return out;
}

val read_surface_js(val input) {
  cdt3d::Plc plc;
  cdt3d::Status st = plc_from_js(input, plc, nullptr, false);
  if (plc.points.empty()) return failure(st.error);  // nothing could be read
  if (st.ok()) st = cdt3d::check_plc(plc);
  // A file that fails its checks (e.g. a degenerate facet) still shows what
  // could be read, so that the page can highlight the facet named.
  std::vector<uint32_t> tris, tri_facet;
  if (!cdt3d::triangulate_surface(plc, tris, tri_facet).ok()) {
    // Fans of the first loop of each facet (display only).
    tris.clear(), tri_facet.clear();
    for (uint32_t f = 0; f < plc.facets.size(); ++f) {
      if (plc.facets[f].loops.empty()) continue;
      const auto& L = plc.facets[f].loops[0];
      for (size_t k = 1; k + 1 < L.size(); ++k) {
        tris.insert(tris.end(), {L[0], L[k], L[k + 1]});
        tri_facet.push_back(f);
      }
    }
  }
  std::vector<double> xyz;
  for (const auto& p : plc.points) xyz.insert(xyz.end(), {p.x, p.y, p.z});
  val out = val::object();
  out.set("ok", val(true));
  out.set("points", to_js(xyz));
  out.set("triangles", to_js(tris));
  out.set("triangleFacets", to_js(tri_facet));
  out.set("error", st.ok() ? val::null() : failure(st.error)["error"]);
  return out;
}

// delaunay(points: Float64Array) -> {ok, tets: Uint32Array, msDelaunay}
val delaunay_js(val points) {
  std::vector<double> xyz;
  from_js(points, xyz);
  std::vector<uint32_t> tets;
  double ms = 0;
  cdt3d::Status st = cdt3d::delaunay_tetrahedralization(xyz, tets, &ms);
  if (!st.ok()) return failure(st.error);
  val out = val::object();
  out.set("ok", val(true));
  out.set("tets", to_js(tets));
  out.set("msDelaunay", val(ms));
  return out;
}

// Catches allocation failure (built with -fwasm-exceptions): the heap stays
// usable, and the caller gets an "out-of-memory" error instead of an abort.
// Anything else becomes an "internal" error with its what() where the build
// can see it. Only `catch (...)` matches in the two-thread module (see
// current_exception_code()); a typed clause let a 4.6M-triangle model's
// allocation failure through to JavaScript as a WebAssembly.Exception.
template <class F>
val guarded(F&& f) {
  cdt3d::clear_allocation_failure();
  try {
    return f();
  } catch (...) {
    if (cdt3d::current_exception_code() == cdt3d::ErrorCode::OutOfMemory)
      return failure(cdt3d::ErrorCode::OutOfMemory,
                     "Out of WebAssembly memory (the browser's limit, or the model is too large).",
                     "");
    const std::string what = cdt3d::current_exception_text();
    return failure(cdt3d::ErrorCode::Internal,
                   "The mesher stopped on an unexpected C++ exception" +
                       (what.empty() ? std::string(".") : ": " + what),
                   "");
  }
}

// The new-handler: records the failure for current_exception_code() (the
// two-thread module cannot tell a std::bad_alloc by its type), then fails
// as operator new would without one.
void on_allocation_failure() {
  cdt3d::note_allocation_failure();
  throw std::bad_alloc();
}

std::string version() { return CDT3D_VERSION; }

// Every stable error code name except "ok", in enum order. error_code_name()
// maps unknown values to "internal", so scanning past the last enumerator is
// harmless.
val error_codes() {
  val out = val::array();
  std::set<std::string> seen{"ok"};
  for (int i = 0; i < 256; ++i) {
    std::string name = cdt3d::error_code_name(static_cast<cdt3d::ErrorCode>(i));
    if (seen.insert(name).second) out.call<void>("push", name);
  }
  return out;
}

// {heapBytes: size of the WASM memory, allocatedBytes: bytes in use by malloc}.
val memory_usage() {
  const struct mallinfo mi = mallinfo();
  val out = val::object();
  out.set("heapBytes", val(static_cast<double>(emscripten_get_heap_size())));
  out.set("allocatedBytes", val(static_cast<double>(mi.uordblks)));
  return out;
}

}  // namespace

EMSCRIPTEN_BINDINGS(cdt3d) {
  std::set_new_handler(&on_allocation_failure);
  emscripten::function("_readPlc", +[](val bytes, val file_name) {
    return guarded([&] { return read_plc_js(bytes, file_name); });
  });
  emscripten::function("_tetrahedralize", +[](val input, val options, val progress) {
    return guarded([&] { return tetrahedralize_js(input, options, progress); });
  });
  emscripten::function("_repair", +[](val input, bool fill_holes, bool union_of_parts,
                                      bool parts_as_regions) {
    return guarded([&] { return repair_js(input, fill_holes, union_of_parts, parts_as_regions); });
  });
  emscripten::function("_validate", +[](val input, val result) {
    return guarded([&] { return validate_js(input, result); });
  });
  emscripten::function("_write", +[](std::string format, val result) {
    return guarded([&] { return write_js(format, result); });
  });
  emscripten::function("_delaunay", +[](val points) {
    return guarded([&] { return delaunay_js(points); });
  });
  emscripten::function("_readSurface", +[](val input) {
    return guarded([&] { return read_surface_js(input); });
  });
  emscripten::function("_version", &version);
  emscripten::function("_errorCodes", &error_codes);
  emscripten::function("_memoryUsage", &memory_usage);
}
