// `orthosonar sweep --scene S -o dir/`: the paper's experiment on one scene. Simulates one
// fixture, fuses every pair once, then runs the 15 keyframe settings (distance 1-5 m x
// rotation 30/60/90 deg; --cells for a subset) over both cores, each cell with every system;
// writes grid.json, grid.csv and tables.md (the paper's coverage grid and Table II layout;
// the same bytes on every machine), runtime.json/.md (Table III, timings), then the
// reference cell's full outputs and report/report.html (heat maps, maps, tables).
// Several scenes or seeds (--scenes a,b --seeds 1-5) write <scene>/seed<N>/ each and
// seeds.md/seeds.json (per seed and pooled over seeds). `orthosonar batch plan sweep`
// shards the same work; its merge writes the same bytes.
#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <sstream>
#include <thread>

#include "hal/fake_source.hpp"
#include "replay/batch/sweep_outputs.hpp"
#include "replay/fixture/fixture.hpp"
#include "tools/cli.hpp"
#include "tools/support_cut_inputs.hpp"
#include "replay/run/mission.hpp"
#include "tools/support_run_args.hpp"
#include "replay/run/sweep.hpp"

namespace orthosonar::cli {
namespace {

struct SweepArgs {
  std::string scene = "harbor";  // one scene, or several separated by commas
  std::string out_dir = "out/sweep";
  double duration_s = 600.0;
  std::string resolution = "full";
  std::string seeds = "1";
  std::string cells = "all";
  int threads = 2;
  bool no_report = false;
  std::string fixture;  // use this fixture instead of simulating
  std::string sim_config;
  CommonRunArgs run;
  // Flags actually given: only these override --sim-config (as in `simulate`).
  bool duration_given = false, resolution_given = false, seeds_given = false;
};

int sweep_fail(const std::string& m) {
  std::cerr << "orthosonar sweep: " << m << "\n";
  return 2;
}

std::vector<std::string> split_scenes(const std::string& spec) {
  std::vector<std::string> out;
  std::stringstream ss(spec);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

// One (fixture, seed) sweep: fuse once, run the cells, write the outputs into `dir` and,
// unless --no-report, the reference cell's full outputs and the report.
Result<SweepReport> sweep_one(const SweepArgs& a, const RunOptions& options, const std::string& fixture,
                              const std::vector<GridCell>& cells, const std::string& dir) {
  const int threads = std::max(1, a.threads);
  // Pass 1: fuse every pair once (both cores) and keep the stream without images.
  auto prepared = prepare_sweep(fixture, options, threads,
                                [&](double f) { print_progress("fuse", f, "pairs fused once for all cells"); });
  if (!prepared.ok()) return prepared.error();
  print_progress("fuse", 1.0, "done");
  {
    char held[160];
    std::snprintf(held, sizeof held, "sweep: holding %zu events (%.1f MB) and %zu pairs' fusion results (%.1f MB) for the cells\n",
                  prepared->events->size(), static_cast<double>(prepared->events->memory_bytes()) / 1e6,
                  prepared->fused->size(), static_cast<double>(prepared->fused->memory_bytes()) / 1e6);
    std::cerr << held;
  }
  note_input(fixture, prepared->recovery);
  // Pass 2: the cells over `threads` workers; results by cell index (deterministic).
  auto ok = run_cells(*prepared, options, cells, threads, [](size_t d, size_t n) {
    print_progress("cells", static_cast<double>(d) / static_cast<double>(n), std::to_string(d) + "/" + std::to_string(n));
  });
  if (!ok.ok()) return ok.error();
  SweepReport report = make_sweep_report(*prepared, std::move(*ok));
  report.input_cut = replay::cut_input_warning(fixture, prepared->recovery).value_or("");
  if (Status s = write_sweep_outputs(report, dir); !s.ok()) return s.error();
  if (!a.no_report) {
    if (Status s = batch::write_reference_outputs(fixture, options, threads, dir); !s.ok()) return s.error();
    if (Status s = batch::write_sweep_report(dir, "orthosonar sweep: " + report.scene); !s.ok()) return s.error();
  }
  return report;
}

int run_sweep(SweepArgs a) {
  namespace fs = std::filesystem;
  auto options = run_options_from(a.run);
  if (!options.ok()) return sweep_fail(options.error().message);
  auto cells = parse_cells(a.cells);
  if (!cells.ok()) return sweep_fail(cells.error().message);
  auto seeds = parse_seeds(a.seeds);
  if (!seeds.ok()) return sweep_fail(seeds.error().message);
  const auto scenes = split_scenes(a.scene);
  if (scenes.empty()) return sweep_fail("--scene: no scene given");
  std::error_code ec;
  fs::create_directories(a.out_dir, ec);
  if (ec) return sweep_fail("cannot create '" + a.out_dir + "': " + ec.message());

  if (!a.fixture.empty()) {  // a given fixture: one sweep into out_dir
    auto report = sweep_one(a, *options, a.fixture, *cells, a.out_dir);
    if (!report.ok()) return sweep_fail(report.error().message);
    std::cout << sweep_tables_markdown(*report);
    std::cerr << "sweep: outputs in " << a.out_dir << "\n";
    return 0;
  }
  std::string sim_yaml;
  if (!a.sim_config.empty()) {
    std::ifstream f(a.sim_config);
    if (!f) return sweep_fail("cannot open '" + a.sim_config + "'");
    std::stringstream ss;
    ss << f.rdbuf();
    sim_yaml = ss.str();
  }
  MissionFlags flags;
  flags.duration_s = a.duration_s;
  flags.duration_given = a.duration_given;
  flags.resolution = a.resolution;
  flags.resolution_given = a.resolution_given;
  flags.seeds = *seeds;
  flags.seeds_given = a.seeds_given;
  if (Status s = resolve_mission_flags(sim_yaml, flags); !s.ok()) return sweep_fail(a.sim_config + ": " + s.error().message);
  *seeds = flags.seeds;
  auto res = sim::parse_resolution(flags.resolution);
  if (!res.ok()) return sweep_fail(res.error().message);
  // One scene and one seed write into out_dir itself (as always); several write one folder
  // per (scene, seed) and seeds.md / seeds.json over them (write_sweep_set).
  const bool set = scenes.size() > 1 || seeds->size() > 1;
  std::vector<SweepReport> reports;
  std::vector<uint64_t> report_seeds;
  for (const auto& scene : scenes)
    for (const uint64_t seed : *seeds) {
      MissionSpec spec;
      spec.scene = scene;
      spec.duration_s = flags.duration_s;
      spec.resolution = *res;
      spec.seed = seed;
      spec.render_threads = std::max(1, a.threads);
      spec.sim_config_yaml = sim_yaml;
      const std::string dir = set ? (fs::path(a.out_dir) / sweep_set_dir(scene, seed)).string() : a.out_dir;
      fs::create_directories(dir, ec);
      if (ec) return sweep_fail("cannot create '" + dir + "': " + ec.message());
      const std::string fixture = (fs::path(dir) / (scene + ".mcap")).string();
      auto made = ensure_mission_fixture(spec, fixture,
                                         [&](double f) { print_progress("simulate", f, scene + " seed " + std::to_string(seed)); });
      if (!made.ok()) return sweep_fail(made.error().message);
      if (!*made) std::cerr << "simulate: reusing " << fixture << "\n";
      auto report = sweep_one(a, *options, fixture, *cells, dir);
      if (!report.ok()) return sweep_fail(scene + " seed " + std::to_string(seed) + ": " + report.error().message);
      if (!set) std::cout << sweep_tables_markdown(*report);
      reports.push_back(std::move(*report));
      report_seeds.push_back(seed);
    }
  if (set) {
    if (Status s = write_sweep_set(reports, report_seeds, a.out_dir); !s.ok()) return sweep_fail(s.error().message);
    std::cout << seeds_markdown(reports, report_seeds);
  }
  std::cerr << "sweep: outputs in " << a.out_dir << "\n";
  return 0;
}

const bool registered_sweep = register_command(
    {"sweep", "Run the paper's keyframe-density experiment on one scene (coverage, error, runtime tables)",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<SweepArgs>();
       sub.add_option("--scene,--scenes", a->scene,
                      "Built-in scene (marina1, marina2, harbor, aircraft); several separated by commas")
           ->capture_default_str();
       sub.add_option("-o,--out", a->out_dir, "Output directory")->capture_default_str();
       auto* duration = sub.add_option("--duration", a->duration_s, "Mission duration (s; overrides --sim-config)")
                            ->capture_default_str();
       auto* resolution = sub.add_option("--resolution", a->resolution, "full or reduced (overrides --sim-config)")
                              ->capture_default_str();
       auto* seeds = sub.add_option("--seed,--seeds", a->seeds,
                      "Simulation seed(s): 2, 1-5 or 1,3,7; several write one folder per scene and seed and "
                      "seeds.md (per seed and pooled)")
           ->capture_default_str();
       sub.add_option("--cells", a->cells, "Keyframe cells: all, or DISTANCE/ROTATION list such as 1/30,3/30,5/90")
           ->capture_default_str();
       sub.add_option("--workers", a->threads, "Worker threads (cells in parallel)")->capture_default_str();
       sub.add_option("--fixture", a->fixture, "Use this fixture instead of simulating one");
       sub.add_option("--sim-config", a->sim_config, "Simulator config YAML (fields of SimConfig)");
       sub.add_flag("--no-report", a->no_report,
                    "Skip the reference-cell (3 m / 30 deg) outputs and report/report.html");
       add_run_options(sub, a->run);
       return [a, duration, resolution, seeds] {
         a->duration_given = duration->count() > 0;
         a->resolution_given = resolution->count() > 0;
         a->seeds_given = seeds->count() > 0;
         return run_sweep(*a);
       };
     }});

}  // namespace
}  // namespace orthosonar::cli
