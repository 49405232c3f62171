#pragma once
// Checking and updating one run of a golden scenario: its recorded expectations
// (golden_scenario.hpp), its absolute bounds (golden_bounds.hpp) and its rendered top views
// (golden_images.hpp). Each function writes its report lines to `out`, as
// `orthosonar golden` prints them.
#include <filesystem>
#include <ostream>
#include <string>

#include "core/result.hpp"
#include "replay/run/run.hpp"
#include "replay/verify/golden_scenario.hpp"

namespace orthosonar::verify {

// The scenario's absolute bounds (`bounds_path`, empty: default_golden_bounds_path), one
// line per check. A missing bounds file or scenario entry fails.
bool bounds_hold(const Scenario& s, const run::RunOutput& run, const std::string& bounds_path, std::ostream& out);

// Renders the run's top views into `run_dir` (cleared first, with the run's outputs) and
// compares them with the stored PNGs. A failed comparison writes
// <system>_top_comparison.png (stored | current) beside the current <system>_top.png.
// `display` is reports::check_display()'s answer: without one the check fails.
bool images_match(const Scenario& s, const run::RunOutput& run, const std::filesystem::path& run_dir,
                  const Status& display, std::ostream& out);

struct CheckOptions {
  bool images = true;            // false: --no-images
  std::string bounds_path;       // empty: default_golden_bounds_path(scenario)
  std::filesystem::path run_dir; // where images_match renders
};

// Expectations, bounds and (with options.images) images of one run; true when all hold.
bool check_run(const Scenario& s, const run::RunOutput& run, const CheckOptions& options, const Status& display,
               std::ostream& out);

// `golden --update` of one scenario from its run: says what changed (digest, metrics,
// images), writes the new top views beside the scenario (with `images`; else keeps the
// stored ones), rewrites the scenario file and checks the bounds, which it never writes.
// Returns whether the bounds hold; an Error when something could not be written.
Result<bool> update_scenario(const Scenario& s, const run::RunOutput& run, bool images,
                             const std::filesystem::path& out_base, const std::string& bounds_path, std::ostream& out);

}  // namespace orthosonar::verify
