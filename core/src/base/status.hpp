// The one builder of the failure Status the core returns (it never throws,
// STYLE.md): the code, the message, then the input element it names, by name
// rather than by position, so no call site can put a facet where a vertex
// belongs:
//
//   return make_error(ErrorCode::Internal, "what went wrong").facet(f).vertex(v);
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <string>
#include <utility>

namespace cdt3d {

class ErrorBuilder {
 public:
  ErrorBuilder(ErrorCode code, std::string message) {
    status_.error.code = code;
    status_.error.message = std::move(message);
  }
  ErrorBuilder& facet(int64_t f) { return set(status_.error.facet, f); }
  ErrorBuilder& other_facet(int64_t f) { return set(status_.error.other_facet, f); }
  ErrorBuilder& vertex(int64_t v) { return set(status_.error.vertex, v); }
  ErrorBuilder& segment(int64_t s) { return set(status_.error.segment, s); }
  ErrorBuilder& file(const std::string& name, int64_t line = -1) {
    status_.error.file = name;
    return set(status_.error.line, line);
  }
  /// Facet f of `plc` with its source position (file, line or record).
  ErrorBuilder& facet_of(const Plc& plc, size_t f) {
    status_.error.file = plc.file;
    status_.error.facet = static_cast<int64_t>(f);
    status_.error.line = plc.facets[f].line;
    status_.error.record = plc.facets[f].record;
    return *this;
  }
  operator Status() const { return status_; }

 private:
  ErrorBuilder& set(int64_t& field, int64_t value) {
    field = value;
    return *this;
  }
  Status status_;
};

/// A failure Status with `code` and `message`; name the element with the
/// builder's setters.
inline ErrorBuilder make_error(ErrorCode code, std::string message) {
  return ErrorBuilder(code, std::move(message));
}

/// The error code of the exception being handled, for a `catch (...)`
/// block: OutOfMemory for std::bad_alloc, Internal otherwise.
///
/// Why every handler catches everything and asks here: in the WebAssembly
/// build with threads (Emscripten 3.1.6, clang 14, -fwasm-exceptions), no
/// typed catch clause ever matches, not even `catch (const std::bad_alloc&)`
/// around a plain `throw std::bad_alloc()`; only `catch (...)` does. (Checked
/// with a 20-line program: single-threaded it matches, with -pthread it does
/// not.) A typed clause there lets the exception through to JavaScript as an
/// opaque WebAssembly.Exception. So where a typed clause cannot match, the
/// allocation failure is known by note_allocation_failure(), which the
/// WebAssembly module's new-handler calls before it throws.
ErrorCode current_exception_code();
/// The what() of the exception being handled, or "" (for `catch (...)`; the
/// threaded WebAssembly build cannot see it, as above).
std::string current_exception_text();
/// Records that an allocation failed (from any thread), for
/// current_exception_code(); clear_allocation_failure() forgets it.
void note_allocation_failure();
void clear_allocation_failure();
/// The error for the exception being handled (inside `catch (...)`):
/// out-of-memory "Out of memory while <doing>." or internal "Unexpected
/// failure while <doing>: <what>", naming `file`.
Error current_exception_error(const std::string& doing, const std::string& file = "");

}  // namespace cdt3d
