#pragma once
// A golden scenario (issue 8): the file golden/scenarios/<name>.yaml that names a simulated
// mission and the pipeline settings and holds what it is expected to produce (digest per
// output and overall, metrics with tolerances, one stored top view per mapping system),
// running it in-process, comparing a run with the expectations and rewriting them.
#include <cstdint>
#include <map>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "replay/run/run.hpp"
#include "replay/verify/golden_images.hpp"

namespace orthosonar::verify {

struct Tolerances {
  double coverage_rel = 0.0;   // relative change of coverage_voxels allowed
  double mae_abs_m = 0.0;
  double rmse_abs_m = 0.0;
  double ate_abs_m = 0.0;
  // Largest reports::image_difference (0..1) between stored and current top view; absent
  // in scenarios recorded before image expectations existed.
  double image_difference = kDefaultImageDifference;
};

// The scenario's `expected` section as recorded by write_expectations.
struct Expectations {
  std::optional<std::string> digest;            // overall digest (hex)
  std::map<std::string, std::string> outputs;   // output name -> digest (hex)
  std::map<std::string, double> metrics;        // "system.metric" -> value
  // system -> PNG path relative to the scenario's directory; nullopt: no `images` key.
  std::optional<std::map<std::string, std::string>> images;
};

struct Scenario {
  std::string path;
  std::string name, scene;
  uint64_t seed = 1;
  double duration_s = 40.0;
  std::string resolution = "reduced";
  double kf_distance_m = 3.0, kf_rotation_deg = 30.0;
  std::vector<std::string> systems = {"fusion", "submap"};
  Tolerances tol;
  std::optional<Expectations> expected;  // nullopt before the first --update
};

// Reads a scenario file. Errors name the file and the key at fault.
Result<Scenario> load_scenario(const std::string& path);

// golden/scenarios/*.yaml relative to the working directory (the repository root), sorted;
// empty when there are none. `golden --check` and `batch plan golden` default to these.
std::vector<std::string> default_golden_scenarios();

// The metrics a scenario pins, flattened to "system.metric" -> value.
std::map<std::string, double> scenario_metrics(const run::RunOutput& run);

// Allowed absolute difference for one metric (counts are exact).
double tolerance_for(const std::string& key, double expected, const Tolerances& t);

// Simulates the scenario's mission in-process (deterministic from the seed) and runs the
// pipeline over it with `threads` fusion threads.
Result<run::RunOutput> run_scenario(const Scenario& s, int threads);

// Compares one run with the scenario's expectations (digest, outputs, metrics within
// tolerance); writes every difference to `out`. False when no expectations are recorded.
bool expectations_match(const Scenario& s, const run::RunOutput& run, std::ostream& out);

// Rewrites the scenario file with the run's digest, outputs and metrics (through a
// temporary file and a rename). `images`: system -> PNG path relative to the scenario's
// directory; empty writes none.
Status write_expectations(const Scenario& s, const run::RunOutput& run, const std::map<std::string, std::string>& images);

}  // namespace orthosonar::verify
