// libFuzzer target for one PLC reader: the bytes are a whole file whose name
// (and so whose format) is fixed at compile time by CDT3D_FUZZ_FILE_NAME, e.g.
// "fuzz.stl". read_plc must return a Status for any input, never crash, hang,
// leak or trip a sanitizer; a success must hand back a PLC that passes
// check_plc again, and a failure must carry an error code and a message.
#include <cdt3d/cdt3d.hpp>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#ifndef CDT3D_FUZZ_FILE_NAME
#error "define CDT3D_FUZZ_FILE_NAME (e.g. \"fuzz.off\")"
#endif

namespace {

[[noreturn]] void fuzz_fail(const char* what, const cdt3d::Status& s) {
  std::fprintf(stderr, "fuzz_read (%s): %s: %s\n", CDT3D_FUZZ_FILE_NAME, what,
               s.error.to_string().c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  cdt3d::Plc plc;
  const cdt3d::Status s = cdt3d::read_plc(data, size, CDT3D_FUZZ_FILE_NAME, plc);
  if (!s.ok()) {
    if (s.error.message.empty()) fuzz_fail("error without a message", s);
    if (!plc.points.empty() || !plc.facets.empty()) fuzz_fail("partial PLC after an error", s);
    (void)s.error.to_string();
    return 0;
  }
  // A PLC that read_plc accepted is well formed: check it again, and walk it
  // the way `cdt3d info` does.
  const cdt3d::Status again = cdt3d::check_plc(plc);
  if (!again.ok()) fuzz_fail("check_plc rejects a PLC that read_plc accepted", again);
  const cdt3d::PlcInfo info = cdt3d::plc_info(plc);
  if (info.points != plc.points.size() || info.facets != plc.facets.size()) {
    fuzz_fail("plc_info disagrees with the PLC", s);
  }
  (void)cdt3d::plc_segments(plc);
  return 0;
}
