// `cdt3d mesh MODEL [options]`: the constrained Delaunay tetrahedralization
// of a PLC (tetrahedralize()), written in a standard format, with statistics.
//
// With --stop-after PHASE the run stops after a step of the algorithm and
// writes the tetrahedralization reached so far (all its tets, nothing
// carved) as PREFIX.node/.ele plus the current subsegments as PREFIX.edge,
// so anyone can inspect an intermediate result in ParaView or another tool.
#include <cdt3d/cdt3d.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iterator>
#include <string>
#include <utility>
#include <vector>

#include "cli.hpp"
#include "refine.hpp"
#include "stats.hpp"

namespace cdt3d {
namespace cli {

namespace {

void usage(std::FILE* out) {
  std::fprintf(
      out,
      "usage: cdt3d mesh MODEL [-o PREFIX] [--format node|vtk|vtu|mesh|msh|msh-binary]\n"
      "                        [--keep-hull] [--validate] [--stats] [--json] [-q]\n"
      "                        [--keep-triangles] [--paper-degeneracy]\n"
      "                        [--no-intersection-check] [--one-thread]\n"
      "                        [--stop-after PHASE]\n"
      "                        [--repair] [--fill-holes] [--keep-inner] [--parts-as-regions]\n"
      "                        [--quality [RATIO]] [--max-volume V] [--min-dihedral D]\n"
      "                        [--max-points N]\n"
      "\n"
      "Constrained Delaunay tetrahedralization of MODEL (.stl .off .obj .ply .poly .smesh).\n"
      "  -o PREFIX         write the mesh: PREFIX.node/.ele/.face (default format),\n"
      "                    PREFIX.vtk, PREFIX.vtu, PREFIX.mesh or PREFIX.msh\n"
      "  --format F        node (TetGen, numbered from 0), vtk (legacy VTK), vtu (VTK XML,\n"
      "                    binary), mesh (Medit), msh or msh-binary (Gmsh 4.1: regions and\n"
      "                    facet markers as physical groups)\n"
      "  --keep-hull       keep the tets between the PLC and its convex hull (tetgen -c)\n"
      "  --validate        check the result: valid, facets recovered, constrained Delaunay\n"
      "  --stats           print quality statistics (dihedral angles, radius-edge ratios;\n"
      "                    before and after refinement when it ran)\n"
      "  --json            print the statistics as one JSON object on stdout\n"
      "  -q                quiet: print nothing but errors\n"
      "  --keep-triangles  keep every input facet (triangle) as a facet, like tetgen -pM; by\n"
      "                    default flat faces are merged first: facets joined by exactly\n"
      "                    coplanar edges form one facet whose inner edges are no\n"
      "                    constraints (like tetgen -p); --merge names that default\n"
      "  --paper-degeneracy  step 3 as in Si & Gaertner 2005, section 6 (perturbations, break points,\n"
      "                    boundary protection) instead of the symbolic perturbation\n"
      "  --no-intersection-check  skip the exact self-intersection test of the input\n"
      "  --one-thread      use one thread (by default the self-intersection test runs beside\n"
      "                    steps 1-2, step 1 of 20,000 points or more takes two threads,\n"
      "                    and half of the facet triangulations and of the statistics run\n"
      "                    beside the other half; same result, more wall time)\n"
      "  --repair          repair the PLC first (as `cdt3d repair`); facets in the output\n"
      "                    and in errors keep their input numbers\n"
      "  --fill-holes      repair, closing the holes of an open surface first (as `cdt3d\n"
      "                    repair --fill-holes`)\n"
      "  --keep-inner      repair, keeping the facets inside the union of crossing\n"
      "                    parts (as `cdt3d repair --keep-inner`)\n"
      "  --parts-as-regions  repair, keeping every part (connected piece of the surface) a\n"
      "                    region of its own: attribute p + 1 where part p alone lies, each\n"
      "                    overlap of parts a region after those (as `cdt3d repair\n"
      "                    --parts-as-regions`)\n"
      "  --stop-after P    delaunay | segments | degeneracy | facets: stop after that step,\n"
      "                    write all tets as PREFIX.node/.ele and the subsegments as .edge\n"
      "quality refinement of the CDT (each of these options turns it on):\n"
      "  --quality [RATIO] bound on circumradius / shortest edge of the tets, >= 1 (default 2.0;\n"
      "                    like tetgen -q); -q stays \"quiet\"\n"
      "  --max-volume V    largest tet volume, > 0 (like tetgen -a); regions' own bounds apply too\n"
      "  --min-dihedral D  then raise the smallest dihedral angle towards D degrees (0-70,\n"
      "                    default 15) by flips, vertex moves and a few new points (like\n"
      "                    tetgen -O); the mesh then covers every facet but is no longer\n"
      "                    Delaunay; 0: no such pass, the result stays a CDT\n"
      "  --max-points N    stop refining after N added points (default 0: 100 times the CDT's\n"
      "                    points plus 1e6; the statistics say when it stopped there)\n"
      "exit codes: 0 success, 1 input or meshing error, 2 usage error\n");
}

}  // namespace

Status write_text(const std::string& name, const std::string& text) {
  Status st;
  std::FILE* f = std::fopen(name.c_str(), "wb");
  if (!f) {
    st.error = {ErrorCode::IoError, "Cannot create the output file.", name};
    return st;
  }
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (std::fclose(f) != 0 || !ok) st.error = {ErrorCode::IoError, "Error while writing the file.", name};
  return st;
}

namespace {

std::string edge_file(const Result& r) {
  std::string s = std::to_string(r.edges.size() / 2) +
                  " 1\n# generated by cdt3d; numbering from 0; marker: input segment + 1\n";
  for (size_t i = 0; i < r.edge_segment.size(); ++i)
    s += std::to_string(i) + " " + std::to_string(r.edges[2 * i]) + " " +
         std::to_string(r.edges[2 * i + 1]) + " " + std::to_string(r.edge_segment[i] + 1) + "\n";
  return s;
}

// TetGen files number from 0 (write_node & co. say so in their header, and
// TetGen reads either); the .edge file uses the same numbering.
Status write_result(const Result& r, const std::string& prefix, const std::string& format,
                    bool intermediate) {
  if (format == "vtk") return write_text(prefix + ".vtk", write_vtk(r.mesh));
  if (format == "mesh") return write_text(prefix + ".mesh", write_medit(r.mesh));
  if (format == "vtu") return write_text(prefix + ".vtu", write_vtu(r));
  if (format == "msh" || format == "msh-binary")
    return write_text(prefix + ".msh", write_msh(r.mesh, format == "msh-binary"));
  Status st = write_text(prefix + ".node", write_node(r.mesh));
  if (st.ok()) st = write_text(prefix + ".ele", write_ele(r.mesh));
  if (st.ok() && !intermediate) st = write_text(prefix + ".face", write_face(r.mesh));
  if (st.ok()) st = write_text(prefix + ".edge", edge_file(r));
  return st;
}

// The statistics come from kStatisticsFields (stats.hpp), the one list the
// bindings and the d.ts are checked against; times are rounded to 1 us.
void print_json(const Result& r, Phase stop, bool validated, const Status& valid,
                const std::string& repair) {
  const Statistics& s = r.stats;
  std::string out = "{\"ok\":true,\"phase\":" + json_string(phase_name(stop)) +
                    ",\"edges\":" + std::to_string(r.edges.size() / 2) +
                    ",\"delaunay\":" + (r.delaunay ? "true" : "false");
  for (const StatisticsField& f : kStatisticsFields) {
    out += ",\"" + std::string(f.name) + "\":";
    if (f.count) {
      out += std::to_string(s.*(f.count));
    } else if (f.real) {
      const bool time = std::strncmp(f.name, "ms", 2) == 0 && std::isupper(f.name[2]);
      char buf[40];
      std::snprintf(buf, sizeof buf, "%.3f", s.*(f.real));
      out += time ? std::string(buf) : json_number(s.*(f.real));
    } else {
      out += "[";
      for (size_t c : s.*(f.histogram)) out += (out.back() == '[' ? "" : ",") + std::to_string(c);
      out += "]";
    }
  }
  out += ",\"valid\":" + std::string(validated ? (valid.ok() ? "true" : "false") : "null") +
         ",\"validation\":" +
         json_string(validated && !valid.ok() ? valid.error.to_string() : "") +
         (repair.empty() ? "" : ",\"repair\":" + repair) + "}\n";
  std::fputs(out.c_str(), stdout);
}

// One histogram line of --stats: "  <title padded> <bin>: <count> ...".
void print_histogram(const char* title, const char* const bins[10],
                     const std::array<size_t, 10>& counts) {
  std::printf("  %-26s", title);
  for (int i = 0; i < 10; ++i) std::printf(" %s: %zu", bins[i], counts[i]);
  std::printf("\n");
}

void print_table(const std::string& input, const Result& r, Phase stop, DegeneracyMode mode,
                 bool show_quality, bool refined, bool validated) {
  const Statistics& s = r.stats;
  std::printf("%s\n", input.c_str());
  std::printf("  Input points:              %zu\n", s.input_points);
  std::printf("  Input facets:              %zu\n", s.input_facets);
  if (r.flat_faces_merged)
    std::printf("  Flat faces:                %zu flat edges, %zu facets merged from several "
                "(--keep-triangles keeps every input facet)\n",
                s.flat_edges, s.merged_facets);
  else
    std::printf("  Flat faces:                not merged (--keep-triangles)\n");
  std::printf("  Input segments:            %zu\n", s.input_segments);
  std::printf("  Mesh points:               %zu\n", s.points);
  std::printf("  Mesh tetrahedra:           %zu\n", s.tets);
  std::printf("  Mesh constrained faces:    %zu\n", s.faces);
  std::printf("  Steiner points:            %zu (segments %zu, facets %zu of which %zu in "
              "failed facet regions, volume %zu)\n",
              s.steiner_segment + s.steiner_facet + s.steiner_volume, s.steiner_segment,
              s.steiner_facet, s.facet_splits, s.steiner_volume);
  std::printf("  Segment recovery (§5):     %zu of %zu segments missing from the Delaunay "
              "tetrahedralization; projection: %zu, shell: %zu, removed again: %zu; "
              "rule 1: %zu, rule 2: %zu, rule 3: %zu, both ends acute: %zu; "
              "at most %zu on one segment\n",
              s.missing_segments, s.input_segments, s.split_projection, s.split_shell,
              s.split_removed, s.rule1, s.rule2, s.rule3, s.acute_both, s.max_splits);
  if (stop >= Phase::Degeneracy) {
    const bool no_points = s.perturbations == 0 && s.break_points == 0 &&
                           s.protect_segment == 0 && s.protect_facet == 0;
    if (mode == DegeneracyMode::Symbolic && no_points)
      std::printf("  Degeneracy removal (§6):   symbolic perturbation (no points)\n");
    else
      std::printf("  Degeneracy removal (§6):   %zu perturbations, %zu break points, %zu + %zu "
                  "protecting points (segments + facets)\n",
                  s.perturbations, s.break_points, s.protect_segment, s.protect_facet);
  }
  if (stop >= Phase::Facets)
    std::printf("  Facet recovery (§7):       %zu missing subfaces, %zu regions, %zu cavities "
                "(largest %zu faces), %zu fallbacks, %zu facet splits\n",
                s.missing_subfaces, s.regions, s.cavities, s.largest_cavity, s.fallbacks,
                s.facet_splits);
  if (refined) {
    std::printf("  Quality refinement:        %zu points (segments %zu, facets %zu, volume %zu); "
                "%zu bad tets left where no split point fits (%zu at small input angles)%s\n",
                s.refine_segment + s.refine_facet + s.refine_volume, s.refine_segment,
                s.refine_facet, s.refine_volume, s.refine_skipped, s.refine_small_angle,
                s.refine_capped ? "; stopped at the point limit (--max-points)" : "");
    std::printf("  Sliver improvement:        %zu flips, %zu vertex moves, %zu points added\n",
                s.improve_flips, s.improve_smooths, s.improve_points);
  }
  std::printf("  Flat tetrahedra:           %zu in the output, %zu removed by flips", s.flat_tets,
              s.flat_flips);
  if (s.flat_peeled > 0) std::printf(", %zu left out of the hull", s.flat_peeled);
  std::printf("\n");
  std::printf("  Time (ms):                 read %.1f, delaunay %.1f, segments %.1f, "
              "degeneracy %.1f, facets %.1f, carve %.1f, ",
              s.ms_read, s.ms_delaunay, s.ms_segments, s.ms_degeneracy, s.ms_facets, s.ms_carve);
  if (refined) std::printf("refine %.1f, ", s.ms_refine);
  std::printf("total %.1f\n", s.ms_total);
  if (show_quality) {
    static const char* const ratio_bins[10] = {"<1",   "1-1.5", "1.5-2", "2-3",    "3-5",
                                               "5-10", "10-20", "20-50", "50-100", ">100"};
    static const char* const angle_bins[10] = {"<1",    "1-5",   "5-10",  "10-15", "15-20",
                                               "20-30", "30-40", "40-50", "50-60", ">60"};
    if (refined) {
      std::printf("  Dihedral angles (deg):     min %.3f (before refinement %.3f), max %.3f\n",
                  s.min_dihedral, s.min_dihedral_before, s.max_dihedral);
      print_histogram("Radius-edge ratios before:", ratio_bins, s.radius_edge_histogram_before);
      print_histogram("Radius-edge ratios after:", ratio_bins, s.radius_edge_histogram);
      print_histogram("Min dihedral/tet before:", angle_bins, s.dihedral_histogram_before);
      print_histogram("Min dihedral/tet after:", angle_bins, s.dihedral_histogram);
    } else {
      std::printf("  Dihedral angles (deg):     min %.3f, max %.3f\n", s.min_dihedral,
                  s.max_dihedral);
      print_histogram("Radius-edge ratios:", ratio_bins, s.radius_edge_histogram);
      print_histogram("Min dihedral/tet (deg):", angle_bins, s.dihedral_histogram);
    }
  }
  if (validated)
    std::printf("  Validation:                passed%s\n",
                r.delaunay ? "" : " (not Delaunay after the improvement pass: not checked)");
}

// A whole command-line word as a double ("1.5", "-1", "1e-3", "inf");
// false for anything else ("abc", "1.5x", ""), `out` then unchanged.
bool parse_number(const char* text, double& out) {
  if (*text == '\0' || std::isspace(static_cast<unsigned char>(*text))) return false;
  char* end = nullptr;
  const double v = std::strtod(text, &end);
  if (*end != '\0') return false;
  out = v;
  return true;
}

// A whole command-line word as a non-negative integer; `out` unchanged on failure.
bool parse_count(const char* text, size_t& out) {
  if (!std::isdigit(static_cast<unsigned char>(*text))) return false;
  char* end = nullptr;
  errno = 0;
  const unsigned long long v = std::strtoull(text, &end, 10);
  if (*end != '\0' || errno == ERANGE || v > SIZE_MAX) return false;
  out = static_cast<size_t>(v);
  return true;
}

// The command line of `cdt3d mesh`.
struct MeshArgs {
  std::string input, prefix, format = "node", stop_name;
  bool json = false, quiet = false, show_quality = false, fix = false;
  RepairOptions repair_options;
  Options opt;
  Phase stop = Phase::Done;
  // Each quality option with its value alone (the other fields at their
  // defaults), checked after parsing so that an error names the option.
  std::vector<std::pair<std::string, QualityOptions>> quality_args;
};

constexpr int kContinue = -1;

// Reads the words into `m`: kContinue, or the exit code (help, usage error).
int parse_mesh_args(int argc, char** argv, MeshArgs& m) {
  std::string& input = m.input;
  std::string& prefix = m.prefix;
  std::string& format = m.format;
  std::string& stop_name = m.stop_name;
  bool& json = m.json;
  bool& quiet = m.quiet;
  bool& show_quality = m.show_quality;
  bool& fix = m.fix;
  RepairOptions& repair_options = m.repair_options;
  Options& opt = m.opt;
  auto& quality_args = m.quality_args;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return kExitOk;
    } else if (a == "--json") {
      json = true;
    } else if (a == "-q") {
      quiet = true;
    } else if (a == "--stats") {
      show_quality = true;
    } else if (a == "--quality") {
      // The ratio is optional: the next word is taken only if it is a number.
      QualityOptions one;
      if (i + 1 < argc && parse_number(argv[i + 1], one.radius_edge)) ++i;
      opt.quality.radius_edge = one.radius_edge;
      quality_args.emplace_back(a, one);
    } else if (a == "--max-volume" || a == "--min-dihedral" || a == "--max-points") {
      QualityOptions one;
      const char* value = i + 1 < argc ? argv[i + 1] : nullptr;
      bool ok = value != nullptr;
      if (ok && a == "--max-volume") ok = parse_number(value, one.max_volume);
      if (ok && a == "--min-dihedral") ok = parse_number(value, one.min_dihedral);
      if (ok && a == "--max-points") ok = parse_count(value, one.max_points);
      if (!ok) {
        if (value)
          std::fprintf(stderr, "cdt3d mesh: %s takes %s, not '%s'\n", a.c_str(),
                       a == "--max-points" ? "a whole number >= 0" : "a number", value);
        else
          std::fprintf(stderr, "cdt3d mesh: %s needs a value\n", a.c_str());
        return kExitUsage;
      }
      ++i;
      if (a == "--max-volume") opt.quality.max_volume = one.max_volume;
      if (a == "--min-dihedral") opt.quality.min_dihedral = one.min_dihedral;
      if (a == "--max-points") opt.quality.max_points = one.max_points;
      quality_args.emplace_back(a, one);
    } else if (a == "--keep-hull") {
      opt.keep_convex_hull = true;
    } else if (a == "--validate") {
      opt.validate = true;
    } else if (a == "--paper-degeneracy") {
      opt.degeneracy = DegeneracyMode::Paper;
    } else if (a == "--keep-triangles") {
      opt.keep_triangles = true;
    } else if (a == "--merge") {
      opt.keep_triangles = false;  // the default, named
    } else if (a == "--repair") {
      fix = true;
    } else if (a == "--fill-holes") {
      fix = true;  // filling holes is a step of repair
      repair_options.fill_holes = true;
    } else if (a == "--keep-inner") {
      fix = true;  // a choice of repair's
      repair_options.union_of_parts = false;
    } else if (a == "--parts-as-regions") {
      fix = true;  // a choice of repair's
      repair_options.parts_as_regions = true;
    } else if (a == "--no-intersection-check") {
      opt.check_intersections = false;
    } else if (a == "--one-thread") {
      opt.threads = false;
    } else if ((a == "-o" || a == "--stop-after" || a == "--format") && i + 1 < argc) {
      (a == "-o" ? prefix : a == "--format" ? format : stop_name) = argv[++i];
    } else if (!a.empty() && a[0] != '-' && input.empty()) {
      input = a;
    } else {
      std::fprintf(stderr, "cdt3d mesh: unexpected argument '%s'\n", a.c_str());
      usage(stderr);
      return kExitUsage;
    }
  }
  return kContinue;
}

// The checks that need all the words: phase, format, quality values.
int check_mesh_args(MeshArgs& m) {
  Phase& stop = m.stop;
  const std::string& stop_name = m.stop_name;
  const std::string& input = m.input;
  std::string& format = m.format;
  Options& opt = m.opt;
  const auto& quality_args = m.quality_args;
  if (!stop_name.empty() &&
      (!phase_from_name(stop_name, stop) || stop < Phase::Delaunay || stop > Phase::Facets)) {
    std::fprintf(stderr, "cdt3d mesh: --stop-after takes delaunay, segments, degeneracy or "
                         "facets, not '%s'\n",
                 stop_name.c_str());
    return kExitUsage;
  }
  static const char* const kFormats[] = {"node", "vtk", "vtu", "mesh", "msh", "msh-binary"};
  const bool known = std::any_of(std::begin(kFormats), std::end(kFormats),
                                 [&](const char* f) { return format == f; });
  if (input.empty() || !known) {
    if (!input.empty()) std::fprintf(stderr, "cdt3d mesh: unknown format '%s'\n", format.c_str());
    usage(stderr);
    return kExitUsage;
  }
  for (auto& [option, one] : quality_args) {
    const Status qs = check_quality_options(one);
    if (!qs.ok()) {
      std::fprintf(stderr, "cdt3d mesh: %s: %s\n", option.c_str(), qs.error.message.c_str());
      return kExitUsage;
    }
  }
  if (m.repair_options.parts_as_regions && !m.repair_options.union_of_parts) {
    std::fprintf(stderr, "cdt3d mesh: --parts-as-regions keeps the union of the parts; it cannot "
                         "go with --keep-inner\n");
    return kExitUsage;
  }
  opt.quality.enabled = !quality_args.empty();
  if (opt.quality.enabled && stop != Phase::Done) {
    std::fprintf(stderr, "cdt3d mesh: %s refines the finished CDT; it cannot go with --stop-after\n",
                 quality_args.front().first.c_str());
    return kExitUsage;
  }
  if (stop != Phase::Done) format = "node";
  opt.stop_after = stop;
  return kContinue;
}

// Ends the process once the answer is out (the output files are closed by
// write_result; std::exit flushes stdio). It does not run the destructors of
// the caller's frame, so the PLC and the Result (two allocations per
// facet) are not freed one allocation at a time only for the process to
// give their memory back anyway.
[[noreturn]] void exit_keeping_memory(int code) { std::exit(code); }

}  // namespace

int run_mesh(int argc, char** argv) {
  MeshArgs m;
  int code = parse_mesh_args(argc, argv, m);
  if (code == kContinue) code = check_mesh_args(m);
  if (code != kContinue) return code;
  const std::string& input = m.input;
  const bool fix = m.fix, json = m.json;
  const Options& opt = m.opt;
  const Phase stop = m.stop;
  const bool intermediate = stop != Phase::Done;
  // --validate runs the full validator on complete results; after an
  // intermediate phase it checks the mesh invariants only.

  const auto t0 = std::chrono::steady_clock::now();
  Plc plc;
  // The input checks (check_plc) are tetrahedralize()'s first step, or
  // repair's business with --repair: reading does not run them too, so
  // their sorts of the points and the facets are not paid twice.
  Status st = read_plc_file(input, plc, false);
  RepairReport report;
  if (st.ok() && fix) {
    Plc fixed;
    st = repair(plc, fixed, report, m.repair_options);
    plc = std::move(fixed);
  }
  const double ms_read =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  Result r;
  if (st.ok()) {
    r = tetrahedralize(plc, opt);  // validates against the repaired PLC (opt.validate)
    if (fix) map_to_input_facets(report, r);
    st = r.status;
  }
  r.stats.ms_read += ms_read;
  r.stats.ms_total += ms_read;
  const bool validated = opt.validate && !intermediate;
  if (st.ok() && !m.prefix.empty()) st = write_result(r, m.prefix, m.format, intermediate);
  if (!st.ok()) {
    if (json)
      print_json_error(st.error);
    else
      std::fprintf(stderr, "cdt3d mesh: %s\n", st.error.to_string().c_str());
    exit_keeping_memory(kExitError);
  }
  if (json) {
    print_json(r, stop, validated, st, fix ? repair_json(report) : std::string());
  } else if (!m.quiet) {
    print_table(input, r, stop, opt.degeneracy, m.show_quality, opt.quality.enabled, validated);
    if (fix) std::printf("%s", repair_summary(report).c_str());
  }
  exit_keeping_memory(kExitOk);
}

}  // namespace cli
}  // namespace cdt3d
