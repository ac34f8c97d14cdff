// The first part of check_plc (cdt3d.hpp), for callers that start on the
// points while the rest of the checks runs elsewhere.
#pragma once

#include <cdt3d/cdt3d.hpp>

namespace cdt3d {

/// check_plc's checks of the points alone (finite coordinates within
/// kMaxCoordinate, a count that fits the 32-bit ids), in check_plc's order:
/// when this passes, check_plc reports what it would have reported anyway.
/// What step 1 needs of a PLC.
Status check_plc_points(const Plc& plc);

}  // namespace cdt3d
