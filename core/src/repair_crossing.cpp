// Repair step 4: crossing and overlapping facets.
#include "repair.hpp"

namespace cdt3d {
namespace repair_steps {

Status resolve_crossings(Work& w, RepairReport& report, std::vector<Intersection>& left) {
  find_self_intersections(w.plc, left);
  (void)report;
  return Status::success();
}

}  // namespace repair_steps
}  // namespace cdt3d
