// Error codes, their stable names and one-line descriptions.
#include <cdt3d/cdt3d.hpp>

namespace cdt3d {

const char* error_code_name(ErrorCode code) {
  switch (code) {
    case ErrorCode::Ok: return "ok";
    case ErrorCode::IoError: return "io";
    case ErrorCode::UnknownFormat: return "unknown-format";
    case ErrorCode::Empty: return "empty";
    case ErrorCode::Truncated: return "truncated";
    case ErrorCode::Parse: return "parse";
    case ErrorCode::NonFinite: return "nan";
    case ErrorCode::CoordinateRange: return "coordinate-range";
    case ErrorCode::IndexOutOfRange: return "index";
    case ErrorCode::DegenerateFacet: return "degenerate";
    case ErrorCode::NonPlanarFacet: return "nonplanar";
    case ErrorCode::DuplicateFacet: return "duplicate";
    case ErrorCode::TooLarge: return "too-large";
    case ErrorCode::Coplanar: return "coplanar";
    case ErrorCode::Collinear: return "collinear";
    case ErrorCode::TooFewPoints: return "too-few-points";
    case ErrorCode::InvalidArgument: return "invalid-argument";
    case ErrorCode::Cancelled: return "cancelled";
    case ErrorCode::OutOfMemory: return "out-of-memory";
    case ErrorCode::Internal: return "internal";
    case ErrorCode::LimitReached: return "limit";
    case ErrorCode::InvalidPlc: return "invalid-plc";
    case ErrorCode::SelfIntersection: return "self-intersection";
    case ErrorCode::OpenBoundary: return "open-boundary";
  }
  return "internal";
}

std::string Error::to_string() const {
  std::string s;
  if (!file.empty()) {
    s += file;
    if (line >= 0) s += ":" + std::to_string(line);
    s += ": ";
  }
  s += message;
  std::string where;
  auto add = [&where](const char* what, int64_t v) {
    if (v < 0) return;
    where += where.empty() ? "" : ", ";
    where += what;
    where += " ";
    where += std::to_string(v);
  };
  if (file.empty()) add("line", line);
  add("record", record);
  add("facet", facet);
  add("other facet", other_facet);
  add("segment", segment);
  add("vertex", vertex);
  if (!where.empty()) s += " (" + where + ")";
  s += " [";
  s += error_code_name(code);
  s += "]";
  return s;
}

}  // namespace cdt3d
