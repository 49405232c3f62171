#pragma once
// Simulated missions for sweep and demo: simulate a built-in scene into a fixture file,
// reusing an existing fixture when its metadata says it was made with the same settings.
#include <functional>
#include <string>
#include <vector>

#include "core/result.hpp"
#include "hal/sim/sim_config.hpp"

namespace orthosonar::run {

struct MissionSpec {
  std::string scene = "harbor";
  std::string route;            // "" or "default": the scene's own (sim::select_route)
  double duration_s = 180.0;
  sim::Resolution resolution = sim::Resolution::kFull;
  uint64_t seed = 1;
  int render_threads = 2;
  std::string sim_config_yaml;  // simulator overrides (fields of SimConfig), may be empty; the
                                // fields above win over it (resolve_mission_flags chose them)
};

// A mission's duration, resolution and seeds from a command line (sweep, batch plan sweep)
// and its simulator config: a flag given wins over the file, the file over the flag's
// default, as `simulate --sim-config` resolves them (docs/SCENES.md). An invalid file is an
// error here, before anything runs.
struct MissionFlags {
  double duration_s = 180.0;
  bool duration_given = false;
  std::string resolution = "full";
  bool resolution_given = false;
  std::vector<uint64_t> seeds;
  bool seeds_given = false;
};
Status resolve_mission_flags(const std::string& sim_config_yaml, MissionFlags& flags);

// Writes `path` unless a complete fixture with the same scene, seed, resolution and
// duration is already there. `progress(fraction)` is called while simulating.
// Returns true when it simulated, false when it reused.
Result<bool> ensure_mission_fixture(const MissionSpec& spec, const std::string& path,
                                    const std::function<void(double)>& progress = {});

}  // namespace orthosonar::run
