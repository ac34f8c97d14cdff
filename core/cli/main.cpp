// cdt3d command-line tool: dispatches to one function per subcommand.
#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#if defined(__GLIBC__)
#include <malloc.h>
#include <sys/stat.h>
#include <unistd.h>
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
// returns the pages to the kernel and faults them in again on first touch,
// a large share of a CLI run (more under a hypervisor). Keeping freed
// memory in the process avoids that (for small inputs: on big ones the
// holes it keeps raise the peak, see rerun_with_tuned_malloc). One arena
// for the two threads of a run (the self-intersection test runs beside
// steps 1-2): a second arena's pages are fresh, and what the test frees
// there would never serve the later phases; the test makes few
// allocations, so the shared lock costs next to nothing.
void keep_freed_memory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, -1);  // never: the CLI exits when its run ends
  mallopt(M_ARENA_MAX, 1);
#endif
}

#if defined(__GLIBC__) && defined(__linux__)
// The largest regular file among the arguments (the input model).
uint64_t input_size(int argc, char** argv) {
  uint64_t input = 0;
  for (int i = 2; i < argc; ++i) {
    struct stat st;
    if (stat(argv[i], &st) == 0 && S_ISREG(st.st_mode))
      input = std::max<uint64_t>(input, static_cast<uint64_t>(st.st_size));
  }
  return input;
}
#endif

// Marks a process that already runs with the tunables below.
constexpr const char* kTunedMark = "CDT3D_MALLOC_TUNED";

// glibc's malloc tuned for a big run, which needs its start-up tunables, so
// the CLI runs itself again with them (same pid, same arguments). Under a
// hypervisor a first touch of a 4 KiB page costs microseconds, and a run
// touches its whole peak at least once; glibc marks its heap and its mmap'd
// blocks MADV_HUGEPAGE only under glibc.malloc.hugetlb=1 (glibc 2.35 and
// later; older ones ignore it), so pages then fault 2 MiB at a time. Blocks
// of 256 MiB and more (the tet arrays, the phases' big tables) are mmap'd
// and given back when freed: kept in the heap (keep_freed_memory), the
// holes they leave, which the next phase's larger blocks do not fit, added
// 1.1-1.6 GB to the 5.2 GB peak of a 10M-triangle CAD model (steps_10000000
// of tests/bench/bench_scale.sh) at the same speed. One arena, as above.
// Only for inputs of 2 MiB and more: a huge page rounds the resident memory
// up by up to 2 MiB a region, which on a small model is most of its peak.
// Returns only when it does not run itself again.
void rerun_with_tuned_malloc(int argc, char** argv) {
#if defined(__GLIBC__) && defined(__linux__)
  constexpr uint64_t kMinInput = 2u << 20;
  if (std::getenv(kTunedMark) || input_size(argc, argv) < kMinInput) return;
  const char* env = std::getenv("GLIBC_TUNABLES");
  const bool had = env != nullptr;
  const std::string old = had ? env : "";
  const std::string tunables = (old.empty() ? "" : old + ":") +
                               "glibc.malloc.hugetlb=1:glibc.malloc.mmap_threshold=268435456:"
                               "glibc.malloc.arena_max=1";
  if (setenv("GLIBC_TUNABLES", tunables.c_str(), 1) == 0 && setenv(kTunedMark, "1", 1) == 0)
    execv("/proc/self/exe", argv);
  // No /proc (or no room in the environment): run as it is.
  if (had)
    setenv("GLIBC_TUNABLES", old.c_str(), 1);
  else
    unsetenv("GLIBC_TUNABLES");
  unsetenv(kTunedMark);
#else
  (void)argc, (void)argv;
#endif
}

}  // namespace

int main(int argc, char** argv) {
  rerun_with_tuned_malloc(argc, argv);
  if (!std::getenv(kTunedMark)) keep_freed_memory();
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
