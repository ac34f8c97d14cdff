// Error codes, their stable names and one-line descriptions.
#include "status.hpp"

#include <atomic>
#include <exception>
#include <new>

namespace cdt3d {

namespace {
std::atomic<bool> allocation_failed{false};
}  // namespace

void note_allocation_failure() { allocation_failed.store(true); }
void clear_allocation_failure() { allocation_failed.store(false); }

ErrorCode current_exception_code() {
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
  try {
    throw;
  } catch (const std::bad_alloc&) {
    return ErrorCode::OutOfMemory;
  } catch (...) {
  }
#endif
  return allocation_failed.load() ? ErrorCode::OutOfMemory : ErrorCode::Internal;
}

Error current_exception_error(const std::string& doing, const std::string& file) {
  if (current_exception_code() == ErrorCode::OutOfMemory)
    return {ErrorCode::OutOfMemory, "Out of memory while " + doing + ".", file};
  const std::string what = current_exception_text();
  return {ErrorCode::Internal, "Unexpected failure while " + doing + (what.empty() ? "." : ": " + what), file};
}

std::string current_exception_text() {
#if defined(__cpp_exceptions) || defined(__EXCEPTIONS)
  try {
    throw;
  } catch (const std::exception& e) {
    return e.what();
  } catch (...) {
  }
#endif
  return "";
}

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
