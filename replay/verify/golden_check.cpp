// One run of a golden scenario checked against, or recorded as, its expectations.
#include "replay/verify/golden_check.hpp"

#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>

#include "replay/verify/golden_bounds.hpp"
#include "replay/verify/golden_images.hpp"
#include "reports/image_compare.hpp"

namespace orthosonar::verify {
namespace {

namespace fs = std::filesystem;

// Scores with six decimals: the tolerance is small and scientific notation reads badly.
std::string score_str(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6f", v);
  return buf;
}

// Stored image paths are relative to the scenario file's directory.
fs::path scenario_dir(const Scenario& s) { return fs::path(s.path).parent_path(); }

// Writes the run's output directory (the output contract read by reports::load_run) and
// renders one top view per system from it.
Result<std::map<std::string, cv::Mat>> render_run_views(const Scenario& s, const run::RunOutput& run,
                                                        const fs::path& run_dir) {
  std::error_code ec;
  fs::remove_all(run_dir, ec);  // no stale renders or comparisons from an earlier run
  run::RunOptions o;
  o.systems = s.systems;
  if (auto st = run::write_run_outputs(run, o, run_dir.string()); !st) return st.error();
  return render_golden_views(run_dir.string(), s.systems, s.name);
}

// Renders the new top views, says each one's difference to the stored image, and writes
// them beside the scenario. Returns system -> relative path for the YAML.
Result<std::map<std::string, std::string>> update_images(const Scenario& s, const run::RunOutput& run,
                                                         const fs::path& out_base, std::ostream& out) {
  auto views = render_run_views(s, run, out_base / s.name / "update");
  if (!views) return views.error();
  const std::map<std::string, std::string> none;
  const auto& stored = s.expected && s.expected->images ? *s.expected->images : none;
  const double tol = s.tol.image_difference;
  std::map<std::string, std::string> paths;
  for (const auto& system : s.systems) {
    const std::string rel = s.name + "/" + golden_image_name(system);
    const cv::Mat& now = views->at(system);
    out << "  " << std::left << std::setw(26) << ("image " + system) << " ";
    if (const auto it = stored.find(system); it != stored.end()) {
      const fs::path old_path = scenario_dir(s) / it->second;
      if (auto old = read_png(old_path.string()); old) {
        const double d = reports::image_difference(*old, now);
        out << "difference to stored " << score_str(d)
            << (d <= tol ? "  (unchanged within tolerance " : "  (CHANGED, tolerance ") << score_str(tol) << ")";
      } else {
        out << "(stored image unreadable: " << old.error().message << ")";
      }
    } else {
      out << "(new)";
    }
    out << " -> " << rel << "\n";
    if (auto st = write_png((scenario_dir(s) / rel).string(), now); !st) return st.error();
    paths[system] = rel;
  }
  return paths;
}

}  // namespace

bool bounds_hold(const Scenario& s, const run::RunOutput& run, const std::string& bounds_path, std::ostream& out) {
  const std::string path = bounds_path.empty() ? default_golden_bounds_path(s.path) : bounds_path;
  auto all = load_golden_bounds(path);
  if (!all) {
    out << "  bounds FAILED: " << all.error().message << "\n";
    return false;
  }
  const auto it = all->find(s.name);
  if (it == all->end()) {
    out << "  bounds FAILED: no absolute bounds for scenario " << s.name << " in " << path << "\n";
    return false;
  }
  const GoldenBoundsVerdict v = check_golden_bounds(it->second, scenario_metrics(run), s.systems);
  for (const auto& line : v.lines) out << "  bound " << line << "\n";
  return v.ok;
}

bool images_match(const Scenario& s, const run::RunOutput& run, const fs::path& run_dir, const Status& display,
                  std::ostream& out) {
  if (!display) {
    out << "  image check FAILED for scenario " << s.name << ": " << display.error().message
        << " (ctest runs under `xvfb-run -a`; pass --no-images to skip the image checks deliberately)\n";
    return false;
  }
  if (!s.expected || !s.expected->images) {
    out << "  no image expectations recorded: run `xvfb-run -a orthosonar golden --update " << s.path << "`\n";
    return false;
  }
  const auto& images = *s.expected->images;
  auto views = render_run_views(s, run, run_dir);
  if (!views) {
    out << "  image check FAILED for scenario " << s.name << ": " << views.error().message << "\n";
    return false;
  }
  const double tol = s.tol.image_difference;
  bool ok = true;
  for (const auto& system : s.systems) {
    const cv::Mat& current = views->at(system);
    const fs::path current_path = run_dir / golden_image_name(system);
    if (auto st = write_png(current_path.string(), current); !st) out << "  warning: " << st.error().message << "\n";
    const auto stored_it = images.find(system);
    if (stored_it == images.end()) {
      ok = false;
      out << "  no image expectation for scenario " << s.name << ", system " << system
          << ": run `xvfb-run -a orthosonar golden --update " << s.path << "`\n";
      continue;
    }
    const fs::path stored_path = scenario_dir(s) / stored_it->second;
    auto stored = read_png(stored_path.string());
    if (!stored) {
      ok = false;
      out << "  image missing for scenario " << s.name << ", system " << system << ": " << stored.error().message << "\n";
      continue;
    }
    const double d = reports::image_difference(*stored, current);
    if (d <= tol) {
      out << "  image " << system << ": difference " << score_str(d) << " <= tolerance " << score_str(tol) << "\n";
      continue;
    }
    ok = false;
    const fs::path comparison = run_dir / (system + "_top_comparison.png");
    const auto st = write_png(comparison.string(), reports::side_by_side(*stored, "golden", current, "current"));
    out << "  image differs: scenario " << s.name << ", system " << system << ": difference " << score_str(d)
        << " > tolerance " << score_str(tol) << "\n"
        << "    golden:       " << stored_path.string() << "\n"
        << "    current:      " << current_path.string() << "\n"
        << "    side by side: " << (st ? comparison.string() : "not written (" + st.error().message + ")") << "\n";
  }
  return ok;
}

bool check_run(const Scenario& s, const run::RunOutput& run, const CheckOptions& options, const Status& display,
               std::ostream& out) {
  bool ok = expectations_match(s, run, out);
  ok = bounds_hold(s, run, options.bounds_path, out) && ok;
  if (options.images) ok = images_match(s, run, options.run_dir, display, out) && ok;
  return ok;
}

Result<bool> update_scenario(const Scenario& s, const run::RunOutput& run, bool images, const fs::path& out_base,
                             const std::string& bounds_path, std::ostream& out) {
  const std::string old = s.expected && s.expected->digest ? *s.expected->digest : "(none)";
  out << s.name << ": digest " << old << " -> " << run.digest.overall_hex
      << (old == run.digest.overall_hex ? "  (unchanged)" : "  (CHANGED)") << "\n";
  for (const auto& [k, v] : scenario_metrics(run)) {
    const auto it = s.expected ? s.expected->metrics.find(k) : std::map<std::string, double>::const_iterator();
    const bool had = s.expected && it != s.expected->metrics.end();
    const double before = had ? it->second : std::nan("");
    if (!had || before != v)
      out << "  " << std::left << std::setw(26) << k << " " << (had ? std::to_string(before) : "(new)") << " -> " << v << "\n";
  }
  std::map<std::string, std::string> image_paths;
  if (images) {
    auto written = update_images(s, run, out_base, out);
    if (!written) return Error{s.name + ": " + written.error().message};
    image_paths = std::move(*written);
  } else if (s.expected && s.expected->images) {
    // --no-images: the stored images stay the expectation, untouched.
    image_paths = *s.expected->images;
    out << "  images kept as stored (--no-images)\n";
  }
  if (auto st = write_expectations(s, run, image_paths); !st) return st.error();
  std::ostringstream bounds_out;
  if (!bounds_hold(s, run, bounds_path, bounds_out)) {
    out << bounds_out.str() << "  " << s.name
        << ": expectations written, but the run violates the absolute bounds above; `golden --check` "
           "keeps failing until the code is fixed (the bounds file is never written by --update)\n";
    return false;
  }
  return true;
}

}  // namespace orthosonar::verify
