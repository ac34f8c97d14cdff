// Two independent halves of one job, the second on a thread of its own where
// the platform has threads (native builds, and the WebAssembly module the
// npm package loads under Node, built with Emscripten's pthreads; the
// browser module is single-threaded) and the build has exceptions (to carry
// an allocation failure across). The pipeline's other work on the second
// core (the self-intersection test beside steps 1-2) is done by then.
#pragma once

#include <exception>
#include <utility>

#if (!defined(__EMSCRIPTEN__) || defined(__EMSCRIPTEN_PTHREADS__)) && \
    (defined(__cpp_exceptions) || defined(__EXCEPTIONS))
#include <system_error>
#include <thread>
#define CDT3D_HAS_THREADS 1
#endif

namespace cdt3d {

/// Whether run_beside can run its halves on two threads here (it may still
/// find no thread to start).
inline bool threads_available() {
#ifdef CDT3D_HAS_THREADS
  return std::thread::hardware_concurrency() > 1;
#else
  return false;
#endif
}

/// Runs first() here and second() beside it when `beside` (and threads
/// exist, and one can be started), else both here, first() first. Returns
/// after both; an exception of second() is rethrown here. The two must not
/// share mutable state; each writes its own result, which the caller merges
/// in a fixed order, so the outcome never depends on the threads.
template <class First, class Second>
void run_beside(bool beside, First&& first, Second&& second) {
#ifdef CDT3D_HAS_THREADS
  if (beside && threads_available()) {
    std::exception_ptr failure;
    std::thread worker;
    try {
      worker = std::thread([&] {
        try {
          second();
        } catch (...) {
          failure = std::current_exception();
        }
      });
    } catch (const std::system_error&) {
      first();  // no thread to be had
      second();
      return;
    }
    try {
      first();
    } catch (...) {
      worker.join();
      throw;
    }
    worker.join();
    if (failure) std::rethrow_exception(failure);
    return;
  }
#else
  (void)beside;
#endif
  first();
  second();
}

}  // namespace cdt3d
