// Simulator throughput: full-resolution ping pairs (horizontal + vertical) on one core in
// the harbor scene, and a whole reduced-resolution mission.
#include <benchmark/benchmark.h>

#include "hal/sim/simulator.hpp"

namespace orthosonar::sim {
namespace {

void BM_SimFullResPair(benchmark::State& state) {
  const Scene scene = *builtin_scene("harbor", 1);
  SimConfig cfg;
  const SonarRenderer renderer(scene.mesh, cfg.sonar, Resolution::kFull, 1);
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
  state.counters["rays_per_pair"] = static_cast<double>(2 * renderer.rays_per_ping());
}
BENCHMARK(BM_SimFullResPair)->Unit(benchmark::kMillisecond)->MinTime(3.0);

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

}  // namespace
}  // namespace orthosonar::sim
