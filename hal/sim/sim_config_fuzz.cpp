// libFuzzer harness: simulator configuration YAML (`simulate --sim-config`), then, for a
// configuration that validates, a short mission simulated with it: the trajectory, the
// navigation streams and rendered pings, so a value that passes validation and still
// divides by zero, overflows or makes NaN reaches ASan/UBSan (issue 35). The mission is kept
// small so each input stays fast: at most 1 s, one render thread, at most 16 beams x 32
// range bins x 32 elevation x 2 beam samples per head, a box and a pile as the scene; every
// other value is the fuzzed one.
#include <algorithm>
#include <string>

#include "hal/fuzz_support.hpp"
#include "hal/sim/primitives.hpp"
#include "hal/sim/sim_config.hpp"
#include "hal/sim/simulator.hpp"

namespace {

orthosonar::sim::Scene sim_config_fuzz_scene() {
  using namespace orthosonar;
  sim::Scene scene;
  scene.name = "fuzz";
  scene.origin = "fuzz";
  sim::MeshBuilder b(scene.mesh);
  b.box(Vec3(0, 0, -9.5), Vec3(40, 40, 1), 0.0, {1, SemanticClass::kSeafloor});
  b.cylinder(Vec3(4, 1, -9), Vec3(4, 1, 1), 0.3, 8, {2, SemanticClass::kPiling});
  scene.route = {{0, 0}, {6, 0}, {6, 4}};
  scene.vehicle_depth_m = 3.0;
  scene.seafloor_depth_m = 9.0;
  return scene;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace orthosonar;
  sim::SimConfig config;
  if (!sim::apply_sim_config_yaml(std::string(fuzz::text(data, size)), config).ok()) return 0;
  if (!sim::validate(config).ok()) return 0;  // apply_sim_config_yaml validated: never taken
  config.duration_s = std::min(config.duration_s, 1.0);
  config.render_threads = 1;
  config.sonar.elevation_samples = 32;
  config.sonar.beam_samples = std::min(config.sonar.beam_samples, 2);
  for (sim::SonarHead* h : {&config.sonar.head_h, &config.sonar.head_v}) {
    h->beams_full = std::min(h->beams_full, 16);
    h->range_bins_full = std::min(h->range_bins_full, 32);
  }
  if (!sim::validate(config).ok()) return 0;  // the caps keep a valid config valid
  sim::Simulator simulator(sim_config_fuzz_scene(), config);
  for (int n = 0; n < 100000; ++n) {
    const hal::Pulled p = simulator.next();
    if (p.error || p.end_of_stream) break;
  }
  return 0;
}
