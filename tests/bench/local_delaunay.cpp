// Counts the interior faces of a TetGen .node/.ele/.face mesh that are not
// constrained and not locally Delaunay, with cdt3d's exact predicates. By the
// constrained Delaunay lemma a tetrahedralization of a PLC is its CDT exactly
// when every such face is locally Delaunay (the apex of one tet not strictly
// inside the circumsphere of the other); a positive count means the mesh is
// not a CDT, so its Steiner point count is not comparable with a CDT's.
// Used by tests/bench/bench_corpus.sh on TetGen's output (`tetgen -pMQ`),
// whose .face lists the faces lying on the input facets; and on cdt3d's own
// output for the same check.
//
// usage: local_delaunay MESH.node MESH.ele MESH.face
// Build (bench_corpus.sh does this; needs the library for the predicates):
//   c++ -O2 -std=c++17 -Icore/include -Icore/src/geometry -Icore/src/mesh tests/bench/local_delaunay.cpp
//       .build/bench/core/libcdt3d.a -o .build/bench/bench/local_delaunay   (one line)
//
// Output, one line: "<violations> <unconstrained interior faces> <constrained faces>".
// Co-spherical ties (insphere = 0) count as locally Delaunay.
// Exit codes: 0 counted, 1 read error (message on stderr), 2 usage.
#include <algorithm>
#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "tetgen_lines.hpp"

#include "predicates.hpp"

namespace {

using bench::read_lines;
int fail(const char* path, const std::string& what) { return bench::fail("local_delaunay", path, what); }

// A face as its sorted vertex triple packed in 64 bits per pair of ids.
struct FaceKey {
  std::array<long long, 3> v;
  bool operator==(const FaceKey& o) const { return v == o.v; }
};
struct FaceHash {
  size_t operator()(const FaceKey& k) const {
    return std::hash<long long>()(k.v[0] * 1000003LL ^ k.v[1] * 998244353LL ^ k.v[2]);
  }
};
FaceKey key_of(long long a, long long b, long long c) {
  std::array<long long, 3> v = {a, b, c};
  std::sort(v.begin(), v.end());
  return {v};
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: local_delaunay MESH.node MESH.ele MESH.face\n");
    return 2;
  }
  std::vector<double> xyz;
  long long first = 0;
  if (const std::string bad = bench::read_nodes(argv[1], xyz, first); !bad.empty()) return fail(argv[1], bad);
  const long long n = static_cast<long long>(xyz.size() / 3);
  std::vector<std::string> lines;

  std::vector<std::array<long long, 4>> tets;
  if (const std::string bad = bench::read_tets(argv[2], n, first, tets); !bad.empty()) return fail(argv[2], bad);
  const long long m = static_cast<long long>(tets.size());

  lines.clear();
  if (!read_lines(argv[3], lines) || lines.empty()) return fail(argv[3], "cannot read");
  long long nf = -1;
  std::istringstream(lines[0]) >> nf;
  std::unordered_map<FaceKey, int, FaceHash> constrained;
  for (long long f = 0; f < nf && 1 + f < static_cast<long long>(lines.size()); ++f) {
    std::istringstream s(lines[1 + f]);
    long long id, a, b, c;
    if (!(s >> id >> a >> b >> c)) return fail(argv[3], "bad face line");
    constrained[key_of(a - first, b - first, c - first)] = 1;
  }

  // Face -> its first tet; the second tet's apex is tested against the
  // first tet's circumsphere.
  auto pt = [&](long long i) { return &xyz[3 * static_cast<size_t>(i)]; };
  std::unordered_map<FaceKey, long long, FaceHash> open;
  open.reserve(static_cast<size_t>(2 * m));
  size_t violations = 0, interior = 0;
  for (long long t = 0; t < m; ++t) {
    const auto& v = tets[t];
    for (int i = 0; i < 4; ++i) {
      const FaceKey k = key_of(v[(i + 1) % 4], v[(i + 2) % 4], v[(i + 3) % 4]);
      auto it = open.find(k);
      if (it == open.end()) {
        open.emplace(k, t);
        continue;
      }
      const long long u = it->second;
      open.erase(it);
      if (constrained.count(k)) continue;
      ++interior;
      const auto& w = tets[u];
      const int o = cdt3d::pred::orient3d(pt(w[0]), pt(w[1]), pt(w[2]), pt(w[3]));
      const int s = cdt3d::pred::insphere(pt(w[0]), pt(w[1]), pt(w[2]), pt(w[3]), pt(v[i]));
      if (o * s > 0) ++violations;
    }
  }
  std::printf("%zu %zu %zu\n", violations, interior, constrained.size());
  return 0;
}
