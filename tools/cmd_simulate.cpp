// `orthosonar simulate --scene harbor --duration 120 --seed 1 -o h.mcap`: runs the simulator
// (hal/sim) and writes a fixture that embeds its scene (docs/SCENES.md); the same arguments
// give a byte-identical file, wherever the scene file lives.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>

#include <opencv2/core.hpp>

#include "hal/sim/simulator.hpp"
#include "hal/codec/image_codec.hpp"
#include "hal/sim/sonar_fan.hpp"
#include "hal/sim/sonar_snapshot.hpp"
#include "replay/run/simulate.hpp"
#include "tools/cli.hpp"
#include "hal/drivers/oculus_ping_file.hpp"

namespace orthosonar::cli {
namespace {

struct SimulateArgs {
  std::string scene = "harbor";
  std::string scene_file;
  double duration_s = 60.0;
  uint64_t seed = 1;
  uint64_t scene_seed = 1;
  std::string resolution = "full";
  bool labels = false;
  std::string out;
  std::string export_mesh;
  std::string config_yaml;      // --sim-config
  std::string old_config_yaml;  // --config, the option's name before 2026-12-07 (hidden; warns)
  std::string profile;  // field (default) or clean
  int threads = 2;
  std::string snapshot_dir;
  std::vector<double> snapshot_at_s;
  std::string snapshot_pose;  // "x y yaw_deg": render both sonars there and exit
  bool compare_profiles = false;  // with --snapshot-pose: clean and field side by side
  std::string real_ping;          // with --compare-profiles: a raw Oculus ping drawn beside
  bool quiet = false;
  int zstd_level = 1;  // fixture chunk compression (1: the renderer's pace; 19: smallest files)
  bool ranges = false;  // list the simulator config's keys with their valid ranges
  // Flags actually given: only these override the --sim-config file (docs/SCENES.md).
  bool duration_given = false, seed_given = false, resolution_given = false, threads_given = false;
};

int simulate_fail(const std::string& msg) {
  std::cerr << "orthosonar simulate: " << msg << "\n";
  return 2;
}

int run_simulate(SimulateArgs a) {
  if (!a.old_config_yaml.empty()) {
    // Every other command's --config is the run configuration; the simulator's file is
    // --sim-config everywhere (sweep, perception-check, batch plan sweep).
    if (!a.config_yaml.empty()) return simulate_fail("--config is the old name of --sim-config: give one of them");
    std::cerr << "orthosonar simulate: --config is now --sim-config (the name sweep, perception-check and batch use); "
                 "reading '" << a.old_config_yaml << "' as --sim-config\n";
    a.config_yaml = a.old_config_yaml;
  }
  if (a.ranges) {
    for (const auto& r : sim::sim_config_key_ranges()) std::cout << r.key << "\t" << r.range << "\n";
    return 0;
  }
  // Precedence, lowest first: SimConfig's defaults and this command's (--threads 2), the
  // --sim-config file, the flags actually given (a flag left at its default never overrides
  // the file: sweep and batch resolve the same way).
  sim::SimConfig cfg;
  cfg.render_threads = a.threads;
  std::optional<sim::SonarProfile> profile;
  if (!a.profile.empty()) {  // before the config file, whose keys refine the profile
    auto p = sim::parse_profile(a.profile);
    if (!p) return simulate_fail(p.error().message);
    profile = *p;
    cfg.profile = *p;
    sim::apply_profile(cfg.sonar, cfg.profile);
  }
  if (!a.config_yaml.empty())
    if (Status s = sim::load_sim_config_file(a.config_yaml, cfg); !s) return simulate_fail(s.error().message);
  if (profile && cfg.profile != *profile)
    return simulate_fail("--profile " + a.profile + " contradicts '" + a.config_yaml + "' (profile: " +
                sim::profile_name(cfg.profile) + ")");
  if (a.duration_given) cfg.duration_s = a.duration_s;
  if (a.seed_given) cfg.seed = a.seed;
  cfg.labels = a.labels || cfg.labels;
  if (a.threads_given) cfg.render_threads = a.threads;
  if (a.resolution_given) {
    auto res = sim::parse_resolution(a.resolution);
    if (!res) return simulate_fail(res.error().message);
    cfg.resolution = *res;
  }
  if (Status s = sim::validate(cfg); !s) return simulate_fail(s.error().message);
  auto scene = a.scene_file.empty() ? sim::builtin_scene(a.scene, a.scene_seed) : sim::load_scene_file(a.scene_file);
  if (!scene) return simulate_fail(scene.error().message);
  if (!a.export_mesh.empty()) {
    if (Status s = sim::write_mesh_ply(scene->mesh, a.export_mesh); !s) return simulate_fail(s.error().message);
  }
  const auto t0 = std::chrono::steady_clock::now();
  if (!a.snapshot_pose.empty()) {
    // One ping of each sonar with the vehicle at a chosen pose (vehicle depth, level).
    std::istringstream in(a.snapshot_pose);
    double x = 0, y = 0, yaw_deg = 0;
    if (!(in >> x >> y >> yaw_deg)) return simulate_fail("--snapshot-pose expects 'x y yaw_deg'");
    if (a.snapshot_dir.empty()) return simulate_fail("--snapshot-pose needs --snapshot-dir");
    const SE3 T_W_V = sim::snapshot_vehicle_pose(*scene, x, y, yaw_deg);
    std::filesystem::create_directories(a.snapshot_dir);
    if (a.compare_profiles) {
      // docs/images/<scene>_profiles.jpg: clean | field, horizontal above vertical.
      const cv::Mat all = sim::profile_comparison_image(*scene, cfg, T_W_V);
      const auto path = (std::filesystem::path(a.snapshot_dir) / (scene->name + "_profiles.jpg")).string();
      if (Status s = codec::write_jpeg(path, all, 85); !s) return simulate_fail(s.error().message);
      if (!a.quiet) std::printf("wrote %s\n", path.c_str());
      if (!a.real_ping.empty()) {
        auto f = hal::drivers::oculus::read_oculus_ping_file(a.real_ping, "--real-ping");
        if (!f) return simulate_fail(f.error().message);
        const auto real_path = (std::filesystem::path(a.snapshot_dir) / "oculus_m1200d_real.png").string();
        if (Status s = sim::write_fan_png(f->ping, real_path, 560, true); !s) return simulate_fail(s.error().message);
        if (!a.quiet) std::printf("wrote %s\n", real_path.c_str());
      }
      return 0;
    }
    auto written = sim::write_pose_snapshots(*scene, cfg, T_W_V, a.snapshot_dir);
    if (!written) return simulate_fail(written.error().message);
    if (!a.quiet)
      for (const auto& path : *written) std::printf("wrote %s\n", path.c_str());
    return 0;
  }
  if (Status s = sim::select_route(*scene, cfg.route); !s) return simulate_fail(s.error().message);
  sim::Simulator simulator(std::move(*scene), cfg);
  run::SimulateOptions so;
  so.out = a.out;
  so.zstd_level = a.zstd_level;
  so.snapshot_dir = a.snapshot_dir;
  so.snapshot_at_s = a.snapshot_at_s;
  auto simulated = run::simulate_to_fixture(simulator, so);
  if (!simulated) return simulate_fail(simulated.error().message);
  const auto& counts = simulated->per_channel;
  const uint64_t events = simulated->events;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!a.quiet) {
    std::printf("simulated %s: %.1f s, seed %llu, %s, pings h/v %llu/%llu, imu %llu, dvl %llu, depth %llu, truth %llu, "
                "labels %llu, path %.0f m, %llu events in %.1f s%s%s\n",
                simulator.describe().c_str(), cfg.duration_s, static_cast<unsigned long long>(cfg.seed),
                sim::resolution_name(cfg.resolution), static_cast<unsigned long long>(counts[0]),
                static_cast<unsigned long long>(counts[1]), static_cast<unsigned long long>(counts[2]),
                static_cast<unsigned long long>(counts[3]), static_cast<unsigned long long>(counts[4]),
                static_cast<unsigned long long>(counts[5]), static_cast<unsigned long long>(counts[6] + counts[7]),
                simulator.trajectory().path_length_m(), static_cast<unsigned long long>(events), wall,
                a.out.empty() ? "" : " -> ", a.out.c_str());
  }
  return 0;
}

const bool registered_simulate = register_command(
    {"simulate", "Simulate a mission in a built-in or user scene and write a fixture (.mcap)",
     [](CLI::App& sub) -> std::function<int()> {
       auto a = std::make_shared<SimulateArgs>();
       auto* scene = sub.add_option("--scene", a->scene, "Built-in scene: marina1, marina2, harbor, aircraft")
                         ->capture_default_str();
       sub.add_option("--scene-file", a->scene_file, "User scene YAML (docs/SCENES.md)")->excludes(scene);
       auto* duration = sub.add_option("--duration", a->duration_s, "Mission length, seconds (overrides --sim-config)")
                            ->capture_default_str();
       auto* seed = sub.add_option("--seed", a->seed, "Noise seed (speckle, sensors; overrides --sim-config)")
                        ->capture_default_str();
       sub.add_option("--scene-seed", a->scene_seed, "Geometry seed of a built-in scene")->capture_default_str();
       auto* resolution = sub.add_option("--resolution", a->resolution,
                                         "full (512x600) or reduced (256x300) (overrides --sim-config)")
                              ->capture_default_str();
       sub.add_flag("--labels", a->labels, "Also write per-pixel class labels per ping");
       sub.add_option("-o,--out", a->out, "Fixture to write (.mcap)");
       sub.add_option("--export-mesh", a->export_mesh, "Write the ground-truth scene mesh (PLY)");
       sub.add_option("--sim-config", a->config_yaml, "Simulator config YAML (fields of SimConfig; docs/SCENES.md)");
       sub.add_option("--config", a->old_config_yaml, "The old name of --sim-config")->group("");
       sub.add_option("--profile", a->profile, "Image formation: field (default: side lobes, multipath, seabed, absorption, TVG) or clean");
       sub.add_option("--zstd-level", a->zstd_level, "zstd level of the fixture's chunks (1 fastest, 19 smallest)")
           ->check(CLI::Range(1, 19))
           ->capture_default_str();
       auto* threads = sub.add_option("--threads", a->threads,
                                      "Render threads (output identical for any count; overrides --sim-config)")
                           ->capture_default_str();
       sub.add_option("--snapshot-dir", a->snapshot_dir, "Write fan PNGs of the pings at --snapshot-at times here");
       sub.add_option("--snapshot-at", a->snapshot_at_s, "Mission times (s) for snapshots");
       sub.add_option("--snapshot-pose", a->snapshot_pose, "Only render both sonars at 'x y yaw_deg' (vehicle depth) into --snapshot-dir");
       sub.add_flag("--compare-profiles", a->compare_profiles,
                    "With --snapshot-pose: write <scene>_profiles.jpg, the clean and field profiles side by side");
       sub.add_option("--real-ping", a->real_ping,
                      "With --compare-profiles: also draw this raw Oculus ping (oculus_m1200d_real.png)");
       sub.add_flag("-q,--quiet", a->quiet, "No summary line");
       sub.add_flag("--ranges", a->ranges, "List every --sim-config key with its valid range, and exit");
       return [a, duration, seed, resolution, threads] {
         a->duration_given = duration->count() > 0;
         a->seed_given = seed->count() > 0;
         a->resolution_given = resolution->count() > 0;
         a->threads_given = threads->count() > 0;
         return run_simulate(*a);
       };
     }});

}  // namespace
}  // namespace orthosonar::cli
