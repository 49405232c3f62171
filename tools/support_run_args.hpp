#pragma once
// The command-line side of the run API (replay/run/run.hpp): the options shared by replay,
// verify, run and sweep (--allow-incomplete among them, tools/support_cut_inputs.hpp),
// and a progress bar. The CLI's commands call the run library
// in-process; its names are visible in orthosonar::cli unqualified.
#include <string>

#include "replay/run/run.hpp"
#include "tools/cli.hpp"

namespace orthosonar::cli {

using namespace ::orthosonar::run;  // NOLINT: the CLI is the run library's own front end

struct CommonRunArgs {
  std::string systems = "fusion,submap";
  int threads = 0;           // 0: from the config (default 1)
  std::string config_path;
  double rate = 0.0;
  std::string mesh_path;
  std::string model_path;
};
void add_run_options(CLI::App& sub, CommonRunArgs& args);
// RunOptions from the parsed arguments (reads and checks --config). Errors name the file
// or value.
Result<RunOptions> run_options_from(const CommonRunArgs& args);

// A fixed-width progress bar on stderr ("label [#####.....] 52%  detail").
void print_progress(const std::string& label, double fraction, const std::string& detail);

// RunControl printing a progress bar labelled `label` (nothing when `show` is false).
RunControl progress_bar_control(const std::string& label, bool show);

}  // namespace orthosonar::cli
