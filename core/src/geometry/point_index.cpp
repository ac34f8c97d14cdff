// PointIndex: an octree whose leaves hold up to kLeafSize points and split
// when they overflow. Cells split at their centre, so the tree depends only
// on the root box and the points, not on floating-point accidents of the
// query; queries compare stored coordinates exactly with the box.
#include "point_index.hpp"

namespace cdt3d {

namespace {
// A cell this deep never splits, beyond kLeafSize points or not
// (its side is 2^-kMaxDepth of the root's: only nearly coincident points
// gather there, and a longer leaf is still correct).
constexpr uint32_t kMaxDepth = 40;
}  // namespace

void PointIndex::reset(const double lo[3], const double hi[3]) {
  cells_.assign(1, Cell());
  blocks_.clear();
  free_blocks_.clear();
  outside_.clear();
  for (int d = 0; d < 3; ++d) cells_[0].lo[d] = lo[d], cells_[0].hi[d] = hi[d];
}

int PointIndex::octant(const Cell& cell, const double* p) {
  int o = 0;
  for (int d = 0; d < 3; ++d)
    if (p[d] >= 0.5 * (cell.lo[d] + cell.hi[d])) o |= 1 << d;
  return o;
}

// Adds e at the end of leaf c's points (a new block when the last is full).
void PointIndex::append(uint32_t c, const Entry& e) {
  Cell& cell = cells_[c];
  if (cell.tail == kNoBlock || blocks_[cell.tail].count == kBlockSize) {
    uint32_t b;
    if (!free_blocks_.empty()) {
      b = free_blocks_.back();
      free_blocks_.pop_back();
      blocks_[b].count = 0, blocks_[b].next = kNoBlock;
    } else {
      b = static_cast<uint32_t>(blocks_.size());
      blocks_.emplace_back();
    }
    if (cell.tail == kNoBlock)
      cell.head = b;
    else
      blocks_[cell.tail].next = b;
    cell.tail = b;
  }
  Block& block = blocks_[cell.tail];
  block.entries[block.count++] = e;
  ++cell.size;
}

void PointIndex::split(uint32_t c) {
  const int32_t first = static_cast<int32_t>(cells_.size());
  cells_.resize(cells_.size() + 8);  // may move cells_[c]: index it afresh below
  {
    const Cell& cell = cells_[c];
    for (int o = 0; o < 8; ++o) {
      Cell& k = cells_[first + o];
      k.depth = cell.depth + 1;
      for (int d = 0; d < 3; ++d) {
        const double mid = 0.5 * (cell.lo[d] + cell.hi[d]);
        k.lo[d] = (o >> d & 1) ? mid : cell.lo[d];
        k.hi[d] = (o >> d & 1) ? cell.hi[d] : mid;
      }
    }
  }
  cells_[c].child = first;
  // The points move to the children in their order; the blocks are reused.
  uint32_t b = cells_[c].head;
  cells_[c].head = cells_[c].tail = kNoBlock;
  cells_[c].size = 0;
  while (b != kNoBlock) {
    for (uint32_t i = 0; i < blocks_[b].count; ++i) {
      const Entry e = blocks_[b].entries[i];
      append(static_cast<uint32_t>(first + octant(cells_[c], e.p)), e);
    }
    free_blocks_.push_back(b);
    b = blocks_[b].next;
  }
}

void PointIndex::insert(uint32_t id, const double* p) {
  const Entry e = {{p[0], p[1], p[2]}, id};
  if (cells_.empty() || !inside(p, cells_[0].lo, cells_[0].hi)) {
    outside_.push_back(e);
    return;
  }
  uint32_t c = 0;
  while (cells_[c].child >= 0) c = static_cast<uint32_t>(cells_[c].child + octant(cells_[c], p));
  append(c, e);
  if (cells_[c].size > kLeafSize && cells_[c].depth < kMaxDepth) split(c);
}

void PointIndex::query(const double lo[3], const double hi[3], std::vector<uint32_t>& out) const {
  out.clear();
  for (const Entry& e : outside_)
    if (inside(e.p, lo, hi)) out.push_back(e.id);
  if (cells_.empty()) return;
  stack_.assign(1, 0);
  while (!stack_.empty()) {
    const Cell& cell = cells_[stack_.back()];
    stack_.pop_back();
    bool meets = true;
    for (int d = 0; d < 3; ++d) meets = meets && cell.lo[d] <= hi[d] && lo[d] <= cell.hi[d];
    if (!meets) continue;
    if (cell.child < 0) {
      for (uint32_t b = cell.head; b != kNoBlock; b = blocks_[b].next)
        for (uint32_t i = 0; i < blocks_[b].count; ++i)
          if (inside(blocks_[b].entries[i].p, lo, hi)) out.push_back(blocks_[b].entries[i].id);
    } else {
      for (int o = 0; o < 8; ++o) stack_.push_back(static_cast<uint32_t>(cell.child + o));
    }
  }
}

}  // namespace cdt3d
