#pragma once
// Test support for golden/ tests that drive the orthosonar CLI as a user runs it. The
// shared Catch main (property_tests/catch_main.cpp) sets ORTHOSONAR_CLI to the built tool.
#include <sys/wait.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <string>

namespace orthosonar::testing {

struct CliRun {
  int code = -1;    // exit code, -1 when the process did not exit normally
  std::string out;  // stdout (and stderr when merged)
};

// Runs `<prefix> '<orthosonar>' <args>`. stderr is merged into `out` when merge_stderr,
// else discarded. `prefix` goes before the CLI (e.g. "env -u DISPLAY").
inline CliRun run_cli(const std::string& args, bool merge_stderr, const std::string& prefix = "") {
  const char* env = std::getenv("ORTHOSONAR_CLI");
  const std::string exe = env && *env ? env : "orthosonar";
  const std::string cmd = prefix + " '" + exe + "' " + args + (merge_stderr ? " 2>&1" : " 2>/dev/null");
  CliRun r;
  FILE* p = popen(cmd.c_str(), "r");
  REQUIRE(p != nullptr);
  char buf[4096];
  while (fgets(buf, sizeof buf, p)) r.out += buf;
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return r;
}

// The last non-empty line of a command's output (the CLI prints its verdict last).
inline std::string last_line(const std::string& s) {
  std::istringstream in(s);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  return last;
}

}  // namespace orthosonar::testing
