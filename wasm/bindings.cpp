// Embind bindings of the cdt3d core: conversion only, no geometry.
//
// Every raw function returns a plain JS object and never throws or aborts on
// bad input: {ok: true, ...fields} on success, {ok: false, error: {...}} on
// failure, the same shape as the native CLI's --json output. api.js turns the
// failures into Cdt3dError. The raw names start with '_' and are not part of
// the public API.
#include <emscripten/bind.h>
#include <emscripten/heap.h>
#include <emscripten/val.h>
#include <malloc.h>

#include <cdt3d/cdt3d.hpp>

#include <cstdint>
#include <cstdlib>
#include <memory>
#include <set>
#include <string>

#ifndef CDT3D_VERSION
#error "CDT3D_VERSION must be defined by the build (wasm/CMakeLists.txt)"
#endif

namespace {

using emscripten::val;

val number(int64_t v) { return val(static_cast<double>(v)); }
val number(size_t v) { return val(static_cast<double>(v)); }

val vec3(const cdt3d::Vec3& p) {
  val a = val::array();
  a.call<void>("push", p.x, p.y, p.z);
  return a;
}

// {ok: false, error: {code, message, file, line, record, facet, vertex, otherFacet}}
val failure(const cdt3d::Error& e) {
  val err = val::object();
  err.set("code", val(std::string(cdt3d::error_code_name(e.code))));
  err.set("message", val(e.message));
  err.set("file", val(e.file));
  err.set("line", number(e.line));
  err.set("record", number(e.record));
  err.set("facet", number(e.facet));
  err.set("vertex", number(e.vertex));
  err.set("otherFacet", number(e.other_facet));
  val out = val::object();
  out.set("ok", val(false));
  out.set("error", err);
  return out;
}

val failure(cdt3d::ErrorCode code, std::string message, std::string file) {
  cdt3d::Error e;
  e.code = code;
  e.message = std::move(message);
  e.file = std::move(file);
  return failure(e);
}

// Summary of a PLC with the field names of `cdt3d info --json`.
val plc_summary(const cdt3d::Plc& plc) {
  const cdt3d::PlcInfo info = cdt3d::plc_info(plc);
  val out = val::object();
  out.set("ok", val(true));
  out.set("file", val(plc.file));
  out.set("fileVertices", number(info.file_vertices));
  out.set("points", number(info.points));
  out.set("welded", number(plc.welded_vertices));
  out.set("unreferenced", number(info.unreferenced));
  out.set("facets", number(info.facets));
  out.set("triangles", number(info.triangles));
  out.set("loops", number(info.loops));
  out.set("segments", number(info.segments));
  out.set("holes", number(info.holes));
  out.set("regions", number(info.regions));
  out.set("bboxMin", vec3(info.bbox_min));
  out.set("bboxMax", vec3(info.bbox_max));
  return out;
}

struct FreeDeleter {
  void operator()(uint8_t* p) const { std::free(p); }
};

// Copies a JS Uint8Array into the WASM heap. malloc (not a vector) so that an
// input too large for the heap is an "out-of-memory" status, not an abort.
// Returns false when the allocation fails.
bool copy_bytes(const val& bytes, size_t size, std::unique_ptr<uint8_t, FreeDeleter>& out) {
  out.reset(static_cast<uint8_t*>(std::malloc(size > 0 ? size : 1)));
  if (!out) return false;
  // The view is created after the allocation, so memory growth cannot detach it.
  if (size > 0) val(emscripten::typed_memory_view(size, out.get())).call<void>("set", bytes);
  return true;
}

// readPlc(bytes: Uint8Array, fileName: string) -> summary or error object.
val read_plc_js(val bytes, val file_name) {
  if (!file_name.isString()) {
    return failure(cdt3d::ErrorCode::InvalidArgument,
                   "The file name must be a string (it picks the format by extension).", "");
  }
  std::string name = file_name.as<std::string>();
  if (name.empty()) {
    return failure(cdt3d::ErrorCode::InvalidArgument,
                   "The file name is empty (it picks the format by extension).", "");
  }
  if (!bytes.instanceof(val::global("Uint8Array"))) {
    return failure(cdt3d::ErrorCode::InvalidArgument,
                   "The file contents must be a Uint8Array, an ArrayBuffer or a Buffer.", name);
  }
  const double length = bytes["length"].as<double>();
  if (!(length >= 0) || length > static_cast<double>(SIZE_MAX)) {
    return failure(cdt3d::ErrorCode::TooLarge, "The file is too large for a 32-bit heap.", name);
  }
  const size_t size = static_cast<size_t>(length);
  std::unique_ptr<uint8_t, FreeDeleter> data;
  if (!copy_bytes(bytes, size, data)) {
    return failure(cdt3d::ErrorCode::OutOfMemory,
                   "Not enough WebAssembly memory to hold the file (" + std::to_string(size) +
                       " bytes).",
                   name);
  }
  cdt3d::Plc plc;
  const cdt3d::Status status = cdt3d::read_plc(data.get(), size, name, plc);
  data.reset();
  if (!status.ok()) return failure(status.error);
  return plc_summary(plc);
}

std::string version() { return CDT3D_VERSION; }

// Every stable error code name except "ok", in enum order. error_code_name()
// maps unknown values to "internal", so scanning past the last enumerator is
// harmless.
val error_codes() {
  val out = val::array();
  std::set<std::string> seen{"ok"};
  for (int i = 0; i < 256; ++i) {
    std::string name = cdt3d::error_code_name(static_cast<cdt3d::ErrorCode>(i));
    if (seen.insert(name).second) out.call<void>("push", name);
  }
  return out;
}

// {heapBytes: size of the WASM memory, allocatedBytes: bytes in use by malloc}.
val memory_usage() {
  const struct mallinfo mi = mallinfo();
  val out = val::object();
  out.set("heapBytes", val(static_cast<double>(emscripten_get_heap_size())));
  out.set("allocatedBytes", val(static_cast<double>(mi.uordblks)));
  return out;
}

}  // namespace

EMSCRIPTEN_BINDINGS(cdt3d) {
  emscripten::function("_readPlc", &read_plc_js);
  emscripten::function("_version", &version);
  emscripten::function("_errorCodes", &error_codes);
  emscripten::function("_memoryUsage", &memory_usage);
}
