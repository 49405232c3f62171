// Cut inputs, one handling for every command (see support_cut_inputs.hpp).
#include "tools/support_cut_inputs.hpp"

#include <iostream>

namespace orthosonar::cli {
namespace {

// The CLI's one process-wide record of its inputs: a command runs once per process.
struct CutInputsState {
  bool allow = false;
  std::vector<std::string> warnings;
};
CutInputsState& cut_inputs_state() {
  static CutInputsState s;
  return s;
}

}  // namespace

void add_allow_incomplete_flag(CLI::App& sub) {
  sub.add_flag("--allow-incomplete", cut_inputs_state().allow,
               "Exit 0 when an input fixture is cut short (it is still reported and recorded in summary.json)");
}

bool allow_incomplete() { return cut_inputs_state().allow; }

bool note_input(const std::string& path, const replay::RecoveryReport& recovery) {
  const auto w = replay::cut_input_warning(path, recovery);
  if (!w) return true;
  note_cut_input_warning(*w);
  return false;
}

void note_cut_input_warning(const std::string& warning) {
  std::cerr << "warning: " << warning << "\n";
  cut_inputs_state().warnings.push_back(warning);
}

const std::vector<std::string>& cut_inputs() { return cut_inputs_state().warnings; }

int exit_code_with_inputs(const std::string& command, int code) {
  const auto& s = cut_inputs_state();
  if (code != 0 || s.warnings.empty() || s.allow) return code;
  std::cerr << "orthosonar " << command << ": exit 1: " << s.warnings.size()
            << (s.warnings.size() == 1 ? " input was" : " inputs were")
            << " cut short and the result covers only what was recovered (--allow-incomplete accepts it)\n";
  return 1;
}

}  // namespace orthosonar::cli
