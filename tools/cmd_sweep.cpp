// `orthosonar sweep --scene S -o dir/`: the paper's experiment on one scene. Simulates one
// fixture, fuses every pair once, then runs the 15 keyframe settings (distance 1-5 m x
// rotation 30/60/90 deg) over both cores, each cell with every system; writes grid.json,
// grid.csv and tables.md (the paper's coverage grid, Table II and Table III layouts), then
// the reference cell's full outputs and report/report.html (heat maps, maps, tables).
#include <atomic>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <thread>

#include "hal/fake_source.hpp"
#include "reports/report.hpp"
#include "replay/fixture.hpp"
#include "tools/cli.hpp"
#include "replay/run/mission.hpp"
#include "tools/support_run_args.hpp"
#include "replay/run/sweep.hpp"

namespace orthosonar::cli {
namespace {

struct SweepArgs {
  std::string scene = "harbor";
  std::string out_dir = "out/sweep";
  double duration_s = 600.0;
  std::string resolution = "full";
  uint64_t seed = 1;
  int threads = 2;
  bool no_report = false;
  std::string fixture;  // use this fixture instead of simulating
  std::string sim_config;
  CommonRunArgs run;
};

int fail(const std::string& m) {
  std::cerr << "orthosonar sweep: " << m << "\n";
  return 2;
}

int run_sweep(SweepArgs a) {
  namespace fs = std::filesystem;
  auto options = run_options_from(a.run);
  if (!options.ok()) return fail(options.error().message);
  const int threads = std::max(1, a.threads);
  std::error_code ec;
  fs::create_directories(a.out_dir, ec);
  if (ec) return fail("cannot create '" + a.out_dir + "': " + ec.message());

  std::string fixture = a.fixture;
  if (fixture.empty()) {
    MissionSpec spec;
    spec.scene = a.scene;
    spec.duration_s = a.duration_s;
    auto res = sim::parse_resolution(a.resolution);
    if (!res.ok()) return fail(res.error().message);
    spec.resolution = *res;
    spec.seed = a.seed;
    spec.render_threads = threads;
    if (!a.sim_config.empty()) {
      std::ifstream f(a.sim_config);
      if (!f) return fail("cannot open '" + a.sim_config + "'");
      std::stringstream ss;
      ss << f.rdbuf();
      spec.sim_config_yaml = ss.str();
    }
    fixture = (fs::path(a.out_dir) / (a.scene + ".mcap")).string();
    auto made = ensure_mission_fixture(spec, fixture, [&](double f) { print_progress("simulate", f, a.scene); });
    if (!made.ok()) return fail(made.error().message);
    if (!*made) std::cerr << "simulate: reusing " << fixture << "\n";
  }

  // Pass 1: fuse every pair once (both cores) and keep the stream without images.
  auto prepared = prepare_sweep(fixture, *options, threads,
                                [&](double f) { print_progress("fuse", f, "pairs fused once for all cells"); });
  if (!prepared.ok()) return fail(prepared.error().message);
  print_progress("fuse", 1.0, "done");

  // Pass 2: the 15 cells over `threads` workers; results by cell index (deterministic).
  const auto cells = paper_grid();
  auto ok = run_cells(*prepared, *options, cells, threads, [](size_t d, size_t n) {
    print_progress("cells", static_cast<double>(d) / static_cast<double>(n), std::to_string(d) + "/" + std::to_string(n));
  });
  if (!ok.ok()) return fail(ok.error().message);
  const SweepReport report = make_sweep_report(*prepared, std::move(*ok));
  if (Status s = write_sweep_outputs(report, a.out_dir); !s.ok()) return fail(s.error().message);
  std::cout << sweep_tables_markdown(report);

  // The reference cell (SPEC §5 defaults: 3 m / 30 deg) replayed in full into the sweep
  // directory (maps, metrics, trajectories, digest), so the report shows the maps beside
  // the heat maps. Skipped with --no-report.
  if (!a.no_report) {
    RunOptions ref = *options;
    ref.threads_override = threads;
    ref.adjust = [](RunConfig& c) {  // the reference cell
      c.pipeline.slam.kf_distance_m = 3.0;
      c.pipeline.slam.kf_rotation_deg = 30.0;
    };
    auto run = run_fixture(fixture, ref);
    if (!run.ok()) return fail(run.error().message);
    if (Status s = write_run_outputs(*run, ref, a.out_dir); !s.ok()) return fail(s.error().message);
    const std::string report_dir = (fs::path(a.out_dir) / "report").string();
    reports::ReportOptions ropt;
    const auto scene_it = run->metadata.find("scene");
    ropt.title = "orthosonar sweep: " + (scene_it != run->metadata.end() ? scene_it->second : a.scene);
    Status rs = reports::write_report(a.out_dir, report_dir, ropt);
    if (!rs.ok()) {
      std::cerr << "sweep: report: " << rs.error().message << "; writing it without 3D renders\n";
      ropt.require_renders = false;
      rs = reports::write_report(a.out_dir, report_dir, ropt);
    }
    if (!rs.ok()) return fail("report: " + rs.error().message);
    std::cerr << "sweep: report " << (fs::path(report_dir) / "report.html").string() << "\n";
  }
  std::cerr << "sweep: outputs in " << a.out_dir << "\n";
  return 0;
}

const bool registered = register_command(
    {"sweep", "Run the paper's keyframe-density experiment on one scene (coverage, error, runtime tables)",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<SweepArgs>();
       sub.add_option("--scene", a->scene, "Built-in scene (marina1, marina2, harbor, aircraft)")->capture_default_str();
       sub.add_option("-o,--out", a->out_dir, "Output directory")->capture_default_str();
       sub.add_option("--duration", a->duration_s, "Mission duration (s)")->capture_default_str();
       sub.add_option("--resolution", a->resolution, "full or reduced")->capture_default_str();
       sub.add_option("--seed", a->seed, "Simulation seed")->capture_default_str();
       sub.add_option("--workers", a->threads, "Worker threads (cells in parallel)")->capture_default_str();
       sub.add_option("--fixture", a->fixture, "Use this fixture instead of simulating one");
       sub.add_option("--sim-config", a->sim_config, "Simulator config YAML (fields of SimConfig)");
       sub.add_flag("--no-report", a->no_report,
                    "Skip the reference-cell (3 m / 30 deg) outputs and report/report.html");
       add_run_options(sub, a->run);
       return [a] { return run_sweep(*a); };
     }});

}  // namespace
}  // namespace orthosonar::cli
