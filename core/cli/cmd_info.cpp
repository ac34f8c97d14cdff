// `cdt3d info MODEL [--json]`: read a PLC and print its summary.
//
// Plain mode prints one "name: value" line per item; on an input error the
// message (Error::to_string) goes to stderr. --json prints exactly one JSON
// object on stdout in both cases, with the field names of the WASM readPlc()
// result. Exit codes: 0 success, 1 input error, 2 usage error.
#include <cdt3d/cdt3d.hpp>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <string>

#include "cli.hpp"

namespace cdt3d {
namespace cli {
namespace {

void info_usage(std::FILE* out) {
  std::fprintf(out,
               "usage: cdt3d info MODEL [--json]\n"
               "\n"
               "Reads MODEL (.stl .off .obj .ply .poly .smesh .node), checks it and prints\n"
               "its summary. --json prints one JSON object on stdout instead.\n");
}

const char* format_name(FileFormat f) {
  switch (f) {
    case FileFormat::Stl:
      return "STL";
    case FileFormat::Off:
      return "OFF";
    case FileFormat::Obj:
      return "OBJ";
    case FileFormat::Ply:
      return "PLY";
    case FileFormat::Poly:
      return "TetGen .poly";
    case FileFormat::Smesh:
      return "TetGen .smesh";
    case FileFormat::Node:
      return "TetGen .node";
    case FileFormat::Unknown:
      break;
  }
  return "unknown";
}

void print_json_info(const Plc& plc, const PlcInfo& info) {
  std::printf(
      "{\"ok\":true,\"file\":%s,\"fileVertices\":%zu,\"points\":%zu,\"welded\":%zu,"
      "\"unreferenced\":%zu,\"facets\":%zu,\"triangles\":%zu,\"loops\":%zu,\"segments\":%zu,"
      "\"holes\":%zu,\"regions\":%zu,\"bboxMin\":%s,\"bboxMax\":%s}\n",
      json_string(plc.file).c_str(), info.file_vertices, info.points, plc.welded_vertices,
      info.unreferenced, info.facets, info.triangles, info.loops, info.segments, info.holes,
      info.regions, json_vec3(info.bbox_min).c_str(), json_vec3(info.bbox_max).c_str());
}

void print_plain_info(const Plc& plc, const PlcInfo& info, double ms) {
  std::printf("file:           %s\n", plc.file.c_str());
  std::printf("format:         %s\n", format_name(format_from_name(plc.file)));
  std::printf("file vertices:  %zu\n", info.file_vertices);
  std::printf("points:         %zu\n", info.points);
  std::printf("welded:         %zu\n", plc.welded_vertices);
  std::printf("unreferenced:   %zu\n", info.unreferenced);
  std::printf("facets:         %zu\n", info.facets);
  std::printf("loops:          %zu\n", info.loops);
  std::printf("triangles:      %zu\n", info.triangles);
  std::printf("segments:       %zu\n", info.segments);
  std::printf("holes:          %zu\n", info.holes);
  std::printf("regions:        %zu\n", info.regions);
  std::printf("bbox min:       %.17g %.17g %.17g\n", info.bbox_min.x, info.bbox_min.y,
              info.bbox_min.z);
  std::printf("bbox max:       %.17g %.17g %.17g\n", info.bbox_max.x, info.bbox_max.y,
              info.bbox_max.z);
  std::printf("read time:      %.1f ms\n", ms);
}

}  // namespace

int run_info(int argc, char** argv) {
  bool json = false;
  const char* model = nullptr;
  for (int i = 0; i < argc; ++i) {
    const char* a = argv[i];
    if (!std::strcmp(a, "--json")) {
      json = true;
    } else if (!std::strcmp(a, "-h") || !std::strcmp(a, "--help")) {
      info_usage(stdout);
      return kExitOk;
    } else if (a[0] == '-' && a[1] != '\0') {
      std::fprintf(stderr, "cdt3d info: unknown option '%s'\n", a);
      info_usage(stderr);
      return kExitUsage;
    } else if (model) {
      std::fprintf(stderr, "cdt3d info: one MODEL only (got '%s' and '%s')\n", model, a);
      info_usage(stderr);
      return kExitUsage;
    } else {
      model = a;
    }
  }
  if (!model) {
    info_usage(stderr);
    return kExitUsage;
  }

  Plc plc;
  const auto t0 = std::chrono::steady_clock::now();
  const Status status = read_plc_file(model, plc);
  const auto t1 = std::chrono::steady_clock::now();
  const double ms = std::chrono::duration<double, std::milli>(t1 - t0).count();
  if (!status.ok()) {
    if (json) {
      print_json_error(status.error);
    } else {
      std::fprintf(stderr, "cdt3d: %s\n", status.error.to_string().c_str());
    }
    return kExitError;
  }
  const PlcInfo info = plc_info(plc);
  if (json) {
    print_json_info(plc, info);
  } else {
    print_plain_info(plc, info, ms);
  }
  return kExitOk;
}

}  // namespace cli
}  // namespace cdt3d
