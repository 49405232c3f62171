// `orthosonar report RUN_DIR -o REPORT_DIR [--golden DIR]`: the review report of an
// output directory (replay, demo or sweep): report.html plus its PNGs.
#include <filesystem>
#include <iostream>

#include "reports/report.hpp"
#include "tools/cli.hpp"
#include "tools/support_cut_inputs.hpp"

namespace orthosonar::cli {
namespace {

struct ReportCmdOptions {
  std::string run_dir;
  std::string report_dir = "report";
  reports::ReportOptions report;
  bool allow_no_display = false;
};

int run_report(ReportCmdOptions o) {
  o.report.require_renders = !o.allow_no_display;
  if (auto cut = reports::run_input_cut(o.run_dir)) note_cut_input_warning(o.run_dir + ": " + *cut);
  const Status s = reports::write_report(o.run_dir, o.report_dir, o.report);
  if (!s) {
    std::cerr << "orthosonar report: " << s.error().message << "\n";
    return 2;
  }
  std::cout << "report: " << (std::filesystem::path(o.report_dir) / "report.html").string() << "\n";
  return 0;
}

const bool registered_report = register_command(
    {"report", "Write report.html (metrics, runtime, map renders, heat maps, golden comparison) for an output directory",
     [](CLI::App& sub) -> std::function<int()> {
       auto o = std::make_shared<ReportCmdOptions>();
       sub.add_option("run_dir", o->run_dir, "Output directory of replay, demo or sweep")->required()->check(CLI::ExistingDirectory);
       sub.add_option("-o,--out", o->report_dir, "Report directory (created)")->capture_default_str();
       sub.add_option("--golden", o->report.golden_dir, "Golden output directory to compare with")
           ->check(CLI::ExistingDirectory);
       sub.add_option("--width", o->report.width_px, "3D render width (px)")->capture_default_str()->check(CLI::Range(64, 8192));
       sub.add_option("--height", o->report.height_px, "3D render height (px)")->capture_default_str()->check(CLI::Range(64, 8192));
       sub.add_option("--diff-max", o->report.diff_max_m, "Difference view colour scale limit (m)")->capture_default_str();
       sub.add_flag("--allow-no-display", o->allow_no_display,
                    "Without an X display, skip the 3D renders instead of failing (normally: run under xvfb-run -a)");
       add_allow_incomplete_flag(sub);
       return [o] { return run_report(*o); };
     }});

}  // namespace
}  // namespace orthosonar::cli
