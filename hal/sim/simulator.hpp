#pragma once
// The simulator as an EventSource (SPEC §10): a vehicle follows the scene's route at
// fixed depth; DVL, IMU, depth and both sonars fire at their rates; ground-truth poses
// come at every sensor stamp on their own channel; optional per-pixel labels per ping.
// Events come out in (stamp, channel, sequence) order. Every random draw is derived from
// (config.seed, stream, index), so the output is a pure function of (scene, config).
#include <map>
#include <memory>
#include <string>

#include "hal/event_source.hpp"
#include "hal/sim/mesh_io.hpp"
#include "hal/sim/scene.hpp"
#include "hal/sim/sim_config.hpp"
#include "hal/sim/sonar_renderer.hpp"
#include "hal/sim/trajectory.hpp"

namespace orthosonar::sim {

using hal::Pulled;

class Simulator final : public hal::EventSource {
 public:
  Simulator(Scene scene, SimConfig config);
  ~Simulator() override;
  Pulled next() override;
  std::string describe() const override;  // "sim:harbor"
  // Fixture metadata (docs/outputs contract): scene (portable_origin: the built-in name
  // or "file:<yaml file name>"), seed, scene_seed, resolution, duration_s, T_V_h, T_V_v,
  // vehicle_depth_m, software_version. The scene itself goes into the fixture as
  // attachments (embed_scene(scene())).
  std::map<std::string, std::string> metadata() const;
  const Scene& scene() const;
  const SimConfig& config() const;
  const SonarRenderer& renderer() const;
  const Trajectory& trajectory() const;  // ground truth of the vehicle
  // Events of each channel in the whole mission (for progress reports).
  uint64_t planned_count(Channel c) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace orthosonar::sim
