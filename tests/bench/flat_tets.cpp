// Counts the numerically flat tetrahedra of a TetGen .node/.ele mesh, with
// cdt3d's definition (Statistics::flat_tets, cdt3d.hpp): 6V computed in
// doubles from the stored coordinates is not above kFlatTetRatio * (longest
// edge)^3. Used by tests/bench/bench_corpus.sh on TetGen's own output
// (`tetgen -pMQ M.poly` writes M.1.node / M.1.ele), so that both programs'
// flat tets are counted the same way.
//
// usage: flat_tets MESH.node MESH.ele
// Build (bench_corpus.sh does this; only the header is used):
//   c++ -O2 -std=c++17 -Icore/include tests/bench/flat_tets.cpp -o .build/bench/bench/flat_tets
//
// Orientation: cdt3d's tets are positively oriented ((a-d).((b-d)x(c-d)) > 0),
// TetGen's the other way round. The mesh's orientation is taken as the sign
// of the majority of its tets; a tet counts as flat when its 6V in that
// orientation is not above the threshold, so zero and inverted tets count as
// flat too.
//
// Output, one line: "<flat> <tets> <inverted>", where inverted counts the
// flat tets whose 6V has the minority sign or is zero.
// Numbering: node indices start at the first index of the .node file (0 or
// 1, as TetGen allows); extra node columns (attributes, markers) and extra
// tet columns (second-order nodes, attributes) are ignored; '#' starts a
// comment.
// Exit codes: 0 counted, 1 read error (message on stderr), 2 usage.
#include <cdt3d/cdt3d.hpp>

#include <array>
#include <cstdio>
#include <string>
#include <vector>

#include "tetgen_lines.hpp"

namespace {

int fail(const char* path, const std::string& what) { return bench::fail("flat_tets", path, what); }

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: flat_tets MESH.node MESH.ele\n");
    return 2;
  }
  const char* node_path = argv[1];
  const char* ele_path = argv[2];

  std::vector<double> xyz;
  long long first = 0;
  if (const std::string bad = bench::read_nodes(node_path, xyz, first); !bad.empty()) return fail(node_path, bad);
  std::vector<std::array<long long, 4>> tets;
  if (const std::string bad = bench::read_tets(ele_path, static_cast<long long>(xyz.size() / 3), first, tets);
      !bad.empty())
    return fail(ele_path, bad);
  const bench::FlatCount c = bench::count_flat(xyz, tets, cdt3d::kFlatTetRatio);
  std::printf("%zu %zu %zu\n", c.flat, tets.size(), c.inverted);
  return 0;
}
