#pragma once
// Child processes of the batch engines (tasks, golden checks, Slurm's clients): spawn with
// stdout and stderr appended to a log file or captured, and wait. The batch library is the
// only library that starts processes; the core and the run library start none.
#include <sys/types.h>

#include <string>
#include <vector>

#include "core/result.hpp"

namespace orthosonar::batch {

// The running executable's absolute path (/proc/self/exe).
std::string self_executable();

// Starts argv[0] (searched on PATH when it has no '/') with stdout and stderr appended to
// `log_path` (created when missing). Errors name the program and the log.
Result<pid_t> spawn_logged(const std::vector<std::string>& argv, const std::string& log_path);

// Waits for `pid`; its exit code, or 128 + signal when a signal ended it.
int wait_exit_code(pid_t pid);
// Like wait_exit_code for any child: returns {pid, code}, pid -1 when there is none.
std::pair<pid_t, int> wait_any();

struct Captured {
  int exit_code = 0;
  std::string out;  // stdout and stderr together
};
// Runs argv to completion and captures its output. An error only when it cannot start.
Result<Captured> run_captured(const std::vector<std::string>& argv);

// Shell-quotes one word for a generated script ('...' with embedded quotes escaped).
std::string shell_quote(const std::string& word);

}  // namespace orthosonar::batch
