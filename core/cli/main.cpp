// cdt3d command-line tool: dispatches to one function per subcommand.
#include <cstdio>
#include <cstring>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

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

// The mesher's big arrays (tets, adjacency, per-phase tables) are allocated,
// freed and allocated again phase after phase. glibc serves blocks above
// 128 KiB by mmap and trims the heap top past 128 KiB, so each round trip
// returns the pages to the kernel and faults them in again on first touch;
// page faults took 10-15% of a CLI run in the profiles (more under a
// hypervisor). Keeping freed memory in the process avoids that; the peak
// (what the process touches at once) does not grow. One arena for the two
// threads of a run (the self-intersection test runs beside step 1): a second
// arena's pages are fresh, and what the test frees there would never serve
// the later phases (armadillo: 19.1k page faults with two arenas, 15.3k with
// one, as on one thread; the test makes few allocations, so the shared lock
// costs nothing measurable).
void keep_freed_memory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, 1 << 30);
  mallopt(M_ARENA_MAX, 1);
#endif
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory();
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
