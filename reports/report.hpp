#pragma once
// The review report: one self-contained report.html (inline CSS, no scripts, every image
// embedded as a data URI and also written as a PNG beside it) with the metrics and runtime
// tables, the map renders, the map coloured by its distance to the truth mesh, the ping pair
// perception saw, the trajectory plot and the trajectory error over time, coverage heat maps
// (sweeps), golden comparisons, the fixture summary, software version and digest. Called by `orthosonar report`, `orthosonar sweep` and the
// demo. Deterministic: no timestamps; the same inputs give the same HTML.
#include <optional>
#include <string>
#include <vector>

#include "core/result.hpp"

namespace orthosonar::reports {

struct ReportOptions {
  std::string golden_dir;          // a golden output directory to compare with; empty: none
  bool require_renders = true;     // false: without an X display, skip the 3D renders (noted in the HTML)
  int width_px = 1280;             // 3D render size
  int height_px = 960;
  double diff_max_m = 0.5;         // difference view colour scale saturates here
  std::string title;               // default: "orthosonar report: <scene>"
};

// Reads `run_dir` (shared output contract; a sweep dir with grid.json works too), writes
// report_dir/report.html and its PNGs (report_dir is created). Errors name the file at
// fault; parts that are missing from run_dir are listed in the report, not errors.
Status write_report(const std::string& run_dir, const std::string& report_dir, const ReportOptions& options = {});

// When `run_dir`'s summary.json records that the run's input fixture was cut short
// (issue 40): a sentence naming the file, the byte offset and what was recovered.
std::optional<std::string> run_input_cut(const std::string& run_dir);

// The relative file names an HTML file references (src="..." and href="..." that are
// not absolute URLs or fragments), in order of appearance. Used by tests and the CLI.
std::vector<std::string> referenced_files(const std::string& html);

}  // namespace orthosonar::reports
