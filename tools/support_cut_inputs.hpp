#pragma once
// Cut inputs (issue 40), handled in one place for every command that reads a fixture:
// the command registers `--allow-incomplete` with add_allow_incomplete_flag() and reports
// each input it opens with note_input(); main() turns a command's exit 0 into 1 when an
// input was cut and the flag was not given (README, "Exit codes": 1 "truncated fixture
// recovered"). Whether a fixture is whole is replay::cut_input_warning's decision, the one
// `inspect` prints.
#include <string>
#include <vector>

#include "replay/fixture/fixture.hpp"
#include "tools/cli.hpp"

namespace orthosonar::cli {

// Adds `--allow-incomplete` (exit 0 on a cut input; it is still reported and recorded).
void add_allow_incomplete_flag(CLI::App& sub);
bool allow_incomplete();

// Prints the warning for a cut input (naming the file, the byte offset and what was
// recovered) and remembers it; returns true when the input is whole.
bool note_input(const std::string& path, const replay::RecoveryReport& recovery);
// A cut input described by its warning text (a child process's or a task's), remembered.
void note_cut_input_warning(const std::string& warning);
// The warnings of the cut inputs noted so far.
const std::vector<std::string>& cut_inputs();

// The process exit code for a command that returned `code`: 1 instead of 0 when an input
// was cut and --allow-incomplete was not given (saying so on stderr).
int exit_code_with_inputs(const std::string& command, int code);

}  // namespace orthosonar::cli
