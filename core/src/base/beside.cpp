// Where the second thread starts (beside.hpp).
#include "beside.hpp"

#ifdef CDT3D_HAS_THREADS

#include <atomic>
#include <memory>
#include <system_error>

#ifdef CDT3D_PLACES_THREADS
#include <sched.h>
#endif

namespace cdt3d {

#ifdef CDT3D_PLACES_THREADS

// Left to the scheduler, a thread created by a busy thread is often queued
// on its creator's core, and the idle core takes it over only at its next
// load balancing, up to a scheduler tick later: milliseconds, as long as
// the halves of work run_beside is given on a small model. Started with an
// affinity that leaves out the creator's core, the thread runs on the idle
// core at once; it then widens its affinity back to the creator's, so that
// the scheduler may move it as before.
namespace {

struct Start {
  std::function<void()> body;
  cpu_set_t allowed;
  bool widen = false;
};

void* run_start(void* arg) {
  std::unique_ptr<Start> start(static_cast<Start*>(arg));
  if (start->widen) sched_setaffinity(0, sizeof(start->allowed), &start->allowed);
  start->body();
  return nullptr;
}

}  // namespace

bool BesideThread::start(std::function<void()> body) {
  auto start = std::make_unique<Start>();
  start->body = std::move(body);
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  CPU_ZERO(&start->allowed);
  const int here = sched_getcpu();
  if (here >= 0 && sched_getaffinity(0, sizeof(start->allowed), &start->allowed) == 0 &&
      CPU_ISSET(here, &start->allowed) && CPU_COUNT(&start->allowed) > 1) {
    cpu_set_t others = start->allowed;
    CPU_CLR(here, &others);
    start->widen = pthread_attr_setaffinity_np(&attr, sizeof(others), &others) == 0;
  }
  int rc = pthread_create(&id_, &attr, run_start, start.get());
  pthread_attr_destroy(&attr);
  if (rc != 0 && start->widen) {  // the placement refused (a cpuset, say): anywhere then
    start->widen = false;
    rc = pthread_create(&id_, nullptr, run_start, start.get());
  }
  if (rc != 0) return false;
  start.release();  // run_start owns it now
  running_ = true;
  return true;
}

void BesideThread::join() {
  if (!running_) return;
  pthread_join(id_, nullptr);
  running_ = false;
}

#elif defined(__EMSCRIPTEN__)

// The Node module has one pool worker (wasm/CMakeLists.txt). Asked for a
// thread while that worker runs one, Emscripten 3.1.6's std::thread throws
// (something no catch of std::system_error or std::exception matched), so a
// second live thread is refused here before it is asked for. (The module
// is called from one JS thread.)
namespace {
std::atomic<int> live_threads{0};
}  // namespace

bool BesideThread::start(std::function<void()> body) {
  if (live_threads.fetch_add(1) > 0) {
    live_threads.fetch_sub(1);
    return false;
  }
  try {
    thread_ = std::thread(std::move(body));
  } catch (...) {
    live_threads.fetch_sub(1);
    return false;
  }
  return true;
}

void BesideThread::join() {
  if (!thread_.joinable()) return;
  thread_.join();
  live_threads.fetch_sub(1);
}

#else

bool BesideThread::start(std::function<void()> body) {
  try {
    thread_ = std::thread(std::move(body));
  } catch (...) {  // std::system_error: no thread to be had
    return false;
  }
  return true;
}

void BesideThread::join() {
  if (thread_.joinable()) thread_.join();
}

#endif

}  // namespace cdt3d

#endif
