// Simulator throughput: full-resolution ping pairs (horizontal + vertical) on one core in
// the harbor scene, and a whole reduced-resolution mission.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <utility>
#include <string>
#include <vector>

#include "core/perception/fusion.hpp"
#include "hal/sim/simulator.hpp"

namespace orthosonar::sim {
namespace {

// Full-resolution pairs along the harbor route in one profile (seafloor_depth_m only
// matters to the field profile's optional seabed mirror).
void sim_full_res_pairs(benchmark::State& state, SonarProfile profile) {
  const Scene scene = *builtin_scene("harbor", 1);
  SimConfig cfg;
  SonarModelConfig c = cfg.sonar;
  apply_profile(c, profile);
  c.seafloor_depth_m = scene.seafloor_depth_m;
  const SonarRenderer renderer(scene.mesh, c, Resolution::kFull, 1);
  const Trajectory traj(scene.route, scene.vehicle_depth_m, cfg.vehicle, Time::from_s(600));
  uint32_t i = 0;
  for (auto _ : state) {
    const Time t = Time::from_ms(200 * (i % 3000));
    const SE3 T_W_V = traj.at(t).T_W_V();
    auto h = renderer.render(T_W_V * cfg.T_V_h, SonarMount::kHorizontal, t, i);
    auto v = renderer.render(T_W_V * cfg.T_V_v, SonarMount::kVertical, t, i);
    benchmark::DoNotOptimize(h.ping.image.data());
    benchmark::DoNotOptimize(v.ping.image.data());
    ++i;
  }
  state.counters["pairs_per_s"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["rays_per_pair"] = static_cast<double>(renderer.rays_per_ping(SonarMount::kHorizontal) + renderer.rays_per_ping(SonarMount::kVertical));
}

// The clean profile.
void BM_SimFullResPair(benchmark::State& state) { sim_full_res_pairs(state, SonarProfile::kClean); }
BENCHMARK(BM_SimFullResPair)->Unit(benchmark::kMillisecond)->MinTime(3.0);

// The field profile, the default (beam pattern, multipath ghosts, Lambertian seabed with
// texture and relief, absorption, noise before the TVG).
void BM_SimFullResPairField(benchmark::State& state) { sim_full_res_pairs(state, SonarProfile::kField); }
BENCHMARK(BM_SimFullResPairField)->Unit(benchmark::kMillisecond)->MinTime(3.0);

void BM_SimReducedHarbor60s(benchmark::State& state) {
  const Scene scene = *builtin_scene("harbor", 1);
  for (auto _ : state) {
    SimConfig cfg;
    cfg.duration_s = 60;
    cfg.resolution = Resolution::kReduced;
    Simulator sim(scene, cfg);
    uint64_t n = 0;
    while (!sim.next().end_of_stream) ++n;
    benchmark::DoNotOptimize(n);
  }
}
BENCHMARK(BM_SimReducedHarbor60s)->Unit(benchmark::kMillisecond)->Iterations(2);

// Fusion of one full-resolution pair (both CFARs + association, SPEC defaults) on pings the
// simulator rendered along a scene's route (one pair every 15 s of a 300 s mission): the
// realistic counterpart of core/perception's synthetic BM_FusePair512x600.
void fuse_simulated_pairs(benchmark::State& state, const Scene& scene) {
  SimConfig cfg;
  const SonarRenderer renderer(scene.mesh, cfg.sonar, Resolution::kFull, 1);
  const Trajectory traj(scene.route, scene.vehicle_depth_m, cfg.vehicle, Time::from_s(300));
  std::vector<std::pair<SonarPing, SonarPing>> pairs;
  for (uint32_t k = 0; k < 20; ++k) {
    const Time t = Time::from_s(15 * static_cast<int64_t>(k));
    const SE3 T_W_V = traj.at(t).T_W_V();
    pairs.emplace_back(renderer.render(T_W_V * cfg.T_V_h, SonarMount::kHorizontal, t, k).ping,
                       renderer.render(T_W_V * cfg.T_V_v, SonarMount::kVertical, t, k).ping);
  }
  perception::FusionConfig fc;
  fc.T_V_h = cfg.T_V_h;
  fc.T_V_v = cfg.T_V_v;
  size_t i = 0, det = 0, points = 0, sloped = 0;
  for (auto _ : state) {
    const auto& [h, v] = pairs[i++ % pairs.size()];
    const perception::FusionResult r = perception::fuse_pair(h, v, fc);
    det += r.detections_h.size() + r.detections_v.size();
    points += r.points.size();
    sloped += r.sloped_face;
    benchmark::DoNotOptimize(r.points.data());
  }
  const double n = static_cast<double>(std::max<size_t>(i, 1));
  state.counters["detections_per_pair"] = static_cast<double>(det) / n;
  state.counters["points_per_pair"] = static_cast<double>(points) / n;
  state.counters["sloped_face_per_pair"] = static_cast<double>(sloped) / n;
}

void BM_FuseSimulatedPairHarbor(benchmark::State& state) { fuse_simulated_pairs(state, *builtin_scene("harbor", 1)); }
BENCHMARK(BM_FuseSimulatedPairHarbor)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

// The same on the example breakwater (docs/examples), whose sloped faces take the
// sloped-face path (issue 34: a field pair <= 1.5 ms).
void BM_FuseSimulatedPairBreakwater(benchmark::State& state) {
  const auto scene = load_scene_file(std::string(ORTHOSONAR_SOURCE_DIR) + "/docs/examples/breakwater/breakwater.yaml");
  if (!scene.ok()) {
    state.SkipWithError(scene.error().message.c_str());
    return;
  }
  fuse_simulated_pairs(state, *scene);
}
BENCHMARK(BM_FuseSimulatedPairBreakwater)->Unit(benchmark::kMicrosecond)->MinTime(2.0);

}  // namespace
}  // namespace orthosonar::sim
