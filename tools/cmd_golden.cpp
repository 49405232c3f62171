// `orthosonar golden`: golden scenarios (issue 8). A scenario file (golden/scenarios/*.yaml)
// names a simulated mission and the pipeline settings, and holds what it is expected to
// produce: the digest (per output and overall), metrics with tolerances, and one rendered
// top view per mapping system (PNG beside the scenario: <dir>/<name>/<system>_top.png,
// compared with reports::image_difference against `tolerances.image_difference`).
//
//   golden --run S.yaml [-o DIR] [--threads N]     simulate + map, print "digest: <hex>"
//   golden --check S.yaml... [--threads N] [--repeat K] [-o BASE] [--no-images] [--bounds B.yaml]
//                                                  exit 0 when every run matches, 1 when not
//   golden --update [S.yaml...] [-o BASE] [--no-images] [--bounds B.yaml]
//                                                  rewrite expectations, print what changed
//
// Beside the recorded expectations, every checked run must stay within the scenario's
// absolute bounds (golden/bounds.yaml, replay/verify/golden_bounds.hpp: SLAM ATE <= k x DR
// and <= a figure, MAE/RMSE against the mesh, coverage floors). --update never writes that
// file; it reports a violated bound and exits 1, and --check keeps failing on it.
//
// Image checks render with VTK and need an X display: run under `xvfb-run -a` (ctest always
// is). Without one the image check FAILS; only --no-images skips it (--update then keeps the
// stored images). Each checked run writes its outputs, current renders and, on a
// difference, a side-by-side comparison to BASE/<name>/threads<N>_run<K>/ (default BASE:
// <tmp>/orthosonar_golden). See docs/VERIFICATION.md.
//
// The fixture is generated in-process by the simulator (deterministic from the seed), so a
// scenario needs no stored recording. What the checks compute lives in the library
// orthosonar_verify (replay/verify/); this file parses arguments and prints.
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "replay/verify/golden_check.hpp"
#include "replay/verify/golden_scenario.hpp"
#include "reports/render.hpp"
#include "tools/cli.hpp"
#include "tools/support_run_args.hpp"

namespace orthosonar::cli {
namespace {

namespace fs = std::filesystem;
using verify::Scenario;

void print_metrics(const std::map<std::string, double>& m) {
  for (const auto& [k, v] : m) std::cout << "  " << std::left << std::setw(26) << k << " " << std::setprecision(6) << v << "\n";
}

int do_run(const std::string& path, const std::string& out_dir, int threads) {
  auto s = verify::load_scenario(path);
  if (!s) { std::cerr << "orthosonar golden: " << s.error().message << "\n"; return 2; }
  auto run = verify::run_scenario(*s, threads);
  if (!run) { std::cerr << "orthosonar golden: " << run.error().message << "\n"; return 2; }
  if (!out_dir.empty()) {
    RunOptions o;
    o.systems = s->systems;
    if (auto st = write_run_outputs(*run, o, out_dir); !st) {
      std::cerr << "orthosonar golden: " << st.error().message << "\n";
      return 2;
    }
  }
  std::cout << "scenario " << s->name << " (" << s->scene << ", seed " << s->seed << ", " << s->duration_s << " s, "
            << s->resolution << ", " << threads << " thread(s))\n";
  print_metrics(verify::scenario_metrics(*run));
  std::cout << "digest: " << run->digest.overall_hex << "\n";
  return 0;
}

int do_check(const std::vector<std::string>& paths, int threads, int repeat, bool images, const fs::path& out_base,
             const std::string& bounds_path) {
  // Asked once: without a display every image check fails with the same message.
  const Status display = images ? reports::check_display() : Status::Ok();
  int failures = 0;
  for (const auto& path : paths) {
    auto s = verify::load_scenario(path);
    if (!s) { std::cerr << "orthosonar golden: " << s.error().message << "\n"; return 2; }
    for (int r = 0; r < repeat; ++r) {
      auto run = verify::run_scenario(*s, threads);
      if (!run) { std::cerr << "orthosonar golden: " << run.error().message << "\n"; return 2; }
      verify::CheckOptions co;
      co.images = images;
      co.bounds_path = bounds_path;
      co.run_dir = out_base / s->name / ("threads" + std::to_string(threads) + "_run" + std::to_string(r + 1));
      std::ostringstream diff;
      const bool ok = verify::check_run(*s, *run, co, display, diff);
      std::cout << (ok ? "PASS " : "FAIL ") << s->name << " (threads " << threads << ", run " << r + 1 << "/" << repeat
                << ") digest " << run->digest.overall_hex << (images ? "" : " (image checks skipped: --no-images)")
                << "\n" << diff.str();
      if (!ok) ++failures;
    }
  }
  return failures == 0 ? 0 : 1;
}

int do_update(const std::vector<std::string>& paths, bool images, const fs::path& out_base, const std::string& bounds_path) {
  int violated = 0;
  if (images)
    if (auto d = reports::check_display(); !d) {
      std::cerr << "orthosonar golden: cannot record image expectations: " << d.error().message
                << " (or pass --no-images to keep the stored images)\n";
      return 2;
    }
  for (const auto& path : paths) {
    auto s = verify::load_scenario(path);
    if (!s) { std::cerr << "orthosonar golden: " << s.error().message << "\n"; return 2; }
    auto run = verify::run_scenario(*s, 1);
    if (!run) { std::cerr << "orthosonar golden: " << run.error().message << "\n"; return 2; }
    auto bounds_ok = verify::update_scenario(*s, *run, images, out_base, bounds_path, std::cout);
    if (!bounds_ok) { std::cerr << "orthosonar golden: " << bounds_ok.error().message << "\n"; return 2; }
    if (!*bounds_ok) ++violated;
  }
  return violated == 0 ? 0 : 1;
}

struct GoldenArgs {
  std::string run;
  bool check = false, update = false;
  bool no_images = false;
  std::vector<std::string> scenarios;
  std::string out_dir;
  int threads = 1;
  int repeat = 1;
  std::string bounds;  // empty: golden/bounds.yaml beside the scenarios' folder
};

int run_golden(GoldenArgs a) {
  if (!a.run.empty()) return do_run(a.run, a.out_dir, a.threads);
  if (a.scenarios.empty()) a.scenarios = verify::default_golden_scenarios();
  if (a.scenarios.empty()) {
    std::cerr << "orthosonar golden: no scenarios given and none in golden/scenarios/ (run from the repository root)\n";
    return 2;
  }
  const fs::path out_base = a.out_dir.empty() ? fs::temp_directory_path() / "orthosonar_golden" : fs::path(a.out_dir);
  if (a.update) return do_update(a.scenarios, !a.no_images, out_base, a.bounds);
  if (a.check) return do_check(a.scenarios, a.threads, a.repeat, !a.no_images, out_base, a.bounds);
  std::cerr << "orthosonar golden: say --run S.yaml, --check or --update\n";
  return 2;
}

const bool registered_golden = register_command(
    {"golden", "Run, check or update golden scenarios (simulated missions with expected digests, metrics and images)",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<GoldenArgs>();
       sub.add_option("--run", a->run, "Run one scenario and print its digest");
       sub.add_flag("--check", a->check, "Check scenarios against their expectations (exit 1 on a difference)");
       sub.add_flag("--update", a->update, "Regenerate expectations and print what changed");
       sub.add_flag("--no-images", a->no_images,
                    "Skip the rendered-image checks (--update: keep the stored images); normally run under xvfb-run -a");
       sub.add_option("scenarios", a->scenarios, "Scenario files (default: golden/scenarios/*.yaml)");
       sub.add_option("-o,--out", a->out_dir,
                      "With --run: write the run's outputs here. With --check/--update: base directory of each run's "
                      "outputs, renders and comparisons (default: <tmp>/orthosonar_golden)");
       sub.add_option("--bounds", a->bounds,
                      "Absolute bounds file (default: bounds.yaml in the folder above the scenario's, i.e. golden/bounds.yaml)");
       sub.add_option("--threads", a->threads, "Fusion threads")->check(CLI::Range(1, 64));
       sub.add_option("--repeat", a->repeat, "With --check: runs per scenario")->check(CLI::Range(1, 100));
       return [a] { return run_golden(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
