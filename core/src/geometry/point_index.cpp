// PointIndex: an octree whose leaves hold up to kLeafSize points and split
// when they overflow. Cells split at their centre, so the tree depends only
// on the root box and the points, not on floating-point accidents of the
// query; queries compare stored coordinates exactly with the box.
#include "point_index.hpp"

namespace cdt3d {

namespace {
// A leaf splits beyond this many points; a cell this deep never splits
// (its side is 2^-kMaxDepth of the root's: only nearly coincident points
// gather there, and a longer leaf is still correct).
constexpr size_t kLeafSize = 16;
constexpr uint32_t kMaxDepth = 40;
}  // namespace

void PointIndex::reset(const double lo[3], const double hi[3]) {
  cells_.assign(1, Cell());
  outside_.clear();
  for (int d = 0; d < 3; ++d) cells_[0].lo[d] = lo[d], cells_[0].hi[d] = hi[d];
}

int PointIndex::octant(const Cell& cell, const double* p) {
  int o = 0;
  for (int d = 0; d < 3; ++d)
    if (p[d] >= 0.5 * (cell.lo[d] + cell.hi[d])) o |= 1 << d;
  return o;
}

void PointIndex::split(uint32_t c) {
  const int32_t first = static_cast<int32_t>(cells_.size());
  cells_.resize(cells_.size() + 8);  // may move cells_[c]: index it afresh below
  Cell& cell = cells_[c];
  for (int o = 0; o < 8; ++o) {
    Cell& k = cells_[first + o];
    k.depth = cell.depth + 1;
    for (int d = 0; d < 3; ++d) {
      const double mid = 0.5 * (cell.lo[d] + cell.hi[d]);
      k.lo[d] = (o >> d & 1) ? mid : cell.lo[d];
      k.hi[d] = (o >> d & 1) ? cell.hi[d] : mid;
    }
  }
  cell.child = first;
  std::vector<Entry> entries;
  entries.swap(cell.entries);
  for (const Entry& e : entries) cells_[first + octant(cells_[c], e.p)].entries.push_back(e);
}

void PointIndex::insert(uint32_t id, const double* p) {
  const Entry e = {{p[0], p[1], p[2]}, id};
  if (cells_.empty() || !inside(p, cells_[0].lo, cells_[0].hi)) {
    outside_.push_back(e);
    return;
  }
  uint32_t c = 0;
  while (cells_[c].child >= 0) c = static_cast<uint32_t>(cells_[c].child + octant(cells_[c], p));
  cells_[c].entries.push_back(e);
  if (cells_[c].entries.size() > kLeafSize && cells_[c].depth < kMaxDepth) split(c);
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
      for (const Entry& e : cell.entries)
        if (inside(e.p, lo, hi)) out.push_back(e.id);
    } else {
      for (int o = 0; o < 8; ++o) stack_.push_back(static_cast<uint32_t>(cell.child + o));
    }
  }
}

}  // namespace cdt3d
