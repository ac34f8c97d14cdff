// Running the native CLI from a test (CDT3D_CLI_PATH, set by tests/CMakeLists.txt)
// and reading its `--json` output, shared by the tests of the CLI.
#pragma once

#include <cdt3d/cdt3d.hpp>

#include <cstdio>
#include <regex>
#include <string>
#include <sys/wait.h>
#include <vector>

#include "stats.hpp"

namespace cli_run {

struct Run {
  int status = -1;     ///< exit code (-1: did not exit normally)
  std::string output;  ///< stdout, with stderr after it when asked for
};

#ifdef CDT3D_CLI_PATH
/// Runs `cdt3d ARGS...` (each word quoted for the shell; none may hold a
/// single quote). With `with_stderr` the output holds stderr too.
inline Run run(const std::vector<std::string>& args, bool with_stderr = false) {
  std::string cmd = std::string("'") + CDT3D_CLI_PATH + "'";
  for (const std::string& a : args) cmd += " '" + a + "'";
  cmd += with_stderr ? " 2>&1" : " 2>/dev/null";
  Run r;
  FILE* pipe = popen(cmd.c_str(), "r");
  if (pipe == nullptr) return r;
  char buf[4096];
  for (size_t n; (n = std::fread(buf, 1, sizeof buf, pipe)) > 0;) r.output.append(buf, n);
  const int w = pclose(pipe);
  r.status = WIFEXITED(w) ? WEXITSTATUS(w) : -1;
  return r;
}
#endif

/// The value of "name" in one-line JSON as written (a number, a literal or a
/// flat array of numbers); empty when the key is missing.
inline std::string json_value(const std::string& json, const std::string& name) {
  const std::regex re("\"" + name + "\":(\\[[0-9,]*\\]|[-0-9.eE+a-z]+)");
  std::smatch m;
  return std::regex_search(json, m, re) ? m[1].str() : std::string();
}

/// What `mesh --json` must print for a count or histogram field of `s`
/// (those are deterministic); empty for times and angles.
inline std::string expected_json(const cdt3d::StatisticsField& f, const cdt3d::Statistics& s) {
  if (f.count) return std::to_string(s.*(f.count));
  if (!f.histogram) return {};
  std::string out = "[";
  for (size_t c : s.*(f.histogram)) out += (out.size() > 1 ? "," : "") + std::to_string(c);
  return out + "]";
}

}  // namespace cli_run
