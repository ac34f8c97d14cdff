// cdt3d command-line tool: dispatches to one function per subcommand.
#include <cstdio>
#include <cstring>

#include "cli.hpp"

namespace {

void print_usage(std::FILE* out) {
  std::fprintf(out,
               "usage: cdt3d <command> [arguments]\n"
               "\n"
               "commands:\n"
               "  info MODEL               read a PLC and print its summary\n"
               "  delaunay POINTS [-o P]   Delaunay tetrahedralization of the points\n"
               "  mesh MODEL --stop-after PHASE [-o P]\n"
               "                           run the CDT pipeline up to a phase\n"
               "  repair MODEL [-o P]      repair the PLC exactly, write P.poly\n"
               "  mesh MODEL --repair      repair, then mesh\n"
               "\n"
               "MODEL: .stl (ASCII/binary) .off .obj .ply .poly .smesh\n"
               "exit codes: 0 success, 1 input or meshing error, 2 usage error\n");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || !std::strcmp(argv[1], "-h") || !std::strcmp(argv[1], "--help")) {
    print_usage(argc < 2 ? stderr : stdout);
    return argc < 2 ? cdt3d::cli::kExitUsage : 0;
  }
  const char* cmd = argv[1];
  if (!std::strcmp(cmd, "info")) return cdt3d::cli::run_info(argc - 2, argv + 2);
  if (!std::strcmp(cmd, "delaunay")) return cdt3d::cli::run_delaunay(argc - 2, argv + 2);
  if (!std::strcmp(cmd, "mesh")) return cdt3d::cli::run_mesh(argc - 2, argv + 2);
  if (!std::strcmp(cmd, "repair")) return cdt3d::cli::run_repair(argc - 2, argv + 2);
  std::fprintf(stderr, "cdt3d: unknown command '%s'\n", cmd);
  print_usage(stderr);
  return cdt3d::cli::kExitUsage;
}
