// `cdt3d repair MODEL -o PREFIX [--json] [-q]`: repair() of a PLC, written
// as PREFIX.poly, with what each step changed. Also the report printing that
// `cdt3d mesh --repair` shares.
#include <cdt3d/cdt3d.hpp>

#include <cstdio>
#include <string>

#include "cli.hpp"
#include "repair.hpp"

namespace cdt3d {
namespace cli {
namespace {

void repair_usage(std::FILE* out) {
  std::fprintf(out,
               "usage: cdt3d repair MODEL [-o PREFIX] [--fill-holes] [--keep-inner]\n"
               "                    [--parts-as-regions] [--json] [-q]\n"
               "\n"
               "Repairs MODEL (.stl .off .obj .ply .poly .smesh) exactly: welds identical points,\n"
               "drops repeated vertices, zero-area polygons and duplicate facets, splits\n"
               "non-planar facets, makes T-junction vertices vertices of the facets they lie\n"
               "on, inserts the intersection segments of crossing facets; where parts crossed,\n"
               "the domain is their union (facets inside it dropped). Prints what changed.\n"
               "  -o PREFIX   write the repaired PLC as PREFIX.poly (TetGen format)\n"
               "  --fill-holes  close every boundary loop of an open surface with triangles of\n"
               "              its vertices (least total area; a non-planar hole's patch then\n"
               "              refined and smoothed) before the other steps\n"
               "  --keep-inner  keep the facets inside the union of crossing parts: every cell\n"
               "              of their arrangement is meshed, bounded by internal facets\n"
               "  --parts-as-regions  keep the union, but with the facets between parts: each\n"
               "              part (connected piece of the surface) and each overlap of parts\n"
               "              becomes a region (`cdt3d mesh --parts-as-regions`; the .poly\n"
               "              gets a region point per region, attributes as the report's)\n"
               "  --json      print the report as one JSON object on stdout\n"
               "  -q          quiet: print nothing but errors\n"
               "exit codes: 0 repaired (or nothing to repair), 1 input error or what repair\n"
               "could not fix (the message names the input facets), 2 usage error\n");
}

// "3 parts, 4 regions: 1 = part 0, 2 = part 1, 4 = parts 0+1" (regions
// without a cell left out).
std::string region_list(const RepairReport& r) {
  std::string list;
  size_t regions = 0;
  for (size_t a = 0; a < r.region_parts.size(); ++a) {
    const std::vector<uint32_t>& parts = r.region_parts[a];
    if (parts.empty()) continue;
    ++regions;
    list += (list.empty() ? ": " : ", ") + std::to_string(a + 1) + (parts.size() == 1 ? " = part " : " = parts ");
    for (size_t i = 0; i < parts.size(); ++i) list += (i ? "+" : "") + std::to_string(parts[i]);
  }
  return std::to_string(r.parts) + " parts, " + std::to_string(regions) + " regions" + list;
}

}  // namespace

std::string repair_summary(const RepairReport& r) {
  if (!r.changed()) {
    std::string text = "  Repair: nothing to change (the PLC is valid)\n";
    if (!r.facet_regions.empty()) text += "    parts as regions: " + region_list(r) + "\n";
    return text;
  }
  char buf[1024];
  std::snprintf(
      buf, sizeof buf,
      "  Repair: %zu -> %zu points, %zu -> %zu facets, %zu input facets changed (%.1f ms)\n"
      "    welded points %zu, repeated vertices %zu, zero-area polygons %zu, degenerate facets "
      "%zu, duplicate facets %zu\n"
      "    holes filled %zu with %zu triangles and %zu new points, %zu left open\n"
      "    non-planar facets split %zu\n"
      "    T-junction vertices %zu in %zu facets\n"
      "    crossing facet pairs %zu: %zu facets split, %zu new points, %zu rounds, %zu pairs left\n"
      "    explicit segments crossing or touching %zu: split into %zu more pieces\n",
      r.input_points, r.points, r.input_facets, r.facets, r.changed_facets.size(), r.ms,
      r.welded_points, r.repeated_vertices, r.zero_area_polygons, r.degenerate_facets,
      r.duplicate_facets, r.filled_holes, r.fill_triangles, r.fill_points, r.unfilled_holes, r.nonplanar_facets,
      r.tjunction_vertices, r.tjunction_facets, r.crossing_pairs, r.crossing_facets,
      r.intersection_points, r.rounds, r.unresolved_pairs, r.crossing_segments, r.segment_splits);
  std::string text = buf;
  if (r.union_skipped) {
    text += "    union of the parts: not formed (the facets, oriented like their input facets, do not close up)\n";
    if (r.outside_facets > 0)
      text += "    facets with the outside on both sides (fins): " + std::to_string(r.outside_facets) + " dropped\n";
  } else if (r.inner_facets > 0) {
    text += "    union of the parts: " + std::to_string(r.inner_facets) + " inner facets dropped\n";
  }
  if (!r.facet_regions.empty()) text += "    parts as regions: " + region_list(r) + "\n";
  return text;
}

std::string repair_json(const RepairReport& r) {
  char buf[1024];
  std::snprintf(
      buf, sizeof buf,
      "{\"changed\":%s,\"inputPoints\":%zu,\"points\":%zu,\"inputFacets\":%zu,\"facets\":%zu,"
      "\"changedFacets\":%zu,\"weldedPoints\":%zu,\"repeatedVertices\":%zu,"
      "\"zeroAreaPolygons\":%zu,\"degenerateFacets\":%zu,\"duplicateFacets\":%zu,"
      "\"filledHoles\":%zu,\"fillTriangles\":%zu,\"fillPoints\":%zu,\"unfilledHoles\":%zu,"
      "\"nonplanarFacets\":%zu,\"tjunctionVertices\":%zu,\"tjunctionFacets\":%zu,"
      "\"crossingPairs\":%zu,\"crossingFacets\":%zu,\"intersectionPoints\":%zu,\"rounds\":%zu,"
      "\"unresolvedPairs\":%zu,\"crossingSegments\":%zu,\"segmentSplits\":%zu,\"innerFacets\":%zu,\"unionSkipped\":%s,\"outsideFacets\":%zu,\"ms\":%.3f}",
      r.changed() ? "true" : "false", r.input_points, r.points, r.input_facets, r.facets,
      r.changed_facets.size(), r.welded_points, r.repeated_vertices, r.zero_area_polygons,
      r.degenerate_facets, r.duplicate_facets, r.filled_holes, r.fill_triangles, r.fill_points, r.unfilled_holes,
      r.nonplanar_facets, r.tjunction_vertices,
      r.tjunction_facets, r.crossing_pairs, r.crossing_facets, r.intersection_points, r.rounds,
      r.unresolved_pairs, r.crossing_segments, r.segment_splits, r.inner_facets, r.union_skipped ? "true" : "false",
      r.outside_facets, r.ms);
  std::string json = buf;
  // "parts": N, "regionParts": [[0], [1], [0, 1]] (entry a - 1 for attribute a).
  std::string list;
  for (size_t a = 0; a < r.region_parts.size(); ++a) {
    list += a ? ",[" : "[";
    for (size_t i = 0; i < r.region_parts[a].size(); ++i)
      list += (i ? "," : "") + std::to_string(r.region_parts[a][i]);
    list += "]";
  }
  json.pop_back();  // the closing brace
  return json + ",\"parts\":" + std::to_string(r.parts) + ",\"regionParts\":[" + list + "]}";
}

int run_repair(int argc, char** argv) {
  std::string input, prefix;
  bool json = false, quiet = false;
  RepairOptions options;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      repair_usage(stdout);
      return kExitOk;
    } else if (a == "--json") {
      json = true;
    } else if (a == "-q") {
      quiet = true;
    } else if (a == "--fill-holes") {
      options.fill_holes = true;
    } else if (a == "--keep-inner") {
      options.union_of_parts = false;
    } else if (a == "--parts-as-regions") {
      options.parts_as_regions = true;
    } else if (a == "-o" && i + 1 < argc) {
      prefix = argv[++i];
    } else if (!a.empty() && a[0] != '-' && input.empty()) {
      input = a;
    } else {
      std::fprintf(stderr, "cdt3d repair: unexpected argument '%s'\n", a.c_str());
      repair_usage(stderr);
      return kExitUsage;
    }
  }
  if (options.parts_as_regions && !options.union_of_parts) {
    std::fprintf(stderr, "cdt3d repair: --parts-as-regions keeps the union of the parts; it "
                         "cannot go with --keep-inner\n");
    return kExitUsage;
  }
  if (input.empty()) {
    repair_usage(stderr);
    return kExitUsage;
  }
  Plc plc, fixed;
  RepairReport report;
  // Read without the input checks: what they reject is what repair fixes.
  Status st = read_plc_file(input, plc, false);
  if (st.ok()) st = repair(plc, fixed, report, options);
  // With parts as regions the .poly says which region is which.
  if (st.ok() && !prefix.empty() && options.parts_as_regions)
    st = repair_steps::add_part_region_points(fixed, report);
  if (st.ok() && !prefix.empty()) st = write_text(prefix + ".poly", write_poly(fixed));
  if (!st.ok()) {
    if (json)
      print_json_error(st.error);
    else
      std::fprintf(stderr, "cdt3d repair: %s\n", st.error.to_string().c_str());
    return kExitError;
  }
  if (json)
    std::printf("{\"ok\":true,\"repair\":%s}\n", repair_json(report).c_str());
  else if (!quiet)
    std::printf("%s\n%s", input.c_str(), repair_summary(report).c_str());
  return kExitOk;
}

}  // namespace cli
}  // namespace cdt3d
