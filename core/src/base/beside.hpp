// Two independent halves of one job, the second on a thread of its own where
// the platform has threads (native builds, and the WebAssembly module the
// npm package loads under Node, built with Emscripten's pthreads; the
// browser module is single-threaded) and the build has exceptions (to carry
// an allocation failure across). The pipeline's other work on the second
// core (the self-intersection test beside steps 1-2) is done by then.
#pragma once

#include <atomic>
#include <exception>
#include <utility>

#if (!defined(__EMSCRIPTEN__) || defined(__EMSCRIPTEN_PTHREADS__)) && \
    (defined(__cpp_exceptions) || defined(__EXCEPTIONS))
#include <functional>
#include <thread>
#define CDT3D_HAS_THREADS 1
#if defined(__linux__) && defined(__GLIBC__) && !defined(__EMSCRIPTEN__)
#include <pthread.h>
#define CDT3D_PLACES_THREADS 1
#endif
#endif

namespace cdt3d {

/// Whether run_beside can run its halves on two threads here (it may still
/// find no thread to start).
inline bool threads_available() {
#ifdef CDT3D_HAS_THREADS
  // Asked once: glibc reads /sys/devices/system/cpu/online on every call.
  static const bool two_or_more = std::thread::hardware_concurrency() > 1;
  return two_or_more;
#else
  return false;
#endif
}

#ifdef CDT3D_HAS_THREADS
/// The second thread of run_beside and of the pipeline's self-intersection
/// test. On Linux it starts on a core other than its creator's, then may run
/// on any (beside.cpp says why); elsewhere it is a plain std::thread.
class BesideThread {
 public:
  BesideThread() = default;
  BesideThread(const BesideThread&) = delete;
  BesideThread& operator=(const BesideThread&) = delete;
  ~BesideThread() { join(); }
  /// Runs body() on a new thread; false (body() not run) when none can be
  /// started. body() must not throw (the callers catch inside it). No
  /// exception reports a refusal: in the WebAssembly build a failed
  /// std::thread throws something that no catch of std::system_error (nor
  /// of std::exception) matched.
  bool start(std::function<void()> body);
  void join();

 private:
#ifdef CDT3D_PLACES_THREADS
  pthread_t id_{};
  bool running_ = false;
#else
  std::thread thread_;
#endif
};
#endif

/// Returns once `flag` is true: another thread sets it (with release order)
/// while this one yields the core. Without threads the flag is already set.
inline void wait_until(const std::atomic<bool>& flag) {
  while (!flag.load(std::memory_order_acquire)) {
#ifdef CDT3D_HAS_THREADS
    std::this_thread::yield();
#endif
  }
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
    BesideThread worker;
    const bool started = worker.start([&] {
      try {
        second();
      } catch (...) {
        failure = std::current_exception();
      }
    });
    if (!started) {
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
