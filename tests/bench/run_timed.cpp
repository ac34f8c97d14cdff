// run_timed: runs one command and reports its wall time, CPU time and peak
// memory, for bench_corpus.sh.
//
//   run_timed TIMEOUT_S LOG CMD [ARGS...]
//
// Runs CMD (found on PATH) as a child with this process's stdin, stdout and
// stderr, and writes one line to LOG:
//
//   <wall ms> <user s> <system s> <peak RSS KiB>
//
// The wall time runs from just before fork() to the return of wait4(), so
// it holds the command's own start-up (exec, dynamic linking, page faults)
// and nothing of the harness around it: timing the same command through a
// bash subshell, timeout(1) and /usr/bin/time added about 17 ms per run on
// the bench machine, the same for every program, which pulled the ratios of
// small models towards 1. CPU times and peak RSS come from the child's
// rusage (wait4), as /usr/bin/time reports them.
//
// Exit status: the command's; 124 when it ran past TIMEOUT_S seconds (it is
// killed, like timeout(1)); 128 + n when signal n ended it; 127 when it could
// not be started.
#include <sys/resource.h>
#include <sys/time.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <ctime>

namespace {

volatile sig_atomic_t g_timed_out = 0;
pid_t g_child = 0;

void on_alarm(int) {
  g_timed_out = 1;
  if (g_child > 0) kill(g_child, SIGKILL);
}

double now_ms() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return 1e3 * static_cast<double>(ts.tv_sec) + 1e-6 * static_cast<double>(ts.tv_nsec);
}

double seconds(const timeval& tv) { return static_cast<double>(tv.tv_sec) + 1e-6 * static_cast<double>(tv.tv_usec); }

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: run_timed TIMEOUT_S LOG CMD [ARGS...]\n");
    return 2;
  }
  const unsigned timeout_s = static_cast<unsigned>(std::strtoul(argv[1], nullptr, 10));
  const char* log_path = argv[2];

  struct sigaction sa = {};
  sa.sa_handler = on_alarm;
  sigaction(SIGALRM, &sa, nullptr);

  const double t0 = now_ms();
  const pid_t pid = fork();
  if (pid < 0) {
    std::perror("run_timed: fork");
    return 127;
  }
  if (pid == 0) {
    execvp(argv[3], argv + 3);
    std::perror("run_timed: exec");
    _exit(127);
  }
  g_child = pid;
  if (timeout_s > 0) alarm(timeout_s);
  int status = 0;
  rusage ru = {};
  pid_t r;
  do {
    r = wait4(pid, &status, 0, &ru);
  } while (r < 0 && errno == EINTR);
  const double wall = now_ms() - t0;
  alarm(0);

  if (FILE* log = std::fopen(log_path, "w")) {
    std::fprintf(log, "%.3f %.3f %.3f %ld\n", wall, seconds(ru.ru_utime), seconds(ru.ru_stime), ru.ru_maxrss);
    std::fclose(log);
  }
  if (g_timed_out) return 124;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return 127;
}
