// `orthosonar demo`: the README's first command. Runs the self-check, simulates the default
// mission (harbor, its survey route facing the structures, full resolution, 300 s) into
// <out>/harbor.mcap, replays it with
// sonar fusion mapping and submapping on both cores, writes the output directory and
// prints a summary table (coverage, MAE, RMSE, MAE with true keyframe poses, ATE DR/SLAM,
// runtime).
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "orthosonar/version.hpp"
#include "reports/report.hpp"
#include "tools/cli.hpp"
#include "hal/sim/scene.hpp"
#include "replay/run/mission.hpp"
#include "tools/support_run_args.hpp"

namespace orthosonar::cli {
int run_selfcheck();
namespace {

struct DemoOptions {
  std::string out_dir = "out/demo";
  std::string scene = "harbor";
  std::string route;  // empty: the scene's "survey" route when it has one, else its own
  // Long enough for the survey to run along the sailing ship and reach the pier and the
  // quay; the whole demo stays within a minute on 2 cores (docs/BENCHMARKS.md).
  double duration_s = 300.0;
  std::string resolution = "full";
  int threads = 2;
};

std::string opt(const std::optional<double>& v, const char* f = "%.3f") {
  if (!v) return "n/a";
  char buf[32];
  std::snprintf(buf, sizeof buf, f, *v);
  return buf;
}

void print_table(const RunOutput& r) {
  std::printf("\n%-8s %10s %8s %8s %11s %8s %9s %16s %16s\n", "system", "coverage", "MAE m", "RMSE m",
              "MAE true m", "ATE DR", "ATE SLAM", "fusion ms/pair", "map ms/step");
  double fusion_ms = 0.0, fusion_sd = 0.0;
  for (const auto& [name, s] : r.runtime)
    if (name == "fusion") fusion_ms = s.mean_ms(), fusion_sd = s.sd_ms();
  for (const auto& s : r.systems) {
    double map_ms = 0.0, map_sd = 0.0;
    for (const auto& [name, st] : s.runtime) map_ms = st.mean_ms(), map_sd = st.sd_ms();
    char f[32], m[32];
    std::snprintf(f, sizeof f, "%.2f±%.2f", fusion_ms, fusion_sd);
    std::snprintf(m, sizeof m, "%.4f±%.4f", map_ms, map_sd);
    std::printf("%-8s %10lld %8s %8s %11s %8s %9s %16s %16s\n", s.name.c_str(),
                static_cast<long long>(s.coverage_voxels),
                opt(s.accuracy ? std::optional<double>(s.accuracy->mae_m) : std::nullopt).c_str(),
                opt(s.accuracy ? std::optional<double>(s.accuracy->rmse_m) : std::nullopt).c_str(),
                opt(s.true_pose_accuracy ? std::optional<double>(s.true_pose_accuracy->mae_m) : std::nullopt).c_str(),
                opt(r.ate_dr_m).c_str(), opt(r.ate_slam_m).c_str(), f, m);
  }
  std::printf("\npairs %lld, keyframes %lld, loop closures %lld; %.0f s of sensor data replayed in %.1f s (%.0fx real time)\n",
              static_cast<long long>(r.counts.pairs), static_cast<long long>(r.counts.keyframes),
              static_cast<long long>(r.counts.loop_closures), r.stream_span.seconds(), r.wall_s,
              r.wall_s > 0 ? r.stream_span.seconds() / r.wall_s : 0.0);
}

int run_demo(const DemoOptions& o) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(o.out_dir, ec);
  if (ec) {
    std::cerr << "orthosonar demo: cannot create output directory '" << o.out_dir << "': " << ec.message() << "\n";
    return 2;
  }
  if (run_selfcheck() != 0) return 1;

  MissionSpec spec;
  spec.scene = o.scene;
  spec.route = o.route;
  // The demo flies a route that keeps structure ahead of the pair (the scene's "survey"),
  // where the scene has one.
  if (spec.route.empty())
    for (const auto& r : sim::builtin_route_names(o.scene))
      if (r == "survey") spec.route = r;
  spec.duration_s = o.duration_s;
  auto res = sim::parse_resolution(o.resolution);
  if (!res.ok()) {
    std::cerr << "orthosonar demo: " << res.error().message << "\n";
    return 2;
  }
  spec.resolution = *res;
  spec.render_threads = o.threads;
  const std::string fixture = (fs::path(o.out_dir) / (o.scene + ".mcap")).string();
  std::cout << "demo: simulating " << o.scene << " (" << o.duration_s << " s, " << o.resolution
            << " resolution) into " << fixture << "\n";
  auto made = ensure_mission_fixture(spec, fixture, [&](double f) { print_progress("simulate", f, o.scene); });
  if (!made.ok()) {
    std::cerr << "orthosonar demo: " << made.error().message << "\n";
    return 2;
  }
  if (!*made) std::cout << "demo: reusing " << fixture << "\n";

  RunOptions options;
  options.threads_override = o.threads;
  options.systems = {"fusion", "submap"};
  auto r = run_fixture(fixture, options, progress_bar_control("replay", true));
  if (!r.ok()) {
    std::cerr << "orthosonar demo: " << r.error().message << "\n";
    return 2;
  }
  if (Status s = write_run_outputs(*r, options, o.out_dir); !s.ok()) {
    std::cerr << "orthosonar demo: " << s.error().message << "\n";
    return 2;
  }
  print_table(*r);
  std::cout << "digest " << r->digest.overall_hex << "\n";
  // The review report. Without an X display (not run under xvfb-run) the 3D renders are
  // skipped and the HTML says so; every other part is still written.
  const std::string report_dir = (fs::path(o.out_dir) / "report").string();
  reports::ReportOptions ropt;
  Status rs = reports::write_report(o.out_dir, report_dir, ropt);
  if (!rs.ok()) {
    std::cerr << "orthosonar demo: report: " << rs.error().message << "; writing it without 3D renders\n";
    ropt.require_renders = false;
    rs = reports::write_report(o.out_dir, report_dir, ropt);
  }
  if (!rs.ok()) {
    std::cerr << "orthosonar demo: report: " << rs.error().message << "\n";
    return 2;
  }
  std::cout << "report: " << (fs::path(report_dir) / "report.html").string() << "\n";
  std::cout << "demo: outputs in " << o.out_dir << " (verify with: orthosonar verify " << fixture << " --expect "
            << (fs::path(o.out_dir) / "digest.json").string() << ")\n";
  return 0;
}

const bool registered_demo = register_command(
    {"demo", "Run the built-in demo mission (simulated) end to end, writing maps and a report",
     [](CLI::App& sub) -> std::function<int()> {
       auto o = std::make_shared<DemoOptions>();
       sub.add_option("-o,--out", o->out_dir, "Output directory")->capture_default_str();
       sub.add_option("--scene", o->scene, "Built-in scene")->capture_default_str();
       sub.add_option("--route", o->route, "Route of the scene (default: its survey route where it has one)");
       sub.add_option("--duration", o->duration_s, "Mission duration (s)")->capture_default_str();
       sub.add_option("--resolution", o->resolution, "full or reduced")->capture_default_str();
       sub.add_option("--threads", o->threads, "Threads (simulation and fusion)")->capture_default_str();
       return [o] { return run_demo(*o); };
     }});

}  // namespace
}  // namespace orthosonar::cli
