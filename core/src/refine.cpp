// Quality refinement (refine.hpp). Work in progress: options are checked and
// the phase is wired; the refinement itself lands next.
#include "refine.hpp"

#include <cmath>
#include <string>

#include "status.hpp"

namespace cdt3d {

Status check_quality_options(const QualityOptions& q) {
  if (!(q.radius_edge >= 1.0) || !std::isfinite(q.radius_edge))
    return make_error(ErrorCode::InvalidArgument,
                      "The radius-edge bound of quality refinement must be a number >= 1 (got " +
                          std::to_string(q.radius_edge) + ").");
  if (!(q.max_volume == -1 || (q.max_volume > 0 && std::isfinite(q.max_volume))))
    return make_error(ErrorCode::InvalidArgument,
                      "The maximum tet volume must be positive, or -1 for none (got " +
                          std::to_string(q.max_volume) + ").");
  if (!(q.min_dihedral >= 0 && q.min_dihedral <= 70))
    return make_error(ErrorCode::InvalidArgument,
                      "The dihedral angle target must be between 0 and 70 degrees (got " +
                          std::to_string(q.min_dihedral) + ").");
  return Status::success();
}

Status refine_quality(const Plc&, const QualityOptions& q, const volatile bool*,
                      const RefineProgress&, Result&) {
  return check_quality_options(q);
}

}  // namespace cdt3d
