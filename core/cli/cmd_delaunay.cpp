// `cdt3d delaunay POINTS [-o PREFIX] [--json] [--one-thread]`: Delaunay tetrahedralization
// of a point set (step 1 alone), for testing and benchmarking.
//
// POINTS is a TetGen .node file (read by the TetGen reader's node-section functions, which keeps
// duplicate points and counts them) or any model read_plc_file() accepts
// (only its points are used). With -o, writes PREFIX.node (every input point,
// in input order, duplicates included) and PREFIX.ele (the tets), both
// numbered from 1 as in TetGen's default output, tets oriented as TetGen
// writes them ((b - a) x (c - a) . (d - a) > 0). Statistics go to stdout.
#include <cdt3d/cdt3d.hpp>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <numeric>
#include <string>
#include <vector>

#include "cli.hpp"
#include "delaunay.hpp"

namespace cdt3d {
namespace cli {

namespace {

void usage(std::FILE* out) {
  std::fprintf(out,
               "usage: cdt3d delaunay POINTS [-o PREFIX] [--json] [--one-thread]\n"
               "  POINTS     .node point file, or a model (.off .stl .obj .ply .poly .smesh)\n"
               "  -o PREFIX  write PREFIX.node and PREFIX.ele (TetGen format, numbered from 1)\n"
               "  --json     print "
               "{\"points\",\"duplicates\",\"vertices\",\"tets\",\"hullFaces\",\"ms\"}\n"
               "  --one-thread  insert every point on this thread and list the tets as they\n"
               "             were made (by default the later rounds of 20,000 points or more go\n"
               "             to two threads and the tets come in a canonical order; the same\n"
               "             tetrahedralization either way)\n");
}

bool ends_with_nocase(const std::string& s, const char* suffix) {
  const size_t n = std::strlen(suffix);
  if (s.size() < n) return false;
  for (size_t i = 0; i < n; ++i) {
    char c = s[s.size() - n + i];
    if (c >= 'A' && c <= 'Z') c = char(c - 'A' + 'a');
    if (c != suffix[i]) return false;
  }
  return true;
}

// Peak resident set size in MiB from /proc/self/status (Linux), or -1.
double peak_rss_mib() {
  std::FILE* f = std::fopen("/proc/self/status", "r");
  if (!f) return -1;
  char line[256];
  double kib = -1;
  while (std::fgets(line, sizeof line, f))
    if (!std::strncmp(line, "VmHWM:", 6)) kib = std::atof(line + 6);
  std::fclose(f);
  return kib < 0 ? -1 : kib / 1024.0;
}

double ms_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

int run_delaunay(int argc, char** argv) {
  std::string input, prefix;
  bool json = false;
  DelaunayOptions options;
  options.threads = true;
  for (int i = 0; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "-h" || a == "--help") {
      usage(stdout);
      return kExitOk;
    } else if (a == "--json") {
      json = true;
    } else if (a == "--one-thread") {
      options.threads = false;
      options.canonical = false;
    } else if (a == "-o") {
      if (i + 1 >= argc) {
        std::fprintf(stderr, "cdt3d delaunay: -o needs a PREFIX\n");
        usage(stderr);
        return kExitUsage;
      }
      prefix = argv[++i];
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "cdt3d delaunay: unknown option '%s'\n", a.c_str());
      usage(stderr);
      return kExitUsage;
    } else if (input.empty()) {
      input = a;
    } else {
      std::fprintf(stderr, "cdt3d delaunay: more than one input file\n");
      usage(stderr);
      return kExitUsage;
    }
  }
  if (input.empty()) {
    usage(stderr);
    return kExitUsage;
  }

  const auto t_read = std::chrono::steady_clock::now();
  TetMesh mesh;
  Status s;
  if (ends_with_nocase(input, ".node")) {
    s = read_node_points_file(input, mesh.coords);
  } else {
    Plc plc;
    s = read_plc_file(input, plc);
    if (s.ok()) {
      mesh.coords.reserve(3 * plc.points.size());
      for (const Vec3& p : plc.points) mesh.coords.insert(mesh.coords.end(), {p.x, p.y, p.z});
    }
  }
  if (!s.ok()) {
    if (s.error.file.empty()) s.error.file = input;
    std::fprintf(stderr, "cdt3d delaunay: %s\n", s.error.to_string().c_str());
    return kExitError;
  }
  const double ms_read = ms_since(t_read);

  std::vector<VertexId> all(mesh.num_vertices());
  std::iota(all.begin(), all.end(), VertexId(0));
  DelaunayStats st;
  s = delaunay_tetrahedralize_vertices(mesh, all, nullptr, &st, options);
  std::vector<VertexId>().swap(all);
  if (!s.ok()) {
    if (s.error.file.empty()) s.error.file = input;
    std::fprintf(stderr, "cdt3d delaunay: %s\n", s.error.to_string().c_str());
    return kExitError;
  }

  double ms_write = 0;
  if (!prefix.empty()) {
    const auto t_write = std::chrono::steady_clock::now();
    s = write_node_ele(mesh, prefix);
    if (!s.ok()) {
      std::fprintf(stderr, "cdt3d delaunay: %s\n", s.error.to_string().c_str());
      return kExitError;
    }
    ms_write = ms_since(t_write);
  }

  const double ms = st.ms_sort + st.ms_insert;
  if (json) {
    std::printf(
        "{\"points\":%zu,\"duplicates\":%zu,\"vertices\":%zu,\"tets\":%zu,\"hullFaces\":%zu,"
        "\"ms\":%.3f}\n",
        st.points, st.duplicates, st.vertices, st.tets, st.hull_faces, ms);
    return kExitOk;
  }
  const double peak = peak_rss_mib();
  std::printf("input points   %zu\n", st.points);
  std::printf("duplicates     %zu\n", st.duplicates);
  std::printf("vertices       %zu\n", st.vertices);
  std::printf("tets           %zu\n", st.tets);
  std::printf("hull faces     %zu\n", st.hull_faces);
  std::printf("time read      %.1f ms\n", ms_read);
  std::printf("time sort      %.1f ms\n", st.ms_sort);
  std::printf("time insert    %.1f ms\n", st.ms_insert);
  if (!prefix.empty()) std::printf("time write     %.1f ms\n", ms_write);
  std::printf("walk steps     %.2f per point\n",
              st.points ? double(st.walk_steps) / double(st.points) : 0.0);
  std::printf("cavity tets    %.2f per point\n",
              st.points ? double(st.cavity_tets) / double(st.points) : 0.0);
  const pred::Counters& pc = pred::counters();
  std::printf(
      "insphere       %.2f per point, %.4f%% exact\n",
      st.points ? double(pc.insphere_calls) / double(st.points) : 0.0,
      pc.insphere_calls ? 100.0 * double(pc.insphere_exact) / double(pc.insphere_calls) : 0.0);
  std::printf(
      "orient3d       %.2f per point, %.4f%% exact\n",
      st.points ? double(pc.orient3d_calls) / double(st.points) : 0.0,
      pc.orient3d_calls ? 100.0 * double(pc.orient3d_exact) / double(pc.orient3d_calls) : 0.0);
  if (peak >= 0)
    std::printf("peak memory    %.1f MiB\n", peak);
  else
    std::printf("peak memory    n/a\n");
  return kExitOk;
}

}  // namespace cli
}  // namespace cdt3d
