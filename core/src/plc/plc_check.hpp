// Parts of check_plc (cdt3d.hpp): the points alone, for callers that start
// on them while the rest of the checks runs elsewhere, and the checks a
// reader's output still needs.
#pragma once

#include <cdt3d/cdt3d.hpp>

namespace cdt3d {

/// check_plc's checks of the points alone (finite coordinates within
/// kMaxCoordinate, a count that fits the 32-bit ids), in check_plc's order:
/// when this passes, check_plc reports what it would have reported anyway.
/// What step 1 needs of a PLC.
Status check_plc_points(const Plc& plc);

/// check_plc for a PLC as the readers return it: their points are welded
/// exactly (io::PlcBuilder), so no two are equal and that check is skipped.
Status check_welded_plc(const Plc& plc);

}  // namespace cdt3d
