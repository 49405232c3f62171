#include "replay/run/mission.hpp"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

#include <unistd.h>
#include <yaml-cpp/yaml.h>

#include "hal/sim/simulator.hpp"
#include "replay/fixture/fixture.hpp"

namespace orthosonar::run {
namespace {

bool same_mission(const replay::FixtureMetadata& m, const MissionSpec& s) {
  auto get = [&](const char* k) -> std::string {
    const auto it = m.find(k);
    return it == m.end() ? std::string() : it->second;
  };
  // The defaults' profiles too: a fixture made before a default changed (the sonar profile
  // on 2026-12-02, the navigation profile on 2026-12-05; fixtures from before either say
  // nothing, or "ahrs") is another mission, not one to reuse.
  const sim::SimConfig defaults;
  const std::string nav = get("nav_profile").empty() ? "ahrs" : get("nav_profile");
  const std::string sonar = get("profile").empty() ? "clean" : get("profile");
  const std::string route = get("route").empty() ? "default" : get("route");
  return get("scene") == s.scene && route == (s.route.empty() ? "default" : s.route) && get("seed") == std::to_string(s.seed) &&
         get("resolution") == sim::resolution_name(s.resolution) &&
         std::abs(std::atof(get("duration_s").c_str()) - s.duration_s) < 1e-6 &&
         nav == sim::nav_profile_name(defaults.nav_profile) && sonar == sim::profile_name(defaults.profile) &&
         s.sim_config_yaml.empty();  // overrides are not in the metadata: always re-simulate
}

}  // namespace

Status resolve_mission_flags(const std::string& sim_config_yaml, MissionFlags& flags) {
  if (sim_config_yaml.empty()) return {};
  sim::SimConfig file;
  if (Status s = sim::apply_sim_config_yaml(sim_config_yaml, file); !s.ok()) return s;
  YAML::Node root;
  try {
    root = YAML::Load(sim_config_yaml);
  } catch (const YAML::Exception& e) {
    return Error{std::string("sim config: ") + e.what()};
  }
  const YAML::Node& doc = root;  // const: a lookup never inserts
  auto sets = [&doc](const char* key) { return doc.IsMap() && doc[key].IsDefined(); };
  if (!flags.duration_given && sets("duration_s")) flags.duration_s = file.duration_s;
  if (!flags.resolution_given && sets("resolution")) flags.resolution = sim::resolution_name(file.resolution);
  if (!flags.seeds_given && sets("seed")) flags.seeds = {file.seed};
  return {};
}

Result<bool> ensure_mission_fixture(const MissionSpec& spec, const std::string& path,
                                    const std::function<void(double)>& progress) {
  if (std::filesystem::exists(path)) {
    auto existing = replay::FixtureSource::open(path);
    if (existing.ok() && (*existing)->recovery().complete && same_mission((*existing)->metadata(), spec))
      return false;
  }
  auto scene = sim::builtin_scene(spec.scene, spec.seed);
  if (!scene.ok()) return scene.error();
  sim::SimConfig cfg;
  cfg.render_threads = spec.render_threads;  // the file may set it (same bytes for any count)
  if (!spec.sim_config_yaml.empty())
    if (Status s = sim::apply_sim_config_yaml(spec.sim_config_yaml, cfg); !s.ok()) return s.error();
  // The spec's mission wins over the file: the caller resolved it (resolve_mission_flags),
  // and the fixture's name and reuse check rely on it.
  cfg.duration_s = spec.duration_s;
  cfg.seed = spec.seed;
  cfg.resolution = spec.resolution;
  if (!spec.route.empty()) cfg.route = spec.route;
  if (Status s = sim::validate(cfg); !s.ok()) return s.error();
  if (Status s = sim::select_route(*scene, cfg.route); !s.ok()) return s.error();
  sim::Simulator simulator(std::move(*scene), cfg);
  std::error_code ec;
  if (const auto parent = std::filesystem::path(path).parent_path(); !parent.empty())
    std::filesystem::create_directories(parent, ec);
  // A name of this process's own: batch tasks sharing a fixture may simulate it at the
  // same time (same bytes; the last rename wins, each rename is atomic).
  const std::string tmp = path + ".partial." + std::to_string(::getpid());
  auto writer = replay::FixtureWriter::open(tmp, simulator.metadata());
  if (!writer.ok()) return writer.error();
  // The fixture carries its scene (docs/SCENES.md): replay needs nothing else.
  auto scene_files = sim::embed_scene(simulator.scene());
  if (!scene_files.ok()) return scene_files.error();
  for (auto& f : *scene_files)
    if (Status s = (*writer)->attach({f.name, f.media_type, std::move(f.data)}); !s.ok()) return s.error();
  const Time duration = Time::from_seconds(spec.duration_s);
  uint64_t n = 0;
  for (;;) {
    auto p = simulator.next();
    if (p.error) return Error{simulator.describe() + ": " + p.error->message};
    if (p.end_of_stream || !p.event) break;
    if (Status s = (*writer)->write(*p.event); !s.ok()) return s.error();
    if (progress && (++n % 1024) == 0) progress(p.event->stamp.seconds() / duration.seconds());
  }
  if (Status s = (*writer)->close(); !s.ok()) return s.error();
  std::filesystem::rename(tmp, path, ec);
  if (ec) {
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    return Error{"cannot rename '" + tmp + "' to '" + path + "': " + ec.message()};
  }
  if (progress) progress(1.0);
  return true;
}

}  // namespace orthosonar::run
