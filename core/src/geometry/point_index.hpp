// A dynamic octree over points, answering "which points lie in this box".
// Segment recovery (§5) uses it to find the vertices that encroach upon a
// missing subsegment: on CAD models the diametral ball of a subsegment meets
// a hundred or more long thin tets, and walking them is costly, while the
// ball holds only a few vertices.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace cdt3d {

class PointIndex {
 public:
  /// Empties the index; its cells cover the box [lo, hi] (points outside it
  /// are still accepted, on a list every query scans).
  void reset(const double lo[3], const double hi[3]);
  /// Adds point `id` at p (coordinates copied).
  void insert(uint32_t id, const double* p);
  /// Every point whose coordinates lie in the closed box [lo, hi], in no
  /// particular order.
  void query(const double lo[3], const double hi[3], std::vector<uint32_t>& out) const;

  /// A leaf splits beyond this many points (point_index.cpp).
  static constexpr uint32_t kLeafSize = 16;

 private:
  struct Entry {
    double p[3];
    uint32_t id;
  };
  static constexpr uint32_t kNoBlock = ~0u;
  // A leaf's points live in blocks of one pool, not in a vector per leaf:
  // allocating and freeing those is slow under WebAssembly, whose malloc
  // takes a lock. One block holds a full leaf (a
  // leaf splits past kLeafSize points); only leaves that may not split any
  // more chain more blocks, in insertion order.
  static constexpr uint32_t kBlockSize = kLeafSize + 1;
  struct Block {
    Entry entries[kBlockSize];
    uint32_t count = 0;
    uint32_t next = kNoBlock;
  };
  struct Cell {
    double lo[3], hi[3];
    int32_t child = -1;  // first of 8 children in cells_, -1 for a leaf
    uint32_t depth = 0;
    uint32_t size = 0;                          // a leaf's points
    uint32_t head = kNoBlock, tail = kNoBlock;  // a leaf's blocks
  };
  void split(uint32_t c);
  void append(uint32_t c, const Entry& e);
  static int octant(const Cell& cell, const double* p);
  static bool inside(const double* p, const double lo[3], const double hi[3]) {
    return lo[0] <= p[0] && p[0] <= hi[0] && lo[1] <= p[1] && p[1] <= hi[1] && lo[2] <= p[2] &&
           p[2] <= hi[2];
  }
  std::vector<Cell> cells_;
  std::vector<Block> blocks_;
  std::vector<uint32_t> free_blocks_;
  std::vector<Entry> outside_;
  mutable std::vector<uint32_t> stack_;
};

}  // namespace cdt3d
