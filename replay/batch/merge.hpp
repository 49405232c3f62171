#pragma once
// Merging a plan's results (state.hpp) into the outputs the one-machine command writes:
// a sweep's grids, tables, seed summary and reference-cell report, byte for byte those of
// `orthosonar sweep`; for verify and golden plans a summary (markdown, JSON) and JUnit XML,
// one test case per task. Missing, failed and stale results are named with their logs.
#include <functional>
#include <iostream>
#include <string>

#include "replay/batch/plan.hpp"

namespace orthosonar::batch {

struct MergeOptions {
  std::string out_dir;  // empty: <plan>/merged
  // Called once per task whose input was cut short ("batch task I (NAME): <warning>");
  // unset: the warning is printed on `log`.
  std::function<void(const std::string&)> on_cut_input;
  std::ostream* out = &std::cout;  // the tables (what the one-machine command prints)
  std::ostream* log = &std::cerr;  // what was merged, what is missing
};

// Gathers the results into options.out_dir. Exit code: 0 everything present and passing,
// 1 verify/golden with a difference, 2 results missing or failed (named on `log` with their
// log paths; the JUnit XML is still written for verify/golden).
int merge(const Plan& plan, const MergeOptions& options = {});

// JUnit XML text escaping (attributes and text).
std::string xml_escape(const std::string& s);

}  // namespace orthosonar::batch
