// orthosonar: the one CLI. Subcommands live in tools/cmd_*.cpp and register themselves.
#include <algorithm>
#include <iostream>
#include <map>
#include <memory>
#include <vector>

#include "core/inference/numeric_pins.hpp"
#include "orthosonar/version.hpp"
#include "tools/cli.hpp"
#include "tools/support_cut_inputs.hpp"

namespace orthosonar::cli {
namespace {
std::vector<Command>& registry() {
  static std::vector<Command> commands;
  return commands;
}
}  // namespace

bool register_command(Command command) {
  registry().push_back(std::move(command));
  return true;
}
}  // namespace orthosonar::cli

int main(int argc, char** argv) {
  using namespace orthosonar;
  // Before anything else runs: pin what the CPU or the core count would otherwise choose
  // (torch kernels and threads, BLAS and OpenCV threads, OpenCV dispatch); `orthosonar
  // selfcheck` prints each pin and its effective value.
  inference::apply_numeric_pins();
  CLI::App app{"orthosonar: dense 3D maps from orthogonal imaging sonars, deterministic replay and verification"};
  app.set_version_flag("--version", std::string("orthosonar ") + kVersion);
  app.require_subcommand(1);

  auto commands = cli::registry();
  std::sort(commands.begin(), commands.end(),
            [](const cli::Command& a, const cli::Command& b) { return a.name < b.name; });
  std::map<CLI::App*, std::function<int()>> actions;
  for (const auto& c : commands) {
    CLI::App* sub = app.add_subcommand(c.name, c.help);
    actions[sub] = c.setup(*sub);
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; every usage error exits 2 like any other bad input
    // (CLI11's own codes, 105 and up, are not part of our contract).
    return app.exit(e) == 0 ? 0 : 2;
  }
  for (auto& [sub, action] : actions) {
    if (sub->parsed()) {
      try {
        return cli::exit_code_with_inputs(sub->get_name(), action());
      } catch (const std::exception& e) {
        std::cerr << "orthosonar " << sub->get_name() << ": error: " << e.what() << "\n";
        return 2;
      }
    }
  }
  return 2;
}
