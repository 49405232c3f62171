#pragma once
// The orthosonar command line: one executable, subcommands registered by the file that
// implements them (tools/cmd_<name>.cpp), so adding a subcommand touches one file.
#include <CLI/CLI.hpp>
#include <functional>
#include <string>

namespace orthosonar::cli {

// Sets up options on `sub` and returns the action to run when the subcommand is chosen.
// The action returns the process exit code (0 ok, 1 a negative verdict such as a digest
// mismatch, 2 bad input or a failure).
using Setup = std::function<std::function<int()>(CLI::App& sub)>;

struct Command {
  std::string name;
  std::string help;
  Setup setup;
};

bool register_command(Command command);

}  // namespace orthosonar::cli
