// cdt3d command-line tool: dispatches to one function per subcommand.
#include <algorithm>
#include <cstdio>
#include <cstring>
#if defined(__GLIBC__)
#include <malloc.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <vector>
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
// memory in the process avoids that; the peak (what the process touches at
// once) does not grow. One arena for the two threads of a run (the
// self-intersection test runs beside steps 1-2): a second arena's pages are
// fresh, and what the test frees there would never serve the later phases;
// the test makes few allocations, so the shared lock costs next to
// nothing.
void keep_freed_memory() {
#if defined(__GLIBC__)
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  mallopt(M_TRIM_THRESHOLD, -1);  // never: the CLI exits when its run ends
  mallopt(M_ARENA_MAX, 1);
#endif
}

// Transparent huge pages for the heap of a big run. Under a hypervisor a
// first touch of a 4 KiB page costs microseconds, and a run touches its
// whole peak at least once. glibc asks for huge pages only under its
// start-up tunable (glibc.malloc.hugetlb=1), so the CLI does it itself: it
// grows the heap by a reserve once (malloc and free; with the thresholds
// above the top is never given back, and blocks below 1 GiB are not served by mmap), and marks the
// reserve MADV_HUGEPAGE, so the later allocations there fault 2 MiB at a
// time. Untouched, the reserve costs address space only. Only for inputs
// of 2 MiB and more: a huge page rounds the resident memory up by up to
// 2 MiB a region, which on a small model is most of its peak.
void huge_pages_for_big_inputs(int argc, char** argv) {
#if defined(__GLIBC__) && defined(MADV_HUGEPAGE)
  constexpr uint64_t kMinInput = 2u << 20, kHuge = 2u << 20;
  uint64_t input = 0;
  for (int i = 2; i < argc; ++i) {
    struct stat st;
    if (stat(argv[i], &st) == 0 && S_ISREG(st.st_mode))
      input = std::max<uint64_t>(input, static_cast<uint64_t>(st.st_size));
  }
  if (input < kMinInput) return;
  // Sized from the input file, with room above the peak memory a model of
  // that size reaches (about 14x an OFF file's size on the 10M-triangle
  // torus), at most half the machine's memory: only the pages touched
  // count, but the heap must be able to grow that far at once.
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGESIZE);
  const uint64_t half_ram = pages > 0 && page_size > 0 ? uint64_t(pages) * uint64_t(page_size) / 2 : 960u << 20;
  const uint64_t reserve = std::min<uint64_t>(24 * input, half_ram);
  // In blocks below the mmap threshold, so that each comes from the heap
  // top; freed in reverse order they merge into one free top chunk.
  constexpr uint64_t kBlock = 768u << 20;
  std::vector<void*> blocks;
  for (uint64_t grown = 0; grown < reserve; grown += kBlock) {
    void* block = std::malloc(std::min(kBlock, reserve - grown));
    if (!block) break;
    const uintptr_t lo = reinterpret_cast<uintptr_t>(block);
    const uintptr_t a = (lo + kHuge - 1) & ~(kHuge - 1);
    const uintptr_t b = (lo + std::min(kBlock, reserve - grown)) & ~(kHuge - 1);
    if (b > a) madvise(reinterpret_cast<void*>(a), b - a, MADV_HUGEPAGE);
    blocks.push_back(block);
  }
  for (auto it = blocks.rbegin(); it != blocks.rend(); ++it) std::free(*it);
#else
  (void)argc, (void)argv;
#endif
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory();
  huge_pages_for_big_inputs(argc, argv);
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
